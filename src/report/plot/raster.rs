//! The raster backend every PNG and GIF is drawn on: plotters' bitmap backend with two of its
//! drawing routines replaced, because they draw things that are not in the figure.
//!
//! - **Thick lines.** plotters strokes a path wider than one pixel by offsetting it into a
//!   polygon with mitred joins, and caps only the *outer* side of sharp joins. Where a dense
//!   curve turns back on itself between integer pixels — a steep step, then one pixel back — the
//!   two inner offset lines are nearly parallel and meet far away: a spike of tens of pixels
//!   (a 27 N·m peak drawn on a torque curve that stays within ±9.9 N·m), and short "hairs" on
//!   every jagged stretch. Here a path of width `w` is instead the union of capsules (segments
//!   with round ends) of radius `r = w/2`: a pixel whose centre is at distance `d` from the
//!   nearest segment is covered `clamp(r + ½ − d, 0, 1)` (anti-aliased), each pixel painted once.
//!   So no painted pixel lies farther than `r + ½` from the path's own points.
//! - **Text.** plotters' `ab_glyph` renderer places each glyph at the pen position truncated to
//!   whole pixels and ignores the glyph's left side bearing, so letters sit unevenly ("torq ue").
//!   Here each glyph is positioned at its exact (sub-pixel) pen position `x = Σ advances + kerning`
//!   on a common baseline and rasterised there, from the same embedded DejaVu Sans faces.
//!   The size convention is plotters' (a style of size `s` has ascent − descent = `s` pixels),
//!   so layouts measured with [`DrawingBackend::estimate_text_size`] are unchanged. Anchors:
//!   horizontally the advance box; vertically `Top` = ascent line, `Center` = half the capital
//!   height above the baseline (digits and capitals look centred), `Bottom` = descent line.
//!
//! Everything else (single-pixel lines, polygons, circles, rectangles, blitting) is plotters'.

use std::sync::OnceLock;

use super::legend::distance;
use ab_glyph::{point, Font, FontRef, GlyphId, OutlinedGlyph, PxScale, ScaleFont};
use plotters::prelude::DrawingBackend;
use plotters::style::FontStyle;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind};

/// A raster [`DrawingBackend`] (plotters' `BitMapBackend`) with spike-free thick lines and
/// correctly spaced text; see the module docs.
pub(crate) struct Raster<B: DrawingBackend> {
    inner: B,
}

impl<B: DrawingBackend> Raster<B> {
    /// Wraps a raster backend.
    pub(crate) fn new(inner: B) -> Self {
        Self { inner }
    }
}

/// Why text could not be drawn: the embedded face was rejected by `ab_glyph`.
#[derive(Debug, thiserror::Error)]
#[error("the embedded DejaVu Sans {0} face was rejected by ab_glyph")]
struct FaceError(&'static str);

/// The embedded face for a plotters font style (bold, oblique for italic and oblique, else
/// regular), parsed once per process.
fn face(style: FontStyle) -> Result<&'static FontRef<'static>, FaceError> {
    static FACES: [OnceLock<Option<FontRef<'static>>>; 3] = [OnceLock::new(), OnceLock::new(), OnceLock::new()];
    let (slot, name, bytes): (usize, &'static str, fn() -> &'static [u8]) = match style {
        FontStyle::Bold => (1, "bold", dejavu::sans::bold),
        FontStyle::Italic | FontStyle::Oblique => (2, "oblique", dejavu::sans::oblique),
        FontStyle::Normal => (0, "regular", dejavu::sans::regular),
    };
    FACES[slot].get_or_init(|| FontRef::try_from_slice(bytes()).ok()).as_ref().ok_or(FaceError(name))
}

/// One line of text laid out on its baseline (`y = 0`), pen starting at `x = 0`.
struct Line {
    glyphs: Vec<OutlinedGlyph>,
    /// Advance width, px.
    width: f32,
    /// Ascent (above the baseline, positive), descent (below, negative), capital height; px.
    ascent: f32,
    descent: f32,
    cap: f32,
}

/// Lays `text` out in `font` at `size` px (ascent − descent), glyphs at sub-pixel pen positions.
fn layout(font: &FontRef<'static>, size: f64, text: &str, baseline: f32) -> Line {
    let scaled = font.as_scaled(PxScale::from(size as f32));
    let (mut caret, mut prev): (f32, Option<GlyphId>) = (0.0, None);
    let mut glyphs = Vec::new();
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            caret += scaled.kern(p, id);
        }
        let glyph = id.with_scale_and_position(scaled.scale(), point(caret, baseline));
        glyphs.extend(font.outline_glyph(glyph));
        caret += scaled.h_advance(id);
        prev = Some(id);
    }
    // Outline bounds are in font units, y up, stored top-left (`min.y` is the top, y_max).
    let cap = font
        .outline(font.glyph_id('H'))
        .map_or(0.7 * scaled.ascent(), |o| o.bounds.min.y.max(o.bounds.max.y) * scaled.scale_factor().vertical);
    Line { glyphs, width: caret, ascent: scaled.ascent(), descent: scaled.descent(), cap }
}

