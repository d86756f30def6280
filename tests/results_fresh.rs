//! The main job end to end (`catflip run`): its slow checks in one place, one run of
//! problems/paper.toml (on two threads, [`paper_run`]) serving all that read it.
//!
//! - The committed `results/paper/` is what the code produces: every number of its JSON files is
//!   regenerated and compared (run times and other timing fields aside). A stale result in the
//!   repository fails here, not in a reader's hands.
//! - Determinism: the same problem gives bit-identical JSON on rerun, timing fields aside
//!   (`*_time_s` and `seconds`: wall-clock times, which are measurements of the machine, not
//!   results), whatever the number of threads the run's parallel parts get (a second run, on one
//!   thread).
//! - Every result file is written, atomically, and the tables agree with each other.
//! - A run whose rapier verifications all end without a result completes (its own problem).
//!
//! The runs write under `target/tmp/main-job/` (`CARGO_TARGET_TMPDIR`), each folder emptied first.
#![deny(clippy::float_cmp)]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use approx::assert_relative_eq;
use catflip::engines::resolved::Resolved;
use catflip::problem::Problem;
use catflip::report::run::RunOutcome;
use serde_json::Value;

/// The paper's main job, run once per test binary on a pool of two threads.
fn paper_run() -> &'static RunOutcome {
    static RUN: OnceLock<RunOutcome> = OnceLock::new();
    RUN.get_or_init(|| run_paper("two-threads", 2))
}

/// problems/paper.toml run on a pool of `threads` threads into `target/tmp/main-job/<name>`.
fn run_paper(name: &str, threads: usize) -> RunOutcome {
    let problem = Problem::load(Path::new("problems/paper.toml"), &[]).expect("the paper's problem loads");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("main-job").join(name);
    let _ = std::fs::remove_dir_all(&out);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
    pool.install(|| {
        let r = Resolved::new(&problem).expect("the paper's problem resolves");
        catflip::report::run::run(&r, "main job test", &out).expect("the main job runs")
    })
}

/// Keys whose values are wall-clock measurements, not results.
fn is_timing(key: &str) -> bool {
    key.contains("time") || key.contains("seconds")
}

/// Compares two JSON values; pushes every difference (path, committed, regenerated).
fn compare(path: &str, old: &Value, new: &Value, out: &mut Vec<String>) {
    match (old, new) {
        (Value::Object(a), Value::Object(b)) => {
            for (k, va) in a {
                if is_timing(k) {
                    continue;
                }
                match b.get(k) {
                    Some(vb) => compare(&format!("{path}.{k}"), va, vb, out),
                    None => out.push(format!("{path}.{k}: missing from the regenerated result")),
                }
            }
            for k in b.keys().filter(|k| !a.contains_key(*k) && !is_timing(k)) {
                out.push(format!("{path}.{k}: missing from the committed result"));
            }
        }
        (Value::Array(a), Value::Array(b)) => {
            if a.len() != b.len() {
                out.push(format!("{path}: {} entries committed, {} regenerated", a.len(), b.len()));
                return;
            }
            for (i, (va, vb)) in a.iter().zip(b).enumerate() {
                compare(&format!("{path}[{i}]"), va, vb, out);
            }
        }
        (Value::Number(a), Value::Number(b)) => {
            let (x, y) = (a.as_f64().unwrap_or(f64::NAN), b.as_f64().unwrap_or(f64::NAN));
            // Same binary, same inputs: the numbers are reproducible; the margin only allows for
            // the last digits a JSON round trip may print differently.
            if (x - y).abs() > 1e-9 * x.abs().max(y.abs()).max(1e-300) {
                out.push(format!("{path}: committed {x}, regenerated {y}"));
            }
        }
        (a, b) if a != b => out.push(format!("{path}: committed {a}, regenerated {b}")),
        _ => {}
    }
}

/// The JSON value with every wall-clock field (`run_time_s`, `solve_time_s`, …) removed.
fn without_timing(v: serde_json::Value) -> serde_json::Value {
    match v {
        serde_json::Value::Object(m) => m
            .into_iter()
            .filter(|(k, _)| !(k.ends_with("time_s") || k == "seconds"))
            .map(|(k, v)| (k, without_timing(v)))
            .collect(),
        serde_json::Value::Array(a) => a.into_iter().map(without_timing).collect(),
        other => other,
    }
}

fn json_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("the run wrote its folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    files
}

/// The records of a CSV text with its header, by column name.
fn csv_records(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let header = reader.headers().expect("a header").iter().map(str::to_string).collect();
    let rows = reader.records().map(|r| r.expect("a record").iter().map(str::to_string).collect()).collect();
    (header, rows)
}

