//! One case through the engines and optimisers: the rows a sweep reports for it.
//!
//! Per case, with the problem's own `exact` settings:
//! - schedule `paper`: the paper's circulation `D_p = π/C` ([`paper_circulation`]), its flip
//!   (twist, swing; [`crate::engines::exact::flip`]) and, with `peaks`, its peak torques per phase and joint;
//! - schedule `calibrated`: the circulation `D_c` for which the exact engine turns the cat by ±π
//!   ([`resolve_circulation`] with `circulation = "calibrated"`, i.e. [`crate::engines::calibrate::calibrate`]),
//!   its swing and peak torques;
//! - schedule `given`: when the problem file gives a circulation in radians, that one as well;
//! - schedule `retimed` (with `retiming`): the certified convex retiming of the calibrated
//!   schedule (the paper's when the calibration fails) along its fixed path, the duration free
//!   to move between the phases ([`super::optimum`]);
//! - schedule `whole` (with `whole`): the whole-manoeuvre optimum of the case's own
//!   `[optimize.whole]` (least peak torque, least effort, or with `min-time` the least fall within
//!   the motors; [`super::optimum`]);
//! - engine `rapier` (with `rapier`): every exact row above verified by rapier
//!   ([`super::verify`]);
//! - the paper formula's error `D_c − D_p` (rad) and `(D_c − D_p)/D_p`, on every row of the case.
//!
//! Accuracy (the problem's `exact.tolerance` = ε): twist and swing to ε rad (Richardson estimate of
//! the sixth-order Magnus integration, reported per row); the calibrated circulation to `10⁻² ε`
//! rad in circulation with its twist within ε of ±π (checked, else the row is `failed`); peak
//! torques from `exact.torque_samples` samples per phase, each peak refined by golden-section search
//! between its neighbouring samples (the schedule's own time scale, as `simulate` samples it); the
//! motor demand (peak speed and power per joint, the limit with the least margin) from the same
//! samples ([`crate::engines::motors::MotorDemand`]).
//!
//! A row is `ok` only when every number it carries is finite and valid; otherwise its status
//! (`refused`, `failed`, `skipped`) and a one-line reason say why, and it carries no number.

use serde::Serialize;

use crate::engines::circulation::{resolve_circulation, CirculationError};
use crate::engines::evaluate::released_on;
use crate::engines::measured::Rig;
use crate::engines::resolved::LANDING_SWING_DEG;
use crate::engines::Engine;
use crate::problem::manoeuvre::Circulation;
use crate::problem::Problem;
use crate::schedule::variant::{Origin, ScheduleName, Variant, VariantCirculation};
use crate::schedule::{paper_circulation, Schedule};

use super::row::{ExactRow, Labels, Numbers, Row, Status, Subject, SweepSchedule};
use super::spec::{Compute, Sweep};

/// What a case gives: its rows and the case-level numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CaseOutcome {
    /// The problem's warnings (outside the paper's assumptions), joined by `; `.
    pub warnings: String,
    /// The paper's `π/C`, rad, when defined.
    pub paper_rad: Option<f64>,
    /// The calibrated circulation, rad, when found.
    pub calibrated_rad: Option<f64>,
    /// The rows, in a fixed order: paper, calibrated, given, retimed, whole; exact then rapier.
    pub rows: Vec<Row>,
}

impl CaseOutcome {
    /// A case the problem file refuses: one row per asked schedule and engine, each carrying the
    /// reason.
    pub fn refused(compute: &Compute, reason: &str) -> CaseOutcome {
        let rows = asked_schedules(compute, false)
            .into_iter()
            .map(|(schedule, engine)| Row::without(schedule, engine, Status::Refused, reason, Labels::default()))
            .collect();
        CaseOutcome { warnings: String::new(), paper_rad: None, calibrated_rad: None, rows }
    }

    /// `D_c − D_p`, rad, when both exist.
    pub fn circulation_error(&self) -> Option<f64> {
        Some(self.calibrated_rad? - self.paper_rad?)
    }
}

