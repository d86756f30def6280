//! A heat map: one quantity over two swept axes, each cell coloured by its value on a sequential
//! scale (viridis anchors, low = dark violet, high = yellow) with the value written in it, a colour
//! bar beside it (its unit above it, from the value label's last `, unit`), and cells without a value grey and marked "—". The axes are the swept
//! values in sweep order, evenly spaced whatever their spacing (so log ranges read as such).
//! Written as PNG and SVG with the shared plot style ([`crate::report::plot`]).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::report::plot::{bold, failed, text, write_png_svg, Figure, PlotError};

/// A heat map, written as `<stem>.png` and `<stem>.svg` by [`heat_map`].
#[derive(Clone, Debug, PartialEq)]
pub struct HeatMap {
    /// File name without extension.
    pub stem: String,
    /// Title.
    pub title: String,
    /// x-axis label (the columns' field).
    pub x_label: String,
    /// y-axis label (the rows' field).
    pub y_label: String,
    /// Label of the colour bar, with the unit.
    pub value_label: String,
    /// Column labels, left to right.
    pub cols: Vec<String>,
    /// Row labels, bottom to top.
    pub rows: Vec<String>,
    /// `cells[row][col]`.
    pub cells: Vec<Vec<Option<f64>>>,
}

/// Writes `map` as `dir/<stem>.png` and `.svg`; [`PlotError::NoData`] when no cell has a value.
pub fn heat_map(dir: &Path, map: &HeatMap) -> Result<Vec<PathBuf>, PlotError> {
    let range = map.cells.iter().flatten().flatten().filter(|v| v.is_finite()).fold(None, |r, &v| match r {
        None => Some((v, v)),
        Some((lo, hi)) => Some((f64::min(lo, v), f64::max(hi, v))),
    });
    let Some(range) = range else {
        return Err(PlotError::NoData { path: dir.join(&map.stem), reason: "no cell has a value".into() });
    };
    write_png_svg(dir, &map.stem, &Drawn { map, range })
}

struct Drawn<'a> {
    map: &'a HeatMap,
    range: (f64, f64),
}

/// Viridis at five anchors.
const VIRIDIS: [(u8, u8, u8); 5] = [(68, 1, 84), (59, 82, 139), (33, 145, 140), (94, 201, 98), (253, 231, 37)];

/// The colour of `u ∈ [0, 1]`, linear between the anchors.
fn colour(u: f64) -> RGBColor {
    let x = u.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let t = x - i as f64;
    let mix = |a: u8, b: u8| (f64::from(a) + (f64::from(b) - f64::from(a)) * t).round() as u8;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A number in four significant digits.
pub fn short(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    // The exponent after rounding to four digits decides, so that 0.99999999 is "1.000" as
    // 1.0000001 is (floor(log10) gave "1.0000"), and 9999.6 is "1.000e4" as 10000 is.
    let exponent = crate::numeric::numfmt::rounded_exponent(v, 4);
    if (-3..4).contains(&exponent) {
        let digits = (3 - exponent).max(0) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.3e}")
    }
}

