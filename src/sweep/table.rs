//! The tidy table of a sweep: one record per case × schedule × engine, written as CSV with the
//! `csv` crate and read back (to merge shards) without loss.
//!
//! Columns: `case`, one column per axis (named by its field, values as written in the sweep),
//! `schedule`, `engine`, `status`, `reason`, `warnings`, the case's `paper_circulation_rad` (π/C),
//! `calibrated_circulation_rad`, `circulation_error_rad` (calibrated − paper) and
//! `circulation_rel_error` ((calibrated − paper)/paper), then the row's `circulation_rad`,
//! `twist_deg`, `swing_deg`, `flip_error_deg` (`|twist| − 180°`), `error_estimate_rad`, the peak
//! torques per phase and joint and their maximum `peak_max_nm` (N·m; the maximum alone for the
//! whole-manoeuvre spline, which has no phases), what the trajectory asks of its motors on every
//! exact row with peak torques (`peak_speed1_rad_s`, `peak_speed2_rad_s`: peak `|q̇_j|`, rad/s;
//! `peak_power1_w`, `peak_power2_w`: peak `|τ_j q̇_j|`, W; and with `[actuator]` limits the least
//! margin's `motor_worst_ratio` (usage, ≤ 1 within), `motor_worst_limit` (e.g. `joint 2 speed`)
//! and `within_motors` (`true`/`false`)), and `calibration_evaluations`; then
//! `retimed_from` and `solver_status` (the optimiser's own word), the retiming's
//! `retime_lower_bound_nm` (certified), `retime_program_peak_nm` and `retime_gap_nm`, the whole
//! optimum's `whole_start`, `energy_n2m2s`, `max_bend_deg`, `fall_time_s` (its duration `T`, s;
//! with the objective `min-time` the least fall within the motors) and `drop_height_m`
//! (`g T²/2`, m), and rapier's `rapier_verdict`,
//! `rapier_twist_extrapolated_deg`, `rapier_swing_extrapolated_deg`,
//! `rapier_peak_extrapolated_nm`, `rapier_steps` and `rapier_finest_dt_s` (its raw finest-run
//! twist, swing and peaks are in the usual columns; the motor columns stay empty on rapier rows,
//! which check the exact engine's torques, not its motor figures). A cell is empty exactly when its quantity
//! does not exist for that row (the status and reason say why); no cell holds NaN. Numbers are
//! written with Rust's shortest round-trip formatting, so reading the CSV back gives the same
//! bits.

use crate::engines::peaks::PhasePeaks;
use crate::engines::Engine;
use crate::exchange::table::{error_message, record_line};

use super::cases::{case, cell};
use super::evaluate::CaseOutcome;
use super::row::{
    Labels, MotorNumbers, Numbers, RapierNumbers, RetimeNumbers, Status, SweepSchedule, WholeNumbers, WorstLimit,
};
use super::spec::Sweep;

/// Why a table could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum TableError {
    /// The CSV writer or reader failed.
    #[error("CSV {context}: {message}")]
    Csv {
        /// What was being done.
        context: String,
        /// The csv crate's message.
        message: String,
    },
}

/// One row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// Case index.
    pub case: usize,
    /// Per axis, the index of its value.
    pub picks: Vec<usize>,
    /// The schedule.
    pub schedule: SweepSchedule,
    /// The engine.
    pub engine: Engine,
    /// How the row ended.
    pub status: Status,
    /// Why, when not `ok`.
    pub reason: String,
    /// The case's warnings.
    pub warnings: String,
    /// The row's words (optimiser status, rapier verdict, …).
    pub labels: Labels,
    /// The case's π/C, rad.
    pub paper_rad: Option<f64>,
    /// The case's calibrated circulation, rad.
    pub calibrated_rad: Option<f64>,
    /// The row's numbers.
    pub numbers: Option<Numbers>,
}

impl Record {
    /// `(D_c − D_p)/D_p`, when both exist.
    pub fn circulation_rel_error(&self) -> Option<f64> {
        Some((self.calibrated_rad? - self.paper_rad?) / self.paper_rad?)
    }

    /// The row's overall peak torque, N·m.
    pub fn peak_max(&self) -> Option<f64> {
        self.numbers.and_then(|n| n.peak_nm)
    }
}

/// The records of one case's outcome.
pub fn records(sweep: &Sweep, index: usize, outcome: &CaseOutcome) -> Vec<Record> {
    let picks = case(sweep, index).picks;
    outcome
        .rows
        .iter()
        .map(|r| Record {
            case: index,
            picks: picks.clone(),
            schedule: r.schedule,
            engine: r.engine,
            status: r.status,
            reason: r.reason.clone(),
            warnings: outcome.warnings.clone(),
            labels: r.labels.clone(),
            paper_rad: outcome.paper_rad,
            calibrated_rad: outcome.calibrated_rad,
            numbers: r.numbers,
        })
        .collect()
}

