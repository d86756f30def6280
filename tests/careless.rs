//! Careless input as a new user writes it: a problem file cut short or missing a section, a value
//! in the wrong unit, several files of which one is bad, a `--rate` the files cannot take, a
//! rapier run that does not converge. Each is said plainly: one error naming the field and the
//! file, or a warning, also with `--json`; never a number passed off as a result with exit 0.

mod common;

use common::catflip;
use std::path::PathBuf;

use catflip::problem::Problem;

/// A fresh scratch folder for this test binary.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("catflip-careless-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("a scratch folder");
    d
}

/// `text` written to `file` in a scratch folder `name`.
fn problem_file(name: &str, file: &str, text: &str) -> PathBuf {
    let path = scratch(name).join(file);
    std::fs::write(&path, text).expect("written");
    path
}

const PAPER: &str = include_str!("../problems/paper.toml");

#[test]
fn an_empty_problem_file_is_refused() {
    let path = problem_file("empty", "empty.toml", "# nothing but a comment\n");
    let err = Problem::load(&path, &[]).expect_err("refused").to_string();
    assert!(err.contains("empty.toml") && err.contains("holds no field"), "{err}");
}

#[test]
fn a_file_without_a_name_is_named_after_its_stem_not_the_paper() {
    let text: String = PAPER.lines().filter(|l| !l.starts_with("name")).map(|l| format!("{l}\n")).collect();
    let path = problem_file("stem", "my-robot.toml", &text);
    let p = Problem::load(&path, &[]).expect("loads");
    assert_eq!(p.name, "my-robot");
    // A stem that cannot name a folder is made one, its other characters `-`, and said
    // (`simulate my.cat.toml` was refused, though it writes no folder); one with nothing to keep
    // is refused, naming the field to give.
    for (file, name) in [("my robot.toml", "my-robot"), ("my.cat.toml", "my-cat")] {
        let made = problem_file("stem-made", file, &text);
        let p = Problem::load(&made, &[]).expect("loads");
        assert_eq!(p.name, name);
        let said = format!("cannot name a results folder (letters, digits, '-' and '_' only): named \"{name}\"");
        assert!(p.warnings().iter().any(|w| w.contains(&said)), "{:?}", p.warnings());
        // `--set name=...` names it, without a word.
        let named = Problem::load(&made, &["name=robot".into()]).expect("loads");
        assert_eq!(named.name, "robot");
        assert!(!named.warnings().iter().any(|w| w.contains("stem")), "{:?}", named.warnings());
    }
    let bad = problem_file("stem-bad", "....toml", &text);
    let err = Problem::load(&bad, &[]).expect_err("refused").to_string();
    assert!(err.starts_with("name = (not given)") && err.contains("give name = "), "{err}");
}

#[test]
fn a_file_cut_short_says_what_its_defaults_fill_in() {
    // Cut in the middle of [drop]: no height, no [manoeuvre], no last line break.
    let cut = &PAPER[..PAPER.find("height").expect("the paper's file gives a height")];
    let cut = cut.trim_end_matches('\n');
    let path = problem_file("cut", "cut.toml", cut);
    let warnings = Problem::load(&path, &[]).expect("loads").warnings();
    let has = |s: &str| warnings.iter().any(|w| w.contains(s));
    assert!(has("no drop.height: the default 10 m"), "{warnings:?}");
    assert!(has("no [manoeuvre] section") && has("theta_deg = 45.0"), "{warnings:?}");
    assert!(has("does not end with a line break"), "{warnings:?}");
    // The whole file: none of these.
    let whole = Problem::load(&problem_file("whole", "paper.toml", PAPER), &[]).expect("loads").warnings();
    assert!(!whole.iter().any(|w| w.contains("the file")), "{whole:?}");
    // An override that gives the section is not a section left out.
    let given = Problem::load(&path, &["manoeuvre.theta_deg=100".into()]).expect("loads").warnings();
    assert!(!given.iter().any(|w| w.contains("[manoeuvre]")), "{given:?}");
}

