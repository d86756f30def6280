//! The sweep file (`SWEEP.toml`): a base problem, the axes to vary, how to combine them, and what
//! to compute per case.
//!
//! ```toml
//! name = "pi-over-c"                 # optional; the file's stem otherwise (names the results folder)
//! base = "paper.toml"                # a problem file, relative to this file; or an inline [base] table
//! combine = "product"                # or "zip" (every axis the same length)
//!
//! [[axis]]
//! field = "cat.radius"               # any problem field, dotted
//! range = { from = 0.05, to = 0.4, count = 8, scale = "log" }   # or "linear" (the default)
//!
//! [[axis]]
//! field = "manoeuvre.bend_path"
//! values = ["joint-circle", "cone"]  # TOML values, written into the problem as `--set` would
//!
//! [compute]                          # what each case computes (see `Compute`)
//! paper_flip = true
//! calibrated = true
//! peaks = true
//! retiming = false                   # the certified convex retiming
//! whole = false                      # the whole-manoeuvre optimum, by the case's [optimize.whole]
//! rapier = false                     # rapier's verdict on every exact row
//! ```
//!
//! Axis values enter the problem exactly like `--set field=value` overrides, so the problem file's
//! own validation and messages apply to every case; a case the problem refuses is reported with that
//! reason, never dropped. The spec itself is checked on load: unknown keys, an axis on a field the
//! problem file does not have, an empty or malformed range, zipped axes of different lengths, a
//! `[compute]` that asks for no schedule. [`Sweep::validate`] repeats every check on a resolved
//! sweep (a shard's manifest).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::problem::Problem;

/// Why a sweep file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum SpecError {
    /// A file could not be read.
    #[error("cannot read {path}")]
    Io {
        /// The path.
        path: String,
        /// What the OS said.
        source: std::io::Error,
    },
    /// The sweep file is not valid TOML or does not have the sweep's shape.
    #[error("sweep file {origin}: {message}")]
    Parse {
        /// The file.
        origin: String,
        /// The parser's message, naming the key.
        message: String,
    },
    /// The base problem does not load (its reason is the source, printed after this).
    #[error("the sweep's base problem")]
    Base(#[from] crate::problem::ProblemError),
    /// A field of the sweep file has a value it cannot use.
    #[error("{field}: {reason}")]
    BadField {
        /// Which field, e.g. `axis[1].range.count`.
        field: String,
        /// Why.
        reason: String,
    },
}

/// Where the base problem comes from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum BaseSource {
    /// A problem file, relative to the sweep file.
    Path(String),
    /// An inline problem table.
    Inline(toml::Table),
}

/// How the values of a range are spaced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RangeScale {
    /// Equal steps.
    #[default]
    Linear,
    /// Equal ratios (both ends positive).
    Log,
}

/// `count` values from `from` to `to`, both ends included.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Range {
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Number of values (1 needs `from` = `to`: a range has both ends).
    pub count: usize,
    /// Spacing.
    #[serde(default)]
    pub scale: RangeScale,
}

impl Range {
    /// The values: `from + (to − from)·k/(count − 1)`, or `from·(to/from)^{k/(count − 1)}` on a log
    /// scale, `k = 0 … count − 1`; the first is `from` and the last `to`, exactly.
    pub fn values(&self) -> Vec<f64> {
        let n = self.count;
        (0..n)
            .map(|k| {
                if k == 0 {
                    return self.from;
                }
                if k + 1 == n {
                    return self.to;
                }
                let u = if n > 1 { k as f64 / (n - 1) as f64 } else { 0.0 };
                match self.scale {
                    RangeScale::Linear => self.from + (self.to - self.from) * u,
                    RangeScale::Log => (self.from.ln() + (self.to.ln() - self.from.ln()) * u).exp(),
                }
            })
            .collect()
    }
}

/// One swept field, as written in the file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisSpec {
    /// Dotted problem field, e.g. `cat.radius`.
    pub field: String,
    /// The values, as TOML values.
    pub values: Option<Vec<toml::Value>>,
    /// Or a numeric range.
    pub range: Option<Range>,
}

