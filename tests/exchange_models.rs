//! Schedule files and URDF/MJCF of unequal halves and of the no-twist joint (issue 22): the
//! orientation and torque columns are the general exact engine's on the model, the model files put
//! each half where DESIGN.md §10 puts it (the no-twist joint as a ball joint in the MJCF and pyBullet's
//! spherical joint in the URDF), and a
//! joint the files do not build (the spherical one) or a release with spin is refused, naming the
//! field.
#![deny(clippy::float_cmp)]

mod common;

use std::path::Path;

use approx::assert_relative_eq;

use catflip::engines::resolved::Resolved;
use catflip::exchange::{model_files, write_schedule, ImportedSchedule};
use catflip::model::Joint;
use catflip::problem::Problem;
use catflip::report::import::ImportReport;
use nalgebra::{UnitQuaternion, Vector3};

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
    let files = model_files(&r.problem).unwrap_or_else(|e| panic!("{e}"));
    let [_, (_, xml)] = files.as_slice() else { panic!("{} model files", files.len()) };
    let doc = roxmltree::Document::parse(xml).unwrap_or_else(|e| panic!("{e}"));
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

/// The rows of a schedule file's CSV that are not boundary rows, by index.
fn plain_rows(csv: &str) -> Vec<usize> {
    csv.lines().skip(1).enumerate().filter(|(_, l)| l.split(',').nth(2) == Some("")).map(|(k, _)| k).collect()
}

