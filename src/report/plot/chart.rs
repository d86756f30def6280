//! The one line chart every static figure is made of: named series, optional phase bands,
//! dashed reference lines, linear, log–log or log-x axes, and a legend beside the plot (never on it).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::legend::{legend_labels, Label, Runs};
use super::style::{bold, colour, dashed, failed, text, write_png_svg, Figure, GUIDE};
use super::{PlotError, Series};

/// How the axes map values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Scale {
    /// Both axes linear.
    #[default]
    Linear,
    /// Both axes logarithmic (base 10); points with a non-positive coordinate are left out.
    LogLog,
    /// The x axis logarithmic (base 10), the y axis linear: a distribution over decades of
    /// errors; points with a non-positive x are left out.
    LogX,
}

impl Scale {
    /// Whether the x axis is logarithmic.
    fn log_x(self) -> bool {
        matches!(self, Scale::LogLog | Scale::LogX)
    }

    /// Whether the y axis is logarithmic.
    fn log_y(self) -> bool {
        self == Scale::LogLog
    }
}

/// A labelled interval of the x axis, e.g. a phase: its start is marked by a dashed vertical
/// line and its label written at the top, centred.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// Start, in x units.
    pub from: f64,
    /// End, in x units.
    pub to: f64,
    /// Label.
    pub label: String,
}

/// A dashed horizontal reference line (e.g. a target), labelled at its left end.
#[derive(Clone, Debug, PartialEq)]
pub struct RefLine {
    /// Height, in y units.
    pub y: f64,
    /// Label.
    pub label: String,
}

/// A line chart, written as `<stem>.png` and `<stem>.svg` by [`line_plot`].
#[derive(Clone, Debug, PartialEq)]
pub struct LinePlot {
    /// File name without extension.
    pub stem: String,
    /// Title (name the problem in it).
    pub title: String,
    /// x-axis label, with its unit.
    pub x_label: String,
    /// y-axis label, with its unit.
    pub y_label: String,
    /// The curves, one legend entry each.
    pub series: Vec<Series>,
    /// Labelled x intervals (phases).
    pub bands: Vec<Band>,
    /// Dashed horizontal reference lines.
    pub ref_lines: Vec<RefLine>,
    /// Linear, log–log or log-x axes.
    pub scale: Scale,
    /// Whether each point is also marked by a dot (for sparse data such as benchmarks).
    pub markers: bool,
}

impl LinePlot {
    /// A linear line chart without bands, reference lines or markers.
    pub fn new(
        stem: impl Into<String>,
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        series: Vec<Series>,
    ) -> Self {
        Self {
            stem: stem.into(),
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series,
            bands: Vec::new(),
            ref_lines: Vec::new(),
            scale: Scale::Linear,
            markers: false,
        }
    }
}

/// Writes `plot` as `dir/<stem>.png` and `dir/<stem>.svg`; returns the two paths.
///
/// Fails with [`PlotError::NoData`] when there is no series, or no drawable point in any.
pub fn line_plot(dir: &Path, plot: &LinePlot) -> Result<Vec<PathBuf>, PlotError> {
    let prepared = Prepared::new(plot).map_err(|reason| PlotError::NoData { path: dir.join(&plot.stem), reason })?;
    write_png_svg(dir, &plot.stem, &prepared)
}

/// A plot with its data mapped to axis coordinates (log10 on log axes) and its ranges found.
struct Prepared<'a> {
    plot: &'a LinePlot,
    /// Per series, the runs of drawable points (a non-drawable point breaks the line).
    runs: Vec<Vec<Vec<(f64, f64)>>>,
    /// Legend entries: the series' names, a hidden one noted "under …" ([`legend_labels`]).
    labels: Vec<Label>,
    x: (f64, f64),
    y: (f64, f64),
}