/// Coverage of a pixel centred at `(x, y)` by a capsule of radius `r` around segment `a`–`b`.
fn capsule_coverage(centre: (f64, f64), a: (f64, f64), b: (f64, f64), r: f64) -> f64 {
    (r + 0.5 - distance(centre, a, b)).clamp(0.0, 1.0)
}

impl<B: DrawingBackend> Raster<B> {
    /// Strokes `points` `width` px wide as a union of capsules, each pixel painted once.
    fn stroke(
        &mut self,
        points: &[BackendCoord],
        width: u32,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        let mut pts: Vec<(f64, f64)> = Vec::with_capacity(points.len());
        for &(x, y) in points {
            let p = (f64::from(x), f64::from(y));
            if pts.last() != Some(&p) {
                pts.push(p);
            }
        }
        let Some(&first) = pts.first() else { return Ok(()) };
        if pts.len() == 1 {
            pts.push(first);
        }
        let r = 0.5 * f64::from(width);
        let reach = (r + 0.5).ceil() as i32;
        let (w, h) = self.inner.get_size();
        let (w, h) = (w as i32, h as i32);
        let (lo, hi) = pts
            .iter()
            .fold((first, first), |(lo, hi), &(x, y)| ((lo.0.min(x), lo.1.min(y)), (hi.0.max(x), hi.1.max(y))));
        let x0 = (lo.0 as i32 - reach).max(0);
        let y0 = (lo.1 as i32 - reach).max(0);
        let x1 = (hi.0 as i32 + reach).min(w - 1);
        let y1 = (hi.1 as i32 + reach).min(h - 1);
        if x0 > x1 || y0 > y1 {
            return Ok(());
        }
        let cols = (x1 - x0 + 1) as usize;
        let mut cover = vec![0f64; cols * (y1 - y0 + 1) as usize];
        for seg in pts.windows(2) {
            let (a, b) = (seg[0], seg[1]);
            let sx0 = (a.0.min(b.0) as i32 - reach).max(x0);
            let sx1 = (a.0.max(b.0) as i32 + reach).min(x1);
            let sy0 = (a.1.min(b.1) as i32 - reach).max(y0);
            let sy1 = (a.1.max(b.1) as i32 + reach).min(y1);
            for y in sy0..=sy1 {
                for x in sx0..=sx1 {
                    let c = capsule_coverage((f64::from(x), f64::from(y)), a, b, r);
                    let cell = &mut cover[(y - y0) as usize * cols + (x - x0) as usize];
                    *cell = cell.max(c);
                }
            }
        }
        for (i, &c) in cover.iter().enumerate() {
            if c > 0.0 {
                let (x, y) = (x0 + (i % cols) as i32, y0 + (i / cols) as i32);
                self.inner.draw_pixel((x, y), color.mix(c))?;
            }
        }
        Ok(())
    }

    /// Lays out `text` for `style` with its anchor at the origin; returns the line and its offset.
    fn anchored<S: BackendTextStyle>(text: &str, style: &S) -> Result<(Line, f32), DrawingErrorKind<B::ErrorType>> {
        let font = face(style.style()).map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let probe = layout(font, style.size(), "", 0.0);
        let anchor = style.anchor();
        let baseline = match anchor.v_pos {
            VPos::Top => probe.ascent,
            VPos::Center => 0.5 * probe.cap,
            VPos::Bottom => probe.descent,
        };
        let line = layout(font, style.size(), text, baseline);
        let dx = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -0.5 * line.width,
            HPos::Right => -line.width,
        };
        Ok((line, dx))
    }
}

