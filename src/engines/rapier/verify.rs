//! A verification of a trajectory in rapier that ends in a verdict (DESIGN.md §6).
//!
//! # Step refinement
//!
//! The first step `h₀` comes from the trajectory's own time scales ([`super::time_scales`]), or
//! is the user's (`rapier.dt = S`, `simulate --dt S`). Each further run halves the step (the
//! step count doubles exactly, so every grid is nested in the next). Rapier's multibody
//! integrator is first order, `X(h) = X₀ + c₁ h + c₂ h² + …`, so two runs at `h` and `h/r`
//! extrapolate (Richardson) to
//!
//! $$ X_0^{(k)} = X(h_k) + \frac{X(h_k) − X(h_{k−1})}{r − 1} \quad (= 2X(h/2) − X(h) \text{ for } r = 2), $$
//!
//! whose error is `O(h²)`. From three runs the observed order is
//! `p = log(|X(h_{k−2}) − X(h_{k−1})| / |X(h_{k−1}) − X(h_k)|) / log r` (≈ 1 in rapier's asymptotic
//! range), and the error of the last extrapolation is estimated by the change between the last
//! two, `E = |X_0^{(k)} − X_0^{(k−1)}|`: conservative (for an `O(h²)` remainder the true error is
//! about `E/3`), and robust to a remainder that is not yet asymptotic. Refinement stops when `E`
//! is below the tolerance for every quantity, or when the next run (twice the last one's steps)
//! would overrun `rapier.step_budget` (all runs' steps together; deterministic) or, when set,
//! `rapier.time_budget_s` (wall clock, predicted from the last run's time per step).
//!
//! The swing is extrapolated as the rotation vector of the swing (its length, the swing angle,
//! is not smooth where it passes through zero); its estimate is the change of that vector.
//!
//! # Verdict
//!
//! With `G = |X₀ − X_exact|` (degrees for twist and swing; relative to the exact peak for the
//! peak torque) and tolerance `ε` (`rapier.twist_tolerance_deg`, `…swing…`,
//! `rapier.peak_torque_tolerance`):
//! - **verified**: `G ≤ ε` and `E ≤ ε` for every quantity;
//! - **not verified**: some quantity has `G > ε + E`: rapier and the exact engine disagree by more
//!   than the tolerance and rapier's own error together (the quantity with the largest `G/(ε+E)`
//!   is named), and its sequence is rapier's asymptotic one (`E ≤ ε`, or an observed order in
//!   [`ASYMPTOTIC`]): a sequence that does not converge proves nothing about the exact engine;
//! - **inconclusive**: otherwise, either `E > ε` (rapier did not converge enough: the quantity and
//!   its `E` are named), or `ε < G ≤ ε + E`, or fewer than three runs could be made (rapier
//!   diverged, the step was too coarse or would need too many steps, or the budget allowed no
//!   more: the reason is stated). A run that diverges (non-finite state) or is refused as too
//!   coarse is recorded and the step halved; the runs before it are discarded, as they were not
//!   in the asymptotic range.
//!
//! # Within the motors
//!
//! With motor limits ([`RapierOptions::motors`], a problem's `[actuator]`) rapier's motors get
//! them as their torque bound ([`super::saturation`]), and the verdict first asks whether the
//! schedule needs more than its motors:
//! - **not verified, saturated**: in the finest run a motor's bound fell short of the torque the
//!   schedule needs. The verdict names the joints, the fraction of the fall, the first instant and
//!   the largest shortfall, and the flip rapier landed with against the planned one. A clipped
//!   motor's run is not smooth in the step (where it clips moves with `dt`), so its runs are not
//!   Richardson-extrapolated: the landed flip is the finest run's raw one, with how far it moved
//!   from the run at twice the step; refinement stops after [`MIN_RUNS`] saturated runs;
//! - **not verified, beyond the motors**: rapier's motors did not saturate, but the exact engine's
//!   motor demand ([`crate::engines::motors::motor_demand`]) exceeds a limit — a speed limit,
//!   which bounds no torque, or a torque limit exceeded by less than [`super::SATURATION_TOLERANCE`];
//! - otherwise the verdict above, with the motors bounded in every run.
//!
//! Nothing here panics or returns a NaN as a result: a number that could not be had is a reason
//! in the verdict.