impl<'a> Prepared<'a> {
    fn new(plot: &'a LinePlot) -> Result<Self, String> {
        if plot.series.is_empty() {
            return Err("no series given".to_string());
        }
        let (log_x, log_y) = (plot.scale.log_x(), plot.scale.log_y());
        let log = log_x || log_y;
        let axis = |v: f64, log: bool| if log { v.log10() } else { v };
        let map = |(x, y): (f64, f64)| (axis(x, log_x), axis(y, log_y));
        let runs: Vec<Vec<Vec<(f64, f64)>>> = plot
            .series
            .iter()
            .map(|s| {
                let mut runs = vec![Vec::new()];
                for p in s.points.iter().map(|&p| map(p)) {
                    match runs.last_mut() {
                        Some(run) if p.0.is_finite() && p.1.is_finite() => run.push(p),
                        Some(run) if !run.is_empty() => runs.push(Vec::new()),
                        _ => {}
                    }
                }
                runs.retain(|r| !r.is_empty());
                runs
            })
            .collect();
        let all = || runs.iter().flatten().flatten();
        if all().next().is_none() {
            let kind = if log { "finite, positive" } else { "finite" };
            return Err(format!("no {kind} point in any of the {} series", plot.series.len()));
        }
        let x = span(all().map(|p| p.0));
        let y = span(all().map(|p| p.1).chain(plot.ref_lines.iter().map(|r| axis(r.y, log_y))));
        let x = if log_x { pad(decades(x), 0.03, 0.03) } else { x };
        let y = if log_y {
            pad(decades(y), 0.03, 0.03)
        } else {
            let top = if plot.bands.is_empty() { 0.06 } else { 0.14 };
            pad(y, 0.06, top)
        };
        let names: Vec<&str> = plot.series.iter().map(|s| s.name.as_str()).collect();
        let drawn: Vec<&Runs> = runs.iter().map(Vec::as_slice).collect();
        let labels = legend_labels(&names, &drawn, x, y);
        Ok(Self { plot, runs, labels, x, y })
    }
}

/// The smallest and largest of finite values (callers guarantee at least one), widened when equal.
fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) =
        values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if hi - lo > 1e-12 * (1.0 + lo.abs().max(hi.abs())) {
        (lo, hi)
    } else {
        let w = 0.5 * lo.abs().max(1.0);
        (lo - w, hi + w)
    }
}

/// Widens a range by fractions of its width below and above.
fn pad((lo, hi): (f64, f64), below: f64, above: f64) -> (f64, f64) {
    let w = hi - lo;
    (lo - below * w, hi + above * w)
}

/// A log10 range widened to whole decades (the ticks fall on them).
fn decades((lo, hi): (f64, f64)) -> (f64, f64) {
    let (lo, hi) = (lo.floor(), hi.ceil());
    (lo, if hi > lo { hi } else { lo + 1.0 })
}

/// A tick label on a log axis: `10ⁿ` at whole decades, the value itself between them.
fn log_tick(v: &f64) -> String {
    const SUPER: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    if (v - v.round()).abs() < 1e-9 {
        let n = v.round() as i64;
        let digits: String =
            n.unsigned_abs().to_string().chars().filter_map(|c| c.to_digit(10)).map(|d| SUPER[d as usize]).collect();
        format!("10{}{digits}", if n < 0 { "⁻" } else { "" })
    } else {
        format!("{:.1e}", 10f64.powf(*v))
    }
}

/// A linear axis's tick label over the range `(lo, hi)`: as many decimals as its tick spacing
/// needs, so counts read `18`, not `18.0`, and every label of an axis has the same decimals.
/// Plotters spaces at most ten ticks by `{1, 2, 5} × 10ᵏ`, counting only the multiples of the
/// step inside the range, so its step can be as small as an eleventh of the range; the smallest
/// such step above that is never larger than the one it picks, so its decimals are always enough.
fn linear_tick((lo, hi): (f64, f64)) -> impl Fn(&f64) -> String {
    let raw = (hi - lo).abs() / 11.0;
    let decimals = if raw > 0.0 && raw.is_finite() {
        let k = raw.log10().floor();
        let mantissa = raw / 10f64.powf(k);
        let exponent = if mantissa > 5.0 { k + 1.0 } else { k };
        (-exponent).clamp(0.0, 12.0) as usize
    } else {
        1
    };
    move |v: &f64| {
        let shown = format!("{v:.decimals$}");
        // `-0` where a tick rounds to zero from below.
        if shown.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
            shown.trim_start_matches('-').to_string()
        } else {
            shown
        }
    }
}

