//! `catflip compare-models` (issue 22): the models it compares are the problem's cat on each
//! joint (and the mean half's when the halves differ); each row's optimum is that model's, as its
//! own exact engine measures it, and a model without an optimum is said, never a number.
//!
//! The comparisons here run on a coarse spline (40 control points, one start, no refinement) so
//! that four models solve in a few seconds; the optimiser itself is tested in tests/whole*.rs.

mod common;

use catflip::compare_models::{compare_models, variants, Beyond, ModelComparison, ModelRow};
use catflip::engines::models::{self, TwoMotorCat};
use catflip::engines::rapier::Status;
use catflip::engines::reduction;
use catflip::model::tree::Tree;
use catflip::model::{Cat, Joint};
use catflip::optimize::whole::spline::SplineShape;
use catflip::problem::manoeuvre::BendPath;
use catflip::problem::Problem;
use catflip::schedule::Trajectory;
use nalgebra::Vector3;

fn preset(name: &str, extra: &[&str]) -> Problem {
    let path = format!("problems/{name}.toml");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let overrides: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    Problem::from_toml(&text, &path, &overrides).unwrap_or_else(|e| panic!("{path}: {e}"))
}

const COARSE: [&str; 3] = [
    "optimize.whole.control_points=40",
    "optimize.whole.switch_refinements=0",
    "optimize.whole.starts=[\"cone-mirrored\"]",
];

