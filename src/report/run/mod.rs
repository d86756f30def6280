//! `catflip run`: everything for one problem ([`crate::measure::run`] computes it), written to
//! `results/<name>/`.
//!
//! The audit, the exact engine on the problem's schedule, the peak-torque table (every library
//! profile, the QP optimum and the exact-dynamics refinement), the rapier verification of every
//! schedule in that table, the schedules as CSV, the plots and the animation, and a Markdown
//! report with a provenance header. On a two-motor cat other than the paper's, the audit and the
//! profile QP with its refinements are not run ([`PaperOnly`]), and the terminal and `report.md`
//! say so, one sentence each; the spherical joint and a release with spin are refused. Files are written into a scratch folder beside the target
//! and moved into place only when everything succeeded: a failed run leaves no half-written
//! results (and keeps the previous ones).

mod answer;
mod figures;
mod tables;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::engines::resolved::Resolved;
use crate::measure::run::{compute, ComputeError, PaperOnly, RunResults};
pub use crate::measure::timings::StageTime;
use crate::measure::timings::Stopwatch;
use crate::report::compare::compare;
use crate::report::export::{exporters, Shown, Views};
use crate::report::results_dir::Staging;
use crate::schedule::variant::WHOLE;
use tables::summary;

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// A file or folder could not be written.
    #[error("cannot write {path}")]
    Io {
        /// The path.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// A computation failed (the optimisers, the engines, the audit, the files).
    #[error(transparent)]
    Compute(#[from] ComputeError),
    /// A plot failed.
    #[error(transparent)]
    Plot(#[from] crate::report::plot::PlotError),
    /// A result could not be serialised.
    #[error("cannot serialise {0}")]
    Json(&'static str),
    /// A file of the run could not be rendered.
    #[error(transparent)]
    Export(#[from] crate::report::export::ExportError),
    /// The problem could not be written as TOML for the report's header.
    #[error("cannot write the problem as TOML for the report header")]
    Toml(#[from] toml::ser::Error),
    /// The results folder could not be staged or swapped in.
    #[error(transparent)]
    ResultsDir(#[from] crate::report::results_dir::ResultsDirError),
}

impl From<crate::exchange::ExchangeError> for RunError {
    fn from(e: crate::exchange::ExchangeError) -> RunError {
        RunError::Compute(e.into())
    }
}

impl From<crate::problem::ProblemError> for RunError {
    fn from(e: crate::problem::ProblemError) -> RunError {
        RunError::Compute(e.into())
    }
}

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunOutcome {
    /// The results folder.
    pub dir: PathBuf,
    /// Files written, relative to it.
    pub files: Vec<String>,
    /// What the command prints: for `run` the answer and one short table (the report's summary
    /// is in `report.md`), for `bench` the reach table.
    pub summary: String,
    /// How long each stage took (`run --timings`), in order of start; empty for `bench`.
    pub stages: Vec<StageTime>,
    /// The schedules whose rapier verification made no usable run (inconclusive, nothing to
    /// compare): `run` exits non-zero when there are any, as `compare --verify` does.
    pub without_result: usize,
    /// The whole computation's wall time, s.
    pub total_s: f64,
}

struct Writer {
    /// Where files are written (the scratch folder).
    dir: PathBuf,
    /// The folder the user asked for, named in errors.
    shown: PathBuf,
    files: Vec<String>,
}

impl Writer {
    fn put(&mut self, name: &str, contents: &str) -> Result<(), RunError> {
        let path = self.dir.join(name);
        let shown = self.shown.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|source| io(shown.parent().unwrap_or(&shown), source))?;
        }
        std::fs::write(&path, contents).map_err(|source| io(&shown, source))?;
        self.files.push(name.to_string());
        Ok(())
    }

    fn json(&mut self, name: &str, value: &impl serde::Serialize) -> Result<(), RunError> {
        let text = serde_json::to_string_pretty(value).map_err(|_| RunError::Json("a JSON result"))?;
        self.put(name, &(text + "\n"))
    }

    fn record(&mut self, written: Vec<PathBuf>) {
        self.files.extend(written.iter().map(|p| p.strip_prefix(&self.dir).unwrap_or(p).display().to_string()));
    }
}

fn io(path: &Path, source: std::io::Error) -> RunError {
    RunError::Io { path: path.display().to_string(), source }
}

/// The stages of a run ([`StageTime`]) as a plain-text table for the terminal: start, end and
/// duration of each, and the run's total.
pub fn timings_table(stages: &[StageTime], total_s: f64) -> String {
    let width = stages.iter().map(|s| s.name.chars().count()).max().unwrap_or(0).max(5);
    let mut out = format!("{:<width$}  {:>7}  {:>7}  {:>7}\n", "stage", "start s", "end s", "wall s");
    for s in stages {
        out.push_str(&format!(
            "{:<width$}  {:>7.3}  {:>7.3}  {:>7.3}\n",
            s.name,
            s.start_s,
            s.start_s + s.wall_s,
            s.wall_s
        ));
    }
    out.push_str(&format!("{:<width$}  {:>7.3}  {:>7.3}  {:>7.3}\n", "run", 0.0, total_s, total_s));
    out
}

/// Runs everything for the resolved problem and writes `out_root/<name>/`. `command` is the
/// command line that regenerates it, for the report's header.
pub fn run(r: &Resolved, command: &str, out_root: &Path) -> Result<RunOutcome, RunError> {
    run_with(r, command, out_root, &crate::exchange::ExportOptions::default())
}

/// Whether `run` takes `problem`: a two-motor cat (not the spherical joint) released without spin.
/// The CLI asks it of every problem before the first is run, so that a bad one writes nothing.
pub fn runnable(problem: &crate::problem::Problem) -> Result<(), crate::problem::ProblemError> {
    problem.require_no_spin("run (its optimisers and retimings)")?;
    problem.require_two_motor_joint("run (its optimisers, rapier verifications and exports)")?;
    problem.validate_robust_draws()
}

/// [`run`] with the schedule files sampled as `export` says (e.g. a uniform `--rate`).
pub fn run_with(
    r: &Resolved,
    command: &str,
    out_root: &Path,
    export: &crate::exchange::ExportOptions,
) -> Result<RunOutcome, RunError> {
    runnable(&r.problem)?;
    let clock = Stopwatch::start();
    let (mut outcome, without_result) =
        atomically(out_root, &r.problem.name, |w| produce(r, command, export, w, &clock))?;
    (outcome.stages, outcome.total_s) = clock.finish();
    outcome.without_result = without_result;
    Ok(outcome)
}

/// Runs `catflip bench` on the resolved problem (rapier at
/// [`crate::measure::bench::RAPIER_STEPS`]), writes `out_root/bench/` and returns the report
/// beside what was written.
pub fn run_bench(
    r: &Resolved,
    command: &str,
    out_root: &Path,
) -> Result<(RunOutcome, crate::measure::bench::BenchReport), RunError> {
    atomically(out_root, "bench", |w| {
        let report =
            crate::measure::bench::bench(r, &crate::measure::bench::RAPIER_STEPS).map_err(ComputeError::from)?;
        w.put("bench.csv", &report.to_csv())?;
        w.json("bench.json", &report)?;
        let plots = w.dir.join("plots");
        std::fs::create_dir_all(&plots).map_err(|e| io(&w.shown.join("plots"), e))?;
        w.record(report.plots(&plots)?);
        let settings = toml::to_string(&r.problem)?;
        let mut md = crate::report::provenance::header("catflip benchmark: run time against error", command, &settings);
        md.push_str(&report.to_markdown());
        w.put("bench.md", &md)?;
        Ok((report.reach_table(), report))
    })
}

/// The robustness verdict in one sentence.
fn robust_line(c: &crate::robust::Robustness) -> String {
    format!("Robustness ({}): the whole optimum {}.", c.engine.describe(), c.verdict)
}

/// Writes into a scratch folder beside `final_dir` and moves it into place only on success;
/// `body` returns what to print and what else it computed.
fn atomically<T>(
    out_root: &Path,
    name: &str,
    body: impl FnOnce(&mut Writer) -> Result<(String, T), RunError>,
) -> Result<(RunOutcome, T), RunError> {
    let start = std::time::Instant::now();
    let staging = Staging::begin(out_root, name)?;
    let mut w = Writer { dir: staging.dir().to_path_buf(), shown: staging.target().to_path_buf(), files: Vec::new() };
    // On an error the staging folder is dropped, and with it the scratch folder: the previous
    // results stay as they were.
    let (summary, value) = body(&mut w).map_err(|e| match e {
        RunError::Plot(p) => RunError::Plot(p.shown_as(|path| staging.shown(&path))),
        other => other,
    })?;
    let dir = staging.commit()?;
    let total_s = start.elapsed().as_secs_f64();
    Ok((RunOutcome { dir, files: w.files, summary, stages: Vec::new(), total_s, without_result: 0 }, value))
}

fn produce(
    r: &Resolved,
    command: &str,
    export: &crate::exchange::ExportOptions,
    w: &mut Writer,
    clock: &Stopwatch,
) -> Result<(String, usize), RunError> {
    let problem = &r.problem;
    let settings = toml::to_string(problem)?;
    let plots = w.dir.join("plots");
    std::fs::create_dir_all(&plots).map_err(|e| io(&w.shown.join("plots"), e))?;
    // The whole optimum's animation is drawn beside its verification, as soon as it exists.
    let (results, animation) = compute(r, export, clock, |m| figures::animation_of(r, &plots, WHOLE, &m.trajectory))?;
    let RunResults { audit, opt, whole, retimed, verified, robustness, files } = results;
    let without_result = verified.iter().filter_map(|m| m.verification()).filter(|v| !v.has_result()).count()
        + usize::from(whole.verification().is_some_and(|v| !v.has_result()));
    let verified =
        verified.iter().map(|m| Shown::new(r, m)).collect::<Result<Vec<_>, _>>().map_err(ComputeError::from)?;
    // The views every format renders: the peak-torque table holds every schedule measured once.
    let opt = opt.as_ref().map(|o| o.to_json(&r.model().cat().rear));
    let extra: Vec<_> = opt
        .iter()
        .flat_map(|opt| {
            [&opt.qp_optimum, &opt.refined_optimum]
                .into_iter()
                .flatten()
                .chain(opt.all_phases.as_ref().map(|a| &a.optimum))
        })
        .map(|o| o.evaluation.clone())
        .collect();
    // The parts that model the paper's cat only, said plainly when they are not run.
    let not_run: Vec<String> =
        [PaperOnly::Audit, PaperOnly::ProfileQp].into_iter().filter_map(|p| p.not_run(problem)).collect();
    let table = compare(r, &extra);
    let whole_row = crate::report::whole::compare_row(&whole);
    let robust = robustness.map(|c| crate::robust::RobustReport { checks: vec![c], command: command.to_string() });
    let views = Views {
        problem,
        audit: audit.as_ref(),
        optimize: opt.as_ref(),
        whole: &whole,
        retimed: &retimed,
        table: &table,
        whole_row: whole_row.as_ref(),
        verified: &verified,
        robust: robust.as_ref(),
    };
    for exporter in exporters() {
        for (name, contents) in exporter.files(&views)? {
            w.put(&name, &contents)?;
        }
    }
    if let Some(report) = &robust {
        for plot in [report.histogram_plot(), report.distribution_plot()] {
            w.record(crate::report::plot::line_plot(&plots, &plot)?);
        }
    }
    // 4–5. Schedules for robots and other simulators (CSV + JSON sidecar) and the model files
    // (computed beside the verifications), the plots and the animation: produced in parallel,
    // recorded in this order.
    let (figures, animation) = rayon::join(
        || clock.time("plots", || figures::plots(r, &plots, &verified, &whole)),
        || {
            animation.unwrap_or_else(|| {
                clock.time("animate the fallback", || figures::fallback_animation(r, &plots, &verified))
            })
        },
    );
    for (name, contents) in files {
        w.put(&name, &contents)?;
    }
    w.record(figures?);
    w.record(animation?);
    // 6. The report.
    let optimum = crate::report::whole::summary_lines(&whole, &retimed);
    let mut summary = summary(r, &views, &not_run, &optimum);
    if let Some(c) = robust.as_ref().and_then(|report| report.checks.first()) {
        let _ = writeln!(
            summary,
            "\n{} The trials, the worst ones and the plots: [`robust.md`](robust.md). Tracked by motors in rapier, with attitude feedback and landing: `catflip robust` with `--schedule` this folder's `schedules/{WHOLE}.csv` (README, *Will it land on its feet, and how often?*).",
            robust_line(c)
        );
        if problem.robust.engine.rapier() {
            let _ = writeln!(
                summary,
                "\n`run` checks the exact engine only; this problem's `robust.engine` (rapier, its controller and landing) is `catflip robust`'s."
            );
        }
    }
    let mut report =
        crate::report::provenance::header(&format!("catflip results: {}", problem.name), command, &settings);
    report.push_str(&summary);
    report.push_str("\n## Files\n\n");
    for f in &w.files {
        let _ = writeln!(report, "- [`{f}`]({f})");
    }
    w.put("report.md", &report)?;
    let own = crate::schedule::variant::Origin::Library(problem.manoeuvre.profile);
    let audited = PaperOnly::Audit.not_run(problem).is_none();
    let best = r.best_library().map(|(_, m)| &m.name);
    let mut answer = answer::answer(own, best, &verified, &whole, &not_run, audited, &w.shown.display().to_string());
    if let Some(c) = robust.as_ref().and_then(|report| report.checks.first()) {
        answer.insert_str(answer.find('\n').map_or(0, |k| k + 1), &format!("{}\n", robust_line(c)));
    }
    Ok((answer, without_result))
}
