//! What a verification in rapier reports (the module docs of [`super::verify`]): the exact
//! engine's reference, each run's record, each quantity's convergence, and the verdict.

use std::fmt;

use nalgebra::Vector3;
use serde::Serialize;

use super::saturation::MotorSaturation;
use super::{RapierRun, TimeScales};
use crate::engines::motors::MotorDemand;

/// Fewest runs for a verdict: two extrapolations, and the observed order.
pub const MIN_RUNS: usize = 3;

/// Observed orders taken as rapier's asymptotic first-order range (measured 0.7–1.04 on the
/// paper problem's schedules).
pub const ASYMPTOTIC: std::ops::RangeInclusive<f64> = 0.5..=2.0;

/// What the exact engine says the trajectory does.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Reference {
    /// Signed twist about A's initial `+z`, rad.
    pub twist: f64,
    /// Swing of the spine axis, rad.
    pub swing: f64,
    /// Peak joint torque `max_t max_i |τ_i|`, N·m.
    pub peak_torque: f64,
}

/// A quantity that is verified.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Quantity {
    /// The final twist.
    Twist,
    /// The final swing.
    Swing,
    /// The peak joint torque.
    PeakTorque,
}

impl Quantity {
    /// The three, in order.
    pub const ALL: [Quantity; 3] = [Quantity::Twist, Quantity::Swing, Quantity::PeakTorque];

    /// How a gap or an estimate of this quantity reads: `0.51°` or `1.20 %`.
    pub fn format_gap(self, x: f64) -> String {
        match self {
            Quantity::PeakTorque => format!("{:.2} %", 100.0 * x),
            _ => format!("{x:.3}°"),
        }
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Quantity::Twist => "twist",
            Quantity::Swing => "swing",
            Quantity::PeakTorque => "peak torque",
        })
    }
}

/// Where a verification's first step came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StepSource {
    /// The trajectory's time scales (`rapier.dt = "auto"`).
    Auto,
    /// The user's step (`rapier.dt = S`, `simulate --dt S`).
    Fixed,
}

impl fmt::Display for StepSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StepSource::Auto => "auto",
            StepSource::Fixed => "fixed",
        })
    }
}

/// How a verification ended, in one word.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Rapier agrees with the exact engine within the tolerances.
    Verified,
    /// Rapier disagrees by more than the tolerance and its own error.
    NotVerified,
    /// Rapier did not converge enough to judge.
    Inconclusive,
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Status::Verified => "verified",
            Status::NotVerified => "not-verified",
            Status::Inconclusive => "inconclusive",
        })
    }
}

/// The verdict with what it rests on. Gaps, estimates and tolerances are in degrees for twist and
/// swing, relative to the exact peak for the peak torque.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Verdict {
    /// Every quantity within tolerance, and rapier's own error below it.
    Verified,
    /// `quantity` differs by `gap`, more than `tolerance + estimate`.
    NotVerified {
        /// The quantity.
        quantity: Quantity,
        /// `|X₀ − X_exact|`.
        gap: f64,
        /// Its tolerance.
        tolerance: f64,
        /// Rapier's own error estimate.
        estimate: f64,
    },
    /// Rapier's own error of `quantity` is above its tolerance.
    NotConverged {
        /// The quantity.
        quantity: Quantity,
        /// Rapier's own error estimate.
        estimate: f64,
        /// Its tolerance.
        tolerance: f64,
        /// The gap to the exact engine.
        gap: f64,
        /// Why the refinement stopped.
        why: String,
    },
    /// `quantity` differs by more than its tolerance, but not by more than rapier's own error.
    WithinEstimate {
        /// The quantity.
        quantity: Quantity,
        /// `|X₀ − X_exact|`.
        gap: f64,
        /// Its tolerance.
        tolerance: f64,
        /// Rapier's own error estimate.
        estimate: f64,
    },
    /// A motor saturated in the finest run: the schedule needs more than its motors.
    Saturated {
        /// The joints whose motors saturated.
        motors: Vec<MotorSaturation>,
        /// The twist rapier landed with (finest run, not extrapolated), degrees.
        twist_deg: f64,
        /// The swing rapier landed with, degrees.
        swing_deg: f64,
        /// How far the landed twist moved from the run at twice the step, degrees (none with
        /// one run).
        twist_change_deg: Option<f64>,
        /// The planned twist (the exact engine's), degrees.
        planned_twist_deg: f64,
        /// The planned swing, degrees.
        planned_swing_deg: f64,
        /// The finest run's step, s.
        dt: f64,
    },
    /// The exact engine finds the schedule beyond its motors, though rapier's did not saturate.
    BeyondMotors {
        /// The exact engine's motor verdict ([`MotorDemand::verdict`]).
        exceeded: String,
    },
    /// Fewer than three runs could be made.
    TooFewRuns {
        /// Runs made in the last unbroken sequence.
        runs: usize,
        /// Why no more.
        why: String,
    },
    /// The exact engine's reference is not finite.
    BadReference,
}

