//! Fuzz the file surfaces added after the problem file (issue 18; `tests/fuzz.rs` fuzzes the
//! problem file and `--set`): schedule files (`simulate --schedule`), sweep files, and shard
//! manifests with their rows (`sweep --merge`). Each input is a valid file edited by a few hostile
//! edits (cells, scales, dropped or doubled rows, renamed columns, values of the wrong type, paths
//! in names). What must hold:
//! - no panic;
//! - a refusal is one non-empty line;
//! - an accepted input gives only finite numbers (the report's JSON has no `null` the clean
//!   file's has not, its text no `NaN` or `inf`; a merge's rows none);
//! - nothing outside `--out` is touched: an accepted sweep or manifest names a results folder
//!   inside `--out`, and a sample of them is run or merged for real in a sandbox whose every other
//!   file is compared before and after.
//!
//! The counts are printed (`--nocapture`). A CI-sized sample runs by default (a few hundred
//! inputs per surface); 10⁵ per surface with
//! `cargo test --release --test fuzz_files -- --ignored --nocapture`.

mod common;

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Component, Path, PathBuf};

use catflip::exchange::import::parse_schedule;
use catflip::exchange::{write_schedule, ExportOptions};
use catflip::problem::Problem;
use catflip::report::import::evaluate;
use catflip::schedule::{paper_circulation, Schedule};
use catflip::sweep::shard::{read_parts, MANIFEST};
use catflip::sweep::spec::with_causes;
use catflip::sweep::{Shard, Sweep, SweepOptions};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

/// What one input came to.
enum Outcome {
    Accepted,
    /// Accepted and run (or merged) for real in the sandbox.
    Ran,
    Refused,
    /// A refusal on several lines, or empty.
    BadMessage(String),
    /// Accepted with a non-finite number.
    NonFinite(String),
    /// A file outside `--out` changed, or the results folder is not inside it.
    Outside(String),
}

/// The counts of one surface.
#[derive(Default)]
struct Tally {
    inputs: usize,
    accepted: usize,
    refused: usize,
    panics: usize,
    bad_messages: usize,
    non_finite: usize,
    outside: usize,
    /// Accepted inputs also run (or merged) in the sandbox.
    run: usize,
    /// The first few failures, to print.
    examples: Vec<String>,
}

impl Tally {
    fn failures(&self) -> usize {
        self.panics + self.bad_messages + self.non_finite + self.outside
    }

    fn print(&self, surface: &str) {
        println!(
            "{surface}: {} inputs, {} accepted ({} run for real), {} refused; {} panics, {} refusals not one line, {} non-finite numbers accepted, {} touched outside --out",
            self.inputs, self.accepted, self.run, self.refused, self.panics, self.bad_messages, self.non_finite, self.outside
        );
        for e in &self.examples {
            println!("  {e}");
        }
    }
}

/// Draws `cases` inputs from `strategy` (seeded: the same inputs every run) and tallies `check`.
fn fuzz<S: Strategy>(cases: usize, strategy: S, mut check: impl FnMut(usize, S::Value) -> Outcome) -> Tally
where
    S::Value: std::fmt::Debug,
{
    let mut runner = TestRunner::deterministic();
    let mut t = Tally::default();
    for i in 0..cases {
        let Ok(tree) = strategy.new_tree(&mut runner) else { continue };
        let input = tree.current();
        let shown = format!("{input:?}");
        t.inputs += 1;
        let note = |t: &mut Tally, what: &str, detail: &str| {
            if t.examples.len() < 5 {
                t.examples.push(format!("{what}: {detail} — input {}", &shown[..shown.len().min(300)]));
            }
        };
        if cases >= 10_000 && i > 0 && i % 10_000 == 0 {
            println!("  … after {i} inputs: {} accepted, {} refused, {} failures", t.accepted, t.refused, t.failures());
        }
        match catch_unwind(AssertUnwindSafe(|| check(i, input))) {
            Ok(Outcome::Accepted) => t.accepted += 1,
            Ok(Outcome::Ran) => {
                t.accepted += 1;
                t.run += 1;
            }
            Ok(Outcome::Refused) => t.refused += 1,
            Ok(Outcome::BadMessage(m)) => {
                t.bad_messages += 1;
                note(&mut t, "refusal not one line", &m);
            }
            Ok(Outcome::NonFinite(m)) => {
                t.non_finite += 1;
                note(&mut t, "non-finite", &m);
            }
            Ok(Outcome::Outside(m)) => {
                t.outside += 1;
                note(&mut t, "outside --out", &m);
            }
            Err(_) => {
                t.panics += 1;
                note(&mut t, "panic", "");
            }
        }
    }
    t
}