#[test]
fn values_in_the_wrong_unit_are_warned_of_naming_the_field_and_its_unit() {
    let cases = [
        ("manoeuvre.circulation=180", "manoeuvre.circulation = 180 rad", "degrees"),
        ("drop.height=10000", "drop.height = 10000 m", "mm or cm"),
        ("drop.height=0.001", "drop.height = 0.001 m", "km"),
        ("drop.gravity=980", "drop.gravity = 980 m/s²", "cm/s²"),
        ("manoeuvre.theta_deg=1.5708", "manoeuvre.theta_deg = 1.5708", "radians"),
        ("cat.length=1000", "cat.length = 1000 m", "mm or cm"),
        ("cat.mass=2000", "cat.mass = 2000 kg", "g?"),
        ("robust.spin_sigma_nms=10", "robust.spin_sigma_nms = 10", "N·m·s"),
    ];
    let paper = PathBuf::from("problems/paper.toml");
    let quiet = Problem::load(&paper, &[]).expect("loads").warnings();
    for (set, field, unit) in cases {
        assert!(!quiet.iter().any(|w| w.contains(field)), "{quiet:?}");
        let warnings = Problem::load(&paper, &[set.into()]).expect(set).warnings();
        assert!(warnings.iter().any(|w| w.contains(field) && w.contains(unit)), "{set}: {warnings:?}");
    }
}

/// A tail's or the legs' length or mass in the wrong unit: more than three times the cat's body
/// or less than a thousandth of it; the committed appendages are not warned of.
#[test]
fn appendages_in_the_wrong_unit_are_warned_of_naming_the_field() {
    let cases = [
        ("problems/legs.toml", "cat.legs.length=45", "cat.legs.length = 45 m is 22.5 times", "mm or cm"),
        ("problems/legs.toml", "cat.legs.length=8", "cat.legs.length = 8 m is 4 times", "too long"),
        ("problems/legs.toml", "cat.legs.mass=200", "cat.legs.mass = 200 kg is 100 times", "in g?"),
        ("problems/real-cat.toml", "cat.legs.rear.length=27", "cat.legs.rear.length = 27 m is", "mm or cm"),
        ("problems/tail.toml", "cat.tail.mass=0.0002", "cat.tail.mass = 2e-4 kg is 1e-4 times", "tonnes"),
        ("problems/tail.toml", "cat.tail.mass=7", "cat.tail.mass = 7 kg is 3.5 times", "too heavy"),
    ];
    for (file, set, field, unit) in cases {
        let path = PathBuf::from(file);
        let quiet = Problem::load(&path, &[]).expect("loads").warnings();
        assert!(!quiet.iter().any(|w| w.contains("cat.legs") || w.contains("cat.tail")), "{file}: {quiet:?}");
        let warnings = Problem::load(&path, &[set.into()]).expect(set).warnings();
        assert!(warnings.iter().any(|w| w.contains(field) && w.contains(unit)), "{set}: {warnings:?}");
    }
}

/// A calibration that has no π/C to start from names the field as the user wrote it (it said
/// `manoeuvre.circulation = "paper"`, which the user had not written, a QA run found).
#[test]
fn a_calibration_without_a_start_names_calibrated() {
    let (code, out, err) = catflip(&[
        "simulate",
        "problems/paper.toml",
        "--set",
        "manoeuvre.circulation=\"calibrated\"",
        "--set",
        "manoeuvre.theta_deg=179",
    ]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        err.starts_with("error: manoeuvre.circulation = \"calibrated\": the calibration starts from the paper's π/C"),
        "{err}"
    );
    assert!(err.contains("exceeds the 1000 rad") && !err.contains("\"paper\""), "{err}");
}

#[test]
fn json_output_keeps_the_warnings_on_stderr() {
    let (code, out, err) =
        catflip(&["simulate", "problems/paper.toml", "--set", "manoeuvre.circulation=180", "--json"]);
    assert_eq!(code, 0, "{err}");
    assert!(serde_json::from_str::<serde_json::Value>(&out).is_ok(), "stdout is the JSON alone: {out}");
    assert!(err.contains("warning: manoeuvre.circulation = 180 rad"), "{err}");
}

