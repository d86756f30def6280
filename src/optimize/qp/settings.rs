//! Settings of the interior-point solve (Clarabel's), with their defaults in one place, and the
//! one call to Clarabel that every program here makes ([`solve_clarabel`]).
//!
//! Clarabel refines each solution of its regularised KKT system iteratively by default. Our
//! programs are scaled to order one, and the interior-point iteration converges on its own true
//! residuals either way, so a solve runs without that refinement first and again with it only
//! when it ends short of a full answer ([`needs_refinement`]); the reported time is both runs'.
//! Measured on `catflip run problems/paper.toml` (profile QP, refinement LPs, whole-manoeuvre
//! subproblems, retiming SOCPs): the retiming bounds move by at most 6e-9 and the whole
//! optimum's energy by 7e-11 (relative), the stalled refinement's peak by 1.4e-6, and the run
//! takes 17 % less CPU time (3.72 → 3.09 s).

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SupportedConeT};
use serde::{Deserialize, Serialize};

use super::{bad, positive, QpError, QpStatus};

/// How hard Clarabel works on a QP. The tolerances apply to the normalised problem (see the
/// module docs), where the peak coefficient is of order one.
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
    pub fn validate(&self) -> Result<(), QpError> {
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
    pub(crate) fn clarabel(&self, refine: bool) -> Result<DefaultSettings<f64>, QpError> {
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
            .map_err(|e| QpError::Setup(e.to_string()))
    }
}

/// Whether a solve made without iterative refinement is repeated with it: any outcome short of
/// a full-accuracy solution or certificate, except the user's time limit.
pub(crate) fn needs_refinement(status: QpStatus) -> bool {
    !matches!(
        status,
        QpStatus::Solved
            | QpStatus::PrimalInfeasible
            | QpStatus::DualInfeasible
            | QpStatus::MaxTime
            | QpStatus::CallbackTerminated
    )
}

/// Solves `min ½xᵀPx + qᵀx` s.t. `Ax + s = b`, `s ∈ cones` with Clarabel (module docs: first
/// without iterative refinement, then, if needed, with it); returns the solver holding the
/// final solution and the time of both solves, s.
pub(crate) fn solve_clarabel(
    settings: &QpSettings,
    p: &CscMatrix<f64>,
    q: &[f64],
    a: &CscMatrix<f64>,
    b: &[f64],
    cones: &[SupportedConeT<f64>],
) -> Result<(DefaultSolver<f64>, f64), QpError> {
    let run = |refine: bool| -> Result<DefaultSolver<f64>, QpError> {
        let mut solver = DefaultSolver::new(p, q, a, b, cones, settings.clarabel(refine)?)
            .map_err(|e| QpError::Setup(e.to_string()))?;
        solver.solve();
        Ok(solver)
    };
    let first = run(false)?;
    if !needs_refinement(first.solution.status.into()) {
        let time = first.solution.solve_time;
        return Ok((first, time));
    }
    let second = run(true)?;
    let time = first.solution.solve_time + second.solution.solve_time;
    Ok((second, time))
}

#[cfg(test)]
mod tests {
    use super::{needs_refinement, QpStatus};

    #[test]
    fn only_an_answer_short_of_full_accuracy_is_solved_again() {
        for done in [QpStatus::Solved, QpStatus::PrimalInfeasible, QpStatus::DualInfeasible, QpStatus::MaxTime] {
            assert!(!needs_refinement(done), "{done:?} was solved again");
        }
        for short in [
            QpStatus::AlmostSolved,
            QpStatus::AlmostPrimalInfeasible,
            QpStatus::MaxIterations,
            QpStatus::NumericalError,
            QpStatus::InsufficientProgress,
        ] {
            assert!(needs_refinement(short), "{short:?} was kept");
        }
    }
}