/// The no-twist joint's schedule file (`problems/kane-scher.toml`'s library schedule): its ball
/// columns are B's rotation relative to A, `exp([q1, q2, 0]×)` (nalgebra's exponential, not the
/// joint's Rodrigues formula), and its rate in B's frame (central differences of that rotation
/// along the schedule, step 1e-5 s, so agreement to ~1e-9); the whole couple `(τ1, τ2, τz)`
/// does the work the motion needs: `(τ1, τ2, τz) · ω_rel = dE/dt` at zero momentum (the joint
/// force does no net work at the joint point), which fails if the constraint's `τz` is left out
/// or wrong (the test checks that leaving it out would be seen). The sidecar names the URDF and
/// has no cross.
#[test]
fn a_schedule_file_of_the_no_twist_joint_carries_the_ball_columns() {
    let r = resolved("kane-scher.toml");
    let file = write_schedule(&r.problem, &common::measured(&r.problem, &r.schedule), &Default::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let col = |name: &str| column(&file.csv, name);
    let (t, tau1, tau2, tauz) = (col("t_s"), col("tau1_nm"), col("tau2_nm"), col("tauz_nm"));
    let rel = ["rel_qw", "rel_qx", "rel_qy", "rel_qz"].map(col);
    let w_b = ["rel_wx_rad_s", "rel_wy_rad_s", "rel_wz_rad_s"].map(col);
    let model = r.model();
    let exp =
        |st: &catflip::schedule::JointState| UnitQuaternion::from_scaled_axis(Vector3::new(st.q[0], st.q[1], 0.0));
    let (h, mut worst_power, mut largest_power, mut without_tauz) = (1e-5, 0.0f64, 0.0f64, 0.0f64);
    let rows = plain_rows(&file.csv);
    for &k in rows.iter().filter(|&&k| t[k] > h && t[k] < t[t.len() - 1] - h) {
        let st = r.schedule.state(t[k]);
        let want = exp(&st);
        let got = [rel[0][k], rel[1][k], rel[2][k], rel[3][k]];
        for (g, w) in got.iter().zip([want.w, want.i, want.j, want.k]) {
            assert!((g - w).abs() <= 1e-14, "row {k}: relative quaternion {got:?} against {want:?}");
        }
        assert!(rel[3][k].abs() <= 1e-15, "row {k}: a relative twist {}", rel[3][k]);
        // ω in B's frame: the vector part of 2 q⁻¹ q̇.
        let (before, after) = (exp(&r.schedule.state(t[k] - h)), exp(&r.schedule.state(t[k] + h)));
        let dq = (after.into_inner() - before.into_inner()) / (2.0 * h);
        let omega = (want.into_inner().conjugate() * dq).vector() * 2.0;
        let w = Vector3::new(w_b[0][k], w_b[1][k], w_b[2][k]);
        assert!((w - omega).norm() <= 1e-7 * (1.0 + omega.norm()), "row {k}: rate {w} against {omega}");
        // The couple's power against the kinetic energy's rate.
        let couple = Vector3::new(tau1[k], tau2[k], tauz[k]);
        let energy = |s: f64| {
            let st = r.schedule.state(s);
            model.kinetic_energy(st.q, st.qd)
        };
        let de_dt = (energy(t[k] + h) - energy(t[k] - h)) / (2.0 * h);
        let rate_in_a = want * w;
        let power = couple.dot(&rate_in_a);
        worst_power = worst_power.max((power - de_dt).abs());
        largest_power = largest_power.max(de_dt.abs());
        without_tauz = without_tauz.max((power - tauz[k] * rate_in_a.z - de_dt).abs());
    }
    assert!(rows.len() > 100, "{} rows", rows.len());
    assert!(worst_power <= 1e-6 * largest_power, "power off by {worst_power} W (largest {largest_power} W)");
    assert!(without_tauz > 1e-3 * largest_power, "without τz the power is off by only {without_tauz} W");
    // The jumps' impulses about A's z sit on their 'start' rows.
    let impulse_z = col("impulsez_nms");
    let starts = file.csv.lines().skip(1).filter(|l| l.split(',').nth(2) == Some("start")).count();
    assert!(file.sidecar.jumps.is_empty() || impulse_z.iter().any(|x| x.abs() > 0.0), "no impulse about z");
    assert!(impulse_z.iter().filter(|x| x.abs() > 0.0).count() <= starts);
    let m = &file.sidecar.model;
    assert!(m.urdf == "model.urdf" && m.cross_mass_kg.is_none(), "{m:?}");
    assert!(m.joint.starts_with("no-twist") && m.model_note.is_some(), "{m:?}");
    assert!(file.sidecar.columns.iter().any(|c| c.name == "tauz_nm"));
    // The universal joint's files keep their 19 columns.
    let paper = resolved("paper.toml");
    let file = write_schedule(&paper.problem, &common::measured(&paper.problem, &paper.schedule), &Default::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(file.sidecar.columns.len(), 19);
    assert!(file.sidecar.model.urdf == "model.urdf" && file.sidecar.model.cross_mass_kg.is_some());
}

/// The no-twist joint's model files: `model.xml` with B on a `ball` joint through B's
/// `(0, 0, +l_B/2)`, B's centre at A's `(0, 0, −l_A/2 − l_B/2)` (so the joint point is A's
/// `(0, 0, −l_A/2)`), no cross, each half's true mass and inertia, and three motors about B's
/// axes; `model.urdf` with links A and B joined by pyBullet's `spherical` joint at A's
/// `(0, 0, −l_A/2)`, B's centre of mass at `(0, 0, −l_B/2)` in B's frame there, the same masses
/// and inertias; on equal halves and on unequal ones.
#[test]
fn the_mjcf_of_the_no_twist_joint_is_a_ball_at_the_joint_point() {
    let sets = ["cat.joint=no-twist".to_string()];
    for (file, sets) in [("kane-scher.toml", &[][..]), ("unequal-halves.toml", &sets[..])] {
        let problem = Problem::load(&Path::new("problems").join(file), sets).unwrap_or_else(|e| panic!("{e}"));
        let cat = problem.cat.model();
        assert_eq!(cat.joint, Joint::NoTwist);
        let files = model_files(&problem).unwrap_or_else(|e| panic!("{e}"));
        let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["model.urdf", "model.xml"], "{file}");
        check_spherical_urdf(&files[0].1, &cat);
        let doc = roxmltree::Document::parse(&files[1].1).unwrap_or_else(|e| panic!("{e}"));
        let bodies: Vec<&str> =
            doc.descendants().filter(|n| n.has_tag_name("body")).filter_map(|n| n.attribute("name")).collect();
        assert_eq!(bodies, ["A", "B"], "{file}");
        let body = |name: &str| {
            doc.descendants()
                .find(|n| n.has_tag_name("body") && n.attribute("name") == Some(name))
                .unwrap_or_else(|| panic!("no body {name}"))
        };
        let xyz = |text: Option<&str>| -> Vec<f64> {
            text.unwrap_or_default().split(' ').map(|x| x.parse().unwrap_or(f64::NAN)).collect()
        };
        let (ha, hb) = (0.5 * cat.front.length, 0.5 * cat.rear.length);
        let b = xyz(body("B").attribute("pos"));
        let joint = body("B").children().find(|n| n.has_tag_name("joint")).unwrap_or_else(|| panic!("no joint"));
        assert_eq!(joint.attribute("type"), Some("ball"), "{file}");
        let anchor = xyz(joint.attribute("pos"));
        assert_relative_eq!(b[2], -(ha + hb), max_relative = 1e-15);
        assert_relative_eq!(anchor[2], hb, max_relative = 1e-15);
        // The joint point in A's frame.
        assert_relative_eq!(b[2] + anchor[2], -ha, epsilon = 1e-15);
        assert_relative_eq!(b[0].abs() + b[1].abs() + anchor[0].abs() + anchor[1].abs(), 0.0, epsilon = 0.0);
        for (name, half) in [("A", cat.front), ("B", cat.rear)] {
            let inertial =
                body(name).children().find(|n| n.has_tag_name("inertial")).unwrap_or_else(|| panic!("{name}"));
            assert_eq!(inertial.attribute("mass"), Some(format!("{:?}", half.mass).as_str()));
            let i = xyz(inertial.attribute("diaginertia"));
            let (t, a) = (half.transverse(), half.axial());
            let want = [t, t, a];
            for k in 0..3 {
                assert_relative_eq!(i[k], want[k], max_relative = 1e-15);
            }
        }
        let gears: Vec<(&str, &str)> = doc
            .descendants()
            .filter(|n| n.has_tag_name("motor"))
            .map(|n| (n.attribute("joint").unwrap_or(""), n.attribute("gear").unwrap_or("")))
            .collect();
        assert_eq!(gears, [("joint", "1 0 0 0 0 0"), ("joint", "0 1 0 0 0 0"), ("joint", "0 0 1 0 0 0")]);
    }
}

/// The no-twist cat's URDF ([`the_mjcf_of_the_no_twist_joint_is_a_ball_at_the_joint_point`]).
fn check_spherical_urdf(text: &str, cat: &catflip::model::Cat) {
    let doc = roxmltree::Document::parse(text).unwrap_or_else(|e| panic!("{e}"));
    let links: Vec<&str> =
        doc.descendants().filter(|n| n.has_tag_name("link")).filter_map(|n| n.attribute("name")).collect();
    assert_eq!(links, ["A", "B"]);
    let joints: Vec<_> = doc.descendants().filter(|n| n.has_tag_name("joint")).collect();
    assert_eq!(joints.len(), 1);
    assert_eq!(joints[0].attribute("type"), Some("spherical"));
    fn child<'a, 'i>(tag: &str, node: roxmltree::Node<'a, 'i>) -> roxmltree::Node<'a, 'i> {
        node.descendants().find(|n| n.has_tag_name(tag)).unwrap_or_else(|| panic!("no {tag}"))
    }
    let xyz = |node: roxmltree::Node| -> Vec<f64> {
        node.attribute("xyz").unwrap_or_default().split(' ').map(|x| x.parse().unwrap_or(f64::NAN)).collect()
    };
    assert_eq!(child("parent", joints[0]).attribute("link"), Some("A"));
    assert_eq!(child("child", joints[0]).attribute("link"), Some("B"));
    let at = xyz(child("origin", joints[0]));
    assert_relative_eq!(at[2], -0.5 * cat.front.length, max_relative = 1e-15);
    assert_relative_eq!(at[0].abs() + at[1].abs(), 0.0, epsilon = 0.0);
    for (name, half, com) in [("A", cat.front, 0.0), ("B", cat.rear, -0.5 * cat.rear.length)] {
        let link = doc
            .descendants()
            .find(|n| n.has_tag_name("link") && n.attribute("name") == Some(name))
            .unwrap_or_else(|| panic!("no link {name}"));
        let inertial = child("inertial", link);
        assert_relative_eq!(xyz(child("origin", inertial))[2], com, max_relative = 1e-15);
        let mass: f64 = child("mass", inertial).attribute("value").unwrap_or_default().parse().unwrap_or(f64::NAN);
        assert_relative_eq!(mass, half.mass, max_relative = 1e-15);
        let inertia = child("inertia", inertial);
        let moment = |k: &str| inertia.attribute(k).unwrap_or_default().parse::<f64>().unwrap_or(f64::NAN);
        assert_relative_eq!(moment("ixx"), half.transverse(), max_relative = 1e-15);
        assert_relative_eq!(moment("iyy"), half.transverse(), max_relative = 1e-15);
        assert_relative_eq!(moment("izz"), half.axial(), max_relative = 1e-15);
    }
}

/// The spherical joint and a release with spin are refused by the files, naming the field; the
/// no-twist joint released without spin passes.
#[test]
fn the_files_refuse_the_spherical_joint_and_a_spin() {
    let r = resolved("kane-scher.toml");
    assert!(catflip::report::whole_files::files_refusal(&r.problem).is_ok());
    let mut spherical = r.problem.clone();
    spherical.cat.joint = Joint::Spherical;
    let e = catflip::report::whole_files::files_refusal(&spherical).map(|_| ()).unwrap_err().to_string();
    assert!(e.starts_with("cat.joint = \"spherical\": optimize --whole --out"), "{e}");
    let e = model_files(&spherical).map(|_| ()).unwrap_err().to_string();
    assert!(e.starts_with("cat.joint = \"spherical\": the URDF/MJCF export"), "{e}");
    let mut spinning = r.problem.clone();
    spinning.drop.angular_momentum = [0.0, 0.0, 0.01];
    let e = catflip::report::whole_files::files_refusal(&spinning).map(|_| ()).unwrap_err().to_string();
    assert!(e.starts_with("drop.angular_momentum = "), "{e}");
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