#[test]
fn committed_paper_results_are_what_the_code_produces() {
    let committed = Path::new("results/paper");
    let outcome = paper_run();
    let mut differences = Vec::new();
    let mut checked = 0;
    for f in outcome.files.iter().filter(|f| f.ends_with(".json")) {
        let read = |p: &Path| std::fs::read_to_string(p).ok().and_then(|t| serde_json::from_str::<Value>(&t).ok());
        let Some(new) = read(&outcome.dir.join(f)) else { panic!("{f}: regenerated file unreadable") };
        match read(&committed.join(f)) {
            Some(old) => compare(f, &old, &new, &mut differences),
            None => differences.push(format!("{f}: not committed (regenerate results/)")),
        }
        checked += 1;
    }
    assert!(checked >= 5, "only {checked} JSON files compared");
    assert!(
        differences.is_empty(),
        "results/paper/ is stale ({} differences; regenerate with `cargo run --release -- run problems/paper.toml`):\n{}",
        differences.len(),
        differences.iter().take(20).cloned().collect::<Vec<_>>().join("\n")
    );
}

#[test]
fn paper_run_gives_identical_json_twice_on_one_and_on_two_threads() {
    let outs: [PathBuf; 2] = [run_paper("one-thread", 1).dir, paper_run().dir.clone()];
    let (a, b) = (json_files(&outs[0]), json_files(&outs[1]));
    assert!(a.len() >= 4, "{a:?}");
    assert_eq!(
        a.iter().map(|p| p.file_name()).collect::<Vec<_>>(),
        b.iter().map(|p| p.file_name()).collect::<Vec<_>>()
    );
    for (x, y) in a.iter().zip(&b) {
        let read = |p: &Path| -> serde_json::Value {
            serde_json::from_str(&std::fs::read_to_string(p).expect("readable JSON")).expect("valid JSON")
        };
        let (vx, vy) = (without_timing(read(x)), without_timing(read(y)));
        // Bit-identical: the serialised text (shortest round-trip floats) must match exactly.
        assert_eq!(vx.to_string(), vy.to_string(), "{} differs between runs", x.display());
    }
    // The animation too: frames drawn in parallel, one palette.
    let gif = |d: &Path| std::fs::read(d.join("plots/flip.gif")).expect("the animation was written");
    assert!(gif(&outs[0]) == gif(&outs[1]), "flip.gif differs between one and two threads");
    let _ = std::fs::remove_dir_all(&outs[0]);
}

#[test]
fn run_prints_the_answer_first_and_one_short_table() {
    // Issue 19: the terminal leads with the optimum's flip and torque against the problem's own
    // schedule, then one row per schedule it names, the numbers those of the report's JSON.
    let outcome = paper_run();
    let first = outcome.summary.lines().next().unwrap_or_default();
    assert!(first.starts_with("The whole-manoeuvre optimum flips the cat"), "{}", outcome.summary);
    let whole: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(outcome.dir.join("whole.json")).expect("readable"))
            .expect("JSON");
    let peak = whole["peak_torque_nm"]["max"].as_f64().expect("the optimum's peak");
    assert!(first.contains(&format!("peak torque of {peak:.4} N·m")), "{first} (whole.json: {peak})");
    let row = |name: &str| outcome.summary.lines().find(|l| l.starts_with(&format!("| {name}"))).map(str::to_string);
    assert!(row("whole-optimum").is_some_and(|r| r.contains(&format!("| {peak:.4} |"))), "{}", outcome.summary);
    assert!(row("paper-cosine (the problem's)").is_some(), "{}", outcome.summary);
    let rows = outcome.summary.lines().filter(|l| l.starts_with("| ")).count();
    assert!(rows <= 10, "a short table: {rows} lines\n{}", outcome.summary);
    assert!(outcome.summary.contains("report.md"), "{}", outcome.summary);
}