use std::fmt;
use std::time::Instant;

use nalgebra::Vector3;
use serde::Serialize;

use super::saturation::MotorSaturation;
use super::{RapierError, RapierOptions, RapierRun, TimeScales, MAX_STEPS};
use crate::engines::evaluate::{released_on, released_torques};
use crate::engines::motors::{motor_demand_from, MotorDemand};
use crate::engines::torque::piece_samples;

use crate::engines::models::TwoMotorCat;
use crate::problem::settings::{ExactSettings, RapierSettings, TimeStep};
use crate::schedule::Trajectory;

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
    /// Peak torque (per-piece peaks), N·m.
    pub peak_torque_nm: f64,
    /// Largest tracking error per joint coordinate (a two-motor cat), or per link as the angle
    /// between the reached and the planned relative rotation (a tree of bodies, [`super::tree_run`]), rad.
    pub tracking_error_rad: Vec<f64>,
    /// Largest angular-momentum drift relative to `I* · max|q̇|`.
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
    swing_vector: Vector3<f64>,
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
    /// Richardson extrapolation of each pair of successive runs.
    pub extrapolated: Vec<f64>,
    /// Observed order from the last three runs (`None` with fewer, or when it is undefined).
    pub observed_order: Option<f64>,
    /// The last extrapolation.
    pub value: Option<f64>,
    /// Its error estimate `|X₀⁽ᵏ⁾ − X₀⁽ᵏ⁻¹⁾|`.
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
    /// Momentum drift of the finest run, relative to `I* · max|q̇|`.
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
    /// The convergence record of one quantity.
    pub fn quantity(&self, q: Quantity) -> Option<&Convergence> {
        self.quantities.iter().find(|c| c.quantity == q)
    }
}

/// Verifies `traj` against the exact engine's `reference` with the default [`RapierOptions`].
///
/// `Err` only when the settings or the trajectory are invalid (or rapier refuses the scene);
/// every way a run can fail is a verdict.
pub fn verify(
    cat: &TwoMotorCat,
    traj: &impl Trajectory,
    settings: &RapierSettings,
    reference: &Reference,
) -> Result<Verification, RapierError> {
    verify_with(cat, traj, settings, reference, &RapierOptions::default())
}

/// [`verify`] with rapier options.
pub fn verify_with(
    cat: &TwoMotorCat,
    traj: &impl Trajectory,
    settings: &RapierSettings,
    reference: &Reference,
    opts: &RapierOptions,
) -> Result<Verification, RapierError> {
    settings.validate()?;
    let scales = super::time_scales_within(cat, traj, &opts.motors);
    let duration: f64 = traj.piece_durations().iter().sum();
    if !(duration.is_finite() && duration > 0.0) {
        return Err(RapierError::BadDuration(duration));
    }
    let (first, source) = match settings.dt {
        TimeStep::Fixed(dt) => (dt, StepSource::Fixed),
        TimeStep::Auto => (scales.first_step, StepSource::Auto),
    };
    // The exact engine's view of the motors, sampled as its reports sample peaks.
    let demand = (!opts.motors.is_ideal()).then(|| {
        let samples = piece_samples(traj, ExactSettings::default().torque_samples);
        let tolerance = ExactSettings::default().tolerance;
        // The spinning cat's torques need its attitude history; at zero momentum none.
        let history =
            (opts.spin.norm_squared() > 0.0).then(|| released_on(cat, traj, &opts.spin, tolerance).1).flatten();
        motor_demand_from(&released_torques(cat, history.as_ref()), traj, &samples, &opts.motors)
    });
    let mut refined = refine(settings, reference, duration, first, |dt| {
        let run = super::simulate_with(cat, traj, &settings.with_dt(dt), opts)?;
        Ok((record(&run), run))
    })?;
    let (runs, finest) = (&refined.runs, refined.finest.take());
    let mut quantities = convergences(runs, reference, settings);
    let verdict = match (&finest, &demand) {
        (Some(run), _) if !run.saturation.is_empty() => {
            // Not extrapolated (module docs): only the raw values stand.
            for c in &mut quantities {
                c.extrapolated.clear();
                (c.observed_order, c.value, c.estimate, c.gap) = (None, None, None, None);
            }
            let n = runs.len();
            Verdict::Saturated {
                motors: run.saturation.clone(),
                twist_deg: run.twist.to_degrees(),
                swing_deg: run.swing.to_degrees(),
                twist_change_deg: (n >= 2).then(|| runs[n - 1].twist_deg - runs[n - 2].twist_deg),
                planned_twist_deg: reference.twist.to_degrees(),
                planned_swing_deg: reference.swing.to_degrees(),
                dt: run.dt,
            }
        }
        (Some(_), Some(d)) if !d.within() => Verdict::BeyondMotors { exceeded: d.verdict() },
        _ => judge(&quantities, reference, runs.len(), &refined.why_stopped, &refined.failures),
    };
    let verification = refined.verification(verdict, quantities, (source, scales), settings, demand);
    Ok(Verification { finest, ..verification })
}