/// A file cut at a line break after a section's header, a half left to the defaults and a
/// shorthand no half uses are each warned of (a QA run found all three silent).
#[test]
fn an_empty_section_and_the_halves_defaults_are_warned_of() {
    let header = problem_file("bare", "bare.toml", "name = \"bare\"\n[cat]\nmass = 1.0\n[manoeuvre]\n");
    let warnings = Problem::load(&header, &[]).expect("loads").warnings();
    let has = |w: &[String], s: &str| w.iter().any(|w| w.contains(s));
    assert!(has(&warnings, "[manoeuvre] section holds no field: was the file cut short?"), "{warnings:?}");
    assert!(has(&warnings, "no cat.length: both halves take the default 1"), "{warnings:?}");
    assert!(!has(&warnings, "no cat.mass"), "{warnings:?}");
    // Only [cat.front]: the rear half is the default's, said so.
    let front =
        problem_file("front", "front.toml", "name = \"front\"\n[cat.front]\nmass = 0.8\nlength = 0.8\nradius = 0.1\n");
    let warnings = Problem::load(&front, &[]).expect("loads").warnings();
    assert!(has(&warnings, "no cat.mass: cat.rear takes the default 1"), "{warnings:?}");
    // [cat]'s mass when both halves give their own is used by neither.
    let unused = problem_file(
        "unused",
        "unused.toml",
        "name = \"unused\"\n[cat]\nmass = 3.0\nlength = 1.0\nradius = 0.1\n[cat.front]\nmass = 0.8\n[cat.rear]\nmass = 1.2\n",
    );
    let warnings = Problem::load(&unused, &[]).expect("loads").warnings();
    assert!(has(&warnings, "cat.mass is used by neither half"), "{warnings:?}");
    // The committed files say none of these.
    for file in ["paper", "unequal-halves", "kane-scher", "real-cat", "tail", "legs", "tail-robot"] {
        let w = Problem::load(std::path::Path::new(&format!("problems/{file}.toml")), &[]).expect("loads").warnings();
        assert!(
            !w.iter().any(|w| w.contains("cat.") && (w.contains("default") || w.contains("neither"))),
            "{file}: {w:?}"
        );
    }
}

/// `--set` given twice for one key, or replacing a whole section the file gives, is refused,
/// naming it (the last value won, or the section's other fields fell back to the defaults,
/// without a word).
#[test]
fn an_override_that_would_lose_a_value_is_refused() {
    let twice = ["cat.front.mass=1".to_string(), "cat.front.mass=2".to_string()];
    let err = Problem::load(std::path::Path::new("problems/paper.toml"), &twice).expect_err("refused").to_string();
    assert!(err.contains("cat.front.mass=2") && err.contains("set twice"), "{err}");
    // A key inside a section another override sets whole is set twice too.
    let inside = ["cat.front={mass=2.0}".to_string(), "cat.front.mass=1".to_string()];
    let err = Problem::load(std::path::Path::new("problems/paper.toml"), &inside).expect_err("refused").to_string();
    assert!(err.contains("cat.front.mass=1") && err.contains("set twice"), "{err}");
    let whole = ["cat={mass=1.2857}".to_string()];
    let err = Problem::load(std::path::Path::new("problems/real-cat.toml"), &whole).expect_err("refused").to_string();
    assert!(err.contains("replaces the whole [cat] section") && err.contains("legs"), "{err}");
    // The fields named are those lost, not the one the override gives.
    let err = Problem::load(std::path::Path::new("problems/paper.toml"), &["cat={mass=2.0}".to_string()])
        .expect_err("refused")
        .to_string();
    assert!(err.contains("whose other fields (length, radius) would fall back"), "{err}");
    // A section set whole with every field the file gives it loses nothing, and is taken.
    let all = ["cat={mass=2.0, length=1.0, radius=0.1}".to_string()];
    let p = Problem::load(std::path::Path::new("problems/paper.toml"), &all).expect("loads");
    assert_eq!(p.cat.front().mass, 2.0);
    // A section the file does not give can still be set whole.
    let new = ["cat.front={mass=0.8}".to_string()];
    let p = Problem::load(std::path::Path::new("problems/paper.toml"), &new).expect("loads");
    assert_eq!(p.cat.front().mass, 0.8);
}

/// `run` resolves every file before it writes anything: a tail among several files is refused
/// with the file named, and the first file's results are not written (a QA run found them
/// written, and the error without the file's name).
#[test]
fn a_cat_run_cannot_take_among_several_is_named_and_nothing_is_written() {
    let out = scratch("several-tail").join("results");
    let (code, _, err) =
        catflip(&["run", "problems/kane-scher.toml", "problems/tail.toml", "--out", out.to_str().expect("utf-8")]);
    assert_ne!(code, 0);
    assert!(err.contains("tail.toml: cat.tail"), "{err}");
    assert!(!out.exists(), "results were written");
}

