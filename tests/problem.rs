//! Problem files: loading, overrides, and one clear error per class of bad input.
#![deny(clippy::float_cmp)]

use catflip::problem::manoeuvre::{BendPath, Circulation, ProfileKind};
use catflip::problem::{Problem, ProblemError};

const PAPER: &str = include_str!("../problems/paper.toml");

fn error_of(text: &str, overrides: &[&str]) -> String {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    match Problem::from_toml(text, "test.toml", &o) {
        Ok(p) => panic!("expected an error, loaded {p:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn shipped_problems_load_and_round_trip() {
    for path in [
        "problems/paper.toml",
        "problems/script-defaults.toml",
        "problems/tail.toml",
        "problems/tail-robot.toml",
        "problems/legs.toml",
        "problems/real-cat.toml",
    ] {
        let p = Problem::load(std::path::Path::new(path), &[]).expect(path);
        let text = toml::to_string(&p).expect("serialises");
        let back = Problem::from_toml(&text, path, &[]).expect("round trip");
        assert_eq!(p, back, "{path} does not round-trip through serde");
    }
}

/// `problems/real-cat.toml` is the cat its comments cite: the mean of seven adult cats of
/// Rahmati et al. 2024 (J. Physiol., doi:10.1113/JP287448; the authors' `MotionData.mat`,
/// `GenericCat`: body 3.2014 kg, head and neck 0.410103 kg, trunk 1.751181 kg, one forelimb's
/// segments 0.198312 kg and 0.271271 m, one hindlimb's 0.238558 kg and 0.267286 m), split and
/// shaped as the file says it assumes (each half and each pair of legs of water's density, the
/// halves with Kane and Scher's ratio of axial to transverse inertia, 1/4); the sizes are
/// rounded to four decimals, hence the tolerances.
#[test]
fn real_cat_is_the_cited_cat() {
    let p = Problem::load(std::path::Path::new("problems/real-cat.toml"), &[]).expect("loads");
    // The paper's worked example's θ = 45° is outside the paper's own stability range, as on paper.toml.
    let warnings = p.warnings();
    assert!(warnings.len() == 1 && warnings[0].starts_with("manoeuvre.theta_deg = 45 < 90"), "{warnings:?}");
    let (body, head, trunk) = (3.2014286, 0.410103, 1.7511814);
    let (fore, hind) = (2.0 * 0.1983124, 2.0 * 0.2385583);
    let cat = p.cat.model();
    let [fore_pair, hind_pair] = p.cat.legs.expect("legs").pairs().expect("both pairs whole");
    let close = |what: &str, got: f64, want: f64, tol: f64| {
        assert!((got - want).abs() <= tol, "{what}: {got} against {want}");
    };
    close("front half", cat.front.mass, head + 0.5 * trunk, 1e-4);
    close("rear half", cat.rear.mass, body - head - 0.5 * trunk - fore - hind, 1e-4);
    close("the forelimbs", fore_pair.mass, fore, 1e-4);
    close("the hindlimbs", hind_pair.mass, hind, 1e-4);
    close("a forelimb's length", fore_pair.length, 0.2712714, 1e-4);
    close("a hindlimb's length", hind_pair.length, 0.2672857, 1e-4);
    close("the whole cat", cat.front.mass + cat.rear.mass + fore_pair.mass + hind_pair.mass, body, 5e-4);
    for (name, half) in [("front", cat.front), ("rear", cat.rear)] {
        close(&format!("{name} half's axial over transverse inertia"), half.axial() / half.transverse(), 0.25, 2e-3);
        let volume = std::f64::consts::PI * half.radius.powi(2) * half.length;
        close(&format!("{name} half's density, kg/m³"), half.mass / volume, 1000.0, 5.0);
    }
    for (name, legs) in [("fore", fore_pair), ("hind", hind_pair)] {
        let volume = std::f64::consts::PI * legs.radius.powi(2) * legs.length;
        close(&format!("the {name}limbs' density, kg/m³"), legs.mass / volume, 1000.0, 5.0);
    }
}

#[test]
fn paper_problem_is_the_worked_example() {
    let p = Problem::from_toml(PAPER, "paper.toml", &[]).expect("loads");
    assert_eq!(p.name, "paper");
    assert_eq!(p.manoeuvre.profile, ProfileKind::PaperCosine);
    assert_eq!(p.manoeuvre.circulation, Circulation::Paper);
    assert_eq!(p.manoeuvre.bend_path, BendPath::JointCircle);
    assert!((p.manoeuvre.theta() - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
}

#[test]
fn overrides_apply_with_toml_values_and_bare_words() {
    let o = [
        "manoeuvre.profile=poly-4567".to_string(),
        "manoeuvre.circulation=3.5".to_string(),
        "manoeuvre.phases=[0.1, 0.8, 0.1]".to_string(),
        "cat.mass = 2".to_string(),
    ];
    let p = Problem::from_toml(PAPER, "paper.toml", &o).expect("loads");
    assert_eq!(p.manoeuvre.profile, ProfileKind::Poly4567);
    assert_eq!(p.manoeuvre.circulation, Circulation::Angle(3.5));
    assert!((p.manoeuvre.phases[1] - 0.8).abs() < 1e-15);
    assert!((p.cat.mass - 2.0).abs() < 1e-15);
}

#[test]
fn every_profile_name_parses() {
    for kind in ProfileKind::ALL {
        let p = Problem::from_toml(PAPER, "paper.toml", &[format!("manoeuvre.profile={}", kind.name())])
            .unwrap_or_else(|e| panic!("{}: {e}", kind.name()));
        assert_eq!(p.manoeuvre.profile, kind);
    }
}

#[test]
fn non_finite_or_non_positive_sizes_are_refused() {
    assert_eq!(error_of(PAPER, &["cat.mass=0"]), "cat.mass = 0: must be positive");
    assert_eq!(error_of(PAPER, &["cat.length=-1"]), "cat.length = -1: must be positive");
    assert_eq!(error_of(PAPER, &["cat.radius=nan"]), "cat.radius = NaN: must be a finite number");
    assert_eq!(error_of(PAPER, &["drop.height=inf"]), "drop.height = inf: must be a finite number");
    assert_eq!(error_of(PAPER, &["drop.gravity=-9.8"]), "drop.gravity = -9.8: must be positive");
}

#[test]
fn theta_outside_its_range_is_refused() {
    let msg = "must lie in (0, 180] degrees (180 is a straight cat)";
    assert_eq!(error_of(PAPER, &["manoeuvre.theta_deg=0"]), format!("manoeuvre.theta_deg = 0: {msg}"));
    assert_eq!(error_of(PAPER, &["manoeuvre.theta_deg=180.5"]), format!("manoeuvre.theta_deg = 180.5: {msg}"));
    assert_eq!(error_of(PAPER, &["manoeuvre.theta_deg=nan"]), "manoeuvre.theta_deg = NaN: must be a finite number");
}

#[test]
fn bad_phases_are_refused() {
    assert_eq!(
        error_of(PAPER, &["manoeuvre.phases=[0.5, 0.6, 0.2]"]),
        "manoeuvre.phases = [0.5, 0.6, 0.2]: fractions must sum to 1 (they sum to 1.3)"
    );
    assert_eq!(
        error_of(PAPER, &["manoeuvre.phases=[-0.2, 1.0, 0.2]"]),
        "manoeuvre.phases[0] = -0.2: each phase must take a positive fraction of the fall"
    );
    assert!(error_of(PAPER, &["manoeuvre.phases=[0.5, 0.5]"]).contains("manoeuvre.phases"));
}

#[test]
fn unknown_keys_and_profiles_are_refused() {
    assert_eq!(
        error_of(PAPER, &["cat.colour=3"]),
        "--set cat.colour=3: unknown field `colour`, expected one of `mass`, `length`, `radius`, `joint`, `front`, `rear`, `tail`, `legs` in `cat`"
    );
    let e = error_of(PAPER, &["manoeuvre.profile=wobble"]);
    assert!(
        e.starts_with("--set manoeuvre.profile=wobble: unknown variant `wobble`, expected one of `paper-cosine`"),
        "{e}"
    );
    assert!(e.ends_with("in `manoeuvre.profile`"), "{e}");
    assert_eq!(
        error_of(PAPER, &["manoeuvre.circulation=lots"]),
        "--set manoeuvre.circulation=lots: invalid value: string \"lots\", expected \"paper\", \"calibrated\" or a number of radians in `manoeuvre.circulation`"
    );
    assert_eq!(
        error_of(PAPER, &["speed=3"]),
        "--set speed=3: unknown field `speed`, expected one of `name`, `cat`, `drop`, `manoeuvre`, `actuator`, `exact`, `rapier`, `optimize`, `robust`"
    );
}

#[test]
fn malformed_toml_names_its_line() {
    assert_eq!(
        error_of("name = \"x\"\n[cat\nmass = 1\n", &[]),
        "problem file test.toml, line 2: unclosed table, expected `]`"
    );
    assert_eq!(
        error_of("[cat]\nmass = \"heavy\"\n", &[]),
        "problem file test.toml: invalid type: string \"heavy\", expected a number in `cat.mass`"
    );
}

#[test]
fn malformed_override_is_refused() {
    assert_eq!(error_of(PAPER, &["cat.mass"]), "--set cat.mass: expected key=value");
    assert_eq!(error_of(PAPER, &["name.first=3"]), "--set name.first=3: `name` is not a section");
}

#[test]
fn cone_near_gimbal_lock_is_refused() {
    let e = error_of(PAPER, &["manoeuvre.bend_path=cone", "manoeuvre.theta_deg=92"]);
    assert!(e.starts_with("manoeuvre.theta_deg = 92: the cone path meets gimbal lock"), "{e}");
    assert!(
        Problem::from_toml(PAPER, "t", &["manoeuvre.bend_path=cone".into(), "manoeuvre.theta_deg=60".into()]).is_ok()
    );
}

#[test]
fn unreadable_file_is_an_io_error() {
    let e = Problem::load(std::path::Path::new("problems/does-not-exist.toml"), &[]);
    assert!(matches!(e, Err(ProblemError::Io { .. })), "{e:?}");
}

#[test]
fn bad_name_is_refused() {
    assert_eq!(
        error_of(PAPER, &["name=\"../etc\""]),
        "name = ../etc: must be non-empty and use only letters, digits, '-' and '_' (it names a results folder)"
    );
}

#[test]
fn circulations_that_cannot_turn_the_cat_are_refused() {
    assert_eq!(
        error_of(PAPER, &["manoeuvre.circulation=0"]),
        "manoeuvre.circulation = 0: must be non-zero: without circulation the cat does not twist"
    );
    assert_eq!(
        error_of(PAPER, &["manoeuvre.circulation=2e3"]),
        "manoeuvre.circulation = 2000: must be at most 1000 rad in magnitude (about 160 turns of the bend)"
    );
    assert_eq!(
        error_of(PAPER, &["manoeuvre.theta_deg=180", "manoeuvre.circulation=\"calibrated\""]),
        "manoeuvre.circulation = \"calibrated\": a straight cat (theta_deg = 180) has no bend to circulate, so no circulation turns it"
    );
}

#[test]
fn paper_circulation_of_a_nearly_straight_cat_is_refused() {
    // C → 0 as θ → 180°, so π/C grows without bound.
    let p = Problem::from_toml(PAPER, "t", &["manoeuvre.theta_deg=179.99999".into()]).expect("loads");
    let e = catflip::schedule::paper_circulation(&p.cat.half(), p.manoeuvre.theta()).expect_err("too large");
    assert!(e.to_string().contains("exceeds the 1000 rad"), "{e}");
}

#[test]
fn readme_problem_file_shows_the_defaults() {
    // The README's annotated problem file lists every section with its default values; it must
    // load and equal `Problem::default()`, so the README cannot drift from the code.
    let readme = include_str!("../README.md");
    let start = readme.find("## Problem files").expect("section");
    let block = &readme[start..];
    let open = block.find("```toml\n").expect("toml block") + "```toml\n".len();
    let close = open + block[open..].find("```").expect("block end");
    let p = Problem::from_toml(&block[open..close], "README.md", &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(p, Problem::default());
}

/// `[cat.tail]` (issue 22): each bad number names its field, the tail's joint has two motors, and
/// a missing or unknown field is named.
#[test]
fn a_bad_tail_is_refused_naming_its_field() {
    let tail = |body: &str| format!("{PAPER}\n[cat.tail]\n{body}\n");
    let good = "mass = 0.2\nlength = 1.0\nradius = 0.02";
    let p = Problem::from_toml(&tail(good), "test.toml", &[]).expect("a valid tail");
    assert_eq!(p.cat.tail.map(|t| t.joint), Some(catflip::model::Joint::Universal), "the joint defaults to universal");
    for (body, field) in [
        ("mass = -0.2\nlength = 1.0\nradius = 0.02", "cat.tail.mass"),
        ("mass = 0.2\nlength = 0.0\nradius = 0.02", "cat.tail.length"),
        ("mass = 0.2\nlength = 1.0\nradius = 5.0", "cat.tail.radius"),
        ("mass = 0.2\nlength = 1.0\nradius = 0.02\njoint = \"spherical\"", "cat.tail.joint"),
    ] {
        let e = error_of(&tail(body), &[]);
        assert!(e.starts_with(field), "{body:?}: {e}");
    }
    let e = error_of(&tail("mass = 0.2\nlength = 1.0"), &[]);
    assert!(e.contains("missing field `radius`") && e.contains("cat.tail"), "{e}");
    let e = error_of(&tail(&format!("{good}\ncolour = 1")), &[]);
    assert!(e.contains("unknown field `colour`"), "{e}");
}

/// `[cat.legs]` (issue 22): each bad number names its field; a hinge is an appendage's joint, the
/// tail's (one motor) but never the halves'.
#[test]
fn bad_legs_and_a_hinge_between_the_halves_are_refused_naming_their_field() {
    let legs = |body: &str| format!("{PAPER}\n[cat.legs]\n{body}\n");
    let p = Problem::from_toml(&legs("mass = 0.2\nlength = 0.45\nradius = 0.03"), "test.toml", &[]).expect("legs");
    assert_eq!(p.cat.appendages().expect("validated").dof(), 2, "one hinge a pair");
    for (body, field) in [
        ("mass = 0.0\nlength = 0.45\nradius = 0.03", "cat.legs.mass"),
        ("mass = 0.2\nlength = -1.0\nradius = 0.03", "cat.legs.length"),
        ("mass = 0.2\nlength = 0.45\nradius = 0.9", "cat.legs.radius"),
    ] {
        let e = error_of(&legs(body), &[]);
        assert!(e.starts_with(field), "{body:?}: {e}");
    }
    let e = error_of(&legs("mass = 0.2\nlength = 0.45\nradius = 0.03\njoint = \"hinge\""), &[]);
    assert!(e.contains("unknown field `joint`"), "{e}");
    let e = error_of(PAPER, &["cat.joint=\"hinge\""]);
    assert!(e.starts_with("cat.joint = \"hinge\": a hinge is an appendage's joint"), "{e}");
    // A pair of its own: each field it leaves out is [cat.legs]'s, each bad one named as written.
    let own = legs("mass = 0.2\nlength = 0.45\nradius = 0.03\n[cat.legs.rear]\nmass = 0.3");
    let p = Problem::from_toml(&own, "test.toml", &[]).expect("a rear pair of its own");
    let [front, rear] = p.cat.legs.expect("legs").pairs().expect("both pairs whole");
    assert_eq!((front.mass, rear.mass, rear.length, rear.radius), (0.2, 0.3, 0.45, 0.03));
    assert_eq!(p.cat.appendages().expect("validated").legs, Some([front, rear]));
    let e = error_of(&legs("mass = 0.2\nlength = 0.45\nradius = 0.03\n[cat.legs.front]\nlength = 0.0"), &[]);
    assert!(e.starts_with("cat.legs.front.length"), "{e}");
    let e = error_of(&legs("mass = 0.2\nlength = 0.45\nradius = 0.03\n[cat.legs.rear]\nradius = 0.9"), &[]);
    assert!(e.starts_with("cat.legs.rear.radius"), "{e}");
    let e = error_of(&legs("mass = 0.2\nlength = 0.45\nradius = 0.03\n[cat.legs.hind]\nmass = 0.3"), &[]);
    assert!(e.contains("unknown field `hind`"), "{e}");
    let hinged = format!("{PAPER}\n[cat.tail]\nmass = 0.2\nlength = 1.0\nradius = 0.02\njoint = \"hinge\"\n");
    let p = Problem::from_toml(&hinged, "test.toml", &[]).expect("a tail on a hinge");
    assert_eq!(p.cat.appendages().expect("validated").dof(), 1);
}

/// `[cat.legs]` gives what both pairs share and may give nothing when `[cat.legs.front]` and
/// `[cat.legs.rear]` give everything; a number neither a pair's section nor `[cat.legs]` gives is
/// refused where the user would write it; a number no pair uses is warned of; and the problem
/// written back loads the same.
#[test]
fn each_pair_of_legs_takes_its_numbers_from_its_section_or_the_shorthand() {
    let legs = |body: &str| format!("{PAPER}\n[cat.legs]\n{body}\n");
    let pairs = "[cat.legs.front]\nmass = 0.2\nlength = 0.45\nradius = 0.03\n[cat.legs.rear]\nmass = 0.3\nlength = 0.4\nradius = 0.035";
    let p = Problem::from_user_text(&legs(pairs), "test.toml", &[]).expect("two pairs of their own, no shorthand");
    let [front, rear] = p.cat.appendages().expect("validated").legs.expect("legs");
    assert_eq!((front.mass, front.length, front.radius), (0.2, 0.45, 0.03));
    assert_eq!((rear.mass, rear.length, rear.radius), (0.3, 0.4, 0.035));
    assert!(p.warnings().iter().all(|w| !w.contains("cat.legs")), "{:?}", p.warnings());
    let written = toml::to_string(&p).expect("TOML");
    let again = Problem::from_user_text(&written, "written.toml", &[]).expect("loads back");
    assert!(again.warnings().iter().all(|w| !w.contains("cat.legs")), "{:?}\n{written}", again.warnings());
    assert_eq!(again.cat, p.cat);
    // What the pairs share in [cat.legs], the rest their own.
    let shared =
        "length = 0.45\n[cat.legs.front]\nmass = 0.2\nradius = 0.03\n[cat.legs.rear]\nmass = 0.3\nradius = 0.035";
    let p = Problem::from_toml(&legs(shared), "test.toml", &[]).expect("the length shared");
    let [front, rear] = p.cat.appendages().expect("validated").legs.expect("legs");
    assert_eq!((front.length, rear.length, rear.mass), (0.45, 0.45, 0.3));
    // A number neither gives: named in the pair's section when it has one, else in [cat.legs].
    let e = error_of(&legs("mass = 0.2\nlength = 0.45\n[cat.legs.rear]\nmass = 0.3\nradius = 0.03"), &[]);
    assert!(e.starts_with("cat.legs.radius = (not given): the front pair has no [cat.legs.front] to give it"), "{e}");
    let e =
        error_of(&legs("mass = 0.2\nlength = 0.45\n[cat.legs.front]\nmass = 0.3\n[cat.legs.rear]\nradius = 0.03"), &[]);
    assert!(
        e.starts_with("cat.legs.front.radius = (not given): given neither in [cat.legs.front] nor in [cat.legs]"),
        "{e}"
    );
    // Missing for both pairs: the one line that supplies both is named.
    let e =
        error_of(&legs("mass = 0.2\nlength = 0.45\n[cat.legs.front]\nmass = 0.3\n[cat.legs.rear]\nmass = 0.3"), &[]);
    assert!(e.starts_with("cat.legs.radius = (not given): neither pair's section gives it, nor [cat.legs]"), "{e}");
    // A [cat.legs] number is checked though both pairs replace it.
    let e = error_of(&legs(&format!("mass = -1.0\n{pairs}")), &[]);
    assert!(e.starts_with("cat.legs.mass = -1"), "{e}");
    let e = error_of(&legs(&format!("radius = 0.0\n{pairs}")), &[]);
    assert!(e.starts_with("cat.legs.radius = 0"), "{e}");
    // A bad number is blamed where it is written, though the other pair's section exists.
    let e = error_of(&legs("mass = 0.2\nlength = -0.45\nradius = 0.03\n[cat.legs.rear]\nmass = 0.3"), &[]);
    assert!(e.starts_with("cat.legs.length"), "{e}");
    let e =
        error_of(&legs("mass = 0.2\nlength = 0.45\nradius = 0.03\n[cat.legs.front]\nmass = 0.3\nradius = 0.9"), &[]);
    assert!(e.starts_with("cat.legs.front.radius") && e.contains("times cat.legs.length = 0.45 m"), "{e}");
    // A shorthand number both pairs replace is said, the others not.
    let p = Problem::from_user_text(&legs(&format!("mass = 0.25\nlength = 0.5\n{pairs}")), "test.toml", &[])
        .expect("loads");
    let unused: Vec<String> = p.warnings().into_iter().filter(|w| w.contains("used by neither pair")).collect();
    assert_eq!(unused.len(), 2, "{unused:?}");
    assert!(unused[0].starts_with("cat.legs.mass is used by neither pair") && unused[1].starts_with("cat.legs.length"));
}

/// A command for the paper's cat alone (a sweep, the audit) refuses `[cat.tail]` naming it and
/// saying where a tail is compared, not as if it were the paper's cat with another joint.
#[test]
fn a_tail_is_refused_where_the_papers_cat_is_required() {
    let text = format!("{PAPER}\n[cat.tail]\nmass = 0.2\nlength = 1.0\nradius = 0.02\n");
    let p = Problem::from_toml(&text, "test.toml", &[]).expect("a valid tail");
    let e = p.require_paper_cat("a sweep").err().map(|e| e.to_string()).unwrap_or_default();
    assert!(e.starts_with("cat.tail = { mass = 0.2, length = 1, radius = 0.02, joint = \"universal\" }: "), "{e}");
    assert!(e.contains("`catflip compare-models` only"), "{e}");
}

/// A robustness study whose spreads would draw cats the loader refuses is refused by the
/// commands that run it, naming the spread (a review's radius 0.5 m on a 1 m half with
/// `length_pct = 90` drew halves of 0.1 m and ran them without a word); the problem itself loads
/// (a cat near a bound is not refused by a study it never runs), and spreads whose every draw
/// is a valid cat pass.
#[test]
fn robust_spreads_that_draw_refused_cats_are_refused() {
    let draws = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let p = Problem::from_toml(PAPER, "paper.toml", &sets).unwrap_or_else(|e| panic!("{sets:?} loads: {e}"));
        p.validate_robust_draws().map_err(|e| e.to_string())
    };
    let e = draws(&["cat.radius=0.5", "robust.length_pct=90.0"]).expect_err("0.1 m halves of radius 0.5 m");
    assert!(e.starts_with("robust.length_pct = 90: the study would draw cats the problem refuses"), "{e}");
    assert!(e.contains("0.1 m and radius 0.5 m") && e.contains("cat.radius = 0.5: must lie in"), "{e}");
    let e = draws(&["cat.radius=0.9", "robust.radius_pct=20.0"]).expect_err("radius beyond the length");
    assert!(e.starts_with("robust.radius_pct = 20:"), "{e}");
    // The spread that fails alone is named, whatever else is spread; a combination names both.
    let e = draws(&["cat.radius=0.9", "robust.radius_pct=20.0", "robust.length_pct=5.0"]).expect_err("radius");
    assert!(e.starts_with("robust.radius_pct = 20:"), "{e}");
    let e = draws(&["cat.radius=0.8", "robust.radius_pct=10.0", "robust.length_pct=15.0"]).expect_err("both");
    assert!(e.starts_with("robust.length_pct and robust.radius_pct = 15 and 10:"), "{e}");
    let e = draws(&["cat.mass=9.5e5", "robust.mass_pct=10.0"]).expect_err("mass beyond its bound");
    assert!(e.starts_with("robust.mass_pct = 10:") && e.contains("cat.mass = 1.045e6: must lie in"), "{e}");
    for ok in [&["cat.radius=0.5", "robust.length_pct=40.0"][..], &["robust.radius_pct=50.0", "robust.length_pct=50.0"]]
    {
        draws(ok).unwrap_or_else(|e| panic!("{ok:?}: {e}"));
    }
}