/// A refusal's outcome: one non-empty line, or not.
fn refused(message: String) -> Outcome {
    if message.is_empty() || message.contains('\n') {
        Outcome::BadMessage(message)
    } else {
        Outcome::Refused
    }
}

/// Hostile text for a CSV cell or a number.
const CELLS: [&str; 24] = [
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e400",
    "1e-320",
    "0",
    "-0",
    "",
    "abc",
    "1e15",
    "-1e15",
    "1e-15",
    "3.14159",
    "1000",
    "-1000",
    "\"",
    "0x10",
    "+1",
    " 1 ",
    "1e200",
    "9007199254740993",
];

/// Factors a whole column is scaled by.
const SCALES: [f64; 12] = [1e-200, 1e-6, 1e-3, -1.0, 0.0, 1e3, 1e6, 1e200, 57.29577951308232, 1.0 + 1e-9, 2.0, 0.5];

/// One edit of a CSV (row and column indices are taken modulo the file's).
#[derive(Clone, Debug)]
enum CsvEdit {
    Cell(usize, usize, String),
    Scale(usize, f64),
    Offset(usize, f64),
    DropColumn(usize),
    RenameColumn(usize, String),
    DoubleRow(usize),
    DropRow(usize),
    SwapRows(usize, usize),
    InsertLine(usize, String),
    Truncate(usize),
}

fn cell() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => proptest::sample::select(CELLS.to_vec()).prop_map(str::to_string),
        1 => any::<f64>().prop_map(|x| format!("{x:e}")),
        1 => "[0-9eE.+\\-,\"a-z ]{0,12}",
    ]
}

fn csv_edit() -> impl Strategy<Value = CsvEdit> {
    let column_name = prop_oneof![
        Just("t_s".to_string()),
        Just("q1_rad".to_string()),
        Just("qd1".to_string()),
        Just("time".to_string()),
        Just("".to_string()),
        "[a-z_]{1,8}"
    ];
    prop_oneof![
        6 => (any::<usize>(), any::<usize>(), cell()).prop_map(|(r, c, v)| CsvEdit::Cell(r, c, v)),
        2 => (any::<usize>(), proptest::sample::select(SCALES.to_vec())).prop_map(|(c, f)| CsvEdit::Scale(c, f)),
        1 => (any::<usize>(), proptest::sample::select(vec![1e15, 1e9, -1e6, 1e-3, 7.0])).prop_map(|(c, o)| CsvEdit::Offset(c, o)),
        1 => any::<usize>().prop_map(CsvEdit::DropColumn),
        1 => (any::<usize>(), column_name).prop_map(|(c, n)| CsvEdit::RenameColumn(c, n)),
        2 => any::<usize>().prop_map(CsvEdit::DoubleRow),
        2 => any::<usize>().prop_map(CsvEdit::DropRow),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(a, b)| CsvEdit::SwapRows(a, b)),
        1 => (any::<usize>(), "[^\n]{0,30}").prop_map(|(r, l)| CsvEdit::InsertLine(r, l)),
        1 => any::<usize>().prop_map(CsvEdit::Truncate),
    ]
}

