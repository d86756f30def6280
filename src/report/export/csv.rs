//! The CSV files of a run: tidy tables (one row per problem × schedule × engine, sorted).

use super::{ExportError, Shown};
use super::{Exporter, Files, Views};
use crate::engines::measured::Measured;
use crate::engines::peaks::PhasePeaks;
use crate::engines::rapier::{Quantity, Verification};
use crate::engines::rapier_check::EngineFigures;
use crate::engines::Engine;
use crate::optimize::whole::spline::BSpline;
use crate::report::simulate::RapierOutcome;

/// The CSV exporter.
pub struct Csv;

impl Exporter for Csv {
    fn files(&self, v: &Views) -> Result<Files, ExportError> {
        let whole: Vec<_> = v.whole_row.into_iter().cloned().collect();
        let mut files = vec![
            ("compare.csv".to_string(), v.table.to_csv_with(&whole)),
            ("verification.csv".to_string(), verification_csv(&v.problem.name, v.verified, v.whole.measured.as_ref())),
        ];
        files.extend(v.robust.map(|r| ("robust.csv".to_string(), r.to_csv())));
        Ok(files)
    }
}

/// The report's columns before rapier's verification columns.
const REPORT_HEAD: [&str; 6] = ["problem", "schedule", "engine", "circulation_rad", "twist_deg", "swing_deg"];
/// The measured columns after the peaks, up to the run time.
const MEASURED: [&str; 4] = ["momentum_max", "dt_s", "tracking1_rad", "tracking2_rad"];

/// `verification.csv`: one row per schedule and engine, sorted, and the whole optimum's two
/// rows (`whole` — its one piece: the phase columns empty but `max_nm`, no circulation) when it
/// was measured. A rapier row carries the verification's columns and `verdict_reason` (the
/// verdict in words); a rapier row without a result has empty number fields. rapier's
/// `twist_deg` and `swing_deg` are extrapolated to `dt → 0` (as its report's), its peaks the
/// finest run's, raw: the last two columns give the other two, `twist_raw_deg` (the finest run's
/// twist) and `max_extrapolated_nm` (the peak the verdict judges; empty where a saturated motor
/// left it out).
fn verification_csv(problem: &str, rows: &[Shown], whole: Option<&Measured<BSpline>>) -> String {
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
        let (name, circulation) = (v.name(), Some(v.exact.circulation_rad));
        let exact = Numbers { figures: &v.exact.figures, peaks: v.exact.peak_torque_nm.fields() };
        all.push((name.clone(), Engine::Exact, fields(problem, &name, Engine::Exact, circulation, Ok(exact))));
        let rapier = match &v.rapier {
            RapierOutcome::Report(r) => Ok(Numbers { figures: &r.figures, peaks: r.peak_torque_nm.fields() }),
            RapierOutcome::NoResult(x) => Err(x.run_time_s),
        };
        let raw = v.rapier.report().and_then(|r| r.figures.check.twist_deg_raw);
        let mut f = fields(problem, &name, Engine::Rapier, circulation, rapier);
        verified_fields(&mut f, reasoned, v.verification(), raw);
        all.push((name, Engine::Rapier, f));
    }
    if let Some(m) = whole {
        let name = m.name.to_string();
        let e = &m.exact;
        let figures = EngineFigures::exact(e);
        let exact = Numbers { figures: &figures, peaks: one_piece(e.peak()) };
        all.push((name.clone(), Engine::Exact, fields(problem, &name, Engine::Exact, None, Ok(exact))));
        if let Some(outcome) = &m.rapier {
            let finest = match outcome {
                RapierOutcome::Report(finest) => {
                    Ok((EngineFigures::rapier(finest.clone()), finest.run.peak_torque.max))
                }
                RapierOutcome::NoResult(x) => Err(x.run_time_s),
            };
            let raw = finest.as_ref().ok().and_then(|(figures, _)| figures.check.twist_deg_raw);
            let rapier = finest.as_ref().map(|(figures, max)| Numbers { figures, peaks: one_piece(*max) });
            let mut f = fields(problem, &name, Engine::Rapier, None, rapier.map_err(|t| *t));
            verified_fields(&mut f, reasoned, m.verification(), raw);
            all.push((name, Engine::Rapier, f));
        }
    }
    all.sort_by(|a, b| (&a.0, a.1).cmp(&(&b.0, b.1)));
    let width = header.len();
    let records = all.into_iter().map(|(_, _, mut f)| {
        f.resize(width, String::new());
        f
    });
    crate::exchange::table::csv_table(&header, records)
}

/// One engine's numbers of a trajectory: its figures and the seven peak fields
/// ([`PhasePeaks::CSV_HEADER`]).
struct Numbers<'a> {
    figures: &'a EngineFigures,
    peaks: [String; 7],
}

/// The peak fields of a trajectory of one piece (the whole optimum): `max_nm` alone.
fn one_piece(max: f64) -> [String; 7] {
    std::array::from_fn(|i| if i == 6 { format!("{max:.9}") } else { String::new() })
}

/// A row's fields up to its run time: `numbers`, or `Err(run time)` for rapier without a usable
/// run (no twist, swing, peaks or measurements: empty fields up to the run time).
fn fields(
    problem: &str,
    name: &str,
    engine: Engine,
    circulation: Option<f64>,
    numbers: Result<Numbers, f64>,
) -> Vec<String> {
    let opt = |x: Option<f64>, format: fn(f64) -> String| x.map_or(String::new(), format);
    let mut f =
        vec![problem.to_string(), name.to_string(), engine.to_string(), opt(circulation, |c| format!("{c:.12}"))];
    match numbers {
        Ok(Numbers { figures: r, peaks }) => {
            let tr = r.check.tracking_error_rad;
            let sci = |x: f64| format!("{x:.6e}");
            f.extend([format!("{:.9}", r.twist_deg), format!("{:.9}", r.swing_deg)]);
            f.extend(peaks);
            f.extend([
                format!("{:.3e}", r.momentum_max),
                opt(r.check.dt, sci),
                opt(tr.map(|t| t[0]), sci),
                opt(tr.map(|t| t[1]), sci),
                format!("{:.6}", r.run_time_s),
            ]);
        }
        Err(run_time_s) => {
            f.resize(REPORT_HEAD.len() + PhasePeaks::CSV_HEADER.split(',').count() + MEASURED.len(), String::new());
            f.push(format!("{run_time_s:.6}"));
        }
    }
    f
}

/// rapier's row after its run time: the verification's fields and the verdict in words (up to
/// the `reasoned` columns), then `twist_raw_deg` (`raw`, the finest run's twist) and
/// `max_extrapolated_nm`.
fn verified_fields(f: &mut Vec<String>, reasoned: usize, verification: Option<&Verification>, raw: Option<f64>) {
    if let Some(x) = verification {
        f.extend(x.fields());
        f.push(x.verdict.to_string());
    }
    f.resize(reasoned, String::new());
    let peak = verification.and_then(|x| x.quantity(Quantity::PeakTorque)).and_then(|c| c.value);
    f.extend([raw, peak].map(|x| x.map_or(String::new(), |x| format!("{x:.9}"))));
}