fn coarse(name: &str) -> ModelComparison {
    compare_models(&preset(name, &COARSE), false, "test").unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn equal_halves_are_compared_on_both_joints() {
    let p = preset("paper", &[]);
    let v = variants(&p).expect("valid models");
    let keys: Vec<&str> = v.iter().map(|x| x.key.as_str()).collect();
    assert_eq!(keys, ["universal", "no-twist", "spherical"]);
    for x in &v {
        let cat = x.problem.cat.model();
        assert!(cat.has_equal_halves(), "{}: {cat:?}", x.key);
        assert_eq!(cat.front, p.cat.model().front, "{}: the problem's halves", x.key);
    }
    assert_eq!(v[0].problem.cat.joint, Joint::Universal);
    assert_eq!(v[1].problem.cat.joint, Joint::NoTwist);
    // The spherical joint starts from the no-twist joint's problem (its twist held at zero).
    assert_eq!((v[2].beyond, v[2].problem.cat.joint), (Beyond::Spherical, Joint::NoTwist));
    // Everything but the cat is the problem's.
    assert_eq!(v[1].problem.drop, p.drop);
    assert_eq!(v[1].problem.optimize, p.optimize);
}

#[test]
fn unequal_halves_are_compared_with_their_mean_half() {
    let p = preset("unequal-halves", &[]);
    let v = variants(&p).expect("valid models");
    let keys: Vec<&str> = v.iter().map(|x| x.key.as_str()).collect();
    assert_eq!(
        keys,
        [
            "mean-universal",
            "mean-no-twist",
            "mean-spherical",
            "unequal-universal",
            "unequal-no-twist",
            "unequal-spherical"
        ]
    );
    let (front, rear) = (p.cat.front(), p.cat.rear());
    let mean = v[0].problem.cat.model().front;
    assert!((mean.mass - 0.5 * (front.mass + rear.mass)).abs() < 1e-15, "{mean:?}");
    assert!((mean.length - 0.5 * (front.length + rear.length)).abs() < 1e-15, "{mean:?}");
    assert!(v[0].problem.cat.model().has_equal_halves() && v[1].problem.cat.model().has_equal_halves());
    for x in &v[3..] {
        let cat = x.problem.cat.model();
        assert_eq!((cat.front, cat.rear), (front, rear), "{}", x.key);
    }
}

#[test]
fn the_cone_becomes_the_joint_circle_on_the_no_twist_joint() {
    let p = preset("cone-calibrated", &[]);
    assert_eq!(p.manoeuvre.bend_path, BendPath::Cone);
    let v = variants(&p).expect("valid models");
    assert_eq!(v[0].problem.manoeuvre.bend_path, BendPath::Cone, "the universal joint keeps the cone");
    assert_eq!(v[1].problem.manoeuvre.bend_path, BendPath::JointCircle);
    assert_eq!(v[2].problem.manoeuvre.bend_path, BendPath::JointCircle, "the spherical joint starts as no-twist");
}

/// Each row's optimum is re-measured here by its own model's general core, independently of the
/// optimiser's measurement: its flip (to 1e-9 rad) and its peak (dense samples, 1e-3 relative:
/// the row's peak is refined between samples, so it may only be higher).
#[test]
fn every_row_is_its_own_models_optimum() {
    let c = coarse("unequal-halves");
    assert_eq!(c.rows.len(), 6);
    assert_eq!(c.rows.iter().filter(|r| r.motors == 2).count(), 4);
    for r in c.rows.iter().filter(|r| r.motors == 3) {
        // The spherical joint on the row's own halves (its problem is the no-twist joint's).
        assert_beyond_row(r, &Cat { joint: Joint::Spherical, ..r.problem.cat.model() }.tree());
    }
    for r in c.rows.iter().filter(|r| r.motors == 2) {
        let (Some(o), Some(spline)) = (&r.optimum, &r.spline) else {
            panic!("{}: no optimum ({}); the coarse spline converges on every model", r.key, r.status)
        };
        let cat = r.problem.cat.model();
        let model = TwoMotorCat::new(cat).expect("two motors");
        let flip = model.flip(spline, 1e-11);
        assert!((flip.twist.abs() - std::f64::consts::PI).abs() < 1e-9, "{}: twist {}", r.key, flip.twist);
        assert!(flip.swing < 1e-9, "{}: swing {}", r.key, flip.swing);
        assert!((flip.twist.to_degrees() - o.twist_deg).abs() < 1e-7, "{}: {} vs {}", r.key, flip.twist, o.twist_deg);
        let n = 20_000;
        let total = spline.total_duration();
        let sampled = (0..=n)
            .map(|k| {
                let tau = model.joint_torques(&spline.state_at(total * k as f64 / n as f64)).tau;
                tau[0].abs().max(tau[1].abs())
            })
            .fold(0.0, f64::max);
        assert!(
            o.peak_torque_nm >= sampled * (1.0 - 1e-9),
            "{}: row {} below sampled {sampled}",
            r.key,
            o.peak_torque_nm
        );
        assert!(
            (o.peak_torque_nm - sampled) / sampled < 1e-3,
            "{}: row {} vs sampled {sampled}",
            r.key,
            o.peak_torque_nm
        );
        assert_eq!(r.joint, cat.joint);
        assert!(r.bend.iter().all(|(_, b)| *b >= 0.0 && *b <= o.max_bend_deg + 0.1), "{}: bend curve", r.key);
    }
    // The cheapest is the least peak, and the report leads with it.
    let least = c.rows.iter().filter_map(|r| r.peak()).fold(f64::INFINITY, f64::min);
    let best = c.cheapest_row().expect("a cheapest model");
    assert_eq!(best.peak(), Some(least));
    let md = c.to_markdown();
    let lead = md.lines().find(|l| l.starts_with("**")).expect("a lead line");
    assert!(lead.contains(&best.label), "lead {lead:?} should name {}", best.label);
    // One CSV row per model, no NaN.
    let csv = c.to_csv();
    assert_eq!(csv.lines().count(), 1 + c.rows.len(), "{csv}");
    assert!(!csv.contains("NaN") && !md.contains("NaN"), "{csv}\n{md}");
    // Each optimum's status, in the table and the CSV, is how its last stage ended: an upper
    // bound exactly when its reason says that stage stopped at its budget.
    let records: Vec<csv::StringRecord> =
        csv::Reader::from_reader(csv.as_bytes()).records().collect::<Result<_, _>>().expect("CSV records");
    for (r, line) in c.rows.iter().zip(&records) {
        let o = r.optimum.as_ref().expect("an optimum on every coarse model");
        assert_eq!(line.get(5), Some(r.status.as_str()), "{line:?}");
        let expected = if common::last_stage_at_budget(&o.reason) { "upper-bound" } else { "converged" };
        assert_eq!(r.status, expected, "{}: {}", r.key, o.reason);
    }
    // The report says what an upper bound is when a row is one, and the lead flags each one it
    // quotes (here every row made one).
    assert_eq!(md.contains("(Status `upper-bound`"), c.rows.iter().any(ModelRow::is_upper_bound), "{md}");
    let mut bounded = c.clone();
    for r in &mut bounded.rows {
        r.status = "upper-bound".into();
    }
    let md = bounded.to_markdown();
    let lead = md.lines().find(|l| l.starts_with("**")).expect("a lead line");
    assert_eq!(lead.matches("(an upper bound, `upper-bound`)").count(), bounded.rows.len(), "{lead}");
    assert!(md.contains("(Status `upper-bound`"), "{md}");
    // A field with a comma (a refined lifted start's name) is quoted in the CSV, not split.
    let mut refined = c.clone();
    let name = "universal optimum from paper, refined";
    refined.rows[0].optimum.as_mut().expect("an optimum").start = name.into();
    let text = refined.to_csv();
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let first = reader.records().next().expect("a row").expect("a CSV record");
    assert_eq!((first.len(), &first[6]), (20, name), "{text}");
}

/// Models without an optimum are rows that say so: no numbers, no cheapest, and the files still
/// written whole (the CLI then exits non-zero, tests/cli.rs).
#[test]
fn a_model_without_an_optimum_is_said_plainly() {
    let mut extra = COARSE.to_vec();
    extra.push("optimize.whole.max_iterations=2");
    let c = compare_models(&preset("paper", &extra), false, "test").expect("runs");
    assert!(c.cheapest.is_none(), "{:?}", c.cheapest);
    for r in &c.rows {
        assert!(r.optimum.is_none() && r.spline.is_none(), "{}: {}", r.key, r.status);
        // The status is a code, the reason the words (the JSON, the CSV and the table agree).
        assert_eq!(r.status, "no-optimum", "{}: {:?}", r.key, r.reason);
        assert!(r.reason.as_deref().is_some_and(|w| w.starts_with("no optimum")), "{}: {:?}", r.key, r.reason);
        assert!(r.schedule.is_some(), "{}: the library schedule is still measured", r.key);
    }
    let md = c.to_markdown();
    assert!(md.contains("No model has an optimum"), "{md}");
    assert!(md.contains("Why a model has no optimum"), "{md}");
    let csv = c.to_csv();
    for line in csv.lines().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells[5], "no-optimum", "{line}");
        assert!(cells[8].is_empty() && cells[9].is_empty(), "absent numbers are empty cells: {line}");
    }
}

