//! Exchange with other tools: the model files parsed back against the model, schedule files
//! read back into the exact engine, and malformed files refused with a line and a column.
#![deny(clippy::float_cmp)]

mod common;

use approx::assert_relative_eq;
use nalgebra::{Matrix3, Rotation3, Unit, UnitQuaternion, Vector3};

use catflip::engines::exact::flip;
use catflip::engines::torque::{joint_torques, peak_torques, peak_torques_on};
use catflip::exchange::import::parse_schedule;
use catflip::exchange::{model_files, write_schedule, ExportOptions, ImportError, Interpolation, Sidecar};
use catflip::model::Cylinder;
use catflip::problem::Problem;
use catflip::report::import::evaluate;
use catflip::schedule::variant::ScheduleName;
use catflip::schedule::{paper_circulation, Schedule, Trajectory};

/// A cat unlike the default, so that no number matches by accident.
fn problem() -> Problem {
    Problem { cat: Cylinder { mass: 1.3, length: 0.7, radius: 0.11 }.into(), ..Default::default() }
}

fn paper_schedule(p: &Problem) -> Schedule {
    Schedule::new(p, paper_circulation(&p.cat.half(), p.manoeuvre.theta()).expect("the paper's circulation exists"))
}

fn numbers(text: &str) -> Vec<f64> {
    text.split_whitespace().map(|x| x.parse().expect("a number")).collect()
}

fn vec3(text: &str) -> Vector3<f64> {
    Vector3::from_column_slice(&numbers(text))
}

fn rotation(axis: Vector3<f64>, angle: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Unit::new_normalize(axis), angle).into_inner()
}

/// The test configuration: neither joint at zero.
const Q: [f64; 2] = [0.4, -0.9];

fn model(p: &Problem, index: usize) -> String {
    model_files(p).unwrap_or_else(|e| panic!("{e}"))[index].1.clone()
}

#[test]
fn urdf_has_the_true_mass_properties_and_joint_frames() {
    let p = problem();
    let text = model(&p, 0);
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    let links: Vec<_> = doc.descendants().filter(|n| n.has_tag_name("link")).collect();
    assert_eq!(links.iter().map(|l| l.attribute("name").unwrap_or("")).collect::<Vec<_>>(), ["A", "cross", "B"]);
    let (t, a) = (p.cat.half().transverse(), p.cat.half().axial());
    let cross_m = p.rapier.cross_mass_fraction * p.cat.mass;
    let cross_i = 0.4 * cross_m * p.cat.radius.powi(2);
    let expected = [(p.cat.mass, [t, t, a]), (cross_m, [cross_i; 3]), (p.cat.mass, [t, t, a])];
    let mut com = Vec::new();
    for (link, (mass, inertia)) in links.iter().zip(expected) {
        let inertial = link.children().find(|n| n.has_tag_name("inertial")).expect("every link has an inertial");
        let get = |tag: &str, attr: &str| -> f64 {
            let node = inertial.children().find(|n| n.has_tag_name(tag)).expect("tag present");
            node.attribute(attr).expect("attribute present").parse().expect("a number")
        };
        assert_relative_eq!(get("mass", "value"), mass, max_relative = 1e-15);
        for (name, v) in ["ixx", "iyy", "izz"].iter().zip(inertia) {
            assert_relative_eq!(get("inertia", name), v, max_relative = 1e-15);
        }
        for name in ["ixy", "ixz", "iyz"] {
            assert_relative_eq!(get("inertia", name), 0.0, epsilon = 0.0);
        }
        let origin = inertial.children().find(|n| n.has_tag_name("origin")).expect("an origin");
        com.push(vec3(origin.attribute("xyz").expect("xyz")));
    }
    let joints: Vec<_> = doc.descendants().filter(|n| n.has_tag_name("joint")).collect();
    assert_eq!(joints.len(), 2);
    let attr = |node: roxmltree::Node, tag: &str, a: &str| {
        node.children().find(|n| n.has_tag_name(tag)).and_then(|n| n.attribute(a)).expect("present").to_string()
    };
    assert_eq!(
        [
            (attr(joints[0], "parent", "link"), attr(joints[0], "child", "link")),
            (attr(joints[1], "parent", "link"), attr(joints[1], "child", "link"))
        ],
        [("A".into(), "cross".into()), ("cross".into(), "B".into())]
    );
    // Forward kinematics from the file: each child frame is Trans(origin)·Rot(axis, q) in its parent.
    let mut r = Matrix3::identity();
    let mut x = Vector3::zeros();
    for (joint, q) in joints.iter().zip(Q) {
        assert_eq!(joint.attribute("type"), Some("continuous"));
        assert_eq!(attr(*joint, "origin", "rpy"), "0 0 0");
        x += r * vec3(&attr(*joint, "origin", "xyz"));
        r *= rotation(vec3(&attr(*joint, "axis", "xyz")), q);
    }
    let cfg = p.cat.half().configuration(Q);
    assert_relative_eq!(r, cfg.rotation, epsilon = 1e-15);
    // B's centre of mass, and the joint point in A, against the model.
    assert_relative_eq!(x + r * com[2], cfg.offset, epsilon = 1e-15);
    assert_relative_eq!(x, Vector3::new(0.0, 0.0, -0.5 * p.cat.length), epsilon = 1e-15);
    assert_relative_eq!(com[0].norm(), 0.0, epsilon = 0.0);
}

