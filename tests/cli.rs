//! The command line as a user meets it: the JSON contract of DESIGN.md §8, clear errors with a
//! non-zero exit, and no half-written results.

mod common;

use common::catflip;
use std::path::PathBuf;
use std::process::{Command, Stdio};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("catflip-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn simulate_json_carries_the_contract_fields() {
    let (code, out, err) = catflip(&["simulate", "problems/paper.toml", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("one JSON object");
    for key in
        ["engine", "twist_deg", "swing_deg", "circulation_rad", "peak_torque_nm", "velocity_jumps", "momentum_max"]
    {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    for phase in ["bend", "twist", "unbend"] {
        assert_eq!(v["peak_torque_nm"][phase].as_array().map(Vec::len), Some(2), "{phase}: one value per joint");
    }
    assert!(v["peak_torque_nm"]["max"].as_f64().is_some());
    assert_eq!(v["engine"], "exact");
    // The paper's cosine ends at 2ω0: exactly one jump, when unbending starts.
    assert_eq!(v["velocity_jumps"].as_array().map(Vec::len), Some(1));
    assert_eq!(v["converged"], true);
}

#[test]
fn calibrated_simulation_reports_the_circulation_found() {
    let (code, out, err) =
        catflip(&["simulate", "problems/paper.toml", "--json", "--set", "manoeuvre.circulation=calibrated"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    let found = v["calibration"]["circulation"].as_f64().expect("calibration reported");
    assert!((found - v["circulation_rad"].as_f64().unwrap_or(f64::NAN)).abs() < 1e-15);
    assert!((v["twist_deg"].as_f64().unwrap_or(0.0).abs() - 180.0).abs() < 1e-6, "{}", v["twist_deg"]);
}

#[test]
fn rapier_simulation_reports_its_step() {
    let (code, out, err) =
        catflip(&["simulate", "problems/paper.toml", "--engine", "rapier", "--dt", "0.002", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    assert_eq!(v["engine"], "rapier");
    let dt = v["dt"].as_f64().expect("dt");
    assert!(dt > 0.0 && dt <= 0.002, "dt = {dt}");
    assert!(v["tracking_error_rad"].as_array().is_some());
}

/// `compare --verify` verifies every library profile in rapier: one entry per row of the table,
/// in its order, each with its verdict, and the Markdown ends with the verdicts. Without
/// `--verify` the JSON is the table alone.
#[test]
fn compare_verify_checks_every_library_profile_in_rapier() {
    let (code, out, err) = catflip(&["compare", "problems/paper.toml", "--verify", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("one JSON object");
    let rows = v["table"]["rows"].as_array().expect("the table's rows");
    let rapier = v["rapier"].as_array().expect("rapier's entries");
    assert_eq!(rows.len(), 9, "the nine library profiles");
    let profiles = |x: &[serde_json::Value]| x.iter().map(|e| e["profile"].clone()).collect::<Vec<_>>();
    assert_eq!(profiles(rows), profiles(rapier));
    // Every library profile of the paper's problem is verified: their extrapolated twists lie
    // within 0.03° of the exact engine's and rapier's own estimates within 0.17°, against the
    // 0.5° tolerance (the table of `catflip compare problems/paper.toml --verify`).
    for e in rapier {
        assert_eq!(e["verdict"], "verified", "{}: {}", e["profile"], e["verification"]["verdict"]);
    }
    let (code, md, err) = catflip(&["compare", "problems/paper.toml", "--verify"]);
    assert_eq!(code, 0, "{err}");
    assert!(md.contains("\nVerdicts: 9 verified, 0 not verified, 0 inconclusive"), "{md}");
    let (code, out, err) = catflip(&["compare", "problems/paper.toml", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("one JSON object");
    assert!(v.get("rapier").is_none() && v["rows"].as_array().is_some_and(|r| r.len() == 9), "{v}");
    // A step budget below rapier's first run: every verdict inconclusive, the table printed, and
    // a non-zero exit that says so.
    let (code, md, err) = catflip(&["compare", "problems/paper.toml", "--verify", "--set", "rapier.step_budget=1"]);
    assert_ne!(code, 0, "{md}");
    assert!(md.contains("Verdicts: 0 verified, 0 not verified, 9 inconclusive"), "{md}");
    assert!(err.contains("rapier has no result for 9 of the 9 profiles"), "{err}");
}

#[test]
fn bad_input_gives_one_clear_error_and_a_non_zero_exit() {
    let (code, out, err) = catflip(&["simulate", "problems/paper.toml", "--set", "cat.mass=-1"]);
    assert_ne!(code, 0);
    assert!(out.is_empty(), "nothing on stdout: {out}");
    assert_eq!(err.trim(), "error: cat.mass = -1: must be positive");
    let (code, _, err) = catflip(&["audit", "problems/nope.toml"]);
    assert_ne!(code, 0);
    assert!(err.contains("cannot read problem file problems/nope.toml"), "{err}");
}

#[test]
fn a_bad_problem_in_a_run_writes_nothing() {
    let out = scratch("bad-run");
    let (code, _, err) = catflip(&[
        "run",
        "problems/paper.toml",
        "problems/script-defaults.toml",
        "--set",
        "manoeuvre.phases=[0.3, 0.3, 0.3]",
        "--out",
        out.to_str().unwrap_or("/nonexistent"),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("manoeuvre.phases"), "{err}");
    assert!(!out.exists() || std::fs::read_dir(&out).map(|d| d.count()).unwrap_or(0) == 0, "results were written");
}

#[test]
fn cone_at_gimbal_lock_is_refused_from_the_command_line() {
    let (code, _, err) = catflip(&[
        "simulate",
        "problems/paper.toml",
        "--set",
        "manoeuvre.bend_path=cone",
        "--set",
        "manoeuvre.theta_deg=90",
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("gimbal lock"), "{err}");
}

#[test]
fn a_closed_stdout_ends_a_command_quietly() {
    // `catflip … | head -1`: the reader is gone before the first write. Rust ignores SIGPIPE, so
    // the write fails with EPIPE, which `println!` turns into a panic (exit 101).
    for args in [
        &["simulate", "problems/paper.toml", "--json"][..],
        &["simulate", "problems/paper.toml"],
        &["audit", "problems/paper.toml", "--json"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_catflip"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the binary runs");
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("the binary ends");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {err}");
        assert!(!err.contains("panicked") && !err.contains("Broken pipe"), "{args:?}: {err}");
    }
}

#[test]
fn robust_with_both_engines_and_landing_writes_its_report_and_pictures() {
    let out = scratch("robust");
    let dir = out.display().to_string();
    let (code, stdout, err) = catflip(&[
        "robust",
        "problems/paper.toml",
        "--schedule",
        "results/paper/schedules/whole-optimum.csv",
        "--set",
        "robust.engine=both",
        "--set",
        "robust.landing=true",
        "--set",
        "robust.trials=4",
        "--set",
        "robust.dt_s=4e-4",
        "--out",
        &dir,
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON object");
    let engines: Vec<&str> =
        v["checks"].as_array().expect("checks").iter().filter_map(|c| c["engine"].as_str()).collect();
    assert_eq!(engines, ["exact", "rapier"]);
    assert!(v["checks"][1]["tracking"]["landing"]["verdict"].as_str().is_some_and(|s| s.contains("lands on its feet")));
    let folder = out.join("paper-robust");
    for f in [
        "robust.md",
        "robust.csv",
        "robust.json",
        "robust.png",
        "robust_histogram.png",
        "robust_histogram.svg",
        "robust_worst_filmstrip.png",
        "robust_touchdown_filmstrip.png",
    ] {
        assert!(folder.join(f).is_file(), "missing {f}");
    }
    let md = std::fs::read_to_string(folder.join("robust.md")).expect("the report");
    assert!(md.contains("**Landing: the cat lands on its feet"), "{md}");
    let _ = std::fs::remove_dir_all(&out);
}

/// Rapier builds unequal halves on the universal joint and Kane and Scher's no-twist joint (a ball
/// joint): `simulate --engine rapier` gives a verdict on both.
#[test]
fn rapier_verifies_unequal_halves_and_the_no_twist_joint() {
    for problem in ["problems/unequal-halves.toml", "problems/kane-scher.toml"] {
        let (code, out, err) = catflip(&["simulate", problem, "--engine", "rapier", "--json"]);
        assert_eq!(code, 0, "{problem}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
        assert_eq!(v["engine"], "rapier");
        assert_eq!(v["verdict"], "verified", "{problem}: {}", v["verification"]);
    }
}

/// `compare-models` with no model able to converge (two iterations): the table says so, nothing
/// is written, and the command exits non-zero naming why; with enough iterations it exits 0,
/// writes its folder and its JSON carries one row per model (the universal, no-twist and
/// spherical joints).
#[test]
fn compare_models_says_when_no_model_has_an_optimum() {
    let out = scratch("compare-models");
    let coarse = ["--set", "optimize.whole.control_points=30", "--set", "optimize.whole.switch_refinements=0"];
    let dir = out.display().to_string();
    let mut args = vec!["compare-models", "problems/kane-scher.toml", "--quiet", "--out", &dir];
    args.extend(["--set", "optimize.whole.max_iterations=2"]);
    args.extend(coarse);
    let (code, text, err) = catflip(&args);
    assert_ne!(code, 0, "{text}");
    assert!(err.contains("no cat model has an optimum"), "{err}");
    assert!(text.contains("**no optimum**"), "{text}");
    assert!(!out.exists(), "nothing is written without an optimum");
    let mut args = vec!["compare-models", "problems/kane-scher.toml", "--json", "--out", &dir];
    args.extend(coarse);
    let (code, json, err) = catflip(&args);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&json).expect("one JSON object");
    assert_eq!(v["rows"].as_array().map(Vec::len), Some(3), "{json}");
    assert!(v["cheapest"].as_str().is_some(), "{json}");
    assert!(out.join("kane-scher-models").join("models.md").is_file());
    let _ = std::fs::remove_dir_all(&out);
}

/// `optimize --whole --out`: the optimum's folder holds its report, its schedule file and the
/// model files, and the schedule file read back by `simulate --schedule` is the optimum (the
/// flip and the peak of `whole.json`), on the universal and the no-twist joint (MJCF only); a
/// release with spin is refused naming `drop.angular_momentum` before anything runs, and without
/// an optimum nothing is written.
#[test]
fn optimize_whole_out_writes_a_schedule_file_that_reads_back_as_the_optimum() {
    let out = scratch("optimize-whole");
    let dir = out.display().to_string();
    let coarse = [
        "--set",
        "optimize.whole.control_points=40",
        "--set",
        "optimize.whole.switch_refinements=0",
        "--set",
        "optimize.whole.starts=[\"cone-mirrored\"]",
    ];
    let mut args = vec!["optimize", "problems/unequal-halves.toml", "--whole", "--quiet", "--out", &dir];
    args.extend(coarse);
    let (code, _, err) = catflip(&args);
    assert_eq!(code, 0, "{err}");
    let folder = out.join("unequal-halves-whole");
    for f in ["whole.md", "whole.json", "whole-optimum.csv", "whole-optimum.json", "model.urdf", "model.xml"] {
        assert!(folder.join(f).is_file(), "{f} missing");
    }
    assert!(folder.join("whole_filmstrip.png").is_file(), "no filmstrip");
    let md = std::fs::read_to_string(folder.join("whole.md")).expect("whole.md");
    assert!(md.contains("Regenerate with `cargo run --release -- optimize problems/unequal-halves.toml --whole --out "));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("whole.json")).expect("whole.json")).expect("JSON");
    let peak = json["peak_torque_nm"]["max"].as_f64().expect("the optimum's peak");
    let csv = folder.join("whole-optimum.csv").display().to_string();
    let (code, back, err) = catflip(&["simulate", "problems/unequal-halves.toml", "--schedule", &csv, "--json"]);
    assert_eq!(code, 0, "{err}");
    let back: serde_json::Value = serde_json::from_str(&back).expect("one JSON object");
    let twist = back["twist_deg"].as_f64().expect("twist");
    assert!((twist.abs() - 180.0).abs() <= 1e-6, "the file's flip {twist}°");
    let read = back["peak_torque_nm"]["max"].as_f64().expect("peak");
    // The CSV carries q, q̇, q̈ at full precision with rows at every knot, and a quintic Hermite
    // between rows reproduces the cubic pieces between knots.
    assert!((read - peak).abs() <= 1e-9 * peak, "the file's peak {read} N·m against the optimum's {peak}");
    let _ = std::fs::remove_dir_all(&out);

    // Kane and Scher's no-twist joint: the MJCF (a ball joint) and the URDF (pyBullet's spherical
    // joint), and the schedule file reads back as the optimum on the same cat.
    let mut args = vec!["optimize", "problems/kane-scher.toml", "--whole", "--quiet", "--out", &dir];
    args.extend(&coarse[..4]);
    let (code, _, err) = catflip(&args);
    assert_eq!(code, 0, "{err}");
    let folder = out.join("kane-scher-whole");
    for f in ["whole.md", "whole.json", "whole-optimum.csv", "whole-optimum.json", "model.xml", "model.urdf"] {
        assert!(folder.join(f).is_file(), "{f} missing");
    }
    let urdf = std::fs::read_to_string(folder.join("model.urdf")).expect("model.urdf");
    assert!(urdf.contains("type=\"spherical\""), "{urdf}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("whole.json")).expect("whole.json")).expect("JSON");
    let (peak, twist) =
        (json["peak_torque_nm"]["max"].as_f64().expect("peak"), json["twist_deg"].as_f64().expect("twist"));
    let csv = folder.join("whole-optimum.csv").display().to_string();
    let (code, back, err) = catflip(&["simulate", "problems/kane-scher.toml", "--schedule", &csv, "--json"]);
    assert_eq!(code, 0, "{err}");
    let back: serde_json::Value = serde_json::from_str(&back).expect("one JSON object");
    let read = back["twist_deg"].as_f64().expect("twist");
    assert!((read - twist).abs() <= 1e-9, "the file's flip {read}° against the optimum's {twist}°");
    let read = back["peak_torque_nm"]["max"].as_f64().expect("peak");
    assert!((read - peak).abs() <= 1e-9 * peak, "the file's peak {read} N·m against the optimum's {peak}");
    let _ = std::fs::remove_dir_all(&out);

    // A release with spin is refused before anything runs (the spherical joint is refused by the
    // problem file itself; tests/exchange_models.rs refuses it in the files too).
    let mut args = vec!["optimize", "problems/kane-scher.toml", "--whole", "--quiet", "--out", &dir];
    args.extend(coarse);
    args.extend(["--set", "drop.angular_momentum=[0,0,0.01]"]);
    let (code, _, err) = catflip(&args);
    assert_ne!(code, 0);
    assert!(err.contains("error: drop.angular_momentum = [0, 0, 0.01]: optimize --whole --out"), "{err}");
    assert!(!out.exists(), "a refused --out writes nothing");

    let mut args = vec!["optimize", "problems/unequal-halves.toml", "--whole", "--quiet", "--out", &dir];
    args.extend(coarse);
    args.extend(["--set", "optimize.whole.max_iterations=2"]);
    let (code, _, err) = catflip(&args);
    assert_ne!(code, 0);
    assert!(err.contains("error: no optimum"), "{err}");
    assert!(!out.exists(), "nothing is written without an optimum");
}

/// A rapier step too coarse for the tracked scene's servo: a warning before the run (its stiffest
/// mode, 2π · 10 Hz · 1e-3 s · √1.2 · 5.8 = 0.40 rad per step), and when a trial
/// diverges the run stops with one error naming the trial, the controller and `robust.dt_s`
/// (the nominal paper cat's open loop diverges at t ≈ 0.18 s with a 1e-3 s step), nothing written.
#[test]
fn a_diverged_robust_trial_is_named_with_the_step_to_shorten() {
    let out = scratch("robust-diverged");
    let dir = out.display().to_string();
    let (code, _, err) = catflip(&[
        "robust",
        "problems/paper.toml",
        "--set",
        "robust.engine=rapier",
        "--set",
        "robust.dt_s=1e-3",
        "--set",
        "robust.trials=2",
        "--out",
        &dir,
    ]);
    assert_ne!(code, 0, "{err}");
    assert!(
        err.contains(
            "warning: robust.servo_hz = 10 at robust.dt_s = 0.001 turns the servo's stiffest mode by 0.40 rad per step"
        ),
        "{err}"
    );
    assert!(err.contains("error: robust: trial "), "{err}");
    assert!(err.contains("(open loop) diverged in rapier"), "{err}");
    assert!(err.contains("with robust.dt_s = 1e-3 s"), "{err}");
    assert!(!out.exists(), "a stopped run writes nothing");
}

/// Issue 22: `[cat.tail]` and `[cat.legs]` are compared by `compare-models` alone; every command
/// that measures two bodies refuses them with one error naming the section, a non-zero exit and
/// no results.
#[test]
fn a_tail_or_legs_are_refused_by_the_commands_that_measure_two_bodies() {
    let out = scratch("appendage-refused");
    let out_arg = out.to_string_lossy().to_string();
    for (name, field) in [("tail", "cat.tail"), ("legs", "cat.legs")] {
        let problem = format!("problems/{name}.toml");
        for args in [
            vec!["simulate", &problem],
            vec!["compare", &problem],
            vec!["optimize", &problem, "--whole"],
            vec!["audit", &problem],
            vec!["run", &problem, "--out", &out_arg],
        ] {
            let (code, _, stderr) = catflip(&args);
            assert_ne!(code, 0, "{args:?}");
            let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
            assert_eq!(errors.len(), 1, "{args:?}: {stderr}");
            // `run` takes several files and names the one refused first.
            let named =
                if args[0] == "run" { format!("error: {problem}: {field}:") } else { format!("error: {field}:") };
            assert!(errors[0].starts_with(&named) && errors[0].contains("compare-models"), "{args:?}: {stderr}");
        }
        assert!(!out.join(name).exists(), "no results are written");
    }
}

/// A verification without one usable run is no result: `run` and `optimize --whole --verify`
/// exit non-zero, saying so, as `simulate --engine rapier` and `compare --verify` do (both
/// exited 0, a QA run found, with every verification "inconclusive"); `run` writes its complete
/// results all the same (they say why for each).
#[test]
fn a_verification_without_a_result_exits_non_zero() {
    let out = scratch("no-rapier-result");
    let o = out.display().to_string();
    let (code, _, err) =
        catflip(&["run", "problems/paper.toml", "--set", "rapier.step_budget=10", "--out", &o, "--quiet"]);
    assert_eq!(code, 1, "{err}");
    let last = err.lines().last().unwrap_or_default();
    assert!(
        last.starts_with("error: run: rapier has no result (inconclusive: no usable run) in paper (14 schedules)"),
        "{err}"
    );
    assert!(out.join("paper/verification.md").is_file(), "the results are written");
    let (code, _, err) =
        catflip(&["optimize", "problems/paper.toml", "--whole", "--verify", "--set", "rapier.step_budget=10"]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.ends_with(
            "rapier has no result for the optimum (inconclusive: no usable run; the verification says why)\n"
        ),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// A file of `run` that fails in its computation is named, with what was written before it (the
/// error named neither the file nor the field, a QA run found).
#[test]
fn run_names_the_file_that_fails_and_what_was_written_before() {
    let out = scratch("run-fails-second");
    std::fs::create_dir_all(&out).expect("scratch");
    let slow = out.join("slow.toml");
    std::fs::write(&slow, "name = \"slow\"\n[optimize]\nrate_limit = 0.001\n").expect("writable");
    let o = out.join("results");
    let (code, _, err) = catflip(&[
        "run",
        "problems/paper.toml",
        &slow.display().to_string(),
        // No rapier step to speak of: the first file's run is quick (its verifications have no
        // result, which `run` would say after the last file).
        "--set",
        "rapier.step_budget=10",
        "--out",
        &o.display().to_string(),
        "--quiet",
    ]);
    assert_eq!(code, 1, "{err}");
    let last = err.lines().last().unwrap_or_default();
    let want = format!(
        "error: {} (written before it, complete: {}): optimize.rate_limit = 0.001: infeasible",
        slow.display(),
        o.join("paper").display()
    );
    assert!(last.starts_with(&want), "{err}");
    let _ = std::fs::remove_dir_all(&out);
}