/// Text sizes of a legend entry's name and of its note, pixels.
const LEGEND_TEXT: (f64, f64) = (16.0, 13.0);

/// The smallest text a title or a legend is shrunk to so that it fits, pixels.
const SMALLEST_TEXT: f64 = 10.0;

/// The legend column as drawn: its width, pixels, the scale of its text, and each entry's note
/// as the lines it is drawn on.
struct LegendLayout {
    width: u32,
    scale: f64,
    notes: Vec<Vec<String>>,
}

/// The legend column ([`LegendLayout`]): [`LEGEND_TEXT`] shrunk, to no less than
/// [`SMALLEST_TEXT`], when its widest entry would not fit in a third of the figure or its rows
/// in its height; a note still too wide at that size is wrapped after a comma ([`wrapped`]), so
/// that every series it names is shown.
fn legend_layout<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, labels: &[Label]) -> Result<LegendLayout, String> {
    let wide = |s: &str, size: f64| root.estimate_text_size(s, &text(size)).map(|(w, _)| w).map_err(failed);
    let (mut names, mut widest) = (0, 0);
    for label in labels {
        names = names.max(wide(&label.name, LEGEND_TEXT.0)?);
        if let Some(note) = label.note() {
            widest = widest.max(wide(&note, LEGEND_TEXT.1)?);
        }
    }
    let (w, h) = root.dim_in_pixel();
    let most = w / 3;
    let room = f64::from(most.saturating_sub(64));
    let high = f64::from(h.saturating_sub(48 + 10));
    // The scale the width allows: every line whole if the smallest text allows it, else the
    // names' and the notes wrapped.
    let least = SMALLEST_TEXT / LEGEND_TEXT.1;
    let whole = room / f64::from(names.max(widest).max(1));
    let across = if whole >= least { whole } else { (room / f64::from(names.max(1))).max(least) };
    // Each note on the lines it takes at the size the width allows.
    let mut notes = Vec::with_capacity(labels.len());
    for label in labels {
        let fits = |line: &str| Ok(f64::from(wide(line, LEGEND_TEXT.1 * across.min(1.0))?) <= room);
        notes.push(wrapped(&label.note_pieces(), fits)?);
    }
    // Its rows, top to bottom, in the figure's height below the title (draw_legend's spacing).
    let note_lines = notes.iter().map(Vec::len).sum::<usize>() as f64;
    let tall = 30.0 + LEGEND_ROWS.0 * labels.len() as f64 + LEGEND_ROWS.1 * note_lines;
    let fits = across.min(high / tall);
    let scale = if fits < 1.0 { fits.max(SMALLEST_TEXT / LEGEND_TEXT.1) } else { 1.0 };
    let mut drawn = 0;
    for line in
        labels.iter().map(|l| (&l.name, LEGEND_TEXT.0)).chain(notes.iter().flatten().map(|n| (n, LEGEND_TEXT.1)))
    {
        drawn = drawn.max(wide(line.0, line.1 * scale)?);
    }
    Ok(LegendLayout { width: (drawn + 64).clamp(140, most), scale, notes })
}

/// A note's pieces ([`Label::note_pieces`]) on as few lines as `fits` allows, broken between
/// two covering series and continued with an indent; a single piece wider than the room keeps
/// its line. No pieces, no lines.
fn wrapped(pieces: &[String], fits: impl Fn(&str) -> Result<bool, String>) -> Result<Vec<String>, String> {
    let mut lines: Vec<String> = Vec::new();
    for piece in pieces {
        match lines.last_mut() {
            Some(line) if fits(&format!("{line} {piece}"))? => *line = format!("{line} {piece}"),
            Some(_) => lines.push(format!("  {piece}")),
            None => lines.push(piece.clone()),
        }
    }
    Ok(lines)
}

/// The legend's row spacing, and the extra spacing of an entry's note, pixels at full size.
const LEGEND_ROWS: (f64, f64) = (26.0, 17.0);

