//! Shards: `--shard K/N` runs the K-th of N deterministic slices of a sweep and writes its own
//! part; `--merge DIR…` joins the parts into the output one run would have written.
//!
//! Shard `K` of `N` (1-based) takes the contiguous cases `⌊(K−1)M/N⌋ ≤ i < ⌊KM/N⌋` of the `M`
//! cases, so the parts, in shard order, concatenate to the single run's rows. A part folder holds
//! `part.json` (the manifest: the whole resolved sweep, `K`, `N` and the case range) and
//! `cases.csv` (its rows, in the single run's format). Merging checks that every part comes from
//! the same sweep and shard count, that each shard appears once and all are present.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::spec::Sweep;
use super::table::{from_csv, Record};
use super::SweepError;

/// One slice of a sweep: shard `k` of `n`, 1-based.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which slice, `1 ≤ k ≤ n`.
    pub k: usize,
    /// How many slices.
    pub n: usize,
}

impl FromStr for Shard {
    type Err = String;

    /// Parses `K/N`.
    fn from_str(s: &str) -> Result<Shard, String> {
        let (k, n) = s.split_once('/').ok_or_else(|| format!("--shard {s}: expected K/N, e.g. 3/16"))?;
        let k: usize = k.trim().parse().map_err(|_| format!("--shard {s}: K must be a whole number"))?;
        let n: usize = n.trim().parse().map_err(|_| format!("--shard {s}: N must be a whole number"))?;
        if n == 0 || k == 0 || k > n {
            return Err(format!("--shard {s}: need 1 ≤ K ≤ N"));
        }
        Ok(Shard { k, n })
    }
}

impl Shard {
    /// The case indices of this shard among `total` cases.
    pub fn range(&self, total: usize) -> Range<usize> {
        let at = |j: usize| ((j as u128 * total as u128) / self.n as u128) as usize;
        at(self.k - 1)..at(self.k)
    }

    /// The part folder's name for a sweep.
    pub fn folder(&self, name: &str) -> String {
        format!("{name}.part-{}-of-{}", self.k, self.n)
    }
}

/// The manifest of a part.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// The resolved sweep.
    pub sweep: Sweep,
    /// The slice.
    pub shard: Shard,
    /// Its first case index.
    pub first: usize,
    /// One past its last case index.
    pub end: usize,
}

/// File names inside a part folder.
pub const MANIFEST: &str = "part.json";
/// The part's rows.
pub const CASES: &str = "cases.csv";

/// Reads the parts in `dirs` and returns the sweep and every record in case order.
pub fn read_parts(dirs: &[PathBuf]) -> Result<(Sweep, Vec<Record>), SweepError> {
    let mut parts: Vec<(Manifest, PathBuf)> = Vec::new();
    for dir in dirs {
        let text = read(&dir.join(MANIFEST))?;
        let m: Manifest = serde_json::from_str(&text)
            .map_err(|e| SweepError::Merge(format!("{}: not a part manifest: {e}", dir.join(MANIFEST).display())))?;
        parts.push((m, dir.clone()));
    }
    let Some((first, _)) = parts.first() else {
        return Err(SweepError::Merge("--merge needs at least one part folder".into()));
    };
    let (sweep, n) = (first.sweep.clone(), first.shard.n);
    for (m, dir) in &parts {
        if m.sweep != sweep || m.shard.n != n {
            return Err(SweepError::Merge(format!(
                "{} is a part of another sweep or shard count than {}",
                dir.display(),
                parts[0].1.display()
            )));
        }
    }
    parts.sort_by_key(|(m, _)| m.shard.k);
    for (j, (m, dir)) in parts.iter().enumerate() {
        if j > 0 && parts[j - 1].0.shard.k == m.shard.k {
            return Err(SweepError::Merge(format!("shard {}/{n} is given twice ({})", m.shard.k, dir.display())));
        }
    }
    let have: Vec<usize> = parts.iter().map(|(m, _)| m.shard.k).collect();
    let missing: Vec<String> = (1..=n).filter(|k| !have.contains(k)).map(|k| format!("{k}/{n}")).collect();
    if !missing.is_empty() {
        return Err(SweepError::Merge(format!("missing shards {}", missing.join(", "))));
    }
    let mut records = Vec::new();
    for (m, dir) in &parts {
        let path = dir.join(CASES);
        let rows = from_csv(&sweep, &read(&path)?, &path.display().to_string())?;
        let expected = m.shard.range(sweep.case_count());
        let mut seen: Vec<usize> = rows.iter().map(|r| r.case).collect();
        seen.dedup();
        if seen != expected.clone().collect::<Vec<_>>() || expected != (m.first..m.end) {
            return Err(SweepError::Merge(format!(
                "{}: its rows do not cover cases {}..{} in order",
                path.display(),
                expected.start,
                expected.end
            )));
        }
        records.extend(rows);
    }
    Ok((sweep, records))
}

fn read(path: &Path) -> Result<String, SweepError> {
    std::fs::read_to_string(path).map_err(|source| SweepError::Io { path: path.display().to_string(), source })
}
