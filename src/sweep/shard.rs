//! Shards: `--shard K/N` runs the K-th of N deterministic slices of a sweep and writes its own
//! part; `--merge DIR…` joins the parts into the output one run would have written.
//!
//! Shard `K` of `N` (1-based) takes the contiguous cases `⌊(K−1)M/N⌋ ≤ i < ⌊KM/N⌋` of the `M`
//! cases, so the parts, in shard order, concatenate to the single run's rows. A part folder holds
//! `part.json` (the manifest: the whole resolved sweep, `K`, `N` and the case range) and
//! `cases.csv` (its rows, in the single run's format). `N` is at most the number of cases.
//!
//! Merging trusts nothing a part says: each manifest is checked as strictly as a sweep file
//! ([`Manifest::validate`]: the sweep's name, axes and `[compute]`, `1 ≤ K ≤ N ≤` cases, the case
//! range), every part must come from the same sweep and shard count, each shard must appear once
//! and all be present, and each case must have exactly the rows one run gives it, every `ok` row
//! with its numbers, all finite ([`super::table::from_csv_lines`]). Errors name the file and the
//! field or line.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::evaluate::row_keys;
use super::spec::{one_line, with_causes, SpecError, Sweep};
use super::table::{from_csv_lines, Record};
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
        let whole = |x: &str, name: &str| {
            x.trim().parse::<usize>().map_err(|e| match e.kind() {
                std::num::IntErrorKind::PosOverflow => {
                    format!("--shard {s}: {name} is too large (at most {})", usize::MAX)
                }
                _ => format!("--shard {s}: {name} must be a whole number"),
            })
        };
        let (k, n) = (whole(k, "K")?, whole(n, "N")?);
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

    /// Checks the shard count against the sweep's `cases`: at most one shard per case (a larger
    /// `N` gives empty shards and, merged, a list of missing shards without bound).
    pub fn check(&self, cases: usize) -> Result<(), SweepError> {
        if self.n > cases {
            return Err(SweepError::TooManyShards { k: self.k, n: self.n, cases });
        }
        Ok(())
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

impl Manifest {
    /// Reads and checks a part's manifest; errors name the file and the field.
    pub fn read(path: &Path) -> Result<Manifest, SweepError> {
        let shown = path.display();
        let m: Manifest = serde_json::from_str(&read(path)?)
            .map_err(|e| SweepError::Merge(format!("{shown}: not a part manifest: {}", one_line(&e.to_string()))))?;
        m.validate().map_err(|(field, reason)| SweepError::Merge(format!("{shown}: {field}: {reason}")))?;
        Ok(m)
    }

    /// Checks a manifest as strictly as a sweep file ([`Sweep::validate`]) and its slice
    /// against the sweep: `1 ≤ k ≤ n ≤` cases, and `first..end` the slice's own cases. Returns
    /// the field (as named in `part.json`) and why.
    pub fn validate(&self) -> Result<(), (String, String)> {
        self.sweep.validate().map_err(|e| match e {
            SpecError::BadField { field, reason } => (format!("sweep.{field}"), reason),
            other => ("sweep".to_string(), one_line(&with_causes(&other))),
        })?;
        let Shard { k, n } = self.shard;
        let cases = self.sweep.case_count();
        if n == 0 {
            return Err(("shard.n".into(), "must be at least 1".into()));
        }
        if k == 0 || k > n {
            return Err(("shard.k".into(), format!("{k} is not between 1 and shard.n = {n}")));
        }
        if n > cases {
            return Err(("shard.n".into(), format!("{n} shards of a sweep of {cases} cases: at most {cases}")));
        }
        let range = self.shard.range(cases);
        if (self.first, self.end) != (range.start, range.end) {
            return Err((
                "first, end".into(),
                format!(
                    "{}..{} is not shard {k}/{n}'s cases {}..{} of {cases}",
                    self.first, self.end, range.start, range.end
                ),
            ));
        }
        Ok(())
    }
}

/// What differs between the sweeps of two parts, in words; none when they are one sweep.
fn difference(a: &Sweep, b: &Sweep) -> Option<String> {
    let what = if a.name != b.name {
        format!("its name (\"{}\" against \"{}\")", a.name, b.name)
    } else if a.base_text != b.base_text || a.base_origin != b.base_origin {
        format!("its base problem ({})", a.base_origin)
    } else if a.axes != b.axes || a.combine != b.combine {
        "its axes".to_string()
    } else if a.compute != b.compute {
        "its [compute]".to_string()
    } else if a != b {
        "its sweep file".to_string()
    } else {
        return None;
    };
    Some(what)
}

/// Reads the parts in `dirs` and returns the sweep and every record in case order.
pub fn read_parts(dirs: &[PathBuf]) -> Result<(Sweep, Vec<Record>), SweepError> {
    let mut parts: Vec<(Manifest, PathBuf)> = Vec::new();
    for dir in dirs {
        parts.push((Manifest::read(&dir.join(MANIFEST))?, dir.clone()));
    }
    let Some((first, _)) = parts.first() else {
        return Err(SweepError::Merge("--merge needs at least one part folder".into()));
    };
    let (sweep, n) = (first.sweep.clone(), first.shard.n);
    for (m, dir) in &parts {
        let differs = if m.shard.n != n {
            Some(format!("its shard count ({} against {n})", m.shard.n))
        } else {
            difference(&m.sweep, &sweep)
        };
        if let Some(what) = differs {
            return Err(SweepError::Merge(format!(
                "{} is a part of another sweep than {}: {what} differs (the parts of one sweep come from one sweep file and one --shard K/N count; run the shards again from the file as it is now)",
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
    if let Some(missing) = missing(&have, n) {
        return Err(SweepError::Merge(missing));
    }
    let mut records = Vec::new();
    for (m, dir) in &parts {
        let path = dir.join(CASES);
        let shown = path.display().to_string();
        let rows = from_csv_lines(&sweep, &read(&path)?, &shown)?;
        check_rows(&sweep, m.shard.range(sweep.case_count()), &shown, &rows)?;
        records.extend(rows.into_iter().map(|(_, r)| r));
    }
    Ok((sweep, records))
}

/// The shards of `1..=n` not in `have` (sorted, distinct), named as ranges: `missing shards
/// 3–998 of 1000`; `None` when every shard is there. At most [`LISTED`] ranges are named.
fn missing(have: &[usize], n: usize) -> Option<String> {
    let mut gaps = Vec::new();
    let mut next = 1;
    for &k in have.iter().chain(std::iter::once(&(n + 1))) {
        if k > next {
            gaps.push((next, k - 1));
        }
        next = k + 1;
    }
    let count: usize = gaps.iter().map(|(a, b)| b - a + 1).sum();
    if count == 0 {
        return None;
    }
    let mut named: Vec<String> =
        gaps.iter().take(LISTED).map(|&(a, b)| if a == b { a.to_string() } else { format!("{a}–{b}") }).collect();
    if gaps.len() > LISTED {
        named.push(format!("and {} more ranges", gaps.len() - LISTED));
    }
    let noun = if count == 1 { "shard" } else { "shards" };
    Some(format!("missing {noun} {} of {n} ({count} missing)", named.join(", ")))
}

/// Most ranges of missing shards named in one message.
const LISTED: usize = 8;

/// Checks that a part's rows are exactly its cases' rows, in order: for each case of `range`
/// the (schedule, engine) rows one run gives it ([`row_keys`]); errors name the file and line.
fn check_rows(sweep: &Sweep, range: Range<usize>, path: &str, rows: &[(u64, Record)]) -> Result<(), SweepError> {
    let keys = |rs: &[(u64, Record)]| -> Vec<String> {
        rs.iter().map(|(_, r)| format!("{}/{}", r.schedule, r.engine)).collect()
    };
    let end_line = rows.last().map_or(2, |(l, _)| l + 1);
    let mut at = 0;
    for case in range.clone() {
        let len = rows[at..].iter().take_while(|(_, r)| r.case == case).count();
        let got = &rows[at..at + len];
        let want: Vec<String> = row_keys(sweep, case).iter().map(|(s, e)| format!("{s}/{e}")).collect();
        if len == 0 {
            let (line, found) = rows
                .get(at)
                .map_or((end_line, "the end of the file".to_string()), |(l, r)| (*l, format!("case {}", r.case)));
            return Err(SweepError::Merge(format!(
                "{path} line {line}: expected case {case} (the part holds cases {}..{} in order), found {found}",
                range.start, range.end
            )));
        }
        let have = keys(got);
        if have != want {
            let j = have.iter().zip(&want).take_while(|(a, b)| a == b).count();
            let line = got.get(j).map_or(got[len - 1].0 + 1, |(l, _)| *l);
            return Err(SweepError::Merge(format!(
                "{path} line {line}: case {case} has rows {}; a run gives it {}",
                have.join(", "),
                want.join(", ")
            )));
        }
        at += len;
    }
    if let Some((line, r)) = rows.get(at) {
        return Err(SweepError::Merge(format!(
            "{path} line {line}: case {} is not one of the part's cases {}..{}",
            r.case, range.start, range.end
        )));
    }
    Ok(())
}

fn read(path: &Path) -> Result<String, SweepError> {
    std::fs::read_to_string(path).map_err(|source| SweepError::Io {
        action: "read",
        path: path.display().to_string(),
        source,
    })
}
