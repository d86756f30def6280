//! The step refinement of a verification and its verdict (the module docs of [`super::verify`]):
//! runs at halving steps until rapier's own error estimate meets the tolerances or a budget stops
//! it ([`refine`]), each quantity's extrapolations, observed order, estimate and gap
//! ([`convergences`]), and the verdict on them ([`judge`]); shared by the two-body verification
//! and the tree scene's ([`super::tree_run`]).

use std::time::Instant;

use nalgebra::Vector3;

use super::saturation::MotorSaturation;
use super::verdict::{
    Convergence, Failure, Quantity, Reference, RunRecord, StepSource, Verdict, Verification, ASYMPTOTIC, MIN_RUNS,
};
use super::{RapierError, TimeScales, MAX_STEPS};
use crate::engines::motors::MotorDemand;
use crate::problem::settings::RapierSettings;

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

/// Each quantity's extrapolations, order, estimate and gap from the runs so far.
pub(super) fn convergences(runs: &[RunRecord], reference: &Reference, settings: &RapierSettings) -> Vec<Convergence> {
    let ratio = |w: &[RunRecord]| w[0].dt / w[1].dt;
    let ref_peak = if reference.peak_torque > 0.0 { reference.peak_torque } else { 1.0 };
    // Each motor's peak is extrapolated on its own and the largest taken: the largest raw peak can
    // pass from one motor to another as the step shrinks (a servo's ripple, first order in the
    // step, lifting a motor that does not peak in the plan above one that does), and an
    // extrapolation across that change lands on neither (a cat with a tail and legs: 2.0 % below
    // the plan's peak by the largest, 0.005 % motor by motor). Runs without each motor's peak
    // (none but a test's) extrapolate the largest.
    let motors = runs.first().map_or(0, |r| r.motor_peaks_nm.len());
    let by_motor = motors > 0 && runs.iter().all(|r| r.motor_peaks_nm.len() == motors);
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
            let ex: Vec<Vector3<f64>> = runs
                .windows(2)
                .map(|w| match quantity {
                    Quantity::PeakTorque if by_motor => Vector3::new(
                        w[0].motor_peaks_nm
                            .iter()
                            .zip(&w[1].motor_peaks_nm)
                            .map(|(c, f)| super::richardson(*c, *f, ratio(w)))
                            .fold(f64::NEG_INFINITY, f64::max),
                        0.0,
                        0.0,
                    ),
                    _ => super::richardson(vector(&w[0]), vector(&w[1]), ratio(w)),
                })
                .collect();
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

/// The verdict on a finest run whose motors saturated (its `saturation`, twist and swing in rad,
/// step `dt`): the raw values only, its quantities not extrapolated (a saturated run is not on the
/// plan, so the step refinement has nothing to converge to), and the planned flip of `reference`.
pub(super) fn saturated(
    quantities: &mut [Convergence],
    runs: &[RunRecord],
    saturation: &[MotorSaturation],
    [twist, swing, dt]: [f64; 3],
    reference: &Reference,
) -> Verdict {
    for c in quantities.iter_mut() {
        c.extrapolated.clear();
        (c.observed_order, c.value, c.estimate, c.gap) = (None, None, None, None);
    }
    let n = runs.len();
    Verdict::Saturated {
        motors: saturation.to_vec(),
        twist_deg: twist.to_degrees(),
        swing_deg: swing.to_degrees(),
        twist_change_deg: (n >= 2).then(|| runs[n - 1].twist_deg - runs[n - 2].twist_deg),
        planned_twist_deg: reference.twist.to_degrees(),
        planned_swing_deg: reference.swing.to_degrees(),
        dt,
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;
    use std::f64::consts::PI;

    /// A run at step `dt` whose two motors peak at `peaks` (each the plan's plus a first-order
    /// error), recorded motor by motor unless `by_motor` is false (then its largest peak alone,
    /// as a run that kept no motor's own would be judged).
    fn run(dt: f64, peaks: [f64; 2], by_motor: bool) -> RunRecord {
        let mut r = RunRecord::new(dt, 1, [PI, 0.0], &UnitQuaternion::identity(), peaks.to_vec(), vec![], 0.0);
        if !by_motor {
            r.motor_peaks_nm.clear();
        }
        r
    }

    /// The plan's peaks are 1.00 (motor 0) and 0.98 (motor 1); motor 1 rides a ripple of
    /// `+0.06·dt/ms`, motor 0 an error of `+0.01·dt/ms`. At 1 ms and 0.5 ms motor 1 reads highest,
    /// at 0.25 ms motor 0: the largest raw peaks, 1.04, 1.01, 1.0025, extrapolate to 0.995 (0.5 %
    /// below the plan), each motor's to its own, the largest 1.00.
    #[test]
    fn the_peak_is_extrapolated_motor_by_motor_when_the_runs_record_each() {
        let plan = [1.0, 0.98];
        let error = [0.01, 0.06];
        let peaks = |dt: f64| [plan[0] + error[0] * dt * 1e3, plan[1] + error[1] * dt * 1e3];
        let reference = Reference { twist: PI, swing: 0.0, peak_torque: 1.0 };
        let settings = RapierSettings::default();
        let peak = |by_motor: bool| {
            let runs: Vec<RunRecord> = [1e-3, 5e-4, 2.5e-4].iter().map(|&dt| run(dt, peaks(dt), by_motor)).collect();
            let c = convergences(&runs, &reference, &settings);
            let p = c.iter().find(|c| c.quantity == Quantity::PeakTorque).expect("a peak");
            (p.value.expect("extrapolated"), p.raw.clone())
        };
        let (largest, raw) = peak(false);
        assert!((raw[1] - 1.01).abs() < 1e-12 && (raw[2] - 1.0025).abs() < 1e-12, "{raw:?}");
        assert!((largest - 0.995).abs() < 1e-12, "the largest raw peak extrapolates to {largest}");
        let (by_motor, raw_by_motor) = peak(true);
        assert_eq!(raw, raw_by_motor, "the raw peaks are the largest either way");
        assert!((by_motor - 1.0).abs() < 1e-12, "motor by motor: {by_motor}");
    }
}