#[test]
fn mjcf_has_the_true_mass_properties_and_joint_frames() {
    let p = problem();
    let text = model(&p, 1);
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    let option = doc.descendants().find(|n| n.has_tag_name("option")).expect("an option");
    assert_relative_eq!(vec3(option.attribute("gravity").expect("gravity")).norm(), 0.0, epsilon = 0.0);
    let bodies: Vec<_> = doc.descendants().filter(|n| n.has_tag_name("body")).collect();
    assert_eq!(bodies.iter().map(|b| b.attribute("name").unwrap_or("")).collect::<Vec<_>>(), ["A", "cross", "B"]);
    fn child<'a, 'i>(b: roxmltree::Node<'a, 'i>, tag: &str) -> Option<roxmltree::Node<'a, 'i>> {
        b.children().find(|n| n.has_tag_name(tag))
    }
    assert!(child(bodies[0], "freejoint").is_some(), "A is the floating base");
    let (t, a) = (p.cat.half().transverse(), p.cat.half().axial());
    let cross_m = p.rapier.cross_mass_fraction * p.cat.mass;
    let cross_i = 0.4 * cross_m * p.cat.radius.powi(2);
    let expected = [(p.cat.mass, [t, t, a]), (cross_m, [cross_i; 3]), (p.cat.mass, [t, t, a])];
    for (body, (mass, inertia)) in bodies.iter().zip(expected) {
        let inertial = child(*body, "inertial").expect("every body has an inertial");
        let m: f64 = inertial.attribute("mass").expect("mass").parse().expect("a number");
        assert_relative_eq!(m, mass, max_relative = 1e-15);
        let i = numbers(inertial.attribute("diaginertia").expect("diaginertia"));
        for (got, want) in i.iter().zip(inertia) {
            assert_relative_eq!(*got, want, max_relative = 1e-15);
        }
        assert_relative_eq!(vec3(inertial.attribute("pos").expect("pos")).norm(), 0.0, epsilon = 0.0);
    }
    // Forward kinematics: a hinge at `pos` (child frame) about `axis` maps a child point y to
    // body_pos + pos + Rot(axis, q)(y − pos) in the parent.
    let mut r = Matrix3::identity();
    let mut x = Vector3::zeros();
    let mut joint_point = Vector3::zeros();
    for (body, q) in bodies[1..].iter().zip(Q) {
        let joint = child(*body, "joint").expect("a hinge");
        assert_eq!(joint.attribute("type"), Some("hinge"));
        let pos = vec3(joint.attribute("pos").expect("pos"));
        let rj = rotation(vec3(joint.attribute("axis").expect("axis")), q);
        let body_pos = vec3(body.attribute("pos").expect("pos"));
        x += r * (body_pos + pos - rj * pos);
        joint_point = x + r * rj * pos;
        r *= rj;
    }
    let cfg = p.cat.half().configuration(Q);
    assert_relative_eq!(r, cfg.rotation, epsilon = 1e-15);
    assert_relative_eq!(x, cfg.offset, epsilon = 1e-15);
    assert_relative_eq!(joint_point, Vector3::new(0.0, 0.0, -0.5 * p.cat.length), epsilon = 1e-15);
    let motors: Vec<_> = doc.descendants().filter(|n| n.has_tag_name("motor")).map(|n| n.attribute("joint")).collect();
    assert_eq!(motors, [Some("joint1"), Some("joint2")]);
}

/// The paper's schedule written at 1 kHz, its sidecar, and the parsed CSV rows.
fn paper_file_at_1khz(p: &Problem) -> (Schedule, String, Sidecar) {
    let s = paper_schedule(p);
    let file =
        write_schedule(p, &common::measured(p, &s), &ExportOptions { rate_hz: Some(1000.0), ..Default::default() })
            .expect("writes");
    (s, file.csv, file.sidecar)
}

fn rows(csv: &str) -> Vec<Vec<String>> {
    csv.lines().skip(1).map(|l| l.split(',').map(str::to_string).collect()).collect()
}

#[test]
fn uniform_grid_marks_boundaries_and_states_the_jump() {
    let p = problem();
    let (s, csv, sidecar) = paper_file_at_1khz(&p);
    let header: Vec<&str> = csv.lines().next().unwrap_or_default().split(',').collect();
    assert_eq!(&header[..5], ["t_s", "phase", "boundary", "q1_rad", "q2_rad"]);
    let rows = rows(&csv);
    assert_eq!(sidecar.sampling.rows, rows.len());
    let marked: Vec<(&str, &str)> =
        rows.iter().filter(|r| !r[2].is_empty()).map(|r| (r[1].as_str(), r[2].as_str())).collect();
    assert_eq!(marked, [("bend", "end"), ("twist", "start"), ("twist", "end"), ("unbend", "start")]);
    // Unmarked rows lie on the grid t = k/1000 (the last row is the end of the fall).
    for r in rows.iter().filter(|r| r[2].is_empty()).take(rows.len() - 5) {
        let t: f64 = r[0].parse().expect("a time");
        assert_relative_eq!(t * 1000.0, (t * 1000.0).round(), epsilon = 1e-9);
    }
    // One jump (the paper's cosine ends at 2ω0), its impulse as the torque module computes it,
    // in the sidecar and on the unbend's start row.
    let expected = catflip::engines::models::TwoMotorCat::paper(p.cat.half()).velocity_jumps(&s, |_| 0.0);
    assert_eq!((sidecar.jumps.len(), expected.len()), (1, 1));
    let start = rows.iter().find(|r| r[1] == "unbend" && r[2] == "start").expect("a start row");
    for j in 0..2 {
        assert_relative_eq!(sidecar.jumps[0].impulse_nms[j], expected[0].impulse[j], max_relative = 1e-12);
        let col: f64 = start[11 + j].parse().expect("a number");
        assert_relative_eq!(col, expected[0].impulse[j], max_relative = 1e-15);
    }
    assert!(sidecar.conventions.quaternion.contains("(w, x, y, z)"));
    assert_relative_eq!(sidecar.model.half_inertia_kg_m2[0], p.cat.half().transverse(), max_relative = 1e-15);
    assert_eq!(sidecar.pieces.len(), 3);
}

#[test]
fn the_sidecar_sizes_the_motors_as_the_evaluation_does() {
    // The sidecar's motor figures are the exact engine's (Evaluation, what `simulate` reports),
    // measured on the file's trajectory; with a torque limit below the peak it says so.
    let mut p = problem();
    let s = paper_schedule(&p);
    let e = catflip::prelude::Evaluation::of_paper(&p.cat.half(), &s, &p.drop.spin(), &p.actuator.motors(), &p.exact);
    let (_, _, sidecar) = paper_file_at_1khz(&p);
    let m = &sidecar.motors;
    assert!(m.within_motors && m.demand.limits.is_empty(), "ideal motors: {}", m.verdict);
    let peak = m.peak_torque_nm[0].value.max(m.peak_torque_nm[1].value);
    assert_relative_eq!(peak, e.peaks.max, max_relative = 1e-9);
    for j in 0..2 {
        let (a, b) = (m.demand.peak_speed_rad_s[j], e.motors.peak_speed_rad_s[j]);
        assert_relative_eq!(a.value, b.value, max_relative = 1e-9);
        assert_relative_eq!(m.demand.peak_power_w[j].value, e.motors.peak_power_w[j].value, max_relative = 1e-9);
    }
    p.actuator.torque_limit_nm = Some(catflip::problem::actuator::PerJoint::Both(0.5 * e.peaks.max));
    let (_, _, limited) = paper_file_at_1khz(&p);
    assert!(!limited.motors.within_motors, "{}", limited.motors.verdict);
    let worst = limited.motors.demand.limits.iter().map(|l| l.ratio).fold(0.0, f64::max);
    assert_relative_eq!(worst, 2.0, max_relative = 1e-9);
    let text = serde_json::to_string(&limited).expect("serialises");
    let back: Sidecar = serde_json::from_str(&text).expect("parses back");
    assert_eq!(back, limited, "the sidecar round-trips with its motor figures");
}

