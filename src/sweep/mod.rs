//! `catflip sweep`: a grid of problems through the exact engine, with tidy CSV, summary tables
//! and plots over the swept axes (DESIGN.md §7, §8).
//!
//! The pipeline: the sweep file ([`spec`]) → cases, each the base problem plus `--set`-style
//! overrides ([`cases`]) → per case the flip with the paper's circulation, the calibrated
//! circulation and peak torques ([`mod@evaluate`]), optionally the certified retiming and the
//! whole-manoeuvre optimum ([`optimum`]) and rapier's verdict on every row ([`verify`]), in
//! parallel with `rayon` → the table ([`table`]),
//! the Markdown summary ([`summary`]) and the plots ([`plots`], [`heatmap`]) written atomically
//! by [`output`]. [`shard`] splits a sweep into parts for a cluster's array job and merges them.
//!
//! Determinism: every case is evaluated on its own, by the same sequential code whatever thread
//! runs it, and results are collected in case order; so the output is byte-identical whatever the
//! thread count, and a merge of shards equals the single run (tests in `tests/sweep.rs`).

pub mod cases;
pub mod evaluate;
pub mod grid;
pub mod heatmap;
pub mod optimum;
pub mod output;
pub mod plots;
pub mod row;
pub mod schedules;
pub mod shard;
pub mod spec;
pub mod summary;
pub mod table;
pub mod verify;

use std::io::IsTerminal;
use std::ops::Range;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

pub use evaluate::{evaluate_case, CaseOutcome};
pub use output::SweepOutcome;
pub use row::Status;
pub use shard::Shard;
pub use spec::{Compute, Sweep};
pub use table::Record;

/// Why a sweep could not run or be written.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The sweep file is unusable.
    #[error(transparent)]
    Spec(#[from] spec::SpecError),
    /// A file or folder could not be read or written.
    #[error("cannot {action} {path}")]
    Io {
        /// What was being done: `read` or `write`.
        action: &'static str,
        /// The path.
        path: String,
        /// What the OS said.
        source: std::io::Error,
    },
    /// The table could not be written or read.
    #[error(transparent)]
    Table(#[from] table::TableError),
    /// A plot failed.
    #[error(transparent)]
    Plot(#[from] crate::report::plot::PlotError),
    /// `--shard K/N` with more shards than cases.
    #[error("--shard {k}/{n}: the sweep has {cases} cases, so N can be at most {cases} (at least one case per shard)")]
    TooManyShards {
        /// The shard asked for.
        k: usize,
        /// The shard count asked for.
        n: usize,
        /// The sweep's cases.
        cases: usize,
    },
    /// A results folder could not be staged or swapped in.
    #[error(transparent)]
    ResultsDir(#[from] crate::report::results_dir::ResultsDirError),
    /// Parts cannot be merged.
    #[error("cannot merge: {0}")]
    Merge(String),
    /// A manifest could not be serialised.
    #[error("cannot serialise {0}")]
    Json(String),
}

/// How to run a sweep.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// Results root: output goes to `<out>/<name>/` (or `<out>/<name>.part-K-of-N/`).
    pub out: PathBuf,
    /// Run one slice only.
    pub shard: Option<Shard>,
    /// Hide the progress bar (it is hidden anyway when stderr is not a terminal).
    pub quiet: bool,
    /// The command line that regenerates the output, for the report's header.
    pub command: String,
}

/// Evaluates the cases `range` of a sweep, in parallel on the current rayon pool, and returns
/// their records in case order. `progress` draws a bar on stderr when it is a terminal.
pub fn evaluate(sweep: &Sweep, range: Range<usize>, progress: bool) -> Vec<Record> {
    let bar = if progress && std::io::stderr().is_terminal() {
        let bar = indicatif::ProgressBar::new(range.len() as u64);
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{prefix} [{elapsed_precise}] {wide_bar} {pos}/{len} cases, {eta} left",
        ) {
            bar.set_style(style);
        }
        bar.set_prefix(format!("sweep {}", sweep.name));
        bar
    } else {
        indicatif::ProgressBar::hidden()
    };
    let out: Vec<Vec<Record>> = range
        .into_par_iter()
        .map(|i| {
            let case = cases::case(sweep, i);
            let outcome = match case.problem(sweep) {
                Ok(problem) => evaluate_case(&problem, &sweep.compute),
                Err(reason) => CaseOutcome::refused(&sweep.compute, &reason),
            };
            bar.inc(1);
            table::records(sweep, i, &outcome)
        })
        .collect();
    bar.finish_and_clear();
    out.into_iter().flatten().collect()
}

/// Runs a sweep (or one shard of it) and writes its output.
pub fn run(sweep: &Sweep, options: &SweepOptions) -> Result<SweepOutcome, SweepError> {
    let total = sweep.case_count();
    match options.shard {
        None => {
            // A bad `--out` is said before the cases run, not after.
            crate::report::results_dir::check_target(&options.out, &sweep.name)?;
            let records = evaluate(sweep, 0..total, !options.quiet);
            output::write_results(sweep, &records, &options.command, &options.out)
        }
        Some(shard) => {
            shard.check(total)?;
            crate::report::results_dir::check_target(&options.out, &shard.folder(&sweep.name))?;
            let range = shard.range(total);
            let records = evaluate(sweep, range.clone(), !options.quiet);
            output::write_part(sweep, shard, range, &records, &options.out)
        }
    }
}

/// Reads a sweep file and runs it.
pub fn run_file(path: &Path, options: &SweepOptions) -> Result<SweepOutcome, SweepError> {
    run(&Sweep::load(path)?, options)
}

/// Merges part folders into `<out>/<name>/`, the output one run of the whole sweep writes.
pub fn merge(parts: &[PathBuf], out: &Path, command: &str) -> Result<SweepOutcome, SweepError> {
    let (sweep, records) = shard::read_parts(parts)?;
    output::write_results(&sweep, &records, command, out)
}
