//! The CSV files of a run: tidy tables (one row per problem × schedule × engine, sorted).

use super::{ExportError, Shown};
use super::{Exporter, Files, Views};
use crate::engines::peaks::PhasePeaks;
use crate::engines::rapier::{Quantity, Verification};
use crate::engines::Engine;
use crate::report::simulate::{RapierOutcome, SimulationReport};

/// The CSV exporter.
pub struct Csv;

impl Exporter for Csv {
    fn files(&self, v: &Views) -> Result<Files, ExportError> {
        let whole: Vec<_> = v.whole_row.into_iter().cloned().collect();
        let mut files = vec![
            ("compare.csv".to_string(), v.table.to_csv_with(&whole)),
            ("verification.csv".to_string(), verification_csv(v.verified)),
        ];
        files.extend(v.robust.map(|r| ("robust.csv".to_string(), r.to_csv())));
        Ok(files)
    }
}

/// The report's columns before rapier's verification columns.
const REPORT_HEAD: [&str; 6] = ["problem", "schedule", "engine", "circulation_rad", "twist_deg", "swing_deg"];
/// The measured columns after the peaks, up to the run time.
const MEASURED: [&str; 4] = ["momentum_max", "dt_s", "tracking1_rad", "tracking2_rad"];

/// `verification.csv`: one row per schedule and engine, sorted. A rapier row carries the
/// verification's columns and `verdict_reason` (the verdict in words); a rapier row without a
/// result has empty number fields. rapier's `twist_deg` and `swing_deg` are extrapolated to
/// `dt → 0` (as its report's), its peaks the finest run's, raw: the last two columns give the
/// other two, `twist_raw_deg` (the finest run's twist) and `max_extrapolated_nm` (the peak the
/// verdict judges; empty where a saturated motor left it out).
fn verification_csv(rows: &[Shown]) -> String {
    let mut header = REPORT_HEAD.to_vec();
    header.extend(PhasePeaks::CSV_HEADER.split(','));
    header.extend(MEASURED);
    header.push("run_time_s");
    header.extend(Verification::CSV_HEADER.split(','));
    header.push("verdict_reason");
    let reasoned = header.len();
    header.extend(["twist_raw_deg", "max_extrapolated_nm"]);
    let mut all: Vec<(String, Engine, Vec<String>)> = Vec::new();
    for v in rows {
        let name = v.name();
        all.push((name.clone(), Engine::Exact, report_fields(&name, &v.exact)));
        let mut rapier = rapier_fields(&name, v);
        rapier.resize(reasoned, String::new());
        let raw = v.rapier.report().and_then(|r| r.figures.check.twist_deg_raw);
        let peak = v.verification().and_then(|x| x.quantity(Quantity::PeakTorque)).and_then(|c| c.value);
        rapier.extend([raw, peak].map(|x| x.map_or(String::new(), |x| format!("{x:.9}"))));
        all.push((name.clone(), Engine::Rapier, rapier));
    }
    all.sort_by(|a, b| (&a.0, a.1).cmp(&(&b.0, b.1)));
    let width = header.len();
    let records = all.into_iter().map(|(_, _, mut f)| {
        f.resize(width, String::new());
        f
    });
    crate::exchange::table::csv_table(&header, records)
}

/// A report's fields up to its run time.
fn report_fields(name: &str, r: &SimulationReport) -> Vec<String> {
    let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:.6e}"));
    let tr = r.figures.check.tracking_error_rad;
    let mut f = vec![
        r.problem.clone(),
        name.to_string(),
        r.engine.to_string(),
        format!("{:.12}", r.circulation_rad),
        format!("{:.9}", r.figures.twist_deg),
        format!("{:.9}", r.figures.swing_deg),
    ];
    f.extend(r.peak_torque_nm.fields());
    f.extend([
        format!("{:.3e}", r.figures.momentum_max),
        opt(r.figures.check.dt),
        opt(tr.map(|t| t[0])),
        opt(tr.map(|t| t[1])),
        format!("{:.6}", r.figures.run_time_s),
    ]);
    f
}

/// rapier's row: its report's fields, or empty ones when it has no result, then the
/// verification's and the verdict's.
fn rapier_fields(name: &str, v: &Shown) -> Vec<String> {
    let mut f = match &v.rapier {
        RapierOutcome::Report(r) => report_fields(name, r),
        RapierOutcome::NoResult(x) => {
            let e = &v.exact;
            let mut f = vec![e.problem.clone(), name.to_string(), Engine::Rapier.to_string()];
            f.push(format!("{:.12}", e.circulation_rad));
            // No twist, swing, peaks or measurements: empty fields up to the run time.
            f.resize(REPORT_HEAD.len() + PhasePeaks::CSV_HEADER.split(',').count() + MEASURED.len(), String::new());
            f.push(format!("{:.6}", x.run_time_s));
            f
        }
    };
    if let Some(x) = v.verification() {
        f.extend(x.fields());
        f.push(x.verdict.to_string());
    }
    f
}
