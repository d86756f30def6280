//! A cat beyond two motors (the spherical joint, a tail) within one torque limit on every motor
//! ([`super::scope::MotorsBeyond::TorqueLimit`]): planned for the least peak torque with ideal
//! motors, then held to the limit by the exact scaling of a zero-momentum flip (DESIGN.md §9).
//!
//! Slowing a path by `k` (`q(t/k)`) leaves the flip unchanged at zero angular momentum and divides
//! every torque by `k²` (each is linear in `q̈` and quadratic in `q̇`). So within `|τ_j| ≤ τ_max`:
//! - the least fall time is the least-peak path at the problem's fall `T` slowed by
//!   `k = √(peak/τ_max)`, `T* = k T` (objective `min-time`: every fall shorter than `T*` would need
//!   a path of peak above `peak` at `T`, which the least-peak optimum says there is not, locally);
//! - at the problem's fall (objective `peak`) the least-peak optimum is within the motors exactly
//!   when its peak is at most `τ_max`; otherwise no flip is within them in this fall, and the row
//!   says so with the least fall that would be.
//!
//! Every number is re-measured on the path flown ([`measure`]: the flip by the general core, each
//! motor's torque usage against the limit).

use super::cat::WholeCat;
use super::measure::measure;
use super::settings::Objective;
use super::solution::{WholeOutcome, WholeStatus};
use crate::model::motor::Motors;

/// `outcome` (the least-peak optima with ideal motors) held to `limit` N·m on every motor for
/// `objective` (module docs), every solution re-measured against `motors`; the best chosen anew.
pub fn within(
    cat: &WholeCat,
    mut outcome: WholeOutcome,
    objective: Objective,
    motors: &Motors,
    limit: f64,
    tolerance: f64,
) -> WholeOutcome {
    for s in &mut outcome.solutions {
        let k = (s.peak_torque_nm / limit).sqrt();
        if objective == Objective::MinTime && k > 0.0 {
            s.spline = s.spline.stretched(k);
            s.reason = format!(
                "{}; the least fall within {limit} N·m on every motor: the least-peak path slowed by {k:.6} (exact for a torque limit alone)",
                s.reason
            );
        }
        let m = measure(cat, &s.spline, motors, tolerance);
        s.twist = m.flip.twist;
        s.swing = m.flip.swing;
        s.twist_error = m.twist_error;
        s.flip_error_estimate = m.flip.error_estimate;
        s.peak_torque_nm = m.peak;
        s.peak_time = m.peak_time;
        s.energy = m.energy;
        s.max_bend_deg = m.max_bend.to_degrees();
        s.bend_turns = m.bend_turns;
        s.fall_time_s = s.spline.duration();
        s.motors = m.motors;
        s.chatter = m.chatter;
        if s.status == WholeStatus::Converged && !s.motors.within() {
            s.status = WholeStatus::Infeasible;
            s.reason = format!(
                "{}; no flip within the motors in this fall: its least peak {:.6} N·m exceeds {limit} N·m (objective \"min-time\" finds the least fall, {:.6} s)",
                s.reason,
                s.peak_torque_nm,
                s.fall_time_s * k
            );
        }
    }
    let value = |i: usize| outcome.solutions[i].value(objective);
    outcome.best = (0..outcome.solutions.len())
        .filter(|&i| outcome.solutions[i].status == WholeStatus::Converged && outcome.solutions[i].flips(tolerance))
        .min_by(|&a, &b| value(a).total_cmp(&value(b)));
    outcome
}
