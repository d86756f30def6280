//! The files of a cat beyond two motors (issue 22: exported and replayable): the schedule file of
//! any tree of bodies agrees with the two-cylinder engine on the paper's cat, its columns are what
//! a replay reads (the ball's couple turned back gives the motors' torques), its last row is the
//! flip, and the MJCF and URDF put every body, joint and motor where the tree has them (a tail's
//! and legs' too).

use catflip::engines::exact;
use catflip::engines::models::flip_on;
use catflip::engines::torque;
use catflip::exchange::tree_file::{tree_columns, write_tree_optimum, TREE_FORMAT};
use catflip::exchange::tree_model::{tree_mjcf, tree_urdf, NamedTree};
use catflip::exchange::{ExportOptions, MjcfOptions};
use catflip::model::cat::Appendages;
use catflip::model::shape::ShapeState;
use catflip::model::{Cat, Cylinder, Joint};
use catflip::optimize::whole::spline::SplineShape;
use catflip::optimize::whole::{BSpline, NamedBody, WholeCat};
use catflip::problem::Problem;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

const HALF: Cylinder = Cylinder { mass: 1.0, length: 1.0, radius: 0.1 };
const TAIL: Cylinder = Cylinder { mass: 0.2, length: 1.0, radius: 0.02 };
const LEG: Cylinder = Cylinder { mass: 0.2, length: 0.45, radius: 0.03 };
/// The hind pair of a cat whose pairs differ (`[cat.legs.rear]`).
const HIND_LEG: Cylinder = Cylinder { mass: 0.25, length: 0.4, radius: 0.035 };

