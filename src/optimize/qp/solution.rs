//! What a solve returns: how it ended, the profile, and Clarabel's diagnostics.

use clarabel::solver::SolverStatus;
use serde::Serialize;

use crate::schedule::profile::Profile;

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
    /// No profile meets the constraints; the iterate is a certificate of infeasibility.
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

/// The solution of a [`ProfileQp`](super::ProfileQp), whatever the status: when the status is
/// not [`QpStatus::is_solved`], `rates` holds Clarabel's last iterate (for an infeasible
/// problem, the certificate), reported as it is.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ProfileQpSolution {
    /// How the solve ended.
    pub status: QpStatus,
    /// Circulation rate `ω_k` at the `N` equally spaced nodes of the twist phase, rad/s.
    pub rates: Vec<f64>,
    /// The model's peak torque `I* max_k |ω_{k+1} − ω_k| / h` of `rates`, N·m; `None` unless
    /// solved.
    pub peak_torque: Option<f64>,
    /// The objective (epigraph bound plus smoothness term), N·m; `None` unless solved.
    pub objective: Option<f64>,
    /// Clarabel's diagnostics.
    #[serde(flatten)]
    pub info: SolveInfo,
}

impl ProfileQpSolution {
    /// The solution if the QP was solved (to full or reduced accuracy), else
    /// [`crate::optimize::qp::QpError::NotSolved`] with the status: for a caller whose result does not exist without it.
    pub fn solved(self) -> Result<ProfileQpSolution, super::QpError> {
        if self.status.is_solved() {
            Ok(self)
        } else {
            Err(super::QpError::NotSolved { status: self.status })
        }
    }

    /// The rate nodes as a profile (linear between nodes, normalised to unit circulation); `None`
    /// unless the QP was solved, or when the rates have no circulation.
    pub fn to_profile(&self) -> Option<Profile> {
        if !self.status.is_solved() {
            return None;
        }
        Profile::from_rate_nodes(crate::schedule::variant::Origin::Qp.profile_name(), &self.rates)
    }
}

/// `max_k |x_{k+1} − x_k|`; zero for fewer than two values.
pub(crate) fn max_abs_difference(x: &[f64]) -> f64 {
    x.windows(2).map(|w| (w[1] - w[0]).abs()).fold(0.0, f64::max)
}
