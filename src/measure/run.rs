//! Everything `catflip run` computes for one problem, before anything is written
//! ([`crate::report::run`] renders and writes it).
//!
//! It runs on every two-motor cat (the paper's, unequal halves, the no-twist joint: DESIGN.md
//! §10). Two parts model the paper's cat only (equal halves on the universal joint) and are not
//! run on another ([`PaperOnly`]): the audit of the paper's numbers and the paper-model profile
//! QP with its exact refinements (built on the two-cylinder engine). Everything else runs on the
//! problem's model: the library's measurements and rapier verifications, the certified
//! retimings, the whole optimum with its verification and robustness, the schedule and model
//! files.
//!
//! The independent computations run in parallel (rayon): the profile QP and its refinements,
//! the whole-manoeuvre optimum, the certified retimings and the rapier verification of every
//! library schedule start together; each optimised schedule is verified, and its schedule file
//! written, as soon as it exists; the whole optimum's robustness (the exact engine's Monte Carlo,
//! [`crate::robust`]) and a caller's own work on the optimum (the report's animation) run beside
//! its verification. Every schedule is measured once ([`Measured`]): its exact numbers serve its
//! table rows, its verification's reference and its schedule file. Each computation is
//! deterministic and its result lands in a fixed place, so the output does not depend on the
//! number of threads.

use rayon::prelude::*;

use crate::engines::circulation::CirculationError;
use crate::engines::measured::Measured;
use crate::engines::rapier::RapierError;
use crate::engines::resolved::Resolved;
use crate::exchange::{model_files, schedule_files, ExportOptions};
use crate::measure::audit::{audit_with_exact, Audit, AuditError};
use crate::measure::retime::{retime_rows, RetimeRow};
use crate::measure::timings::Stopwatch;
use crate::measure::whole::{whole, WholeReport};
use crate::optimize::{optimize, OptimizeError, OptimizeReport};
use crate::robust::{robustness, Robustness};
use crate::schedule::variant::{Origin, ScheduleName, Variant, WHOLE};
use crate::schedule::Schedule;

