//! The JSON files of a run: every result as data, the same numbers the tables show. They hold
//! results only: the command that made them is in the Markdown, and wall-clock times are the
//! machine's (`*_time_s`, `seconds`).

use super::{ExportError, Shown};
use super::{Exporter, Files, Views};
use crate::engines::rapier::{Status, Verification};
use crate::engines::Engine;
use crate::report::simulate::{RapierOutcome, SimulationReport};
use crate::robust::RobustReport;

/// The JSON exporter.
pub struct Json;

/// `value`, the file `name`, as pretty JSON with a final newline.
fn file(name: &str, value: &impl serde::Serialize) -> Result<(String, String), ExportError> {
    let text =
        serde_json::to_string_pretty(value).map_err(|source| ExportError::Json { what: name.to_string(), source })?;
    Ok((name.to_string(), text + "\n"))
}

impl Exporter for Json {
    fn files(&self, v: &Views) -> Result<Files, ExportError> {
        let mut files: Files = v.audit.map(|a| file("audit.json", a)).transpose()?.into_iter().collect();
        files.extend(v.optimize.map(|o| file("optimize.json", o)).transpose()?);
        files.extend([
            file("whole.json", v.whole)?,
            file("retime.json", &v.retimed)?,
            file("simulate_exact.json", &v.verified.iter().map(|s| &s.exact).collect::<Vec<_>>())?,
            file("simulate_rapier.json", &v.verified.iter().map(rapier_json).collect::<Vec<_>>())?,
        ]);
        if let Some(verification) = v.whole.verification() {
            files.push(file("verification_whole.json", verification)?);
        }
        if let Some(r) = v.robust {
            files.push(file("robust.json", &RobustReport { command: String::new(), ..r.clone() })?);
        }
        Ok(files)
    }
}

/// The entry of `simulate_rapier.json` of one schedule.
pub fn rapier_json<'a>(s: &'a Shown<'a>) -> RapierJson<'a> {
    match &s.rapier {
        RapierOutcome::Report(r) => RapierJson::Report(r),
        RapierOutcome::NoResult(v) => RapierJson::NoResult {
            problem: &s.exact.problem,
            engine: Engine::Rapier,
            profile: &s.exact.profile,
            bend_path: s.exact.bend_path,
            circulation_rad: s.exact.circulation_rad,
            twist_deg: None,
            swing_deg: None,
            peak_torque_nm: None,
            verdict: v.status,
            reason: v.verdict.to_string(),
            verification: v,
        },
    }
}

/// An entry of `simulate_rapier.json`: rapier's report, or, when rapier has no result, the
/// schedule's identity, `null` numbers, the verdict (`inconclusive`) and why.
#[derive(serde::Serialize)]
#[serde(untagged)]
pub enum RapierJson<'a> {
    /// rapier's report.
    Report(&'a SimulationReport),
    /// No usable run: the schedule's identity, the verdict and why.
    NoResult {
        /// Problem name.
        problem: &'a str,
        /// Always rapier.
        engine: Engine,
        /// The schedule's profile.
        profile: &'a str,
        /// The bend path.
        bend_path: crate::problem::BendPath,
        /// Circulation, rad.
        circulation_rad: f64,
        /// No twist (`null`).
        twist_deg: Option<f64>,
        /// No swing (`null`).
        swing_deg: Option<f64>,
        /// No peak torque (`null`).
        peak_torque_nm: Option<f64>,
        /// The verdict (`inconclusive`).
        verdict: Status,
        /// The verdict in words.
        reason: String,
        /// The verification behind it.
        verification: &'a Verification,
    },
}