impl<B: DrawingBackend> DrawingBackend for Raster<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        if style.stroke_width() > 1 {
            return self.stroke(&[from, to], style.stroke_width(), style.color());
        }
        self.inner.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        if style.stroke_width() > 1 {
            let points: Vec<BackendCoord> = path.into_iter().collect();
            return self.stroke(&points, style.stroke_width(), style.color());
        }
        self.inner.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let (line, dx) = Self::anchored(text, style)?;
        let (w, h) = self.inner.get_size();
        let trans = style.transform();
        let mut pixels = Vec::new();
        for glyph in &line.glyphs {
            let bounds = glyph.px_bounds();
            let (gx, gy) = ((bounds.min.x + dx).round() as i32, bounds.min.y.floor() as i32);
            glyph.draw(|x, y, c| pixels.push((gx + x as i32, gy + y as i32, c)));
        }
        for (x, y, c) in pixels {
            let (x, y) = trans.transform(x, y);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if c > 0.0 && (0..w as i32).contains(&x) && (0..h as i32).contains(&y) {
                self.inner.draw_pixel((x, y), color.mix(f64::from(c.min(1.0))))?;
            }
        }
        Ok(())
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        let (line, _) = Self::anchored(text, style)?;
        Ok((line.width.ceil().max(0.0) as u32, (line.ascent - line.descent).ceil().max(0.0) as u32))
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;
    use plotters::style::text_anchor::Pos;

    const SIZE: (u32, u32) = (300, 600);
    const INK: RGBColor = RGBColor(214, 39, 40);

    /// Draws with `f` on a white raster of [`SIZE`]; returns the RGB buffer.
    fn raster(f: impl FnOnce(&DrawingArea<Raster<BitMapBackend>, plotters::coord::Shift>)) -> Vec<u8> {
        let mut buf = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
        {
            let root = Raster::new(BitMapBackend::with_buffer(&mut buf, SIZE)).into_drawing_area();
            root.fill(&WHITE).ok();
            f(&root);
            root.present().ok();
        }
        buf
    }

    /// Columns and rows of pixels that are not white.
    fn inked(buf: &[u8]) -> Vec<(i32, i32)> {
        darker_than(buf, 250)
    }

    /// Columns and rows of pixels with a channel below `level` (128: at least half covered).
    fn darker_than(buf: &[u8], level: u8) -> Vec<(i32, i32)> {
        buf.chunks(3)
            .enumerate()
            .filter(|(_, p)| p.iter().any(|&v| v < level))
            .map(|(i, _)| ((i as u32 % SIZE.0) as i32, (i as u32 / SIZE.0) as i32))
            .collect()
    }

    /// The pixel path plotters produced for the step of `torques_joint1` at t ≈ 0.11 s (read
    /// from its SVG twin): flat at y = 368, down to 454, then jitter of one pixel.
    const STEP: [(i32, i32); 12] = [
        (145, 368),
        (147, 368),
        (149, 368),
        (150, 368),
        (150, 373),
        (151, 454),
        (151, 453),
        (152, 455),
        (152, 454),
        (153, 453),
        (153, 455),
        (155, 454),
    ];

    #[test]
    fn a_thick_step_stays_within_its_points() {
        let buf = raster(|root| {
            root.draw(&PathElement::new(STEP.to_vec(), Color::stroke_width(&INK, 2))).ok();
        });
        let ink = inked(&buf);
        assert!(!ink.is_empty(), "nothing drawn");
        let (top, bottom) = (ink.iter().map(|p| p.1).min(), ink.iter().map(|p| p.1).max());
        // Radius 1 plus the half pixel of anti-aliasing: rows 367 ..= 456 at most.
        assert!(top >= Some(367) && bottom <= Some(456), "ink spans rows {top:?} ..= {bottom:?}, points 368 ..= 455");
    }

    #[test]
    fn plotters_own_thick_step_spikes() {
        // The flaw this backend replaces, shown on plotters' plain bitmap backend: if plotters
        // ever fixes it, this test says so and the replacement can go.
        let mut buf = vec![255u8; (SIZE.0 * SIZE.1 * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area();
            root.draw(&PathElement::new(STEP.to_vec(), Color::stroke_width(&INK, 2))).ok();
            root.present().ok();
        }
        let top = inked(&buf).iter().map(|p| p.1).min();
        assert!(top < Some(350), "plotters' own stroke no longer spikes (top row {top:?})");
    }

    /// Widest run of blank columns between the first and the last inked column.
    fn widest_gap(buf: &[u8]) -> i32 {
        let columns: std::collections::BTreeSet<i32> = darker_than(buf, 128).iter().map(|p| p.0).collect();
        columns.iter().zip(columns.iter().skip(1)).map(|(a, b)| b - a - 1).max().unwrap_or(-1)
    }

    /// The font's own widest blank between neighbouring letters of `text` at `size` px, from its
    /// metrics: pen positions (advances + kerning) and each outline's horizontal extent.
    fn font_gap(text: &str, size: f32) -> f32 {
        let font = face(FontStyle::Normal).ok();
        let Some(font) = font else { return f32::NAN };
        let scaled = font.as_scaled(PxScale::from(size));
        let (mut pen, mut prev, mut last_right, mut widest) = (0.0f32, None, None::<f32>, 0.0f32);
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = prev {
                pen += scaled.kern(p, id);
            }
            if let Some(o) = font.outline(id) {
                let k = scaled.scale_factor().horizontal;
                let (left, right) = (pen + o.bounds.min.x * k, pen + o.bounds.max.x * k);
                if let Some(r) = last_right {
                    widest = widest.max(left - r);
                }
                last_right = Some(right);
            }
            pen += scaled.h_advance(id);
            prev = Some(id);
        }
        widest
    }

    #[test]
    fn letters_are_spaced_as_the_font_says() {
        // Each neighbouring pair of "torque", drawn alone at the label's 16 px: the blank between
        // its two letters is the font's own, to the pixel that anti-aliasing may close or open.
        crate::report::plot::style::ensure_fonts().ok();
        let style = || TextStyle::from(("sans-serif", 16.0).into_font()).color(&BLACK);
        let (mut ours, mut theirs) = (Vec::new(), Vec::new());
        for pair in ["to", "or", "rq", "qu", "ue"] {
            let want = font_gap(pair, 16.0);
            let drawn = raster(|root| {
                root.draw(&Text::new(pair, (10, 10), style())).ok();
            });
            let mut plain = vec![255u8; (SIZE.0 * SIZE.1 * 3) as usize];
            {
                let root = BitMapBackend::with_buffer(&mut plain, SIZE).into_drawing_area();
                root.draw(&Text::new(pair, (10, 10), style())).ok();
                root.present().ok();
            }
            ours.push((pair, widest_gap(&drawn) as f32 - want));
            theirs.push((pair, widest_gap(&plain) as f32 - want));
        }
        assert!(ours.iter().all(|(_, d)| d.abs() <= 1.0), "blank minus the font's, px: {ours:?}");
        // plotters' own renderer (truncated pen, left side bearings dropped) misses by more.
        assert!(theirs.iter().any(|(_, d)| d.abs() > 1.0), "plotters' own renderer: {theirs:?} (flaw gone?)");
    }

    #[test]
    fn centred_text_is_centred_on_its_anchor() {
        // Capitals and digits, anchored at their centre, spread evenly above and below it.
        let style =
            TextStyle::from(("sans-serif", 40.0).into_font()).color(&BLACK).pos(Pos::new(HPos::Center, VPos::Center));
        let buf = raster(|root| {
            root.draw(&Text::new("H80", (150, 300), style)).ok();
        });
        let ink = inked(&buf);
        let (top, bottom) = (ink.iter().map(|p| p.1).min().unwrap_or(0), ink.iter().map(|p| p.1).max().unwrap_or(0));
        let (left, right) = (ink.iter().map(|p| p.0).min().unwrap_or(0), ink.iter().map(|p| p.0).max().unwrap_or(0));
        assert!((top + bottom - 600).abs() <= 2, "rows {top} ..= {bottom} around 300");
        assert!((left + right - 300).abs() <= 4, "columns {left} ..= {right} around 150");
    }

    #[test]
    fn text_width_is_the_advance_sum() {
        let style = TextStyle::from(("sans-serif", 20.0).into_font());
        let mut buf = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
        let back = Raster::new(BitMapBackend::with_buffer(&mut buf, SIZE));
        let (w, h) = back.estimate_text_size("torque", &style).unwrap_or((0, 0));
        let font = face(FontStyle::Normal).ok();
        let want = font.map_or(0.0, |f| layout(f, 20.0, "torque", 0.0).width);
        assert_eq!(w, want.ceil() as u32);
        assert_eq!(h, 20, "ascent − descent is the size");
    }
}
