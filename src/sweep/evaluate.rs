//! One case through the exact engine: the rows a sweep reports for it.
//!
//! Per case, with the problem's own `exact` settings:
//! - schedule `paper`: the paper's circulation `D_p = π/C` ([`paper_circulation`]), its flip
//!   (twist, swing; [`flip`]) and, with `peaks`, its peak torques per phase and joint;
//! - schedule `calibrated`: the circulation `D_c` for which the exact engine turns the cat by ±π
//!   ([`resolve_circulation`] with `circulation = "calibrated"`, i.e. [`crate::engines::calibrate::calibrate`]),
//!   its swing and peak torques;
//! - schedule `given`: when the problem file gives a circulation in radians, that one as well;
//! - the paper formula's error `D_c − D_p` (rad) and `(D_c − D_p)/D_p`, on every row of the case.
//!
//! Accuracy (the problem's `exact.tolerance` = ε): twist and swing to ε rad (Richardson estimate of
//! the sixth-order Magnus integration, reported per row); the calibrated circulation to `10⁻² ε`
//! rad in circulation with its twist within ε of ±π (checked, else the row is `failed`); peak
//! torques from `exact.torque_samples` samples per phase, each peak refined by golden-section search
//! between its neighbouring samples.
//!
//! The convex retiming, the whole-manoeuvre optimum and the rapier verdict are not wired into
//! this build: asked for, they give rows with status `not-available` and say so.

use serde::Serialize;

use crate::engines::circulation::{resolve_circulation, CirculationError};
use crate::engines::exact::flip;
use crate::engines::peaks::PhasePeaks;
use crate::engines::torque::peak_torques;
use crate::problem::manoeuvre::Circulation;
use crate::problem::Problem;
use crate::schedule::{paper_circulation, Schedule};

use super::spec::Compute;

/// How a row ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Computed; every number of the row is valid to its stated accuracy.
    Ok,
    /// The problem (or the paper's formula) refuses this case; the reason says why.
    Refused,
    /// The computation ran but gave no valid result (e.g. calibration found no root).
    Failed,
    /// Asked for, but not available in this build.
    NotAvailable,
}

impl Status {
    /// The kebab-case name written in the CSV.
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Refused => "refused",
            Status::Failed => "failed",
            Status::NotAvailable => "not-available",
        }
    }

    /// The status of a name written by [`Status::name`].
    pub fn parse(s: &str) -> Option<Status> {
        [Status::Ok, Status::Refused, Status::Failed, Status::NotAvailable].into_iter().find(|x| x.name() == s)
    }
}

/// The numbers of one schedule of one case (present when the row's status is `ok`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Numbers {
    /// Circulation `∫ω ds`, rad.
    pub circulation_rad: f64,
    /// Signed twist about A's initial `+z`, degrees.
    pub twist_deg: f64,
    /// Swing of the spine axis, degrees.
    pub swing_deg: f64,
    /// `|twist| − 180°`, degrees: how far the schedule misses the flip.
    pub flip_error_deg: f64,
    /// Richardson estimate of the orientation error, rad.
    pub error_estimate_rad: f64,
    /// Peak torques per phase and joint, N·m (when `peaks` is asked for).
    pub peaks: Option<PhasePeaks>,
    /// Exact-engine evaluations of the calibration (calibrated rows).
    pub calibration_evaluations: Option<usize>,
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
    /// The numbers, when `ok`.
    pub numbers: Option<Numbers>,
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
    /// A case the problem file refuses: one row per asked schedule, each carrying the reason.
    pub fn refused(compute: &Compute, reason: &str) -> CaseOutcome {
        let rows = asked_schedules(compute, false)
            .into_iter()
            .map(|(schedule, engine)| Row {
                schedule: schedule.to_string(),
                engine: engine.to_string(),
                status: if engine == "exact" { Status::Refused } else { Status::NotAvailable },
                reason: if engine == "exact" { reason.to_string() } else { NOT_AVAILABLE.to_string() },
                numbers: None,
            })
            .collect();
        CaseOutcome { warnings: String::new(), paper_rad: None, calibrated_rad: None, rows }
    }

    /// `D_c − D_p`, rad, when both exist.
    pub fn circulation_error(&self) -> Option<f64> {
        Some(self.calibrated_rad? - self.paper_rad?)
    }
}

