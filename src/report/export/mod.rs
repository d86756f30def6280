//! The one seam between a run's results and its files (hyperfine's `export/`): an [`Exporter`]
//! per format turns the rendered views of a run ([`Views`]) into `(file name, contents)`, one
//! file of the format per table. [`markdown`] writes the reports people read, [`csv`] the tidy
//! tables scripts read (one row per problem × schedule × engine), [`json`] every result as data.
//! The plots, the animation, the schedule files and `report.md` (which lists every file) are
//! written beside them by [`crate::report::run`].

pub mod csv;
pub mod json;
pub mod markdown;

use crate::engines::measured::Measured;
use crate::engines::rapier::{RapierError, Verification};
use crate::engines::resolved::Resolved;
use crate::measure::audit::Audit;
use crate::measure::retime::RetimeRow;
use crate::measure::whole::WholeReport;
use crate::problem::Problem;
use crate::report::compare::{CompareRow, CompareTable};
use crate::report::optimize::OptimizeJson;
use crate::report::simulate::{RapierOutcome, SimulationReport};
use crate::robust::RobustReport;
use crate::schedule::Schedule;

/// Why a file could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// A result could not be serialised as JSON.
    #[error("cannot serialise {what} as JSON")]
    Json {
        /// The file.
        what: String,
        /// serde's error.
        source: serde_json::Error,
    },
}

/// The reports of one measured and verified schedule: the exact engine's, and rapier's or its
/// verification alone when it made no usable run.
pub struct Shown<'a> {
    /// The schedule, measured and verified.
    pub measured: &'a Measured<Schedule>,
    /// The exact engine's report.
    pub exact: SimulationReport,
    /// rapier's report, or its verification alone when it made no usable run.
    pub rapier: RapierOutcome<SimulationReport>,
}

impl<'a> Shown<'a> {
    /// The reports of `m`, one of `r`'s schedules, verified ([`crate::engines::measured::Measured::verify`]).
    pub fn new(r: &Resolved, m: &'a Measured<Schedule>) -> Result<Shown<'a>, RapierError> {
        let exact = SimulationReport::exact(r, m);
        let rapier = SimulationReport::rapier(m, &exact)?;
        Ok(Shown { measured: m, exact, rapier })
    }

    /// The schedule's name.
    pub fn name(&self) -> String {
        self.measured.name.to_string()
    }

    /// rapier's verification of the schedule, with or without a result.
    pub fn verification(&self) -> Option<&Verification> {
        self.measured.verification()
    }
}

/// `catflip compare --verify`: the table, then rapier's verification of its schedules
/// (`measured`, every library profile measured and verified, [`crate::measure::run::verify_library`])
/// as `verification.md` writes it and a line of verdicts; and as JSON, `{"table", "rapier"}` with
/// `rapier` the entries of `simulate_rapier.json`.
pub fn with_verification(
    r: &Resolved,
    table: &CompareTable,
    measured: &[Measured<Schedule>],
) -> Result<(String, serde_json::Value), RapierError> {
    let shown = measured.iter().map(|m| Shown::new(r, m)).collect::<Result<Vec<_>, _>>()?;
    let verdicts = Verification::verdicts_line(shown.iter().map(|v| (v.name(), v.verification())));
    let markdown = format!(
        "{}\n{}\nVerdicts: {verdicts}.\n",
        table.to_markdown(),
        markdown::verification_markdown(&r.problem, &shown)
    );
    let json = serde_json::json!({ "table": table, "rapier": shown.iter().map(json::rapier_json).collect::<Vec<_>>() });
    Ok((markdown, json))
}

/// A run's results as its exporters read them: every table rendered once.
pub struct Views<'a> {
    /// The problem.
    pub problem: &'a Problem,
    /// The paper's numbers; `None` on a cat other than the paper's
    /// ([`crate::measure::run::PaperOnly::Audit`]: no file is written).
    pub audit: Option<&'a Audit>,
    /// The profile QP and its refinements; `None` on a cat other than the paper's
    /// ([`crate::measure::run::PaperOnly::ProfileQp`]: no file is written).
    pub optimize: Option<&'a OptimizeJson<'a>>,
    /// The whole-manoeuvre optimum, measured and verified.
    pub whole: &'a WholeReport,
    /// The certified retimings.
    pub retimed: &'a [RetimeRow],
    /// The peak-torque table (library and optimised schedules).
    pub table: &'a CompareTable,
    /// The whole optimum's row of the peak-torque table, when it exists.
    pub whole_row: Option<&'a CompareRow>,
    /// Every schedule of the table, measured and verified, with its reports.
    pub verified: &'a [Shown<'a>],
    /// The whole optimum's robustness, when it exists.
    pub robust: Option<&'a RobustReport>,
}

/// Files as `(name in the results folder, contents)`.
pub type Files = Vec<(String, String)>;

/// One format's files of a run.
pub trait Exporter {
    /// The files of this format for the run's `views`.
    fn files(&self, views: &Views) -> Result<Files, ExportError>;
}

/// Every format, in the order their files are written: Markdown, CSV, JSON.
pub fn exporters() -> [&'static dyn Exporter; 3] {
    [&markdown::Markdown, &csv::Csv, &json::Json]
}
