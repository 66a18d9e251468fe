//! Text in bitmaps, set on one baseline.
//!
//! Plotters' `ab_glyph` text path places each glyph on its own: it offsets the glyph's pixel
//! box by `size / 2 + top`, with `top` the box's top edge relative to the baseline, and
//! truncates that offset toward zero. At a font size whose half is not a whole number of
//! pixels the offset is fractional, and truncation rounds it down for a tall glyph (a digit,
//! whose top lies more than half the size above the baseline, gives a negative offset) but
//! up for a short one (a decimal point gives a positive one): the point lands a pixel above
//! the digits' baseline, "0·04" for "0.04". Horizontal offsets are truncated glyph by glyph
//! in the same way, so letter spacing wobbles by a pixel.
//!
//! [`Typeset`] wraps the bitmap backend and draws text itself with the same rasterizer
//! (ab_glyph) and the same layout box as plotters — the same anchor, width and baseline
//! `size / 2` below the box's top, so every label stays where it was laid out — but
//! positions each glyph at its exact pen position on the shared baseline and lets the
//! rasterizer spread the fraction of a pixel over the glyph's edge. Everything else is
//! passed to the wrapped backend.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, ScaleFont, point};
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

/// The bundled font, parsed once; `None` if it cannot be read (then text is left to
/// plotters, which will report the same failure).
fn bundled(bytes: &'static [u8]) -> Option<&'static FontRef<'static>> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(bytes).ok())
        .as_ref()
}

/// A bitmap backend whose text in the family `family` (the bundled font `font`) is set on
/// one baseline; see the module's documentation.
pub(crate) struct Typeset<B> {
    inner: B,
    family: &'static str,
    font: &'static [u8],
}

impl<B> Typeset<B> {
    pub(crate) fn new(inner: B, family: &'static str, font: &'static [u8]) -> Self {
        Typeset {
            inner,
            family,
            font,
        }
    }
}

impl<B: DrawingBackend> DrawingBackend for Typeset<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        let font = match bundled(self.font) {
            Some(font) if style.family().as_str() == self.family => font,
            _ => return self.inner.draw_text(text, style, pos),
        };
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        // Plotters' layout box, so that the text sits where the chart laid it out.
        let ((min_x, min_y), (max_x, max_y)) = style
            .layout_box(text)
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let (width, height) = (max_x - min_x, max_y - min_y);
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let transform = style.transform();
        let (w, h) = self.inner.get_size();
        let mut result = Ok(());
        for_each_pixel(font, style.size() as f32, text, |x, y, coverage| {
            if result.is_err() {
                return;
            }
            let (x, y) = transform.transform(x + dx - min_x, y + dy - min_y);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if x >= 0 && x < w as i32 && y >= 0 && y < h as i32 {
                let alpha = color.alpha * f64::from(coverage);
                result = self.inner.draw_pixel(
                    (x, y),
                    BackendColor {
                        alpha,
                        rgb: color.rgb,
                    },
                );
            }
        });
        result
    }
}

/// Calls `pixel(x, y, coverage)` for every pixel the glyphs of `text` cover, at `size`
/// pixels, in the text's layout box (its top left at (0, 0)): each glyph at its pen
/// position — the advances and kerning before it — on the baseline `size / 2` below the
/// top, as plotters lays text out, with no rounding until the rasterizer's.
pub(crate) fn for_each_pixel(
    font: &FontRef<'_>,
    size: f32,
    text: &str,
    mut pixel: impl FnMut(i32, i32, f32),
) {
    let scaled = font.as_scaled(size);
    let baseline = size / 2.0;
    let mut pen = 0.0f32;
    let mut previous = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(before) = previous {
            pen += scaled.kern(before, id);
        }
        previous = Some(id);
        let glyph = id.with_scale_and_position(size, point(pen, baseline));
        if let Some(outline) = scaled.outline_glyph(glyph) {
            let corner = outline.px_bounds().min;
            let (left, top) = (corner.x as i32, corner.y as i32);
            outline.draw(|x, y, coverage| pixel(left + x as i32, top + y as i32, coverage));
        }
        pen += scaled.h_advance(id);
    }
}
