//! The commands, each the library call the CLI makes for it (`src/main.rs`), its report returned
//! as JSON text with the warnings the CLI would print beside it.

use std::path::PathBuf;
use std::sync::Arc;

use catflip::engines::Engine;
use catflip::exchange::{ExportOptions, ImportedSchedule};
use catflip::schedule::Trajectory;
use pyo3::prelude::*;

use crate::problem::Problem;
use crate::{message, refuse, worker, CatflipError};

/// A report as JSON text, and the warnings that go with it.
type Report = (String, Vec<String>);
/// A report, its warnings, and schedule files `(name, csv, sidecar_json)`.
type WithFiles = (String, Vec<String>, Vec<(String, String, String)>);
/// A report, its warnings, and maybe one schedule file `(csv, sidecar_json)`.
type WithFile = (String, Vec<String>, Option<(String, String)>);

/// An error of the library as a [`CatflipError`] with the CLI's message.
fn refuse_any(e: anyhow::Error) -> PyErr {
    CatflipError::new_err(message(e.as_ref()))
}

fn json(value: &impl serde::Serialize) -> anyhow::Result<String> {
    Ok(serde_json::to_string(value)?)
}

fn engine(name: &str) -> PyResult<Engine> {
    match name {
        "exact" => Ok(Engine::Exact),
        "rapier" => Ok(Engine::Rapier),
        other => Err(CatflipError::new_err(format!(
            "engine {other:?}: not an engine (possible values: \"exact\", \"rapier\")"
        ))),
    }
}

fn export(steps_per_piece: usize, rate_hz: Option<f64>) -> ExportOptions {
    ExportOptions { rate_hz, steps_per_piece }
}

/// Runs `f` on a worker thread (GIL released, interruptible), its error as a [`CatflipError`].
fn run<T: Send + 'static>(py: Python<'_>, f: impl FnOnce() -> anyhow::Result<T> + Send + 'static) -> PyResult<T> {
    worker::run(py, f)?.map_err(refuse_any)
}

/// `catflip simulate PROBLEM --engine ENGINE --json`: the problem's schedule through an engine.
#[pyfunction]
pub fn simulate(py: Python<'_>, problem: &Problem, engine_name: &str) -> PyResult<Report> {
    let engine = engine(engine_name)?;
    let inner = problem.inner.clone();
    run(py, move || {
        let r = inner.resolved()?;
        let report = catflip::report::simulate::simulate(&r, engine)?;
        Ok((json(&report)?, r.warnings()))
    })
}

/// The problem's schedule as the file `catflip run` exports (`schedules/problem.csv` and its
/// sidecar): `(csv, sidecar_json)`.
#[pyfunction]
pub fn schedule_file(
    py: Python<'_>,
    problem: &Problem,
    steps_per_piece: usize,
    rate_hz: Option<f64>,
) -> PyResult<(String, String)> {
    let inner = problem.inner.clone();
    run(py, move || {
        let r = inner.resolved()?;
        let own = r.own().clone().named(catflip::schedule::variant::ScheduleName::Problem);
        let file = catflip::exchange::write_schedule(&r.problem, &own, &export(steps_per_piece, rate_hz))?;
        let sidecar = file.sidecar_json()?;
        Ok((file.csv, sidecar))
    })
}

/// `catflip compare PROBLEM [--verify] --json`: every library profile side by side; with
/// `verify`, each verified in rapier (`{"table", "rapier"}`).
#[pyfunction]
#[pyo3(signature = (problem, verify = false))]
pub fn compare(py: Python<'_>, problem: &Problem, verify: bool) -> PyResult<Report> {
    let inner = problem.inner.clone();
    run(py, move || {
        let r = inner.resolved()?;
        let table = catflip::report::compare::compare(&r, &[]);
        if !verify {
            return Ok((json(&table)?, r.warnings()));
        }
        let verified = catflip::measure::run::verify_library(&r, &catflip::measure::timings::Stopwatch::start())?;
        let (_, value) = catflip::report::export::with_verification(&r, &table, &verified)?;
        Ok((json(&value)?, r.warnings()))
    })
}