const HEAD: [&str; 5] = ["schedule", "engine", "status", "reason", "warnings"];
const NUMBERS: [&str; 40] = [
    "paper_circulation_rad",
    "calibrated_circulation_rad",
    "circulation_error_rad",
    "circulation_rel_error",
    "circulation_rad",
    "twist_deg",
    "swing_deg",
    "flip_error_deg",
    "error_estimate_rad",
    "bend_tau1_nm",
    "bend_tau2_nm",
    "twist_tau1_nm",
    "twist_tau2_nm",
    "unbend_tau1_nm",
    "unbend_tau2_nm",
    "peak_max_nm",
    "peak_speed1_rad_s",
    "peak_speed2_rad_s",
    "peak_power1_w",
    "peak_power2_w",
    "motor_worst_ratio",
    "motor_worst_limit",
    "within_motors",
    "calibration_evaluations",
    "retimed_from",
    "solver_status",
    "retime_lower_bound_nm",
    "retime_program_peak_nm",
    "retime_gap_nm",
    "whole_start",
    "energy_n2m2s",
    "max_bend_deg",
    "fall_time_s",
    "drop_height_m",
    "rapier_verdict",
    "rapier_twist_extrapolated_deg",
    "rapier_swing_extrapolated_deg",
    "rapier_peak_extrapolated_nm",
    "rapier_steps",
    "rapier_finest_dt_s",
];

/// The columns after the axes, in order.
fn tail() -> impl Iterator<Item = &'static str> {
    HEAD.into_iter().chain(NUMBERS)
}

/// The header row.
pub fn header(sweep: &Sweep) -> Vec<String> {
    let mut h = vec!["case".to_string()];
    h.extend(sweep.axes.iter().map(|a| a.field.clone()));
    h.extend(tail().map(str::to_string));
    h
}

fn num(x: Option<f64>) -> String {
    x.filter(|v| v.is_finite()).map_or_else(String::new, |v| format!("{v:?}"))
}

fn count(x: Option<usize>) -> String {
    x.map_or_else(String::new, |v| v.to_string())
}

fn fields(sweep: &Sweep, r: &Record) -> Vec<String> {
    let mut f = vec![r.case.to_string()];
    f.extend(sweep.axes.iter().zip(&r.picks).map(|(a, &k)| cell(&a.values[k])));
    f.extend([
        r.schedule.name().to_string(),
        r.engine.name().to_string(),
        r.status.name().to_string(),
        r.reason.clone(),
        r.warnings.clone(),
    ]);
    let n = r.numbers.as_ref();
    let p = n.and_then(|n| n.peaks);
    let (rt, wh, ra) = (n.and_then(|n| n.retiming), n.and_then(|n| n.whole), n.and_then(|n| n.rapier));
    let error = r.calibrated_rad.zip(r.paper_rad).map(|(c, p)| c - p);
    f.extend([num(r.paper_rad), num(r.calibrated_rad), num(error), num(r.circulation_rel_error())]);
    f.extend(
        [
            n.and_then(|n| n.circulation_rad),
            n.map(|n| n.twist_deg),
            n.map(|n| n.swing_deg),
            n.map(|n| n.flip_error_deg),
            n.and_then(|n| n.error_estimate_rad),
            p.map(|p| p.bend[0]),
            p.map(|p| p.bend[1]),
            p.map(|p| p.twist[0]),
            p.map(|p| p.twist[1]),
            p.map(|p| p.unbend[0]),
            p.map(|p| p.unbend[1]),
            n.and_then(|n| n.peak_nm),
        ]
        .map(num),
    );
    let m = n.and_then(|n| n.motors);
    let worst = m.and_then(|m| m.worst);
    f.extend(
        [
            m.map(|m| m.peak_speed_rad_s[0]),
            m.map(|m| m.peak_speed_rad_s[1]),
            m.map(|m| m.peak_power_w[0]),
            m.map(|m| m.peak_power_w[1]),
            worst.map(|w| w.ratio),
        ]
        .map(num),
    );
    f.push(worst.map_or_else(String::new, |w| w.name()));
    f.push(worst.map_or_else(String::new, |w| w.within().to_string()));
    f.push(count(n.and_then(|n| n.calibration_evaluations)));
    let l = &r.labels;
    f.extend([l.retimed_from.map_or_else(String::new, |s| s.name().to_string()), l.solver_status.clone()]);
    f.extend([rt.map(|x| x.lower_bound_nm), rt.map(|x| x.program_peak_nm), rt.map(|x| x.gap_nm)].map(num));
    f.push(l.whole_start.clone());
    f.extend(
        [wh.map(|x| x.energy), wh.map(|x| x.max_bend_deg), wh.map(|x| x.fall_time_s), wh.map(|x| x.drop_height_m)]
            .map(num),
    );
    f.push(l.rapier_verdict.clone());
    f.extend(
        [
            ra.and_then(|x| x.twist_extrapolated_deg),
            ra.and_then(|x| x.swing_extrapolated_deg),
            ra.and_then(|x| x.peak_extrapolated_nm),
        ]
        .map(num),
    );
    f.push(count(ra.map(|x| x.steps)));
    f.push(num(ra.map(|x| x.finest_dt_s)));
    f
}

