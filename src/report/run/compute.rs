//! Everything `catflip run` computes for one problem, before anything is written.
//!
//! The independent computations run in parallel (rayon): the profile QP and its refinements,
//! the whole-manoeuvre optimum, the certified retimings and the rapier verification of every
//! library schedule start together; each optimised schedule is verified, and its schedule file
//! written, as soon as it exists; the whole optimum's robustness (the exact engine's Monte Carlo,
//! [`crate::robust`]) runs beside its verification. Each computation is deterministic and its result lands in a fixed place, so the output does not
//! depend on the number of threads.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::timings::Stopwatch;
use super::{figures, RunError, Verified};
use crate::engines::circulation::ResolvedCirculation;
use crate::engines::evaluate::Evaluation;
use crate::engines::rapier::{RapierError, Verification};
use crate::engines::resolved::Resolved;
use crate::exchange::{model_files, schedule_files, ExportOptions};
use crate::optimize::{optimize, OptimizeReport};
use crate::report::audit::Audit;
use crate::report::simulate::{exact_report, rapier_outcome};
use crate::report::whole::{retime_rows, verify_whole, RetimeRow, WholeReport, WHOLE};
use crate::robust::{robustness, Robustness};
use crate::schedule::variant::{Origin, Variant};
use crate::schedule::Schedule;

/// The results of one run.
pub(super) struct Computed {
    pub audit: Audit,
    pub opt: OptimizeReport,
    pub whole: WholeReport,
    pub retimed: Vec<RetimeRow>,
    /// Library schedules first (in [`crate::problem::ProfileKind::ALL`] order), then the
    /// optimised ones, then the most refined one with the calibrated circulation.
    pub verified: Vec<Verified>,
    pub whole_verification: Option<Verification>,
    /// The animation's files, when the whole optimum exists and was animated.
    pub animation: Option<Vec<PathBuf>>,
    /// The whole optimum's robustness on the exact engine (`[robust]`'s draws, ideal tracking),
    /// when the optimum exists.
    pub robustness: Option<Robustness>,
    /// Everything under `schedules/` as (path in the results folder, contents): the problem's
    /// schedule, every optimised one, the model files, the whole optimum's.
    pub files: Vec<(String, String)>,
}

/// Files as (path in the results folder, contents).
type Files = Vec<(String, String)>;

/// The whole optimum's branch: the report, its verification, its animation's files, its
/// robustness, its schedule files.
type WholeBranch = (WholeReport, Option<Verification>, Option<Vec<PathBuf>>, Option<Robustness>, Files);

/// One schedule to verify: its name, itself, its circulation and its exact evaluation when
/// one exists already.
type Run<'a> = (Variant, Schedule, ResolvedCirculation, Option<&'a Evaluation>);

/// Computes everything for `r` (module docs).
pub(super) fn compute(
    r: &Resolved,
    plots: &Path,
    export: &ExportOptions,
    clock: &Stopwatch,
) -> Result<Computed, RunError> {
    let audit = clock.time("audit", || crate::report::audit::audit_with_exact(r))?;
    let library: Vec<Run> = r
        .library()
        .iter()
        .map(|(k, s, e)| (Variant::new(Origin::Library(*k)), s.clone(), r.circulation, Some(e)))
        .collect();
    // Four branches; each verifies what it produced as soon as it has it. The longest chains
    // start first: the whole optimum (solve, then verification beside the animation) and the
    // refinement (sequential steps, then four verifications); the retimings and the library's
    // verifications fill the gaps.
    let problem_file = || {
        let own = [("problem".to_string(), r.schedule.clone())];
        clock.time("schedule files: problem", || schedule_files(&r.problem, &own, export))
    };
    let (whole, (opt, (retimed, (library, problem_files)))) = rayon::join(
        || whole_and_verify(r, plots, export, clock),
        || {
            rayon::join(
                || optimise_and_verify(r, export, clock),
                || rayon::join(|| retimings(r, clock), || rayon::join(|| verify_all(r, library, clock), problem_file)),
            )
        },
    );
    let (
        (opt, optimised, optimised_files),
        (whole, whole_verification, animation, robustness, whole_files),
        mut verified,
    ) = (opt?, whole?, library?);
    verified.extend(optimised);
    let mut files = problem_files?;
    files.extend(optimised_files);
    files.extend(model_files(&r.problem).map(|(n, text)| (format!("schedules/{n}"), text)));
    files.extend(whole_files);
    Ok(Computed { audit, opt, whole, retimed, verified, whole_verification, animation, robustness, files })
}

