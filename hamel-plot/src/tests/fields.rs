//! Fields: their contours, their colours (the centre level near white, blue below, red
//! above, grey where there is no value), their colour bar, and every way they can be wrong.

use super::super::heatmap::checked;
use super::super::render::pixels;
use super::super::*;
use super::{check_svg, texts};

fn grid(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

#[test]
fn the_contour_of_a_paraboloid_is_its_circle() {
    let g = grid(41, -2.0, 2.0);
    let field = Field::from_fn("r² − 1", &g, &g, |x, y| x * x + y * y - 1.0);
    let lines = field.contour(0.0);
    assert_eq!(lines.len(), 1, "one line");
    let circle = &lines[0];
    assert_eq!(circle.first(), circle.last(), "closed");
    assert!(circle.len() > 40);
    // Linear interpolation along the cells' edges: within h²/8 of the circle (h = 0.1).
    for &(x, y) in circle {
        let r = (x * x + y * y).sqrt();
        assert!(
            (r - 1.0).abs() < 0.1 * 0.1 / 8.0 * 2.0,
            "r = {r} at ({x}, {y})"
        );
    }
    // A circle of radius √3 lies inside the grid; one of radius 2 leaves it at four points,
    // in four arcs; a level above every value has none.
    assert_eq!(field.contour(2.0).len(), 1);
    assert_eq!(field.contour(3.0).len(), 4);
    assert!(field.contour(10.0).is_empty());
    let saddle = Field::from_fn("x y", &g, &g, |x, y| x * y + 0.01);
    let lines = saddle.contour(0.0);
    assert_eq!(lines.len(), 2, "the hyperbola's two branches");
    assert!(
        lines.iter().all(|l| l.first() != l.last()),
        "open, ending at the edges"
    );
    let series = saddle.contour_series("x y = 0", 0.0);
    assert_eq!(series.name(), "x y = 0");
}

#[test]
fn nan_cells_end_contours_and_are_grey() {
    let g = grid(11, 0.0, 1.0);
    let field = Field::from_fn("x − 0.5", &g, &g, |x, y| {
        if (0.45..0.55).contains(&y) {
            f64::NAN
        } else {
            x - 0.5
        }
    });
    // The vertical line x = 0.5 is cut in two by the row of NaN.
    assert_eq!(field.contour(0.0).len(), 2);
    let checked = checked(&field, "p", false).unwrap();
    let cells = checked.cells(((-0.05, 1.05), (-0.05, 1.05)));
    assert_eq!(cells.len(), 121);
    assert!(cells.iter().any(|c| c.color == NO_VALUE));
}

/// The fill colours of an SVG's filled rectangles after the background, in drawing order:
/// a field's cells first, row by row.
fn fills(svg: &str) -> Vec<(i32, i32, i32)> {
    svg.split("<rect ")
        .skip(2)
        .filter_map(|r| {
            let hex = r.split("fill=\"#").nth(1)?.get(..6)?;
            let channel = |k: usize| i32::from_str_radix(&hex[2 * k..2 * k + 2], 16).ok();
            Some((channel(0)?, channel(1)?, channel(2)?))
        })
        .collect()
}

#[test]
fn below_the_centre_is_blue_above_it_red_and_at_it_white() {
    // f = x over x = −1, −0.95, …, 3: the scale's two sides span 1 and 3.
    let (x, y) = (grid(81, -1.0, 3.0), grid(5, 0.0, 1.0));
    let panel = Panel::new("").field(Field::from_fn("f (1/s)", &x, &y, |x, _| x));
    let svg = Figure::from(panel.clone()).size(600, 300).to_svg().unwrap();
    check_svg(&svg);
    let cells = fills(&svg);
    assert!(cells.len() >= 81 * 5);
    let (r, g, b) = cells[2]; // x = −0.9
    assert!(b > r + 60 && b > g, "below the centre: ({r}, {g}, {b})");
    let (r, g, b) = cells[70]; // x = 2.5
    assert!(r > b + 80 && r > g, "above the centre: ({r}, {g}, {b})");
    let (r, g, b) = cells[20]; // x = 0
    assert!(r.min(g).min(b) > 235, "at the centre: ({r}, {g}, {b})");
    // The darkest colours at the ends, the rows alike.
    assert_eq!((cells[0], cells[80]), ((5, 48, 97), (103, 0, 31)));
    assert_eq!(cells[..81], cells[81..162]);
    assert!(texts(&svg).contains(&"f (1/s)"), "the colour bar's label");
    // The PNG draws them too: its middle row holds the darkest blue and red.
    let (width, height, rgb) = pixels(&Figure::from(panel).size(600, 300)).unwrap();
    let row = &rgb[3 * (width * height / 2) as usize..3 * (width * (height / 2 + 1)) as usize];
    let has = |c: [u8; 3]| row.chunks(3).any(|p| p == c);
    assert!(has([5, 48, 97]) && has([103, 0, 31]) && has([247, 247, 247]));
}

#[test]
fn the_colour_bar_spans_both_sides_and_marks_the_centre() {
    let (x, y) = (grid(5, 0.0, 1.0), grid(5, 0.0, 1.0));
    let field = Field::from_fn("growth (1/s)", &x, &y, |x, y| 6.0 * x - 0.5 * y - 0.5)
        .scale(ColorScale::SymLog { linear: 0.05 });
    let checked = checked(&field, "p", false).unwrap();
    let bar = checked.colorbar(6);
    assert_eq!((bar.lo, bar.center, bar.hi), (-1.0, 0.0, 5.5));
    assert_eq!(bar.position(0.0), 0.0);
    assert_eq!((bar.position(-1.0), bar.position(5.5)), (-1.0, 1.0));
    // Logarithmic beyond 0.05: 0.5 lies one decade in, of 1 + log₁₀(110) on that side.
    let expected = 2.0 / (2.0 + 110f64.log10() - 1.0);
    assert!((bar.position(0.5) - expected).abs() < 1e-12);
    assert!(bar.position(0.06) > 0.2, "a small growth reads clearly");
    assert_eq!(bar.ticks, [-0.5, -0.05, 0.0, 0.05, 0.5, 5.0]);
    // Linear, the ticks are round values on each side.
    let linear = checked_bar(Field::from_fn("f", &x, &y, |x, _| 4.0 * x - 1.0));
    assert!(linear.ticks.contains(&0.0) && linear.ticks.contains(&-1.0));
    assert!(linear.ticks.contains(&2.0) && linear.ticks.windows(2).all(|w| w[0] < w[1]));
}

fn checked_bar(field: Field) -> super::super::heatmap::ColorBar {
    checked(&field, "p", false).unwrap().colorbar(6)
}

#[test]
fn fields_that_cannot_be_drawn_are_errors_naming_the_reason() {
    let g = grid(3, 0.0, 1.0);
    let reason = |field: Field| -> String {
        let err = Figure::from(Panel::new("map").field(field))
            .to_svg()
            .unwrap_err();
        match err.kind() {
            ErrorKind::InvalidField { panel, reason } if panel == "map" => reason.clone(),
            other => panic!("{other:?}"),
        }
    };
    let values = [0.0; 9];
    assert!(reason(Field::new("f", &[0.0], &g, &values[..3])).contains("two grid values"));
    assert!(reason(Field::new("f", &[0.0, 1.0, 0.5], &g, &values)).contains("x[2] = 0.5"));
    assert!(reason(Field::new("f", &g, &[0.0, f64::NAN, 1.0], &values)).contains("y[1]"));
    assert!(reason(Field::new("f", &g, &g, &values[..8])).contains("8 values"));
    assert!(reason(Field::new("f", &g, &g, &[f64::NAN; 9])).contains("no finite value"));
    assert!(reason(Field::new("f", &g, &g, &values).range(1.0, 2.0)).contains("hold its centre"));
    let symlog = Field::new("f", &g, &g, &values).scale(ColorScale::SymLog { linear: 0.0 });
    assert!(reason(symlog).contains("positive number"));
    let err = Figure::from(
        Panel::new("map")
            .log_y()
            .field(Field::new("f", &g, &g, &values)),
    )
    .to_svg()
    .unwrap_err();
    assert!(err.to_string().contains("above 0"), "{err}");
    // A constant field at its centre draws (white), and a field alone needs no series.
    let flat = Figure::from(Panel::new("flat").field(Field::new("f", &g, &g, &values)));
    check_svg(&flat.to_svg().unwrap());
}