/// The (schedule, engine) pairs of case `index`'s rows, in order: those [`evaluate_case`] gives
/// the case's problem, or [`CaseOutcome::refused`] when the problem file refuses it.
pub fn row_keys(sweep: &Sweep, index: usize) -> Vec<(SweepSchedule, Engine)> {
    let given = super::cases::case(sweep, index)
        .problem(sweep)
        .is_ok_and(|p| matches!(p.manoeuvre.circulation, Circulation::Angle(_)));
    asked_schedules(&sweep.compute, given)
}

/// The (schedule, engine) pairs `compute` asks for, in row order.
fn asked_schedules(compute: &Compute, given: bool) -> Vec<(SweepSchedule, Engine)> {
    let mut out = Vec::new();
    if compute.paper_flip {
        out.push((SweepSchedule::Paper, Engine::Exact));
    }
    if compute.calibrated {
        out.push((SweepSchedule::Calibrated, Engine::Exact));
    }
    if given {
        out.push((SweepSchedule::Given, Engine::Exact));
    }
    if compute.retiming {
        out.push((SweepSchedule::Retimed, Engine::Exact));
    }
    if compute.whole {
        out.push((SweepSchedule::Whole, Engine::Exact));
    }
    if compute.rapier {
        let verified: Vec<_> = out.iter().filter(|(_, e)| *e == Engine::Exact).map(|(s, _)| *s).collect();
        out.extend(verified.into_iter().map(|s| (s, Engine::Rapier)));
    }
    out
}

/// A circulation and the calibration's evaluations, or the status and reason there is none.
type Resolution = Result<(f64, Option<usize>), (Status, String)>;

/// Evaluates one case.
pub fn evaluate_case(problem: &Problem, compute: &Compute) -> CaseOutcome {
    let rig = match Rig::new(problem) {
        Ok(rig) => rig,
        Err(e) => return CaseOutcome::refused(compute, &e.to_string()),
    };
    let given = match problem.manoeuvre.circulation {
        Circulation::Angle(a) => Some(a),
        _ => None,
    };
    let paper = paper_circulation(&problem.cat.half(), problem.manoeuvre.theta());
    let paper_rad = paper.as_ref().ok().copied();
    let paper: Resolution = paper.map(|d| (d, None)).map_err(|e| (Status::Refused, e.to_string()));
    let calibrated = (compute.calibrated || compute.retiming).then(|| calibrate(problem));
    let calibrated_rad = calibrated.as_ref().and_then(|c| c.as_ref().ok()).map(|c| c.0);
    let mut measured = Vec::new();
    for (schedule, engine) in asked_schedules(compute, given.is_some()) {
        if engine != Engine::Exact {
            continue;
        }
        let m = match schedule {
            SweepSchedule::Paper => schedule_row(problem, &rig, compute, schedule, &paper),
            SweepSchedule::Calibrated => match &calibrated {
                Some(c) => schedule_row(problem, &rig, compute, schedule, c),
                None => schedule_row(problem, &rig, compute, schedule, &calibrate(problem)),
            },
            SweepSchedule::Retimed => match calibrated.as_ref() {
                Some(Ok((d, _))) => super::optimum::retimed(problem, &rig, SweepSchedule::Calibrated, *d),
                _ => match &paper {
                    Ok((d, _)) => super::optimum::retimed(problem, &rig, SweepSchedule::Paper, *d),
                    Err((status, reason)) => ExactRow::alone(Row::without(
                        schedule,
                        engine,
                        *status,
                        &format!("no schedule to retime: the calibration failed and π/C is undefined ({reason})"),
                        Labels::default(),
                    )),
                },
            },
            SweepSchedule::Whole => super::optimum::whole(problem, &rig),
            SweepSchedule::Given => {
                let g =
                    given.map(|d| (d, None)).ok_or((Status::Failed, "the problem gives no circulation".to_string()));
                schedule_row(problem, &rig, compute, schedule, &g)
            }
        };
        measured.push(m);
    }
    let mut rows: Vec<Row> = measured.iter().map(|m| m.row.clone()).collect();
    if compute.rapier {
        rows.extend(measured.iter().map(|m| super::verify::rapier_row(&rig, m)));
    }
    let mut warnings = problem.warnings();
    warnings.extend(swung(&rows));
    CaseOutcome { warnings: warnings.join("; "), paper_rad, calibrated_rad, rows }
}