/// What the step refinement leaves: the runs kept (an unbroken halving sequence), the finest
/// run in full, the failures, the time and steps spent, and why it stopped short (empty when the
/// estimates met the tolerances).
pub(super) struct Refined<R> {
    pub runs: Vec<RunRecord>,
    pub finest: Option<R>,
    pub failures: Vec<Failure>,
    pub spent: f64,
    pub attempted: f64,
    pub why_stopped: String,
}

impl<R> Refined<R> {
    /// The verification of these runs: the `verdict` on their `quantities`, where the first step
    /// came from and the time scales, the budget of `settings`, the exact engine's motor demand;
    /// without the finest run in full.
    pub(super) fn verification(
        self,
        verdict: Verdict,
        quantities: Vec<Convergence>,
        (first_step, time_scales): (StepSource, TimeScales),
        settings: &RapierSettings,
        motor_demand: Option<MotorDemand>,
    ) -> Verification {
        Verification {
            status: verdict.status(),
            verdict,
            first_step,
            time_scales,
            dt_sequence: self.runs.iter().map(|r| r.dt).collect(),
            tracking_error_rad: self.runs.last().map(|r| r.tracking_error_rad.clone()),
            momentum_drift: self.runs.last().map(|r| r.momentum_drift),
            runs: self.runs,
            failures: self.failures,
            quantities,
            run_time_s: self.spent,
            steps_taken: self.attempted as usize,
            step_budget: settings.step_budget,
            motor_demand,
            finest: None,
        }
    }
}

