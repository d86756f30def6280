//! One case through the engines and optimisers: the rows a sweep reports for it.
//!
//! Per case, with the problem's own `exact` settings:
//! - schedule `paper`: the paper's circulation `D_p = π/C` ([`paper_circulation`]), its flip
//!   (twist, swing; [`flip`]) and, with `peaks`, its peak torques per phase and joint;
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
//! samples ([`MotorDemand`]).
//!
//! A row is `ok` only when every number it carries is finite and valid; otherwise its status
//! (`refused`, `failed`, `skipped`) and a one-line reason say why, and it carries no number.

use serde::Serialize;

use crate::engines::circulation::{resolve_circulation, CirculationError};
use crate::engines::evaluate::Evaluation;
use crate::engines::exact::flip;
use crate::engines::motors::{MotorDemand, RATIO_TOLERANCE};
use crate::engines::peaks::PhasePeaks;
use crate::engines::rapier::Reference;
use crate::model::motor::Limit;
use crate::problem::manoeuvre::Circulation;
use crate::problem::Problem;
use crate::schedule::{paper_circulation, Schedule};

use super::optimum::Subject;
use super::spec::{one_line, Compute, Sweep};

/// How a row ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Computed; every number of the row is valid to its stated accuracy.
    Ok,
    /// The problem (or the paper's formula) refuses this case; the reason says why.
    Refused,
    /// The computation ran but gave no valid result (e.g. calibration found no root, the
    /// optimiser did not converge).
    Failed,
    /// Not computed because the row it rests on has no result (a rapier check of a failed row).
    Skipped,
}

impl Status {
    /// The kebab-case name written in the CSV.
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Refused => "refused",
            Status::Failed => "failed",
            Status::Skipped => "skipped",
        }
    }

    /// The status of a name written by [`Status::name`].
    pub fn parse(s: &str) -> Option<Status> {
        [Status::Ok, Status::Refused, Status::Failed, Status::Skipped].into_iter().find(|x| x.name() == s)
    }
}

/// The convex retiming's own numbers (schedule `retimed`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RetimeNumbers {
    /// Clarabel's dual objective: a certified lower bound on the peak of any timing of this path
    /// on the program's grid, N·m.
    pub lower_bound_nm: f64,
    /// The program's primal objective (peak at the grid nodes), N·m.
    pub program_peak_nm: f64,
    /// `program_peak − lower_bound`, N·m.
    pub gap_nm: f64,
}

/// The whole-manoeuvre optimum's own numbers (schedule `whole`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct WholeNumbers {
    /// Effort `∫ τ·τ dt`, N²·m²·s.
    pub energy: f64,
    /// Largest bend (angle between the spine axes), degrees.
    pub max_bend_deg: f64,
    /// The optimum's duration `T`, s: the case's fall time, or with the objective `min-time`
    /// the least fall time within the motors.
    pub fall_time_s: f64,
    /// The drop height of that fall, `g T²/2`, m.
    pub drop_height_m: f64,
}

/// The limit a trajectory comes closest to (or exceeds most): [`MotorDemand::worst`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct WorstLimit {
    /// Which limit.
    pub limit: Limit,
    /// Which joint, 1 or 2.
    pub joint: usize,
    /// Its usage ratio `max ρ`, dimensionless (at most 1 within the limit).
    pub ratio: f64,
}

impl WorstLimit {
    /// The limit in words, e.g. `joint 2 speed` (the CSV's `motor_worst_limit`).
    pub fn name(&self) -> String {
        format!("joint {} {}", self.joint, self.limit)
    }

    /// The limit of a name written by [`WorstLimit::name`], with its ratio.
    pub fn parse(name: &str, ratio: f64) -> Option<WorstLimit> {
        let rest = name.strip_prefix("joint ")?;
        let (joint, limit) = rest.split_once(' ')?;
        let joint = match joint {
            "1" => 1,
            "2" => 2,
            _ => return None,
        };
        let limit = Limit::ALL.into_iter().find(|l| l.name() == limit)?;
        Some(WorstLimit { limit, joint, ratio })
    }

    /// Whether the trajectory stays within every limit (the worst one holds, up to
    /// [`RATIO_TOLERANCE`]; [`MotorDemand::within`]).
    pub fn within(&self) -> bool {
        self.ratio <= 1.0 + RATIO_TOLERANCE
    }
}