/// How axes combine into cases.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Combine {
    /// Every combination; the first axis varies slowest.
    #[default]
    Product,
    /// The k-th values of every axis together; all axes the same length.
    Zip,
}

/// What each case computes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Compute {
    /// The flip (twist, swing) with the paper's circulation `π/C`.
    pub paper_flip: bool,
    /// The calibrated circulation (exact flip by π) and its swing.
    pub calibrated: bool,
    /// Peak motor torques per phase and joint of each schedule.
    pub peaks: bool,
    /// The convex retiming's certified optimum of the calibrated (else the paper's) schedule
    /// along its path ([`super::optimum`]).
    pub retiming: bool,
    /// The whole-manoeuvre optimum by each case's own `[optimize.whole]` and `[actuator]`
    /// ([`super::optimum`]).
    pub whole: bool,
    /// Retired: refused at load ([`RETIRED_CONTROL_POINTS`]). The spline's control points are
    /// the problem's `optimize.whole.control_points` (in the base problem or as an axis), the
    /// one place `optimize --whole` reads them too. Never written to a shard's manifest.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub whole_control_points: Option<toml::Value>,
    /// Rapier's verification of every exact row ([`super::verify`]).
    pub rapier: bool,
}

impl Default for Compute {
    fn default() -> Self {
        Self {
            paper_flip: true,
            calibrated: true,
            peaks: true,
            retiming: false,
            whole: false,
            whole_control_points: None,
            rapier: false,
        }
    }
}

/// A sweep file as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// Name of the sweep (letters, digits, `-`, `_`); the file's stem when absent.
    pub name: Option<String>,
    /// The base problem.
    pub base: BaseSource,
    /// The swept fields.
    #[serde(default, rename = "axis")]
    pub axes: Vec<AxisSpec>,
    /// How the axes combine.
    #[serde(default)]
    pub combine: Combine,
    /// What each case computes.
    #[serde(default)]
    pub compute: Compute,
}

/// One axis resolved to its values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// Dotted problem field.
    pub field: String,
    /// The values.
    pub values: Vec<toml::Value>,
    /// Whether every value is a number (the axis can be plotted along).
    pub numeric: bool,
}

/// A checked sweep, ready to expand into cases (serialised whole into each shard's manifest, so
/// parts can be merged where the sweep's files are not).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sweep {
    /// Name of the sweep; names its results folder.
    pub name: String,
    /// The sweep file's text as read (recorded in the report and the shard manifests).
    pub text: String,
    /// The base problem's TOML text.
    pub base_text: String,
    /// Where the base text came from, for messages.
    pub base_origin: String,
    /// The axes, in file order.
    pub axes: Vec<Axis>,
    /// How they combine.
    pub combine: Combine,
    /// What each case computes.
    pub compute: Compute,
}

/// Largest number of cases one sweep may expand to.
pub const MAX_CASES: usize = 10_000_000;

