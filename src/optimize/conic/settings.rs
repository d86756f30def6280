//! Settings of the interior-point solve (Clarabel's), with their defaults in one place.

use clarabel::solver::{DefaultSettings, DefaultSettingsBuilder};
use serde::{Deserialize, Serialize};

use super::error::{bad, positive, ConicError};

/// How hard Clarabel works on a conic program. The tolerances apply to the normalised problem
/// each program poses (the profile QP's module docs, for one), where the peak coefficient is of
/// order one.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct QpSettings {
    /// Most interior-point iterations before the solve stops with
    /// [`QpStatus::MaxIterations`](super::QpStatus::MaxIterations).
    pub max_iterations: u32,
    /// Wall-clock limit of one solve, s; none when absent.
    pub time_limit: Option<f64>,
    /// Absolute and relative duality-gap tolerance and feasibility tolerance.
    pub tolerance: f64,
}

impl Default for QpSettings {
    fn default() -> Self {
        Self { max_iterations: 200, time_limit: None, tolerance: 1e-8 }
    }
}

impl QpSettings {
    /// Checks every field; names the first one that is wrong.
    pub fn validate(&self) -> Result<(), ConicError> {
        if self.max_iterations == 0 {
            return Err(bad("max_iterations", self.max_iterations, "must be at least 1"));
        }
        if let Some(limit) = self.time_limit {
            positive("time_limit", limit)?;
        }
        positive("tolerance", self.tolerance)?;
        if !(1e-14..=1e-2).contains(&self.tolerance) {
            return Err(bad("tolerance", self.tolerance, "must lie in [1e-14, 1e-2]"));
        }
        Ok(())
    }

    /// Clarabel's settings: these, printing off, iterative refinement of the KKT solves as
    /// `refine` says, the rest Clarabel's defaults.
    pub(crate) fn clarabel(&self, refine: bool) -> Result<DefaultSettings<f64>, ConicError> {
        self.validate()?;
        DefaultSettingsBuilder::default()
            .verbose(false)
            .iterative_refinement_enable(refine)
            .max_iter(self.max_iterations)
            .time_limit(self.time_limit.unwrap_or(f64::INFINITY))
            .tol_gap_abs(self.tolerance)
            .tol_gap_rel(self.tolerance)
            .tol_feas(self.tolerance)
            .build()
            .map_err(|e| ConicError::Setup(e.to_string()))
    }
}