/// The largest size up to `size` at which a text `wide` pixels wide at `size` fits in `room`
/// pixels (no less than [`SMALLEST_TEXT`]): the title's and the axis labels' rule.
fn fitted(size: f64, wide: u32, room: u32) -> f64 {
    if wide > room {
        (size * f64::from(room) / f64::from(wide)).floor().max(SMALLEST_TEXT)
    } else {
        size
    }
}

/// The largest size up to `size` at which `title` fits in `width` pixels, bold ([`fitted`]).
fn title_size<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    size: f64,
    width: u32,
) -> Result<f64, String> {
    Ok(fitted(size, root.estimate_text_size(title, &bold(size)).map_err(failed)?.0, width))
}

/// Where each reference line's label goes: above its line, or below it when the label above
/// would overlap the label of the line above it (two lines closer than a label's height, in
/// pixels of `height` for the range `y`); in the order of `ys`.
fn label_sides(ys: &[f64], y: (f64, f64), height: f64) -> Vec<VPos> {
    const LABEL: f64 = 18.0;
    let pixel = |v: f64| (y.1 - v) / (y.1 - y.0) * height;
    let mut order: Vec<usize> = (0..ys.len()).collect();
    order.sort_by(|&a, &b| ys[b].total_cmp(&ys[a]));
    let mut sides = vec![VPos::Bottom; ys.len()];
    let mut last_bottom = f64::NEG_INFINITY;
    for i in order {
        let at = pixel(ys[i]);
        // A label above its line spans (at − LABEL, at); below, (at, at + LABEL).
        if at - LABEL < last_bottom {
            sides[i] = VPos::Top;
            last_bottom = at + LABEL;
        } else {
            last_bottom = at;
        }
    }
    sides
}

impl Figure for Prepared<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let plot = self.plot;
        root.fill(&WHITE).map_err(failed)?;
        let (w, _) = root.dim_in_pixel();
        let (head, body) = root.split_vertically(48);
        let size = title_size(root, &plot.title, 22.0, w.saturating_sub(24))?;
        head.draw(&Text::new(
            plot.title.clone(),
            (w as i32 / 2, 14),
            bold(size).pos(Pos::new(HPos::Center, VPos::Top)),
        ))
        .map_err(failed)?;
        let layout = legend_layout(root, &self.labels)?;
        let (area, legend) = body.split_horizontally(w - layout.width);
        let (x, y) = (self.x, self.y);
        let mut chart = ChartBuilder::on(&area)
            .margin(12)
            .x_label_area_size(58)
            .y_label_area_size(88)
            .build_cartesian_2d(x.0..x.1, y.0..y.1)
            .map_err(failed)?;
        let (log_x, log_y) = (plot.scale.log_x(), plot.scale.log_y());
        let ticks =
            |(lo, hi): (f64, f64), log: bool| if log { ((hi - lo).round() as usize + 1).clamp(2, 12) } else { 10 };
        // The axis labels at 18 px, or smaller so that each fits along its axis.
        let (across, along) = chart.plotting_area().dim_in_pixel();
        let fit = |label: &str, room: u32| -> Result<f64, String> {
            Ok(fitted(18.0, root.estimate_text_size(label, &text(18.0)).map_err(failed)?.0, room))
        };
        let desc = fit(&plot.x_label, across)?.min(fit(&plot.y_label, along)?);
        let mut mesh = chart.configure_mesh();
        mesh.x_desc(plot.x_label.as_str())
            .y_desc(plot.y_label.as_str())
            .label_style(text(16.0))
            .axis_desc_style(text(desc))
            .x_labels(ticks(x, log_x))
            .y_labels(ticks(y, log_y))
            .light_line_style(RGBColor(238, 238, 238))
            .max_light_lines(if log_x || log_y { 0 } else { 1 });
        let (x_tick, y_tick) = (linear_tick(x), linear_tick(y));
        if log_x {
            mesh.x_label_formatter(&log_tick);
        } else {
            mesh.x_label_formatter(&x_tick);
        }
        if log_y {
            mesh.y_label_formatter(&log_tick);
        } else {
            mesh.y_label_formatter(&y_tick);
        }
        mesh.draw().map_err(failed)?;

        let guide = GUIDE.stroke_width(1);
        let on_x = |v: f64| if log_x { v.log10() } else { v };
        for band in &plot.bands {
            let (from, to) = (on_x(band.from), on_x(band.to));
            if from > x.0 + 1e-9 * (x.1 - x.0) {
                chart.draw_series(DashedLineSeries::new([(from, y.0), (from, y.1)], 6, 5, guide)).map_err(failed)?;
            }
            let label = Text::new(
                band.label.clone(),
                (0.5 * (from + to), y.1),
                text(16.0).color(&GUIDE).pos(Pos::new(HPos::Center, VPos::Top)),
            );
            chart.draw_series(std::iter::once(label)).map_err(failed)?;
        }
        let levels: Vec<f64> = plot.ref_lines.iter().map(|l| if log_y { l.y.log10() } else { l.y }).collect();
        let height = f64::from(chart.plotting_area().dim_in_pixel().1);
        for ((line, &yv), side) in plot.ref_lines.iter().zip(&levels).zip(label_sides(&levels, y, height)) {
            chart
                .draw_series(DashedLineSeries::new([(x.0, yv), (x.1, yv)], 10, 6, GUIDE.stroke_width(2)))
                .map_err(failed)?;
            let label = Text::new(
                line.label.clone(),
                (x.0 + 0.01 * (x.1 - x.0), yv),
                text(15.0).color(&GUIDE).pos(Pos::new(HPos::Left, side)),
            );
            chart.draw_series(std::iter::once(label)).map_err(failed)?;
        }
        for (runs, i) in self.runs.iter().zip(self.slots()) {
            let style = colour(i).stroke_width(2);
            for run in runs {
                if dashed(i) {
                    chart.draw_series(DashedLineSeries::new(run.iter().copied(), 9, 5, style)).map_err(failed)?;
                } else {
                    chart.draw_series(LineSeries::new(run.iter().copied(), style)).map_err(failed)?;
                }
                if plot.markers {
                    chart.draw_series(run.iter().map(|&p| Circle::new(p, 4, colour(i).filled()))).map_err(failed)?;
                }
            }
        }
        draw_legend(&legend, &self.labels, &layout, &self.slots().collect::<Vec<_>>(), plot.markers)
    }
}