#[test]
fn the_files_and_pictures_are_written_together() {
    let c = coarse("kane-scher");
    let out = std::env::temp_dir().join(format!("catflip-compare-models-{}", std::process::id()));
    let dir = c.write(&out).expect("written");
    for name in ["models.md", "models.csv", "models.json", "models_bend.png", "models_bend.svg"] {
        assert!(dir.join(name).is_file(), "{name} missing in {}", dir.display());
    }
    for r in &c.rows {
        assert!(dir.join(format!("{}_filmstrip.png", r.key)).is_file(), "{} filmstrip", r.key);
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("models.json")).expect("json")).expect("parses");
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(c.rows.len()));
    let _ = std::fs::remove_dir_all(&out);
}

/// With the objective `min-time` each model flies its own least fall within its motors: the table
/// gives each one's fall and the drop height it needs (`g t²/2`), and does not call it the
/// problem's fall (measured on Kane and Scher's cat, `|τ| ≤ 0.5 N·m`, 40 control points: the
/// universal joint 1.143268 s, 6.40 m; the no-twist joint 1.149759 s, 6.48 m; the spherical
/// joint, its three motors within the limit, 1.139592 s, 6.36 m), and how each optimum ended in
/// the optimiser's words.
#[test]
fn least_fall_times_are_compared_with_their_drop_heights() {
    let extra =
        ["actuator.torque_limit_nm=0.5", "optimize.whole.objective=\"min-time\"", "optimize.whole.control_points=40"];
    let p = preset("kane-scher", &extra);
    let c = compare_models(&p, false, "test").unwrap_or_else(|e| panic!("{e}"));
    let md = c.to_markdown();
    assert!(md.contains("| fall s | drop m |") && !md.contains("on the same fall"), "{md}");
    assert_eq!(c.rows.iter().map(|r| r.motors).collect::<Vec<_>>(), [2, 2, 3]);
    for r in &c.rows {
        // Beyond two motors too: the torque limit on every motor (the least-peak path slowed).
        let o = r.optimum.as_ref().unwrap_or_else(|| panic!("{}: {}", r.label, r.status));
        assert!(o.peak_torque_nm <= 0.5 * (1.0 + 1e-6), "{}: peak {} N·m", r.label, o.peak_torque_nm);
        assert!(o.fall_time_s < p.drop.fall_time(), "{}: {} s is not below the problem's fall", r.label, o.fall_time_s);
        approx::assert_relative_eq!(
            o.drop_height_m,
            0.5 * p.drop.gravity * o.fall_time_s.powi(2),
            max_relative = 1e-12
        );
        assert!(md.contains(&format!("| {:.4} |", o.drop_height_m)), "{}: {md}", r.label);
        // How it ended, in the optimiser's words (the spherical joint's names where it started).
        let ended = format!("- {}: from the start `{}`, {} iterations: {}", r.label, o.start, o.iterations, o.reason);
        assert!(md.contains(&ended), "{}: {md}", r.label);
    }
}

