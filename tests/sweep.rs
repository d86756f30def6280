//! Sweeps: expansion of the axes into cases, refused cases that carry their reason, output that is
//! byte-identical whatever the thread count, shards that merge into the single run, and the
//! command line end to end.

mod common;

use common::catflip;
use std::path::{Path, PathBuf};

use approx::assert_relative_eq;
use catflip::sweep::cases::{case, cases};
use catflip::sweep::spec::{SpecError, Sweep};
use catflip::sweep::table::{from_csv, to_csv, Record};
use catflip::sweep::{evaluate, merge, run, Shard, Status, SweepOptions};

/// A fresh folder under the system's temporary directory, unique to this test and run.
fn scratch(name: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
    let d = std::env::temp_dir().join(format!("catflip-sweep-{name}-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&d).expect("scratch folder");
    d
}

/// The sweep text with an inline base problem (the paper's cat, a cheaper tolerance).
fn with_base(rest: &str) -> String {
    format!("name = \"t\"\n{rest}\n[base]\nname = \"tiny\"\n[base.exact]\ntolerance = 1e-8\ntorque_samples = 40\n")
}

fn sweep(text: &str) -> Result<Sweep, SpecError> {
    Sweep::from_toml(text, "test.toml", "test", Path::new("."))
}

fn sweep_ok(text: &str) -> Sweep {
    match sweep(text) {
        Ok(s) => s,
        Err(e) => panic!("the sweep should load: {e}"),
    }
}

/// The bad field named by a spec error.
fn bad_field(text: &str) -> (String, String) {
    match sweep(text) {
        Err(SpecError::BadField { field, reason }) => (field, reason),
        Err(e) => panic!("expected a BadField error, got {e}"),
        Ok(_) => panic!("expected the sweep to be refused"),
    }
}

const TWO_AXES: &str = r#"
[[axis]]
field = "manoeuvre.bend_path"
values = ["joint-circle", "cone"]
[[axis]]
field = "manoeuvre.theta_deg"
range = { from = 120.0, to = 150.0, count = 3 }
"#;

#[test]
fn a_product_varies_the_first_axis_slowest() {
    let s = sweep_ok(&with_base(TWO_AXES));
    assert_eq!(s.case_count(), 6);
    let all = cases(&s);
    let overrides: Vec<Vec<String>> = all.iter().map(|c| c.overrides.clone()).collect();
    assert_eq!(overrides[0], ["manoeuvre.bend_path=\"joint-circle\"", "manoeuvre.theta_deg=120.0"]);
    assert_eq!(overrides[2], ["manoeuvre.bend_path=\"joint-circle\"", "manoeuvre.theta_deg=150.0"]);
    assert_eq!(overrides[3], ["manoeuvre.bend_path=\"cone\"", "manoeuvre.theta_deg=120.0"]);
    assert_eq!(all[4].picks, [1, 1]);
    // Each case is a problem the problem file itself built from those overrides.
    let p = all[4].problem(&s).expect("case 4 loads");
    assert_eq!(p.manoeuvre.bend_path, catflip::problem::BendPath::Cone);
    assert_relative_eq!(p.manoeuvre.theta_deg, 135.0, max_relative = 1e-15);
}

#[test]
fn zip_takes_the_kth_value_of_every_axis_and_needs_equal_lengths() {
    let s = sweep_ok(&with_base(&format!("combine = \"zip\"\n{}", TWO_AXES.replace("count = 3", "count = 2"))));
    assert_eq!(s.case_count(), 2);
    assert_eq!(case(&s, 1).overrides, ["manoeuvre.bend_path=\"cone\"", "manoeuvre.theta_deg=150.0"]);
    let (field, reason) = bad_field(&with_base(&format!("combine = \"zip\"\n{TWO_AXES}")));
    assert_eq!(field, "combine");
    assert!(reason.contains("`manoeuvre.theta_deg` has 3"), "{reason}");
}

#[test]
fn linear_and_log_ranges_include_both_ends_exactly() {
    let lin = sweep_ok(&with_base("[[axis]]\nfield = \"cat.radius\"\nrange = { from = 0.1, to = 0.2, count = 5 }"));
    let v: Vec<f64> = lin.axes[0].values.iter().filter_map(toml::Value::as_float).collect();
    assert_eq!(v.len(), 5);
    for (x, want) in v.iter().zip([0.1, 0.125, 0.15, 0.175, 0.2]) {
        assert_relative_eq!(*x, want, max_relative = 1e-15);
    }
    assert_eq!(v[0].to_bits(), 0.1f64.to_bits());
    assert_eq!(v[4].to_bits(), 0.2f64.to_bits());
    let log = sweep_ok(&with_base(
        "[[axis]]\nfield = \"drop.height\"\nrange = { from = 0.01, to = 100.0, count = 5, scale = \"log\" }",
    ));
    let v: Vec<f64> = log.axes[0].values.iter().filter_map(toml::Value::as_float).collect();
    for (x, want) in v.iter().zip([0.01, 0.1, 1.0, 10.0, 100.0]) {
        assert_relative_eq!(*x, want, max_relative = 1e-14);
    }
    assert_eq!((v[0].to_bits(), v[4].to_bits()), (0.01f64.to_bits(), 100.0f64.to_bits()));
    // The override carries the value to the problem without loss.
    let p = case(&log, 1).problem(&log).expect("loads");
    assert_eq!(p.drop.height.to_bits(), v[1].to_bits());
}

#[test]
fn a_bad_axis_is_refused_with_its_field_named() {
    let (field, reason) = bad_field(&with_base("[[axis]]\nfield = \"cat.radus\"\nvalues = [0.1]"));
    assert_eq!(field, "axis[0].field");
    assert!(reason.contains("`cat.radus` is not a problem field") && reason.contains("`radius`"), "{reason}");
    // The fields offered are the section's, the optional ones too (the defaults' leaves alone left
    // out every motor limit, which an axis may name).
    let (_, reason) = bad_field(&with_base("[[axis]]\nfield = \"actuator.torque_limt_nm\"\nvalues = [0.1]"));
    assert!(reason.contains("`torque_limit_nm`") && reason.contains("in `actuator`"), "{reason}");
    // A value the field cannot hold is the file's mistake, not a refused case (a QA run's sweep
    // with a string among numbers, or a misspelt profile, ran with exit 0 and "refused" rows).
    let (field, reason) = bad_field(&with_base("[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1, \"0.2\", 0.3]"));
    assert_eq!(field, "axis[0].values[1]");
    assert!(reason.contains("expected a number in `cat.radius`"), "{reason}");
    let (field, reason) =
        bad_field(&with_base("[[axis]]\nfield = \"manoeuvre.profile\"\nvalues = [\"cycloidal\", \"cycloïdal\"]"));
    assert_eq!(field, "axis[0].values[1]");
    assert!(reason.contains("unknown variant `cycloïdal`"), "{reason}");
    // An optional field (none in the defaults) with a value of the wrong type: the value, not
    // the field, is wrong; an integer out of its field's range is found wherever it stands.
    let (field, reason) = bad_field(&with_base("[[axis]]\nfield = \"optimize.rate_limit\"\nvalues = [\"fast\"]"));
    assert_eq!(field, "axis[0].values[0]", "{reason}");
    let (field, reason) = bad_field(&with_base("[[axis]]\nfield = \"robust.seed\"\nvalues = [1, 2, -3]"));
    assert_eq!(field, "axis[0].values[2]", "{reason}");
    // A value that is no number is refused wherever it stands (a review's `[0.1, nan]` ran and
    // wrote a `NaN` row: only the first float was tried).
    for (values, k) in [("[0.1, nan]", 1), ("[inf, 0.2]", 0), ("[0.1, 0.2, -inf]", 2)] {
        let (field, reason) = bad_field(&with_base(&format!("[[axis]]\nfield = \"cat.radius\"\nvalues = {values}")));
        assert_eq!(field, format!("axis[0].values[{k}]"), "{values}");
        assert!(reason.ends_with("must be a finite number"), "{reason}");
    }
    let (field, reason) = bad_field(&with_base("[[axis]]\nfield = \" cat.radius\"\nvalues = [0.1]"));
    assert_eq!((field.as_str(), reason.as_str()), ("axis[0].field", "` cat.radius` holds spaces: write `cat.radius`"));
    let (field, _) = bad_field(&with_base(
        "[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1]\nrange = { from = 1.0, to = 2.0, count = 2 }",
    ));
    assert_eq!(field, "axis[0].values");
    let (field, _) = bad_field(&with_base(
        "[[axis]]\nfield = \"cat.radius\"\nrange = { from = -1.0, to = 2.0, count = 3, scale = \"log\" }",
    ));
    assert_eq!(field, "axis[0].range.scale");
    let (field, _) =
        bad_field(&with_base("[[axis]]\nfield = \"cat.radius\"\nrange = { from = 1.0, to = 2.0, count = 0 }"));
    assert_eq!(field, "axis[0].range.count");
    // One value cannot be both ends of a range: refused unless they are equal.
    let (field, reason) =
        bad_field(&with_base("[[axis]]\nfield = \"cat.radius\"\nrange = { from = 0.05, to = 0.1, count = 1 }"));
    assert_eq!(field, "axis[0].range.count", "{reason}");
    assert!(reason.contains("0.05") && reason.contains("0.1") && reason.contains("count >= 2"), "{reason}");
    let one = sweep_ok(&with_base("[[axis]]\nfield = \"cat.radius\"\nrange = { from = 0.05, to = 0.05, count = 1 }"));
    assert_eq!(one.axes[0].values, [toml::Value::Float(0.05)]);
    let (field, reason) = bad_field(&with_base(
        "[[axis]]\nfield = \"cat.mass\"\nvalues = [1.0]\n[[axis]]\nfield = \"cat.mass\"\nvalues = [2.0]",
    ));
    assert_eq!(field, "axis[1].field", "{reason}");
    // An optional field absent from the defaults is still a field.
    sweep_ok(&with_base("[[axis]]\nfield = \"optimize.rate_limit\"\nvalues = [10.0]"));
    match sweep(&with_base("[compute]\nrapid = true")) {
        Err(SpecError::Parse { message, .. }) => assert!(message.contains("rapid"), "{message}"),
        other => panic!("an unknown key must be refused by name: {other:?}"),
    }
}

#[test]
fn a_base_problem_file_that_cannot_be_read_is_refused_naming_base() {
    let dir = scratch("no-base");
    let text = "base = \"nonexist.toml\"\n[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1]\n";
    match Sweep::from_toml(text, "s.toml", "s", &dir) {
        Err(SpecError::BadField { field, reason }) => {
            assert_eq!(field, "base", "{reason}");
            let path = dir.join("nonexist.toml");
            assert!(reason.contains(&format!("cannot read the problem file {}", path.display())), "{reason}");
        }
        Err(e) => panic!("expected the `base` field named, got {e}"),
        Ok(_) => panic!("a sweep without its base problem must be refused"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_file_that_is_not_a_sweep_is_refused_on_its_line_and_a_problem_file_is_named_as_one() {
    // A problem file given to `sweep`: the line of its first section, the parser's message on one
    // line (it quoted the file across several, squashed into one), and what a sweep file is.
    let problem = std::fs::read_to_string("problems/paper.toml").expect("a committed problem");
    let e = sweep(&problem).map(|_| ()).expect_err("refused").to_string();
    assert!(e.starts_with("sweep file test.toml, line 5: unknown field `cat`, expected one of"), "{e}");
    assert!(e.contains("(this reads as a problem file: a sweep file names its problem as base ="), "{e}");
    assert!(!e.contains('|') && !e.contains('^'), "the parser's quotation of the file: {e}");
    // A sweep file's own slip: its line, and no hint about problem files.
    let e =
        sweep("base = \"problems/paper.toml\"\n[[axis]]\nfeild = \"cat.radius\"\n").map(|_| ()).expect_err("refused");
    let e = e.to_string();
    assert!(e.starts_with("sweep file test.toml, line 3: unknown field `feild`"), "{e}");
    assert!(!e.contains("problem file:"), "{e}");
}

#[test]
fn a_refused_case_carries_its_reason_and_never_a_nan() {
    // θ = 90° on the cone path is gimbal lock; θ = 200° is no angle between the halves.
    let s = sweep_ok(&with_base(
        "[[axis]]\nfield = \"manoeuvre.bend_path\"\nvalues = [\"cone\"]\n[[axis]]\nfield = \"manoeuvre.theta_deg\"\nvalues = [90.0, 200.0, 135.0]\n[compute]\nrapier = true",
    ));
    let records = evaluate(&s, 0..s.case_count(), false);
    let exact: Vec<_> = records.iter().filter(|r| r.engine.name() == "exact").collect();
    assert_eq!(exact.len(), 6, "paper and calibrated rows of three cases");
    for r in &exact[..4] {
        assert_eq!(r.status, Status::Refused, "case {}", r.case);
        assert!(r.numbers.is_none());
        assert!(!r.reason.is_empty() && !r.reason.contains('\n'), "{}", r.reason);
    }
    assert!(exact[0].reason.contains("gimbal lock"), "{}", exact[0].reason);
    assert!(exact[2].reason.contains("manoeuvre.theta_deg = 200"), "{}", exact[2].reason);
    assert!(exact[4..].iter().all(|r| r.status == Status::Ok && r.numbers.is_some()));
    // Rapier checks each exact row: a refused case's rapier rows carry the case's reason, the
    // computed case's are verified or say what they found.
    let rapier: Vec<_> = records.iter().filter(|r| r.engine.name() == "rapier").collect();
    assert_eq!(rapier.len(), 6);
    for r in &rapier[..4] {
        assert_eq!(r.status, Status::Refused);
        assert_eq!(r.reason, exact[if r.case == 0 { 0 } else { 2 }].reason);
    }
    for r in &rapier[4..] {
        assert_eq!(r.status, Status::Ok, "{}", r.reason);
        assert!(!r.labels.rapier_verdict.is_empty());
    }
    let csv = to_csv(&s, &records).expect("CSV");
    let lower = csv.to_lowercase();
    assert!(!lower.contains("nan") && !lower.contains("inf"), "{csv}");
    assert!(csv.lines().nth(1).is_some_and(|l| l.contains(",refused,") && l.contains("gimbal")), "{csv}");
}

/// A sweep of four cases with calibration and peaks.
fn small() -> Sweep {
    sweep_ok(&with_base(
        "[[axis]]\nfield = \"cat.radius\"\nvalues = [0.08, 0.2]\n[[axis]]\nfield = \"manoeuvre.theta_deg\"\nvalues = [45.0, 135.0]",
    ))
}

#[test]
fn output_is_byte_identical_whatever_the_thread_count() {
    let s = small();
    let csv_with = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a rayon pool");
        let records = pool.install(|| evaluate(&s, 0..s.case_count(), false));
        to_csv(&s, &records).expect("CSV")
    };
    let one = csv_with(1);
    let two = csv_with(2);
    assert_eq!(one.lines().count(), 1 + 4 * 2, "{one}");
    assert!(one == two, "1 thread and 2 threads differ:\n{one}\n---\n{two}");
}

/// Every file under `dir`, relative path and bytes, sorted.
fn tree(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("readable").flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).map_or_else(|_| p.display().to_string(), |r| r.display().to_string());
                out.push((rel, std::fs::read(&p).expect("readable")));
            }
        }
    }
    out.sort();
    out
}

