//! Expansion of a sweep into cases: each case is the base problem plus one value per axis, applied
//! as `--set field=value` overrides through [`Problem::from_toml`], so a case is validated, and
//! refused, with the problem file's own messages.
//!
//! Order: with `combine = "product"` the first axis varies slowest (nested loops in file order);
//! with `"zip"` case `k` takes the `k`-th value of every axis. A case's index in that order is its
//! identity: shards slice by it, and every output is sorted by it.

use crate::problem::Problem;

use super::spec::{Combine, Sweep};

/// One case of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    /// Index in the sweep's order, from 0.
    pub index: usize,
    /// Per axis, the index of its value.
    pub picks: Vec<usize>,
    /// The overrides `field=value`, one per axis.
    pub overrides: Vec<String>,
}

impl Case {
    /// The case's problem, or the one-line reason the problem file refuses it.
    pub fn problem(&self, sweep: &Sweep) -> Result<Problem, String> {
        Problem::from_toml(&sweep.base_text, &sweep.base_origin, &self.overrides)
            .and_then(|p| p.require_no_spin("a sweep").and_then(|()| p.require_paper_cat("a sweep")).map(|()| p))
            .map_err(|e| super::spec::one_line(&e.to_string()))
    }
}

/// The `index`-th case of a sweep (`index < sweep.case_count()`).
pub fn case(sweep: &Sweep, index: usize) -> Case {
    let picks: Vec<usize> = match sweep.combine {
        Combine::Zip => sweep.axes.iter().map(|_| index).collect(),
        Combine::Product => {
            let mut rest = index;
            let mut picks = vec![0; sweep.axes.len()];
            for (i, axis) in sweep.axes.iter().enumerate().rev() {
                let n = axis.values.len().max(1);
                picks[i] = rest % n;
                rest /= n;
            }
            picks
        }
    };
    let overrides =
        sweep.axes.iter().zip(&picks).map(|(a, &k)| format!("{}={}", a.field, a.values[k])).collect::<Vec<_>>();
    Case { index, picks, overrides }
}

/// Every case of a sweep, in order.
pub fn cases(sweep: &Sweep) -> Vec<Case> {
    (0..sweep.case_count()).map(|i| case(sweep, i)).collect()
}

/// An axis value as a CSV cell: a string without its quotes, a number as written (floats with
/// round-trip precision), anything else as TOML.
pub fn cell(value: &toml::Value) -> String {
    match value {
        toml::Value::String(s) => s.clone(),
        toml::Value::Float(x) => format!("{x:?}"),
        other => other.to_string(),
    }
}