impl Figure for Drawn<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let m = self.map;
        root.fill(&WHITE).map_err(failed)?;
        let (w, h) = root.dim_in_pixel();
        let (w, h) = (w as i32, h as i32);
        root.draw(&Text::new(m.title.clone(), (w / 2, 10), bold(22.0).pos(Pos::new(HPos::Center, VPos::Top))))
            .map_err(failed)?;
        root.draw(&Text::new(m.value_label.clone(), (w / 2, 40), text(17.0).pos(Pos::new(HPos::Center, VPos::Top))))
            .map_err(failed)?;
        let (left, right, top, bottom) = (110, w - 140, 90, h - 80);
        let (nx, ny) = (m.cols.len().max(1) as i32, m.rows.len().max(1) as i32);
        let (cw, ch) = ((right - left) / nx, (bottom - top) / ny);
        let (lo, hi) = self.range;
        let span = if hi > lo { hi - lo } else { 1.0 };
        let size = if nx <= 12 && ny <= 16 { 14.0 } else { 0.0 };
        for (i, row) in m.cells.iter().enumerate() {
            let y1 = bottom - ch * i as i32;
            for (j, v) in row.iter().enumerate() {
                let x0 = left + cw * j as i32;
                let rect = [(x0, y1 - ch), (x0 + cw, y1)];
                let (fill, label) = match v {
                    Some(v) => (colour((v - lo) / span), short(*v)),
                    None => (RGBColor(225, 225, 225), "—".to_string()),
                };
                root.draw(&Rectangle::new(rect, fill.filled())).map_err(failed)?;
                root.draw(&Rectangle::new(rect, WHITE.stroke_width(1))).map_err(failed)?;
                if size > 0.0 {
                    let u = v.map_or(1.0, |v| (v - lo) / span);
                    let ink = if u > 0.6 { BLACK } else { WHITE };
                    let ink = if v.is_none() { RGBColor(90, 90, 90) } else { ink };
                    let style = text(size).color(&ink).pos(Pos::new(HPos::Center, VPos::Center));
                    root.draw(&Text::new(label, (x0 + cw / 2, y1 - ch / 2), style)).map_err(failed)?;
                }
            }
        }
        let tick = text(15.0);
        // At most about ten labels on the x axis, so they never overlap.
        let stride = m.cols.len().div_ceil(10).max(1);
        for (j, l) in m.cols.iter().enumerate().filter(|(j, _)| j % stride == 0) {
            let x = left + cw * j as i32 + cw / 2;
            root.draw(&Text::new(l.clone(), (x, bottom + 8), tick.pos(Pos::new(HPos::Center, VPos::Top))))
                .map_err(failed)?;
        }
        let stride = m.rows.len().div_ceil(16).max(1);
        for (i, l) in m.rows.iter().enumerate().filter(|(i, _)| i % stride == 0) {
            let y = bottom - ch * i as i32 - ch / 2;
            root.draw(&Text::new(l.clone(), (left - 8, y), tick.pos(Pos::new(HPos::Right, VPos::Center))))
                .map_err(failed)?;
        }
        let axis = text(18.0);
        root.draw(&Text::new(
            m.x_label.clone(),
            ((left + right) / 2, bottom + 40),
            axis.pos(Pos::new(HPos::Center, VPos::Top)),
        ))
        .map_err(failed)?;
        root.draw(&Text::new(m.y_label.clone(), (12, top - 26), axis.pos(Pos::new(HPos::Left, VPos::Top))))
            .map_err(failed)?;
        // Colour bar.
        let (bx, bw) = (right + 30, 24);
        let steps = 64;
        for k in 0..steps {
            let y0 = bottom - (bottom - top) * (k + 1) / steps;
            let y1 = bottom - (bottom - top) * k / steps;
            let c = colour((f64::from(k) + 0.5) / f64::from(steps));
            root.draw(&Rectangle::new([(bx, y0), (bx + bw, y1)], c.filled())).map_err(failed)?;
        }
        // The colour bar's unit: what follows the value label's last comma ("…, m").
        if let Some((_, unit)) = m.value_label.rsplit_once(", ") {
            let style = text(15.0).pos(Pos::new(HPos::Left, VPos::Bottom));
            root.draw(&Text::new(unit.to_string(), (bx, top - 8), style)).map_err(failed)?;
        }
        for (v, y) in [(hi, top), (0.5 * (lo + hi), (top + bottom) / 2), (lo, bottom)] {
            root.draw(&Text::new(short(v), (bx + bw + 6, y), tick.pos(Pos::new(HPos::Left, VPos::Center))))
                .map_err(failed)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::short;

    /// Four significant digits whichever side of a power of ten a value rounds from (a ratio of
    /// 1 − 1e-13 read "1.0000" beside "1.000" for 1 + 1e-13 in one table).
    #[test]
    fn a_value_that_rounds_up_to_a_power_of_ten_keeps_four_digits() {
        assert_eq!(short(1.0 - 1e-13), "1.000");
        assert_eq!(short(1.0 + 1e-13), "1.000");
        assert_eq!(short(9.99996), "10.00");
        assert_eq!(short(0.0012346), "0.001235");
        assert_eq!(short(2.051), "2.051");
        assert_eq!(short(12345.0), "1.234e4");
        assert_eq!(short(9999.6), "1.000e4");
        assert_eq!(short(0.00099996), "0.001000");
    }
}