/// `catflip compare-models PROBLEM [--verify] --json`: the whole optimum of each cat model on the
/// problem's cat and fall, side by side.
#[pyfunction]
#[pyo3(signature = (problem, verify = false))]
pub fn compare_models(py: Python<'_>, problem: &Problem, verify: bool) -> PyResult<Report> {
    let inner = problem.inner.clone();
    run(py, move || {
        let p = &inner.problem;
        // The call that made it (the CLI's field holds its command line; a problem here may
        // come from a dict or a string, with no file to name).
        let verified = if verify { ", verify=True" } else { "" };
        let command = format!("catflip.compare_models(problem {:?}{verified}) (Python)", p.name);
        let comparison = catflip::compare_models::compare_models(p, verify, &command)?;
        Ok((json(&comparison)?, p.warnings()))
    })
}

/// `catflip optimize PROBLEM --json`: the profile QP, its exact refinement and the retiming of
/// every phase; with `series`, each optimum's schedule file `(name, csv, sidecar_json)` as well.
#[pyfunction]
pub fn optimize(
    py: Python<'_>,
    problem: &Problem,
    series: bool,
    steps_per_piece: usize,
    rate_hz: Option<f64>,
) -> PyResult<WithFiles> {
    let inner = problem.inner.clone();
    run(py, move || {
        inner.problem.require_no_spin("optimize (the profile QP and the refinements)")?;
        let r = inner.resolved()?;
        let report = catflip::optimize::optimize(&r)?;
        let mut files = Vec::new();
        if series {
            for o in report.optima() {
                let file =
                    catflip::exchange::write_schedule(&r.problem, &o.measured, &export(steps_per_piece, rate_hz))?;
                let sidecar = file.sidecar_json()?;
                files.push((o.measured.name.to_string(), file.csv, sidecar));
            }
        }
        Ok((json(&report.to_json(&r.model().cat().rear))?, r.warnings(), files))
    })
}

/// `catflip optimize PROBLEM --whole --json`: the whole-manoeuvre optimum; with `series`, its
/// schedule file `(csv, sidecar_json)` (`whole-optimum.csv` and `.json` of `catflip run`) when
/// there is an optimum.
#[pyfunction]
pub fn optimize_whole(
    py: Python<'_>,
    problem: &Problem,
    series: bool,
    steps_per_piece: usize,
    rate_hz: Option<f64>,
) -> PyResult<WithFile> {
    let inner = problem.inner.clone();
    run(py, move || {
        // With spin the optimum is planned; its schedule file is refused (naming
        // drop.angular_momentum) before the solve, as `catflip run` refuses it.
        if series {
            inner.problem.require_no_spin("a schedule file (its orientation and torque columns)")?;
        }
        let r = inner.resolved()?;
        let report = catflip::measure::whole::whole(&r)?;
        let file = match (series, report.measured.as_ref()) {
            (true, Some(m)) => {
                Some(catflip::exchange::write_whole_optimum(&r.problem, m, &export(steps_per_piece, rate_hz))?)
            }
            _ => None,
        };
        let file = file.map(|f| f.sidecar_json().map(|sidecar| (f.csv, sidecar))).transpose()?;
        Ok((json(&report)?, r.warnings(), file))
    })
}

/// A schedule read from elsewhere (a CSV file or arrays), ready to evaluate.
#[pyclass(frozen, module = "catflip._catflip")]
pub struct Schedule {
    inner: Arc<ImportedSchedule>,
}

#[pymethods]
impl Schedule {
    /// Where it came from (the file, or the name given to arrays).
    #[getter]
    fn origin(&self) -> String {
        self.inner.path.clone()
    }

    /// Data rows read.
    #[getter]
    fn rows(&self) -> usize {
        self.inner.rows
    }

    /// Its pieces (smooth stretches between repeated times).
    #[getter]
    fn pieces(&self) -> usize {
        self.inner.pieces.len()
    }

    /// Its duration, s.
    #[getter]
    fn duration(&self) -> f64 {
        self.inner.total_duration()
    }

    /// How its rows are interpolated, as the reports name it.
    #[getter]
    fn interpolation(&self) -> PyResult<String> {
        let name = serde_json::to_value(self.inner.interpolation).map_err(refuse)?;
        Ok(name.as_str().unwrap_or_default().to_string())
    }

