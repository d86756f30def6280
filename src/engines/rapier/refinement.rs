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
use super::{largest, RapierError, TimeScales, MAX_STEPS};
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
    // Each motor's peak extrapolated on its own (`richardson_peaks`); runs without them (none but
    // a test's) extrapolate the largest raw peak as the other quantities are.
    let motors = runs.first().map_or(0, |r| r.motor_peaks_nm.len());
    let by_motor = motors > 0 && runs.iter().all(|r| r.motor_peaks_nm.len() == motors);
    let peaks = by_motor.then(|| MotorPeaks::of(runs));
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
            let ex: Vec<Vector3<f64>> = match (&peaks, quantity) {
                (Some(p), Quantity::PeakTorque) => {
                    p.limits.iter().map(|l| Vector3::new(largest(l), 0.0, 0.0)).collect()
                }
                _ => runs.windows(2).map(|w| super::richardson(vector(&w[0]), vector(&w[1]), ratio(w))).collect(),
            };
            // The order of the motor whose extrapolation is the last value (the peak's), or of the
            // quantity itself.
            let lead = |r: &RunRecord| match (&peaks, quantity) {
                (Some(p), Quantity::PeakTorque) => {
                    Vector3::new(p.lead.map_or(f64::NAN, |i| r.motor_peaks_nm[i]), 0.0, 0.0)
                }
                _ => vector(r),
            };
            let observed_order = runs.windows(3).last().and_then(|w| {
                let (d1, d2) = ((lead(&w[0]) - lead(&w[1])).norm(), (lead(&w[1]) - lead(&w[2])).norm());
                let p = (d1 / d2).ln() / ratio(&w[1..]).ln();
                p.is_finite().then_some(p)
            });
            let (reference, tolerance, scale) = match quantity {
                Quantity::Twist => (reference.twist.to_degrees(), settings.twist_tolerance_deg, 1.0),
                Quantity::Swing => (reference.swing.to_degrees(), settings.swing_tolerance_deg, 1.0),
                Quantity::PeakTorque => (reference.peak_torque, settings.peak_torque_tolerance, ref_peak),
            };
            let value = ex.last().map(|v| scalar(*v));
            let estimate = match (&peaks, quantity) {
                (Some(p), Quantity::PeakTorque) => p.estimate().map(|e| e / scale),
                _ => ex.windows(2).last().map(|w| (w[1] - w[0]).norm() / scale),
            }
            .filter(|e| e.is_finite());
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

/// Each motor's peak ([`RunRecord::motor_peaks_nm`]) extrapolated on its own from each pair of
/// successive runs.
struct MotorPeaks {
    /// Per pair of runs, each motor's extrapolation.
    limits: Vec<Vec<f64>>,
    /// The motor whose extrapolation in the last pair is the largest (the value's).
    lead: Option<usize>,
}

impl MotorPeaks {
    fn of(runs: &[RunRecord]) -> Self {
        let limits: Vec<Vec<f64>> = runs
            .windows(2)
            .map(|w| super::richardson_peaks(&w[0].motor_peaks_nm, &w[1].motor_peaks_nm, w[0].dt / w[1].dt))
            .collect();
        let lead = limits.last().and_then(|l| (0..l.len()).max_by(|&a, &b| l[a].total_cmp(&l[b])));
        MotorPeaks { limits, lead }
    }

    /// The largest change between the last two pairs' extrapolations of any motor that may be
    /// the peak: one whose extrapolation in either pair reaches the smaller of the two pairs'
    /// peaks (two motors trading places would hide each other's change in the change of the
    /// largest). None with fewer than two pairs.
    fn estimate(&self) -> Option<f64> {
        let [before, last] = self.limits.last_chunk::<2>()?;
        let floor = largest(before).min(largest(last));
        let contenders = before.iter().zip(last).filter(|(b, l)| b.max(**l) >= floor || b.is_nan() || l.is_nan());
        Some(largest(&contenders.map(|(b, l)| (l - b).abs()).collect::<Vec<_>>()))
    }
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
            c.into_iter().find(|c| c.quantity == Quantity::PeakTorque).expect("a peak")
        };
        let largest = peak(false);
        let raw = &largest.raw;
        assert!((raw[1] - 1.01).abs() < 1e-12 && (raw[2] - 1.0025).abs() < 1e-12, "{raw:?}");
        let value = largest.value.expect("extrapolated");
        assert!((value - 0.995).abs() < 1e-12, "the largest raw peak extrapolates to {value}");
        // Its differences, 0.03 then 0.0075, read as an order of 2: neither motor's.
        assert!((largest.observed_order.expect("an order") - 2.0).abs() < 1e-9, "{:?}", largest.observed_order);
        let by_motor = peak(true);
        assert_eq!(&by_motor.raw, raw, "the raw peaks are the largest either way");
        let value = by_motor.value.expect("extrapolated");
        assert!((value - 1.0).abs() < 1e-12, "motor by motor: {value}");
        // Motor 0's order (the value's), and no change between the two pairs' extrapolations.
        assert!((by_motor.observed_order.expect("an order") - 1.0).abs() < 1e-9, "{:?}", by_motor.observed_order);
        assert!(by_motor.estimate.expect("an estimate") < 1e-12, "{:?}", by_motor.estimate);
    }

    /// Two motors that trade places between the last two pairs of runs: the largest
    /// extrapolation stays at 1.00, yet each motor's moved by 0.01, and the estimate says so; a
    /// motor far below the peak does not count, and one that is not a number makes the estimate
    /// and the largest peak not numbers either.
    #[test]
    fn the_peak_estimate_counts_every_motor_that_may_be_the_peak() {
        let traded = MotorPeaks { limits: vec![vec![1.0, 0.99, 0.5], vec![0.99, 1.0, 0.2]], lead: Some(1) };
        let estimate = traded.estimate().expect("two pairs");
        assert!((estimate - 0.01).abs() < 1e-12, "{estimate}");
        let broken = MotorPeaks { limits: vec![vec![1.0, 0.99], vec![1.0, f64::NAN]], lead: Some(0) };
        assert!(broken.estimate().expect("two pairs").is_nan());
        assert!(largest(&[1.0, f64::NAN]).is_nan() && largest(&[f64::NAN, 1.0]).is_nan());
        assert!(MotorPeaks { limits: vec![vec![1.0]], lead: Some(0) }.estimate().is_none());
    }
}