/// The step refinement (module docs) of a trajectory lasting `duration` s from the first step
/// `first`: `simulate(dt)` runs it at `dt` and returns its record (its `run_time_s` is filled
/// here) and the run in full.
pub(super) fn refine<R>(
    settings: &RapierSettings,
    reference: &Reference,
    duration: f64,
    first: f64,
    mut simulate: impl FnMut(f64) -> Result<(RunRecord, R), RapierError>,
) -> Result<Refined<R>, RapierError> {
    // Step counts double exactly: n_k = n_0 2^k, dt_k = T / n_k.
    let mut steps = (duration / first).ceil().max(1.0);
    let (mut runs, mut finest, mut failures) = (Vec::<RunRecord>::new(), None, Vec::new());
    let mut spent = 0.0;
    let mut why_stopped = String::new();
    let mut last_attempt: Option<(f64, f64)> = None;
    let mut attempted = 0.0;
    loop {
        if steps > MAX_STEPS as f64 {
            let dt = duration / steps;
            why_stopped = format!(
                "a run at dt = {dt:.3e} s would need {} steps, more than the {MAX_STEPS} a run may take",
                crate::numeric::numfmt::num(steps)
            );
            break;
        }
        if attempted + steps > settings.step_budget as f64 {
            let next = if attempted > 0.0 { "the next run" } else { "the first run" };
            why_stopped = format!(
                "{next}, {steps:.0} steps, would overrun the budget of {} steps ({attempted:.0} taken)",
                settings.step_budget
            );
            break;
        }
        // The next run costs about the last attempt's time per step (failed ones included).
        if let (Some((last_time, last_steps)), Some(budget)) = (last_attempt, settings.time_budget_s) {
            let predicted = last_time * steps / last_steps;
            if spent + predicted > budget {
                why_stopped =
                    format!("the next run, about {predicted:.2} s, would overrun the time budget of {budget} s");
                break;
            }
        }
        let dt = duration / steps * (1.0 + 1e-12);
        let start = Instant::now();
        let result = simulate(dt);
        let elapsed = start.elapsed().as_secs_f64();
        spent += elapsed;
        last_attempt = Some((elapsed, steps));
        attempted += steps;
        match result {
            Ok((record, run)) => {
                runs.push(RunRecord { run_time_s: elapsed, ..record });
                finest = Some(run);
            }
            Err(e @ (RapierError::Diverged(_) | RapierError::TooCoarse { .. })) => {
                failures.push(Failure { dt, reason: e.to_string() });
                runs.clear();
                finest = None;
                if failures.len() > 12 {
                    why_stopped = format!("rapier failed {} times in a row ({e})", failures.len());
                    break;
                }
            }
            Err(RapierError::TooManySteps { .. }) => {
                why_stopped =
                    format!("a run at dt = {dt:.3e} s would need more than the {MAX_STEPS} steps a run may take");
                break;
            }
            Err(e) => return Err(e),
        }
        if runs.len() >= MIN_RUNS && runs[runs.len() - MIN_RUNS..].iter().all(|r| !r.saturation.is_empty()) {
            // Saturated runs are not extrapolated, so refining them further shows nothing new.
            break;
        }
        let quantities = convergences(&runs, reference, settings);
        if runs.len() >= MIN_RUNS && quantities.iter().all(|c| c.estimate.is_some_and(|e| e <= c.tolerance)) {
            break;
        }
        steps *= 2.0;
    }
    Ok(Refined { runs, finest, failures, spent, attempted, why_stopped })
}

fn record(run: &RapierRun) -> RunRecord {
    RunRecord {
        saturation: run.saturation.clone(),
        spine_twist_max_deg: run.spine_twist_max.map(f64::to_degrees),
        ..RunRecord::new(
            run.dt,
            run.steps,
            [run.twist, run.swing],
            &run.orientation,
            run.peak_torque.max,
            run.tracking_error.to_vec(),
            run.momentum.max_rel,
        )
    }
}

impl RunRecord {
    /// The record of a run at step `dt` of `steps` steps that ends with A at `orientation`
    /// (its twist and swing, rad), with the peak torque `peak` (N·m), the tracking errors (rad) and
    /// the relative momentum drift; no saturation, no spine twist, no time yet.
    pub(super) fn new(
        dt: f64,
        steps: usize,
        [twist, swing]: [f64; 2],
        orientation: &nalgebra::UnitQuaternion<f64>,
        peak: f64,
        tracking_error_rad: Vec<f64>,
        momentum_drift: f64,
    ) -> Self {
        let swing_vector = super::swing_vector(orientation, twist);
        RunRecord {
            dt,
            steps,
            twist_deg: twist.to_degrees(),
            swing_deg: swing.to_degrees(),
            peak_torque_nm: peak,
            tracking_error_rad,
            momentum_drift,
            run_time_s: 0.0,
            saturation: Vec::new(),
            spine_twist_max_deg: None,
            swing_vector: swing_vector.map(f64::to_degrees),
        }
    }
}