    fn __repr__(&self) -> String {
        format!("<catflip.Schedule {:?}: {} rows, {} s>", self.inner.path, self.inner.rows, self.inner.total_duration())
    }
}

/// Reads a schedule CSV (`catflip::exchange::read_schedule`, as `simulate --schedule FILE.csv`).
#[pyfunction]
pub fn read_schedule(py: Python<'_>, path: PathBuf) -> PyResult<Schedule> {
    py.detach(|| catflip::exchange::read_schedule(&path)).map(|s| Schedule { inner: Arc::new(s) }).map_err(refuse)
}

/// A schedule from named columns (`catflip::exchange::schedule_from_columns`).
#[pyfunction]
pub fn schedule_from_columns(
    py: Python<'_>,
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
    origin: String,
) -> PyResult<Schedule> {
    py.detach(|| {
        let named: Vec<(&str, &[f64])> =
            names.iter().map(String::as_str).zip(columns.iter().map(Vec::as_slice)).collect();
        catflip::exchange::schedule_from_columns(&named, &origin)
    })
    .map(|s| Schedule { inner: Arc::new(s) })
    .map_err(refuse)
}

/// `catflip simulate PROBLEM --schedule FILE.csv --engine ENGINE --json`: an imported schedule
/// on the problem's cat with its settings; the warnings are the import's checks.
#[pyfunction]
pub fn simulate_schedule(
    py: Python<'_>,
    problem: &Problem,
    schedule: &Schedule,
    engine_name: &str,
) -> PyResult<Report> {
    let engine = engine(engine_name)?;
    let (inner, imported) = (problem.inner.clone(), schedule.inner.clone());
    run(py, move || {
        let problem = &inner.problem;
        let report = catflip::report::import::simulate_import(problem, (*imported).clone(), engine)?;
        Ok((json(&report)?, report.warnings.clone()))
    })
}

/// The model files of the problem's cat, `[(file name, contents)]`: `model.urdf` and `model.xml`
/// (MJCF), as `catflip run` writes them beside the schedules; on the no-twist joint a ball joint
/// in the MJCF and pyBullet's non-standard spherical joint in the URDF.
#[pyfunction]
pub fn model_files(problem: &Problem) -> PyResult<Vec<(String, String)>> {
    catflip::exchange::model_files(&problem.inner.problem).map_err(refuse)
}

/// `catflip sweep SWEEP.toml`: the tidy table (the `sweep.csv` text) of every case; with `out`,
/// the sweep's whole output folder written to `<out>/<name>/` too, and what was written as JSON.
#[pyfunction]
pub fn sweep(py: Python<'_>, path: PathBuf, out: Option<PathBuf>) -> PyResult<(String, Option<String>, Vec<String>)> {
    run(py, move || {
        let sweep = catflip::sweep::Sweep::load(&path)?;
        let records = catflip::sweep::evaluate(&sweep, 0..sweep.case_count(), false);
        let csv = catflip::sweep::table::to_csv(&sweep, &records)?;
        let written = match &out {
            Some(out) => {
                let command = format!("cargo run --release -- sweep {}", path.display());
                let outcome = catflip::sweep::output::write_results(&sweep, &records, &command, out)?;
                Some(json(&outcome)?)
            }
            None => None,
        };
        // The cases' warnings, as the CLI says them: how many cases, and one case's in full (the
        // records carry every case's; `sweep.md` lists them all under "Warnings").
        let mut warned: Vec<(usize, &str)> =
            records.iter().filter(|r| !r.warnings.is_empty()).map(|r| (r.case, r.warnings.as_str())).collect();
        warned.dedup_by_key(|w| w.0);
        let warnings = match warned.first() {
            None => Vec::new(),
            Some((case, first)) => vec![format!(
                "sweep {}: {} of its {} cases carry warnings (the problem file's with the case's values, and flips that end swung past 45°; each record's \"warnings\" holds its own), case {case}'s: {first}",
                sweep.name,
                warned.len(),
                sweep.case_count(),
            )],
        };
        Ok((csv, written, warnings))
    })
}
