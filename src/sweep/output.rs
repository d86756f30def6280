//! Writing a sweep's output folder, atomically, through the same [`Staging`] as `catflip run`
//! ([`crate::report::results_dir`]): everything goes into a scratch folder beside the target,
//! which replaces the target only once complete, so a failed sweep leaves the previous results in
//! place, and a killed one leaves hidden folders the next sweep into `--out` removes.
//!
//! `<out>/<name>/` holds `sweep.csv` (the tidy table, [`super::table`]), `sweep.md` (provenance
//! header and summary tables, [`super::summary`]), `plots/` (PNG + SVG, [`super::plots`]) and
//! `sweep.json` (the counts: cases, rows, rows per status). A shard writes `<out>/<name>.part-K-of-N/` with `part.json` and
//! `cases.csv` instead ([`super::shard`]).

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::report::results_dir::Staging;

use super::shard::{Manifest, Shard, CASES, MANIFEST};
use super::spec::Sweep;
use super::table::{to_csv, Record};
use super::SweepError;

/// What a sweep wrote.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepOutcome {
    /// Name of the sweep.
    pub name: String,
    /// The folder written.
    pub dir: PathBuf,
    /// Cases evaluated.
    pub cases: usize,
    /// Rows written.
    pub rows: usize,
    /// Rows per status (`ok`, `refused`, `failed`, `skipped`).
    pub statuses: BTreeMap<String, usize>,
    /// Cases with warnings (a sweep's `sweep.md` lists them under "Warnings", a shard's
    /// `cases.csv` in its `warnings` column).
    pub warned_cases: usize,
    /// Files written, relative to `dir`.
    pub files: Vec<String>,
}

impl SweepOutcome {
    /// Whether any row has a result (status `ok`).
    pub fn has_result(&self) -> bool {
        self.statuses.contains_key(super::row::Status::Ok.name())
    }

    /// The rows per status, `3 ok, 1 refused`.
    pub fn counts(&self) -> String {
        let counts: Vec<String> = self.statuses.iter().map(|(s, n)| format!("{n} {s}")).collect();
        counts.join(", ")
    }

    /// One line per fact, for the terminal.
    pub fn to_text(&self) -> String {
        format!(
            "sweep {}: {} cases, {} rows ({}); {} files in {}\n",
            self.name,
            self.cases,
            self.rows,
            self.counts(),
            self.files.len(),
            self.dir.display()
        )
    }
}

fn outcome(name: &str, dir: &Path, records: &[Record], files: Vec<String>) -> SweepOutcome {
    let mut statuses = BTreeMap::new();
    for r in records {
        *statuses.entry(r.status.name().to_string()).or_insert(0) += 1;
    }
    let mut cases: Vec<usize> = records.iter().map(|r| r.case).collect();
    cases.dedup();
    let mut warned: Vec<usize> = records.iter().filter(|r| !r.warnings.is_empty()).map(|r| r.case).collect();
    warned.dedup();
    SweepOutcome {
        warned_cases: warned.len(),
        name: name.to_string(),
        dir: dir.to_path_buf(),
        cases: cases.len(),
        rows: records.len(),
        statuses,
        files,
    }
}

/// Writes the full output of a sweep from its records (in case order) to `<out>/<name>/`.
pub fn write_results(sweep: &Sweep, records: &[Record], command: &str, out: &Path) -> Result<SweepOutcome, SweepError> {
    let dir = out.join(&sweep.name);
    let csv = to_csv(sweep, records)?;
    let mut files = Vec::new();
    atomically(out, &sweep.name, |scratch| {
        put(scratch, "sweep.csv", &csv, &mut files)?;
        let plots = super::plots::plots(sweep, records, &scratch.join("plots"))?;
        files.extend(plots.iter().flat_map(|p| [format!("plots/{}", p.file), format!("plots/{}", p.svg)]));
        let md = super::summary::markdown(sweep, records, command, &plots);
        put(scratch, "sweep.md", &md, &mut files)?;
        let o = outcome(&sweep.name, &dir, records, Vec::new());
        let counts = serde_json::json!({ "name": o.name, "cases": o.cases, "rows": o.rows, "statuses": o.statuses });
        let json = serde_json::to_string_pretty(&counts).map_err(|e| SweepError::Json(e.to_string()))?;
        put(scratch, "sweep.json", &(json + "\n"), &mut files)
    })?;
    Ok(outcome(&sweep.name, &dir, records, files))
}

/// Writes one shard's part to `<out>/<name>.part-K-of-N/`.
pub fn write_part(
    sweep: &Sweep,
    shard: Shard,
    range: Range<usize>,
    records: &[Record],
    out: &Path,
) -> Result<SweepOutcome, SweepError> {
    let folder = shard.folder(&sweep.name);
    let dir = out.join(&folder);
    let manifest = Manifest { sweep: sweep.clone(), shard, first: range.start, end: range.end };
    let json = serde_json::to_string_pretty(&manifest).map_err(|e| SweepError::Json(e.to_string()))?;
    let csv = to_csv(sweep, records)?;
    let mut files = Vec::new();
    atomically(out, &folder, |scratch| {
        put(scratch, MANIFEST, &(json + "\n"), &mut files)?;
        put(scratch, CASES, &csv, &mut files)
    })?;
    let mut o = outcome(&sweep.name, &dir, records, files);
    o.cases = range.len();
    Ok(o)
}

fn io(path: &Path, source: std::io::Error) -> SweepError {
    SweepError::Io { action: "write", path: path.display().to_string(), source }
}

fn put(dir: &Path, name: &str, text: &str, files: &mut Vec<String>) -> Result<(), SweepError> {
    let path = dir.join(name);
    std::fs::write(&path, text).map_err(|e| io(&path, e))?;
    files.push(name.to_string());
    Ok(())
}

/// Fills a scratch folder beside `out/name` with `fill`, then swaps it in place of `out/name`,
/// through the results folder's [`Staging`] (which also removes what killed runs left, and
/// refuses an `out/name` that is not a folder); on any error the scratch folder is removed and
/// `out/name` is left as it was. Errors name the user's folder, never the scratch folder.
fn atomically(out: &Path, name: &str, fill: impl FnOnce(&Path) -> Result<(), SweepError>) -> Result<(), SweepError> {
    let staging = Staging::begin(out, name)?;
    fill(staging.dir()).map_err(|e| shown(&staging, e))?;
    staging.commit()?;
    Ok(())
}

/// `e` with any path in the scratch folder shown as the user's.
fn shown(staging: &Staging, e: SweepError) -> SweepError {
    let at = |p: PathBuf| staging.shown(&p);
    match e {
        SweepError::Io { action, path, source } => {
            SweepError::Io { action, path: at(path.into()).display().to_string(), source }
        }
        SweepError::Plot(p) => SweepError::Plot(p.shown_as(at)),
        other => other,
    }
}
