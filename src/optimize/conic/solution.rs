//! What a conic solve returns besides its iterate: how it ended ([`QpStatus`], Clarabel's
//! `SolverStatus` one for one, in words for reports) and Clarabel's diagnostics ([`SolveInfo`]).
//! An outcome short of a solution is a status, not an error (module docs of the layer).

use clarabel::solver::SolverStatus;
use serde::Serialize;

/// How a solve ended: Clarabel's `SolverStatus`, one for one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum QpStatus {
    /// Clarabel did not run.
    Unsolved,
    /// Solved to the requested tolerances.
    Solved,
    /// Solved to Clarabel's reduced tolerances.
    AlmostSolved,
    /// No point meets the constraints; the iterate is a certificate of infeasibility.
    PrimalInfeasible,
    /// The objective is unbounded below; the iterate is a certificate.
    DualInfeasible,
    /// Primal infeasible to reduced tolerances.
    AlmostPrimalInfeasible,
    /// Dual infeasible to reduced tolerances.
    AlmostDualInfeasible,
    /// The iteration limit was reached first.
    MaxIterations,
    /// The time limit was reached first.
    MaxTime,
    /// Clarabel stopped on a numerical error.
    NumericalError,
    /// Clarabel stopped for lack of progress.
    InsufficientProgress,
    /// A user callback stopped the solve.
    CallbackTerminated,
}

impl From<SolverStatus> for QpStatus {
    fn from(status: SolverStatus) -> Self {
        match status {
            SolverStatus::Unsolved => QpStatus::Unsolved,
            SolverStatus::Solved => QpStatus::Solved,
            SolverStatus::AlmostSolved => QpStatus::AlmostSolved,
            SolverStatus::PrimalInfeasible => QpStatus::PrimalInfeasible,
            SolverStatus::DualInfeasible => QpStatus::DualInfeasible,
            SolverStatus::AlmostPrimalInfeasible => QpStatus::AlmostPrimalInfeasible,
            SolverStatus::AlmostDualInfeasible => QpStatus::AlmostDualInfeasible,
            SolverStatus::MaxIterations => QpStatus::MaxIterations,
            SolverStatus::MaxTime => QpStatus::MaxTime,
            SolverStatus::NumericalError => QpStatus::NumericalError,
            SolverStatus::InsufficientProgress => QpStatus::InsufficientProgress,
            SolverStatus::CallbackTerminated => QpStatus::CallbackTerminated,
        }
    }
}

impl std::fmt::Display for QpStatus {
    /// How the solve ended, in words (never Clarabel's variant names).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            QpStatus::Unsolved => "not run",
            QpStatus::Solved => "solved",
            QpStatus::AlmostSolved => "solved to reduced accuracy",
            QpStatus::PrimalInfeasible => "infeasible: no profile meets the constraints",
            QpStatus::DualInfeasible => "unbounded: the objective has no minimum",
            QpStatus::AlmostPrimalInfeasible => "infeasible to reduced accuracy: no profile meets the constraints",
            QpStatus::AlmostDualInfeasible => "unbounded to reduced accuracy",
            QpStatus::MaxIterations => "stopped at the iteration limit before converging",
            QpStatus::MaxTime => "stopped at the time limit before converging",
            QpStatus::NumericalError => "stopped on a numerical error",
            QpStatus::InsufficientProgress => "stopped for lack of progress",
            QpStatus::CallbackTerminated => "stopped by a callback",
        })
    }
}

impl QpStatus {
    /// Whether the iterate is a solution, to full or reduced accuracy.
    pub fn is_solved(self) -> bool {
        matches!(self, QpStatus::Solved | QpStatus::AlmostSolved)
    }

    /// Whether Clarabel certified the constraints infeasible, to full or reduced accuracy.
    pub fn is_infeasible(self) -> bool {
        matches!(self, QpStatus::PrimalInfeasible | QpStatus::AlmostPrimalInfeasible)
    }
}

/// Clarabel's account of a solve (its `DefaultInfo`), for reports and for the outer loop.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SolveInfo {
    /// Interior-point iterations.
    pub iterations: u32,
    /// Setup and solve time as Clarabel measured it, s.
    pub solve_time_s: f64,
    /// Clarabel's relative primal residual, of the normalised problem (dimensionless).
    pub primal_residual: f64,
    /// Clarabel's relative dual residual, of the normalised problem (dimensionless).
    pub dual_residual: f64,
    /// Absolute duality gap, in the units of the objective.
    pub duality_gap: f64,
    /// Relative duality gap (dimensionless).
    pub relative_gap: f64,
}
