//! A cat beyond two motors (the spherical joint, a tail, legs) within one torque limit on every motor
//! ([`crate::model::motor::MotorsBeyond::TorqueLimit`]): planned for the least peak torque with ideal
//! motors, then held to the limit by the exact time scaling of a zero-momentum flip (DESIGN.md §9).
//!
//! Giving a path the duration `k T` (`q(t/k)`) leaves its flip unchanged at zero angular momentum
//! and divides every torque by `k²` (each is linear in `q̈` and quadratic in `q̇`). So within
//! `|τ_j| ≤ τ_max`:
//! - the least fall time is the least-peak path at the problem's fall `T` with its duration scaled
//!   by `k = √(peak/τ_max)` (objective `min-time`; `k < 1` when the least peak is below the
//!   limit): the least fall within one torque limit is the least-peak problem scaled in time, its
//!   optimum as local, and as converged, as the least-peak one;
//! - at the problem's fall (objective `peak`) the least-peak optimum is within the motors exactly
//!   when its peak is at most `τ_max`; otherwise no flip of that start is within them in this
//!   fall, and its reason gives the least fall it would need, `k T`.
//!
//! Every figure is re-measured on the path flown ([`measure`], its flip at the optimiser's
//! re-measurement tolerance, each motor's torque usage against the limit). The log, the
//! iterations and the Newton steps stay the planning run's at the problem's fall (objective
//! `peak`).
//!
//! ## References
//! - DESIGN.md §9 (the least fall time and its `1/T²` scaling of the torques);
//! - J. M. Hollerbach, *Dynamic scaling of manipulator trajectories*, ASME J. Dyn. Syst. Meas.
//!   Control 106 (1984) 102–106 (the time scaling of a trajectory's torques).

use super::cat::WholeCat;
use super::measure::measure;
use super::settings::Objective;
use super::solution::{best_of, WholeOutcome, WholeStatus};
use crate::model::motor::Motors;

/// `outcome` (the least-peak optima with ideal motors) held to `limit` N·m on every motor —
/// `motors`' one torque limit — for `objective` (module docs): every solution re-measured, the best
/// chosen anew; `tolerance` is the result's flip tolerance, rad.
pub fn within(
    cat: &WholeCat,
    mut outcome: WholeOutcome,
    objective: Objective,
    motors: &Motors,
    limit: f64,
    tolerance: f64,
) -> WholeOutcome {
    for s in &mut outcome.solutions {
        let optimum = s.status.is_result() && s.flips(tolerance);
        let k = (s.peak_torque_nm / limit).sqrt();
        let least_fall = s.fall_time_s * k;
        if objective == Objective::MinTime && k > 0.0 {
            s.spline = s.spline.stretched(k);
            s.reason = if optimum {
                format!(
                    "{}; the least fall within {limit} N·m on every motor: the least-peak path's duration scaled by {k:.6} (exact for a torque limit alone)",
                    s.reason
                )
            } else {
                format!("{}; its duration scaled by {k:.6} to fly at {limit} N·m", s.reason)
            };
        }
        let m = measure(cat, &s.spline, motors, super::flip_tolerance(tolerance));
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
        if objective == Objective::Peak && !s.motors.within() {
            if s.status.is_result() {
                s.status = WholeStatus::Infeasible;
            }
            s.reason = format!(
                "{}; no flip within the motors in this fall: its least peak {:.6} N·m exceeds {limit} N·m, which it would need a fall of {least_fall:.6} s for (objective \"min-time\" finds the least fall)",
                s.reason, s.peak_torque_nm
            );
        }
    }
    outcome.best = best_of(&outcome.solutions, objective, tolerance);
    outcome
}