/// The reason written on rows this build cannot compute.
pub const NOT_AVAILABLE: &str = "not available in this build";

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

/// Evaluates one case. The single call site of the engines: switch it to the shared evaluation here.
pub fn evaluate_case(problem: &Problem, compute: &Compute) -> CaseOutcome {
    let cat = &problem.cat;
    let tol = problem.exact.tolerance;
    let given = match problem.manoeuvre.circulation {
        Circulation::Angle(a) => Some(a),
        _ => None,
    };
    let paper = paper_circulation(cat, problem.manoeuvre.theta());
    let paper_rad = paper.as_ref().ok().copied();
    let mut calibrated_rad = None;
    let mut rows = Vec::new();
    for (schedule, engine) in asked_schedules(compute, given.is_some()) {
        let row = |status, reason: String, numbers| Row {
            schedule: schedule.to_string(),
            engine: engine.to_string(),
            status,
            reason,
            numbers,
        };
        if engine != "exact" || schedule == "retimed" || schedule == "whole" {
            rows.push(row(Status::NotAvailable, NOT_AVAILABLE.to_string(), None));
            continue;
        }
        let circulation = match schedule {
            "paper" => paper.as_ref().map(|&d| (d, None)).map_err(|e| (Status::Refused, e.to_string())),
            "calibrated" => {
                let mut p = problem.clone();
                p.manoeuvre.circulation = Circulation::Calibrated;
                match resolve_circulation(&p.cat, &p.manoeuvre, p.drop.fall_time(), p.exact.tolerance) {
                    Ok(c) => Ok((c.radians, c.calibration.map(|x| x.evaluations))),
                    Err(e @ CirculationError::Calibration { .. }) => Err((Status::Failed, e.to_string())),
                    Err(e) => Err((Status::Refused, e.to_string())),
                }
            }
            _ => given.map(|d| (d, None)).ok_or((Status::Failed, "the problem gives no circulation".to_string())),
        };
        let (radians, evaluations) = match circulation {
            Ok(x) => x,
            Err((status, reason)) => {
                rows.push(row(status, super::spec::one_line(&reason), None));
                continue;
            }
        };
        if schedule == "calibrated" {
            calibrated_rad = Some(radians);
        }
        let s = Schedule::new(problem, radians);
        let f = flip(cat, &s, tol);
        if !f.converged {
            let reason = format!(
                "the exact integration did not meet exact.tolerance = {tol:e} rad (estimate {:e} rad)",
                f.error_estimate
            );
            rows.push(row(Status::Failed, reason, None));
            continue;
        }
        let peaks = compute.peaks.then(|| PhasePeaks::from_peaks(&peak_torques(cat, &s, problem.exact.torque_samples)));
        let numbers = Numbers {
            circulation_rad: radians,
            twist_deg: f.twist.to_degrees(),
            swing_deg: f.swing.to_degrees(),
            flip_error_deg: f.twist.to_degrees().abs() - 180.0,
            error_estimate_rad: f.error_estimate,
            peaks,
            calibration_evaluations: evaluations,
        };
        if all_finite(&numbers) {
            rows.push(row(Status::Ok, String::new(), Some(numbers)));
        } else {
            rows.push(row(Status::Failed, "the engine returned a non-finite number".to_string(), None));
        }
    }
    CaseOutcome { warnings: problem.warnings().join("; "), paper_rad, calibrated_rad, rows }
}

/// Whether every number of a row is finite.
fn all_finite(n: &Numbers) -> bool {
    let mut v = vec![n.circulation_rad, n.twist_deg, n.swing_deg, n.flip_error_deg, n.error_estimate_rad];
    if let Some(p) = &n.peaks {
        v.extend([p.bend[0], p.bend[1], p.twist[0], p.twist[1], p.unbend[0], p.unbend[1], p.max]);
    }
    v.iter().all(|x| x.is_finite())
}
