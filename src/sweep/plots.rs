//! The sweep's figures: each quantity ([`quantities`]) as heat maps over the first two numeric
//! axes (one per combination of the other axes) and as a line plot along the first numeric axis
//! (one series per combination of the others), PNG + SVG in `plots/`.

use std::path::Path;

use crate::report::plot::{line_plot, LinePlot, PlotError, Series};

use super::grid::{grids, layout, primary_schedule, Grid};
use super::heatmap::{heat_map, HeatMap};
use super::row::SweepSchedule;
use super::spec::Sweep;
use super::table::Record;

/// At most this many heat maps per quantity.
pub const MAX_FIGURES: usize = 10;
/// At most this many series per line plot.
pub const MAX_SERIES: usize = 20;

/// A figure written, for the summary to show.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotInfo {
    /// File name of the PNG (the SVG beside it has the same stem).
    pub file: String,
    /// The SVG's file name.
    pub svg: String,
    /// What it shows.
    pub caption: String,
}

/// A quantity the summary and the plots show.
pub struct Quantity {
    /// File-name stem.
    pub stem: &'static str,
    /// What it is, with its unit.
    pub label: String,
    /// The schedule whose rows carry it.
    pub schedule: SweepSchedule,
    /// Its value on a row.
    pub value: fn(&Record) -> Option<f64>,
}

/// The quantities a sweep computed.
pub fn quantities(sweep: &Sweep) -> Vec<Quantity> {
    let c = &sweep.compute;
    let mut q = Vec::new();
    if c.calibrated {
        q.push(Quantity {
            stem: "pi-over-c-error",
            label: "π/C error (calibrated − π/C)/(π/C), %".into(),
            schedule: SweepSchedule::Calibrated,
            value: |r| r.circulation_rel_error().map(|e| 100.0 * e),
        });
    }
    if c.paper_flip {
        q.push(Quantity {
            stem: "paper-flip-error",
            label: "flip error of π/C, |twist| − 180°, degrees".into(),
            schedule: SweepSchedule::Paper,
            value: |r| r.numbers.map(|n| n.flip_error_deg),
        });
    }
    if c.peaks && (c.calibrated || c.paper_flip) {
        let s = primary_schedule(sweep);
        q.push(Quantity {
            stem: "peak-torque",
            label: format!("peak torque ({s} circulation), N·m"),
            schedule: s,
            value: Record::peak_max,
        });
    }
    if c.retiming {
        q.push(Quantity {
            stem: "retimed-peak",
            label: "peak torque of the certified retiming (exact), N·m".into(),
            schedule: SweepSchedule::Retimed,
            value: Record::peak_max,
        });
    }
    if c.whole && min_time(sweep) {
        q.push(Quantity {
            stem: "drop-height",
            label: "least drop height g·T²/2 within the motors (whole optimum, min-time), m".into(),
            schedule: SweepSchedule::Whole,
            value: |r| r.numbers.and_then(|n| n.whole).map(|w| w.drop_height_m),
        });
    }
    if c.whole {
        q.push(Quantity {
            stem: "whole-peak",
            label: "peak torque of the whole-manoeuvre optimum, N·m".into(),
            schedule: SweepSchedule::Whole,
            value: Record::peak_max,
        });
    }
    q
}

/// Whether a sweep's whole optimum minimises the fall time: the base problem's
/// `optimize.whole.objective` is `min-time`, or an axis sweeps the objective.
pub fn min_time(sweep: &Sweep) -> bool {
    let base = crate::problem::Problem::from_toml(&sweep.base_text, &sweep.base_origin, &[]);
    base.is_ok_and(|p| p.optimize.whole.objective == crate::optimize::whole::Objective::MinTime)
        || sweep.axes.iter().any(|a| a.field == "optimize.whole.objective")
}