impl Sweep {
    /// Reads and checks a sweep file.
    pub fn load(path: &Path) -> Result<Sweep, SpecError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| SpecError::Io { path: path.display().to_string(), source })?;
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "sweep".into());
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Sweep::from_toml(&text, &path.display().to_string(), &stem, &dir)
    }

    /// Parses and checks sweep text; `stem` names the sweep when the text does not, and `dir` is
    /// where a base path is resolved from.
    pub fn from_toml(text: &str, origin: &str, stem: &str, dir: &Path) -> Result<Sweep, SpecError> {
        let file: SweepFile = toml::from_str(text).map_err(|e| {
            let (origin, message) = crate::problem::toml_error(text, origin, &e);
            SpecError::Parse { origin, message: format!("{message}{}", problem_file_hint(text)) }
        })?;
        let name = file.name.clone().unwrap_or_else(|| stem.to_string());
        check_name(&name)?;
        let (base_text, base_origin) = match &file.base {
            BaseSource::Path(p) => {
                let path: PathBuf = dir.join(p);
                let t = std::fs::read_to_string(&path).map_err(|e| {
                    bad(
                        "base",
                        &format!(
                            "cannot read the problem file {} ({p:?}, relative to the sweep file): {e}",
                            path.display()
                        ),
                    )
                })?;
                (t, path.display().to_string())
            }
            BaseSource::Inline(table) => (
                toml::to_string(table).map_err(|e| bad("base", &one_line(&e.to_string())))?,
                format!("{origin} [base]"),
            ),
        };
        let axes = file.axes.iter().enumerate().map(|(i, a)| resolve_axis(i, a)).collect::<Result<Vec<_>, _>>()?;
        let sweep = Sweep {
            name,
            text: text.to_string(),
            base_text,
            base_origin,
            axes,
            combine: file.combine,
            compute: file.compute,
        };
        sweep.validate()?;
        Ok(sweep)
    }

    /// Checks a resolved sweep as strictly as its file is checked on load: the name, the base
    /// problem, every axis (values, field, each swept once), the number of cases and `[compute]`.
    /// A sweep read back from a shard's manifest goes through this before anything is merged,
    /// so a manifest cannot name a folder outside `--out` or expand beyond [`MAX_CASES`].
    pub fn validate(&self) -> Result<(), SpecError> {
        check_name(&self.name)?;
        let base = Problem::from_toml(&self.base_text, &self.base_origin, &[])?;
        base.require_no_spin("a sweep")?;
        base.require_paper_cat("a sweep")?;
        let known = known_fields();
        let mut seen = BTreeSet::new();
        for (i, axis) in self.axes.iter().enumerate() {
            check_axis(i, axis, &known, &self.base_text, &self.base_origin)?;
            if !seen.insert(axis.field.as_str()) {
                return Err(bad(&format!("axis[{i}].field"), &format!("`{}` is swept twice", axis.field)));
            }
        }
        check_count(&self.axes, self.combine)?;
        check_compute(&self.compute)
    }

    /// Number of cases the axes expand to (1 with no axis: the base problem alone).
    pub fn case_count(&self) -> usize {
        match self.combine {
            Combine::Product => self.axes.iter().map(|a| a.values.len()).product(),
            Combine::Zip => self.axes.first().map_or(1, |a| a.values.len()),
        }
    }
}

/// Resolves one axis to its values (a range checked and expanded); [`check_axis`] checks the rest.
fn resolve_axis(i: usize, a: &AxisSpec) -> Result<Axis, SpecError> {
    let at = |k: &str| format!("axis[{i}].{k}");
    let values: Vec<toml::Value> = match (&a.values, &a.range) {
        (Some(v), None) => v.clone(),
        (None, Some(r)) => {
            check_range(&at("range"), r)?;
            r.values().into_iter().map(toml::Value::Float).collect()
        }
        _ => return Err(bad(&at("values"), "give exactly one of `values = [...]` or `range = {from, to, count}`")),
    };
    let numeric = is_numeric(&values);
    Ok(Axis { field: a.field.clone(), values, numeric })
}

/// Whether every value is a number.
fn is_numeric(values: &[toml::Value]) -> bool {
    values.iter().all(|v| matches!(v, toml::Value::Float(_) | toml::Value::Integer(_)))
}