/// `csv` with `edits` applied.
fn edited(csv: &str, edits: &[CsvEdit]) -> String {
    let mut rows: Vec<Vec<String>> = csv.lines().map(|l| l.split(',').map(str::to_string).collect()).collect();
    for e in edits {
        let n = rows.len().max(1);
        let data = |r: usize| 1 + r % (n - 1).max(1);
        match e {
            CsvEdit::Cell(r, c, v) => {
                let row = &mut rows[data(*r).min(n - 1)];
                if !row.is_empty() {
                    let k = c % row.len();
                    row[k] = v.clone();
                }
            }
            CsvEdit::Scale(c, f) | CsvEdit::Offset(c, f) => {
                let add = matches!(e, CsvEdit::Offset(..));
                for row in rows.iter_mut().skip(1) {
                    if let Some(x) = row.get_mut(c % 6) {
                        if let Ok(v) = x.parse::<f64>() {
                            *x = format!("{}", if add { v + f } else { v * f });
                        }
                    }
                }
            }
            CsvEdit::DropColumn(c) => {
                for row in &mut rows {
                    if !row.is_empty() {
                        let k = c % row.len();
                        row.remove(k);
                    }
                }
            }
            CsvEdit::RenameColumn(c, name) => {
                if let Some(h) = rows.first_mut().filter(|h| !h.is_empty()) {
                    let k = c % h.len();
                    h[k] = name.clone();
                }
            }
            CsvEdit::DoubleRow(r) => {
                let k = data(*r).min(n - 1);
                let row = rows[k].clone();
                rows.insert(k, row);
            }
            CsvEdit::DropRow(r) => {
                if n > 1 {
                    rows.remove(data(*r).min(n - 1));
                }
            }
            CsvEdit::SwapRows(a, b) => rows.swap(data(*a).min(n - 1), data(*b).min(n - 1)),
            CsvEdit::InsertLine(r, line) => rows.insert(data(*r).min(n), vec![line.clone()]),
            CsvEdit::Truncate(r) => rows.truncate(data(*r)),
        }
    }
    rows.iter().map(|r| r.join(",")).collect::<Vec<_>>().join("\n") + "\n"
}

/// Paths to `null` in a JSON value (NaN and infinities serialise as `null`).
fn nulls(v: &serde_json::Value, at: &str, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Null => out.push(at.to_string()),
        serde_json::Value::Array(a) => a.iter().for_each(|x| nulls(x, &format!("{at}[]"), out)),
        serde_json::Value::Object(o) => o.iter().for_each(|(k, x)| nulls(x, &format!("{at}.{k}"), out)),
        _ => {}
    }
}

/// A cheap problem for the schedules: the paper's cat, a looser engine tolerance.
fn cheap_problem() -> Problem {
    Problem::from_toml("[exact]\ntolerance = 1e-6\ntorque_samples = 20\n", "fuzz.toml", &[])
        .unwrap_or_else(|e| panic!("the fuzz problem loads: {e}"))
}

