//! What the profile QP's solve returns: how it ended, the rate nodes, and Clarabel's diagnostics.

use serde::Serialize;

use super::QpError;
use crate::optimize::conic::{QpStatus, SolveInfo};
use crate::schedule::profile::Profile;

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
    /// [`QpError::NotSolved`] with the status: for a caller whose result does not exist without it.
    pub fn solved(self) -> Result<ProfileQpSolution, QpError> {
        if self.status.is_solved() {
            Ok(self)
        } else {
            Err(QpError::NotSolved { status: self.status })
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
