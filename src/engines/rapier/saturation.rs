//! The motors' limits in rapier: each joint motor's force bound, and when the schedule needed
//! more than it (DESIGN.md §9; `[actuator]` in a problem file).
//!
//! # The bound
//!
//! Rapier's joint motor is one velocity-constraint row on the joint coordinate; its accumulated
//! impulse over a step is clamped to `±max_force · h`. The row's Jacobian is the unit vector of
//! the coordinate, so the impulse is a generalized impulse conjugate to the joint angle — for a
//! revolute joint an axial torque times the step, N·m·s — and `max_force` bounds the motor's
//! torque in N·m, with either [`rapier3d_f64::dynamics::MotorModel`]: the acceleration-based
//! model only scales the row's compliance by the coordinate's apparent inertia, not the impulse
//! (rapier 0.36, `unit_joint_motor_constraint` and `GenericJointConstraint::solve`). The bound
//! clips the PD servo's whole output, feed-forward and feedback together, as a real motor's
//! torque limit would.
//!
//! At each step, joint `j`'s bound is the torque its motor has at rapier's joint rate `q̇_j` at
//! the start of the step ([`available_torque`]): the least of `τ_max`, the DC envelope's
//! `τ_s (1 − |q̇|/ω_0)` (zero at and beyond the free speed) and the power limit's `P/|q̇|`. A
//! speed limit bounds no torque: the exact engine's motor demand reports it.
//!
//! # Saturation
//!
//! A step saturates joint `j`'s motor when the torque the schedule needs there — the exact
//! engine's Newton–Euler torque of the schedule at the end of the step, the feed-forward an
//! ideal motor would deliver — exceeds the step's bound by more than [`SATURATION_TOLERANCE`]
//! of it. Per joint: the fraction of the steps saturated, the first saturated instant and the
//! largest shortfall `τ_need − bound`. A motor that fell behind needs more than the schedule's
//! torque to catch up, so the fraction is a lower bound on how long the motor was at its limit;
//! the flip rapier lands with says what the clipping did.
//!
//! The impulses the motors answer the schedule's jumps of `q̇` with (the paper's cosine profile)
//! are not torques and are not counted: a bounded motor cannot deliver them at all.

use serde::Serialize;

use crate::model::motor::{Motor, Motors};

/// A step is saturated when the schedule's torque exceeds the bound by more than this fraction
/// of it. The bound is taken at rapier's joint rate, which differs from the plan's by the
/// tracking error, so a schedule planned on its limit (the least-fall-time optimum on a DC
/// envelope, whose bound falls as `τ_s |Δq̇|/ω_0`) touches it by more than round-off: on
/// `problems/servo.toml` by under 1e-3 of the bound, twenty times below the verification's peak
/// torque tolerance. A schedule that needs more than its motors by less than this is still
/// reported by the exact engine's motor demand (verdict `beyond motors`).
pub const SATURATION_TOLERANCE: f64 = 1e-3;

/// The torque, N·m, that `motor` can deliver at joint rate `rate` (rad/s): the least of its
/// torque limit, its DC envelope `τ_s (1 − |q̇|/ω_0)` (at least zero) and `P/|q̇|`; `None` when no
/// limit bounds the torque (ideal, or a speed limit alone).
pub fn available_torque(motor: &Motor, rate: f64) -> Option<f64> {
    let w = rate.abs();
    let envelope = motor.envelope.map(|(stall, free)| (stall * (1.0 - w / free)).max(0.0));
    let power = motor.power.filter(|_| w > 0.0).map(|p| p / w);
    [motor.torque, envelope, power].into_iter().flatten().reduce(f64::min)
}

/// Whether any of `motors` bounds a torque (else rapier's motors are left unbounded).
pub fn bounds_torque(motors: &Motors) -> bool {
    motors.joints.iter().any(|m| m.torque.is_some() || m.envelope.is_some() || m.power.is_some())
}

/// How one joint's motor saturated in a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MotorSaturation {
    /// The joint coordinate (its motor): 1 or 2; on a tree's scene 1 to the number of motors.
    pub joint: usize,
    /// Fraction of the run's steps in which the schedule needed more than the motor's bound.
    pub fraction: f64,
    /// The first such step's end, s.
    pub first_time: f64,
    /// The largest `τ_need − bound`, N·m.
    pub shortfall_nm: f64,
    /// When it occurred, s.
    pub shortfall_time: f64,
}

impl MotorSaturation {
    /// E.g. "joint 2's motor saturated for 12 % of the fall (from 0.410 s, short by up to 0.80 N·m)".
    pub fn describe(&self) -> String {
        format!(
            "joint {}'s motor saturated for {:.0} % of the fall (from {:.3} s, short by up to {:.3} N·m)",
            self.joint,
            100.0 * self.fraction,
            self.first_time,
            self.shortfall_nm
        )
    }
}

/// Counts the saturated steps of one run, per motor (two on the two-body scene, every motor of a
/// tree's).
#[derive(Clone, Debug, Default)]
pub(crate) struct SaturationTracker {
    steps: usize,
    saturated: Vec<usize>,
    first: Vec<Option<f64>>,
    shortfall: Vec<(f64, f64)>,
}

impl SaturationTracker {
    /// One step ending at `t`: the bounds it ran with and the schedule's torques, one per motor.
    pub fn step(&mut self, t: f64, bound: &[Option<f64>], need: &[f64]) {
        self.steps += 1;
        let n = bound.len().max(self.saturated.len());
        self.saturated.resize(n, 0);
        self.first.resize(n, None);
        self.shortfall.resize(n, (0.0, 0.0));
        for (j, (b, need)) in bound.iter().zip(need).enumerate() {
            let Some(b) = *b else { continue };
            let short = need.abs() - b;
            if short > SATURATION_TOLERANCE * b.max(f64::MIN_POSITIVE) {
                self.saturated[j] += 1;
                self.first[j].get_or_insert(t);
                if short > self.shortfall[j].0 {
                    self.shortfall[j] = (short, t);
                }
            }
        }
    }

    /// The motors that saturated.
    pub fn finish(&self) -> Vec<MotorSaturation> {
        (0..self.saturated.len())
            .filter_map(|j| {
                let first_time = self.first[j]?;
                Some(MotorSaturation {
                    joint: j + 1,
                    fraction: self.saturated[j] as f64 / self.steps.max(1) as f64,
                    first_time,
                    shortfall_nm: self.shortfall[j].0,
                    shortfall_time: self.shortfall[j].1,
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound is the least of the limits that apply at the rate.
    #[test]
    fn available_torque_is_the_least_limit() {
        let m = Motor { torque: Some(0.5), speed: Some(6.0), envelope: Some((0.6, 12.0)), power: Some(2.0) };
        let at = |w: f64| available_torque(&m, w).unwrap_or(f64::NAN);
        assert!((at(0.0) - 0.5).abs() < 1e-15, "{}", at(0.0));
        assert!((at(-6.0) - 0.3).abs() < 1e-15, "envelope at half the free speed: {}", at(-6.0));
        assert!((at(11.0) - 0.05).abs() < 1e-15, "envelope near the free speed: {}", at(11.0));
        assert!(at(13.0).abs() < 1e-15, "beyond the free speed: {}", at(13.0));
        let p = Motor { power: Some(2.0), ..Motor::default() };
        assert!((available_torque(&p, 4.0).unwrap_or(f64::NAN) - 0.5).abs() < 1e-15);
        assert_eq!(available_torque(&p, 0.0), None);
        assert_eq!(available_torque(&Motor { speed: Some(1.0), ..Motor::default() }, 3.0), None);
    }
}