/// Hostile edits of the paper's schedule at 100 Hz through `parse_schedule` and `evaluate`.
fn schedule_surface(cases: usize) -> Tally {
    let p = cheap_problem();
    let c = paper_circulation(&p.cat.half(), p.manoeuvre.theta()).unwrap_or_else(|e| panic!("{e}"));
    let s = Schedule::new(&p, c);
    let csv =
        write_schedule(&p, &common::measured(&p, &s), &ExportOptions { rate_hz: Some(100.0), ..Default::default() })
            .unwrap_or_else(|e| panic!("the schedule writes: {e}"))
            .csv;
    let clean = evaluate(&p, &parse_schedule(&csv, "fuzz.csv").unwrap_or_else(|e| panic!("{e}")))
        .unwrap_or_else(|e| panic!("the clean schedule evaluates: {e}"));
    let mut allowed = Vec::new();
    nulls(&serde_json::to_value(&clean).unwrap_or_default(), "", &mut allowed);
    fuzz(cases, proptest::collection::vec(csv_edit(), 1..4), |_, edits| {
        let text = edited(&csv, &edits);
        match parse_schedule(&text, "fuzz.csv").and_then(|imported| evaluate(&p, &imported)) {
            Err(e) => refused(with_causes(&e)),
            Ok(report) => {
                let mut found = Vec::new();
                nulls(&serde_json::to_value(&report).unwrap_or_default(), "", &mut found);
                found.retain(|k| !allowed.contains(k));
                let prose = report.to_text();
                let words = prose.split(|c: char| !c.is_alphanumeric()).any(|w| w == "NaN" || w == "inf");
                if !found.is_empty() || words {
                    Outcome::NonFinite(format!("null at {found:?}; text: {}", &prose[..prose.len().min(300)]))
                } else {
                    Outcome::Accepted
                }
            }
        }
    })
}

/// Every file under `root` except those under `skip`, with its contents.
fn snapshot(root: &Path, skip: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for e in entries.filter_map(Result::ok) {
            let path = e.path();
            if path.starts_with(skip) {
                continue;
            }
            if path.is_dir() {
                files.insert(path.clone(), Vec::new());
                stack.push(path);
            } else {
                files.insert(path.clone(), std::fs::read(&path).unwrap_or_default());
            }
        }
    }
    files
}

/// Whether `name` is one folder inside `--out`.
fn inside(name: &str) -> bool {
    let mut parts = Path::new(name).components();
    matches!((parts.next(), parts.next()), (Some(Component::Normal(_)), None))
}