/// What a row's trajectory asks of its motors, from the exact engine's [`MotorDemand`] (the same
/// measurement `simulate` and `optimize --whole` report).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MotorNumbers {
    /// Peak `|q̇_j|` of joints 1 and 2, rad/s.
    pub peak_speed_rad_s: [f64; 2],
    /// Peak mechanical power `|τ_j q̇_j|` of joints 1 and 2, W.
    pub peak_power_w: [f64; 2],
    /// The limit with the least margin; none with ideal motors (no `[actuator]` limit).
    pub worst: Option<WorstLimit>,
}

impl MotorNumbers {
    /// The figures of a measured demand.
    pub fn new(demand: &MotorDemand) -> MotorNumbers {
        MotorNumbers {
            peak_speed_rad_s: demand.peak_speed_rad_s.map(|p| p.value),
            peak_power_w: demand.peak_power_w.map(|p| p.value),
            worst: demand.worst().map(|w| WorstLimit { limit: w.limit, joint: w.joint, ratio: w.ratio }),
        }
    }
}

/// Rapier's verification numbers (engine `rapier`; its raw finest-run twist, swing and peak are
/// the row's `twist_deg`, `swing_deg` and peaks).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RapierNumbers {
    /// Richardson-extrapolated twist, degrees (none with fewer than two runs).
    pub twist_extrapolated_deg: Option<f64>,
    /// Extrapolated swing, degrees.
    pub swing_extrapolated_deg: Option<f64>,
    /// Extrapolated peak torque, N·m.
    pub peak_extrapolated_nm: Option<f64>,
    /// Rapier steps of every run together.
    pub steps: usize,
    /// The finest run's step, s.
    pub finest_dt_s: f64,
}

/// The numbers of one schedule of one case through one engine (present when the row's status is
/// `ok`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Numbers {
    /// Circulation `∫ω ds`, rad (none for the whole-manoeuvre optimum, which has no such parameter).
    pub circulation_rad: Option<f64>,
    /// Signed twist about A's initial `+z`, degrees.
    pub twist_deg: f64,
    /// Swing of the spine axis, degrees.
    pub swing_deg: f64,
    /// `|twist| − 180°`, degrees: how far the schedule misses the flip.
    pub flip_error_deg: f64,
    /// Richardson estimate of the exact engine's orientation error, rad (none for rapier rows).
    pub error_estimate_rad: Option<f64>,
    /// Peak torques per phase and joint, N·m (three-phase schedules, when `peaks` is asked for).
    pub peaks: Option<PhasePeaks>,
    /// The overall peak torque `max |τ|`, N·m (when measured).
    pub peak_nm: Option<f64>,
    /// Exact-engine evaluations of the calibration (calibrated rows).
    pub calibration_evaluations: Option<usize>,
    /// The retiming's numbers (`retimed` rows).
    pub retiming: Option<RetimeNumbers>,
    /// The whole-manoeuvre optimum's numbers (`whole` rows).
    pub whole: Option<WholeNumbers>,
    /// What the trajectory asks of the motors (exact rows that report peak torques).
    pub motors: Option<MotorNumbers>,
    /// The verification's numbers (`rapier` rows).
    pub rapier: Option<RapierNumbers>,
}

impl Numbers {
    /// A flip's numbers: twist and swing in radians, everything else absent.
    pub fn flip(circulation_rad: Option<f64>, twist: f64, swing: f64, error_estimate_rad: Option<f64>) -> Numbers {
        Numbers {
            circulation_rad,
            twist_deg: twist.to_degrees(),
            swing_deg: swing.to_degrees(),
            flip_error_deg: twist.to_degrees().abs() - 180.0,
            error_estimate_rad,
            peaks: None,
            peak_nm: None,
            calibration_evaluations: None,
            retiming: None,
            whole: None,
            motors: None,
            rapier: None,
        }
    }

    /// Whether every number is finite.
    pub fn all_finite(&self) -> bool {
        let mut v = vec![self.twist_deg, self.swing_deg, self.flip_error_deg];
        v.extend(self.circulation_rad.iter().chain(&self.error_estimate_rad).chain(&self.peak_nm));
        if let Some(p) = &self.peaks {
            v.extend([p.bend[0], p.bend[1], p.twist[0], p.twist[1], p.unbend[0], p.unbend[1], p.max]);
        }
        if let Some(r) = &self.retiming {
            v.extend([r.lower_bound_nm, r.program_peak_nm, r.gap_nm]);
        }
        if let Some(w) = &self.whole {
            v.extend([w.energy, w.max_bend_deg, w.fall_time_s, w.drop_height_m]);
        }
        if let Some(m) = &self.motors {
            v.extend(m.peak_speed_rad_s.iter().chain(&m.peak_power_w));
            v.extend(m.worst.map(|w| w.ratio));
        }
        if let Some(r) = &self.rapier {
            v.push(r.finest_dt_s);
            v.extend(r.twist_extrapolated_deg.iter().chain(&r.swing_extrapolated_deg).chain(&r.peak_extrapolated_nm));
        }
        v.iter().all(|x| x.is_finite())
    }
}

