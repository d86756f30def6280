//! `catflip bench`: run time against error for every engine and optimiser, one run, one
//! machine, one report; and numerical stress tests.
//!
//! Each curve is a sweep of one resolution setting ([`curve::Curve`]): the exact engine fixed-step
//! and adaptive, rapier raw and extrapolated ([`engines`]), the profile QP over `N`, the
//! calibration over tolerances, the certified retiming over grid sizes and the whole-manoeuvre
//! optimiser over control points ([`optimizers`]). Every point is timed [`curve::Timing::measure`]
//! (best and median of up to 7 runs within a budget) on this machine, named in the report.
//! The table "time to reach 1e-3 / 1e-6 / 1e-9 rad" takes, per engine curve, the least best
//! time of a point at or below the target ([`crate::report::bench`]).
//!
//! Stress: the named edge cases ([`stress`]) and a seeded sample of random problems spanning
//! decades ([`random`], with the invariants they are checked against).
//!
//! ## Adding a curve
//! Write `fn my_curve(...) -> Curve` that computes the reference once and returns
//! `Curve::sweep(name, setting, error, &settings, |x| { …solve at x…; Ok(Outcome::error(gap)) })`
//! (an `Err(status)` for a run without a result), then push it in [`fn@bench`]. The CSV, the
//! Markdown and the plots pick it up by its name. When the error needs a costly measurement
//! that is not the method's own work, [`curve::Curve::sweep_with`] times only the solve; a
//! sentence on what the error means goes in [`BenchReport::notes`].
//!
//! Times are for the record, not for pass/fail (the criterion benches in `benches/` are the
//! controlled measurement).

pub mod curve;
pub mod engines;
pub mod optimizers;
pub mod random;
pub mod stress;

use serde::Serialize;

use crate::engines::resolved::Resolved;
use crate::problem::ProfileKind;
use curve::{Curve, CurveNote, Timing};
use random::{RandomResult, Tally, Verdict};
use stress::StressCase;

/// Why the benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The problem asks for what this computation does not model.
    #[error(transparent)]
    Problem(#[from] crate::problem::ProblemError),
    /// The base problem could not be written as TOML for the stress cases' overrides.
    #[error("cannot write the bench problem as TOML for the stress cases")]
    Toml(#[from] toml::ser::Error),
}

/// Seed of the random stress sample in the report.
pub const RANDOM_SEED: u64 = 11;
/// Random stress cases in the report.
pub const RANDOM_CASES: usize = 100;

/// Grid intervals per phase of the retiming curve (the two finest also give its reference).
pub const RETIME_GRIDS: [usize; 7] = [25, 50, 100, 200, 400, 800, 1600];
/// Control points per joint of the whole-manoeuvre optimiser's curve.
pub const WHOLE_CONTROL_POINTS: [usize; 6] = [20, 40, 60, 90, 120, 160];
/// Control points per joint of the whole-manoeuvre optimiser's reference run.
pub const WHOLE_REFERENCE_POINTS: usize = 240;

/// The whole benchmark.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BenchReport {
    /// The machine, as [`crate::measure::machine::machine`] names it.
    pub machine: String,
    /// The work-precision curves.
    pub curves: Vec<Curve>,
    /// What some curves' errors mean and their references, printed under their tables.
    pub notes: Vec<CurveNote>,
    /// Time of one default evaluation of the problem's schedule (flip, peaks, jumps).
    pub evaluation: Timing,
    /// The named stress cases.
    pub stress: Vec<StressCase>,
    /// The random stress sample's tally.
    pub random: Tally,
    /// The random cases that did not simply pass.
    pub random_notable: Vec<RandomResult>,
}

/// The rapier time steps `catflip bench` measures, s: from a game engine's 60 Hz, halving
/// (with 125 Hz between) down to 32 kHz, where rapier's first-order error meets round-off on
/// the paper's cat.
pub const RAPIER_STEPS: [f64; 10] = [
    1.0 / 60.0,
    1.0 / 125.0,
    1.0 / 250.0,
    1.0 / 500.0,
    1.0 / 1000.0,
    1.0 / 2000.0,
    1.0 / 4000.0,
    1.0 / 8000.0,
    1.0 / 16000.0,
    1.0 / 32000.0,
];

/// The full benchmark on a resolved problem: its schedule for the exact engine and the
/// calibration, a cycloidal profile (rest-to-rest) for rapier, rapier time steps `dts` (s,
/// halving).
pub fn bench(r: &Resolved, dts: &[f64]) -> Result<BenchReport, BenchError> {
    r.require_paper_cat("bench")?;
    let p = &r.problem;
    let smooth = r.with_library(ProfileKind::Cycloidal);
    let mut curves = vec![engines::exact_fixed(p, &r.schedule), engines::exact_adaptive(p, &r.schedule)];
    curves.extend(engines::rapier_curves(p, &smooth, dts));
    let nodes: Vec<usize> = (0..10).map(|k| 10usize << k).collect();
    curves.push(optimizers::qp_curve(&p.cat.half(), &r.schedule, &nodes));
    let tolerances = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11];
    curves.push(optimizers::calibration_curve(&p.cat.half(), &r.schedule, &tolerances));
    let (retime, retime_note) = optimizers::retime_curve(&p.cat.half(), &r.schedule, &RETIME_GRIDS, [800, 1600]);
    let (whole, whole_note) = optimizers::whole_curve(p, &WHOLE_CONTROL_POINTS, WHOLE_REFERENCE_POINTS);
    curves.extend([retime, whole]);
    let base = toml::to_string(p)?;
    let (results, tally) = random::run_many(&base, RANDOM_SEED, RANDOM_CASES);
    Ok(BenchReport {
        machine: crate::measure::machine::machine(),
        curves,
        notes: vec![retime_note, whole_note],
        evaluation: engines::evaluation_timing(p, &r.schedule),
        stress: stress::stress(p)?,
        random: tally,
        random_notable: results.into_iter().filter(|x| x.verdict != Verdict::Passed).collect(),
    })
}