/// A fresh sandbox for `tag`.
fn sandbox(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("catflip-fuzz-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap_or_else(|e| panic!("a sandbox: {e}"));
    d
}

/// Non-finite typed numbers among `records`, said.
fn non_finite(records: &[catflip::sweep::Record]) -> Option<String> {
    records.iter().find_map(|r| {
        let numbers = format!("{:?} {:?} {:?}", r.numbers, r.paper_rad, r.calibrated_rad);
        (numbers.contains("NaN") || numbers.contains("inf"))
            .then(|| format!("case {} {}/{}: {numbers}", r.case, r.schedule, r.engine))
    })
}

/// Runs `write` with `--out` = `root/out` and checks that nothing else under `root` changed, and
/// that the `sweep.csv` written for `sweep` reads back with finite numbers only.
fn contained(root: &Path, sweep: &Sweep, write: impl FnOnce(&Path) -> Result<(), String>) -> Outcome {
    let out = root.join("out");
    let _ = std::fs::remove_dir_all(&out);
    let before = snapshot(root, &out);
    let result = write(&out);
    let after = snapshot(root, &out);
    if before != after {
        let changed: Vec<_> = after.keys().filter(|k| before.get(*k) != after.get(*k)).collect();
        return Outcome::Outside(format!("changed outside --out: {changed:?}"));
    }
    if let Err(e) = result {
        return refused(e);
    }
    let path = out.join(&sweep.name).join("sweep.csv");
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    match catflip::sweep::table::from_csv(sweep, &text, &path.display().to_string()) {
        Err(e) => Outcome::NonFinite(format!("the written {} does not read back: {e}", path.display())),
        Ok(records) => non_finite(&records).map_or(Outcome::Ran, Outcome::NonFinite),
    }
}

/// The sweep file every sweep input edits: an inline cheap base, two axes, peaks only.
const SWEEP: &str = r#"name = "fz"
combine = "product"

[[axis]]
field = "cat.radius"
values = [0.1, 0.2]

[[axis]]
field = "manoeuvre.theta_deg"
range = { from = 100.0, to = 140.0, count = 2, scale = "linear" }

[compute]
paper_flip = true
calibrated = false
peaks = true

[base]
name = "tiny"
[base.exact]
tolerance = 1e-6
torque_samples = 20
"#;

/// Keys of [`SWEEP`] (as `line prefix`) and hostile TOML values for them.
const SWEEP_KEYS: [&str; 10] = [
    "name = ",
    "combine = ",
    "field = ",
    "values = ",
    "range = ",
    "paper_flip = ",
    "peaks = ",
    "tolerance = ",
    "torque_samples = ",
    "calibrated = ",
];
const SWEEP_VALUES: [&str; 36] = [
    "\"fz2\"",
    "[0.15]",
    "[100.0, 120.0]",
    "{ from = 0.1, to = 0.2, count = 2 }",
    "1e-7",
    "40",
    "\"\"",
    "\"..\"",
    "\"/tmp/catflip-fuzz-escape\"",
    "\"a/b\"",
    "\".\"",
    "\"../up\"",
    "\"fz\\u0000\"",
    "\"zip\"",
    "\"product\"",
    "\"cat.mass\"",
    "\"drop.height\"",
    "\"manoeuvre.profile\"",
    "\"nope.nope\"",
    "[]",
    "[1e308, -1e308]",
    "[nan]",
    "[\"cycloidal\", 3]",
    "{ from = 0.0, to = 1.0, count = 0 }",
    "{ from = nan, to = 1.0, count = 2 }",
    "{ from = 1.0, to = 2.0, count = 100000000 }",
    "{ from = 1e-300, to = 1e300, count = 3, scale = \"log\" }",
    "{ from = -1.0, to = 1.0, count = 3, scale = \"log\" }",
    "true",
    "false",
    "0",
    "-1",
    "1e-300",
    "nan",
    "18446744073709551616",
    "{ a = 1 }",
];

fn sweep_surface(cases: usize, run_every: usize) -> Tally {
    let root = sandbox("sweep");
    let dir = root.join("files");
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{e}"));
    let mut accepted = 0;
    let edit = (
        proptest::sample::select(SWEEP_KEYS.to_vec()),
        any::<usize>(),
        proptest::sample::select(SWEEP_VALUES.to_vec()),
    );
    let t = fuzz(cases, proptest::collection::vec(edit, 0..3), |_, edits| {
        let mut lines: Vec<String> = SWEEP.lines().map(str::to_string).collect();
        for (key, nth, value) in &edits {
            let at: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].starts_with(key)).collect();
            if let Some(&i) = at.get(nth % at.len().max(1)) {
                lines[i] = format!("{key}{value}");
            }
        }
        let text = lines.join("\n") + "\n";
        let sweep = match Sweep::from_toml(&text, "fuzz.toml", "fuzz", &dir) {
            Err(e) => return refused(with_causes(&e)),
            Ok(s) => s,
        };
        if !inside(&sweep.name) {
            return Outcome::Outside(format!("results folder `{}` is not inside --out", sweep.name));
        }
        let count = sweep.case_count();
        for i in 0..count.min(8) {
            if let Err(reason) = catflip::sweep::cases::case(&sweep, i).problem(&sweep) {
                if reason.is_empty() || reason.contains('\n') {
                    return Outcome::BadMessage(reason);
                }
            }
        }
        accepted += 1;
        if count > 8 || accepted % run_every != 0 {
            return Outcome::Accepted;
        }
        contained(&root, &sweep, |out| {
            let options = SweepOptions { out: out.to_path_buf(), shard: None, quiet: true, command: "fuzz".into() };
            catflip::sweep::run(&sweep, &options).map(|_| ()).map_err(|e| with_causes(&e))
        })
    });
    let _ = std::fs::remove_dir_all(&root);
    t
}

