//! The peak-torque table, the optimisers against the exact engine, and `catflip run`'s output.
#![deny(clippy::float_cmp)]

use approx::assert_relative_eq;
use catflip::engines::circulation::Resolved;
use catflip::optimize::optimize;
use catflip::problem::manoeuvre::ProfileKind;
use catflip::problem::Problem;
use catflip::report::compare::compare;

fn small() -> Problem {
    let mut p = Problem::default();
    p.optimize.nodes = 61;
    p
}

#[test]
fn table_has_every_profile_and_the_paper_model_peaks() {
    let p = Problem::default();
    let t = compare(&Resolved::new(&p).expect("resolves"), &[]);
    assert_eq!(t.rows.len(), ProfileKind::ALL.len());
    let t2 = 0.6 * p.drop.fall_time();
    for r in &t.rows {
        // Model peak I*·C_a·D/T² (paper §8 with the correct I*).
        assert_relative_eq!(
            r.model_peak_nm,
            p.cat.end_transverse() * r.accel_coefficient * r.circulation_rad / (t2 * t2),
            max_relative = 1e-12
        );
        // Path invariance: twist and swing do not depend on the profile.
        assert_relative_eq!(r.twist_deg, t.rows[0].twist_deg, epsilon = 1e-7);
        assert_relative_eq!(r.swing_deg, t.rows[0].swing_deg, epsilon = 1e-7);
        let jumps = if r.profile == "paper-cosine" { 1 } else { 0 };
        assert_eq!(r.velocity_jumps, jumps, "{}", r.profile);
        // The exact peak is far above the paper's model: centripetal terms dominate.
        assert!(r.exact_peak_nm.max > r.model_peak_nm, "{}", r.profile);
    }
    let csv = t.to_csv();
    assert_eq!(csv.lines().count(), 1 + t.rows.len());
}

#[test]
fn qp_matches_its_closed_form_and_refinement_beats_every_library_profile() {
    let p = small();
    let resolved = Resolved::new(&p).expect("resolves");
    let r = optimize(&resolved).expect("runs");
    assert!(r.qp.status.is_solved(), "{:?}", r.qp.status);
    // N = 61 is odd: the discrete optimum is the bang-bang value 4 D I*/T² (qp module docs).
    assert_relative_eq!(
        r.qp.peak_torque.expect("solved"),
        r.qp_closed_form_nm.unwrap_or(f64::NAN),
        max_relative = 1e-7
    );
    let t2 = 0.6 * p.drop.fall_time();
    assert_relative_eq!(
        r.qp.peak_torque.expect("solved"),
        4.0 * r.circulation.radians * p.cat.end_transverse() / (t2 * t2),
        max_relative = 1e-7
    );
    let refined = r.refined_optimum.as_ref().expect("refinement ran");
    let peak = refined.evaluation.exact_peak_nm.twist[0].max(refined.evaluation.exact_peak_nm.twist[1]);
    let table = compare(&resolved, &[]);
    for row in &table.rows {
        let lib = row.exact_peak_nm.twist[0].max(row.exact_peak_nm.twist[1]);
        assert!(peak < lib, "refined {peak} ≥ {} ({lib})", row.profile);
    }
    // The refinement changes the timing only: the flip is unchanged, and with the calibrated
    // circulation it is π.
    assert_relative_eq!(refined.evaluation.twist_deg, table.rows[0].twist_deg, epsilon = 1e-7);
    assert_relative_eq!(refined.calibrated_twist_deg.expect("calibration converged").abs(), 180.0, epsilon = 1e-6);
    assert_eq!(refined.evaluation.velocity_jumps, 0);
    // Retiming bend and unbend too lowers the whole manoeuvre's peak below the twist-only
    // refinement's (which the harmonic bend dominates), keeps every phase rest to rest, and
    // leaves the flip alone (same joint path).
    let whole = r.whole.as_ref().expect("whole retiming ran");
    assert!(
        whole.optimum.evaluation.exact_peak_nm.max < refined.evaluation.exact_peak_nm.max,
        "{} vs {}",
        whole.optimum.evaluation.exact_peak_nm.max,
        refined.evaluation.exact_peak_nm.max
    );
    assert_eq!(whole.optimum.evaluation.velocity_jumps, 0);
    assert_relative_eq!(whole.optimum.evaluation.twist_deg, table.rows[0].twist_deg, epsilon = 1e-7);
    assert_relative_eq!(whole.optimum.evaluation.swing_deg, table.rows[0].swing_deg, epsilon = 1e-7);
    assert_relative_eq!(
        whole.optimum.calibrated_twist_deg.expect("calibration converged").abs(),
        180.0,
        epsilon = 1e-6
    );
}

