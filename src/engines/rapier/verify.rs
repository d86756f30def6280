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
//! The peak torque is extrapolated motor by motor: each motor's peak has its own `X₀`
//! ([`super::richardson_peaks`]), and the peak at `dt → 0` is their largest (the largest raw
//! peak can pass from one motor to another as the step shrinks, and an extrapolation across
//! that change lands on neither); its observed order is that motor's, its estimate the largest
//! change of any motor that may be the peak.
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

use super::refinement::{convergences, judge, refine, saturated};
use super::verdict::{Reference, RunRecord, StepSource, Verdict, Verification};
use super::{RapierError, RapierOptions, RapierRun};
use crate::engines::evaluate::{released_on, released_torques};
use crate::engines::models::TwoMotorCat;
use crate::engines::motors::motor_demand_from;
use crate::engines::torque::piece_samples;
use crate::problem::settings::{ExactSettings, RapierSettings, TimeStep};
use crate::schedule::Trajectory;

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
            saturated(&mut quantities, runs, &run.saturation, [run.twist, run.swing, run.dt], reference)
        }
        (Some(_), Some(d)) if !d.within() => Verdict::BeyondMotors { exceeded: d.verdict() },
        _ => judge(&quantities, reference, runs.len(), &refined.why_stopped, &refined.failures),
    };
    let verification = refined.verification(verdict, quantities, (source, scales), settings, demand);
    Ok(Verification { finest, ..verification })
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
            run.peak_torque.per_motor(),
            run.tracking_error.to_vec(),
            run.momentum.max_rel,
        )
    }
}
