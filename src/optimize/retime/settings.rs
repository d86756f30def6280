//! Settings of the retiming program, with their defaults in one place.

use serde::{Deserialize, Serialize};

use super::{positive, RetimeError};
use crate::optimize::conic::QpSettings;

/// How the total duration is shared between the pieces of the path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Split {
    /// Each piece keeps its share of the path parameter: piece `i` takes `T S_i / S` (for a path
    /// timed by its local time, the original split of the phases).
    Kept,
    /// Only the total duration is fixed; the program chooses the split.
    Free,
}

/// What the retiming program solves and how hard Clarabel works at it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RetimeSettings {
    /// Grid intervals `N` per piece (the grid has `N + 1` nodes, ends included).
    pub intervals: usize,
    /// How the duration is shared between pieces.
    pub split: Split,
    /// Bound on the path rate `|ṡ|`, in units of `s` per second; none when absent.
    pub rate_limit: Option<f64>,
    /// Bound on the path acceleration `|s̈|`, in units of `s` per second squared; none when
    /// absent.
    pub accel_limit: Option<f64>,
    /// Clarabel's iteration limit, time limit and tolerances (of the normalised program).
    pub solver: QpSettings,
}

impl Default for RetimeSettings {
    fn default() -> Self {
        Self { intervals: 200, split: Split::Kept, rate_limit: None, accel_limit: None, solver: QpSettings::default() }
    }
}

impl RetimeSettings {
    /// Checks every field; names the first one that is wrong.
    pub fn validate(&self) -> Result<(), RetimeError> {
        if self.intervals < 2 {
            return Err(super::bad(
                "intervals",
                self.intervals,
                "must be at least 2 (a piece at rest at both ends needs an interior node)",
            ));
        }
        if let Some(r) = self.rate_limit {
            positive("rate_limit", r)?;
        }
        if let Some(a) = self.accel_limit {
            positive("accel_limit", a)?;
        }
        self.solver.validate()?;
        Ok(())
    }
}
