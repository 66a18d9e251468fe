//! Text in PNG figures sits on its baseline: the glyphs of one line are placed together, so
//! that a decimal point is drawn at the foot of the digits ("0.04"), not raised ("0·04").

use plotters::prelude::*;

use super::super::render::{bitmap, font, register_font};

/// `text` drawn black on white at `size` pixels, the top left corner of its layout box at
/// (4, 30) (plotters' layout lets tall glyphs reach above the box), with the backend PNG
/// figures are drawn on: the darkness (0 to 1) of each pixel of a 120 × 80 image, row by
/// row.
fn rendered(text: &str, size: f64) -> Vec<f64> {
    register_font().unwrap();
    let mut rgb = vec![255u8; WIDTH * 80 * 3];
    {
        let root = bitmap(&mut rgb, (WIDTH as u32, 80)).into_drawing_area();
        root.draw_text(text, &font(size), (4, 30)).unwrap();
        root.present().unwrap();
    }
    rgb.chunks(3)
        .map(|p| 1.0 - f64::from(p[0].min(p[1]).min(p[2])) / 255.0)
        .collect()
}

const WIDTH: usize = 120;

/// The ink of `with` that `without` lacks: the glyph that differs between two renderings of
/// a line whose other glyphs are in the same places.
fn difference(with: &[f64], without: &[f64]) -> Vec<f64> {
    with.iter()
        .zip(without)
        .map(|(a, b)| (a - b).max(0.0))
        .collect()
}

/// The height of the ink's centre of mass, in pixels from the top (pixel centres at
/// half-integers). Antialiasing inks a pixel by the fraction of it a glyph covers, so this is
/// the centroid of the glyph's area to well within a tenth of a pixel.
fn centroid(ink: &[f64]) -> f64 {
    let (mut moment, mut total) = (0.0, 0.0);
    for (i, v) in ink.iter().enumerate() {
        moment += (i / WIDTH) as f64 * v + 0.5 * v;
        total += v;
    }
    moment / total
}

/// How far below the centre of a `0` the centre of a `.` lies in the bundled font, in
/// pixels at `size`: both shapes are symmetric top to bottom (a ring, a square), so their
/// centroids are the middles of their outlines' bounds.
fn point_below_zero(size: f64) -> f64 {
    use ab_glyph::{Font, FontRef, ScaleFont};
    let font = FontRef::try_from_slice(include_bytes!("../font/DejaVuSans.ttf")).unwrap();
    let middle = |c: char| {
        let bounds = font.outline(font.glyph_id(c)).unwrap().bounds;
        f64::from(bounds.min.y + bounds.max.y) / 2.0
    };
    let scale = f64::from(font.as_scaled(size as f32).v_scale_factor());
    // Font units run up, pixels down.
    (middle('0') - middle('.')).abs() * scale
}

#[test]
fn the_decimal_point_sits_on_the_baseline() {
    // The sizes of the figures' text (14 px tick labels at 0.6 to 2 times the default panel
    // size, 16 and 20 px labels and titles), every 0.3 px: rounding each glyph's offset on
    // its own raised the point by a pixel at every size but the even whole ones. In the
    // bundled font a space is as wide as a point and nothing is kerned, so "0 0" has the
    // zeros of "0.0" in the same places.
    for tenths in (84..=400).step_by(3) {
        let size = f64::from(tenths) / 10.0;
        let (line, zeros) = (rendered("0.0", size), rendered("0 0", size));
        let point = difference(&line, &zeros);
        let drop = centroid(&point) - centroid(&zeros);
        let expected = point_below_zero(size);
        assert!(
            (drop - expected).abs() < 0.15,
            "at {size} px the point's centre is {drop:.2} px below the zeros' centre, not \
             {expected:.2} px: it is {:.2} px too high",
            expected - drop
        );
    }
}