/// The profile QP and its refinements, then their verification, and the recommended schedule's:
/// the most refined one with the calibrated circulation (when the calibration converged).
fn optimise_and_verify(
    r: &Resolved,
    export: &ExportOptions,
    clock: &Stopwatch,
) -> Result<(OptimizeReport, Vec<Verified>, Files), RunError> {
    let opt = clock.time("profile QP and refinements", || optimize(r))?;
    let mut runs: Vec<Run> =
        opt.optima().map(|o| (o.variant, o.schedule.clone(), r.circulation, Some(&o.exact))).collect();
    let most_refined =
        opt.optima().last().filter(|o| matches!(o.variant.origin, Origin::Refined | Origin::RefinedAllPhases));
    if let (Some(o), Some(cal)) = (most_refined, r.calibrated()) {
        runs.push((o.variant.calibrated(), o.schedule.with_circulation(cal.radians), cal, None));
    }
    let exported: Vec<(String, Schedule)> = runs.iter().map(|(v, s, _, _)| (v.to_string(), s.clone())).collect();
    let (verified, files) = rayon::join(
        || verify_all(r, runs, clock),
        || clock.time("schedule files: optimised", || schedule_files(&r.problem, &exported, export)),
    );
    Ok((opt, verified?, files?))
}

/// The whole-manoeuvre optimum, then its verification and, beside it, its animation in `plots`
/// (the schedule to replay: it flips the cat exactly).
fn whole_and_verify(
    r: &Resolved,
    plots: &Path,
    export: &ExportOptions,
    clock: &Stopwatch,
) -> Result<WholeBranch, RunError> {
    let whole = clock.time("whole optimum", || crate::report::whole::whole(r))?;
    let ((verification, robustness), (animation, files)) = rayon::join(
        || {
            rayon::join(
                || clock.time(format!("verify {WHOLE}"), || verify_whole(r, &whole)),
                || {
                    whole.spline().map(|spline| {
                        clock
                            .time(format!("robustness of {WHOLE}"), || robustness(&r.problem, spline, WHOLE))
                            .map_err(RapierError::from)
                    })
                },
            )
        },
        || {
            rayon::join(
                || {
                    whole.spline().map(|spline| {
                        clock.time(format!("animate {WHOLE}"), || figures::animation_of(r, plots, WHOLE, spline))
                    })
                },
                || clock.time(format!("schedule files: {WHOLE}"), || whole_files(r, &whole, export)),
            )
        },
    );
    Ok((whole, verification?, animation.transpose()?, robustness.transpose()?, files?))
}

/// The whole optimum's CSV and sidecar, when it exists.
fn whole_files(r: &Resolved, whole: &WholeReport, export: &ExportOptions) -> Result<Files, RunError> {
    let Some(file) = crate::report::whole::optimum_file(&r.problem, whole, export)? else { return Ok(Vec::new()) };
    let sidecar = file.sidecar_json()?;
    Ok(vec![(format!("schedules/{WHOLE}.csv"), file.csv), (format!("schedules/{WHOLE}.json"), sidecar)])
}

/// The certified retimings of the problem's schedule and, when the calibration converged, of
/// the calibrated one.
fn retimings(r: &Resolved, clock: &Stopwatch) -> Vec<RetimeRow> {
    let mut schedules = vec![("problem".to_string(), r.schedule.clone())];
    if let Some(cal) = r.calibrated() {
        let name = Variant::new(Origin::Library(r.problem.manoeuvre.profile)).calibrated().to_string();
        schedules.push((name, r.schedule.with_circulation(cal.radians)));
    }
    schedules
        .par_iter()
        .flat_map_iter(|(name, s)| clock.time(format!("retime {name}"), || retime_rows(r, name, s)))
        .collect()
}

/// Each schedule through the exact engine and rapier, in parallel, in order. A verification
/// without a rapier result is an outcome (its verdict is `inconclusive`), not an error.
fn verify_all(r: &Resolved, runs: Vec<Run>, clock: &Stopwatch) -> Result<Vec<Verified>, RunError> {
    runs.into_par_iter()
        .map(|(variant, schedule, circ, evaluation)| {
            clock.time(format!("verify {variant}"), || {
                let exact = exact_report(r, &schedule, circ, evaluation).map_err(RapierError::from)?;
                let rapier = rapier_outcome(r, &schedule, &exact)?;
                Ok(Verified { variant, schedule, exact, rapier })
            })
        })
        .collect()
}
