//! Everything `catflip run` computes for one problem, before anything is written.
//!
//! The independent computations run in parallel (rayon): the profile QP and its refinements,
//! the whole-manoeuvre optimum, the certified retimings and the rapier verification of every
//! library schedule start together; each optimised schedule is verified as soon as it exists. Each
//! computation is deterministic and its result lands in a fixed place, so the output does not
//! depend on the number of threads.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::{figures, RunError, Verified};
use crate::engines::circulation::{Resolved, ResolvedCirculation};
use crate::engines::evaluate::Evaluation;
use crate::engines::rapier::Verification;
use crate::optimize::{optimize, OptimizeReport};
use crate::report::audit::Audit;
use crate::report::simulate::{exact_report, rapier_outcome};
use crate::report::whole::{retime_rows, verify_whole, RetimeRow, WholeReport, WHOLE};
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
}

/// The whole optimum's branch: the report, its verification, its animation's files.
type WholeBranch = (WholeReport, Option<Verification>, Option<Vec<PathBuf>>);

/// One schedule to verify: its name, itself, its circulation and its exact evaluation when
/// one exists already.
type Run<'a> = (Variant, Schedule, ResolvedCirculation, Option<&'a Evaluation>);

/// Computes everything for `r` (module docs).
pub(super) fn compute(r: &Resolved, plots: &Path) -> Result<Computed, RunError> {
    let audit = crate::report::audit::audit_with_exact(r)?;
    let library: Vec<Run> = r
        .library()
        .iter()
        .map(|(k, s, e)| (Variant::new(Origin::Library(*k)), s.clone(), r.circulation, Some(e)))
        .collect();
    // Four branches; each verifies what it produced as soon as it has it. The longest chains
    // start first: the whole optimum (solve, then verification beside the animation) and the
    // refinement (sequential steps, then four verifications); the retimings and the library's
    // verifications fill the gaps.
    let (whole, (opt, (retimed, library))) = rayon::join(
        || whole_and_verify(r, plots),
        || rayon::join(|| optimise_and_verify(r), || rayon::join(|| retimings(r), || verify_all(r, library))),
    );
    let ((opt, optimised), (whole, whole_verification, animation), mut verified) = (opt?, whole?, library?);
    verified.extend(optimised);
    Ok(Computed { audit, opt, whole, retimed, verified, whole_verification, animation })
}

/// The profile QP and its refinements, then their verification, and the recommended schedule's:
/// the most refined one with the calibrated circulation (when the calibration converged).
fn optimise_and_verify(r: &Resolved) -> Result<(OptimizeReport, Vec<Verified>), RunError> {
    let opt = optimize(r)?;
    let mut runs: Vec<Run> =
        opt.optima().map(|o| (o.variant, o.schedule.clone(), r.circulation, Some(&o.exact))).collect();
    let most_refined =
        opt.optima().last().filter(|o| matches!(o.variant.origin, Origin::Refined | Origin::RefinedAllPhases));
    if let (Some(o), Some(cal)) = (most_refined, r.calibrated()) {
        runs.push((o.variant.calibrated(), o.schedule.with_circulation(cal.radians), cal, None));
    }
    let verified = verify_all(r, runs)?;
    Ok((opt, verified))
}

/// The whole-manoeuvre optimum, then its verification and, beside it, its animation in `plots`
/// (the schedule to replay: it flips the cat exactly).
fn whole_and_verify(r: &Resolved, plots: &Path) -> Result<WholeBranch, RunError> {
    let whole = crate::report::whole::whole(r)?;
    let (verification, animation) = rayon::join(
        || verify_whole(r, &whole),
        || whole.spline().map(|spline| figures::animation_of(r, plots, WHOLE, spline)),
    );
    Ok((whole, verification?, animation.transpose()?))
}

/// The certified retimings of the problem's schedule and, when the calibration converged, of
/// the calibrated one.
fn retimings(r: &Resolved) -> Vec<RetimeRow> {
    let mut schedules = vec![("problem".to_string(), r.schedule.clone())];
    if let Some(cal) = r.calibrated() {
        let name = Variant::new(Origin::Library(r.problem.manoeuvre.profile)).calibrated().to_string();
        schedules.push((name, r.schedule.with_circulation(cal.radians)));
    }
    schedules.par_iter().flat_map_iter(|(name, s)| retime_rows(r, name, s)).collect()
}

/// Each schedule through the exact engine and rapier, in parallel, in order. A verification
/// without a rapier result is an outcome (its verdict is `inconclusive`), not an error.
fn verify_all(r: &Resolved, runs: Vec<Run>) -> Result<Vec<Verified>, RunError> {
    runs.into_par_iter()
        .map(|(variant, schedule, circ, evaluation)| {
            let exact = exact_report(r, &schedule, circ, evaluation);
            let rapier = rapier_outcome(r, &schedule, &exact)?;
            Ok(Verified { variant, schedule, exact, rapier })
        })
        .collect()
}
