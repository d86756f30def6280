//! Work-precision curves of the engines on one schedule.
//!
//! - `exact-magnus6`: the exact engine's sixth-order Magnus integration with `n = 2…2048`
//!   steps per phase (doubling); error = angle of `R_n⁻¹ R_ref` (rad) against `n = 8192`.
//! - `exact-adaptive`: [`crate::engines::exact::flip`] at tolerances 1e-2…1e-13; same error.
//! - `rapier`: rapier3d-f64 at time steps 1/60…1/32000 s on a rest-to-rest profile (cycloidal;
//!   no impulse enters); error = `max(|Δtwist|, |Δs|)` (rad) against the exact engine at
//!   1e-12 rad, with `s` the swing's rotation vector ([`FinalAngles`]); secondary = relative
//!   error of the peak torque.
//! - `rapier-extrapolated`: Richardson extrapolation of successive rapier runs `dt` and `dt/2`
//!   for a first-order method, `x = x₂ + (x₂ − x₁)/(r − 1)` with `r = dt₁/dt₂`, of the twist and
//!   of the swing vector (as [`crate::engines::rapier::verify`] does); same error; its time is
//!   the two runs'.
//! - `rapier-<profile>` and `rapier-<profile>-extrapolated`: the same on the problem's own
//!   schedule when its profile is another (the paper's cosine, whose rate jumps when unbending
//!   starts).
//!
//! # Why the swing vector, not the swing angle
//!
//! The swing angle `|s|` is the length of a vector that rapier gets wrong by `c·dt`; where the
//! exact swing `s₀` is small against that error the length `|s₀ + c dt|` is not smooth in `dt`
//! (a cone), and a first-order extrapolation of it tends to `ĉ·s₀` instead of `|s₀|`: an error
//! of `|s₀| − ĉ·s₀`, up to `2|s₀|`, that no step removes. On the paper problem the exact swing is
//! `|s₀|` = 1.030e-2 rad while rapier's swing-vector error is about `258 rad/s · dt`, nearly
//! opposite to `s₀`, so the angle is smooth only for `dt ≪ 4e-5` s. Comparing and extrapolating
//! angles (as the bench once did) gave a raw curve that was not monotone and an extrapolated
//! curve that plateaued at 2.05e-2 rad ≈ `2|s₀|` from `dt` = 5e-4 to 1.25e-4 s. The vectors fix
//! it. Measured on problems/paper.toml with `cargo run --release --example rapier_convergence --
//! PROFILE` (errors in rad; the bench's steps 1/1000…1/32000 s; the other arguments of that
//! example give the sensitivities below):
//!
//! | profile | dt (s) | 1e-3 | 5e-4 | 2.5e-4 | 1.25e-4 | 6.25e-5 | 3.125e-5 |
//! |---|---|---:|---:|---:|---:|---:|---:|
//! | cycloidal | raw `|Δtwist|` | 8.19e-2 | 4.60e-2 | 2.33e-2 | 1.17e-2 | 5.83e-3 | 2.91e-3 |
//! | cycloidal | raw `|Δs|` | 2.00e-1 | 1.30e-1 | 6.46e-2 | 3.23e-2 | 1.61e-2 | 8.07e-3 |
//! | cycloidal | extrapolated (pair from dt) | 7.87e-2 | 2.73e-3 | 6.88e-4 | 1.73e-4 | 4.33e-5 | |
//! | paper-cosine | raw | 2.17e-1 | 1.25e-1 | 6.13e-2 | 3.03e-2 | 1.51e-2 | 7.53e-3 |
//! | paper-cosine | extrapolated (pair from dt) | 3.29e-2 | 2.18e-3 | 6.07e-4 | 1.65e-4 | 3.91e-5 | |
//!
//! So rapier is cleanly first order from `dt` ≈ 5e-4 s, its extrapolation second order, and the
//! paper's schedule reaches 1e-3 rad extrapolated from the pair 2.5e-4/1.25e-4 s.
//!
//! # What is rapier's own
//!
//! - **Steps of 1 ms and coarser are pre-asymptotic.** The error there is not `∝ dt` (the
//!   cycloidal raw error rises from 7.4e-2 at 2 ms to 2.0e-1 at 1 ms; the twist error changes
//!   sign between 4 and 2 ms; the momentum drift is 1.75 % at 2 ms and 1.56 % at 1 ms, then
//!   halves), and it depends erratically on the step count: on the smooth schedule the twist
//!   moves by up to 6e-3 rad between 1429 and 1433 steps (dt ≈ 1 ms) but by 1.0e-6 rad per step,
//!   steadily, at 11429…11433 steps. None of it is the scene's: the twist and swing stay within
//!   3.4e-4 rad at 1 ms (where the bump is 0.13 rad) and 7.2e-5 rad at 0.25 ms across motor
//!   bandwidths `α` = 5…40 per step, 8 or 32 Gauss–Seidel sweeps, and a cross of 1e-9…1e-3 of a
//!   half's mass (2 sweeps do move them, by 15 %).
//! - **The paper's rate jump is negligible.** Where the unbend's jump falls between steps moves
//!   the twist by up to 1.2e-5 rad from one step count to the next at 11429…11433 steps
//!   (dt ≈ 1.25e-4 s; ±5e-6 rad about a straight line), far below the extrapolated error, which
//!   converges at order ≈ 2 as on the smooth profile.
//! - **The end time is exact**: a run takes `ceil(T/dt)` steps of `T/ceil(T/dt)`, so the last
//!   orientation is read at `T`.