#[test]
fn a_schedule_file_of_a_spinning_release_is_refused_naming_the_field() {
    // Its orientation and torque columns would be the zero-momentum flip's: refused, not written.
    let mut p = problem();
    p.drop.angular_momentum = [0.0, 0.0, 0.01];
    let s = paper_schedule(&p);
    let e = write_schedule(&p, &common::measured(&p, &s), &ExportOptions::default()).map(|_| ()).expect_err("refused");
    assert!(e.to_string().starts_with("drop.angular_momentum = [0, 0, 0.01]: a schedule file"), "{e}");
}

#[test]
fn orientation_columns_meet_the_engine_tolerance() {
    // Reference: the exact engine's final orientation at exact.tolerance = 1e-10 rad.
    let p = problem();
    let (s, csv, sidecar) = paper_file_at_1khz(&p);
    let f = flip(&p.cat.half(), &s, p.exact.tolerance);
    let last = rows(&csv).pop().expect("rows");
    let v: Vec<f64> = last[13..19].iter().map(|x| x.parse().expect("a number")).collect();
    let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(v[0], v[1], v[2], v[3]));
    let gap = (q.inverse() * f.orientation).angle();
    assert!(gap < 1e-9, "last row's orientation is {gap:.2e} rad from the engine's");
    assert_relative_eq!(v[4].to_radians(), f.twist, epsilon = 1e-9);
    assert_relative_eq!(v[5].to_radians(), f.swing, epsilon = 1e-9);
    assert!(sidecar.orientation.converged);
}

#[test]
fn round_trip_at_1khz_keeps_twist_swing_and_peak_torque() {
    // Target (issue 10): 1e-6 rad on twist and swing. Quintic Hermite at h = 1 ms interpolates q
    // to h⁶·max|q⁽⁶⁾|/46080 and q̈ to O(h⁴), far inside it; the peak torque follows q̈.
    let p = problem();
    let (s, csv, _) = paper_file_at_1khz(&p);
    let imported = parse_schedule(&csv, "paper.csv").expect("reads back");
    assert_eq!(imported.interpolation, Interpolation::QuinticHermite);
    assert_eq!(imported.pieces.iter().map(|x| x.name.as_str()).collect::<Vec<_>>(), ["bend", "twist", "unbend"]);
    let report = evaluate(&p, &imported).expect("evaluates");
    let f = flip(&p.cat.half(), &s, p.exact.tolerance);
    let peaks = peak_torques(&p.cat.half(), &s, p.exact.torque_samples);
    let (dt, ds) = (report.figures.twist_deg.to_radians() - f.twist, report.figures.swing_deg.to_radians() - f.swing);
    eprintln!(
        "round trip at 1 kHz: twist {dt:.2e} rad, swing {ds:.2e} rad, peak {:.2e} relative",
        report.peak_torque_nm.max / peaks.max - 1.0
    );
    assert!(dt.abs() < 1e-9 && ds.abs() < 1e-9, "twist {dt:.2e} rad, swing {ds:.2e} rad");
    assert_relative_eq!(report.peak_torque_nm.max, peaks.max, max_relative = 1e-9);
    assert_eq!(report.velocity_jumps.len(), 1);
    // catflip's own file at 1 kHz: nothing to warn of.
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
}

#[test]
fn round_trip_with_angles_only_uses_the_spline() {
    // Only t, q1, q2: the not-a-knot spline, O(h⁴) in q; at 1 kHz still within the 1e-6 rad target.
    let p = problem();
    let (s, csv, _) = paper_file_at_1khz(&p);
    let slim: String = csv
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            format!("{},{},{}\n", f[0], f[3], f[4])
        })
        .collect();
    let imported = parse_schedule(&slim, "slim.csv").expect("reads back");
    assert_eq!(imported.interpolation, Interpolation::NotAKnotSpline);
    let report = evaluate(&p, &imported).expect("evaluates");
    let f = flip(&p.cat.half(), &s, p.exact.tolerance);
    let (dt, ds) = (report.figures.twist_deg.to_radians() - f.twist, report.figures.swing_deg.to_radians() - f.swing);
    eprintln!("spline round trip at 1 kHz: twist {dt:.2e} rad, swing {ds:.2e} rad");
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    assert!(dt.abs() < 1e-6 && ds.abs() < 1e-6, "twist {dt:.2e} rad, swing {ds:.2e} rad");
    // The paper's one jump is found; the spline's O(h³) end rates make no others.
    let expected = catflip::engines::models::TwoMotorCat::paper(p.cat.half()).velocity_jumps(&s, |_| 0.0);
    assert_eq!(report.velocity_jumps.len(), 1);
    for j in 0..2 {
        let got = report.velocity_jumps[0].impulse[j];
        eprintln!("spline impulse {j}: {got} against {}", expected[0].impulse[j]);
        assert_relative_eq!(got, expected[0].impulse[j], max_relative = 1e-6);
    }
}

fn parse_err(text: &str) -> ImportError {
    parse_schedule(text, "bad.csv").expect_err("refused")
}

