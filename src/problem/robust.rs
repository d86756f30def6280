//! `[robust]`: the draws of the robustness check ([`crate::robust`]), how many and how wide.

use serde::{Deserialize, Serialize};

use super::error::{bad, ProblemError};
use crate::numeric::numfmt::echo;
use crate::problem::limits::{count_in_range, CountRange};

/// Trials of one robustness check.
pub const TRIALS: CountRange = CountRange { min: 1, max: 100_000 };
/// Largest spread of a size, percent: a half must keep a positive mass, length and radius.
pub const MAX_SPREAD_PCT: f64 = 90.0;
/// Coarsest rapier step of the tracked trials, s: the servo and the schedule's time scales
/// (tenths of a second) need many steps.
pub const MAX_DT_S: f64 = 0.01;
/// Longest rapier step at which the feedback has been measured to land every trial, s (at 4e-4 s
/// some trials of the paper's cat diverge).
pub const FEEDBACK_DT_S: f64 = 3e-4;
/// Largest `ω h` (rad per step) of the tracked trials' stiffest servo mode without a warning
/// (a warning of [`crate::problem::Problem::warnings`]). Measured on the paper's cat (stiffening 5.8), open loop: 48
/// trials at 4e-4 s (up to 0.16 with the gains drawn +20 %) run; at 5e-4 s (0.20) trial 3
/// diverges, and the nominal cat (no gain drawn) at 1e-3 s (0.36); a fat nominal cat (r = 0.25 m,
/// stiffening 2.4) runs at 1e-3 s (0.15), as the thin one does with a 3 Hz servo (0.11).
pub const WARN_SERVO_PER_STEP: f64 = 0.15;
/// Fewer trials than this are warned of: their percentiles are a few trials' values.
pub const WARN_FEW_TRIALS: usize = 20;
/// A landing tolerance at or above this, degrees, is warned of: a cat this far off is not on
/// its feet.
pub const WARN_TOLERANCE_DEG: f64 = 90.0;
/// A landing tolerance below this many degrees reads like one written in radians (5° is
/// 0.0873 rad): warned about.
pub const WARN_RADIAN_TOLERANCE_DEG: f64 = 0.2;

/// Which engines the robustness check runs its trials through.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RobustEngine {
    /// The exact engine with ideal tracking: the joints follow the schedule exactly.
    Exact,
    /// Rapier, the schedule tracked by feed-forward plus joint PD through the actuators, with
    /// an attitude sensor (and, with `landing`, the ground).
    Rapier,
    /// Both, side by side.
    Both,
}

impl RobustEngine {
    /// Whether the exact engine's check runs.
    pub fn exact(self) -> bool {
        matches!(self, RobustEngine::Exact | RobustEngine::Both)
    }
    /// Whether rapier's tracked check runs.
    pub fn rapier(self) -> bool {
        matches!(self, RobustEngine::Rapier | RobustEngine::Both)
    }
}

/// Which controllers drive rapier's tracked trials.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RobustController {
    /// Feed-forward of the plan plus joint PD: the attitude ignored.
    OpenLoop,
    /// Attitude feedback: time-varying LQR with a Kalman filter
    /// ([`crate::engines::rapier::feedback`]).
    Feedback,
    /// Both, on the same trials (same draws, same sensor noise).
    Both,
}

impl RobustController {
    /// Whether the open-loop trials run.
    pub fn open_loop(self) -> bool {
        matches!(self, RobustController::OpenLoop | RobustController::Both)
    }
    /// Whether the feedback trials run.
    pub fn feedback(self) -> bool {
        matches!(self, RobustController::Feedback | RobustController::Both)
    }
}