/// The report after its provenance header (date, machine and command differ between runs).
fn body(md: &[u8]) -> String {
    let text = String::from_utf8_lossy(md);
    text.split_once("</details>").map_or_else(|| text.to_string(), |(_, b)| b.to_string())
}

#[test]
fn merged_shards_equal_the_single_run() {
    let s = small();
    let root = scratch("merge");
    let options =
        |out: &Path, shard| SweepOptions { out: out.to_path_buf(), shard, quiet: true, command: "test".into() };
    let single = run(&s, &options(&root.join("single"), None)).expect("single run");
    let mut parts = Vec::new();
    for k in [3, 1, 2] {
        let part = run(&s, &options(&root.join("parts"), Some(Shard { k, n: 3 }))).expect("shard");
        parts.push(part.dir);
    }
    // Merging refuses an incomplete set, naming what is missing.
    match merge(&parts[..2], &root.join("merged"), "test") {
        Err(e) => assert!(e.to_string().contains("missing shard 2 of 3"), "{e}"),
        Ok(_) => panic!("an incomplete set of parts must not merge"),
    }
    let merged = merge(&parts, &root.join("merged"), "test").expect("merge");
    assert_eq!((merged.cases, merged.rows), (single.cases, single.rows));
    let (a, b) = (tree(&single.dir), tree(&merged.dir));
    assert_eq!(a.iter().map(|f| &f.0).collect::<Vec<_>>(), b.iter().map(|f| &f.0).collect::<Vec<_>>());
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        match name.as_str() {
            "sweep.md" => assert_eq!(body(x), body(y), "{name}"),
            _ => assert!(x == y, "{name} differs between the single run and the merge"),
        }
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn shards_slice_the_cases_contiguously_and_completely() {
    for total in [0usize, 1, 7, 10, 10_000] {
        for n in [1usize, 2, 3, 16] {
            let ranges: Vec<_> = (1..=n).map(|k| Shard { k, n }.range(total)).collect();
            assert_eq!(ranges[0].start, 0);
            assert_eq!(ranges[n - 1].end, total);
            assert!(ranges.windows(2).all(|w| w[0].end == w[1].start));
        }
    }
    assert_eq!("3/16".parse::<Shard>(), Ok(Shard { k: 3, n: 16 }));
    assert!("0/4".parse::<Shard>().is_err() && "5/4".parse::<Shard>().is_err() && "x".parse::<Shard>().is_err());
    let huge = "99999999999999999999/3".parse::<Shard>().expect_err("beyond usize");
    assert!(huge.ends_with("K is too large (at most 18446744073709551615)"), "{huge}");
    assert!("1.5/3".parse::<Shard>().expect_err("not whole").ends_with("K must be a whole number"));
}

#[test]
fn the_command_line_runs_shards_and_merges_a_tiny_sweep() {
    let root = scratch("cli");
    let file = root.join("tiny.toml");
    std::fs::write(
        &file,
        with_base("[[axis]]\nfield = \"manoeuvre.profile\"\nvalues = [\"cycloidal\", \"bang-bang\"]\n[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1, 0.2]"),
    )
    .expect("write the sweep file");
    let (f, out) = (file.display().to_string(), root.join("out").display().to_string());
    let (code, stdout, stderr) = catflip(&["sweep", &f, "--out", &out, "--json", "--quiet"]);
    assert_eq!(code, 0, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON object");
    assert_eq!((v["cases"].as_u64(), v["rows"].as_u64()), (Some(4), Some(8)), "{stdout}");
    let single = std::fs::read(root.join("out/t/sweep.csv")).expect("the CSV is written");
    let md = std::fs::read_to_string(root.join("out/t/sweep.md")).expect("the report is written");
    assert!(md.contains("## Best `manoeuvre.profile` by peak torque"), "{md}");
    for k in ["1/2", "2/2"] {
        let (code, _, stderr) = catflip(&["sweep", &f, "--out", &out, "--shard", k, "--quiet"]);
        assert_eq!(code, 0, "{stderr}");
    }
    let merged = root.join("merged").display().to_string();
    let p1 = root.join("out/t.part-1-of-2").display().to_string();
    let p2 = root.join("out/t.part-2-of-2").display().to_string();
    let (code, _, stderr) = catflip(&["sweep", "--merge", &p2, &p1, "--out", &merged]);
    assert_eq!(code, 0, "{stderr}");
    assert!(std::fs::read(root.join("merged/t/sweep.csv")).expect("merged CSV") == single);
    // A bad sweep file fails with the field named, and leaves the previous results in place.
    std::fs::write(&file, with_base("[[axis]]\nfield = \"cat.radus\"\nvalues = [0.1]")).expect("rewrite");
    let (code, _, stderr) = catflip(&["sweep", &f, "--out", &out]);
    assert_ne!(code, 0);
    assert!(stderr.contains("axis[0].field") && stderr.contains("cat.radus"), "{stderr}");
    assert!(std::fs::read(root.join("out/t/sweep.csv")).expect("still there") == single);
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_case_gives_the_numbers_simulate_gives_for_its_problem() {
    // The same problem through `simulate` (the library's one-problem path) and through a sweep
    // case: the same code, so the same bits.
    let mut problem = catflip::problem::Problem::default();
    problem.manoeuvre.profile = catflip::problem::ProfileKind::Cycloidal;
    let outcome = catflip::sweep::evaluate_case(&problem, &catflip::sweep::Compute::default());
    let row =
        |s: &str| outcome.rows.iter().find(|r| r.schedule.name() == s).and_then(|r| r.numbers).expect("an ok row");
    let (paper, calibrated) = (row("paper"), row("calibrated"));
    let sim_paper = catflip::report::simulate::simulate(
        &catflip::engines::resolved::Resolved::new(&problem).expect("resolves"),
        catflip::engines::Engine::Exact,
    )
    .expect("simulates");
    problem.manoeuvre.circulation = catflip::problem::Circulation::Calibrated;
    let sim_cal = catflip::report::simulate::simulate(
        &catflip::engines::resolved::Resolved::new(&problem).expect("resolves"),
        catflip::engines::Engine::Exact,
    )
    .expect("simulates");
    for (n, sim) in [(paper, &sim_paper), (calibrated, &sim_cal)] {
        assert_eq!(n.circulation_rad.map(f64::to_bits), Some(sim.circulation_rad.to_bits()));
        assert_eq!(n.twist_deg.to_bits(), sim.figures.twist_deg.to_bits());
        assert_eq!(n.swing_deg.to_bits(), sim.figures.swing_deg.to_bits());
        assert_eq!(n.peaks, Some(sim.peak_torque_nm));
        assert_eq!(n.peak_nm.map(f64::to_bits), Some(sim.peak_torque_nm.max.to_bits()));
    }
    // The calibrated schedule flips by π to the tolerance; the paper's misses (DESIGN.md §4).
    assert!(calibrated.flip_error_deg.abs() < 1e-10_f64.to_degrees() * 2.0, "{}", calibrated.flip_error_deg);
    assert!(paper.flip_error_deg.abs() > 0.1, "{}", paper.flip_error_deg);
    assert_relative_eq!(
        outcome.circulation_error().expect("both circulations"),
        calibrated.circulation_rad.expect("a circulation") - paper.circulation_rad.expect("a circulation"),
        max_relative = 1e-15
    );
}

#[test]
fn a_given_circulation_adds_its_own_row() {
    let s = sweep_ok(
        &with_base("[compute]\npeaks = false")
            .replace("name = \"tiny\"", "name = \"tiny\"\n[base.manoeuvre]\ncirculation = 3.3"),
    );
    let records = evaluate(&s, 0..1, false);
    let schedules: Vec<&str> = records.iter().map(|r| r.schedule.name()).collect();
    assert_eq!(schedules, ["paper", "calibrated", "given"]);
    let given = records[2].numbers.expect("computed");
    assert_eq!(given.circulation_rad.map(f64::to_bits), Some(3.3f64.to_bits()));
    assert!(given.peaks.is_none(), "peaks were not asked for");
}

/// Two cases with the retiming, the whole-manoeuvre optimum (a coarse 12-point spline, the base
/// problem's `optimize.whole.control_points`, for speed) and rapier on.
fn optimised() -> Sweep {
    sweep_ok(&format!(
        "{}[base.optimize.whole]\ncontrol_points = 12\n",
        with_base("[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1, 0.2]\n[compute]\nretiming = true\nwhole = true\nrapier = true")
    ))
}

/// The record of a case's schedule through an engine.
fn row<'a>(records: &'a [Record], case: usize, schedule: &str, engine: &str) -> &'a Record {
    records
        .iter()
        .find(|r| r.case == case && r.schedule.name() == schedule && r.engine.name() == engine)
        .unwrap_or_else(|| panic!("no {schedule}/{engine} row for case {case}"))
}

#[test]
fn retiming_whole_optimum_and_rapier_give_numbers_or_a_stated_status() {
    let s = optimised();
    let records = evaluate(&s, 0..s.case_count(), false);
    let order: Vec<(&str, &str)> =
        records.iter().filter(|r| r.case == 0).map(|r| (r.schedule.name(), r.engine.name())).collect();
    let want = ["paper", "calibrated", "retimed", "whole"];
    let expected: Vec<(&str, &str)> =
        want.iter().map(|&x| (x, "exact")).chain(want.iter().map(|&x| (x, "rapier"))).collect();
    assert_eq!(order, expected);
    for r in &records {
        match r.status {
            Status::Ok => assert!(r.numbers.is_some() && r.reason.is_empty(), "{r:?}"),
            _ => assert!(r.numbers.is_none() && !r.reason.is_empty(), "{r:?}"),
        }
    }
    // The paper's cat at r = 0.1 and a stouter one: both optimisers must succeed (tests/retime.rs
    // and tests/whole.rs solve these cats).
    for case in 0..2 {
        let calibrated = row(&records, case, "calibrated", "exact").numbers.expect("calibrated numbers");
        let retimed = row(&records, case, "retimed", "exact");
        assert_eq!(retimed.labels.retimed_from, Some(catflip::sweep::row::SweepSchedule::Calibrated));
        assert_eq!(retimed.labels.solver_status, "solved");
        let n = retimed.numbers.expect("the retiming solves");
        let rt = n.retiming.expect("the retiming's numbers");
        // Weak duality: the certified bound is below the program's peak, and the exact peak of
        // the timed trajectory is not below the bound by more than the grid's discretisation.
        assert!(rt.lower_bound_nm <= rt.program_peak_nm * (1.0 + 1e-6), "{rt:?}");
        let peak = n.peak_nm.expect("re-measured");
        assert!(peak >= rt.lower_bound_nm * (1.0 - 1e-2), "exact {peak} vs bound {}", rt.lower_bound_nm);
        // The library timing is one timing of the same path: the optimum cannot be above it.
        assert!(peak < calibrated.peak_nm.expect("calibrated peak"), "{peak} vs {calibrated:?}");
        // Retiming keeps the path, so the flip: the calibrated schedule's twist, to the two
        // integrations' tolerances (1e-8 rad each, the base problem's).
        let twist_gap = (n.twist_deg - calibrated.twist_deg).abs();
        assert!(twist_gap <= 2e-8_f64.to_degrees(), "retimed twist {} vs {}", n.twist_deg, calibrated.twist_deg);
        let whole = row(&records, case, "whole", "exact");
        let w = whole.numbers.unwrap_or_else(|| panic!("the whole optimum: {}", whole.reason));
        assert!(w.flip_error_deg.abs() <= 1e-8_f64.to_degrees(), "{w:?}");
        assert!(w.circulation_rad.is_none() && w.peaks.is_none());
        assert!(w.peak_nm.is_some_and(|p| p > 0.0) && w.whole.is_some_and(|x| x.max_bend_deg > 0.0));
        assert!(!whole.labels.whole_start.is_empty() && whole.labels.solver_status.contains("converged"));
        // The peak objective keeps the case's fall (10 m, g = 9.8 m/s²), and measures the motors.
        let wn = w.whole.expect("the whole optimum's numbers");
        assert_relative_eq!(wn.fall_time_s, (2.0f64 * 10.0 / 9.8).sqrt(), max_relative = 1e-12);
        assert_relative_eq!(wn.drop_height_m, 10.0, max_relative = 1e-12);
        assert!(w.motors.is_some_and(|m| m.worst.is_none() && m.peak_speed_rad_s[0] > 0.0), "{w:?}");
        for schedule in want {
            let r = row(&records, case, schedule, "rapier");
            assert_eq!(r.status, Status::Ok, "{}", r.reason);
            let n = r.numbers.expect("rapier numbers");
            let v = n.rapier.expect("the verification's numbers");
            // Rapier checks the exact engine's torques; the motor figures are the exact row's.
            assert!(n.motors.is_none(), "{schedule}: a rapier row with motor figures");
            assert!(v.steps > 0 && v.steps <= 150_000 && v.finest_dt_s > 0.0, "{v:?}");
            assert!(["verified", "not verified", "inconclusive"]
                .iter()
                .any(|w| r.labels.rapier_verdict.starts_with(w)));
        }
    }
    let csv = to_csv(&s, &records).expect("CSV");
    let lower = csv.to_lowercase();
    assert!(!lower.contains("nan") && !lower.contains(",inf"), "{csv}");
    // The CSV reads back to the same records, bit for bit (what a merge of shards relies on).
    assert!(from_csv(&s, &csv, "test").expect("reads back") == records);
}

#[test]
fn output_is_byte_identical_whatever_the_thread_count_with_the_optimisers_and_rapier() {
    let s = optimised();
    let csv_with = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a rayon pool");
        let records = pool.install(|| evaluate(&s, 0..s.case_count(), false));
        to_csv(&s, &records).expect("CSV")
    };
    let (one, two) = (csv_with(1), csv_with(2));
    assert_eq!(one.lines().count(), 1 + 2 * 8, "{one}");
    assert!(one == two, "1 thread and 2 threads differ:\n{one}\n---\n{two}");
}

