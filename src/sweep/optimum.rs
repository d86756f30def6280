//! The optimised rows of a case: the convex retiming of its schedule (`retimed`) and the
//! whole-manoeuvre optimum (`whole`), each re-measured by the exact engine.
//!
//! - `retimed`: [`crate::optimize::retime::retime`] of the schedule with the calibrated
//!   circulation (the paper's `π/C` when the calibration fails; the `retimed_from` column says
//!   which) to the fall time, with [`Split::Free`] (the program shares the duration between the
//!   phases) and otherwise default [`RetimeSettings`] (200 intervals per phase). The row reports
//!   Clarabel's certified lower bound `τ_lb` (weak duality: no timing of this path on the
//!   program's grid has a smaller peak), the program's primal peak and their gap, and the timed
//!   trajectory measured as every schedule is ([`Rig::measure`]): its peak torques per phase
//!   (`peak_max_nm` ≥ `τ_lb` up to the discretisation between grid nodes) and its motor demand
//!   with the case's `[actuator]`. Twist and swing are the path's, which retiming leaves
//!   unchanged (a geometric phase): the exact flip of the original schedule, to `exact.tolerance`.
//! - `whole`: [`optimize_whole`] over the fall time from the problem's manoeuvre with the case's
//!   own `[optimize.whole]` and motors (`[actuator]`): exactly what `catflip optimize --whole`
//!   computes for the case's problem, so an axis over `optimize.whole.*` or `actuator.*` is
//!   honoured. The best start that ended on a result (converged, or an upper bound) and flips
//!   the cat to `exact.tolerance`, measured ([`Rig::measure`]), gives twist, swing, peak and the
//!   motor demand; the optimiser gives its effort, largest bend, and its duration `T` with the
//!   drop height `g T²/2` (with the objective `min-time`, the least fall within the motors).
//!   When no start does, the row is `failed` with every start's status and reason.

use crate::engines::measured::Rig;
use crate::engines::Engine;
use crate::optimize::retime::{retime_schedule, PhasePath, RetimeSettings, Retiming, Split};
use crate::optimize::whole::{optimize_whole, WholeError, WholeOutcome};
use crate::problem::Problem;
use crate::schedule::variant::ScheduleName;
use crate::schedule::Schedule;

use super::row::{ExactRow, Labels, Numbers, RetimeNumbers, Row, Status, Subject, SweepSchedule, WholeNumbers};

/// The retiming settings of a sweep: the defaults with the phase durations free.
pub fn retime_settings() -> RetimeSettings {
    RetimeSettings { split: Split::Free, ..RetimeSettings::default() }
}

/// The `retimed` row: the schedule `from` (with circulation `radians`) retimed along its path,
/// the timed trajectory measured on the case's rig.
pub(crate) fn retimed(problem: &Problem, rig: &Rig, from: SweepSchedule, radians: f64) -> ExactRow {
    let (cat, tol) = (&problem.cat.half(), problem.exact.tolerance);
    let labels = |solver: String| Labels { retimed_from: Some(from), solver_status: solver, ..Labels::default() };
    let failed = |status, reason: &str, solver: String| {
        ExactRow::alone(Row::without(SweepSchedule::Retimed, Engine::Exact, status, reason, labels(solver)))
    };
    let s = Schedule::new(problem, radians);
    let r: Retiming<PhasePath> = match retime_schedule(cat, &s, retime_settings()) {
        Ok(r) => r,
        Err(e) => return failed(Status::Failed, &format!("the retiming could not be set up: {e}"), String::new()),
    };
    let sol = &r.solution;
    let solver = sol.status.to_string();
    if !sol.status.is_solved() {
        return failed(Status::Failed, &format!("the retiming program is {solver}"), solver);
    }
    let Some(traj) = r.trajectory.clone() else {
        return failed(Status::Failed, "the solved retiming has no trajectory", solver);
    };
    let m = rig.measure(ScheduleName::Retimed(Box::new(ScheduleName::Problem)), traj);
    // The retimed trajectory's own flip: retiming keeps the path, so it is the path's (a
    // geometric phase) up to the tolerance, which the tests check.
    let f = &m.exact.flip;
    if !f.converged {
        let reason = format!(
            "the exact integration did not meet exact.tolerance = {tol:e} rad (estimate {:e} rad)",
            f.error_estimate
        );
        return failed(Status::Failed, &reason, solver);
    }
    let mut numbers = Numbers::measured(Some(radians), &m.exact, true);
    numbers.retiming =
        Some(RetimeNumbers { lower_bound_nm: sol.lower_bound, program_peak_nm: sol.peak, gap_nm: sol.gap });
    let row = Row::with(SweepSchedule::Retimed, Engine::Exact, numbers, labels(solver));
    let subject = (row.status == Status::Ok).then_some(Subject::Retimed(m));
    ExactRow { row, subject }
}

/// The `whole` row: the whole-manoeuvre optimum of the case, measured on its rig.
pub(crate) fn whole(problem: &Problem, rig: &Rig) -> ExactRow {
    let outcome = optimize_whole(
        problem.cat.half(),
        problem.drop.fall_time(),
        &problem.manoeuvre,
        &problem.optimize.whole,
        &problem.actuator.motors(),
        problem.exact.tolerance,
    );
    let outcome: WholeOutcome = match outcome {
        Ok(o) => o,
        Err(e @ WholeError::BadFieldValue { .. }) => {
            return ExactRow::alone(Row::without(
                SweepSchedule::Whole,
                Engine::Exact,
                Status::Refused,
                &e.to_string(),
                Labels::default(),
            ))
        }
        Err(e) => {
            return ExactRow::alone(Row::without(
                SweepSchedule::Whole,
                Engine::Exact,
                Status::Failed,
                &e.to_string(),
                Labels::default(),
            ))
        }
    };
    let solver: Vec<String> = outcome.solutions.iter().map(|s| format!("{}: {}", s.start, s.status)).collect();
    let Some(best) = outcome.best() else {
        let reason = outcome.no_optimum(&problem.optimize.whole, problem.exact.tolerance);
        let labels = Labels { solver_status: solver.join("; "), ..Labels::default() };
        return ExactRow::alone(Row::without(SweepSchedule::Whole, Engine::Exact, Status::Failed, &reason, labels));
    };
    let labels = Labels { solver_status: solver.join("; "), whole_start: best.start.clone(), ..Labels::default() };
    let m = rig.measure(ScheduleName::WholeOptimum, best.spline.clone());
    let mut numbers = Numbers::measured(None, &m.exact, false);
    let t = best.fall_time_s;
    numbers.whole = Some(WholeNumbers {
        energy: best.energy,
        max_bend_deg: best.max_bend_deg,
        fall_time_s: t,
        drop_height_m: problem.drop.height_for(t),
    });
    let row = Row::with(SweepSchedule::Whole, Engine::Exact, numbers, labels);
    let subject = (row.status == Status::Ok).then_some(Subject::Whole(m));
    ExactRow { row, subject }
}