/// Checks one resolved axis: at least one value, at most [`MAX_CASES`], a field the problem
/// file has (never `name`), and `numeric` true exactly when every value is a number.
fn check_axis(
    i: usize,
    a: &Axis,
    known: &BTreeSet<String>,
    base_text: &str,
    base_origin: &str,
) -> Result<(), SpecError> {
    let at = |k: &str| format!("axis[{i}].{k}");
    if a.values.is_empty() {
        return Err(bad(&at("values"), "an axis needs at least one value"));
    }
    if a.values.len() > MAX_CASES {
        return Err(bad(&at("values"), &format!("at most {MAX_CASES} values")));
    }
    if a.field == "name" {
        return Err(bad(&at("field"), "`name` cannot be swept: the sweep names its cases"));
    }
    if a.field.chars().any(char::is_whitespace) {
        let trimmed = a.field.trim();
        let hint = if trimmed.contains(char::is_whitespace) { String::new() } else { format!(": write `{trimmed}`") };
        return Err(bad(&at("field"), &format!("`{}` holds spaces{hint}", a.field)));
    }
    // A value that is no number (`nan`, `inf`) is the file's mistake whatever the field: only the
    // first float is tried below, so a NaN later in the list would reach the cases.
    if let Some(k) = a.values.iter().position(|v| matches!(v, toml::Value::Float(x) if !x.is_finite())) {
        return Err(bad(&format!("axis[{i}].values[{k}]"), &format!("{}: must be a finite number", a.values[k])));
    }
    // Each value the field cannot hold (a string among numbers, a misspelt name, an integer out
    // of its range) is the file's mistake, said here rather than as a refused case; a value the
    // problem then refuses for what it means (a bend at gimbal lock) is a case's. A field the
    // parser does not know is the axis's. Every non-number is tried, and of the numbers the first
    // float and the least and largest integer (their type and range decide).
    let (mut least, mut most) = (None::<(usize, i64)>, None::<(usize, i64)>);
    let mut tried: Vec<usize> = Vec::new();
    let mut float = false;
    let mut seen = BTreeSet::new();
    for (k, value) in a.values.iter().enumerate() {
        match value {
            toml::Value::Integer(n) => {
                if least.is_none_or(|(_, m)| *n < m) {
                    least = Some((k, *n));
                }
                if most.is_none_or(|(_, m)| *n > m) {
                    most = Some((k, *n));
                }
            }
            toml::Value::Float(_) => {
                if !std::mem::replace(&mut float, true) {
                    tried.push(k);
                }
            }
            other => {
                if seen.insert(other.to_string()) {
                    tried.push(k);
                }
            }
        }
    }
    tried.extend(least.map(|l| l.0));
    tried.extend(most.map(|m| m.0).filter(|m| least.is_none_or(|l| l.0 != *m)));
    tried.sort_unstable();
    for k in tried {
        let value = &a.values[k];
        if let Some(why) = refused_by_problem(base_text, base_origin, &a.field, value) {
            if why.contains("unknown field") && !known.contains(&a.field) {
                return Err(bad(&at("field"), &format!("`{}` is not a problem field: {why}", a.field)));
            }
            return Err(bad(&format!("axis[{i}].values[{k}]"), &format!("{value}: {why}")));
        }
    }
    if a.numeric != is_numeric(&a.values) {
        return Err(bad(&at("numeric"), &format!("is {} but the values say otherwise", a.numeric)));
    }
    Ok(())
}

/// Checks a sweep's name: it names a folder under `--out`, so it must be a plain, non-empty
/// name (letters, digits, `-`, `_`): never empty, `..`, or a path.
pub fn check_name(name: &str) -> Result<(), SpecError> {
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
        return Err(bad("name", &format!("{name:?} must be non-empty and use only letters, digits, '-' and '_'")));
    }
    Ok(())
}

/// Checks a range's ends, count and scale.
fn check_range(field: &str, r: &Range) -> Result<(), SpecError> {
    if !r.from.is_finite() || !r.to.is_finite() {
        return Err(bad(field, "`from` and `to` must be finite numbers"));
    }
    if r.count == 0 {
        return Err(bad(&format!("{field}.count"), "must be at least 1"));
    }
    // One value cannot be both ends: it would be `from` alone, `to` dropped unsaid.
    if r.count == 1 && (r.to - r.from).abs() > 0.0 {
        return Err(bad(
            &format!("{field}.count"),
            &format!(
                "1 gives one value, but `from` = {} and `to` = {} differ: a range has both ends; give count >= 2, or from = to for one value",
                r.from, r.to
            ),
        ));
    }
    if r.scale == RangeScale::Log && (r.from <= 0.0 || r.to <= 0.0) {
        return Err(bad(&format!("{field}.scale"), "a log range needs positive `from` and `to`"));
    }
    if r.count > MAX_CASES {
        return Err(bad(&format!("{field}.count"), &format!("must be at most {MAX_CASES}")));
    }
    Ok(())
}