/// Beyond two motors only one torque limit on every motor is planned: with a speed limit too the
/// spherical joint's row is "not run" and names `[actuator]`, while the two-motor rows plan within
/// both limits.
#[test]
fn beyond_two_motors_other_limits_are_a_row_that_says_why() {
    let extra = [
        "actuator.torque_limit_nm=0.5",
        "actuator.speed_limit_rad_s=10.0",
        "optimize.whole.objective=\"min-time\"",
        "optimize.whole.control_points=30",
    ];
    let c = compare_models(&preset("kane-scher", &extra), false, "test").unwrap_or_else(|e| panic!("{e}"));
    for r in &c.rows {
        if r.motors > 2 {
            assert!(r.optimum.is_none() && r.status == "not-run", "{}: {}", r.key, r.status);
            assert!(r.reason.as_deref().is_some_and(|w| w.starts_with("actuator")), "{}: {:?}", r.key, r.reason);
            assert!(r.files.is_empty(), "{}: no files without an optimum", r.key);
        } else {
            assert!(r.optimum.is_some(), "{}: {}", r.key, r.status);
        }
    }
}

/// Issue 22: the models beyond two motors, on the paper's cat with a tail (`[cat.tail]`, a tenth of
/// its mass on a universal joint; 30 control points): the spherical joint and the tailed cat are
/// rows of their own, each optimum re-measured here by the general core on its tree of bodies (its
/// flip to 1e-9 rad, its peak against dense samples of every motor, 1e-3 relative) and verified in
/// rapier's tree scene; the tailed cat needs the least peak.
#[test]
fn rows_beyond_two_motors_are_planned_remeasured_and_verified() {
    let text = std::fs::read_to_string("problems/paper.toml").expect("the paper's problem")
        + "\n[cat.tail]\nmass = 0.2\nlength = 1.0\nradius = 0.02\njoint = \"universal\"\n";
    let overrides: Vec<String> =
        ["optimize.whole.control_points=30", "optimize.whole.switch_refinements=0"].map(String::from).to_vec();
    let p = Problem::from_toml(&text, "paper-with-tail.toml", &overrides).unwrap_or_else(|e| panic!("{e}"));
    let c = compare_models(&p, true, "test").unwrap_or_else(|e| panic!("{e}"));
    let keys: Vec<(&str, usize)> = c.rows.iter().map(|r| (r.key.as_str(), r.motors)).collect();
    assert_eq!(keys, [("universal", 2), ("no-twist", 2), ("spherical", 3), ("universal-tail", 4)]);
    let half = p.cat.model().front;
    let tail = p.cat.tail.expect("a tail").rod();
    for r in c.rows.iter().filter(|r| r.motors > 2) {
        let tree = if r.joint == Joint::Spherical {
            Cat::equal(half, Joint::Spherical).tree()
        } else {
            Cat::equal(half, Joint::Universal).tree_with_tail(&tail, Joint::Universal)
        };
        assert_beyond_row(r, &tree);
        let v = r.rapier.as_ref().unwrap_or_else(|| panic!("{}: not verified", r.key));
        assert_eq!(v.status, Status::Verified, "{}: {}", r.key, v.verdict);
    }
    assert_eq!(c.cheapest.as_deref(), Some("universal-tail"), "{}", c.to_markdown());
    // The library schedule with the twist held at zero is the no-twist joint's motion (DESIGN.md
    // §10): the same flip, and a peak at least its two motors' (the third holds the twist).
    let schedule = |key: &str| c.rows.iter().find(|r| r.key == key).and_then(|r| r.schedule.clone()).expect(key);
    let (held, no_twist) = (schedule("spherical"), schedule("no-twist"));
    assert!((held.twist_deg - no_twist.twist_deg).abs() < 1e-8, "{held:?} against {no_twist:?}");
    assert!(held.peak_torque_nm >= no_twist.peak_torque_nm * (1.0 - 1e-5), "{held:?} against {no_twist:?}");
}