#[test]
fn run_writes_every_result_file_atomically() {
    let outcome = paper_run();
    let out = outcome.dir.parent().expect("the results folder is inside its output root");
    for f in [
        "report.md",
        "audit.md",
        "audit.json",
        "compare.md",
        "compare.csv",
        "optimize.json",
        "verification.csv",
        "schedules/problem.csv",
        "plots/flip.gif",
    ] {
        let path = outcome.dir.join(f);
        assert!(std::fs::metadata(&path).map(|m| m.len() > 0).unwrap_or(false), "{f} missing or empty");
    }
    // No scratch folder is left behind.
    let leftovers: Vec<_> = std::fs::read_dir(out)
        .expect("exists")
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    // compare.csv has the whole-manoeuvre optimum's row as compare.md has it: the same columns,
    // empty where the paper's profile model does not apply.
    let (header, rows) = csv_records(&std::fs::read_to_string(outcome.dir.join("compare.csv")).expect("readable"));
    let col = |name: &str| header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"));
    let whole = rows.iter().find(|r| r[col("profile")] == "whole-optimum").expect("the optimum's row");
    assert_eq!(whole.len(), header.len());
    for empty in ["rest_to_rest", "accel_coefficient", "model_peak_nm", "circulation_rad"] {
        assert!(whole[col(empty)].is_empty(), "{empty}: {whole:?}");
    }
    assert_eq!((whole[col("origin")].as_str(), whole[col("velocity_jumps")].as_str()), ("whole", "0"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(outcome.dir.join("whole.json")).expect("readable"))
            .expect("JSON");
    let peak = json["peak_torque_nm"]["max"].as_f64().expect("the optimum's peak");
    assert_relative_eq!(whole[col("max_nm")].parse::<f64>().expect("a number"), peak, max_relative = 1e-8);
    assert_relative_eq!(whole[col("twist_deg")].parse::<f64>().expect("a number").abs(), 180.0, epsilon = 1e-6);
    let md = std::fs::read_to_string(outcome.dir.join("compare.md")).expect("readable");
    let md_rows = md.lines().filter(|l| l.starts_with("| ") && !l.starts_with("| profile")).count();
    assert_eq!(md_rows, rows.len(), "compare.md and compare.csv have the same rows");
    assert!(
        md.contains(&format!(
            "| whole-optimum | whole | — | — | {:.3}, ",
            whole[col("bend_tau1_nm")].parse::<f64>().expect("a number")
        )),
        "{md}"
    );
    // The schedule CSV replays the schedule: first row at rest and straight, last row straight.
    let csv = std::fs::read_to_string(outcome.dir.join("schedules/problem.csv")).expect("readable");
    let last = csv.lines().last().unwrap_or_default();
    let fields: Vec<f64> = last.split(',').filter_map(|x| x.parse().ok()).collect();
    assert!(fields[1].abs() < 1e-12 && fields[2].abs() < 1e-12, "{last}");
}

/// Every schedule of the run's peak-torque table is verified in rapier (DESIGN.md §6), and the
/// measurements line up: `simulate_exact.json` and `simulate_rapier.json` hold the same schedules
/// in the same order, the table's rows but the whole optimum's (in its own files) and the most
/// refined schedule with the calibrated circulation.
#[test]
fn run_verifies_every_schedule_it_reports() {
    let outcome = paper_run();
    let read = |f: &str| std::fs::read_to_string(outcome.dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
    let json = |f: &str| -> Vec<serde_json::Value> {
        serde_json::from_str::<serde_json::Value>(&read(f)).expect("JSON").as_array().cloned().expect("a list")
    };
    let (exact, rapier) = (json("simulate_exact.json"), json("simulate_rapier.json"));
    let (_, table) = csv_records(&read("compare.csv"));
    // The table's rows, less the optimum's, plus the calibrated schedule's.
    assert_eq!(exact.len(), table.len());
    assert_eq!(rapier.len(), exact.len());
    for (e, x) in exact.iter().zip(&rapier) {
        assert_eq!((&e["profile"], &e["circulation_rad"]), (&x["profile"], &x["circulation_rad"]));
        assert_eq!(x["engine"], "rapier", "{x}");
        assert!(x["verdict"].is_string(), "every rapier entry ends in a verdict: {x}");
    }
}

#[test]
fn a_run_without_rapier_results_completes_with_inconclusive_rows() {
    // A step budget below rapier's first run: no verification makes a usable run, so rapier has
    // no number for any schedule. That is a reported outcome, not a failed run: every file is
    // written, each verification row says `inconclusive` and why, and no table shows a NaN.
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("main-job").join("inconclusive");
    let _ = std::fs::remove_dir_all(&out);
    let mut p = Problem::default();
    p.optimize.nodes = 61;
    p.rapier.step_budget = 1;
    let outcome = catflip::report::run::run(&Resolved::new(&p).expect("resolves"), "test", &out)
        .expect("an inconclusive verification does not fail the run");
    let read = |f: &str| std::fs::read_to_string(outcome.dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
    let (header, rows) = csv_records(&read("verification.csv"));
    let col = |name: &str| header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"));
    let (rapier, exact): (Vec<_>, Vec<_>) = rows.iter().partition(|r| r[col("engine")] == "rapier");
    assert!(!rapier.is_empty() && rapier.len() == exact.len(), "{} rapier rows, {} exact", rapier.len(), exact.len());
    // The whole optimum's two rows beside the schedules': the same verdict, no circulation.
    let whole = |r: &[String]| r[col("schedule")] == "whole-optimum";
    let wholes = |rows: &[&Vec<String>]| rows.iter().filter(|r| whole(&r[..])).count();
    assert_eq!((wholes(&rapier), wholes(&exact)), (1, 1), "{rows:?}");
    for r in &rapier {
        assert_eq!(r[col("verdict")], "inconclusive", "{r:?}");
        let reason = &r[col("verdict_reason")];
        assert!(reason.starts_with("inconclusive: 0 of the 3 runs") && reason.contains("budget of 1 steps"), "{r:?}");
        for empty in ["twist_deg", "swing_deg", "max_nm", "momentum_max", "dt_s", "tracking1_rad"] {
            assert!(r[col(empty)].is_empty(), "{empty} of {r:?}");
        }
        assert_eq!(r[col("circulation_rad")].is_empty(), whole(&r[..]), "{r:?}");
    }
    assert!(exact.iter().all(|r| !r[col("twist_deg")].is_empty() && r[col("verdict")].is_empty()));
    assert!(exact.iter().all(|r| r[col("max_nm")].parse::<f64>().is_ok()), "every exact row has its peak");
    // The Markdown row of each schedule: the exact engine's numbers, — for rapier's, the verdict.
    let md = read("verification.md");
    let schedule_rows: Vec<&str> =
        md.lines().filter(|l| l.starts_with("| ") && l.contains("inconclusive: 0 of the 3 runs")).collect();
    assert_eq!(schedule_rows.len(), rapier.len(), "the schedules and the whole optimum, as in the CSV:\n{md}");
    for l in &schedule_rows {
        let cells: Vec<&str> = l.split(" | ").collect();
        assert!(cells[1].parse::<f64>().is_ok() && cells[2] == "—" && cells[3] == "—", "{l}");
    }
    // simulate_rapier.json: null numbers beside the verdict and its reason.
    let json: serde_json::Value = serde_json::from_str(&read("simulate_rapier.json")).expect("JSON");
    let entries = json.as_array().expect("a list");
    assert_eq!(entries.len(), rapier.len() - 1, "the schedules'");
    for e in entries {
        assert!(e["engine"] == "rapier" && e["verdict"] == "inconclusive", "{e}");
        assert!(e["twist_deg"].is_null() && e["peak_torque_nm"].is_null(), "{e}");
        assert!(e["reason"].as_str().is_some_and(|r| r.starts_with("inconclusive: ")), "{e}");
    }
    // The report's summary counts them; the terminal's table says so on every row.
    let n = rapier.len() - 1; // the schedules (the report counts the whole optimum on its own line)
    let report = read("report.md");
    let counted = format!("0 verified, 0 not verified, {n} inconclusive");
    assert!(report.contains(&counted), "{report}");
    assert!(report.contains(&format!("rapier has no result for {n} of them")), "{report}");
    let rows: Vec<&str> =
        outcome.summary.lines().filter(|l| l.starts_with("| ") && !l.starts_with("| schedule")).collect();
    assert!(!rows.is_empty() && rows.iter().all(|l| l.ends_with("| inconclusive |")), "{}", outcome.summary);
    for f in outcome.files.iter().filter(|f| f.ends_with(".md") || f.ends_with(".csv")) {
        assert!(!read(f).contains("NaN"), "NaN in {f}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn run_checks_the_optimums_robustness_as_robust_does_on_its_exported_schedule() {
    // Issue 21 §2: `run` has a robustness section. Its trials are `catflip robust`'s on the
    // same schedule: the exported whole optimum, read back, gives the same landing errors to the
    // file's sampling (the CSV is a dense spline interpolant of the optimum, not the optimum).
    let outcome = paper_run();
    let read = |f: &str| std::fs::read_to_string(outcome.dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
    let json: Value = serde_json::from_str(&read("robust.json")).expect("robust.json is JSON");
    let check = &json["checks"][0];
    assert_eq!(check["engine"], "exact", "{check}");
    let p95 = check["landing_error_deg"]["p95"].as_f64().expect("a 95th percentile");
    let problem = Problem::load(Path::new("problems/paper.toml"), &[]).expect("loads");
    let file = catflip::exchange::read_schedule(&outcome.dir.join("schedules/whole-optimum.csv")).expect("reads");
    let again = catflip::robust::robustness(&problem, &file, "file").expect("the paper's cat has two motors");
    assert_relative_eq!(again.landing_error_deg.p95, p95, max_relative = 1e-4);
    assert_eq!(check["trials"], Value::Null, "the trials are in robust.csv, not the JSON");
    let report = read("report.md");
    let verdict = check["verdict"].as_str().expect("a verdict");
    assert!(report.contains(verdict), "report.md quotes the verdict {verdict:?}");
    assert!(outcome.summary.lines().nth(1).is_some_and(|l| l.contains(verdict)), "{}", outcome.summary);
    let csv = read("robust.csv");
    assert_eq!(csv.lines().count(), 1 + problem.robust.trials, "a header and one row per trial:\n{csv}");
    for plot in ["plots/robust_histogram.png", "plots/robust.png"] {
        assert!(outcome.files.iter().any(|f| f == plot), "{plot} not in {:?}", outcome.files);
    }
}