/// Checks the number of cases: zipped axes of equal length, a product not beyond [`MAX_CASES`].
fn check_count(axes: &[Axis], combine: Combine) -> Result<(), SpecError> {
    match combine {
        Combine::Zip => {
            if let Some(first) = axes.first() {
                for (i, a) in axes.iter().enumerate().skip(1) {
                    if a.values.len() != first.values.len() {
                        return Err(bad(
                            "combine",
                            &format!(
                                "\"zip\" needs axes of one length: axis[0] `{}` has {} values, axis[{i}] `{}` has {}",
                                first.field,
                                first.values.len(),
                                a.field,
                                a.values.len()
                            ),
                        ));
                    }
                }
            }
        }
        Combine::Product => {
            let n = axes.iter().try_fold(1usize, |acc, a| acc.checked_mul(a.values.len()));
            if n.is_none_or(|n| n > MAX_CASES) {
                return Err(bad("combine", &format!("the product of the axes exceeds {MAX_CASES} cases")));
            }
        }
    }
    Ok(())
}

/// Why `[compute] whole_control_points` is refused: it duplicated (and silently overrode) the
/// problem's own `optimize.whole.control_points`.
pub const RETIRED_CONTROL_POINTS: &str = "the whole optimum uses each case's own [optimize.whole]; set `optimize.whole.control_points` in the base problem (or an inline [base.optimize.whole] table), \
     or sweep it as an axis (field = \"optimize.whole.control_points\")";

/// Checks `[compute]`: at least one schedule asked for, and not the retired
/// `whole_control_points`.
fn check_compute(c: &Compute) -> Result<(), SpecError> {
    if let Some(v) = &c.whole_control_points {
        return Err(bad("compute.whole_control_points", &format!("is retired (found {v}): {RETIRED_CONTROL_POINTS}")));
    }
    if !(c.paper_flip || c.calibrated || c.retiming || c.whole) {
        return Err(bad(
            "compute",
            "[compute] asks for no schedule (paper_flip, calibrated, retiming and whole are all false): \
             the sweep would compute nothing; set at least one of them to true",
        ));
    }
    Ok(())
}

/// The dotted paths of every leaf of the default problem (the fields an axis may name).
pub fn known_fields() -> BTreeSet<String> {
    fn walk(prefix: &str, t: &toml::Table, out: &mut BTreeSet<String>) {
        for (k, v) in t {
            let key = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
            match v {
                toml::Value::Table(sub) => walk(&key, sub, out),
                _ => {
                    out.insert(key);
                }
            }
        }
    }
    let mut out = BTreeSet::new();
    if let Ok(t) = toml::Table::try_from(Problem::default()) {
        walk("", &t, &mut out);
    }
    out.remove("name");
    out
}

/// Why the problem file does not take `field` (an optional field absent from the defaults is
/// taken): the parser's words when the base problem with that field set does not parse (naming
/// the section and the fields it has, the optional ones too), none when it parses, whatever it
/// then says of the value.
fn refused_by_problem(base_text: &str, base_origin: &str, field: &str, value: &toml::Value) -> Option<String> {
    use crate::problem::ProblemError;
    let set = format!("{field}={value}");
    match Problem::from_toml(base_text, base_origin, &[set]) {
        Err(ProblemError::Parse { message, .. }) => Some(one_line(&message)),
        Err(ProblemError::BadOverride { reason, .. }) => Some(one_line(&reason)),
        _ => None,
    }
}

/// What a sweep file's parse error adds when `text` reads as a problem file (it has one of a
/// problem's sections at its top level): that a sweep file names its problem instead.
fn problem_file_hint(text: &str) -> &'static str {
    let problem_sections = ["cat", "drop", "manoeuvre", "actuator", "exact", "rapier", "optimize", "robust"];
    let table: Option<toml::Table> = text.parse().ok();
    if table.is_some_and(|t| problem_sections.iter().any(|s| t.get(*s).is_some_and(toml::Value::is_table))) {
        " (this reads as a problem file: a sweep file names its problem as base = \"problems/….toml\" and what it varies in [[axis]] tables; README, \"Sweeps\")"
    } else {
        ""
    }
}

fn bad(field: &str, reason: &str) -> SpecError {
    SpecError::BadField { field: field.to_string(), reason: reason.to_string() }
}

pub(crate) use crate::problem::one_line;

/// `e` and its causes, joined as the command line prints them (`the sweep's base problem: …`).
pub fn with_causes(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        text = format!("{text}: {c}");
        cause = c.source();
    }
    text
}