/// `compare-models` refuses a problem whose own halves cannot take its schedule, as `simulate`
/// does (a QA run got rows "not run" beside the models that could, and exit 0).
#[test]
fn compare_models_refuses_a_circulation_its_own_halves_do_not_define() {
    let (code, out, err) =
        catflip(&["compare-models", "problems/kane-scher.toml", "--quiet", "--set", "cat.rear.mass=1.2"]);
    assert_ne!(code, 0);
    assert!(out.is_empty() && err.contains("circulation = \"paper\"") && err.contains("cat.rear.mass"), "{err}");
}

/// A `--out` that cannot take the results is refused before the optimisation runs, not after it:
/// with one iteration no model has an optimum, which a comparison run first would report (and
/// write nothing); refused first, the `--out` is what the error names.
#[test]
fn an_out_under_a_file_is_refused_before_the_work() {
    let file = problem_file("out-file", "a-file", "not a folder\n");
    let (code, out, err) = catflip(&[
        "compare-models",
        "problems/kane-scher.toml",
        "--quiet",
        "--set",
        "optimize.whole.max_iterations=1",
        "--out",
        file.to_str().expect("utf-8"),
    ]);
    assert_ne!(code, 0);
    assert!(out.is_empty() && err.contains("a-file is a file, not a folder"), "{err}");
    assert!(!err.contains("no cat model has an optimum"), "the comparison ran first: {err}");
}

/// What catflip writes back loads without the warnings meant for a careless file: the provenance
/// TOML of a report (an empty `[actuator]`, every `[cat]` number, the defaults included), and a
/// whole `[cat]` given by one override.
#[test]
fn a_problem_catflip_wrote_loads_without_careless_warnings() {
    for file in ["paper", "unequal-halves", "real-cat"] {
        let p = Problem::load(std::path::Path::new(&format!("problems/{file}.toml")), &[]).expect("loads");
        let text = toml::to_string(&p).expect("TOML");
        let again = Problem::from_user_text(&text, "written.toml", &[]).expect("loads back");
        let w = again.warnings();
        assert!(!w.iter().any(|w| w.contains("cut short") || w.contains("cat.")), "{file}: {w:?}\n{text}");
    }
    let nameless = problem_file("no-cat", "no-cat.toml", "name = \"no-cat\"\n[drop]\nheight = 10.0\n");
    let whole = ["cat={mass=2.0,length=1.0,radius=0.1}".to_string()];
    let w = Problem::load(&nameless, &whole).expect("loads").warnings();
    assert!(!w.iter().any(|w| w.contains("cat.")), "{w:?}");
}

/// Serde's words become the file's: a joint given as a number, and the list of the halves'
/// joints, which leaves the tail's hinge out.
#[test]
fn a_joint_given_wrongly_is_named_in_the_users_words() {
    let paper = std::path::Path::new("problems/paper.toml");
    let err = Problem::load(paper, &["cat.joint=1".to_string()]).expect_err("refused").to_string();
    assert!(err.contains("expected a name in quotes in `cat.joint`") && !err.contains("unit variant"), "{err}");
    let err = Problem::load(paper, &["cat.joint=ball".to_string()]).expect_err("refused").to_string();
    assert!(err.contains("`spherical` (a hinge joins a tail only)") && !err.contains("`hinge`"), "{err}");
}