/// A row beyond two motors is its own model's optimum on `tree`, re-measured here by the general
/// core: its flip (to 1e-9 rad) and its peak (dense samples of every motor, 1e-3 relative: the
/// row's peak is refined between samples, so it may only be higher); it has a library schedule
/// (the problem's, the further coordinates held at zero).
fn assert_beyond_row(r: &ModelRow, tree: &Tree) {
    let (Some(o), Some(spline)) = (&r.optimum, &r.spline) else { panic!("{}: no optimum ({})", r.key, r.status) };
    let flip = models::flip_on(tree, &SplineShape(spline), &Vector3::zeros(), 1e-11);
    assert!((flip.twist.abs() - std::f64::consts::PI).abs() < 1e-9, "{}: twist {}", r.key, flip.twist);
    assert!(flip.swing < 1e-9, "{}: swing {}", r.key, flip.swing);
    assert!((flip.twist.to_degrees() - o.twist_deg).abs() < 1e-7, "{}: {} vs {}", r.key, flip.twist, o.twist_deg);
    let total = spline.duration();
    let sampled = (0..=20_000)
        .map(|k| spline.shape(total * k as f64 / 2e4))
        .flat_map(|shape| reduction::joint_torques(tree, &shape, &Vector3::zeros()).into_iter().flat_map(|l| l.tau))
        .fold(0.0, |m: f64, t| m.max(t.abs()));
    assert!(o.peak_torque_nm >= sampled * (1.0 - 1e-9), "{}: row {} below {sampled}", r.key, o.peak_torque_nm);
    assert!((o.peak_torque_nm - sampled) / sampled < 1e-3, "{}: row {} vs {sampled}", r.key, o.peak_torque_nm);
    assert!(r.schedule.is_some(), "{}: the library schedule held", r.key);
    // Its files: the model files and the schedule file, whose last row is the flip.
    let names: Vec<&str> = r.files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["model.urdf", "model.xml", "whole-optimum.json", "whole-optimum.csv"], "{}", r.key);
    let csv = &r.files[3].1;
    let header: Vec<&str> = csv.lines().next().expect("a header").split(',').collect();
    let last: Vec<&str> = csv.lines().last().expect("rows").split(',').collect();
    let twist: f64 = last[header.iter().position(|h| *h == "twist_deg").expect("twist_deg")].parse().expect("a number");
    assert!((twist - o.twist_deg).abs() < 1e-7, "{}: the file's last row {twist} against {}", r.key, o.twist_deg);
}

