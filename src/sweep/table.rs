//! The tidy table of a sweep: one record per case × schedule × engine, written as CSV with the
//! `csv` crate and read back (to merge shards) without loss.
//!
//! Columns: `case`, one column per axis (named by its field, values as written in the sweep),
//! `schedule`, `engine`, `status`, `reason`, `warnings`, the case's `paper_circulation_rad` (π/C),
//! `calibrated_circulation_rad`, `circulation_error_rad` (calibrated − paper) and
//! `circulation_rel_error` ((calibrated − paper)/paper), then the row's `circulation_rad`,
//! `twist_deg`, `swing_deg`, `flip_error_deg` (`|twist| − 180°`), `error_estimate_rad`, the peak
//! torques per phase and joint and their maximum (N·m), and `calibration_evaluations`. A cell is
//! empty exactly when its quantity does not exist for that row (the status and reason say why);
//! no cell holds NaN. Numbers are written with Rust's shortest round-trip formatting, so reading
//! the CSV back gives the same bits.

use crate::engines::peaks::PhasePeaks;

use super::cases::{case, cell};
use super::evaluate::{CaseOutcome, Numbers, Status};
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
    /// `paper`, `calibrated`, `given`, `retimed`, `whole`.
    pub schedule: String,
    /// `exact` or `rapier`.
    pub engine: String,
    /// How the row ended.
    pub status: Status,
    /// Why, when not `ok`.
    pub reason: String,
    /// The case's warnings.
    pub warnings: String,
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
        self.numbers.and_then(|n| n.peaks).map(|p| p.max)
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
            schedule: r.schedule.clone(),
            engine: r.engine.clone(),
            status: r.status,
            reason: r.reason.clone(),
            warnings: outcome.warnings.clone(),
            paper_rad: outcome.paper_rad,
            calibrated_rad: outcome.calibrated_rad,
            numbers: r.numbers,
        })
        .collect()
}

const HEAD: [&str; 5] = ["schedule", "engine", "status", "reason", "warnings"];
const NUMBERS: [&str; 17] = [
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
    "calibration_evaluations",
];

/// The header row.
pub fn header(sweep: &Sweep) -> Vec<String> {
    let mut h = vec!["case".to_string()];
    h.extend(sweep.axes.iter().map(|a| a.field.clone()));
    h.extend(HEAD.iter().map(|s| s.to_string()));
    h.extend(NUMBERS.iter().map(|s| s.to_string()));
    h
}

fn num(x: Option<f64>) -> String {
    x.filter(|v| v.is_finite()).map_or_else(String::new, |v| format!("{v:?}"))
}

fn fields(sweep: &Sweep, r: &Record) -> Vec<String> {
    let mut f = vec![r.case.to_string()];
    f.extend(sweep.axes.iter().zip(&r.picks).map(|(a, &k)| cell(&a.values[k])));
    f.extend([r.schedule.clone(), r.engine.clone(), r.status.name().to_string(), r.reason.clone(), r.warnings.clone()]);
    let n = r.numbers.as_ref();
    let p = n.and_then(|n| n.peaks);
    let error = r.calibrated_rad.zip(r.paper_rad).map(|(c, p)| c - p);
    f.extend([num(r.paper_rad), num(r.calibrated_rad), num(error), num(r.circulation_rel_error())]);
    f.extend(
        [
            n.map(|n| n.circulation_rad),
            n.map(|n| n.twist_deg),
            n.map(|n| n.swing_deg),
            n.map(|n| n.flip_error_deg),
            n.map(|n| n.error_estimate_rad),
            p.map(|p| p.bend[0]),
            p.map(|p| p.bend[1]),
            p.map(|p| p.twist[0]),
            p.map(|p| p.twist[1]),
            p.map(|p| p.unbend[0]),
            p.map(|p| p.unbend[1]),
            p.map(|p| p.max),
        ]
        .map(num),
    );
    f.push(n.and_then(|n| n.calibration_evaluations).map_or_else(String::new, |e| e.to_string()));
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
    let fail = |message: String| TableError::Csv { context: format!("reading {origin}"), message };
    let mut rd = csv::Reader::from_reader(text.as_bytes());
    let head: Vec<String> = rd.headers().map_err(|e| fail(e.to_string()))?.iter().map(str::to_string).collect();
    if head != header(sweep) {
        return Err(fail("its columns are not this sweep's".into()));
    }
    let axes = sweep.axes.len();
    let mut out = Vec::new();
    for (line, rec) in rd.records().enumerate() {
        let rec = rec.map_err(|e| fail(e.to_string()))?;
        let at = |i: usize| rec.get(i).unwrap_or("");
        let bad = |what: &str| fail(format!("row {}: bad {what}", line + 2));
        let float = |i: usize| -> Result<Option<f64>, TableError> {
            let s = at(i);
            if s.is_empty() {
                Ok(None)
            } else {
                s.parse::<f64>().map(Some).map_err(|_| bad(&head[i]))
            }
        };
        let index: usize = at(0).parse().map_err(|_| bad("case"))?;
        if index >= sweep.case_count() {
            return Err(bad("case (beyond the sweep)"));
        }
        let picks = case(sweep, index).picks;
        let o = 1 + axes;
        let status = Status::parse(at(o + 2)).ok_or_else(|| bad("status"))?;
        let n = o + HEAD.len();
        let v = (0..12).map(|k| float(n + 4 + k)).collect::<Result<Vec<_>, _>>()?;
        let peaks = match v[5..12] {
            [Some(b1), Some(b2), Some(t1), Some(t2), Some(u1), Some(u2), Some(max)] => {
                Some(PhasePeaks { bend: [b1, b2], twist: [t1, t2], unbend: [u1, u2], max })
            }
            _ => None,
        };
        let evals = at(n + 16);
        let calibration_evaluations =
            if evals.is_empty() { None } else { Some(evals.parse().map_err(|_| bad("calibration_evaluations"))?) };
        let numbers = match v[..5] {
            [Some(circulation_rad), Some(twist_deg), Some(swing_deg), Some(flip_error_deg), Some(error_estimate_rad)] => {
                Some(Numbers {
                    circulation_rad,
                    twist_deg,
                    swing_deg,
                    flip_error_deg,
                    error_estimate_rad,
                    peaks,
                    calibration_evaluations,
                })
            }
            _ => None,
        };
        out.push(Record {
            case: index,
            picks,
            schedule: at(o).to_string(),
            engine: at(o + 1).to_string(),
            status,
            reason: at(o + 3).to_string(),
            warnings: at(o + 4).to_string(),
            paper_rad: float(n)?,
            calibrated_rad: float(n + 1)?,
            numbers,
        });
    }
    Ok(out)
}