#[test]
fn compute_whole_control_points_is_refused_naming_the_problem_field() {
    // One source of truth: the spline's control points are the problem's
    // `optimize.whole.control_points`, which `optimize --whole` reads too.
    for compute in ["[compute]\nwhole = true\nwhole_control_points = 20", "[compute]\nwhole_control_points = 20"] {
        let (field, reason) = bad_field(&with_base(compute));
        assert_eq!(field, "compute.whole_control_points");
        assert!(
            reason.contains("retired") && reason.contains("optimize.whole.control_points") && reason.contains("axis"),
            "{reason}"
        );
    }
    // Its replacement: the problem's own field, in an inline base or as an axis; a value the
    // optimiser cannot use is the problem file's refusal, naming that field, per case.
    let s = sweep_ok(&format!(
        "{}[base.optimize.whole]\ncontrol_points = 20\n",
        with_base("[[axis]]\nfield = \"optimize.whole.control_points\"\nvalues = [3]\n[compute]\nwhole = true")
    ));
    let r = &evaluate(&s, 0..1, false)[2];
    assert_eq!((r.schedule.name(), r.status), ("whole", Status::Refused));
    assert!(r.reason.contains("optimize.whole.control_points = 3"), "{}", r.reason);
}

#[test]
fn a_verification_without_a_usable_run_counts_as_inconclusive() {
    // A step budget below rapier's first run: no rapier number, but a verdict. The row has no
    // numbers (`failed`, the verdict as reason), and the verdicts table counts it as
    // `inconclusive`, as `catflip run` does, not as a row without a verdict.
    let text = "name = \"t\"\n[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1]\n[compute]\nrapier = true\n[base]\nname = \"tiny\"\n[base.exact]\ntolerance = 1e-8\ntorque_samples = 40\n[base.rapier]\nstep_budget = 1\n";
    let s = sweep_ok(text);
    let root = scratch("no-rapier-run");
    let options = SweepOptions { out: root.clone(), shard: None, quiet: true, command: "test".into() };
    run(&s, &options).expect("the sweep runs");
    let records =
        from_csv(&s, &std::fs::read_to_string(root.join("t/sweep.csv")).expect("CSV"), "test").expect("reads");
    let rapier: Vec<&Record> = records.iter().filter(|r| r.engine.name() == "rapier").collect();
    assert!(!rapier.is_empty());
    for r in &rapier {
        assert_eq!(r.status, Status::Failed, "{r:?}");
        assert!(r.numbers.is_none(), "{r:?}");
        assert!(r.labels.rapier_verdict.starts_with("inconclusive: 0 of the 3 runs"), "{r:?}");
        assert!(r.reason.contains("budget of 1 steps"), "{r:?}");
    }
    let md = std::fs::read_to_string(root.join("t/sweep.md")).expect("the report");
    for r in &rapier {
        let line = format!("| {} | 0 | 0 | 1 | 0 |", r.schedule);
        assert!(md.contains(&line), "no `{line}` in\n{md}");
    }
    let _ = std::fs::remove_dir_all(&root);
}

