//! One quantity of a sweep laid out over its axes, for the summary's tables and the plots.
//!
//! The first numeric axis with more than one value gives the rows (the x axis of line plots), the
//! second the columns (a heat map's x axis); every other axis makes groups, one grid per
//! combination of their values, in case order.

use super::cases::cell;
use super::row::SweepSchedule;
use super::spec::Sweep;
use super::table::Record;
use crate::engines::Engine;
use crate::numeric::numfmt::sig;

/// Which axes play which part.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Axis giving the rows.
    pub rows: Option<usize>,
    /// Axis giving the columns.
    pub cols: Option<usize>,
    /// The other axes.
    pub groups: Vec<usize>,
}

/// The layout of a sweep. Zipped axes vary together: the first numeric one gives the rows alone.
pub fn layout(sweep: &Sweep) -> Layout {
    if sweep.combine == super::spec::Combine::Zip {
        let rows = (0..sweep.axes.len()).find(|&i| sweep.axes[i].numeric && sweep.axes[i].values.len() > 1);
        return Layout { rows, cols: None, groups: Vec::new() };
    }
    let mut numeric = (0..sweep.axes.len()).filter(|&i| sweep.axes[i].numeric && sweep.axes[i].values.len() > 1);
    let rows = numeric.next();
    let cols = numeric.next();
    let groups = (0..sweep.axes.len()).filter(|&i| Some(i) != rows && Some(i) != cols).collect();
    Layout { rows, cols, groups }
}

/// One quantity over the rows and columns axes, for one combination of the group axes.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// `field = value` of each group axis, joined by `, ` (empty with no group axis).
    pub group: String,
    /// The group axes' values alone, as labels.
    pub group_values: Vec<String>,
    /// Row labels (the row axis' values, four significant digits, integers whole; with
    /// `combine = "zip"` the zipped axes' values beside each).
    pub row_labels: Vec<String>,
    /// Row values as numbers (for line plots), NaN where not numeric.
    pub row_values: Vec<f64>,
    /// Column labels.
    pub col_labels: Vec<String>,
    /// `cells[row][col]`, `None` where the quantity does not exist.
    pub cells: Vec<Vec<Option<f64>>>,
}

/// A value as a number, if it is one.
fn number(v: &toml::Value) -> Option<f64> {
    v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
}

/// A value as a label: an integer whole, a float to four significant digits without trailing
/// zeros (`2` and `10`, not `2.000` beside `10.00`; a log range's `0.1516`), anything else as its
/// CSV cell.
fn label(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(x) => sig(*x, 4),
        other => cell(other),
    }
}

/// The axes zipped with axis `r` (every other axis, with `combine = "zip"`; none otherwise).
pub fn zipped_with(sweep: &Sweep, r: usize) -> Vec<usize> {
    if sweep.combine != super::spec::Combine::Zip {
        return Vec::new();
    }
    (0..sweep.axes.len()).filter(|&a| a != r).collect()
}

/// The labels and numeric values of an axis (one unnamed entry when there is no such axis).
fn labels(sweep: &Sweep, axis: Option<usize>) -> (Vec<String>, Vec<f64>) {
    match axis {
        Some(a) => sweep.axes[a].values.iter().map(|v| (label(v), number(v).unwrap_or(f64::NAN))).unzip(),
        None => (vec![String::new()], vec![f64::NAN]),
    }
}

/// The grids of `quantity` on the rows of `schedule` (engine `exact`), one per group, in case
/// order.
pub fn grids(
    sweep: &Sweep,
    records: &[Record],
    schedule: SweepSchedule,
    quantity: impl Fn(&Record) -> Option<f64>,
) -> Vec<Grid> {
    let lay = layout(sweep);
    let (mut row_labels, row_values) = labels(sweep, lay.rows);
    if let Some(r) = lay.rows {
        // The axes zipped with the rows' change with them: each row names their values too,
        // or a table along one axis would credit it with the others' effect.
        for (k, row) in row_labels.iter_mut().enumerate() {
            let partners: Vec<String> = zipped_with(sweep, r)
                .into_iter()
                .map(|a| format!("{} = {}", sweep.axes[a].field, label(&sweep.axes[a].values[k])))
                .collect();
            if !partners.is_empty() {
                *row = format!("{row} ({})", partners.join(", "));
            }
        }
    }
    let (col_labels, _) = labels(sweep, lay.cols);
    let mut keys: Vec<Vec<usize>> = Vec::new();
    let mut out: Vec<Grid> = Vec::new();
    for r in records.iter().filter(|r| r.schedule == schedule && r.engine == Engine::Exact) {
        let key: Vec<usize> = lay.groups.iter().map(|&g| r.picks[g]).collect();
        let g = match keys.iter().position(|k| *k == key) {
            Some(g) => g,
            None => {
                let group = lay
                    .groups
                    .iter()
                    .zip(&key)
                    .map(|(&a, &k)| format!("{} = {}", sweep.axes[a].field, label(&sweep.axes[a].values[k])))
                    .collect::<Vec<_>>()
                    .join(", ");
                let group_values =
                    lay.groups.iter().zip(&key).map(|(&a, &k)| label(&sweep.axes[a].values[k])).collect();
                keys.push(key);
                out.push(Grid {
                    group,
                    group_values,
                    row_labels: row_labels.clone(),
                    row_values: row_values.clone(),
                    col_labels: col_labels.clone(),
                    cells: vec![vec![None; col_labels.len()]; row_labels.len()],
                });
                out.len() - 1
            }
        };
        let i = lay.rows.map_or(0, |a| r.picks[a]);
        let j = lay.cols.map_or(0, |a| r.picks[a]);
        out[g].cells[i][j] = quantity(r).filter(|v| v.is_finite());
    }
    out
}

/// The schedule whose torques the summary ranks by: the calibrated one when computed.
pub fn primary_schedule(sweep: &Sweep) -> SweepSchedule {
    if sweep.compute.calibrated {
        SweepSchedule::Calibrated
    } else {
        SweepSchedule::Paper
    }
}
