//! Joint-rate jumps between the pieces of any [`Trajectory`], with the impulse each needs.
//!
//! At the boundary between pieces `k` and `k + 1` the rates may jump from `q̇⁻` (piece `k`'s
//! end) to `q̇⁺` (piece `k + 1`'s start). The joint then delivers the generalised impulse
//! `M(q) (q̇⁺ − q̇⁻)`, N·m·s, with `M` the reduced zero-momentum mass matrix
//! ([`generalised_impulse`]): an impulse, not a torque. A jump smaller than
//! [`JUMP_TOLERANCE`] relative to `max(1 rad/s, |q̇⁻|, |q̇⁺|)` is round-off and not reported; nor
//! is one within the rates' own uncertainty at that boundary (for rates that come from an
//! interpolant, not from a formula or a file: see [`crate::exchange::import`]).

use serde::{Deserialize, Serialize};

use crate::engines::torque::generalised_impulse;
use crate::engines::JUMP_TOLERANCE;
use crate::model::Cylinder;
use crate::schedule::Trajectory;

/// A jump of the joint rates at a piece boundary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Jump {
    /// Time of the jump from the trajectory's start, s.
    pub time_s: f64,
    /// Index of the piece that ends there (the next one starts there).
    pub after_piece: usize,
    /// Rates just before, rad/s.
    pub rates_before_rad_s: [f64; 2],
    /// Rates just after, rad/s.
    pub rates_after_rad_s: [f64; 2],
    /// The motors' impulse on joints 1 and 2 (on the universal joint the generalised impulse
    /// `M(q) Δq̇`), N·m·s.
    pub impulse_nms: [f64; 2],
}

/// The rate jumps of `traj` at its piece boundaries whose rates are exact (formulas or data).
pub fn rate_jumps(cat: &Cylinder, traj: &impl Trajectory) -> Vec<Jump> {
    uncertain_rate_jumps(cat, traj, |_| 0.0)
}

/// The rate jumps of `traj` larger than `uncertainty(k)`, the uncertainty (rad/s, Euclidean) of
/// the rate difference at the boundary after piece `k`.
pub fn uncertain_rate_jumps(cat: &Cylinder, traj: &impl Trajectory, uncertainty: impl Fn(usize) -> f64) -> Vec<Jump> {
    rate_jumps_by(|q, dq| generalised_impulse(cat, q, dq), traj, uncertainty)
}

/// [`uncertain_rate_jumps`] with the motor impulse `impulse(q, Δq̇)` of any two-motor model
/// ([`crate::engines::models::TwoMotorCat::motor_impulse`]; on the universal joint the generalised
/// impulse `M(q) Δq̇`).
pub fn rate_jumps_by(
    impulse: impl Fn([f64; 2], [f64; 2]) -> [f64; 2],
    traj: &impl Trajectory,
    uncertainty: impl Fn(usize) -> f64,
) -> Vec<Jump> {
    let durations = traj.piece_durations();
    let mut out = Vec::new();
    let mut time = 0.0;
    for (k, &duration) in durations.iter().enumerate().take(durations.len().saturating_sub(1)) {
        time += duration;
        let before = traj.piece_state(k, duration);
        let after = traj.piece_state(k + 1, 0.0);
        let dq = [after.qd[0] - before.qd[0], after.qd[1] - before.qd[1]];
        let scale =
            [1.0, before.qd[0].hypot(before.qd[1]), after.qd[0].hypot(after.qd[1])].into_iter().fold(0.0, f64::max);
        if dq[0].hypot(dq[1]) <= (JUMP_TOLERANCE * scale).max(uncertainty(k)) {
            continue;
        }
        let impulse = impulse(after.q, dq);
        out.push(Jump {
            time_s: time,
            after_piece: k,
            rates_before_rad_s: before.qd,
            rates_after_rad_s: after.qd,
            impulse_nms: impulse,
        });
    }
    out
}