/// Issue 22: legs (`problems/legs.toml`: Kane and Scher's cat with a pair of legs on each half, a
/// hinge at the hips; coarse spline, one start): the cat with its legs is a row of its own, four
/// motors, re-measured by the general core on its tree ([`assert_beyond_row`]) and verified in
/// rapier's tree scene; its legs never swing past their fold (90°, parallel to the spine) on the
/// whole curve, and with them the cat needs a lower peak than without.
#[test]
fn a_cat_with_legs_is_planned_within_the_fold_and_verified() {
    let p = preset("legs", &COARSE);
    let c = compare_models(&p, true, "test").unwrap_or_else(|e| panic!("{e}"));
    let keys: Vec<(&str, usize)> = c.rows.iter().map(|r| (r.key.as_str(), r.motors)).collect();
    assert_eq!(keys, [("universal", 2), ("no-twist", 2), ("spherical", 3), ("no-twist-legs", 4)]);
    let legs = &c.rows[3];
    let tree = p.cat.model().tree_with(&p.cat.appendages().expect("validated"));
    assert_eq!(tree.links().iter().map(|l| l.joint).collect::<Vec<_>>(), [Joint::NoTwist, Joint::Hinge, Joint::Hinge]);
    assert_beyond_row(legs, &tree);
    let v = legs.rapier.as_ref().unwrap_or_else(|| panic!("not verified"));
    assert_eq!(v.status, Status::Verified, "{}", v.verdict);
    let spline = legs.spline.as_ref().expect("an optimum");
    let fold = catflip::model::cat::LEG_FOLD_LIMIT_DEG.to_radians();
    let widest = (0..=20_000)
        .map(|k| spline.shape(spline.duration() * k as f64 / 2e4))
        .flat_map(|s| [s.q[2], s.q[3]])
        .fold(0.0, |m: f64, q| m.max(q.abs()));
    assert!(widest <= fold * (1.0 + 1e-12), "the legs swing to {}°", widest.to_degrees());
    let peak =
        |key: &str| c.rows.iter().find(|r| r.key == key).and_then(|r| r.optimum.as_ref()).expect(key).peak_torque_nm;
    assert!(peak("no-twist-legs") < peak("no-twist"), "{}", c.to_markdown());
}

/// Issue 22: a cat with a tail and legs (six coordinates: `problems/legs.toml` with the tail of
/// `problems/tail.toml`; coarse spline, one start) is planned and re-measured as the others: its
/// legs within their fold, and the flip exact to 1e-9 rad; and verified in rapier's tree scene.
/// This optimum starts at its peak torque, where the servo's first steps overshoot (5.7 % on the
/// cat joint's first motor at 0.2 ms), and a servo ripple lifts the cat joint's motors above the
/// tail's, which peaks in the plan: measured with those first steps in and extrapolated as the
/// largest of the motors, rapier said "not verified" (3.7 % off) and then "inconclusive" (2.0 %).
#[test]
fn a_cat_with_a_tail_and_legs_is_planned_remeasured_and_verified() {
    let text = std::fs::read_to_string("problems/legs.toml").expect("the legs problem")
        + "\n[cat.tail]\nmass = 0.2\nlength = 1.0\nradius = 0.02\njoint = \"universal\"\n";
    let overrides: Vec<String> = COARSE.map(String::from).to_vec();
    let p = Problem::from_toml(&text, "legs-and-tail.toml", &overrides).unwrap_or_else(|e| panic!("{e}"));
    let c = compare_models(&p, true, "test").unwrap_or_else(|e| panic!("{e}"));
    let row = c.rows.iter().find(|r| r.key == "no-twist-tail-legs").unwrap_or_else(|| panic!("{}", c.to_markdown()));
    assert_eq!(row.motors, 6);
    let v = row.rapier.as_ref().unwrap_or_else(|| panic!("no rapier verification\n{}", c.to_markdown()));
    assert_eq!(v.status, Status::Verified, "{}\n{}", v.verdict, c.to_markdown());
    assert!(row.cat.ends_with("2.6 kg in all"), "{}", row.cat);
    assert_beyond_row(row, &p.cat.model().tree_with(&p.cat.appendages().expect("validated")));
    let spline = row.spline.as_ref().expect("an optimum");
    let fold = catflip::model::cat::LEG_FOLD_LIMIT_DEG.to_radians();
    for curve in &spline.coefficients[4..] {
        assert!(curve.iter().all(|c| c.abs() <= fold), "a leg's control point past its fold: {curve:?}");
    }
}