/// Settings of the robustness check: each trial draws a cat around the problem's (each size
/// scaled by a factor uniform in `[1 − p/100, 1 + p/100]`, both halves alike), a release spin
/// (each world component normal with standard deviation `spin_sigma_nms`) and, for rapier, each
/// joint's servo gains (a factor uniform in `1 ± gain_pct/100`), and runs the schedule on it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RobustSettings {
    /// Number of trials.
    pub trials: usize,
    /// Seed of the draws; trial `k` draws from its own stream, so any trial can be rerun alone.
    pub seed: u64,
    /// Spread of each half's mass, percent.
    pub mass_pct: f64,
    /// Spread of each half's length, percent.
    pub length_pct: f64,
    /// Spread of each half's radius, percent.
    pub radius_pct: f64,
    /// Standard deviation of each component of the release spin `L`, N·m·s (added to
    /// `drop.angular_momentum`).
    pub spin_sigma_nms: f64,
    /// A trial lands when A's final attitude is within this angle of the target, degrees.
    pub tolerance_deg: f64,
    /// The engines the trials run through.
    #[serde(skip_serializing_if = "default::engine")]
    pub engine: RobustEngine,
    /// Rapier's time step in the tracked trials, s (first-order integrator: its attitude bias
    /// is proportional to it).
    #[serde(skip_serializing_if = "default::dt_s")]
    pub dt_s: f64,
    /// Natural frequency of the joint servo (PD on the straight cat's joint inertia), Hz.
    #[serde(skip_serializing_if = "default::servo_hz")]
    pub servo_hz: f64,
    /// Damping ratio of the joint servo.
    #[serde(skip_serializing_if = "default::servo_damping")]
    pub servo_damping: f64,
    /// Spread of each joint's servo gains, percent.
    #[serde(skip_serializing_if = "default::gain_pct")]
    pub gain_pct: f64,
    /// Latency of the attitude estimate handed to the controller, s.
    #[serde(skip_serializing_if = "default::attitude_latency_s")]
    pub attitude_latency_s: f64,
    /// Noise of the attitude estimate, per axis (standard deviation), degrees.
    #[serde(skip_serializing_if = "default::attitude_noise_deg")]
    pub attitude_noise_deg: f64,
    /// Whether the tracked trials fall onto the ground `drop.height` below the release and
    /// report their touch-down.
    #[serde(skip_serializing_if = "default::landing")]
    pub landing: bool,
    /// A trial lands on its feet when each half's feet point within this angle of straight
    /// down at touch-down, degrees.
    #[serde(skip_serializing_if = "default::feet_down_deg")]
    pub feet_down_deg: f64,
    /// The controllers of rapier's tracked trials.
    #[serde(skip_serializing_if = "default::controller")]
    pub controller: RobustController,
    /// Rate of the feedback's regulator, Hz.
    #[serde(skip_serializing_if = "default::feedback_hz")]
    pub feedback_hz: f64,
    /// Rate at which the feedback re-plans the rest of the fall from its estimate (re-linearised
    /// about the motion it then expects, its gains re-solved), Hz; 0: never, the gains solved
    /// once along the plan. Rounded to a whole number of the regulator's steps.
    #[serde(skip_serializing_if = "default::feedback_replan_hz")]
    pub feedback_replan_hz: f64,
    /// The feedback's attitude error scale (its LQR weight `1/θ²`), degrees.
    #[serde(skip_serializing_if = "default::feedback_attitude_deg")]
    pub feedback_attitude_deg: f64,
    /// The feedback's joint correction scale (its LQR weight; the correction is kept within
    /// three times it), degrees.
    #[serde(skip_serializing_if = "default::feedback_joint_deg")]
    pub feedback_joint_deg: f64,
    /// The feedback's joint acceleration scale and bound, rad/s².
    #[serde(skip_serializing_if = "default::feedback_accel")]
    pub feedback_accel: f64,
    /// The feedback filter's prior on the unknown release spin, N·m·s per axis: a tuning of the
    /// filter (how readily it attributes an attitude drift to spin), not the spin's spread.
    #[serde(skip_serializing_if = "default::feedback_spin_prior_nms")]
    pub feedback_spin_prior_nms: f64,
}