/// A warning for each exact row whose spine ends swung by more than [`LANDING_SWING_DEG`]: its
/// twist may be a half turn, but the cat does not land on its feet (as `simulate` warns of a
/// calibrated flip).
fn swung(rows: &[Row]) -> Vec<String> {
    rows.iter()
        .filter(|r| r.engine == Engine::Exact)
        .filter_map(|r| Some((r, r.numbers?.swing_deg)))
        .filter(|(_, swing)| swing.abs() > LANDING_SWING_DEG)
        .map(|(r, swing)| {
            format!(
                "the {} schedule ends with the spine swung by {swing:.1}° (more than {LANDING_SWING_DEG}°): whatever its twist, the cat does not land on its feet",
                r.schedule.name()
            )
        })
        .collect()
}

/// The calibrated circulation of the case's manoeuvre.
fn calibrate(problem: &Problem) -> Resolution {
    let mut p = problem.clone();
    p.manoeuvre.circulation = Circulation::Calibrated;
    match resolve_circulation(
        &crate::engines::models::TwoMotorCat::paper(p.cat.half()),
        &p.manoeuvre,
        p.drop.fall_time(),
        &p.drop.spin(),
        p.exact.tolerance,
    ) {
        Ok(c) => Ok((c.radians, c.calibration.map(|x| x.evaluations))),
        Err(e @ CirculationError::Calibration { .. }) => Err((Status::Failed, e.to_string())),
        Err(e) => Err((Status::Refused, e.to_string())),
    }
}

/// The exact row of the library schedule with `circulation`: with `peaks` (or `rapier`, which
/// checks the peak) the schedule measured as every command measures it ([`Rig::measure`]: flip,
/// peaks and motor demand), else its flip alone (the same engine's, [`released_on`]).
fn schedule_row(
    problem: &Problem,
    rig: &Rig,
    compute: &Compute,
    schedule: SweepSchedule,
    circulation: &Resolution,
) -> ExactRow {
    let tol = problem.exact.tolerance;
    let (radians, evaluations) = match circulation {
        Ok(x) => *x,
        Err((status, reason)) => {
            return ExactRow::alone(Row::without(schedule, Engine::Exact, *status, reason, Labels::default()))
        }
    };
    let s = Schedule::new(problem, radians);
    let circulation = match schedule {
        SweepSchedule::Calibrated => VariantCirculation::Calibrated,
        _ => VariantCirculation::Problem,
    };
    let name = Variant { origin: Origin::Library(problem.manoeuvre.profile), circulation };
    let measured = (compute.peaks || compute.rapier).then(|| rig.measure(ScheduleName::Variant(name), s.clone()));
    let f = match &measured {
        Some(m) => m.exact.flip,
        None => released_on(&rig.model, &s, &rig.spin, tol).0,
    };
    if !f.converged {
        let reason = format!(
            "the exact integration did not meet exact.tolerance = {tol:e} rad (estimate {:e} rad)",
            f.error_estimate
        );
        return ExactRow::alone(Row::without(schedule, Engine::Exact, Status::Failed, &reason, Labels::default()));
    }
    let mut numbers = match (&measured, compute.peaks) {
        (Some(m), true) => Numbers::measured(Some(radians), &m.exact, true),
        _ => Numbers::flip(Some(radians), f.twist, f.swing, Some(f.error_estimate)),
    };
    numbers.calibration_evaluations = evaluations;
    let row = Row::with(schedule, Engine::Exact, numbers, Labels::default());
    let subject = measured.filter(|_| row.status == Status::Ok).map(Subject::Schedule);
    ExactRow { row, subject }
}