#[test]
fn malformed_files_name_the_line_and_column() {
    let ok = "t_s,q1_rad,q2_rad\n0,0,0\n0.1,0.1,0\n0.2,0.2,0\n0.3,0.3,0\n";
    assert!(parse_schedule(ok, "ok.csv").is_ok());
    match parse_err("t_s,q1_rad\n0,0\n0.1,0.1\n") {
        ImportError::MissingColumn { column, path, .. } => {
            assert_eq!((column.as_str(), path.as_str()), ("q2_rad", "bad.csv"))
        }
        e => panic!("{e}"),
    }
    match parse_err("t_s,q1_rad,q2_rad\n0,0,0\n0.2,0.1,0\n0.1,0.2,0\n0.3,0.3,0\n") {
        ImportError::TimeNotIncreasing { line, column, .. } => assert_eq!((line, column), (4, 1)),
        e => panic!("{e}"),
    }
    match parse_err("t_s,q1_rad,q2_rad\n0,0,0\n0.1,NaN,0\n0.2,0.2,0\n0.3,0.3,0\n") {
        ImportError::NotFinite { line, column, name, .. } => {
            assert_eq!((line, column, name.as_str()), (3, 2, "q1_rad"))
        }
        e => panic!("{e}"),
    }
    match parse_err("t_s,q1_rad,q2_rad\n0,0,0\n0.1,0.1,x\n0.2,0.2,0\n0.3,0.3,0\n") {
        ImportError::NotANumber { line, column, .. } => assert_eq!((line, column), (3, 3)),
        e => panic!("{e}"),
    }
    match parse_err("t_s,q1_rad,q2_rad\n0,0,0\n0.1,0.1,0\n0.2,0.2,0\n") {
        ImportError::TooFewRows { rows, needed, first_line, last_line, .. } => {
            assert_eq!((rows, needed, first_line, last_line), (3, 4, 2, 4))
        }
        e => panic!("{e}"),
    }
    match parse_err("t_s,q1_rad,q2_rad,qdd1,qdd2\n0,0,0,0,0\n0.1,0.1,0,0,0\n") {
        ImportError::IncompleteColumns { present, missing, .. } => {
            assert_eq!((present.as_str(), missing.as_str()), ("qdd1_rad_s2", "qd1_rad_s"))
        }
        e => panic!("{e}"),
    }
    match parse_err("t_s,q1_rad,q2_rad\n0,0,0\n0.1,0.1\n") {
        ImportError::Csv { line, .. } => assert_eq!(line, 3),
        e => panic!("{e}"),
    }
    // One quantity in two columns: which was read was a guess (a QA run's first, all zeros, was
    // flipped by nothing, silently); the same name twice, or two of its names.
    for (text, columns, what) in [
        ("t_s,q1_rad,q1_rad,q2_rad\n0,0,0,0\n", (2, 3), "joint 1's angle"),
        ("t,t_s,q1_rad,q2_rad\n0,0,0,0\n", (1, 2), "the time"),
        ("t_s,q1,q2_rad,q1_rad\n0,0,0,0\n", (2, 4), "joint 1's angle"),
    ] {
        match parse_err(text) {
            e @ ImportError::RepeatedColumn { first, second, what: w, .. } => {
                assert_eq!(((first, second), w), (columns, what), "{e}");
                assert!(e.to_string().ends_with(&format!("both give {what}: keep one")), "{e}");
            }
            e => panic!("{text}: {e}"),
        }
    }
    // A time written three times in a row is not a piece boundary.
    let triple = "t,q1,q2,qd1,qd2\n0,0,0,0,0\n0.1,0.1,0,1,0\n0.1,0.1,0,1,0\n0.1,0.1,0,1,0\n0.2,0.2,0,1,0\n";
    match parse_err(triple) {
        ImportError::TimeNotIncreasing { line, .. } => assert_eq!(line, 5),
        e => panic!("{e}"),
    }
    // The message names the file, the line and the column.
    let msg = parse_err("t_s,q1_rad,q2_rad\n0,0,0\n0.1,inf,0\n0.2,0.2,0\n0.3,0.3,0\n").to_string();
    assert!(msg.contains("bad.csv") && msg.contains("line 3") && msg.contains("column 2"), "{msg}");
}