impl Prepared<'_> {
    /// Each series' place in the palette ([`super::Series::slot`]).
    fn slots(&self) -> impl Iterator<Item = usize> + '_ {
        self.plot.series.iter().enumerate().map(|(i, s)| s.slot.unwrap_or(i))
    }
}

/// The legend: one short line (and dot) and name per series, top to bottom; a hidden series'
/// note ("under …") below it in smaller grey lines ([`LegendLayout`]).
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    labels: &[Label],
    layout: &LegendLayout,
    slots: &[usize],
    markers: bool,
) -> Result<(), String> {
    let scale = layout.scale;
    let (row, note_row) = ((LEGEND_ROWS.0 * scale).round() as i32, (LEGEND_ROWS.1 * scale).round() as i32);
    let mut y = 30;
    for ((label, note), &i) in labels.iter().zip(&layout.notes).zip(slots) {
        let style = colour(i).stroke_width(3);
        if dashed(i) {
            // Two dashes with a gap that stays visible beside a marker between them (drawn at
            // 19 px, 4 px in radius: the dashes of 4–14 and 20–30 px read as one solid line).
            let dashes: [(i32, i32); 2] = if markers { [(2, 9), (29, 36)] } else { [(4, 14), (20, 30)] };
            for (from, to) in dashes {
                area.draw(&PathElement::new(vec![(from, y), (to, y)], style)).map_err(failed)?;
            }
        } else {
            area.draw(&PathElement::new(vec![(2, y), (36, y)], style)).map_err(failed)?;
        }
        if markers {
            area.draw(&Circle::new((19, y), 4, colour(i).filled())).map_err(failed)?;
        }
        let name = text(LEGEND_TEXT.0 * scale).pos(Pos::new(HPos::Left, VPos::Center));
        area.draw(&Text::new(label.name.clone(), (44, y), name)).map_err(failed)?;
        for line in note {
            let style = text(LEGEND_TEXT.1 * scale).color(&GUIDE).pos(Pos::new(HPos::Left, VPos::Center));
            area.draw(&Text::new(line.clone(), (44, y + note_row), style)).map_err(failed)?;
            y += note_row;
        }
        y += row;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::raster::Raster;
    use super::super::style::PNG_SIZE;
    use super::*;

    #[test]
    fn a_note_too_wide_is_wrapped_between_its_series_and_keeps_every_name() {
        let label = |under: &[&str]| Label { name: "x".into(), under: under.iter().map(|n| n.to_string()).collect() };
        let hidden = label(&["modified-trapezoid, 10", "modified-sine, 10", "poly-345, 10"]);
        let fits = |n: usize| move |line: &str| Ok::<bool, String>(line.chars().count() <= n);
        let lines = wrapped(&hidden.note_pieces(), fits(32)).unwrap();
        assert_eq!(lines, ["under modified-trapezoid, 10;", "  modified-sine, 10;", "  poly-345, 10"]);
        assert!(lines.iter().all(|l| l.chars().count() <= 32));
        let whole = hidden.note().unwrap();
        assert_eq!(
            wrapped(&hidden.note_pieces(), fits(200)).unwrap(),
            std::slice::from_ref(&whole),
            "one line where it fits"
        );
        assert_eq!(whole, "under modified-trapezoid, 10; modified-sine, 10; poly-345, 10");
        assert_eq!(wrapped(&label(&["a-very-long-name"]).note_pieces(), fits(5)).unwrap(), ["under a-very-long-name"]);
        assert!(wrapped(&label(&[]).note_pieces(), fits(5)).unwrap().is_empty(), "a seen series has no note");
    }

    #[test]
    fn linear_ticks_have_the_decimals_of_their_spacing() {
        let counts = linear_tick((0.0, 19.0));
        assert_eq!([counts(&0.0), counts(&18.0)], ["0", "18"]);
        let rates = linear_tick((-0.5, 9.1));
        assert_eq!([rates(&0.0), rates(&9.0)], ["0", "9"], "a step of 1 needs no decimals");
        let torques = linear_tick((-0.33, 0.33));
        assert_eq!([torques(&-0.3), torques(&0.1), torques(&-1e-17)], ["-0.3", "0.1", "0.0"]);
        let offset = linear_tick((0.01, 5.49));
        assert_eq!(offset(&1.5), "1.5", "ten ticks 0.5 apart fit inside (0.01, 5.49)");
        let fine = linear_tick((0.0, 0.2));
        assert_eq!(fine(&0.02), "0.02", "a step of 0.02 keeps two decimals");
        let narrow = linear_tick((0.31645, 0.3166));
        assert_eq!(narrow(&0.3165), "0.31650");
    }

    #[test]
    fn reference_labels_that_would_overlap_go_below_their_line() {
        // On 400 px for 0–1, lines at 0.125 and 0.115 are 4 px apart: the lower one's label goes
        // below it (it read on top of the other's, robust.png); a line far off keeps its label
        // above; the order of the lines given does not matter.
        let below = |sides: Vec<VPos>| sides.iter().map(|s| matches!(s, VPos::Top)).collect::<Vec<_>>();
        assert_eq!(below(label_sides(&[0.115, 0.995, 0.125], (0.0, 1.0), 400.0)), [true, false, false]);
        assert_eq!(below(label_sides(&[0.2, 0.8], (0.0, 1.0), 400.0)), [false, false]);
    }

    #[test]
    fn log_ticks_read_as_powers_of_ten() {
        assert_eq!(log_tick(&-3.0), "10⁻³");
        assert_eq!(log_tick(&12.0), "10¹²");
        assert_eq!(log_tick(&0.0), "10⁰");
        assert_eq!(log_tick(&0.5), "3.2e0");
    }

    /// The torque of `torques_joint1`'s retimed bend in miniature: +9.8 N·m, a step to −9.8 N·m
    /// at t = 0.11 s, and the 0.4 N·m saw-tooth of period 1.4 ms the retimed schedule carries.
    fn step(t: f64) -> f64 {
        let saw = 0.4 * ((t / 1.4e-3).fract() - 0.5);
        if t < 0.11 {
            9.8 + saw
        } else {
            -9.8 + saw
        }
    }

    /// `plot` drawn as its PNG is (on [`Raster`]), or on plotters' plain bitmap backend; RGB.
    fn render(plot: &LinePlot, raster: bool) -> Vec<u8> {
        let prepared = Prepared::new(plot).unwrap_or_else(|e| panic!("not drawable: {e}"));
        crate::report::plot::style::ensure_fonts().ok();
        let mut buf = vec![255u8; (PNG_SIZE.0 * PNG_SIZE.1 * 3) as usize];
        {
            let bitmap = BitMapBackend::with_buffer(&mut buf, PNG_SIZE);
            let result = if raster {
                let root = Raster::new(bitmap).into_drawing_area();
                prepared.draw(&root).and_then(|()| root.present().map_err(failed))
            } else {
                let root = bitmap.into_drawing_area();
                prepared.draw(&root).and_then(|()| root.present().map_err(failed))
            };
            assert_eq!(result, Ok(()));
        }
        buf
    }

    /// Rows of the pixels painted in series 0's colour (that colour blended over white), left of
    /// the legend column (whose swatch has the same colour).
    fn curve_rows(buf: &[u8]) -> Vec<i32> {
        let RGBColor(r, g, b) = colour(0);
        let w = PNG_SIZE.0 as usize;
        let blend = |a: f64, c: u8| a * f64::from(c) + (1.0 - a) * 255.0;
        buf.chunks(3)
            .enumerate()
            .filter(|(i, p)| {
                let a = (255.0 - f64::from(p[2])) / (255.0 - f64::from(b));
                let fits = [r, g, b].iter().zip(p.iter()).all(|(&c, &v)| (blend(a, c) - f64::from(v)).abs() < 14.0);
                a > 0.25 && fits && i % w < 3 * w / 5
            })
            .map(|(i, _)| (i / w) as i32)
            .collect()
    }

    #[test]
    fn a_step_is_drawn_within_the_range_of_its_data() {
        let n = 1500;
        let points: Vec<(f64, f64)> = (0..=n).map(|k| 1.43 * k as f64 / n as f64).map(|t| (t, step(t))).collect();
        let (lo, hi) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
        let data = LinePlot::new("step", "a step", "t (s)", "τ (N·m)", vec![Series::new("step", points)]);
        // Two level lines at the data's least and greatest values: the same span, so the same axes.
        let levels = vec![(0.0, lo), (1.43, lo), (f64::NAN, 0.0), (0.0, hi), (1.43, hi)];
        let band = LinePlot::new("band", "a step", "t (s)", "τ (N·m)", vec![Series::new("step", levels)]);
        let band_rows = curve_rows(&render(&band, true));
        let (top, bottom) = (band_rows.iter().min().copied(), band_rows.iter().max().copied());
        let (Some(top), Some(bottom)) = (top, bottom) else { panic!("the level lines were not drawn") };
        let rows = curve_rows(&render(&data, true));
        assert!(rows.len() > 1000, "the step is hardly drawn: {} pixels", rows.len());
        let outside: Vec<i32> = rows.iter().copied().filter(|r| !(top..=bottom).contains(r)).collect();
        assert!(outside.is_empty(), "rows {outside:?} lie outside the data's band {top} ..= {bottom}");
        // plotters' own stroke of the same data strays outside it (the 27 N·m spike).
        let plain = curve_rows(&render(&data, false));
        let strays = plain.iter().filter(|r| !(top..=bottom).contains(r)).count();
        assert!(strays > 0, "plotters' own stroke stays inside the band (flaw gone?)");
    }

    #[test]
    fn non_finite_points_break_the_line() {
        let s = Series::new("s", vec![(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0), (3.0, 4.0)]);
        let plot = LinePlot::new("x", "t", "x", "y", vec![s]);
        let lengths = Prepared::new(&plot).map(|p| p.runs[0].iter().map(Vec::len).collect::<Vec<_>>());
        assert_eq!(lengths, Ok(vec![1, 2]));
    }
}