impl Default for RobustSettings {
    fn default() -> Self {
        DEFAULT
    }
}

/// The settings' defaults (the one place they live; [`Default`] returns them).
const DEFAULT: RobustSettings = RobustSettings {
    trials: 200,
    seed: 1,
    mass_pct: 10.0,
    length_pct: 0.0,
    radius_pct: 0.0,
    spin_sigma_nms: 0.005,
    tolerance_deg: 5.0,
    engine: RobustEngine::Exact,
    dt_s: 1e-4,
    servo_hz: 10.0,
    servo_damping: 1.0,
    gain_pct: 20.0,
    attitude_latency_s: 0.010,
    attitude_noise_deg: 0.5,
    landing: false,
    feet_down_deg: 20.0,
    controller: RobustController::OpenLoop,
    feedback_hz: 1000.0,
    feedback_replan_hz: 0.0,
    feedback_attitude_deg: 1.0,
    feedback_joint_deg: 10.0,
    feedback_accel: 20.0,
    feedback_spin_prior_nms: 0.001,
};

/// Whether a tracked-check setting is at its default, and so left out of a problem's echo
/// (problem files and results written before the tracked check stay as they were, as
/// `drop.angular_momentum` is left out at zero).
mod default {
    use super::{RobustController, RobustEngine, DEFAULT};

    pub fn engine(v: &RobustEngine) -> bool {
        *v == DEFAULT.engine
    }
    pub fn controller(v: &RobustController) -> bool {
        *v == DEFAULT.controller
    }
    pub fn landing(v: &bool) -> bool {
        *v == DEFAULT.landing
    }
    macro_rules! same_number {
        ($($f:ident),*) => {$(
            pub fn $f(v: &f64) -> bool {
                v.to_bits() == DEFAULT.$f.to_bits()
            }
        )*};
    }
    same_number!(
        dt_s,
        servo_hz,
        servo_damping,
        gain_pct,
        attitude_latency_s,
        attitude_noise_deg,
        feet_down_deg,
        feedback_hz,
        feedback_replan_hz,
        feedback_attitude_deg,
        feedback_joint_deg,
        feedback_accel,
        feedback_spin_prior_nms
    );
}

/// What steadies a tracked scene that diverges at its step: the warning's advice and the
/// divergence error's.
pub const SERVO_REMEDY: &str =
    "shorten robust.dt_s, lower robust.servo_hz, or bring robust.servo_damping down towards 1";