#[test]
fn a_bad_file_among_several_is_named_and_nothing_is_written() {
    let bad = problem_file("several", "falls-up.toml", &PAPER.replace("height = 10.0", "height = -1.0"));
    let out = scratch("several-out").join("results");
    let (code, _, err) = catflip(&[
        "run",
        "problems/kane-scher.toml",
        bad.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("falls-up.toml: drop.height = -1"), "{err}");
    assert!(!out.exists(), "results were written");
}

#[test]
fn a_rate_the_files_cannot_take_is_refused_before_anything_runs() {
    let out = scratch("rate").join("results");
    let (code, _, err) =
        catflip(&["run", "problems/kane-scher.toml", "--rate", "1e9", "--out", out.to_str().expect("utf-8")]);
    assert_ne!(code, 0);
    assert!(err.contains("kane-scher.toml: --rate 1000000000") && err.contains("rows"), "{err}");
    assert!(!out.exists(), "a folder was left behind");
}

#[test]
fn a_joint_limit_too_tight_to_flip_is_named() {
    let (code, _, err) = catflip(&[
        "optimize",
        "problems/paper.toml",
        "--whole",
        "--quiet",
        "--set",
        "optimize.whole.joint_limit_deg=2",
    ]);
    assert_ne!(code, 0);
    let last = err.lines().last().unwrap_or_default();
    assert!(last.contains("optimize.whole.joint_limit_deg = 2 lets a start bend only 1.000°"), "{err}");
    assert!(!last.contains("lower manoeuvre.theta_deg"), "the advice is the joint limit's: {err}");
}

#[test]
fn an_inconclusive_rapier_run_is_no_result_and_exits_non_zero() {
    // A spin of 91 turns: rapier's runs do not converge within the step budget.
    let (code, out, err) =
        catflip(&["simulate", "problems/paper.toml", "--engine", "rapier", "--set", "drop.angular_momentum=[0,0,4]"]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(out.lines().nth(1).is_some_and(|l| l.contains("NO RESULT") && l.contains("inconclusive")), "{out}");
    assert!(err.lines().last().is_some_and(|l| l.starts_with("error: rapier's verification is inconclusive")), "{err}");
}

#[test]
fn a_duplicate_key_is_named_on_its_own_line() {
    // toml says "duplicate key" without the key; the message names it, on the repeat's line.
    let path = problem_file("dup", "dup.toml", "name = \"x\"\n[cat]\nmass = 1.0\nlength = 1.0\nmass = 2.0\n");
    let err = Problem::load(&path, &[]).expect_err("refused").to_string();
    assert!(err.ends_with("dup.toml, line 5: duplicate key `mass`"), "{err}");
    // An error at the start of a line is on that line, not the one before.
    let path = problem_file("unclosed", "unclosed.toml", "name = \"x\"\n[cat\nmass = 1.0\n");
    let err = Problem::load(&path, &[]).expect_err("refused").to_string();
    assert!(err.contains("unclosed.toml, line 2:"), "{err}");
}

#[test]
fn a_rate_too_coarse_for_the_shortest_phase_is_warned_of() {
    use catflip::exchange::ExportOptions;
    // The paper's shortest phase: 0.2 of a 1.43 s fall.
    let paper = Problem::default();
    let coarse = ExportOptions { rate_hz: Some(0.1), ..Default::default() }.coarse(&paper);
    assert!(coarse.is_some_and(|w| w.starts_with("--rate 0.1 Hz gives 0.03 rows") && w.contains("35 Hz")));
    assert_eq!(ExportOptions { rate_hz: Some(1000.0), ..Default::default() }.coarse(&paper), None);
    assert_eq!(ExportOptions::default().coarse(&paper), None);
}

#[test]
fn a_schedule_file_made_for_another_cat_or_release_is_said_to_be() {
    // The committed optimum of unequal halves, on the paper's equal halves: its sidecar says so.
    let file = "results/unequal-halves/schedules/whole-optimum.csv";
    let (code, _, err) = catflip(&["simulate", "problems/paper.toml", "--schedule", file]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("made for problem \"unequal-halves\"") && err.contains("front half 0.8 kg"), "{err}");
    // On its own problem, nothing of the kind.
    let (code, _, err) = catflip(&["simulate", "problems/unequal-halves.toml", "--schedule", file]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("made for problem") && !err.contains("planned for a release"), "{err}");
    // Released with a spin it was not planned for (it landed at −132.5°, unsaid).
    let (code, _, err) = catflip(&[
        "simulate",
        "problems/unequal-halves.toml",
        "--schedule",
        file,
        "--set",
        "drop.angular_momentum=[0,0,0.01]",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains(
            "planned for a release with drop.angular_momentum = [0, 0, 0] N·m·s, this problem's is [0, 0, 0.01]"
        ),
        "{err}"
    );
}

#[test]
fn robustness_settings_that_say_little_are_warned_of() {
    let paper = PathBuf::from("problems/paper.toml");
    let quiet = Problem::load(&paper, &[]).expect("loads").warnings();
    assert!(!quiet.iter().any(|w| w.starts_with("robust.")), "{quiet:?}");
    let few = Problem::load(&paper, &["robust.trials=5".into()]).expect("loads").warnings();
    assert!(few.iter().any(|w| w.starts_with("robust.trials = 5: percentiles")), "{few:?}");
    let any = Problem::load(&paper, &["robust.tolerance_deg=180".into()]).expect("loads").warnings();
    assert!(any.iter().any(|w| w.starts_with("robust.tolerance_deg = 180")), "{any:?}");
    // 5° typed in radians.
    let radians = Problem::load(&paper, &["robust.tolerance_deg=0.0873".into()]).expect("loads").warnings();
    assert!(radians.iter().any(|w| w.contains("robust.tolerance_deg = 0.0873: is it in radians?")), "{radians:?}");
}

/// A tolerance that makes a verdict or a convergence say nothing is refused, naming the field (a
/// QA run had rapier 27° from the exact twist "verified", a peak torque tolerance of 2 meant as
/// 2 %, and an optimality of 1 end the whole optimiser "converged" at twice its optimum).
#[test]
fn tolerances_that_would_make_a_verdict_empty_are_refused() {
    let paper = PathBuf::from("problems/paper.toml");
    for (set, field) in [
        ("rapier.twist_tolerance_deg=1000", "rapier.twist_tolerance_deg = 1000: must be at most 10°"),
        ("rapier.swing_tolerance_deg=11", "rapier.swing_tolerance_deg = 11: must be at most 10°"),
        ("rapier.peak_torque_tolerance=2", "rapier.peak_torque_tolerance = 2: is a fraction (0.02 is 2 %)"),
        ("optimize.whole.optimality=1", "optimize.whole.optimality = 1: must be at most 1e-3"),
    ] {
        let err = Problem::load(&paper, &[set.into()]).expect_err(set).to_string();
        assert!(err.contains(field), "{set}: {err}");
    }
    // The largest accepted.
    for set in ["rapier.twist_tolerance_deg=10", "rapier.peak_torque_tolerance=0.5", "optimize.whole.optimality=1e-3"] {
        assert!(Problem::load(&paper, &[set.into()]).is_ok(), "{set}");
    }
}

#[test]
fn a_results_folder_holding_a_file_catflip_did_not_write_is_not_replaced() {
    let out = scratch("foreign");
    let folder = out.join("paper-robust");
    std::fs::create_dir_all(&folder).expect("a folder");
    std::fs::write(folder.join("mine.txt"), "keep").expect("written");
    let args = ["robust", "problems/paper.toml", "--set", "robust.trials=20", "--out", out.to_str().expect("utf-8")];
    let (code, _, err) = catflip(&args);
    assert_ne!(code, 0);
    assert!(err.contains("mine.txt") && err.contains("catflip did not write"), "{err}");
    assert_eq!(std::fs::read_to_string(folder.join("mine.txt")).expect("kept"), "keep");
    // Without the user's file, catflip writes the folder, with its list of files, and replaces it
    // on the next run.
    std::fs::remove_file(folder.join("mine.txt")).expect("removed");
    assert_eq!(catflip(&args).0, 0);
    let listed = std::fs::read_to_string(folder.join(".catflip-files")).expect("the list");
    assert!(listed.lines().any(|l| l == "robust.md"), "{listed}");
    assert_eq!(catflip(&args).0, 0, "its own folder is replaced");
}

#[test]
fn exact_engine_rows_of_robust_csv_leave_the_unused_servo_gains_empty() {
    let out = scratch("robust-csv");
    let args = ["robust", "problems/paper.toml", "--set", "robust.trials=20", "--out", out.to_str().expect("utf-8")];
    assert_eq!(catflip(&args).0, 0);
    let csv = std::fs::read_to_string(out.join("paper-robust/robust.csv")).expect("written");
    let header: Vec<&str> = csv.lines().next().expect("a header").split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).expect("a column");
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 20);
    for r in &rows {
        assert_eq!(r[at("engine")], "exact");
        assert_eq!((r[at("gain1")], r[at("gain2")]), ("", ""), "{r:?}");
        assert!(r[at("landing_error_deg")].parse::<f64>().is_ok(), "{r:?}");
    }
}

/// `optimize` says how its optima meet the problem's motors (its text said nothing of a torque
/// limit twenty times exceeded, a QA run found; `compare` says it), and nothing with ideal motors.
#[test]
fn optimize_says_how_its_optima_meet_the_motors() {
    let (code, out, err) = catflip(&["optimize", "problems/paper.toml", "--set", "actuator.torque_limit_nm=1"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("**Against the motors** (`[actuator]`):"), "{out}");
    assert!(out.contains("- exact-refined: exceeds joint 1's torque limit"), "{out}");
    let (code, out, err) = catflip(&["optimize", "problems/paper.toml"]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("Against the motors"), "{out}");
}

/// `robust` refuses a schedule far longer or shorter than the fall, whose every trial runs to its
/// end (times in milliseconds: warned of, then more than two minutes of trials, a QA run found).
#[test]
fn robust_refuses_a_schedule_of_another_fall() {
    let dir = scratch("robust-ms");
    let csv = std::fs::read_to_string("results/paper/schedules/whole-optimum.csv").expect("the committed optimum");
    let mut lines = csv.lines();
    let mut ms = lines.next().unwrap_or_default().to_string() + "\n";
    for line in lines {
        let (t, rest) = line.split_once(',').unwrap_or((line, ""));
        let t: f64 = t.parse().expect("a time");
        ms += &format!("{},{rest}\n", t * 1e3);
    }
    let file = dir.join("ms.csv");
    std::fs::write(&file, ms).expect("writable");
    let (code, _, err) = catflip(&["robust", "problems/paper.toml", "--schedule", &file.display().to_string()]);
    assert_eq!(code, 1, "{err}");
    let last = err.lines().last().unwrap_or_default();
    assert!(last.contains("the schedule lasts 1428.57 s, the fall 1.42857 s") && last.contains("is refused"), "{err}");
}

#[test]
fn bench_warns_of_a_careless_problem_as_every_command_does() {
    // `bench` loaded its problem without printing its warnings: a mass in grams went unsaid.
    // Refused for its spin right after loading, so the test runs no benchmark.
    let out = std::env::temp_dir().join(format!("catflip-careless-bench-{}", std::process::id()));
    let out = out.to_string_lossy().into_owned();
    let (code, _, err) =
        catflip(&["bench", "--set", "cat.mass=1000", "--set", "drop.angular_momentum=[0,0,0.01]", "--out", &out]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("warning: cat.mass = 1000 kg is outside the 0.01–500 kg"), "{err}");
    assert!(err.contains("error: drop.angular_momentum = [0, 0, 0.01]: bench assumes"), "{err}");
    assert!(!std::path::Path::new(&out).exists(), "a refused bench wrote {out}");
}

/// The interior-point method asked for by name where it does not plan (a bend limit, motor
/// limits, the effort) is warned of, naming what keeps the trust-region loop; asked for on the
/// least peak with ideal motors, or beyond two motors within one torque limit, it is not; as the
/// default, not asked for, it is not either. An unknown method is refused naming the field and
/// the three it knows.
#[test]
fn the_interior_point_method_where_it_does_not_plan_is_warned_of() {
    let paper = std::path::Path::new("problems/paper.toml");
    let method = "optimize.whole.method=\"interior-point\"";
    let said = |sets: &[&str]| {
        let sets: Vec<String> = std::iter::once(method).chain(sets.iter().copied()).map(String::from).collect();
        let warnings = Problem::load(paper, &sets).expect("loads").warnings();
        warnings.into_iter().find(|w| w.starts_with("optimize.whole.method"))
    };
    assert_eq!(said(&[]), None, "the least peak with ideal motors is the interior point's");
    let bend = said(&["optimize.whole.min_angle_deg=120"]).expect("a bend limit is warned of");
    assert!(bend.contains("optimize.whole.min_angle_deg") && bend.contains("trust-region loop"), "{bend}");
    let default = Problem::load(paper, &["optimize.whole.min_angle_deg=120".into()]).expect("loads").warnings();
    assert!(!default.iter().any(|w| w.starts_with("optimize.whole.method")), "the default: {default:?}");
    let both = said(&["actuator.torque_limit_nm=1", "optimize.whole.objective=\"energy\""]).expect("warned of");
    assert!(both.contains("[actuator]") && both.contains("objective = \"energy\""), "{both}");
    // Beyond two motors one torque limit on every motor is planned as the least peak with ideal
    // motors, then slowed: the interior point's, whatever the objective; not on two motors.
    let tail = Problem::load(
        std::path::Path::new("problems/tail.toml"),
        &[method.into(), "actuator.torque_limit_nm=1".into(), "optimize.whole.objective=\"energy\"".into()],
    )
    .expect("loads");
    assert!(!tail.warnings().iter().any(|w| w.starts_with("optimize.whole.method")), "{:?}", tail.warnings());
    let unknown = Problem::load(paper, &["optimize.whole.method=\"ipm\"".into()]).expect_err("refused").to_string();
    assert!(
        unknown.contains("optimize.whole.method")
            && unknown.contains("auto")
            && unknown.contains("trust-region")
            && unknown.contains("interior-point"),
        "{unknown}"
    );
}