fn paper() -> Problem {
    let text = std::fs::read_to_string("problems/paper.toml").expect("the paper's problem");
    Problem::from_toml(&text, "paper.toml", &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// A smooth path over 1.2 s that bends, circulates and unbends (rest to rest), with `joints`
/// coordinates: the further ones (a twist, a tail) move too.
fn circulation(joints: usize) -> BSpline {
    let mut s = BSpline::zero(1.2, 12, 3).with_joints(joints);
    let rows = [
        [0.0, 0.0, 0.3, 0.8, 0.9, 0.2, -0.6, -0.9, -0.5, 0.1, 0.0, 0.0],
        [0.0, 0.0, 0.1, -0.4, 0.5, 0.9, 0.6, -0.2, -0.7, -0.2, 0.0, 0.0],
        [0.0, 0.0, 0.2, 0.4, -0.3, -0.5, 0.1, 0.4, 0.2, -0.1, 0.0, 0.0],
        [0.0, 0.0, -0.3, 0.2, 0.6, 0.1, -0.4, -0.3, 0.2, 0.1, 0.0, 0.0],
        [0.0, 0.0, 0.4, -0.2, -0.5, 0.3, 0.5, -0.1, -0.3, 0.1, 0.0, 0.0],
    ];
    s.coefficients = rows[..joints].iter().map(|r| r.to_vec()).collect();
    s
}

/// The CSV as (header, rows of numbers; text cells as NaN).
fn table(csv: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut lines = csv.lines();
    let header = lines.next().expect("a header").split(',').map(String::from).collect();
    let rows = lines.map(|l| l.split(',').map(|c| c.parse().unwrap_or(f64::NAN)).collect()).collect();
    (header, rows)
}

fn at(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"))
}

/// On the paper's cat (two equal halves, universal joint) the tree's file is computed by the
/// general core; the two-cylinder engine computes the same motion its own way (closed-form
/// torques, its own momentum map). Every row's torques agree to 1e-10 N·m, and the last row's
/// orientation is the two-cylinder engine's flip to 1e-9 rad.
#[test]
fn on_the_papers_cat_the_tree_file_is_the_two_cylinder_engines() {
    let (problem, path) = (paper(), circulation(2));
    let model = NamedTree::of(&WholeCat::from(HALF), 1e-6).expect("cylinders");
    let flip = flip_on(&model.tree, &SplineShape(&path), &Vector3::zeros(), 1e-11);
    let file =
        write_tree_optimum(&problem, &model, &SplineShape(&path), &flip, &ExportOptions::default()).expect("written");
    let (header, rows) = table(&file.csv);
    assert_eq!(rows.len(), file.sidecar.sampling.rows);
    let (t, tau1, tau2) = (at(&header, "t_s"), at(&header, "tau1_nm"), at(&header, "tau2_nm"));
    let mut largest: f64 = 0.0;
    for row in &rows {
        let expected = torque::joint_torques(&HALF, &path.state(row[t]));
        for (j, c) in [tau1, tau2].into_iter().enumerate() {
            assert!(
                (row[c] - expected.tau[j]).abs() < 1e-10,
                "t = {}: tau{} {} against {}",
                row[t],
                j + 1,
                row[c],
                expected.tau[j]
            );
            largest = largest.max(row[c].abs());
        }
    }
    assert!(largest > 0.1, "the path asks for torque ({largest} N·m)");
    let two = exact::flip(&HALF, &path, 1e-11);
    let last = rows.last().expect("rows");
    let q = UnitQuaternion::from_quaternion(Quaternion::new(
        last[at(&header, "qw")],
        last[at(&header, "qx")],
        last[at(&header, "qy")],
        last[at(&header, "qz")],
    ));
    assert!(q.angle_to(&two.orientation) < 1e-9, "{} rad from the two-cylinder engine", q.angle_to(&two.orientation));
    assert!(two.twist.to_degrees().abs() > 10.0, "the path turns the cat ({} rad)", two.twist);
    assert_eq!(file.sidecar.format, TREE_FORMAT);
    assert!(file.sidecar.jumps.is_empty());
}

/// What a replay reads on the spherical joint: the ball's relative rotation is the joint's at the
/// row's coordinates, and its couple (B's frame) turned into A's frame projects on the motor axes
/// (A's x, A's y, B's spine) as the motors' torque columns; the last row's twist is the flip's
/// (to 1e-7°).
#[test]
fn a_replay_reads_the_motors_from_the_balls_couple() {
    let cat = Cat::equal(HALF, Joint::Spherical);
    let model = NamedTree::of(&WholeCat::spherical(cat).expect("spherical"), 1e-6).expect("cylinders");
    let path = circulation(3);
    let flip = flip_on(&model.tree, &SplineShape(&path), &Vector3::zeros(), 1e-11);
    let file =
        write_tree_optimum(&paper(), &model, &SplineShape(&path), &flip, &ExportOptions::default()).expect("written");
    let (header, rows) = table(&file.csv);
    let names: Vec<String> = tree_columns(&model).into_iter().map(|c| c.name).collect();
    assert_eq!(header, names);
    let c = |name: &str| at(&header, name);
    for row in rows.iter().step_by(7) {
        let q: Vec<f64> = (1..=3).map(|k| row[c(&format!("q{k}_rad"))]).collect();
        let rel = UnitQuaternion::from_quaternion(Quaternion::new(
            row[c("B_rel_qw")],
            row[c("B_rel_qx")],
            row[c("B_rel_qy")],
            row[c("B_rel_qz")],
        ));
        let r = rel.to_rotation_matrix().into_inner();
        assert!((r - Joint::Spherical.rotation(&q)).amax() < 1e-12, "t = {}", row[0]);
        let couple_b = Vector3::new(row[c("B_couple_x_nm")], row[c("B_couple_y_nm")], row[c("B_couple_z_nm")]);
        let couple_a = r * couple_b;
        for (k, axis) in Joint::Spherical.motor_axes(&q).iter().enumerate() {
            let tau = row[c(&format!("tau{}_nm", k + 1))];
            assert!(
                (couple_a.dot(axis) - tau).abs() < 1e-12,
                "t = {}: motor {}: {} against {tau}",
                row[0],
                k + 1,
                couple_a.dot(axis)
            );
        }
    }
    let last = rows.last().expect("rows");
    assert!(
        (last[c("twist_deg")] - flip.twist.to_degrees()).abs() < 1e-7,
        "{} against {}",
        last[c("twist_deg")],
        flip.twist.to_degrees()
    );
}

/// The MJCF of a no-twist cat with a tail on a universal joint and legs: a ball for the halves,
/// two hinges through a cross for the tail, one hinge about its half's `x` for each pair of legs,
/// one motor per hinge and three for the ball; every body's mass, moments and (at `q = 0`)
/// position relative to A are the tree's; the legs' cylinders are drawn along their `y`, each
/// pair (they differ here) with its own mass and size under its own name.
#[test]
fn the_mjcf_of_a_cat_with_a_tail_and_legs_builds_the_trees_bodies_and_joints() {
    let appendages = Appendages { tail: Some((TAIL, Joint::Universal)), legs: Some([LEG, HIND_LEG]) };
    let cat = WholeCat::appended(Cat::equal(HALF, Joint::NoTwist), appendages).expect("two-motor joints");
    let model = NamedTree::of(&cat, 1e-6).expect("cylinders");
    let text = tree_mjcf(&model, "tailed", &MjcfOptions::default());
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    let zero = ShapeState { q: vec![0.0; 6], qd: vec![0.0; 6], qdd: vec![0.0; 6] };
    let motion = model.tree.motion(&zero);
    let numbers = |s: &str| -> Vec<f64> { s.split(' ').map(|x| x.parse().expect("a number")).collect() };
    let zaxes: Vec<(&str, Option<&str>)> = doc
        .descendants()
        .filter(|n| n.has_tag_name("geom"))
        .map(|n| (n.attribute("name").expect("name"), n.attribute("zaxis")))
        .collect();
    assert_eq!(
        zaxes,
        [
            ("A", None),
            ("B", None),
            ("tail", None),
            ("hind-legs", Some("0.0 1.0 0.0")),
            ("front-legs", Some("0.0 1.0 0.0"))
        ]
    );
    for (k, NamedBody { name, .. }) in model.bodies.iter().enumerate() {
        let node = doc.descendants().find(|n| n.has_tag_name("body") && n.attribute("name") == Some(name)).expect(name);
        // Its position relative to A: the sum of the body positions up to A (A itself excluded).
        let mut position = Vector3::zeros();
        for b in node.ancestors().filter(|n| n.has_tag_name("body") && n.attribute("name") != Some("A")) {
            let p = numbers(b.attribute("pos").expect("pos"));
            position += Vector3::new(p[0], p[1], p[2]);
        }
        let expected = motion.bodies[k].position - motion.bodies[0].position;
        assert!((position - expected).amax() < 1e-15, "{name}: {position} against {expected}");
        let inertial = node.children().find(|n| n.has_tag_name("inertial")).expect("inertial");
        let body = model.tree.bodies()[k];
        assert_eq!(inertial.attribute("mass").map(|m| m.parse::<f64>().expect("mass")), Some(body.mass), "{name}");
        let moments = numbers(inertial.attribute("diaginertia").expect("moments"));
        assert_eq!(moments, [body.inertia[(0, 0)], body.inertia[(1, 1)], body.inertia[(2, 2)]], "{name}");
    }
    for (name, pair) in [("front-legs", LEG), ("hind-legs", HIND_LEG)] {
        let body = doc.descendants().find(|n| n.has_tag_name("body") && n.attribute("name") == Some(name)).expect(name);
        let inertial = body.children().find(|n| n.has_tag_name("inertial")).expect("inertial");
        assert_eq!(inertial.attribute("mass").map(|m| m.parse::<f64>().expect("mass")), Some(pair.mass), "{name}");
        let geom = body.children().find(|n| n.has_tag_name("geom")).expect("geom");
        let size = numbers(geom.attribute("size").expect("size"));
        assert_eq!(size, [pair.radius, 0.5 * pair.length], "{name}");
    }
    let joints: Vec<(&str, &str)> = doc
        .descendants()
        .filter(|n| n.has_tag_name("joint"))
        .map(|n| (n.attribute("name").expect("name"), n.attribute("type").expect("type")))
        .collect();
    assert_eq!(
        joints,
        [
            ("B_ball", "ball"),
            ("tail_1", "hinge"),
            ("tail_2", "hinge"),
            ("hind-legs_1", "hinge"),
            ("front-legs_1", "hinge")
        ]
    );
    let motors: Vec<&str> =
        doc.descendants().filter(|n| n.has_tag_name("motor")).map(|n| n.attribute("name").expect("name")).collect();
    assert_eq!(motors, ["B_bx", "B_by", "B_bz", "tau3", "tau4", "tau5", "tau6"]);
    // Every joint's anchor relative to A (its body's position plus its `pos`) is the tree's joint
    // point, and the hinges' axes are the universal joint's.
    for (i, point) in motion.links.iter().map(|l| l.point - motion.bodies[0].position).enumerate() {
        let names: Vec<String> = match i {
            0 => vec!["B_ball".into()],
            1 => vec!["tail_1".into(), "tail_2".into()],
            2 => vec!["front-legs_1".into()],
            _ => vec!["hind-legs_1".into()],
        };
        for name in names {
            let node = doc
                .descendants()
                .find(|n| n.has_tag_name("joint") && n.attribute("name") == Some(&name))
                .expect("joint");
            let mut anchor = Vector3::from_vec(numbers(node.attribute("pos").expect("pos")));
            for b in node.ancestors().filter(|n| n.has_tag_name("body") && n.attribute("name") != Some("A")) {
                anchor += Vector3::from_vec(numbers(b.attribute("pos").expect("pos")));
            }
            assert!((anchor - point).amax() < 1e-15, "{name}: {anchor} against {point}");
            let axis = node.attribute("axis").map(numbers);
            let expected = match name.as_str() {
                "tail_1" | "front-legs_1" | "hind-legs_1" => Some(vec![1.0, 0.0, 0.0]),
                "tail_2" => Some(vec![0.0, 1.0, 0.0]),
                _ => None,
            };
            assert_eq!(axis, expected, "{name}");
        }
    }
    // The URDF: each link's frame is placed by its joints' origins, and each body's centre of
    // mass (its inertial origin) lands where the tree puts it.
    let urdf = tree_urdf(&model, "tailed");
    let doc = roxmltree::Document::parse(&urdf).expect("well-formed URDF");
    let kinds: Vec<&str> =
        doc.descendants().filter(|n| n.has_tag_name("joint")).map(|n| n.attribute("type").expect("type")).collect();
    assert_eq!(kinds, ["spherical", "continuous", "continuous", "continuous", "continuous"]);
    // The legs' visuals lie along their links' y: URDF's cylinder (along z) turned by Rx(−π/2).
    for name in ["front-legs", "hind-legs"] {
        let link = doc.descendants().find(|n| n.has_tag_name("link") && n.attribute("name") == Some(name)).expect(name);
        let visual = link.descendants().find(|n| n.has_tag_name("visual")).expect("a visual");
        let rpy = numbers(
            visual.children().find(|c| c.has_tag_name("origin")).and_then(|o| o.attribute("rpy")).expect("rpy"),
        );
        assert!(
            (rpy[0] + std::f64::consts::FRAC_PI_2).abs() < 1e-15 && rpy[1].abs() < 1e-15 && rpy[2].abs() < 1e-15,
            "{name}: {rpy:?}"
        );
    }
    let origin_of = |n: roxmltree::Node| -> Vector3<f64> {
        let o = n.children().find(|c| c.has_tag_name("origin")).expect("origin");
        Vector3::from_vec(numbers(o.attribute("xyz").expect("xyz")))
    };
    let frame = |link: &str| -> Vector3<f64> {
        let mut at = Vector3::zeros();
        let mut name = link.to_string();
        while let Some(j) = doc.descendants().find(|n| {
            n.has_tag_name("joint")
                && n.children().any(|c| c.has_tag_name("child") && c.attribute("link") == Some(&name))
        }) {
            at += origin_of(j);
            name = j
                .children()
                .find(|c| c.has_tag_name("parent"))
                .and_then(|c| c.attribute("link"))
                .expect("parent")
                .to_string();
        }
        at
    };
    for (k, NamedBody { name, .. }) in model.bodies.iter().enumerate() {
        let link = doc.descendants().find(|n| n.has_tag_name("link") && n.attribute("name") == Some(name)).expect(name);
        let inertial = link.children().find(|n| n.has_tag_name("inertial")).expect("inertial");
        let centre = frame(name) + origin_of(inertial);
        let expected = motion.bodies[k].position - motion.bodies[0].position;
        assert!((centre - expected).amax() < 1e-15, "{name}: {centre} against {expected}");
    }
}

/// A ball inside the tree (a tail on a no-twist joint hanging from the spherical cat's rear half):
/// each ball's relative rotation and rate are its joint's at the row's coordinates (the rate in
/// the child's frame), and its couple, turned from the child's frame into A's by the child's
/// orientation relative to A (the product of the joints' rotations), projects on that joint's
/// motor axes (in A's frame) as its motors' torque columns.
#[test]
fn every_ball_of_a_tree_reads_in_its_childs_frame() {
    let cat = Cat::equal(HALF, Joint::Spherical);
    let tree = cat.tree_with_tail(&TAIL, Joint::NoTwist);
    let named = |name, cylinder| NamedBody { name, cylinder, axis: Vector3::z() };
    let model =
        NamedTree { tree, bodies: vec![named("A", HALF), named("B", HALF), named("tail", TAIL)], cross: (0.0, 0.0) };
    let path = circulation(5);
    let flip = flip_on(&model.tree, &SplineShape(&path), &Vector3::zeros(), 1e-11);
    let file =
        write_tree_optimum(&paper(), &model, &SplineShape(&path), &flip, &ExportOptions::default()).expect("written");
    let (header, rows) = table(&file.csv);
    let c = |name: &str| at(&header, name);
    let quaternion = |row: &[f64], child: &str| {
        let part = |p: &str| row[c(&format!("{child}_rel_q{p}"))];
        UnitQuaternion::from_quaternion(Quaternion::new(part("w"), part("x"), part("y"), part("z")))
            .to_rotation_matrix()
            .into_inner()
    };
    let vector = |row: &[f64], name: &dyn Fn(&str) -> String| {
        Vector3::new(row[c(&name("x"))], row[c(&name("y"))], row[c(&name("z"))])
    };
    for row in rows.iter().step_by(11) {
        let q: Vec<f64> = (1..=5).map(|k| row[c(&format!("q{k}_rad"))]).collect();
        let qd: Vec<f64> = (1..=5).map(|k| row[c(&format!("qd{k}_rad_s"))]).collect();
        let tau: Vec<f64> = (1..=5).map(|k| row[c(&format!("tau{k}_nm"))]).collect();
        let (r_b, r_tail) = (quaternion(row, "B"), quaternion(row, "tail"));
        assert!((r_b - Joint::Spherical.rotation(&q[..3])).amax() < 1e-12, "t = {}", row[0]);
        assert!((r_tail - Joint::NoTwist.rotation(&q[3..])).amax() < 1e-12, "t = {}", row[0]);
        let rate_b = r_b.transpose() * Joint::Spherical.relative_rate(&q[..3], &qd[..3]);
        let rate_tail = r_tail.transpose() * Joint::NoTwist.relative_rate(&q[3..], &qd[3..]);
        assert!((vector(row, &|p| format!("B_rel_w{p}_rad_s")) - rate_b).amax() < 1e-12, "t = {}", row[0]);
        assert!((vector(row, &|p| format!("tail_rel_w{p}_rad_s")) - rate_tail).amax() < 1e-12, "t = {}", row[0]);
        // Each couple in A's frame, against the motor axes in A's frame (the tail's are B's x, y).
        let in_a = [
            r_b * vector(row, &|p| format!("B_couple_{p}_nm")),
            r_b * r_tail * vector(row, &|p| format!("tail_couple_{p}_nm")),
        ];
        let axes: Vec<Vector3<f64>> = Joint::Spherical
            .motor_axes(&q[..3])
            .into_iter()
            .chain(Joint::NoTwist.motor_axes(&q[3..]).into_iter().map(|a| r_b * a))
            .collect();
        for (k, axis) in axes.iter().enumerate() {
            let couple = in_a[usize::from(k >= 3)];
            assert!(
                (couple.dot(axis) - tau[k]).abs() < 1e-12,
                "t = {}: motor {}: {} against {}",
                row[0],
                k + 1,
                couple.dot(axis),
                tau[k]
            );
        }
    }
}