/// Hostile JSON values for a manifest's leaves.
fn json_value() -> impl Strategy<Value = serde_json::Value> {
    use serde_json::json;
    prop_oneof![
        proptest::sample::select(vec![
            json!(0),
            json!(-1),
            json!(1),
            json!(2),
            json!(3),
            json!(u64::MAX),
            json!(1e308),
            json!(-0.5),
            json!(""),
            json!(".."),
            json!("/tmp/catflip-fuzz-escape"),
            json!("a/b"),
            json!("."),
            json!(null),
            json!(true),
            json!([]),
            json!({}),
            json!("zip"),
            json!("cat.mass"),
            json!([1e308]),
        ]),
        any::<i64>().prop_map(|x| json!(x)),
        "[a-z./]{0,8}".prop_map(|s| json!(s)),
    ]
}

/// One edit of a manifest: the `k`-th leaf (in document order) set to a value, or removed.
#[derive(Clone, Debug)]
enum JsonEdit {
    Set(usize, serde_json::Value),
    Remove(usize),
}

/// The leaf paths of `v`, in document order.
fn leaves(v: &serde_json::Value, at: Vec<String>, out: &mut Vec<Vec<String>>) {
    match v {
        serde_json::Value::Object(o) if !o.is_empty() => {
            o.iter().for_each(|(k, x)| leaves(x, [at.clone(), vec![k.clone()]].concat(), out))
        }
        serde_json::Value::Array(a) if !a.is_empty() => {
            a.iter().enumerate().for_each(|(i, x)| leaves(x, [at.clone(), vec![i.to_string()]].concat(), out))
        }
        _ => out.push(at),
    }
}

fn apply(v: &mut serde_json::Value, path: &[String], edit: &JsonEdit) {
    let Some((last, parents)) = path.split_last() else { return };
    let mut node = v;
    for p in parents {
        node = match node {
            serde_json::Value::Object(o) => match o.get_mut(p) {
                Some(n) => n,
                None => return,
            },
            serde_json::Value::Array(a) => match p.parse::<usize>().ok().and_then(|i| a.get_mut(i)) {
                Some(n) => n,
                None => return,
            },
            _ => return,
        };
    }
    match (node, edit) {
        (serde_json::Value::Object(o), JsonEdit::Set(_, x)) => {
            o.insert(last.clone(), x.clone());
        }
        (serde_json::Value::Object(o), JsonEdit::Remove(_)) => {
            o.remove(last);
        }
        (serde_json::Value::Array(a), JsonEdit::Set(_, x)) => {
            if let Some(slot) = last.parse::<usize>().ok().and_then(|i| a.get_mut(i)) {
                *slot = x.clone();
            }
        }
        (serde_json::Value::Array(a), JsonEdit::Remove(_)) => {
            if let Some(i) = last.parse::<usize>().ok().filter(|&i| i < a.len()) {
                a.remove(i);
            }
        }
        _ => {}
    }
}

