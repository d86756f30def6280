//! A sweep's rows: how each ended ([`Status`]), the numbers it carries ([`Numbers`] and its
//! parts, from one measured schedule: [`Numbers::measured`]), its labels, and what an exact row
//! measured for rapier to verify (`ExactRow`, the [`Subject`]).
//!
//! A row is `ok` only when every number it carries is finite and valid; otherwise its status
//! (`refused`, `failed`, `skipped`) and a one-line reason say why, and it carries no number.

use serde::Serialize;

use crate::engines::evaluate::Evaluation;
use crate::engines::measured::Measured;
use crate::engines::motors::{MotorDemand, RATIO_TOLERANCE};
use crate::engines::peaks::PhasePeaks;
use crate::engines::Engine;
use crate::model::motor::Limit;
use crate::optimize::retime::{PhasePath, RetimedTrajectory};
use crate::optimize::whole::BSpline;
use crate::schedule::Schedule;

use super::spec::one_line;

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

/// The schedule a row measures (the CSV's `schedule`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SweepSchedule {
    /// The library schedule with the paper's circulation `π/C`.
    Paper,
    /// The library schedule with the calibrated circulation.
    Calibrated,
    /// The library schedule with the circulation the problem gives.
    Given,
    /// The certified convex retiming of the calibrated (or the paper's) schedule.
    Retimed,
    /// The whole-manoeuvre optimum.
    Whole,
}

impl SweepSchedule {
    /// Every schedule, in row order.
    pub const ALL: [SweepSchedule; 5] = [
        SweepSchedule::Paper,
        SweepSchedule::Calibrated,
        SweepSchedule::Given,
        SweepSchedule::Retimed,
        SweepSchedule::Whole,
    ];

    /// The kebab-case name written in the CSV.
    pub fn name(self) -> &'static str {
        match self {
            SweepSchedule::Paper => "paper",
            SweepSchedule::Calibrated => "calibrated",
            SweepSchedule::Given => "given",
            SweepSchedule::Retimed => "retimed",
            SweepSchedule::Whole => "whole",
        }
    }

    /// The schedule of a name written by [`SweepSchedule::name`].
    pub fn parse(s: &str) -> Option<SweepSchedule> {
        SweepSchedule::ALL.into_iter().find(|x| x.name() == s)
    }
}

impl std::fmt::Display for SweepSchedule {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Writes an optional schedule as its name, or an empty string (the CSV's cell).
fn name_or_empty<S: serde::Serializer>(s: &Option<SweepSchedule>, out: S) -> Result<S::Ok, S::Error> {
    out.serialize_str(s.map_or("", SweepSchedule::name))
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
            peak_speed_rad_s: std::array::from_fn(|j| demand.peak_speed_rad_s[j].value),
            peak_power_w: std::array::from_fn(|j| demand.peak_power_w[j].value),
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

    /// The numbers of a measured trajectory: its flip, its peaks (per phase when `phases`, a
    /// three-phase schedule) and what it asks of its motors.
    pub fn measured(circulation_rad: Option<f64>, e: &Evaluation, phases: bool) -> Numbers {
        let f = &e.flip;
        let mut numbers = Numbers::flip(circulation_rad, f.twist, f.swing, Some(f.error_estimate));
        numbers.peaks = phases.then(|| e.phase_peaks());
        numbers.peak_nm = Some(e.peak());
        numbers.motors = Some(MotorNumbers::new(&e.motors));
        numbers
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
    /// The schedule a `retimed` row retimes: `calibrated`, or `paper` when the calibration failed
    /// (written as its name, empty for other rows).
    #[serde(serialize_with = "name_or_empty")]
    pub retimed_from: Option<SweepSchedule>,
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
    /// The schedule.
    pub schedule: SweepSchedule,
    /// The engine.
    pub engine: Engine,
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
    pub fn without(schedule: SweepSchedule, engine: Engine, status: Status, reason: &str, labels: Labels) -> Row {
        Row { schedule, engine, status, reason: one_line(reason), labels, numbers: None }
    }

    /// An `ok` row, or a `failed` one when a number is not finite.
    pub fn with(schedule: SweepSchedule, engine: Engine, numbers: Numbers, labels: Labels) -> Row {
        if numbers.all_finite() {
            Row { schedule, engine, status: Status::Ok, reason: String::new(), labels, numbers: Some(numbers) }
        } else {
            Row::without(schedule, engine, Status::Failed, "the engine returned a non-finite number", labels)
        }
    }
}

/// A trajectory an exact row measured, for rapier to verify.
pub enum Subject {
    /// A library schedule.
    Schedule(Measured<Schedule>),
    /// A schedule retimed.
    Retimed(Measured<RetimedTrajectory<PhasePath>>),
    /// The whole-manoeuvre optimum's spline.
    Whole(Measured<BSpline>),
}

/// An exact row and, when it is `ok`, the measured trajectory rapier verifies.
pub(crate) struct ExactRow {
    /// The row.
    pub row: Row,
    /// What rapier verifies.
    pub subject: Option<Subject>,
}

impl ExactRow {
    /// A row with nothing to verify.
    pub fn alone(row: Row) -> ExactRow {
        ExactRow { row, subject: None }
    }
}
