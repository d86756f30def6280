//! `catflip run` on a two-motor cat other than the paper's (issue 22): Kane and Scher's cat
//! (`problems/kane-scher.toml`, equal halves on the no-twist joint), run once per test binary
//! ([`kane_scher_run`]).
//!
//! - everything that applies is computed and written: the library's table and rapier
//!   verifications, the whole optimum verified, the certified retimings, the schedule files and
//!   the model file MJCF alone (URDF has no no-twist joint);
//! - the two parts that model the paper's cat only (the audit, the profile QP and its
//!   refinements) are not run, and the terminal and `report.md` say so in one sentence each,
//!   naming the field; no file of theirs is written, no NaN anywhere;
//! - the retimings and the torque plots use the no-twist joint's own torques and axes.
//!
//! The run writes under `target/tmp/run-models/` (`CARGO_TARGET_TMPDIR`), emptied first.
#![deny(clippy::float_cmp)]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use catflip::engines::resolved::Resolved;
use catflip::measure::run::PaperOnly;
use catflip::problem::{Problem, ProfileKind};
use catflip::report::run::RunOutcome;
use serde_json::Value;

/// problems/kane-scher.toml run once into `target/tmp/run-models/kane-scher`, with the problem.
fn kane_scher_run() -> &'static (Problem, RunOutcome) {
    static RUN: OnceLock<(Problem, RunOutcome)> = OnceLock::new();
    RUN.get_or_init(|| {
        let problem = Problem::load(Path::new("problems/kane-scher.toml"), &[]).expect("the preset loads");
        let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("run-models");
        let _ = std::fs::remove_dir_all(&out);
        let r = Resolved::new(&problem).expect("the preset resolves");
        let outcome = catflip::report::run::run(&r, "run models test", &out).expect("run runs on Kane and Scher's cat");
        (problem, outcome)
    })
}

fn file(name: &str) -> PathBuf {
    kane_scher_run().1.dir.join(name)
}