/// Each quantity's extrapolations, order, estimate and gap from the runs so far.
pub(super) fn convergences(runs: &[RunRecord], reference: &Reference, settings: &RapierSettings) -> Vec<Convergence> {
    let ratio = |w: &[RunRecord]| w[0].dt / w[1].dt;
    let ref_peak = if reference.peak_torque > 0.0 { reference.peak_torque } else { 1.0 };
    Quantity::ALL
        .iter()
        .map(|&quantity| {
            // Vector values (the swing's rotation vector; scalars as x) and their extrapolations.
            let vector = |r: &RunRecord| match quantity {
                Quantity::Twist => Vector3::new(r.twist_deg, 0.0, 0.0),
                Quantity::Swing => r.swing_vector,
                Quantity::PeakTorque => Vector3::new(r.peak_torque_nm, 0.0, 0.0),
            };
            let scalar = |v: Vector3<f64>| if quantity == Quantity::Swing { v.norm() } else { v.x };
            let ex: Vec<Vector3<f64>> =
                runs.windows(2).map(|w| super::richardson(vector(&w[0]), vector(&w[1]), ratio(w))).collect();
            let observed_order = runs.windows(3).last().and_then(|w| {
                let (d1, d2) = ((vector(&w[0]) - vector(&w[1])).norm(), (vector(&w[1]) - vector(&w[2])).norm());
                let p = (d1 / d2).ln() / ratio(&w[1..]).ln();
                p.is_finite().then_some(p)
            });
            let (reference, tolerance, scale) = match quantity {
                Quantity::Twist => (reference.twist.to_degrees(), settings.twist_tolerance_deg, 1.0),
                Quantity::Swing => (reference.swing.to_degrees(), settings.swing_tolerance_deg, 1.0),
                Quantity::PeakTorque => (reference.peak_torque, settings.peak_torque_tolerance, ref_peak),
            };
            let value = ex.last().map(|v| scalar(*v));
            let estimate = ex.windows(2).last().map(|w| (w[1] - w[0]).norm() / scale).filter(|e| e.is_finite());
            Convergence {
                quantity,
                reference,
                raw: runs.iter().map(|r| scalar(vector(r))).collect(),
                extrapolated: ex.iter().map(|v| scalar(*v)).collect(),
                observed_order,
                value,
                estimate,
                gap: value.map(|v| (v - reference).abs() / scale).filter(|g| g.is_finite()),
                tolerance,
            }
        })
        .collect()
}

/// One quantity as the verdict sees it.
#[derive(Clone, Copy)]
struct Judged {
    quantity: Quantity,
    gap: f64,
    estimate: f64,
    tolerance: f64,
    asymptotic: bool,
}

/// The verdict from the convergence records (module docs).
pub(super) fn judge(
    quantities: &[Convergence],
    reference: &Reference,
    runs: usize,
    why_stopped: &str,
    failures: &[Failure],
) -> Verdict {
    if ![reference.twist, reference.swing, reference.peak_torque].iter().all(|x| x.is_finite()) {
        return Verdict::BadReference;
    }
    let judged: Vec<Judged> = quantities
        .iter()
        .filter_map(|c| {
            // A disagreement is only claimed from a sequence that behaves as a first-order
            // method's: converged to the tolerance, or with an observed order near one.
            let (gap, estimate, tolerance) = (c.gap?, c.estimate?, c.tolerance);
            let asymptotic = estimate <= tolerance || c.observed_order.is_some_and(|p| ASYMPTOTIC.contains(&p));
            Some(Judged { quantity: c.quantity, gap, estimate, tolerance, asymptotic })
        })
        .collect();
    if runs < MIN_RUNS || judged.len() < quantities.len() {
        let mut why = why_stopped.to_string();
        if let Some(f) = failures.last() {
            why = format!("{why}; the last failure: {} at dt = {:.3e} s", f.reason, f.dt);
        }
        if runs >= MIN_RUNS {
            why = format!("{why}; a quantity is not a finite number");
        }
        return Verdict::TooFewRuns { runs, why: why.trim_start_matches("; ").to_string() };
    }
    let worst =
        |f: fn(&Judged) -> f64| judged.iter().copied().max_by(|a, b| f(a).total_cmp(&f(b))).filter(|x| f(x) > 1.0);
    if let Some(j) = worst(|j| if j.asymptotic { j.gap / (j.tolerance + j.estimate) } else { 0.0 }) {
        return Verdict::NotVerified { quantity: j.quantity, gap: j.gap, tolerance: j.tolerance, estimate: j.estimate };
    }
    if let Some(j) = worst(|j| j.estimate / j.tolerance) {
        let why = why_stopped.to_string();
        return Verdict::NotConverged {
            quantity: j.quantity,
            estimate: j.estimate,
            tolerance: j.tolerance,
            gap: j.gap,
            why,
        };
    }
    if let Some(j) = worst(|j| j.gap / j.tolerance) {
        return Verdict::WithinEstimate {
            quantity: j.quantity,
            gap: j.gap,
            tolerance: j.tolerance,
            estimate: j.estimate,
        };
    }
    Verdict::Verified
}