/// Writes every figure into `dir` and returns them in order.
pub fn plots(sweep: &Sweep, records: &[Record], dir: &Path) -> Result<Vec<PlotInfo>, PlotError> {
    let lay = layout(sweep);
    let mut out = Vec::new();
    let mut record = |stem: String, caption: String| {
        out.push(PlotInfo { file: format!("{stem}.png"), svg: format!("{stem}.svg"), caption });
    };
    for q in quantities(sweep) {
        let gs = grids(sweep, records, q.schedule, q.value);
        if let (Some(r), Some(c)) = (lay.rows, lay.cols) {
            for (k, g) in gs.iter().take(MAX_FIGURES).enumerate() {
                let stem = format!("heatmap-{}-{}", q.stem, k + 1);
                let title = title(&sweep.name, &g.group);
                let map = HeatMap {
                    stem: stem.clone(),
                    title,
                    x_label: with_unit(&sweep.axes[c].field),
                    y_label: with_unit(&sweep.axes[r].field),
                    value_label: q.label.clone(),
                    cols: g.col_labels.clone(),
                    rows: g.row_labels.clone(),
                    cells: g.cells.clone(),
                };
                match heat_map(dir, &map) {
                    Ok(_) => record(stem, format!("{} — {}", q.label, none_to_all(&g.group))),
                    Err(PlotError::NoData { .. }) => {}
                    Err(e) => return Err(e),
                }
            }
        }
        if let Some(r) = lay.rows {
            if !sweep.axes[r].values.is_empty() {
                let series = line_series(&gs, lay.cols);
                let stem = format!("line-{}", q.stem);
                let fields = series_fields(sweep, &lay);
                let axis = along(sweep, r, with_unit(&sweep.axes[r].field));
                let x_label = if fields.is_empty() { axis } else { format!("{axis}        (series: {fields})") };
                let plot = LinePlot {
                    markers: true,
                    ..LinePlot::new(
                        stem.clone(),
                        format!("{}: {}", sweep.name, q.label),
                        x_label,
                        q.label.clone(),
                        series,
                    )
                };
                match line_plot(dir, &plot) {
                    Ok(_) => {
                        record(stem, format!("{} along {}", q.label, along(sweep, r, sweep.axes[r].field.clone())))
                    }
                    Err(PlotError::NoData { .. }) => {}
                    Err(e) => return Err(e),
                }
            }
        }
    }
    Ok(out)
}

/// An axis label: the field with its unit, e.g. `cat.mass (kg)`, `actuator.stall_torque_nm (N·m)`.
pub fn with_unit(field: &str) -> String {
    let unit = match field {
        "cat.mass" => Some("kg"),
        "cat.length" | "cat.radius" | "drop.height" => Some("m"),
        "drop.gravity" => Some("m/s²"),
        _ => [("_nm", "N·m"), ("_rad_s", "rad/s"), ("_w", "W"), ("_deg", "°"), ("_s", "s")]
            .into_iter()
            .find(|(suffix, _)| field.ends_with(suffix))
            .map(|(_, u)| u),
    };
    unit.map_or_else(|| field.to_string(), |u| format!("{field} ({u})"))
}

fn title(name: &str, group: &str) -> String {
    if group.is_empty() {
        format!("sweep {name}")
    } else {
        format!("sweep {name}: {group}")
    }
}

fn none_to_all(group: &str) -> &str {
    if group.is_empty() {
        "all cases"
    } else {
        group
    }
}

/// One series per group × column value, at most [`MAX_SERIES`], named by the values alone (the
/// title names their fields).
fn line_series(gs: &[Grid], cols: Option<usize>) -> Vec<Series> {
    let mut out = Vec::new();
    for g in gs {
        for (j, col) in g.col_labels.iter().enumerate() {
            let mut name: Vec<String> = g.group_values.clone();
            if cols.is_some() {
                name.push(col.clone());
            }
            let points = g.row_values.iter().zip(&g.cells).map(|(&x, row)| (x, row[j].unwrap_or(f64::NAN))).collect();
            out.push(Series::new(if name.is_empty() { "all".to_string() } else { name.join(", ") }, points));
        }
    }
    out.truncate(MAX_SERIES);
    out
}

/// The axis `r` a line plot runs along, named `name`, with the axes zipped with it
/// (`cat.radius (m), with drop.height zipped`).
fn along(sweep: &Sweep, r: usize, name: String) -> String {
    let zipped: Vec<&str> =
        super::grid::zipped_with(sweep, r).into_iter().map(|a| sweep.axes[a].field.as_str()).collect();
    if zipped.is_empty() {
        name
    } else {
        format!("{name}, with {} zipped", zipped.join(", "))
    }
}

/// The fields the series of a line plot are named by: the group axes, then the columns axis.
fn series_fields(sweep: &Sweep, lay: &super::grid::Layout) -> String {
    let fields: Vec<String> =
        lay.groups.iter().chain(lay.cols.iter()).map(|&a| with_unit(&sweep.axes[a].field)).collect();
    fields.join(", ")
}