fn read(name: &str) -> String {
    std::fs::read_to_string(file(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn json(name: &str) -> Value {
    serde_json::from_str(&read(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn run_on_kane_and_schers_cat_writes_what_applies_and_names_what_it_leaves_out() {
    let (problem, outcome) = kane_scher_run();
    let report = read("report.md");
    // The whole optimum, verified in rapier.
    assert!(report.contains("rapier verification of `whole-optimum`: **verified**"), "{report}");
    assert_eq!(json("verification_whole.json")["status"], "verified");
    // The library's table: every profile (the paper's cosine is origin `paper`), on the exact
    // engine, flipping the cat by -180°.
    let compare = read("compare.csv");
    for kind in ProfileKind::ALL {
        let row = compare
            .lines()
            .find(|l| l.starts_with(&format!("kane-scher,{},", kind.name())) && l.contains(",exact,"))
            .unwrap_or_else(|| panic!("no row for {} in\n{compare}", kind.name()));
        let twist: f64 = row.split(',').nth(16).and_then(|x| x.parse().ok()).expect("twist_deg, the 17th column");
        assert!((twist + 180.0).abs() < 1e-6, "{row}");
    }
    // The model files: a ball joint in the MJCF, pyBullet's spherical joint in the URDF (URDF has
    // no joint that bends without twisting).
    assert!(file("schedules/model.xml").is_file());
    let urdf = std::fs::read_to_string(file("schedules/model.urdf")).expect("schedules/model.urdf");
    assert!(urdf.contains("type=\"spherical\""), "{urdf}");
    assert!(file("schedules/whole-optimum.csv").is_file() && file("schedules/problem.csv").is_file());
    // What is left out: said once in the terminal and once in the report, naming the field; no
    // file of theirs.
    for part in [PaperOnly::Audit, PaperOnly::ProfileQp] {
        let said = part.not_run(problem).expect("Kane and Scher's cat is not the paper's");
        assert!(said.contains("cat.joint = \"no-twist\""), "{said}");
        assert_eq!(outcome.summary.matches(&said).count(), 1, "{}", outcome.summary);
        assert_eq!(report.matches(&said).count(), 1, "{report}");
    }
    for absent in ["audit.md", "audit.json", "optimize.md", "optimize.json"] {
        assert!(!file(absent).exists(), "{absent} written");
        assert!(!outcome.files.iter().any(|f| f == absent), "{absent} listed");
        assert!(!report.contains(&format!("`{absent}`")), "{absent} named in the report");
    }
    // No number passed off as a result where there is none.
    for f in outcome.files.iter().filter(|f| f.ends_with(".md") || f.ends_with(".csv") || f.ends_with(".json")) {
        let text = read(f);
        assert!(!text.contains("NaN") && !text.to_lowercase().contains(" nan"), "{f} holds a NaN");
    }
}

#[test]
fn the_retimings_on_the_no_twist_joint_use_its_own_torques() {
    let rows = json("retime.json");
    let rows = rows.as_array().expect("a list of retimings");
    // The problem's schedule (on π/C, already exactly π on this joint: no calibrated variant), with
    // the phases kept and with the split free.
    assert_eq!(rows.len(), 2, "{rows:?}");
    for row in rows {
        assert_eq!(row["status"], "solved", "{row}");
        let program = row["peak_nm"].as_f64().expect("a peak");
        let exact = row["exact_peak_nm"].as_f64().expect("an exact peak");
        // The program's torques are the model's at the grid nodes: the exact engine's peak of the
        // timed trajectory (the no-twist joint's torques) meets it to the discretisation error.
        assert!((exact - program).abs() < 1e-4 * program, "program {program} N·m, exact {exact} N·m: {row}");
        let twist = row["twist_deg"].as_f64().expect("a twist");
        assert!((twist + 180.0).abs() < 1e-6, "the path's flip is kept: {twist}°");
    }
}

#[test]
fn the_torque_plots_name_the_no_twist_joints_axes() {
    // SVG escapes the apostrophe.
    let joint2 = read("plots/torques_joint2.svg").replace("&apos;", "'");
    assert!(joint2.contains("about A's y axis") && !joint2.contains("cross"), "joint 2's axis on the no-twist joint");
    let whole = read("plots/torques_whole_optimum.svg").replace("&apos;", "'");
    assert!(whole.contains("joint 2, about A's y") && !whole.contains("cross"), "the optimum's legend");
}

/// A `…-calibrated` variant is made only where the problem's own schedule does not already turn
/// the cat by π: a problem on the calibrated circulation (problems/cone-calibrated.toml) and Kane
/// and Scher's cat on π/C (exactly π on the no-twist joint) would repeat their schedules under a
/// second name (their runs once retimed and verified their own schedule twice); the paper's
/// problem on π/C, 3.3 % short, gets the calibrated one.
#[test]
fn calibrated_variants_are_made_only_where_they_change_the_circulation() {
    let load = |name: &str| {
        let p = Problem::load(Path::new(&format!("problems/{name}.toml")), &[]).expect("loads");
        Resolved::new(&p).expect("resolves")
    };
    let calibrated = load("cone-calibrated");
    let own = calibrated.calibrated().expect("the calibration converges");
    assert_eq!(calibrated.schedule.circulation.to_bits(), own.radians.to_bits(), "runs on the calibrated circulation");
    assert!(calibrated.recalibration().is_none());
    let (kane_scher, _) = kane_scher_run();
    let exact_pi = Resolved::new(kane_scher).expect("resolves");
    assert!(exact_pi.calibrated().is_some() && exact_pi.recalibration().is_none());
    let names: Vec<String> =
        json("retime.json").as_array().expect("rows").iter().map(|row| row["schedule"].to_string()).collect();
    assert!(!names.iter().any(|n| n.contains("-calibrated")), "{names:?}");
    let paper = load("paper");
    let other = paper.recalibration().expect("the calibration converges and differs from π/C");
    assert!(
        (other.radians / paper.schedule.circulation - 1.0).abs() > 0.01,
        "{} against {}",
        other.radians,
        paper.schedule.circulation
    );
}