fn manifest_surface(cases: usize, merge_every: usize) -> Tally {
    let root = sandbox("manifest");
    let parts_dir = root.join("parts");
    let sweep = Sweep::from_toml(SWEEP, "fuzz.toml", "fuzz", &root).unwrap_or_else(|e| panic!("{e}"));
    let mut parts = Vec::new();
    for k in 1..=2 {
        let options = SweepOptions {
            out: parts_dir.clone(),
            shard: Some(Shard { k, n: 2 }),
            quiet: true,
            command: "fuzz".into(),
        };
        catflip::sweep::run(&sweep, &options).unwrap_or_else(|e| panic!("part {k}: {e}"));
        parts.push(parts_dir.join(Shard { k, n: 2 }.folder(&sweep.name)));
    }
    let originals: Vec<(String, String)> = parts
        .iter()
        .map(|p| {
            let read = |f: &str| std::fs::read_to_string(p.join(f)).unwrap_or_else(|e| panic!("{e}"));
            (read(MANIFEST), read(catflip::sweep::shard::CASES))
        })
        .collect();
    let mut paths = Vec::new();
    let first: serde_json::Value = serde_json::from_str(&originals[0].0).unwrap_or_else(|e| panic!("{e}"));
    leaves(&first, Vec::new(), &mut paths);
    let edit = prop_oneof![
        4 => (any::<usize>(), json_value()).prop_map(|(k, v)| JsonEdit::Set(k, v)),
        1 => any::<usize>().prop_map(JsonEdit::Remove),
    ];
    let input =
        (proptest::collection::vec((0..2usize, edit), 0..4), proptest::collection::vec(csv_edit(), 0..2), 0..2usize);
    let mut accepted = 0;
    let t = fuzz(cases, input, |_, (edits, row_edits, rows_of)| {
        for (p, (manifest, rows)) in parts.iter().zip(&originals) {
            let _ = std::fs::write(p.join(MANIFEST), manifest);
            let _ = std::fs::write(p.join(catflip::sweep::shard::CASES), rows);
        }
        let mut docs: Vec<serde_json::Value> =
            originals.iter().map(|(m, _)| serde_json::from_str(m).unwrap_or_default()).collect();
        for (which, e) in &edits {
            let k = match e {
                JsonEdit::Set(k, _) | JsonEdit::Remove(k) => *k,
            };
            apply(&mut docs[*which], &paths[k % paths.len()], e);
        }
        for (p, doc) in parts.iter().zip(&docs) {
            let _ = std::fs::write(p.join(MANIFEST), doc.to_string());
        }
        if !row_edits.is_empty() {
            let rows = edited(&originals[rows_of].1, &row_edits);
            let _ = std::fs::write(parts[rows_of].join(catflip::sweep::shard::CASES), rows);
        }
        let (merged, records) = match read_parts(&parts) {
            Err(e) => return refused(with_causes(&e)),
            Ok(x) => x,
        };
        if !inside(&merged.name) {
            return Outcome::Outside(format!("results folder `{}` is not inside --out", merged.name));
        }
        // The rows' typed numbers (the text columns may hold any word, "NaN" included).
        if let Some(bad) = non_finite(&records) {
            return Outcome::NonFinite(bad);
        }
        accepted += 1;
        if accepted % merge_every != 0 {
            return Outcome::Accepted;
        }
        contained(&root, &merged, |out| {
            catflip::sweep::merge(&parts, out, "fuzz").map(|_| ()).map_err(|e| with_causes(&e))
        })
    });
    let _ = std::fs::remove_dir_all(&root);
    t
}

fn assert_clean(surface: &str, t: &Tally) {
    t.print(surface);
    assert_eq!(t.failures(), 0, "{surface}: {} failures (see above)", t.failures());
}

#[test]
fn hostile_schedule_files_are_refused_in_one_line_or_give_finite_numbers() {
    assert_clean("schedule files", &schedule_surface(300));
}

#[test]
fn hostile_sweep_files_stay_inside_out_and_are_refused_in_one_line() {
    assert_clean("sweep files", &sweep_surface(400, 10));
}

#[test]
fn hostile_manifests_stay_inside_out_and_are_refused_in_one_line() {
    assert_clean("shard manifests", &manifest_surface(300, 1));
}

#[test]
#[ignore = "10⁵ inputs: cargo test --release --test fuzz_files -- --ignored --nocapture"]
fn fuzz_schedule_files_one_hundred_thousand() {
    assert_clean("schedule files", &schedule_surface(100_000));
}

#[test]
#[ignore = "10⁵ inputs: cargo test --release --test fuzz_files -- --ignored --nocapture"]
fn fuzz_sweep_files_one_hundred_thousand() {
    assert_clean("sweep files", &sweep_surface(100_000, 500));
}

#[test]
#[ignore = "10⁵ inputs: cargo test --release --test fuzz_files -- --ignored --nocapture"]
fn fuzz_manifests_one_hundred_thousand() {
    assert_clean("shard manifests", &manifest_surface(100_000, 50));
}