/// The words of a row beside its numbers (empty where they do not apply); written whatever the
/// status, so a failed optimisation still says how its solver ended.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Labels {
    /// The schedule a `retimed` row retimes: `calibrated`, or `paper` when the calibration failed.
    pub retimed_from: String,
    /// How the optimiser ended: the retiming's [`crate::optimize::retime::RetimeStatus`], the
    /// whole optimum's [`crate::optimize::whole::WholeStatus`] per start.
    pub solver_status: String,
    /// The start the whole-manoeuvre optimum came from.
    pub whole_start: String,
    /// Rapier's verdict ([`crate::engines::rapier::Verdict`]'s text).
    pub rapier_verdict: String,
}

/// One row: a schedule of a case through an engine.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// `paper`, `calibrated`, `given`, `retimed` or `whole`.
    pub schedule: String,
    /// `exact` or `rapier`.
    pub engine: String,
    /// How it ended.
    pub status: Status,
    /// Why, when not `ok` (one line).
    pub reason: String,
    /// The row's words.
    pub labels: Labels,
    /// The numbers, when `ok`.
    pub numbers: Option<Numbers>,
}

impl Row {
    /// A row without numbers.
    pub fn without(schedule: &str, engine: &str, status: Status, reason: &str, labels: Labels) -> Row {
        Row {
            schedule: schedule.to_string(),
            engine: engine.to_string(),
            status,
            reason: one_line(reason),
            labels,
            numbers: None,
        }
    }

    /// An `ok` row, or a `failed` one when a number is not finite.
    pub fn with(schedule: &str, engine: &str, numbers: Numbers, labels: Labels) -> Row {
        if numbers.all_finite() {
            Row {
                schedule: schedule.to_string(),
                engine: engine.to_string(),
                status: Status::Ok,
                reason: String::new(),
                labels,
                numbers: Some(numbers),
            }
        } else {
            Row::without(schedule, engine, Status::Failed, "the engine returned a non-finite number", labels)
        }
    }
}

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
pub fn row_keys(sweep: &Sweep, index: usize) -> Vec<(&'static str, &'static str)> {
    let given = super::cases::case(sweep, index)
        .problem(sweep)
        .is_ok_and(|p| matches!(p.manoeuvre.circulation, Circulation::Angle(_)));
    asked_schedules(&sweep.compute, given)
}

/// The (schedule, engine) pairs `compute` asks for, in row order.
fn asked_schedules(compute: &Compute, given: bool) -> Vec<(&'static str, &'static str)> {
    let mut out = Vec::new();
    if compute.paper_flip {
        out.push(("paper", "exact"));
    }
    if compute.calibrated {
        out.push(("calibrated", "exact"));
    }
    if given {
        out.push(("given", "exact"));
    }
    if compute.retiming {
        out.push(("retimed", "exact"));
    }
    if compute.whole {
        out.push(("whole", "exact"));
    }
    if compute.rapier {
        let verified: Vec<_> = out.iter().filter(|(_, e)| *e == "exact").map(|(s, _)| *s).collect();
        out.extend(verified.into_iter().map(|s| (s, "rapier")));
    }
    out
}

/// An exact row and, when it is `ok`, the trajectory it measured and the exact engine's numbers
/// for rapier to check.
pub(crate) struct Measured {
    /// The row.
    pub row: Row,
    /// What rapier verifies.
    pub subject: Option<(Subject, Reference)>,
}

impl Measured {
    /// A row with nothing to verify.
    pub fn alone(row: Row) -> Measured {
        Measured { row, subject: None }
    }
}

/// A circulation and the calibration's evaluations, or the status and reason there is none.
type Resolution = Result<(f64, Option<usize>), (Status, String)>;