impl RobustSettings {
    pub(crate) fn validate(&self) -> Result<(), ProblemError> {
        count_in_range("robust.trials", self.trials, TRIALS)?;
        for (field, v) in [
            ("robust.mass_pct", self.mass_pct),
            ("robust.length_pct", self.length_pct),
            ("robust.radius_pct", self.radius_pct),
        ] {
            if !(0.0..=MAX_SPREAD_PCT).contains(&v) {
                return Err(bad(field, echo(v), &format!("must lie in [0, {MAX_SPREAD_PCT}] percent")));
            }
        }
        if !(self.spin_sigma_nms.is_finite() && self.spin_sigma_nms >= 0.0) {
            return Err(bad("robust.spin_sigma_nms", echo(self.spin_sigma_nms), "must be a finite number ≥ 0 (N·m·s)"));
        }
        if !(self.tolerance_deg > 0.0 && self.tolerance_deg <= 180.0) {
            return Err(bad("robust.tolerance_deg", echo(self.tolerance_deg), "must lie in (0, 180] degrees"));
        }
        if !(self.dt_s > 0.0 && self.dt_s <= MAX_DT_S) {
            return Err(bad("robust.dt_s", echo(self.dt_s), &format!("must lie in (0, {MAX_DT_S}] s")));
        }
        if !(self.servo_hz.is_finite() && self.servo_hz >= 0.0) {
            return Err(bad(
                "robust.servo_hz",
                echo(self.servo_hz),
                "must be a finite number ≥ 0 (Hz; 0: feed-forward alone)",
            ));
        }
        if !(self.servo_damping.is_finite() && self.servo_damping >= 0.0) {
            return Err(bad("robust.servo_damping", echo(self.servo_damping), "must be a finite number ≥ 0"));
        }
        if !(0.0..=MAX_SPREAD_PCT).contains(&self.gain_pct) {
            return Err(bad(
                "robust.gain_pct",
                echo(self.gain_pct),
                &format!("must lie in [0, {MAX_SPREAD_PCT}] percent"),
            ));
        }
        if !(self.attitude_latency_s.is_finite() && self.attitude_latency_s >= 0.0) {
            return Err(bad(
                "robust.attitude_latency_s",
                echo(self.attitude_latency_s),
                "must be a finite number ≥ 0 (s)",
            ));
        }
        if !(self.attitude_noise_deg.is_finite() && (0.0..=180.0).contains(&self.attitude_noise_deg)) {
            return Err(bad(
                "robust.attitude_noise_deg",
                echo(self.attitude_noise_deg),
                "must lie in [0, 180] degrees",
            ));
        }
        if !(self.feet_down_deg > 0.0 && self.feet_down_deg <= 180.0) {
            return Err(bad("robust.feet_down_deg", echo(self.feet_down_deg), "must lie in (0, 180] degrees"));
        }
        if !(self.feedback_hz.is_finite() && self.feedback_hz > 0.0) {
            return Err(bad("robust.feedback_hz", echo(self.feedback_hz), "must be a finite number > 0 (Hz)"));
        }
        if self.feedback_hz * self.dt_s > 1.0 {
            return Err(bad(
                "robust.feedback_hz",
                echo(self.feedback_hz),
                &format!("must not exceed the rapier step's rate 1/robust.dt_s = {} Hz", echo(1.0 / self.dt_s)),
            ));
        }
        if !(self.feedback_replan_hz.is_finite() && self.feedback_replan_hz >= 0.0) {
            return Err(bad(
                "robust.feedback_replan_hz",
                echo(self.feedback_replan_hz),
                "must be a finite number ≥ 0 (Hz; 0: never re-plan)",
            ));
        }
        if self.feedback_replan_hz > self.feedback_hz {
            return Err(bad(
                "robust.feedback_replan_hz",
                echo(self.feedback_replan_hz),
                &format!("must not exceed the regulator's rate robust.feedback_hz = {} Hz", echo(self.feedback_hz)),
            ));
        }
        for (field, v) in [
            ("robust.feedback_attitude_deg", self.feedback_attitude_deg),
            ("robust.feedback_joint_deg", self.feedback_joint_deg),
        ] {
            if !(v > 0.0 && v <= 90.0) {
                return Err(bad(field, echo(v), "must lie in (0, 90] degrees"));
            }
        }
        if !(self.feedback_accel.is_finite() && self.feedback_accel > 0.0) {
            return Err(bad(
                "robust.feedback_accel",
                echo(self.feedback_accel),
                "must be a finite number > 0 (rad/s²)",
            ));
        }
        if !(self.feedback_spin_prior_nms.is_finite() && self.feedback_spin_prior_nms > 0.0) {
            return Err(bad(
                "robust.feedback_spin_prior_nms",
                echo(self.feedback_spin_prior_nms),
                "must be a finite number > 0 (N·m·s)",
            ));
        }
        if self.controller.feedback() && !self.engine.rapier() {
            return Err(bad(
                "robust.controller",
                "\"feedback\"",
                "needs rapier's tracked trials: set robust.engine = \"rapier\" or \"both\"",
            ));
        }
        Ok(())
    }