impl Verdict {
    /// The verdict in one word.
    pub fn status(&self) -> Status {
        match self {
            Verdict::Verified => Status::Verified,
            Verdict::NotVerified { .. } | Verdict::Saturated { .. } | Verdict::BeyondMotors { .. } => {
                Status::NotVerified
            }
            _ => Status::Inconclusive,
        }
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Verdict::Verified => write!(f, "verified"),
            Verdict::NotVerified { quantity: q, gap, tolerance, estimate } => write!(
                f,
                "not verified: the {q} differs from the exact engine's by {}, more than the tolerance {} plus rapier's own error {}",
                q.format_gap(*gap),
                q.format_gap(*tolerance),
                q.format_gap(*estimate)
            ),
            Verdict::NotConverged { quantity: q, estimate, tolerance, why, .. } => write!(
                f,
                "inconclusive: rapier's own {q} error {} is above the tolerance {} ({why})",
                q.format_gap(*estimate),
                q.format_gap(*tolerance)
            ),
            Verdict::WithinEstimate { quantity: q, gap, tolerance, estimate } => write!(
                f,
                "inconclusive: the {q} differs by {}, above the tolerance {} but within it plus rapier's own error {}",
                q.format_gap(*gap),
                q.format_gap(*tolerance),
                q.format_gap(*estimate)
            ),
            Verdict::Saturated {
                motors,
                twist_deg,
                swing_deg,
                twist_change_deg,
                planned_twist_deg,
                planned_swing_deg,
                dt,
            } => {
                let which: Vec<String> = motors.iter().map(MotorSaturation::describe).collect();
                let moved = twist_change_deg
                    .map_or(String::new(), |c| format!("; its twist moved {c:.1}° from the run at twice the step"));
                write!(
                    f,
                    "not verified: {}: the cat lands with twist {twist_deg:+.1}°, swing {swing_deg:.1}° (planned {planned_twist_deg:+.1}°, {planned_swing_deg:.1}°; rapier's finest run, dt = {dt:.3e} s, not extrapolated: a clipped motor is not smooth in the step{moved})",
                    which.join(", ")
                )
            }
            Verdict::BeyondMotors { exceeded } => {
                write!(f, "not verified: the schedule {exceeded} (the exact engine); rapier's motors did not saturate")
            }
            Verdict::TooFewRuns { runs, why } => {
                write!(f, "inconclusive: {runs} of the {MIN_RUNS} runs needed to judge ({why})")
            }
            Verdict::BadReference => write!(f, "inconclusive: the exact engine's reference is not a number"),
        }
    }
}

/// One rapier run of the refinement.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunRecord {
    /// Step used, s.
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// Final twist, degrees.
    pub twist_deg: f64,
    /// Final swing, degrees.
    pub swing_deg: f64,
    /// Peak torque, N·m: the largest of [`RunRecord::motor_peaks_nm`].
    pub peak_torque_nm: f64,
    /// Each motor's peak, N·m: extrapolated motor by motor, the largest judged
    /// ([`super::richardson_peaks`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub motor_peaks_nm: Vec<f64>,
    /// Largest tracking error per joint coordinate (a two-motor cat), or per link as the angle
    /// between the reached and the planned relative rotation (a tree of bodies, [`super::tree_run`]), rad.
    pub tracking_error_rad: Vec<f64>,
    /// Largest angular-momentum drift, relative to `I* · max|q̇|` (a two-motor cat) or to the
    /// largest momentum of the shape motion `max_t |h(t)|` (a tree of bodies, [`super::tree_run`]).
    pub momentum_drift: f64,
    /// Wall-clock time, s.
    pub run_time_s: f64,
    /// The joints whose motors saturated (absent when none did).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub saturation: Vec<MotorSaturation>,
    /// On the ball joint, the halves' largest twist about the spine relative to each other,
    /// degrees ([`RapierRun::spine_twist_max`]); absent on the universal joint.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spine_twist_max_deg: Option<f64>,
    /// The swing's rotation vector, degrees (what is extrapolated).
    #[serde(skip)]
    pub(super) swing_vector: Vector3<f64>,
}