/// The table as CSV text, records in the order given.
pub fn to_csv(sweep: &Sweep, records: &[Record]) -> Result<String, TableError> {
    let fail = |e: csv::Error| TableError::Csv { context: "writing".into(), message: e.to_string() };
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header(sweep)).map_err(fail)?;
    for r in records {
        w.write_record(fields(sweep, r)).map_err(fail)?;
    }
    let bytes = w.into_inner().map_err(|e| TableError::Csv { context: "writing".into(), message: e.to_string() })?;
    String::from_utf8(bytes).map_err(|e| TableError::Csv { context: "writing".into(), message: e.to_string() })
}

/// Reads a table written by [`to_csv`] for the same sweep.
pub fn from_csv(sweep: &Sweep, text: &str, origin: &str) -> Result<Vec<Record>, TableError> {
    Ok(from_csv_lines(sweep, text, origin)?.into_iter().map(|(_, r)| r).collect())
}

/// Reads a table written by [`to_csv`] for the same sweep, each record with its line in the file.
///
/// Nothing is dropped or changed silently: every number must be finite (the writer leaves a cell
/// empty rather than write NaN), an `ok` row must carry its twist, swing and flip error and any
/// other row none, and each row must read back to exactly its cells (a group of cells read
/// together, e.g. the six phase peaks, present in full or not at all; axis cells the case's own
/// values). Errors name the line and column.
pub fn from_csv_lines(sweep: &Sweep, text: &str, origin: &str) -> Result<Vec<(u64, Record)>, TableError> {
    let fail = |message: String| TableError::Csv { context: format!("reading {origin}"), message };
    let mut rd = csv::Reader::from_reader(text.as_bytes());
    let head: Vec<String> = rd.headers().map_err(|e| fail(e.to_string()))?.iter().map(str::to_string).collect();
    if head != header(sweep) {
        return Err(fail("its columns are not this sweep's".into()));
    }
    let o = 1 + sweep.axes.len();
    let mut out = Vec::new();
    let columns = header(sweep);
    // Lines as the file has them, whatever its line ends (an editor may have written `\r\n`).
    let line_of = |p: &csv::Position| record_line(text.as_bytes(), p, None);
    for rec in rd.records() {
        let rec = rec.map_err(|e| match e.position() {
            Some(p) => fail(format!("line {}: {}", line_of(p), error_message(&e))),
            None => fail(e.to_string()),
        })?;
        let line = rec.position().map_or(0, line_of);
        let bad = |what: &str| fail(format!("line {line}: bad {what}"));
        // The cell of a named column after the axes.
        let at = |name: &str| tail().position(|c| c == name).and_then(|k| rec.get(o + k)).unwrap_or("");
        let text = |name: &str| at(name).to_string();
        let float = |name: &str| -> Result<Option<f64>, TableError> {
            let s = at(name);
            if s.is_empty() {
                return Ok(None);
            }
            match s.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(Some(x)),
                _ => Err(fail(format!("line {line}: {name} = {s:?} is not a finite number"))),
            }
        };
        let whole = |name: &str| -> Result<Option<usize>, TableError> {
            let s = at(name);
            if s.is_empty() {
                Ok(None)
            } else {
                s.parse::<usize>().map(Some).map_err(|_| bad(name))
            }
        };
        let index: usize = rec.get(0).unwrap_or("").parse().map_err(|_| bad("case"))?;
        if index >= sweep.case_count() {
            return Err(bad("case (beyond the sweep)"));
        }
        let status = Status::parse(at("status")).ok_or_else(|| bad("status"))?;
        let phase =
            ["bend_tau1_nm", "bend_tau2_nm", "twist_tau1_nm", "twist_tau2_nm", "unbend_tau1_nm", "unbend_tau2_nm"]
                .map(float);
        let peak_nm = float("peak_max_nm")?;
        let peaks = match (phase, peak_nm) {
            ([Ok(Some(b1)), Ok(Some(b2)), Ok(Some(t1)), Ok(Some(t2)), Ok(Some(u1)), Ok(Some(u2))], Some(max)) => {
                Some(PhasePeaks { bend: [b1, b2], twist: [t1, t2], unbend: [u1, u2], max })
            }
            (phase, _) => {
                for p in phase {
                    p?;
                }
                None
            }
        };
        let retiming =
            match (float("retime_lower_bound_nm")?, float("retime_program_peak_nm")?, float("retime_gap_nm")?) {
                (Some(lower_bound_nm), Some(program_peak_nm), Some(gap_nm)) => {
                    Some(RetimeNumbers { lower_bound_nm, program_peak_nm, gap_nm })
                }
                _ => None,
            };
        let whole_numbers =
            match (float("energy_n2m2s")?, float("max_bend_deg")?, float("fall_time_s")?, float("drop_height_m")?) {
                (Some(energy), Some(max_bend_deg), Some(fall_time_s), Some(drop_height_m)) => {
                    Some(WholeNumbers { energy, max_bend_deg, fall_time_s, drop_height_m })
                }
                _ => None,
            };
        let worst = match (float("motor_worst_ratio")?, at("motor_worst_limit")) {
            (None, "") => None,
            (Some(ratio), name) => Some(WorstLimit::parse(name, ratio).ok_or_else(|| bad("motor_worst_limit"))?),
            (None, _) => return Err(bad("motor_worst_ratio (empty beside motor_worst_limit)")),
        };
        let motors = match ["peak_speed1_rad_s", "peak_speed2_rad_s", "peak_power1_w", "peak_power2_w"].map(float) {
            [Ok(Some(s1)), Ok(Some(s2)), Ok(Some(p1)), Ok(Some(p2))] => {
                Some(MotorNumbers { peak_speed_rad_s: [s1, s2], peak_power_w: [p1, p2], worst })
            }
            cells => {
                for c in cells {
                    c?;
                }
                None
            }
        };
        let rapier = match (whole("rapier_steps")?, float("rapier_finest_dt_s")?) {
            (Some(steps), Some(finest_dt_s)) => Some(RapierNumbers {
                twist_extrapolated_deg: float("rapier_twist_extrapolated_deg")?,
                swing_extrapolated_deg: float("rapier_swing_extrapolated_deg")?,
                peak_extrapolated_nm: float("rapier_peak_extrapolated_nm")?,
                steps,
                finest_dt_s,
            }),
            _ => None,
        };
        let numbers = match (float("twist_deg")?, float("swing_deg")?, float("flip_error_deg")?) {
            (Some(twist_deg), Some(swing_deg), Some(flip_error_deg)) => Some(Numbers {
                circulation_rad: float("circulation_rad")?,
                twist_deg,
                swing_deg,
                flip_error_deg,
                error_estimate_rad: float("error_estimate_rad")?,
                peaks,
                peak_nm,
                calibration_evaluations: whole("calibration_evaluations")?,
                retiming,
                whole: whole_numbers,
                motors,
                rapier,
            }),
            _ => None,
        };
        let record = Record {
            case: index,
            picks: case(sweep, index).picks,
            schedule: SweepSchedule::parse(at("schedule")).ok_or_else(|| bad("schedule"))?,
            engine: Engine::parse(at("engine")).ok_or_else(|| bad("engine"))?,
            status,
            reason: text("reason"),
            warnings: text("warnings"),
            labels: Labels {
                retimed_from: match at("retimed_from") {
                    "" => None,
                    name => Some(SweepSchedule::parse(name).ok_or_else(|| bad("retimed_from"))?),
                },
                solver_status: text("solver_status"),
                whole_start: text("whole_start"),
                rapier_verdict: text("rapier_verdict"),
            },
            paper_rad: float("paper_circulation_rad")?,
            calibrated_rad: float("calibrated_circulation_rad")?,
            numbers,
        };
        match (record.status, &record.numbers) {
            (Status::Ok, None) => {
                let empty = ["twist_deg", "swing_deg", "flip_error_deg"].into_iter().find(|c| at(c).is_empty());
                return Err(fail(format!("line {line}: status is ok but {} is empty", empty.unwrap_or("a number"))));
            }
            (status, Some(_)) if status != Status::Ok => {
                return Err(fail(format!("line {line}: status is {} but the row carries numbers", status.name())));
            }
            _ => {}
        }
        let again = fields(sweep, &record);
        if let Some(k) = (0..columns.len()).find(|&k| rec.get(k).unwrap_or("") != again[k]) {
            return Err(fail(format!(
                "line {line}: {} = {:?} does not fit the rest of the row (a sweep writes {:?} there)",
                columns[k],
                rec.get(k).unwrap_or(""),
                again[k]
            )));
        }
        out.push((line, record));
    }
    Ok(out)
}