/// A cheap sweep of `count` cases: the paper's flip alone, over the cat's radius.
fn cheap(count: usize) -> Sweep {
    sweep_ok(&with_base(&format!(
        "[[axis]]\nfield = \"cat.radius\"\nrange = {{ from = 0.1, to = 0.2, count = {count} }}\n[compute]\npaper_flip = true\ncalibrated = false\npeaks = false"
    )))
}

fn options(out: &Path, shard: Option<Shard>) -> SweepOptions {
    SweepOptions { out: out.to_path_buf(), shard, quiet: true, command: "test".into() }
}

/// Runs every shard of `n` into `root/parts` and returns the part folders in shard order.
fn parts(s: &Sweep, root: &Path, n: usize) -> Vec<PathBuf> {
    (1..=n).map(|k| run(s, &options(&root.join("parts"), Some(Shard { k, n }))).expect("shard").dir).collect()
}

/// The merge's error message, which must exist.
fn merge_error(parts: &[PathBuf], out: &Path) -> String {
    match merge(parts, out, "test") {
        Err(e) => e.to_string(),
        Ok(o) => panic!("the merge must be refused, but wrote {}", o.dir.display()),
    }
}

/// Rewrites a part's manifest through `edit` on its JSON.
fn edit_manifest(part: &Path, edit: impl FnOnce(&mut serde_json::Value)) {
    let path = part.join("part.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("manifest")).expect("JSON manifest");
    edit(&mut v);
    std::fs::write(&path, serde_json::to_string_pretty(&v).expect("JSON")).expect("rewrite the manifest");
}

/// Names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|d| d.flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect())
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn a_manifest_naming_a_folder_outside_out_is_refused_before_anything_is_written() {
    let s = cheap(2);
    let root = scratch("manifest-name");
    let part = parts(&s, &root, 1).remove(0);
    let out = root.join("merged");
    std::fs::create_dir_all(out.join("unrelated")).expect("a folder the merge must not touch");
    let outside = root.join("outside");
    for name in ["", "..", "../outside", outside.to_str().unwrap_or("/tmp/outside"), "a/b"] {
        edit_manifest(&part, |v| v["sweep"]["name"] = serde_json::json!(name));
        let e = merge_error(std::slice::from_ref(&part), &out);
        let want = format!("{}: sweep.name: {name:?} must be non-empty", part.join("part.json").display());
        assert!(e.contains(&want), "name {name:?}: {e}");
        assert!(!e.contains('\n'), "one line: {e}");
        assert_eq!(listing(&out), ["unrelated"], "name {name:?}: --out was touched");
        assert!(!outside.exists(), "name {name:?}: a folder was written outside --out");
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_manifest_is_checked_like_a_sweep_file_field_by_field() {
    let s = cheap(2);
    let root = scratch("manifest-fields");
    let part = parts(&s, &root, 1).remove(0);
    let original = std::fs::read_to_string(part.join("part.json")).expect("manifest");
    type Edit = fn(&mut serde_json::Value);
    let cases: [(&str, Edit); 6] = [
        ("sweep.axis[0].values: an axis needs at least one value", |v| {
            v["sweep"]["axes"][0]["values"] = serde_json::json!([])
        }),
        ("sweep.axis[0].field: `cat.radus` is not a problem field", |v| {
            v["sweep"]["axes"][0]["field"] = serde_json::json!("cat.radus")
        }),
        ("sweep.compute: [compute] asks for no schedule", |v| {
            v["sweep"]["compute"]["paper_flip"] = serde_json::json!(false)
        }),
        ("shard.k: 3 is not between 1 and shard.n = 1", |v| v["shard"]["k"] = serde_json::json!(3)),
        ("shard.n: 5 shards of a sweep of 2 cases: at most 2", |v| v["shard"] = serde_json::json!({"k": 1, "n": 5})),
        ("first, end: 0..1 is not shard 1/1's cases 0..2 of 2", |v| v["end"] = serde_json::json!(1)),
    ];
    for (want, edit) in cases {
        std::fs::write(part.join("part.json"), &original).expect("restore");
        edit_manifest(&part, edit);
        let e = merge_error(std::slice::from_ref(&part), &root.join("merged"));
        assert!(e.contains(&format!("part.json: {want}")), "want {want:?}, got: {e}");
        assert!(!root.join("merged").exists(), "{want}: results were written");
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_manifest_of_shard_zero_of_zero_is_refused_without_a_panic() {
    let s = cheap(2);
    let root = scratch("manifest-zero");
    let p = parts(&s, &root, 2);
    for part in &p {
        edit_manifest(part, |v| v["shard"] = serde_json::json!({"k": 0, "n": 0}));
    }
    let e = merge_error(&p, &root.join("merged"));
    assert!(e.ends_with("part.json: shard.n: must be at least 1"), "{e}");
    edit_manifest(&p[0], |v| v["shard"] = serde_json::json!({"k": 1, "n": 0}));
    let e = merge_error(&p[..1], &root.join("merged"));
    assert!(e.ends_with("part.json: shard.n: must be at least 1") && !e.contains("twice"), "{e}");
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn more_shards_than_cases_are_refused_and_missing_shards_are_named_as_ranges() {
    let s = cheap(1000);
    let root = scratch("shard-count");
    match run(&s, &options(&root, Some(Shard { k: 1, n: 1001 }))) {
        Err(e) => assert_eq!(
            e.to_string(),
            "--shard 1/1001: the sweep has 1000 cases, so N can be at most 1000 (at least one case per shard)"
        ),
        Ok(o) => panic!("1001 shards of 1000 cases must be refused, wrote {}", o.dir.display()),
    }
    assert!(listing(&root).is_empty(), "nothing is written: {:?}", listing(&root));
    let p: Vec<PathBuf> = [1, 2, 999, 1000]
        .into_iter()
        .map(|k| run(&s, &options(&root.join("parts"), Some(Shard { k, n: 1000 }))).expect("shard").dir)
        .collect();
    let e = merge_error(&p, &root.join("merged"));
    assert_eq!(e, "cannot merge: missing shards 3–998 of 1000 (996 missing)");
    let e = merge_error(&[p[0].clone(), p[2].clone()], &root.join("merged"));
    assert_eq!(e, "cannot merge: missing shards 2–998, 1000 of 1000 (998 missing)");
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_sweep_that_computes_nothing_is_refused_at_load() {
    let (field, reason) = bad_field(&with_base(
        "[compute]\npaper_flip = false\ncalibrated = false\npeaks = false\nretiming = false\nwhole = false\nrapier = false",
    ));
    assert_eq!(field, "compute");
    assert!(reason.contains("[compute] asks for no schedule"), "{reason}");
    // Peaks and rapier check schedules; alone they ask for none.
    let (field, _) =
        bad_field(&with_base("[compute]\npaper_flip = false\ncalibrated = false\npeaks = true\nrapier = true"));
    assert_eq!(field, "compute");
}

/// Rewrites line `line` (1-based; every record is one line) of a part's `cases.csv` through
/// `edit` on its cells.
fn edit_row(part: &Path, line: usize, edit: impl FnOnce(&[String], &mut Vec<String>)) {
    let path = part.join("cases.csv");
    let text = std::fs::read_to_string(&path).expect("cases.csv");
    let mut rows: Vec<Vec<String>> = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(text.as_bytes())
        .records()
        .map(|r| r.expect("a CSV record").iter().map(str::to_string).collect())
        .collect();
    let head = rows[0].clone();
    edit(&head, &mut rows[line - 1]);
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in &rows {
        w.write_record(r).expect("CSV");
    }
    std::fs::write(&path, w.into_inner().expect("CSV")).expect("rewrite cases.csv");
}

fn set(head: &[String], cells: &mut [String], column: &str, value: &str) {
    let k = head.iter().position(|h| h == column).unwrap_or_else(|| panic!("no column {column}"));
    cells[k] = value.to_string();
}

#[test]
fn edited_parts_are_refused_naming_the_file_and_line() {
    // Two cases of two rows each (paper, calibrated); shard 2 of 2 holds case 1 on lines 2 and 3.
    let s = sweep_ok(&with_base(
        "[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1, 0.2]\n[compute]\npaper_flip = true\ncalibrated = true\npeaks = false",
    ));
    let root = scratch("edited");
    let p = parts(&s, &root, 2);
    let csv = p[1].join("cases.csv");
    let original = std::fs::read_to_string(&csv).expect("cases.csv");
    assert!(merge(&p, &root.join("merged"), "test").is_ok(), "the unedited parts merge");
    type Edit = Box<dyn Fn(&Path)>;
    let edits: [(&str, Edit); 5] = [
        // The calibrated row dropped and the paper row doubled: same case, same row count.
        (
            "line 3: case 1 has rows paper/exact, paper/exact; a run gives it paper/exact, calibrated/exact",
            Box::new(|part: &Path| {
                let path = part.join("cases.csv");
                let text = std::fs::read_to_string(&path).expect("cases.csv");
                let lines: Vec<&str> = text.lines().collect();
                std::fs::write(&path, format!("{}\n{}\n{}\n", lines[0], lines[1], lines[1])).expect("rewrite");
            }),
        ),
        (
            "line 2: swing_deg = \"NaN\" is not a finite number",
            Box::new(|part: &Path| edit_row(part, 2, |h, c| set(h, c, "swing_deg", "NaN"))),
        ),
        (
            "line 3: peak_max_nm = \"inf\" is not a finite number",
            Box::new(|part: &Path| edit_row(part, 3, |h, c| set(h, c, "peak_max_nm", "inf"))),
        ),
        (
            "line 2: status is ok but swing_deg is empty",
            Box::new(|part: &Path| edit_row(part, 2, |h, c| set(h, c, "swing_deg", ""))),
        ),
        (
            "line 3: cat.radius = \"0.1\" does not fit the rest of the row (a sweep writes \"0.2\" there)",
            Box::new(|part: &Path| edit_row(part, 3, |h, c| set(h, c, "cat.radius", "0.1"))),
        ),
    ];
    for (want, edit) in edits {
        // As edited, and with `\r\n` line ends (as a spreadsheet or Python's csv module writes):
        // the same lines.
        for crlf in [false, true] {
            std::fs::write(&csv, &original).expect("restore");
            edit(&p[1]);
            if crlf {
                let text = std::fs::read_to_string(&csv).expect("cases.csv");
                std::fs::write(&csv, text.replace("\r\n", "\n").replace('\n', "\r\n")).expect("rewrite");
            }
            let _ = std::fs::remove_dir_all(root.join("merged"));
            let e = merge_error(&p, &root.join("merged"));
            assert!(
                e.contains(&format!("{}", csv.display())) && e.contains(want),
                "crlf {crlf}: want {want:?}, got: {e}"
            );
            assert!(!e.contains('\n'), "one line: {e}");
            assert!(!root.join("merged").exists(), "{want}: results were written");
        }
    }
    // A row with a cell too many is named by its line too.
    for end in ["\n", "\r\n"] {
        let lines: Vec<&str> = original.lines().collect();
        std::fs::write(&csv, format!("{}{end}{}{end}{},x{end}", lines[0], lines[1], lines[2])).expect("rewrite");
        let e = merge_error(&p, &root.join("merged"));
        assert!(e.contains("line 3: ") && e.contains("fields where the header has"), "{end:?}: {e}");
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_file_where_the_results_folder_goes_is_refused_and_left_alone() {
    let root = scratch("file-in-the-way");
    let file = root.join("tiny.toml");
    std::fs::write(&file, with_base("[compute]\ncalibrated = false\npeaks = false")).expect("the sweep file");
    let out = root.join("out");
    std::fs::create_dir_all(&out).expect("out");
    std::fs::write(out.join("t"), "mine").expect("a file named like the results folder");
    let (f, o) = (file.display().to_string(), out.display().to_string());
    let (code, stdout, stderr) = catflip(&["sweep", &f, "--out", &o, "--quiet"]);
    assert_eq!(code, 1, "{stdout}{stderr}");
    assert_eq!(
        stderr.trim(),
        format!("error: {}: is a file, not a folder, so it is not a results folder to replace; move it away or choose another --out", out.join("t").display())
    );
    assert_eq!(listing(&out), ["t"], "nothing hidden, nothing added");
    assert_eq!(std::fs::read_to_string(out.join("t")).expect("still a file"), "mine");
    let _ = std::fs::remove_dir_all(&root);
}

/// `root/tiny.toml` written as [`with_base`] of `body`: the `--out` folder `root/out`, and the
/// file and that folder as the command line's arguments.
fn sweep_file(root: &Path, body: &str) -> (PathBuf, String, String) {
    let file = root.join("tiny.toml");
    std::fs::write(&file, with_base(body)).expect("the sweep file");
    let out = root.join("out");
    let (f, o) = (file.display().to_string(), out.display().to_string());
    (out, f, o)
}

/// A sweep whose every case is refused has no result: its table says why for each, and the exit
/// is non-zero (it was 0, a QA run found, so a script took it for a sweep that worked); a shard
/// of it exits 0, for the merge decides, and the merge then refuses.
#[test]
fn a_sweep_without_one_result_exits_non_zero() {
    let root = scratch("all-refused");
    // θ = 90° on the cone path is gimbal lock: every case refused.
    let axes = "[[axis]]\nfield = \"manoeuvre.bend_path\"\nvalues = [\"cone\"]\n[[axis]]\nfield = \"manoeuvre.theta_deg\"\nvalues = [90.0]\n";
    let (out, f, o) = sweep_file(&root, &format!("{axes}[compute]\ncalibrated = false\npeaks = false"));
    let (code, stdout, stderr) = catflip(&["sweep", &f, "--out", &o, "--quiet"]);
    assert_eq!(code, 1, "{stdout}{stderr}");
    let table = out.join("t/sweep.csv");
    assert_eq!(
        stderr.trim(),
        format!(
            "error: sweep t: no case gave a result (1 refused): the reason column of {} says why for each",
            table.display()
        )
    );
    let csv = std::fs::read_to_string(&table).expect("the table of refusals");
    assert!(csv.contains(",refused,") && csv.contains("gimbal"), "{csv}");
    let (code, _, stderr) = catflip(&["sweep", &f, "--out", &o, "--quiet", "--shard", "1/1"]);
    assert_eq!(code, 0, "{stderr}");
    let (part, merged) = (out.join("t.part-1-of-1").display().to_string(), root.join("merged").display().to_string());
    let (code, _, stderr) = catflip(&["sweep", "--merge", &part, "--out", &merged]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("no case gave a result (1 refused)"), "{stderr}");
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_sweep_removes_what_killed_sweeps_left_behind() {
    let root = scratch("stale");
    let file = root.join("tiny.toml");
    std::fs::write(&file, with_base("[compute]\ncalibrated = false\npeaks = false")).expect("the sweep file");
    let out = root.join("out");
    // A PID above Linux's PID_MAX_LIMIT: never a live process.
    let dead = 4_194_304 + 21;
    for stale in [
        format!(".t.scratch-{dead}"),
        format!(".t.partial-{dead}"),
        format!(".t.old-{dead}"),
        format!(".t.part-1-of-1.partial-{dead}"),
    ] {
        std::fs::create_dir_all(out.join(stale)).expect("a stale folder");
    }
    let (f, o) = (file.display().to_string(), out.display().to_string());
    let (code, _, stderr) = catflip(&["sweep", &f, "--out", &o, "--quiet"]);
    assert_eq!(code, 0, "{stderr}");
    let (code, _, stderr) = catflip(&["sweep", &f, "--out", &o, "--quiet", "--shard", "1/1"]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(listing(&out), ["t", "t.part-1-of-1"]);
    let _ = std::fs::remove_dir_all(&root);
}

/// The report `catflip optimize --whole` gives for a case's problem.
fn optimize_whole_report(s: &Sweep, index: usize) -> catflip::measure::whole::WholeReport {
    let problem = case(s, index).problem(s).expect("the case loads");
    let resolved = catflip::engines::resolved::Resolved::new(&problem).expect("resolves");
    catflip::measure::whole::whole(&resolved).expect("the optimiser runs")
}

/// The whole optimum alone, on the base `base` (inline tables) and with `rest` before it.
fn whole_only(rest: &str, base: &str) -> Sweep {
    sweep_ok(&format!(
        "{}{base}",
        with_base(&format!("{rest}\n[compute]\npaper_flip = false\ncalibrated = false\npeaks = false\nwhole = true"))
    ))
}

#[test]
fn an_axis_over_whole_control_points_changes_the_whole_rows_as_optimize_whole_does() {
    // The base says 12 control points (the default is 120) and the axis 12 and 16: each whole
    // row is what `optimize --whole` gives for the case's own problem, bit for bit. Without the
    // knot refinement where the torques switch, the optimum's spline has the axis's points.
    let s = whole_only(
        "[[axis]]\nfield = \"optimize.whole.control_points\"\nvalues = [12, 16]",
        "[base.optimize.whole]\ncontrol_points = 12\nswitch_refinements = 0\n",
    );
    let records = evaluate(&s, 0..2, false);
    assert_eq!(records.len(), 2);
    let peaks: Vec<u64> =
        records.iter().map(|r| r.peak_max().unwrap_or_else(|| panic!("{}", r.reason)).to_bits()).collect();
    assert_ne!(peaks[0], peaks[1], "the axis must change the optimum");
    for (k, r) in records.iter().enumerate() {
        let report = optimize_whole_report(&s, k);
        let best = report.best().expect("optimize --whole finds an optimum");
        assert_eq!(best.spline.control_points(), [12, 16][k], "{k}");
        // The sweep's row and `optimize --whole` measure the same optimum the same way.
        let measured = report.measured.as_ref().expect("the optimum is measured");
        assert_eq!(peaks[k], measured.exact.peak().to_bits(), "case {k}");
        assert_eq!(r.labels.whole_start, best.start);
    }
}

/// A robot cat (halves 1.5 kg, 0.25 m, r = 0.06 m) with DC motors (2 N·m stall, 30 rad/s free),
/// the least fall within them on a 20-point spline.
const ROBOT: &str = "[base.cat]\nmass = 1.5\nlength = 0.25\nradius = 0.06\n[base.actuator]\nstall_torque_nm = 2.0\nfree_speed_rad_s = 30.0\n[base.optimize.whole]\nobjective = \"min-time\"\ncontrol_points = 20\n";

/// The cell of `column` on data line `line` (1-based) of a CSV text.
fn csv_cell(csv: &str, line: usize, column: &str) -> String {
    let mut rd = csv::Reader::from_reader(csv.as_bytes());
    let head: Vec<String> = rd.headers().expect("a header").iter().map(str::to_string).collect();
    let k = head.iter().position(|h| h == column).unwrap_or_else(|| panic!("no column {column}"));
    let rec = rd.records().nth(line - 1).expect("the line").expect("a record");
    rec.get(k).unwrap_or("").to_string()
}

#[test]
fn the_min_time_row_reports_the_drop_height_optimize_whole_gives() {
    let s = whole_only("", ROBOT);
    let records = evaluate(&s, 0..1, false);
    let r = &records[0];
    let n = r.numbers.unwrap_or_else(|| panic!("the min-time optimum: {}", r.reason));
    let w = n.whole.expect("the whole optimum's numbers");
    let report = optimize_whole_report(&s, 0);
    // Bit for bit what `optimize --whole` reports for the same problem.
    assert_eq!(Some(w.fall_time_s.to_bits()), report.fall_time_s.map(f64::to_bits));
    assert_eq!(Some(w.drop_height_m.to_bits()), report.drop_height_m.map(f64::to_bits));
    // h = g T²/2 (g = 9.8 m/s², the base's default), and the least fall is shorter than the
    // base's 10 m drop (1.43 s).
    assert_relative_eq!(w.drop_height_m, 0.5 * 9.8 * w.fall_time_s * w.fall_time_s, max_relative = 1e-15);
    assert!(w.fall_time_s > 0.1 && w.fall_time_s < 1.0, "{w:?}");
    // The least fall uses a limit fully, and stays within every one.
    let m = n.motors.expect("the motor figures");
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(Some(bits(&m.peak_speed_rad_s)), report.peak_speed_rad_s.as_deref().map(bits));
    assert_eq!(Some(bits(&m.peak_power_w)), report.peak_power_w.as_deref().map(bits));
    let worst = m.worst.expect("a limit");
    assert!(worst.within() && worst.ratio > 0.99, "{worst:?}");
    assert_eq!(worst.limit, catflip::model::motor::Limit::Envelope);
    // In the table: the same numbers, the verdict in words.
    let csv = to_csv(&s, &records).expect("CSV");
    assert_eq!(csv_cell(&csv, 1, "drop_height_m"), format!("{:?}", w.drop_height_m));
    assert_eq!(csv_cell(&csv, 1, "fall_time_s"), format!("{:?}", w.fall_time_s));
    assert_eq!(csv_cell(&csv, 1, "within_motors"), "true");
    assert_eq!(csv_cell(&csv, 1, "motor_worst_limit"), format!("joint {} envelope", worst.joint));
    assert!(from_csv(&s, &csv, "test").expect("reads back") == records);
}

/// The motor-sizing columns, as the peak-torque table names them.
const MOTOR_COLUMNS: [&str; 7] = catflip::engines::motors::MotorDemand::CSV_HEADER;

#[test]
fn motor_columns_are_finite_where_they_exist_and_empty_elsewhere() {
    // Ideal motors: speeds and powers on every row with peak torques, no limit to use.
    let ideal = sweep_ok(&with_base("[compute]\nretiming = true"));
    let records = evaluate(&ideal, 0..1, false);
    let csv = to_csv(&ideal, &records).expect("CSV");
    assert_eq!(records.len(), 3, "paper, calibrated, retimed");
    for (line, r) in records.iter().enumerate() {
        let n = r.numbers.unwrap_or_else(|| panic!("{}: {}", r.schedule, r.reason));
        let m = n.motors.unwrap_or_else(|| panic!("{} has no motor figures", r.schedule));
        let peak = n.peak_nm.expect("a peak torque");
        for j in 0..2 {
            let (speed, power) = (m.peak_speed_rad_s[j], m.peak_power_w[j]);
            assert!(speed.is_finite() && speed > 0.0 && power.is_finite() && power > 0.0, "{m:?}");
            // |τ q̇| ≤ max|τ| max|q̇| (both refined peaks; the product of separate maxima).
            assert!(power <= peak * speed * (1.0 + 1e-9), "{} joint {}: {power} > {peak} × {speed}", r.schedule, j + 1);
        }
        assert!(m.worst.is_none(), "{m:?}");
        for c in &MOTOR_COLUMNS[..4] {
            assert!(csv_cell(&csv, line + 1, c).parse::<f64>().is_ok_and(f64::is_finite), "{c}");
        }
        for c in &MOTOR_COLUMNS[4..] {
            assert_eq!(csv_cell(&csv, line + 1, c), "", "{c} with ideal motors");
        }
        for c in ["fall_time_s", "drop_height_m"] {
            assert_eq!(csv_cell(&csv, line + 1, c), "", "{c} on a {} row", r.schedule);
        }
    }
    // A torque limit of 0.5 N·m: its usage is the peak torque over the limit.
    let limited = sweep_ok(&format!("{}[base.actuator]\ntorque_limit_nm = 0.5\n", with_base("")));
    let records = evaluate(&limited, 0..1, false);
    let csv = to_csv(&limited, &records).expect("CSV");
    for (line, r) in records.iter().enumerate() {
        let n = r.numbers.expect("computed");
        let worst = n.motors.and_then(|m| m.worst).expect("a limit's usage");
        assert_eq!(worst.limit, catflip::model::motor::Limit::Torque);
        assert_relative_eq!(worst.ratio, n.peak_nm.expect("a peak") / 0.5, max_relative = 1e-6);
        assert_eq!(csv_cell(&csv, line + 1, "within_motors"), worst.within().to_string());
        assert_eq!(csv_cell(&csv, line + 1, "motor_worst_limit"), format!("joint {} torque", worst.joint));
    }
    // Without peak torques, no motor figures.
    let no_peaks = sweep_ok(&with_base("[compute]\npeaks = false"));
    let records = evaluate(&no_peaks, 0..1, false);
    let csv = to_csv(&no_peaks, &records).expect("CSV");
    for (line, r) in records.iter().enumerate() {
        assert!(r.numbers.is_some_and(|n| n.motors.is_none()), "{r:?}");
        for c in MOTOR_COLUMNS {
            assert_eq!(csv_cell(&csv, line + 1, c), "", "{c} without peaks");
        }
    }
    assert!(!csv.to_lowercase().contains("nan"));
}

#[test]
fn edited_motor_cells_are_refused_by_the_merge() {
    // Two cases (paper and calibrated rows) with a torque limit; shard 2 of 2 holds case 1.
    let s = sweep_ok(&format!(
        "{}[base.actuator]\ntorque_limit_nm = 0.5\n",
        with_base("[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1, 0.2]")
    ));
    let root = scratch("edited-motors");
    let p = parts(&s, &root, 2);
    let csv = p[1].join("cases.csv");
    let original = std::fs::read_to_string(&csv).expect("cases.csv");
    assert!(merge(&p, &root.join("merged"), "test").is_ok(), "the unedited parts merge");
    let flip = |v: &str| if v == "true" { "false" } else { "true" }.to_string();
    let within = csv_cell(&original, 1, "within_motors");
    let edits: [(String, &str, String); 4] = [
        (
            format!("line 2: within_motors = {:?} does not fit the rest of the row", flip(&within)),
            "within_motors",
            flip(&within),
        ),
        ("line 2: bad motor_worst_limit".into(), "motor_worst_limit", "joint 3 torque".into()),
        ("line 3: peak_power2_w = \"NaN\" is not a finite number".into(), "peak_power2_w", "NaN".into()),
        ("line 3: peak_speed2_rad_s = ".into(), "peak_speed1_rad_s", String::new()),
    ];
    for (want, column, value) in edits {
        std::fs::write(&csv, &original).expect("restore");
        let line = if want.starts_with("line 2") { 2 } else { 3 };
        edit_row(&p[1], line, |h, c| set(h, c, column, &value));
        let _ = std::fs::remove_dir_all(root.join("merged"));
        let e = merge_error(&p, &root.join("merged"));
        assert!(e.contains(&format!("{}", csv.display())) && e.contains(&want), "want {want:?}, got: {e}");
        assert!(!root.join("merged").exists(), "{want}: results were written");
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_min_time_case_without_a_flip_is_failed_with_its_reason_never_a_height() {
    // One trust-region iteration converges nowhere: the row is `failed`, says why (a flip its
    // last iterate may already be is named in the reason, not given as the least height), and
    // the report's drop-height table shows the reason where the height would be.
    let s = whole_only("", &format!("{ROBOT}max_iterations = 1\n"));
    let records = evaluate(&s, 0..1, false);
    let r = &records[0];
    assert_eq!(r.status, Status::Failed, "{r:?}");
    assert!(
        r.numbers.is_none() && r.reason.starts_with("no optimum: none of the 2 start(s) converged to a flip"),
        "{}",
        r.reason
    );
    let csv = to_csv(&s, &records).expect("CSV");
    for c in ["drop_height_m", "fall_time_s", "peak_speed1_rad_s", "within_motors"] {
        assert_eq!(csv_cell(&csv, 1, c), "", "{c}");
    }
    let md = catflip::sweep::summary::body(&s, &records, &[]);
    let table = md.split("## Least drop height").nth(1).expect("the drop-height table");
    assert!(table.contains("| — | — | failed: no optimum: none of the 2 start(s) converged to a flip"), "{table}");
}

/// The cases' warnings reach the terminal and `sweep.md` (a drop height read as kilometres was
/// said in the CSV's column alone, a QA run found), and a schedule beyond the case's motors is
/// marked and never named the lowest (it was, 1418 times over its torque limit).
#[test]
fn warnings_and_schedules_beyond_the_motors_are_said() {
    let root = scratch("warned");
    // θ = 100°, inside the paper's stability range: only the two 1 cm drops are warned of.
    let axes = "[[axis]]\nfield = \"actuator.torque_limit_nm\"\nvalues = [10.0, 0.05]\n[[axis]]\nfield = \"drop.height\"\nvalues = [3.0, 0.01]\n[[axis]]\nfield = \"manoeuvre.theta_deg\"\nvalues = [100.0]\n";
    let (out, f, o) = sweep_file(&root, &format!("{axes}[compute]\ncalibrated = true\npeaks = true\nretiming = true"));
    let (code, _, stderr) = catflip(&["sweep", &f, "--out", &o, "--quiet"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("warning: sweep t: 2 of its 4 cases carry warnings"), "{stderr}");
    let md = std::fs::read_to_string(out.join("t/sweep.md")).expect("the report");
    assert!(md.contains("## Warnings") && md.contains("drop.height = 0.01 m is outside"), "{md}");
    // Case 0 (10 N·m, 3 m): the library schedules exceed the limit (26.6 N·m), the retiming
    // (7.0 N·m) does not.
    let case = |k: usize| md.lines().find(|l| l.starts_with(&format!("| {k} |"))).unwrap_or_default().to_string();
    let first = case(0);
    assert!(first.contains("†") && first.ends_with("| retimed |"), "{first}");
    // Case 2 (0.05 N·m): nothing within the motors, so no lowest.
    assert!(case(2).ends_with("| — (none within the motors) |"), "{}", case(2));
    let _ = std::fs::remove_dir_all(&root);
}

/// Parts of two sweeps are refused naming what differs (the message said "another sweep or
/// shard count" whatever it was, a QA run found, after the base file was edited between shards).
#[test]
fn parts_of_two_sweeps_are_refused_naming_what_differs() {
    let s = cheap(2);
    let root = scratch("two-sweeps");
    let mut first = parts(&s, &root.join("a"), 2);
    let edited = sweep_ok(&with_base(
        "[[axis]]\nfield = \"cat.radius\"\nrange = { from = 0.1, to = 0.2, count = 2 }\n[compute]\npaper_flip = true\ncalibrated = false\npeaks = false\n[base.drop]\nheight = 3.0",
    ));
    let second = parts(&edited, &root.join("b"), 2);
    let out = root.join("merged");
    let e = merge_error(&[first.remove(0), second[1].clone()], &out);
    assert!(
        e.contains("is a part of another sweep than") && e.contains("its base problem (test.toml [base]) differs"),
        "{e}"
    );
    let other_count = parts(&s, &root.join("c"), 1);
    let e = merge_error(&[first.remove(0), other_count[0].clone()], &out);
    assert!(e.contains("its shard count (1 against 2) differs"), "{e}");
    let _ = std::fs::remove_dir_all(&root);
}

/// Axes zipped together change together: each row of `sweep.md` names the zipped axes' values
/// beside its own (a review's radius zipped with the drop height read as if the radius alone made
/// the peak rise 6×), and values read as written (`2`, not `2.000`).
#[test]
fn a_zipped_sweeps_rows_name_every_zipped_value() {
    let root = scratch("zip-rows");
    let s = sweep_ok(&with_base(
        "combine = \"zip\"\n[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1, 0.2]\n[[axis]]\nfield = \"drop.height\"\nvalues = [10.0, 2.0]",
    ));
    run(&s, &options(&root, None)).expect("the sweep runs");
    let md = std::fs::read_to_string(root.join("t/sweep.md")).expect("the report");
    assert!(md.contains("\n| 0.1 (drop.height = 10) | "), "{md}");
    assert!(md.contains("\n| 0.2 (drop.height = 2) | "), "{md}");
}

/// A case whose flip ends with the spine swung past 45° does not land on its feet whatever its
/// twist: its warnings say so for each such schedule, and no other case's do (a review found the
/// π/C sweep's cone cases at r = 0.4 swung by 48–155° with only the θ warning).
#[test]
fn a_flip_that_ends_swung_is_warned_of_in_its_case() {
    let s = sweep_ok(&with_base(
        "[[axis]]\nfield = \"manoeuvre.bend_path\"\nvalues = [\"cone\"]\n[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1, 0.4]\n[[axis]]\nfield = \"manoeuvre.theta_deg\"\nvalues = [60.0, 75.0, 135.0]\n[compute]\npaper_flip = true\ncalibrated = true\npeaks = false",
    ));
    let records = evaluate(&s, 0..s.case_count(), false);
    let mut swung = 0;
    for r in records.iter().filter(|r| r.engine == catflip::engines::Engine::Exact) {
        let Some(n) = r.numbers else { continue };
        let said = r.warnings.contains(&format!("the {} schedule ends with the spine swung by", r.schedule.name()));
        assert_eq!(
            said,
            n.swing_deg.abs() > 45.0,
            "case {} {}: swing {}°, warnings {}",
            r.case,
            r.schedule.name(),
            n.swing_deg,
            r.warnings
        );
        swung += usize::from(said);
    }
    assert!(swung > 0, "the sample has a swung flip");
}