/// A run that could not be made.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Failure {
    /// Step asked for, s.
    pub dt: f64,
    /// Why (rapier's error).
    pub reason: String,
}

/// The convergence of one quantity. Raw and extrapolated values in degrees (twist, swing) or
/// N·m (peak torque); `gap`, `estimate` and `tolerance` in degrees or relative to the exact peak.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Convergence {
    /// The quantity.
    pub quantity: Quantity,
    /// The exact engine's value.
    pub reference: f64,
    /// Rapier's value per run.
    pub raw: Vec<f64>,
    /// Richardson extrapolation of each pair of successive runs (the peak torque's: the largest of
    /// each motor's own, [`super::richardson_peaks`], not of `raw`).
    pub extrapolated: Vec<f64>,
    /// Observed order from the last three runs (`None` with fewer, or when it is undefined); the
    /// peak torque's, of the motor whose extrapolation is the last `value`.
    pub observed_order: Option<f64>,
    /// The last extrapolation.
    pub value: Option<f64>,
    /// Its error estimate `|X₀⁽ᵏ⁾ − X₀⁽ᵏ⁻¹⁾|`; the peak torque's, the largest such change of any
    /// motor that may be the peak (its extrapolation in either of the last two pairs at least the
    /// smaller of their peaks): two motors that trade places would otherwise hide each other's.
    pub estimate: Option<f64>,
    /// `|value − reference|`.
    pub gap: Option<f64>,
    /// The tolerance.
    pub tolerance: f64,
}

/// A verification: the runs, each quantity's convergence and the verdict.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Verification {
    /// The verdict.
    pub verdict: Verdict,
    /// Its word.
    pub status: Status,
    /// Where the first step came from.
    pub first_step: StepSource,
    /// The trajectory's time scales (they set the first step when automatic).
    pub time_scales: TimeScales,
    /// The steps of the runs kept, s.
    pub dt_sequence: Vec<f64>,
    /// The runs kept (an unbroken halving sequence).
    pub runs: Vec<RunRecord>,
    /// Runs that failed (divergence, step refused).
    pub failures: Vec<Failure>,
    /// Twist, swing, peak torque.
    pub quantities: Vec<Convergence>,
    /// Tracking error of the finest run ([`RunRecord::tracking_error_rad`]), rad.
    pub tracking_error_rad: Option<Vec<f64>>,
    /// Momentum drift of the finest run ([`RunRecord::momentum_drift`]).
    pub momentum_drift: Option<f64>,
    /// Time spent in rapier, s.
    pub run_time_s: f64,
    /// Rapier steps taken, all runs (failed ones included) together.
    pub steps_taken: usize,
    /// The step budget.
    pub step_budget: usize,
    /// What the trajectory asks of its motors by the exact engine (absent with ideal motors).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub motor_demand: Option<MotorDemand>,
    /// The finest run in full (torque peaks per piece, jumps, histories).
    #[serde(skip)]
    pub finest: Option<RapierRun>,
}

impl Verification {
    /// Whether it made at least one usable run (without one it has nothing to compare: `run`,
    /// `compare --verify` and `optimize --whole --verify` then exit 1).
    pub fn has_result(&self) -> bool {
        !self.runs.is_empty()
    }

    /// The convergence record of one quantity.
    pub fn quantity(&self, q: Quantity) -> Option<&Convergence> {
        self.quantities.iter().find(|c| c.quantity == q)
    }
}

impl RunRecord {
    /// The record of a run at step `dt` of `steps` steps that ends with A at `orientation`
    /// (its twist and swing, rad), with each motor's peak torque `motor_peaks_nm` (N·m;
    /// the peak is their largest), the tracking errors (rad) and the relative momentum drift; no
    /// saturation, no spine twist, no time yet.
    pub(super) fn new(
        dt: f64,
        steps: usize,
        [twist, swing]: [f64; 2],
        orientation: &nalgebra::UnitQuaternion<f64>,
        motor_peaks_nm: Vec<f64>,
        tracking_error_rad: Vec<f64>,
        momentum_drift: f64,
    ) -> Self {
        let swing_vector = super::swing_vector(orientation, twist);
        RunRecord {
            dt,
            steps,
            twist_deg: twist.to_degrees(),
            swing_deg: swing.to_degrees(),
            peak_torque_nm: super::largest(&motor_peaks_nm),
            tracking_error_rad,
            momentum_drift,
            run_time_s: 0.0,
            motor_peaks_nm,
            saturation: Vec::new(),
            spine_twist_max_deg: None,
            swing_vector: swing_vector.map(f64::to_degrees),
        }
    }
}