/// The paper's schedule written at 1 kHz into a fresh scratch folder `catflip-<tag>-<pid>`:
/// the folder, the file, the problem and the schedule.
fn paper_csv_at_1khz(tag: &str) -> (std::path::PathBuf, std::path::PathBuf, Problem, Schedule) {
    let dir = std::env::temp_dir().join(format!("catflip-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let p = Problem::default();
    let s = paper_schedule(&p);
    let file =
        write_schedule(&p, &common::measured(&p, &s), &ExportOptions { rate_hz: Some(1000.0), ..Default::default() })
            .expect("writes");
    let path = dir.join("paper.csv");
    std::fs::write(&path, &file.csv).expect("writable");
    (dir, path, p, s)
}

#[test]
fn simulate_cli_evaluates_a_schedule_file() {
    let (dir, path, p, s) = paper_csv_at_1khz("exchange");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_catflip"))
        .args(["simulate", "problems/paper.toml", "--schedule"])
        .arg(&path)
        .arg("--json")
        .output()
        .expect("the binary runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let f = flip(&p.cat.half(), &s, p.exact.tolerance);
    assert_relative_eq!(v["twist_deg"].as_f64().unwrap_or(f64::NAN), f.twist.to_degrees(), epsilon = 1e-7);
    assert_eq!(v["interpolation"], "quintic-hermite");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn simulate_cli_verifies_a_schedule_file_in_rapier() {
    // The paper's schedule written at 1 kHz and read back, through rapier against the exact
    // engine on the same imported trajectory (it verifies in four runs, about 0.2 s).
    let (dir, path, p, s) = paper_csv_at_1khz("exchange-rapier");
    let simulate = |extra: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_catflip"))
            .args(["simulate", "problems/paper.toml", "--engine", "rapier", "--schedule"])
            .arg(&path)
            .args(extra)
            .output()
            .expect("the binary runs")
    };
    let out = simulate(&["--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!((v["engine"].as_str(), v["interpolation"].as_str()), (Some("rapier"), Some("quintic-hermite")));
    assert_eq!(v["verdict"], "verified", "{}", v["verification"]["verdict"]);
    // The reference is the exact engine on the imported trajectory, which is the schedule's
    // (the round trip keeps the twist to 1e-9 rad); rapier → 0 agrees with it within the
    // verification's stated tolerance.
    let f = flip(&p.cat.half(), &s, p.exact.tolerance);
    let twist = v["verification"]["quantities"].as_array().and_then(|q| q.iter().find(|c| c["quantity"] == "twist"));
    let twist = twist.expect("the twist's convergence");
    let number = |x: &serde_json::Value| x.as_f64().expect("a number");
    assert_relative_eq!(number(&twist["reference"]), f.twist.to_degrees(), epsilon = 1e-6);
    let tolerance = number(&twist["tolerance"]);
    let extrapolated = number(&v["extrapolated"]["twist_deg"]);
    assert!(
        (extrapolated - f.twist.to_degrees()).abs() <= tolerance,
        "rapier → 0 twist {extrapolated}° against the exact {}° (tolerance {tolerance}°)",
        f.twist.to_degrees()
    );
    assert!(number(&v["dt"]) > 0.0 && v["peak_torque_nm"]["pieces"].as_array().is_some_and(|p| p.len() == 3));
    // The headline is the verified estimate (dt → 0); the finest run's value is labelled raw.
    assert_relative_eq!(number(&v["twist_deg"]), extrapolated, epsilon = 0.0);
    assert_relative_eq!(number(&v["swing_deg"]), number(&v["extrapolated"]["swing_deg"]), epsilon = 0.0);
    let raw = number(&v["twist_deg_raw"]);
    assert_relative_eq!(raw, f.twist.to_degrees() - number(&v["twist_error_deg"]), epsilon = 1e-9);
    // With no usable run (the budget below the first run), there is no rapier number to print:
    // one line saying so, and a non-zero exit.
    let out = simulate(&["--set", "rapier.step_budget=1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        err.lines().last().is_some_and(|l| l.starts_with(
            "error: rapier has no result for this schedule: inconclusive: 0 of the 3 runs needed to judge (the first run, "
        ) && l.ends_with("would overrun the budget of 1 steps (0 taken))")),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn results_files_hold_each_schedule_with_its_sidecar_and_the_model_once() {
    let p = problem();
    let s = paper_schedule(&p);
    let file = |name: &str| common::measured(&p, &s).named(ScheduleName::File(name.to_string()));
    let (problem_file, other) = (file("problem"), file("other"));
    let files =
        catflip::exchange::results_files(&p, &[&problem_file, &other], &ExportOptions::default()).expect("writes");
    let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
    assert_eq!(
        names,
        [
            "schedules/problem.json",
            "schedules/problem.csv",
            "schedules/other.json",
            "schedules/other.csv",
            "schedules/model.urdf",
            "schedules/model.xml"
        ]
    );
    // Without a rate: 400 intervals per phase, boundary times twice.
    assert_eq!(files[1].1.lines().count(), 1 + 3 * 401);
    let sidecar: Sidecar = serde_json::from_str(&files[0].1).expect("the sidecar parses back");
    assert_eq!((sidecar.sampling.kind.as_str(), sidecar.sampling.steps_per_piece), ("per-piece", Some(400)));
}

#[test]
fn a_bad_rate_is_refused_before_any_work() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_catflip"))
        .args(["run", "problems/paper.toml", "--rate=-5", "--out"])
        .arg(std::env::temp_dir().join(format!("catflip-badrate-{}", std::process::id())))
        .output()
        .expect("the binary runs");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--rate -5"), "{err}");
    // Written with a space, the same refusal (not the parser's "unexpected argument '-5'").
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_catflip"))
        .args(["run", "problems/paper.toml", "--rate", "-5", "--out"])
        .arg(std::env::temp_dir().join(format!("catflip-badrate-{}", std::process::id())))
        .output()
        .expect("the binary runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("error: --rate -5: must be a positive number of Hz"), "{err}");
}

#[test]
fn acceleration_jumps_inside_a_phase_become_boundaries_and_keep_the_peak_torque() {
    // A piecewise-linear rate (as the QP's optimum): q̈ jumps at every node inside the twist.
    // Without the cuts, the 1 kHz grid smooths each jump over a row interval and the peak moves.
    let p = problem();
    let profile =
        catflip::schedule::profile::Profile::from_rate_nodes("nodes", &[0.0, 1.0, 3.0, 2.0, 0.5, 0.0]).expect("nodes");
    let s = paper_schedule(&p).with_profile(profile);
    let file =
        write_schedule(&p, &common::measured(&p, &s), &ExportOptions { rate_hz: Some(1000.0), ..Default::default() })
            .expect("writes");
    // Four inner nodes: four cuts inside the twist, each an end/start pair, plus the two phase boundaries.
    assert_eq!(file.sidecar.pieces.len(), 3 + 4);
    assert!(file.sidecar.jumps.is_empty(), "the rates are continuous at the cuts: {:?}", file.sidecar.jumps);
    let imported = parse_schedule(&file.csv, "nodes.csv").expect("reads back");
    let report = evaluate(&p, &imported).expect("evaluates");
    let peaks = peak_torques(&p.cat.half(), &s, p.exact.torque_samples);
    eprintln!("q̈-jump round trip: peak {:.2e} relative", report.peak_torque_nm.max / peaks.max - 1.0);
    assert_relative_eq!(report.peak_torque_nm.max, peaks.max, max_relative = 1e-9);
    assert_eq!(report.peak_torque_nm.pieces.len(), 3, "cut pieces are merged back into phases");
    let f = flip(&p.cat.half(), &s, p.exact.tolerance);
    assert_relative_eq!(report.figures.twist_deg.to_radians(), f.twist, epsilon = 1e-9);
}

// ---- Nothing silently wrong (issue 18): what an imported schedule is refused or warned for ----

/// The columns of catflip's own file that make a quintic Hermite import.
const QUINTIC: [&str; 8] = ["t_s", "phase", "q1_rad", "q2_rad", "qd1_rad_s", "qd2_rad_s", "qdd1_rad_s2", "qdd2_rad_s2"];

/// The paper's schedule for `p` written at `rate_hz`.
fn paper_csv(p: &Problem, rate_hz: f64) -> String {
    let s = paper_schedule(p);
    write_schedule(p, &common::measured(p, &s), &ExportOptions { rate_hz: Some(rate_hz), ..Default::default() })
        .expect("writes")
        .csv
}

/// `csv` with the columns `keep` only (in that order), every number through `f(column, value)`
/// (written back exactly, `{:e}`).
fn reshape(csv: &str, keep: &[&str], f: impl Fn(&str, f64) -> f64) -> String {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let index: Vec<usize> = keep.iter().map(|k| header.iter().position(|h| h == k).expect("a column")).collect();
    let mut out = keep.join(",") + "\n";
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        let row: Vec<String> = index
            .iter()
            .zip(keep)
            .map(|(&i, k)| fields[i].parse::<f64>().map_or(fields[i].to_string(), |v| format!("{:e}", f(k, v))))
            .collect();
        out += &(row.join(",") + "\n");
    }
    out
}

/// `text` written as `name` into a fresh scratch folder for test `tag`.
fn scratch(tag: &str, name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("catflip-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("writable");
    path
}

/// `catflip simulate problems/paper.toml --schedule FILE ARGS…`: (exit code, stdout, stderr).
fn simulate_file(path: &std::path::Path, args: &[&str]) -> (Option<i32>, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_catflip"))
        .args(["simulate", "problems/paper.toml", "--schedule"])
        .arg(path)
        .args(args)
        .output()
        .expect("the binary runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn warned(warnings: &[String], words: &[&str]) -> bool {
    warnings.iter().any(|w| words.iter().all(|x| w.contains(x)))
}

#[test]
fn absurd_times_and_angles_are_refused_never_printed_as_nan() {
    // Times scaled by 1e±200 (rates and accelerations with them), angles of 1e60 rad, rates of
    // 1e200 rad/s: each refused with an error naming the column, and the CLI prints no number.
    let p = Problem::default();
    let csv = paper_csv(&p, 1000.0);
    for scale in [1e200, 1e-200] {
        let text = reshape(&csv, &QUINTIC[..6], |c, v| match c {
            "t_s" => v * scale,
            c if c.starts_with("qd") => v / scale,
            _ => v,
        });
        let imported = parse_schedule(&text, "scaled.csv").expect("well-formed");
        match evaluate(&p, &imported).expect_err("refused") {
            ImportError::AbsurdDuration { name, .. } => assert_eq!(name, "t_s"),
            e => panic!("{e}"),
        }
        let path = scratch("absurd", "scaled.csv", &text);
        let (code, out, err) = simulate_file(&path, &["--json"]);
        assert_eq!(code, Some(1), "{out}");
        assert!(out.is_empty() && err.contains("column `t_s`") && err.contains("seconds"), "{err}");
    }
    let huge = reshape(&csv, &QUINTIC, |c, v| if c == "q1_rad" { v * 1e60 + 1e60 } else { v });
    match parse_err(&huge) {
        ImportError::AbsurdAngle { line, column, name, .. } => {
            assert_eq!((line, column, name.as_str()), (2, 3, "q1_rad"))
        }
        e => panic!("{e}"),
    }
    let fast = reshape(&csv, &QUINTIC, |c, v| if c.starts_with("qd") && !c.starts_with("qdd") { v * 1e200 } else { v });
    // Refused as the file is read, at the first row whose rate is not zero (the cat starts at rest).
    let first_moving = 2 + fast
        .lines()
        .skip(1)
        .position(|l| l.split(',').nth(4).is_some_and(|v| v.parse::<f64>().is_ok_and(|x| x != 0.0)))
        .expect("a moving row") as u64;
    match parse_err(&fast) {
        ImportError::AbsurdRate { line, column, name, .. } => {
            assert_eq!((line, column, name.as_str()), (first_moving, 5, "qd1_rad_s"))
        }
        e => panic!("{e}"),
    }
    let path = scratch("absurd", "fast.csv", &fast);
    let (code, out, err) = simulate_file(&path, &[]);
    assert_eq!(code, Some(1), "{out}");
    assert!(!out.contains("NaN") && err.contains("is not a joint rate"), "{out}{err}");
}

#[test]
fn a_position_jump_at_a_repeated_time_is_refused_naming_the_lines() {
    // The twist's start row moved by 0.5 rad in q1: two rows at one time with different angles.
    let p = Problem::default();
    let csv = paper_csv(&p, 1000.0);
    let mut lines: Vec<String> = csv.lines().map(str::to_string).collect();
    let k = lines.iter().position(|l| l.contains(",twist,start,")).expect("a start row");
    let mut fields: Vec<String> = lines[k].split(',').map(str::to_string).collect();
    fields[3] = format!("{:e}", fields[3].parse::<f64>().expect("a number") + 0.5);
    lines[k] = fields.join(",");
    let text = lines.join("\n") + "\n";
    let line = k as u64 + 1;
    match parse_err(&text) {
        ImportError::PositionJump { lines, name, .. } => {
            assert_eq!((lines, name.as_str()), ([line - 1, line], "q1_rad"))
        }
        e => panic!("{e}"),
    }
    let path = scratch("position-jump", "jump.csv", &text);
    let (code, out, err) = simulate_file(&path, &[]);
    assert_eq!(code, Some(1), "{out}");
    assert!(err.contains(&format!("lines [{}, {line}]", line - 1)) && err.contains("q1_rad"), "{err}");
}

#[test]
fn degrees_milliseconds_and_a_short_file_are_warned() {
    let p = Problem::default();
    let csv = paper_csv(&p, 1000.0);
    let evaluated = |text: &str| evaluate(&p, &parse_schedule(text, "f.csv").expect("reads")).expect("evaluates");
    // Degrees in the `_rad` columns (rates and accelerations too).
    let deg = reshape(&csv, &QUINTIC, |c, v| if c == "t_s" { v } else { v.to_degrees() });
    let r = evaluated(&deg);
    assert!(warned(&r.warnings, &["`q1_rad`", "degrees"]), "{:?}", r.warnings);
    // Milliseconds in `t_s` (rates per millisecond).
    let ms = reshape(&csv, &QUINTIC, |c, v| match c {
        "t_s" => 1e3 * v,
        c if c.starts_with("qdd") => 1e-6 * v,
        c if c.starts_with("qd") => 1e-3 * v,
        _ => v,
    });
    let r = evaluated(&ms);
    assert!(warned(&r.warnings, &["`t_s`", "milliseconds"]), "{:?}", r.warnings);
    // A file that ends 9 ms before the fall, the joints still bent and moving.
    let fall = p.drop.fall_time();
    let cut: String = csv
        .lines()
        .enumerate()
        .filter(|(i, l)| {
            *i == 0
                || l.split(',').next().and_then(|t| t.parse::<f64>().ok()).is_some_and(|t| t <= fall - 0.009 + 1e-12)
        })
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    let r = evaluated(&cut);
    assert!(warned(&r.warnings, &["line 1425", "ms before the cat lands"]), "{:?}", r.warnings);
    assert!(
        warned(&r.warnings, &["ends bent"]) && warned(&r.warnings, &["ends moving", "impulse"]),
        "{:?}",
        r.warnings
    );
    // The CLI: a warning on stderr, the `warnings` list in JSON.
    let path = scratch("units", "ms.csv", &ms);
    let (code, _, err) = simulate_file(&path, &[]);
    assert_eq!(code, Some(0));
    assert!(err.lines().any(|l| l.starts_with("warning: ") && l.contains("milliseconds")), "{err}");
    let (_, out, _) = simulate_file(&path, &["--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).expect("one JSON object");
    assert!(v["warnings"]
        .as_array()
        .is_some_and(|w| w.iter().any(|x| x.as_str().is_some_and(|x| x.contains("milliseconds")))));
}

#[test]
fn rates_that_contradict_the_angles_are_warned() {
    // q̇ = 0 (and q̈ = 0) while q moves.
    let p = Problem::default();
    let csv = paper_csv(&p, 1000.0);
    let still = reshape(&csv, &QUINTIC, |c, v| if c.starts_with("qd") { 0.0 } else { v });
    let r = evaluate(&p, &parse_schedule(&still, "still.csv").expect("reads")).expect("evaluates");
    assert!(warned(&r.warnings, &["`qd1_rad_s` contradicts `q1_rad`"]), "{:?}", r.warnings);
    // Rates in degrees per second beside angles in radians.
    let deg = reshape(&csv, &QUINTIC[..6], |c, v| if c.starts_with("qd") { v.to_degrees() } else { v });
    let r = evaluate(&p, &parse_schedule(&deg, "deg.csv").expect("reads")).expect("evaluates");
    assert!(warned(&r.warnings, &["`qd2_rad_s` contradicts `q2_rad`"]), "{:?}", r.warnings);
}

#[test]
fn a_start_bent_and_moving_is_warned_with_its_impulse() {
    // The file starts half way through the twist, bent and moving.
    let p = Problem::default();
    let csv = paper_csv(&p, 1000.0);
    let t1 = (p.manoeuvre.phases[0] + 0.5 * p.manoeuvre.phases[1]) * p.drop.fall_time();
    let late: String = csv
        .lines()
        .enumerate()
        .filter(|(i, l)| *i == 0 || l.split(',').next().and_then(|t| t.parse::<f64>().ok()).is_some_and(|t| t >= t1))
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    let late = reshape(&late, &QUINTIC, |c, v| if c == "t_s" { v - t1 } else { v });
    let r = evaluate(&p, &parse_schedule(&late, "late.csv").expect("reads")).expect("evaluates");
    assert!(warned(&r.warnings, &["line 2", "starts bent"]), "{:?}", r.warnings);
    assert!(warned(&r.warnings, &["line 2", "starts moving", "impulse"]), "{:?}", r.warnings);
}

#[test]
fn coarse_rows_are_warned() {
    // The paper's schedule at 100 Hz: with q̇ and q̈ the quintic Hermite is accurate (its q̈ is
    // O(h⁴)), and so is the cubic Hermite (0.05 % from it on every piece), but the spline from q
    // alone is not: its unbend peak of joint 2 is 0.6 % off the quintic's, which the halving
    // estimate sees (0.7 %). At 1 kHz nothing is warned (the round trips).
    let p = Problem::default();
    let csv = paper_csv(&p, 100.0);
    for (keep, coarse) in [(&QUINTIC[..], false), (&QUINTIC[..6], false), (&QUINTIC[..4], true)] {
        let text = reshape(&csv, keep, |_, v| v);
        let r = evaluate(&p, &parse_schedule(&text, "100hz.csv").expect("reads")).expect("evaluates");
        eprintln!("100 Hz, {}: peaks {:?}, {:?}", r.interpolation, r.peak_torque_nm.pieces, r.warnings);
        assert_eq!(warned(&r.warnings, &["too far apart"]), coarse, "{}: {:?}", r.interpolation, r.warnings);
    }
}

#[test]
fn short_spline_pieces_say_the_jumps_could_not_be_checked() {
    // Angles only, pieces of five rows: the spline's end rates are too uncertain to judge a jump.
    let p = problem();
    let s = paper_schedule(&p);
    let d = s.piece_durations();
    let mut text = String::from("t_s,q1_rad,q2_rad\n");
    let mut t0 = 0.0;
    for (k, dk) in d.iter().enumerate() {
        for i in 0..5 {
            let st = s.piece_state(k, dk * i as f64 / 4.0);
            text += &format!("{:e},{:e},{:e}\n", t0 + dk * i as f64 / 4.0, st.q[0], st.q[1]);
        }
        t0 += dk;
    }
    let r = evaluate(&p, &parse_schedule(&text, "short.csv").expect("reads")).expect("evaluates");
    assert_eq!(r.velocity_jumps_unchecked.len(), 2);
    assert!(!r.to_text().contains("velocity jumps   none"), "{}", r.to_text());
    assert!(r.to_text().contains("could not check"), "{}", r.to_text());
}

#[test]
fn the_peak_is_sampled_at_every_row() {
    // Cubic Hermite: q̈ is piecewise linear and jumps at the rows, so |τ| peaks at a row (from one
    // side). The reported peak is at least every row's torque from both sides.
    let p = problem();
    let text = reshape(&paper_csv(&p, 1000.0), &QUINTIC[..6], |_, v| v);
    let imported = parse_schedule(&text, "cubic.csv").expect("reads");
    let r = evaluate(&p, &imported).expect("evaluates");
    let mut rows_max = [0.0f64; 2];
    for (k, piece) in imported.pieces.iter().enumerate() {
        for row in &piece.rows {
            let s = row.t - piece.file_start;
            for st in [imported.piece_state(k, s), imported.piece_state_before(k, s)] {
                let tau = joint_torques(&p.cat.half(), &st).tau;
                rows_max = [rows_max[0].max(tau[0].abs()), rows_max[1].max(tau[1].abs())];
            }
        }
    }
    let best = rows_max[0].max(rows_max[1]);
    eprintln!("cubic Hermite at 1 kHz: peak {:.12} N·m, largest row {best:.12}", r.peak_torque_nm.max);
    assert!(r.peak_torque_nm.max >= best, "peak {} below a row's {best}", r.peak_torque_nm.max);
    // And no lower than a dense sampling of the same interpolant (16 points per row interval).
    let dense: Vec<usize> = imported.pieces.iter().map(|x| 16 * x.rows.len()).collect();
    let reference = peak_torques_on(&p.cat.half(), &imported, &dense).max;
    assert!(r.peak_torque_nm.max >= reference * (1.0 - 1e-12), "peak {} below {reference}", r.peak_torque_nm.max);
}

#[test]
fn simulate_schedule_json_names_jumps_as_simulate_does() {
    let p = problem();
    let imported = parse_schedule(&paper_csv(&p, 1000.0), "paper.csv").expect("reads");
    let v = serde_json::to_value(evaluate(&p, &imported).expect("evaluates")).expect("serialises");
    let jump = &v["velocity_jumps"][0];
    for key in ["time", "rates_before", "rates_after", "impulse"] {
        assert!(jump.get(key).is_some(), "no `{key}` in {jump}");
    }
    assert!(v["warnings"].as_array().is_some_and(Vec::is_empty));
}

#[test]
fn simulate_schedule_reports_the_motor_demand_and_the_release_as_simulate_does() {
    // README, "Motor limits": every report of a peak torque says what it asks of the motors. A
    // file of the paper's schedule at 1 kHz, measured against a torque limit of half its peak and
    // a speed limit of 90 % of its fastest joint: its motor figures are the schedule's own (the
    // file interpolates it to O(h⁴) in q̈, so its demand agrees to 1e-6) and both
    // limits are exceeded, by 2 and by 1/0.9.
    let mut p = problem();
    let s = paper_schedule(&p);
    let own = common::measured(&p, &s).exact;
    let fastest = own.motors.peak_speed_rad_s.iter().map(|v| v.value).fold(0.0, f64::max);
    p.actuator.torque_limit_nm = Some(catflip::problem::actuator::PerJoint::Both(0.5 * own.peaks.max));
    p.actuator.speed_limit_rad_s = Some(catflip::problem::actuator::PerJoint::Both(0.9 * fastest));
    let r = evaluate(&p, &parse_schedule(&paper_csv(&p, 1000.0), "paper.csv").expect("reads")).expect("evaluates");
    for j in 0..2 {
        assert_relative_eq!(r.motors.peak_speed_rad_s[j], own.motors.peak_speed_rad_s[j].value, max_relative = 1e-6);
        assert_relative_eq!(r.motors.peak_power_w[j], own.motors.peak_power_w[j].value, max_relative = 1e-6);
    }
    assert!(!r.motors.within, "{}", r.motors.verdict);
    use catflip::model::motor::Limit;
    let worst = |limit: Limit| r.motors.limits.iter().filter(|l| l.limit == limit).map(|l| l.ratio).fold(0.0, f64::max);
    assert_relative_eq!(worst(Limit::Torque), 2.0, max_relative = 1e-6);
    assert_relative_eq!(worst(Limit::Speed), 1.0 / 0.9, max_relative = 1e-6);
    let text = r.to_text();
    assert!(text.contains("  motors           exceeds joint "), "{text}");
    assert!(text.contains("  peak speed ") && !text.contains("release spin"), "{text}");
    let v = serde_json::to_value(&r).expect("serialises");
    assert_eq!(v["motors"]["within"], false);
    assert_eq!(v["angular_momentum_nms"], serde_json::json!([0.0, 0.0, 0.0]));
    // Released with spin, the report says so, as `simulate` does.
    p.drop.angular_momentum = [0.0, 0.0, 0.01];
    let spun =
        evaluate(&p, &parse_schedule(&paper_csv(&problem(), 1000.0), "paper.csv").expect("reads")).expect("evaluates");
    assert_eq!(
        serde_json::to_value(&spun).expect("serialises")["angular_momentum_nms"],
        serde_json::json!([0.0, 0.0, 0.01])
    );
    let text = spun.to_text();
    assert!(text.contains("  release spin     L = [0, 0, 0.01] N·m·s (world frame)"), "{text}");
    assert!(text.contains("|R H − L|"), "{text}");
}

#[test]
fn plain_text_simulate_schedule_says_nothing_of_the_manoeuvre_and_ends_its_line() {
    // problems/paper.toml has theta_deg = 45 (< 90), which `simulate` warns of; an imported
    // schedule does not use the manoeuvre.
    let (dir, path, _, _) = paper_csv_at_1khz("exchange-text");
    let (code, out, err) = simulate_file(&path, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("theta_deg"), "{err}");
    assert!(out.ends_with('\n'), "{out:?}");
    // The cat is used: a careless mass (grams?) is warned of as every command warns of it.
    let (code, _, err) = simulate_file(&path, &["--set", "cat.mass=1000"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("warning: cat.mass = 1000 kg is outside the 0.01–500 kg"), "{err}");
    assert!(!err.contains("theta_deg"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn model_files_cite_the_readme_not_a_missing_design_section() {
    let p = problem();
    for (name, text) in model_files(&p).unwrap_or_else(|e| panic!("{e}")) {
        assert!(!text.contains("DESIGN.md"), "{name}");
        assert!(text.contains("README.md") && text.contains("Replay elsewhere"), "{name}");
    }
}

#[test]
fn simulate_rapier_json_leads_with_the_verified_estimate() {
    // The built-in schedule through rapier: `twist_deg` is the extrapolation the verdict judges,
    // `twist_deg_raw` the finest run's.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_catflip"))
        .args(["simulate", "problems/paper.toml", "--engine", "rapier", "--json"])
        .output()
        .expect("the binary runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let number = |x: &serde_json::Value| x.as_f64().expect("a number");
    assert_relative_eq!(number(&v["twist_deg"]), number(&v["extrapolated"]["twist_deg"]), epsilon = 0.0);
    assert_relative_eq!(number(&v["swing_deg"]), number(&v["extrapolated"]["swing_deg"]), epsilon = 0.0);
    let (raw, headline) = (number(&v["twist_deg_raw"]), number(&v["twist_deg"]));
    assert!((raw - headline).abs() > 0.0, "the raw twist {raw}° is the finest run's, not the estimate");
}

#[test]
fn a_field_with_a_line_break_is_refused_on_one_line() {
    // Found by tests/fuzz_files.rs's long run: a quoted CSV field may hold a newline, and the
    // refusal quoted it raw, over two lines.
    let dir = std::env::temp_dir().join(format!("catflip-newline-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let path = dir.join("s.csv");
    std::fs::write(&path, "t_s,q1_rad,q2_rad\n0,0,0\n\"0.5\n1\",0.1,0\n1,0,0\n").expect("written");
    let err = catflip::exchange::read_schedule(&path).expect_err("a field that is not a number");
    let msg = err.to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(!msg.contains('\n') && msg.contains("is not a number") && msg.contains("\\n"), "{msg}");
}
