//! Work-precision curves of the engines on one schedule.
//!
//! - `exact-magnus6`: the exact engine's sixth-order Magnus integration with `n = 2…2048`
//!   steps per phase (doubling); error = angle of `R_n⁻¹ R_ref` (rad) against `n = 8192`.
//! - `exact-adaptive`: [`crate::engines::exact::flip`] at tolerances 1e-2…1e-13; same error.
//! - `rapier`: rapier3d-f64 at time steps 1/60…1/32000 s (a rest-to-rest profile, so no
//!   impulse enters); error = `max(|Δtwist|, |Δswing|)` (rad) against the exact engine at
//!   1e-12 rad; secondary = relative error of the peak torque.
//! - `rapier-extrapolated`: Richardson extrapolation of successive rapier runs `dt` and `dt/2`
//!   for a first-order method, `x = (r x₂ − x₁)/(r − 1)` with `r = dt₁/dt₂` (rapier's
//!   symplectic Euler; its observed order → 1, see the `rapier` curve); its time is the two runs'.

use crate::engines::evaluate::Evaluation;
use crate::engines::exact::{flip, integrate};
use crate::engines::rapier::{simulate, RapierRun};
use crate::problem::settings::ExactSettings;
use crate::problem::Problem;
use crate::report::bench::curve::{Curve, Outcome, Timing};
use crate::schedule::Schedule;

/// Steps per phase of the fixed-step reference.
pub const REFERENCE_STEPS: usize = 8192;

/// The exact engine's fixed-step curve (steps per phase `2^1…2^11`).
pub fn exact_fixed(problem: &Problem, schedule: &Schedule) -> Curve {
    let cat = &problem.cat;
    let (reference, ref_angles) = integrate(cat, schedule, REFERENCE_STEPS, |_| {});
    let steps: Vec<f64> = (1..=11).map(|k| f64::from(1u32 << k)).collect();
    Curve::sweep("exact-magnus6", "steps per phase", "orientation error (rad)", &steps, |n| {
        let (r, a) = integrate(cat, schedule, n as usize, |_| {});
        Ok(Outcome { error: (r.inverse() * reference).angle(), secondary: Some((a.swing - ref_angles.swing).abs()) })
    })
    .angle()
    .with_secondary("swing error (rad)")
}

/// The exact engine's adaptive curve (tolerances 1e-2…1e-13 rad).
pub fn exact_adaptive(problem: &Problem, schedule: &Schedule) -> Curve {
    let cat = &problem.cat;
    let (reference, ref_angles) = integrate(cat, schedule, REFERENCE_STEPS, |_| {});
    let tolerances = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13];
    Curve::sweep("exact-adaptive", "tolerance (rad)", "orientation error (rad)", &tolerances, |tol| {
        let f = flip(cat, schedule, tol);
        if !f.converged {
            return Err(format!("did not meet {tol:e} rad (estimate {:e})", f.error_estimate));
        }
        Ok(Outcome {
            error: (f.orientation.inverse() * reference).angle(),
            secondary: Some((f.swing - ref_angles.swing).abs()),
        })
    })
    .angle()
    .with_secondary("swing error (rad)")
}

/// rapier's raw and extrapolated curves on `schedule` (give it a rest-to-rest profile) over
/// the time steps `dts` (s, decreasing by halves for the extrapolation).
pub fn rapier_curves(problem: &Problem, schedule: &Schedule, dts: &[f64]) -> [Curve; 2] {
    let cat = &problem.cat;
    let exact = Evaluation::new(cat, schedule, &ExactSettings { tolerance: 1e-12, ..problem.exact });
    let run_at = |dt: f64| simulate(cat, schedule, &problem.rapier.with_dt(dt));
    let error = |twist: f64, swing: f64| (twist - exact.flip.twist).abs().max((swing - exact.flip.swing).abs());
    let raw = Curve::sweep("rapier", "time step (s)", "max twist/swing error (rad)", dts, |dt| {
        let run = run_at(dt).map_err(|e| e.to_string())?;
        let peak = (run.peak_torque.max - exact.peaks.max) / exact.peaks.max;
        Ok(Outcome { error: error(run.twist, run.swing), secondary: Some(peak) })
    })
    .angle()
    .with_secondary("peak torque rel. error");
    // Each extrapolated point reruns its pair and is timed as the pair (the raw timing rule).
    let extrapolate = |a: &RapierRun, b: &RapierRun| {
        let r = a.dt / b.dt;
        let x = |p: f64, q: f64| (r * q - p) / (r - 1.0);
        error(x(a.twist, b.twist), x(a.swing, b.swing))
    };
    let mut points = Vec::new();
    for w in dts.windows(2) {
        let pair = Curve::sweep("", "", "", &[w[0]], |_| {
            let a = run_at(w[0]).map_err(|e| e.to_string())?;
            let b = run_at(w[1]).map_err(|e| e.to_string())?;
            Ok(Outcome::error(extrapolate(&a, &b)))
        });
        points.extend(pair.points);
    }
    let extrapolated = Curve {
        name: "rapier-extrapolated".into(),
        setting: "coarser time step of the pair (s)".into(),
        error: "max twist/swing error (rad)".into(),
        secondary: None,
        error_is_angle: true,
        points,
    };
    [raw, extrapolated]
}

/// The wall time of one `catflip`-style evaluation (flip, peaks, jumps) for the record.
pub fn evaluation_timing(problem: &Problem, schedule: &Schedule) -> Timing {
    Timing::measure(|| {
        std::hint::black_box(Evaluation::new(&problem.cat, schedule, &problem.exact));
    })
}