use crate::engines::evaluate::Evaluation;
use crate::engines::exact::{flip, integrate};
use crate::engines::models::TwoMotorCat;
use crate::engines::rapier::{richardson, simulate, swing_vector, RapierRun};
use crate::measure::bench::curve::{Curve, Outcome, Timing};
use crate::problem::settings::ExactSettings;
use crate::problem::Problem;
use crate::schedule::profile::Profile;
use crate::schedule::Schedule;
use nalgebra::{UnitQuaternion, Vector3};

/// Steps per phase of the fixed-step reference.
pub const REFERENCE_STEPS: usize = 8192;

/// The exact engine's fixed-step curve (steps per phase `2^1…2^11`).
pub fn exact_fixed(problem: &Problem, schedule: &Schedule) -> Curve {
    let cat = &problem.cat.half();
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
    let cat = &problem.cat.half();
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

/// The final twist and swing as the rapier curves compare them: the twist (rad, continued) and
/// the swing's rotation vector (rad, [`swing_vector`]), both smooth in rapier's step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinalAngles {
    /// Signed twist about A's initial `+z`, rad.
    pub twist: f64,
    /// The swing's rotation vector, rad (its length is the swing angle).
    pub swing: Vector3<f64>,
}

impl FinalAngles {
    /// The angles of A's final `orientation` with (continued) twist `twist`, rad.
    pub fn new(orientation: &UnitQuaternion<f64>, twist: f64) -> Self {
        Self { twist, swing: swing_vector(orientation, twist) }
    }

    /// The angles at the end of a rapier run.
    pub fn of_run(run: &RapierRun) -> Self {
        Self::new(&run.orientation, run.twist)
    }

    /// `max(|Δtwist|, |Δswing vector|)` against `reference`, rad. The swing vector's gap bounds
    /// the swing angle's (`||a| − |b|| ≤ |a − b|`) and, unlike it, is `O(dt)` for rapier.
    pub fn error(&self, reference: &FinalAngles) -> f64 {
        (self.twist - reference.twist).abs().max((self.swing - reference.swing).norm())
    }

    /// First-order Richardson extrapolation `f + (f − c)/(r − 1)` of a coarse run `c` and a fine
    /// run `f` with step ratio `r = dt_c/dt_f`, of the twist and of the swing vector (as
    /// [`crate::engines::rapier::verify`] does).
    pub fn extrapolate(c: &FinalAngles, f: &FinalAngles, r: f64) -> FinalAngles {
        FinalAngles { twist: richardson(c.twist, f.twist, r), swing: richardson(c.swing, f.swing, r) }
    }
}

/// rapier's raw and extrapolated curves over the time steps `dts` (s, decreasing by halves for
/// the extrapolation): `rapier` and `rapier-extrapolated` on `smooth` (give it a rest-to-rest
/// profile), then, when the problem's own profile is another, `rapier-<profile>` and
/// `rapier-<profile>-extrapolated` on the problem's schedule (`smooth` with that profile).
pub fn rapier_curves(problem: &Problem, smooth: &Schedule, dts: &[f64]) -> Vec<Curve> {
    let mut curves = rapier_pair(problem, smooth, dts, "rapier");
    let own = smooth.with_profile(Profile::library(problem.manoeuvre.profile));
    if own != *smooth {
        curves.extend(rapier_pair(problem, &own, dts, &format!("rapier-{}", problem.manoeuvre.profile)));
    }
    curves
}

/// The raw and extrapolated curves of one schedule, named `name` and `name-extrapolated`.
fn rapier_pair(problem: &Problem, schedule: &Schedule, dts: &[f64], name: &str) -> Vec<Curve> {
    let cat = &problem.cat.half();
    let exact = Evaluation::of_paper(
        cat,
        schedule,
        &problem.drop.spin(),
        &problem.actuator.motors(),
        &ExactSettings { tolerance: 1e-12, ..problem.exact },
    );
    let reference = FinalAngles::new(&exact.flip.orientation, exact.flip.twist);
    let model = TwoMotorCat::paper(*cat);
    let run_at = |dt: f64| simulate(&model, schedule, &problem.rapier.with_dt(dt));
    let error = "max(|Δtwist|, |Δswing vector|) (rad)";
    let profile = schedule.profile.name();
    let raw = Curve::sweep(name, &format!("time step (s), {profile} profile"), error, dts, |dt| {
        let run = run_at(dt).map_err(|e| e.to_string())?;
        let peak = (run.peak_torque.max - exact.peaks.max) / exact.peaks.max;
        Ok(Outcome { error: FinalAngles::of_run(&run).error(&reference), secondary: Some(peak) })
    })
    .angle()
    .with_secondary("peak torque rel. error");
    // Each extrapolated point reruns its pair and is timed as the pair (the raw timing rule).
    let mut points = Vec::new();
    for w in dts.windows(2) {
        let pair = Curve::sweep("", "", "", &[w[0]], |_| {
            let a = run_at(w[0]).map_err(|e| e.to_string())?;
            let b = run_at(w[1]).map_err(|e| e.to_string())?;
            let x = FinalAngles::extrapolate(&FinalAngles::of_run(&a), &FinalAngles::of_run(&b), a.dt / b.dt);
            Ok(Outcome::error(x.error(&reference)))
        });
        points.extend(pair.points);
    }
    let extrapolated = Curve {
        name: format!("{name}-extrapolated"),
        setting: format!("coarser time step of the pair (s), {profile} profile"),
        error: error.into(),
        secondary: None,
        error_is_angle: true,
        points,
    };
    vec![raw, extrapolated]
}

/// The wall time of one `catflip`-style evaluation (flip, peaks, jumps) for the record.
pub fn evaluation_timing(problem: &Problem, schedule: &Schedule) -> Timing {
    Timing::measure(|| {
        std::hint::black_box(Evaluation::of_paper(
            &problem.cat.half(),
            schedule,
            &problem.drop.spin(),
            &problem.actuator.motors(),
            &problem.exact,
        ));
    })
}
