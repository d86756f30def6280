//! Schedule files and URDF/MJCF of unequal halves (issue 22): the orientation and torque columns
//! are the general exact engine's on the model, the model files put each half where DESIGN.md §10
//! puts it, and a joint the files do not build is refused, naming `cat.joint`.
#![deny(clippy::float_cmp)]

mod common;

use std::path::Path;

use approx::assert_relative_eq;

use catflip::engines::resolved::Resolved;
use catflip::exchange::{model_files, write_schedule, ImportedSchedule};
use catflip::problem::Problem;
use catflip::report::import::ImportReport;

fn resolved(file: &str) -> Resolved {
    let problem = Problem::load(&Path::new("problems").join(file), &[]).unwrap_or_else(|e| panic!("{file}: {e}"));
    Resolved::new(&problem).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// The column `name` of the CSV `text`, parsed, with the rows' `(phase, boundary)`.
fn column(text: &str, name: &str) -> Vec<f64> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let k = header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    lines.map(|l| l.split(',').nth(k).and_then(|x| x.parse().ok()).unwrap_or(f64::NAN)).collect()
}

/// The problem's schedule written as a schedule file, read back from a scratch folder named for
/// `tag`, and evaluated by the exact engine on the problem's model (`simulate --schedule`).
fn read_back(r: &Resolved, tag: &str) -> (ImportedSchedule, ImportReport) {
    let file = write_schedule(&r.problem, &common::measured(&r.problem, &r.schedule), &Default::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let dir = std::env::temp_dir().join(format!("catflip-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{e}"));
    let path = dir.join("s.csv");
    std::fs::write(&path, &file.csv).unwrap_or_else(|e| panic!("{e}"));
    let imported = catflip::exchange::read_schedule(&path).unwrap_or_else(|e| panic!("{e}"));
    let report = catflip::report::import::evaluate(&r.problem, &imported).unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_dir_all(&dir);
    (imported, report)
}

/// The library schedule of `problems/unequal-halves.toml` as a schedule file: the last row's twist
/// and swing are the general core's flip, each row's torques the general core's at its state
/// (not the paper's cat of the mean half), and the sidecar describes both halves.
#[test]
fn a_schedule_file_of_unequal_halves_carries_the_models_numbers() {
    let r = resolved("unequal-halves.toml");
    let file = write_schedule(&r.problem, &common::measured(&r.problem, &r.schedule), &Default::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let e = r.evaluate(&r.schedule);
    let twist = column(&file.csv, "twist_deg");
    let swing = column(&file.csv, "swing_deg");
    assert_relative_eq!(*twist.last().unwrap_or(&f64::NAN), e.twist_deg(), epsilon = 1e-6);
    assert_relative_eq!(*swing.last().unwrap_or(&f64::NAN), e.swing_deg(), epsilon = 1e-6);
    let (t, tau1, tau2) = (column(&file.csv, "t_s"), column(&file.csv, "tau1_nm"), column(&file.csv, "tau2_nm"));
    let boundary: Vec<String> =
        file.csv.lines().skip(1).map(|l| l.split(',').nth(2).unwrap_or("").to_string()).collect();
    let mut checked = 0;
    for k in (0..t.len()).filter(|&k| boundary[k].is_empty()) {
        let want = r.model().joint_torques(&r.schedule.state(t[k])).tau;
        assert_relative_eq!(tau1[k], want[0], epsilon = 1e-9 * (1.0 + want[0].abs()));
        assert_relative_eq!(tau2[k], want[1], epsilon = 1e-9 * (1.0 + want[1].abs()));
        checked += 1;
    }
    assert!(checked > 10, "{checked} rows checked");
    let model = &file.sidecar.model;
    let rear = model.rear.as_ref().unwrap_or_else(|| panic!("the sidecar has no rear half"));
    let cat = r.model().cat();
    assert_relative_eq!(model.mass_kg, cat.front.mass, epsilon = 0.0);
    assert_relative_eq!(rear.mass_kg, cat.rear.mass, epsilon = 0.0);
    assert_relative_eq!(model.joint_point_in_a_m[2], -0.5 * cat.front.length, epsilon = 0.0);
    assert_relative_eq!(model.joint_point_in_b_m[2], 0.5 * cat.rear.length, epsilon = 0.0);
    // The paper's cat keeps its sidecar: no rear half.
    let paper = resolved("paper.toml");
    let file = write_schedule(&paper.problem, &common::measured(&paper.problem, &paper.schedule), &Default::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(file.sidecar.model.rear.is_none());
}

/// MJCF of unequal halves: the cross at A's `(0, 0, −l_A/2)`, B's centre at the cross's
/// `(0, 0, −l_B/2)`, joint 2 through B's `(0, 0, +l_B/2)`, each half its own mass.
#[test]
fn the_mjcf_of_unequal_halves_puts_each_half_where_the_model_does() {
    let r = resolved("unequal-halves.toml");
    let cat = r.model().cat();
    let [_, (_, xml)] = model_files(&r.problem);
    let doc = roxmltree::Document::parse(&xml).unwrap_or_else(|e| panic!("{e}"));
    let body = |name: &str| {
        doc.descendants()
            .find(|n| n.has_tag_name("body") && n.attribute("name") == Some(name))
            .unwrap_or_else(|| panic!("no body {name}"))
    };
    let z = |text: Option<&str>| text.and_then(|p| p.split(' ').nth(2)).and_then(|x| x.parse::<f64>().ok());
    assert_eq!(z(body("cross").attribute("pos")), Some(-0.5 * cat.front.length));
    assert_eq!(z(body("B").attribute("pos")), Some(-0.5 * cat.rear.length));
    let hinge = body("B").children().find(|n| n.has_tag_name("joint")).unwrap_or_else(|| panic!("no joint 2"));
    assert_eq!(z(hinge.attribute("pos")), Some(0.5 * cat.rear.length));
    let mass = |name: &str| {
        body(name).children().find(|n| n.has_tag_name("inertial")).and_then(|n| n.attribute("mass")).map(str::to_string)
    };
    assert_eq!(mass("A"), Some(format!("{:?}", cat.front.mass)));
    assert_eq!(mass("B"), Some(format!("{:?}", cat.rear.mass)));
}

/// The no-twist joint has no schedule file yet (its model files would be the universal joint's).
#[test]
fn a_schedule_file_of_the_no_twist_joint_is_refused() {
    let r = resolved("kane-scher.toml");
    let e = write_schedule(&r.problem, &common::measured(&r.problem, &r.schedule), &Default::default())
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("cat.joint = \"no-twist\""), "{e}");
}

/// The schedule file of unequal halves read back (`simulate --schedule`): the exact engine on the
/// model measures what the file says (twist, swing, peaks), and rapier verifies it.
#[test]
fn a_schedule_file_of_unequal_halves_reads_back_and_is_verified() {
    let r = resolved("unequal-halves.toml");
    let (imported, exact) = read_back(&r, "unequal");
    let e = r.evaluate(&r.schedule);
    assert!(
        (exact.figures.twist_deg - e.twist_deg()).abs() <= 1e-6,
        "{} against {}",
        exact.figures.twist_deg,
        e.twist_deg()
    );
    assert!(
        (exact.figures.swing_deg - e.swing_deg()).abs() <= 1e-6,
        "{} against {}",
        exact.figures.swing_deg,
        e.swing_deg()
    );
    let peak = exact.peak_torque_nm.max;
    assert!((peak - e.peaks.max).abs() <= 1e-3 * e.peaks.max, "peak {peak} against {}", e.peaks.max);
    assert_eq!(exact.velocity_jumps.len(), e.jumps.len());
    assert!(exact.warnings.iter().all(|w| !w.contains("too far apart")), "{:?}", exact.warnings);
    let report = catflip::report::import::simulate_import(&r.problem, imported, catflip::engines::Engine::Rapier)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.figures.check.verdict, Some(catflip::engines::rapier::Status::Verified));
}

/// A half shorter than √3 radii is warned about by name when a schedule is read back on unequal
/// halves (`cat.rear.length`), as the problem file names it, not as the `[cat]` shorthand.
#[test]
fn reading_back_warns_of_a_short_half_by_its_name() {
    let sets = ["cat.rear.length=0.15".to_string()];
    let problem = Problem::load(Path::new("problems/unequal-halves.toml"), &sets).unwrap_or_else(|e| panic!("{e}"));
    let r = Resolved::new(&problem).unwrap_or_else(|e| panic!("{e}"));
    let (_, report) = read_back(&r, "short-half");
    assert!(
        report.warnings.iter().any(|w| w.starts_with("cat.rear.length = 0.15 < √3 · cat.rear.radius")),
        "{:?}",
        report.warnings
    );
    assert!(!report.warnings.iter().any(|w| w.starts_with("cat.length")), "{:?}", report.warnings);
}