/// Evaluates one case.
pub fn evaluate_case(problem: &Problem, compute: &Compute) -> CaseOutcome {
    let given = match problem.manoeuvre.circulation {
        Circulation::Angle(a) => Some(a),
        _ => None,
    };
    let paper = paper_circulation(&problem.cat, problem.manoeuvre.theta());
    let paper_rad = paper.as_ref().ok().copied();
    let paper: Resolution = paper.map(|d| (d, None)).map_err(|e| (Status::Refused, e.to_string()));
    let calibrated = (compute.calibrated || compute.retiming).then(|| calibrate(problem));
    let calibrated_rad = calibrated.as_ref().and_then(|c| c.as_ref().ok()).map(|c| c.0);
    let mut measured = Vec::new();
    for (schedule, engine) in asked_schedules(compute, given.is_some()) {
        if engine != "exact" {
            continue;
        }
        let m = match schedule {
            "paper" => schedule_row(problem, compute, schedule, &paper),
            "calibrated" => match &calibrated {
                Some(c) => schedule_row(problem, compute, schedule, c),
                None => schedule_row(problem, compute, schedule, &calibrate(problem)),
            },
            "retimed" => match calibrated.as_ref() {
                Some(Ok((d, _))) => super::optimum::retimed(problem, "calibrated", *d),
                _ => match &paper {
                    Ok((d, _)) => super::optimum::retimed(problem, "paper", *d),
                    Err((status, reason)) => Measured::alone(Row::without(
                        schedule,
                        engine,
                        *status,
                        &format!("no schedule to retime: the calibration failed and π/C is undefined ({reason})"),
                        Labels::default(),
                    )),
                },
            },
            "whole" => super::optimum::whole(problem),
            _ => {
                let g =
                    given.map(|d| (d, None)).ok_or((Status::Failed, "the problem gives no circulation".to_string()));
                schedule_row(problem, compute, schedule, &g)
            }
        };
        measured.push(m);
    }
    let mut rows: Vec<Row> = measured.iter().map(|m| m.row.clone()).collect();
    if compute.rapier {
        rows.extend(measured.iter().map(|m| super::verify::rapier_row(problem, m)));
    }
    CaseOutcome { warnings: problem.warnings().join("; "), paper_rad, calibrated_rad, rows }
}

/// The calibrated circulation of the case's manoeuvre.
fn calibrate(problem: &Problem) -> Resolution {
    let mut p = problem.clone();
    p.manoeuvre.circulation = Circulation::Calibrated;
    match resolve_circulation(&p.cat, &p.manoeuvre, p.drop.fall_time(), &p.drop.spin(), p.exact.tolerance) {
        Ok(c) => Ok((c.radians, c.calibration.map(|x| x.evaluations))),
        Err(e @ CirculationError::Calibration { .. }) => Err((Status::Failed, e.to_string())),
        Err(e) => Err((Status::Refused, e.to_string())),
    }
}

/// The exact row of the library schedule with `circulation`: with `peaks` (or `rapier`, which
/// checks the peak) the shared [`Evaluation`] (flip, peaks and motor demand, as `simulate`
/// measures them), else the flip alone.
fn schedule_row(problem: &Problem, compute: &Compute, schedule: &str, circulation: &Resolution) -> Measured {
    let (cat, tol) = (&problem.cat, problem.exact.tolerance);
    let (radians, evaluations) = match circulation {
        Ok(x) => *x,
        Err((status, reason)) => {
            return Measured::alone(Row::without(schedule, "exact", *status, reason, Labels::default()))
        }
    };
    let s = Schedule::new(problem, radians);
    let evaluation = (compute.peaks || compute.rapier)
        .then(|| Evaluation::new(cat, &s, &problem.drop.spin(), &problem.actuator.motors(), &problem.exact));
    let f = match &evaluation {
        Some(e) => e.flip,
        None => flip(cat, &s, tol),
    };
    if !f.converged {
        let reason = format!(
            "the exact integration did not meet exact.tolerance = {tol:e} rad (estimate {:e} rad)",
            f.error_estimate
        );
        return Measured::alone(Row::without(schedule, "exact", Status::Failed, &reason, Labels::default()));
    }
    let mut numbers = Numbers::flip(Some(radians), f.twist, f.swing, Some(f.error_estimate));
    numbers.calibration_evaluations = evaluations;
    if compute.peaks {
        if let Some(e) = &evaluation {
            numbers.peaks = Some(e.peaks);
            numbers.peak_nm = Some(e.peaks.max);
            numbers.motors = Some(MotorNumbers::new(&e.motors));
        }
    }
    let row = Row::with(schedule, "exact", numbers, Labels::default());
    let subject = match (&row.status, evaluation) {
        (Status::Ok, Some(e)) => {
            Some((Subject::Schedule(s), Reference { twist: f.twist, swing: f.swing, peak_torque: e.peaks.max }))
        }
        _ => None,
    };
    Measured { row, subject }
}