    /// Careless settings that still run: so few trials that a percentile says little, a landing
    /// tolerance any schedule meets; for the tracked check, a servo the step barely resolves, an
    /// attitude estimate older than the fall.
    ///
    /// The servo is an explicit PD whose gains are sized on `J = I_end/2` (a half's transverse
    /// inertia about its end, [`crate::engines::rapier::PdGains::servo`]), while a bend that
    /// brings B's spine near joint 1's axis (A's `x`) leaves that joint little more than B's axial inertia `I_ax = m r²/2` to move: the
    /// stiffest mode turns up to `√(J/I_ax)` times faster than `ω_n` (`servo_stiffening`, 5.8 on
    /// the paper's cat; the nominal cat at 1e-3 s diverges at t = 0.18 s, as the bend grows). Its angle
    /// per step `2π f_servo h √(1 + gain_pct/100) √(J/I_ax)` beyond [`WARN_SERVO_PER_STEP`] is
    /// warned about: there the tracked trials diverge.
    pub(crate) fn warnings(&self, fall_time: f64, servo_stiffening: f64) -> Vec<String> {
        let mut out = Vec::new();
        if self.trials < WARN_FEW_TRIALS {
            out.push(format!(
                "robust.trials = {}: percentiles from so few trials say little (the 95th of {} trials is its largest or next to it); {WARN_FEW_TRIALS} or more make a distribution",
                self.trials, self.trials
            ));
        }
        if self.tolerance_deg >= WARN_TOLERANCE_DEG {
            out.push(format!(
                "robust.tolerance_deg = {}: a cat within {}° of its target is not on its feet; any schedule lands \"within\" it",
                echo(self.tolerance_deg),
                echo(self.tolerance_deg)
            ));
        }
        if self.tolerance_deg < WARN_RADIAN_TOLERANCE_DEG {
            out.push(format!(
                "robust.tolerance_deg = {}: is it in radians? (the field is in degrees: {} rad is {:.1}°; a landing within {}° is far stricter than any cat needs)",
                echo(self.tolerance_deg),
                echo(self.tolerance_deg),
                self.tolerance_deg.to_degrees(),
                echo(self.tolerance_deg)
            ));
        }
        if !self.engine.rapier() {
            return out;
        }
        // An overdamped servo's fast mode decays at ω_n (ζ + √(ζ² − 1)), up to 2ζ ω_n.
        let zeta = self.servo_damping;
        let damped = if zeta > 1.0 { zeta + (zeta * zeta - 1.0).sqrt() } else { 1.0 };
        let per_step = std::f64::consts::TAU
            * self.servo_hz
            * self.dt_s
            * (1.0 + self.gain_pct / 100.0).sqrt()
            * servo_stiffening
            * damped;
        if per_step > WARN_SERVO_PER_STEP {
            let damping = if zeta > 1.0 {
                format!(" with robust.servo_damping = {} (its fast mode {damped:.1}× ω_n)", echo(zeta))
            } else {
                String::new()
            };
            out.push(format!(
                "robust.servo_hz = {}{damping} at robust.dt_s = {} turns the servo's stiffest mode by {per_step:.2} rad per step (a bend that brings B's spine near joint 1's axis leaves that joint little more than B's axial inertia, so the mode runs up to {servo_stiffening:.1}× faster than the servo's ω_n, with the gains drawn up to +{}%): the explicit PD diverges beyond about {WARN_SERVO_PER_STEP} rad per step (and the run stops, naming the trial); {SERVO_REMEDY}",
                echo(self.servo_hz),
                echo(self.dt_s),
                echo(self.gain_pct)
            ));
        }
        if self.controller.feedback() && self.dt_s > FEEDBACK_DT_S {
            out.push(format!(
                "robust.dt_s = {} with robust.controller = feedback: the feedback was measured at steps up to {FEEDBACK_DT_S:e} s; at 4e-4 s some trials of the paper's cat diverge (and the run stops, naming the trial); shorten robust.dt_s",
                echo(self.dt_s)
            ));
        }
        if self.attitude_latency_s >= fall_time {
            out.push(format!(
                "robust.attitude_latency_s = {} s is not shorter than the fall ({fall_time:.3} s): the controller never sees the cat move",
                echo(self.attitude_latency_s)
            ));
        }
        out
    }
}