#[test]
fn run_writes_every_result_file_atomically() {
    let out = std::env::temp_dir().join(format!("catflip-run-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let p = small();
    let outcome = catflip::report::run::run(&Resolved::new(&p).expect("resolves"), "test", &out).expect("runs");
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
    let leftovers: Vec<_> = std::fs::read_dir(&out)
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
    let _ = std::fs::remove_dir_all(&out);
}

/// The records of a CSV text with its header, by column name.
fn csv_records(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let header = reader.headers().expect("a header").iter().map(str::to_string).collect();
    let rows = reader.records().map(|r| r.expect("a record").iter().map(str::to_string).collect()).collect();
    (header, rows)
}

#[test]
fn a_run_without_rapier_results_completes_with_inconclusive_rows() {
    // A step budget below rapier's first run: no verification makes a usable run, so rapier has
    // no number for any schedule. That is a reported outcome, not a failed run: every file is
    // written, each verification row says `inconclusive` and why, and no table shows a NaN.
    let out = std::env::temp_dir().join(format!("catflip-run-inconclusive-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let mut p = small();
    p.rapier.step_budget = 1;
    let outcome = catflip::report::run::run(&Resolved::new(&p).expect("resolves"), "test", &out)
        .expect("an inconclusive verification does not fail the run");
    let read = |f: &str| std::fs::read_to_string(outcome.dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
    let (header, rows) = csv_records(&read("verification.csv"));
    let col = |name: &str| header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"));
    let (rapier, exact): (Vec<_>, Vec<_>) = rows.iter().partition(|r| r[col("engine")] == "rapier");
    assert!(!rapier.is_empty() && rapier.len() == exact.len(), "{} rapier rows, {} exact", rapier.len(), exact.len());
    for r in &rapier {
        assert_eq!(r[col("verdict")], "inconclusive", "{r:?}");
        let reason = &r[col("verdict_reason")];
        assert!(reason.starts_with("inconclusive: 0 of the 3 runs") && reason.contains("budget of 1 steps"), "{r:?}");
        for empty in ["twist_deg", "swing_deg", "max_nm", "momentum_max", "dt_s", "tracking1_rad"] {
            assert!(r[col(empty)].is_empty(), "{empty} of {r:?}");
        }
        assert!(!r[col("circulation_rad")].is_empty(), "{r:?}");
    }
    assert!(exact.iter().all(|r| !r[col("twist_deg")].is_empty() && r[col("verdict")].is_empty()));
    // The Markdown row of each schedule: the exact engine's numbers, — for rapier's, the verdict.
    let md = read("verification.md");
    let schedule_rows: Vec<&str> =
        md.lines().filter(|l| l.starts_with("| ") && l.contains("inconclusive: 0 of the 3 runs")).collect();
    assert_eq!(schedule_rows.len(), rapier.len() + 1, "the schedules and the whole optimum:\n{md}");
    for l in &schedule_rows {
        let cells: Vec<&str> = l.split(" | ").collect();
        assert!(cells[1].parse::<f64>().is_ok() && cells[2] == "—" && cells[3] == "—", "{l}");
    }
    // simulate_rapier.json: null numbers beside the verdict and its reason.
    let json: serde_json::Value = serde_json::from_str(&read("simulate_rapier.json")).expect("JSON");
    let entries = json.as_array().expect("a list");
    assert_eq!(entries.len(), rapier.len());
    for e in entries {
        assert!(e["engine"] == "rapier" && e["verdict"] == "inconclusive", "{e}");
        assert!(e["twist_deg"].is_null() && e["peak_torque_nm"].is_null(), "{e}");
        assert!(e["reason"].as_str().is_some_and(|r| r.starts_with("inconclusive: ")), "{e}");
    }
    // The summary counts them.
    let n = rapier.len();
    let counted = format!("0 verified, 0 not verified, {n} inconclusive");
    assert!(outcome.summary.contains(&counted), "{}", outcome.summary);
    assert!(outcome.summary.contains(&format!("rapier has no result for {n} of them")), "{}", outcome.summary);
    for f in outcome.files.iter().filter(|f| f.ends_with(".md") || f.ends_with(".csv")) {
        assert!(!read(f).contains("NaN"), "NaN in {f}");
    }
    let _ = std::fs::remove_dir_all(&out);
}