/// Why a run's computations failed.
#[derive(Debug, thiserror::Error)]
pub enum ComputeError {
    /// The problem's circulation could not be resolved.
    #[error(transparent)]
    Circulation(#[from] CirculationError),
    /// The problem asks for what `run` does not model.
    #[error(transparent)]
    Problem(#[from] crate::problem::ProblemError),
    /// The rapier engine failed.
    #[error(transparent)]
    Rapier(#[from] RapierError),
    /// An optimiser failed.
    #[error(transparent)]
    Optimize(#[from] OptimizeError),
    /// The audit refused a value.
    #[error(transparent)]
    Audit(#[from] AuditError),
    /// The benchmark failed.
    #[error(transparent)]
    Bench(#[from] crate::measure::bench::BenchError),
    /// The whole-manoeuvre optimisation could not run.
    #[error(transparent)]
    Whole(#[from] crate::optimize::whole::WholeError),
    /// A schedule file could not be written.
    #[error(transparent)]
    Exchange(#[from] crate::exchange::ExchangeError),
}

/// A part of `run` that models the paper's cat only (equal halves on the universal joint): on
/// any other cat it is not run, and the report says so ([`PaperOnly::not_run`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PaperOnly {
    /// The audit of the paper's numbers ([`audit_with_exact`]): its formulas are the paper's cat's.
    Audit,
    /// The paper-model profile QP and its exact refinements ([`optimize`]): the QP's model is the
    /// paper's `I*`, the refinements run the two-cylinder engine.
    ProfileQp,
}

impl PaperOnly {
    /// The part as the sentence's subject, with its verb.
    fn subject(self) -> &'static str {
        match self {
            PaperOnly::Audit => "The audit of the paper's numbers models",
            PaperOnly::ProfileQp => "The paper-model profile QP and its refinements model",
        }
    }

    /// One plain sentence saying that the part is not run for `problem`'s cat, and why (the field
    /// that departs from the paper's cat); `None` on the paper's cat, where it runs.
    pub fn not_run(self, problem: &crate::problem::Problem) -> Option<String> {
        let (field, value) = problem.cat.departure()?;
        Some(format!(
            "{} the paper's cat (equal halves on the universal joint): not run for this cat ({field} = {value}).",
            self.subject()
        ))
    }
}

/// The results of one run.
pub struct RunResults {
    /// The paper's numbers, with the exact engine's column; `None` on a cat other than the
    /// paper's ([`PaperOnly::Audit`]).
    pub audit: Option<Audit>,
    /// The profile QP and its refinements, each optimum measured; `None` on a cat other than the
    /// paper's ([`PaperOnly::ProfileQp`]).
    pub opt: Option<OptimizeReport>,
    /// The whole-manoeuvre optimum, measured and verified.
    pub whole: WholeReport,
    /// The certified retimings of the problem's schedule (and of the calibrated one).
    pub retimed: Vec<RetimeRow>,
    /// Every schedule of the peak-torque table, measured and verified in rapier (DESIGN.md §6):
    /// the library first (in [`crate::problem::ProfileKind::ALL`] order), then the optimised ones,
    /// then the most refined one with the calibrated circulation.
    pub verified: Vec<Measured<Schedule>>,
    /// The whole optimum's robustness on the exact engine (`[robust]`'s draws, ideal tracking),
    /// when the optimum exists.
    pub robustness: Option<Robustness>,
    /// Everything under `schedules/` as (path in the results folder, contents): the problem's
    /// schedule, every optimised one, the model files, the whole optimum's.
    pub files: Vec<(String, String)>,
}

/// Files as (path in the results folder, contents).
type Files = Vec<(String, String)>;

/// Computes everything for `r` (module docs); `beside` runs on the whole optimum, when there is
/// one, in parallel with its verification (the report draws its animation there), and what it
/// returns comes back beside the results.
pub fn compute<A: Send>(
    r: &Resolved,
    export: &ExportOptions,
    clock: &Stopwatch,
    beside: impl Fn(&Measured<crate::optimize::whole::BSpline>) -> A + Sync,
) -> Result<(RunResults, Option<A>), ComputeError> {
    // Four branches; each verifies what it produced as soon as it has it. The longest chains
    // start first: the whole optimum (solve, then verification beside the robustness and
    // `beside`) and the refinement (sequential steps, then four verifications); the retimings,
    // the library's verifications, the audit and the problem's schedule file fill the gaps.
    // The library's measurements, made once before the branches that read them.
    r.library();
    let audit = || r.problem.cat.is_paper().then(|| clock.time("audit", || audit_with_exact(r))).transpose();
    let problem_file = || {
        let own = r.own().clone().named(ScheduleName::Problem);
        clock.time("schedule files: problem", || schedule_files(&r.problem, &[&own], export))
    };
    let (whole, (opt, (retimed, (library, (audit, problem_files))))) = rayon::join(
        || whole_and_verify(r, export, clock, &beside),
        || {
            rayon::join(
                || optimise_and_verify(r, export, clock),
                || {
                    rayon::join(
                        || retimings(r, clock),
                        || rayon::join(|| verify_library(r, clock), || rayon::join(audit, problem_file)),
                    )
                },
            )
        },
    );
    let ((opt, optimised, optimised_files), (whole, robustness, beside, whole_files), mut verified, audit) =
        (opt?, whole?, library?, audit?);
    verified.extend(optimised);
    let mut files = problem_files?;
    files.extend(optimised_files);
    files.extend(model_files(&r.problem)?.into_iter().map(|(n, text)| (format!("schedules/{n}"), text)));
    files.extend(whole_files);
    Ok((RunResults { audit, opt, whole, retimed, verified, robustness, files }, beside))
}

/// The profile QP's report (none on a cat other than the paper's), its optima measured and
/// verified, and their schedule files.
type OptimiseBranch = (Option<OptimizeReport>, Vec<Measured<Schedule>>, Files);

/// The profile QP and its refinements, then their verification, and the recommended schedule's:
/// the most refined one with the calibrated circulation (when the calibration converged). On a
/// cat other than the paper's, nothing ([`PaperOnly::ProfileQp`]).
fn optimise_and_verify(
    r: &Resolved,
    export: &ExportOptions,
    clock: &Stopwatch,
) -> Result<OptimiseBranch, ComputeError> {
    if !r.problem.cat.is_paper() {
        return Ok((None, Vec::new(), Vec::new()));
    }
    let opt = clock.time("profile QP and refinements", || optimize(r))?;
    let mut runs: Vec<Measured<Schedule>> = opt.optima().map(|o| o.measured.clone()).collect();
    let most_refined =
        opt.optima().last().filter(|o| matches!(o.variant().origin, Origin::Refined | Origin::RefinedAllPhases));
    if let (Some(o), Some(cal)) = (most_refined, r.recalibration()) {
        let name = ScheduleName::from(o.variant().calibrated());
        let calibrated = o.schedule().with_circulation(cal.radians);
        runs.push(clock.time(format!("measure {name}"), || r.measure(name.clone(), calibrated)));
    }
    let exported: Vec<&Measured<Schedule>> = runs.iter().collect();
    let (files, verified) = rayon::join(
        || clock.time("schedule files: optimised", || schedule_files(&r.problem, &exported, export)),
        || verify_all(r, runs.clone(), clock),
    );
    Ok((Some(opt), verified?, files?))
}

/// The whole optimum with its robustness, what `beside` made of it, and its schedule files.
type WholeBranch<A> = (WholeReport, Option<Robustness>, Option<A>, Files);

/// The whole-manoeuvre optimum, then its verification and, beside it, its robustness, `beside`
/// and its schedule files.
fn whole_and_verify<A: Send>(
    r: &Resolved,
    export: &ExportOptions,
    clock: &Stopwatch,
    beside: &(impl Fn(&Measured<crate::optimize::whole::BSpline>) -> A + Sync),
) -> Result<WholeBranch<A>, ComputeError> {
    let mut report = clock.time("whole optimum", || whole(r))?;
    let unverified = report.measured.clone();
    let ((verified, robustness), (made, files)) = rayon::join(
        || {
            rayon::join(
                || clock.time(format!("verify {WHOLE}"), || report.verify(r).map(|()| report)),
                || {
                    unverified.as_ref().map(|m| {
                        clock
                            .time(format!("robustness of {WHOLE}"), || robustness(&r.problem, &m.trajectory, WHOLE))
                            .map_err(RapierError::from)
                    })
                },
            )
        },
        || {
            rayon::join(
                || unverified.as_ref().map(|m| clock.time(format!("animate {WHOLE}"), || beside(m))),
                || clock.time(format!("schedule files: {WHOLE}"), || whole_files(r, unverified.as_ref(), export)),
            )
        },
    );
    Ok((verified?, robustness.transpose()?, made, files?))
}

/// The whole optimum's CSV and sidecar, when it exists.
fn whole_files(
    r: &Resolved,
    m: Option<&Measured<crate::optimize::whole::BSpline>>,
    export: &ExportOptions,
) -> Result<Files, ComputeError> {
    let Some(m) = m else { return Ok(Vec::new()) };
    let file = crate::exchange::write_whole_optimum(&r.problem, m, export)?;
    let sidecar = file.sidecar_json()?;
    Ok(vec![(format!("schedules/{WHOLE}.csv"), file.csv), (format!("schedules/{WHOLE}.json"), sidecar)])
}

/// The certified retimings of the problem's schedule and, when the calibration converged, of
/// the calibrated one.
fn retimings(r: &Resolved, clock: &Stopwatch) -> Vec<RetimeRow> {
    let mut schedules = vec![(ScheduleName::Problem, r.schedule.clone())];
    if let Some(cal) = r.recalibration() {
        let name = Variant::new(Origin::Library(r.problem.manoeuvre.profile)).calibrated().into();
        schedules.push((name, r.schedule.with_circulation(cal.radians)));
    }
    schedules
        .par_iter()
        .flat_map_iter(|(name, s)| clock.time(format!("retime {name}"), || retime_rows(r, name, s)))
        .collect()
}

/// Every library profile of `r` verified in rapier, in parallel, in library order (`run`'s and
/// `catflip compare --verify`'s).
pub fn verify_library(r: &Resolved, clock: &Stopwatch) -> Result<Vec<Measured<Schedule>>, ComputeError> {
    verify_all(r, r.library().iter().map(|(_, m)| m.clone()).collect(), clock)
}

/// Each measured schedule verified in rapier, in parallel, in order. A verification without a
/// rapier result is an outcome (its verdict is `inconclusive`), not an error.
fn verify_all(
    r: &Resolved,
    runs: Vec<Measured<Schedule>>,
    clock: &Stopwatch,
) -> Result<Vec<Measured<Schedule>>, ComputeError> {
    runs.into_par_iter()
        .map(|m| {
            let name = m.name.to_string();
            clock.time(format!("verify {name}"), || m.verified(r.rig())).map_err(ComputeError::from)
        })
        .collect()
}
