//! Every number of a problem has a range (issue 9, "NaN or no end, exit 0"): inside it the exact
//! engine's answer is finite, outside it the problem is refused with the field and the range.
#![deny(clippy::float_cmp)]

use catflip::engines::resolved::Resolved;
use catflip::engines::Engine;
use catflip::problem::Problem;
use catflip::report::simulate::simulate;

fn load(overrides: &[&str]) -> Result<Problem, String> {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Problem::from_toml("", "test.toml", &o).map_err(|e| e.to_string())
}

fn error_of(overrides: &[&str]) -> String {
    match load(overrides) {
        Ok(p) => panic!("{overrides:?}: expected an error, loaded {p:?}"),
        Err(e) => e,
    }
}

/// Loads and runs the exact engine; every number it reports must be finite.
fn finite_at(overrides: &[&str]) {
    let p = load(overrides).unwrap_or_else(|e| panic!("{overrides:?} refused: {e}"));
    let resolved = Resolved::new(&p).unwrap_or_else(|e| panic!("{overrides:?}: {e}"));
    let r = simulate(&resolved, Engine::Exact).unwrap_or_else(|e| panic!("{overrides:?}: {e}"));
    let peaks = r.peak_torque_nm;
    let all = [r.figures.twist_deg, r.figures.swing_deg, r.circulation_rad, r.figures.momentum_max, peaks.max]
        .into_iter()
        .chain(peaks.bend)
        .chain(peaks.twist)
        .chain(peaks.unbend);
    for v in all {
        assert!(v.is_finite(), "{overrides:?}: non-finite result in {r:?}");
    }
    assert_eq!(r.figures.converged, Some(true), "{overrides:?}: not converged: {r:?}");
}

#[test]
fn boundary_values_give_finite_answers() {
    for o in [
        &["cat.mass=1e-6"][..],
        &["cat.mass=1e6"],
        &["cat.length=1e-3", "cat.radius=1e-4"],
        &["cat.length=1e3", "cat.radius=100"],
        &["cat.radius=1e-4"],
        &["cat.radius=1.0"],
        &["drop.height=0.0005", "drop.gravity=10"],
        &["drop.height=50000", "drop.gravity=10"],
        &["drop.height=1e-4", "drop.gravity=1.9"],
        &["drop.height=1e5", "drop.gravity=1000"],
        &["manoeuvre.theta_deg=1"],
        &["manoeuvre.theta_deg=180", "manoeuvre.circulation=1.0"],
        &["manoeuvre.phases=[1e-3, 0.998, 1e-3]"],
        &["manoeuvre.phases=[0.4995, 1e-3, 0.4995]"],
        &["cat.mass=1e-6", "cat.length=1e-3", "cat.radius=1e-7", "drop.height=0.0005", "drop.gravity=10"],
        &["cat.mass=1e6", "cat.length=1e3", "cat.radius=1e3", "drop.height=50000", "drop.gravity=10"],
    ] {
        finite_at(o);
    }
}

#[test]
fn sizes_beyond_their_range_are_refused_with_the_range() {
    assert_eq!(error_of(&["cat.mass=1e-300"]), "cat.mass = 1e-300: must lie in [1e-6, 1e6] kg");
    assert_eq!(error_of(&["cat.mass=5e-324"]), "cat.mass = 4.94065645841247e-324: must lie in [1e-6, 1e6] kg");
    assert_eq!(error_of(&["cat.mass=1e300"]), "cat.mass = 1e300: must lie in [1e-6, 1e6] kg");
    assert_eq!(error_of(&["cat.mass=1.1e6"]), "cat.mass = 1.1e6: must lie in [1e-6, 1e6] kg");
    assert_eq!(error_of(&["cat.length=1e300"]), "cat.length = 1e300: must lie in [0.001, 1000] m");
    assert_eq!(error_of(&["cat.length=9e-4"]), "cat.length = 9e-4: must lie in [0.001, 1000] m");
    assert_eq!(
        error_of(&["cat.radius=1e-300"]),
        "cat.radius = 1e-300: must lie in [1e-4, 1] m, [1e-4, 1] times cat.length = 1 m"
    );
    assert_eq!(
        error_of(&["cat.radius=2.5", "cat.length=2"]),
        "cat.radius = 2.5: must lie in [2e-4, 2] m, [1e-4, 1] times cat.length = 2 m"
    );
    assert_eq!(error_of(&["drop.height=1e300"]), "drop.height = 1e300: must lie in [1e-4, 100000] m");
    assert_eq!(error_of(&["drop.height=5e-324"]), "drop.height = 4.94065645841247e-324: must lie in [1e-4, 100000] m");
    assert_eq!(error_of(&["drop.gravity=1e300"]), "drop.gravity = 1e300: must lie in [0.001, 1000] m/s²");
    assert_eq!(error_of(&["drop.gravity=1e-300"]), "drop.gravity = 1e-300: must lie in [0.001, 1000] m/s²");
}

#[test]
fn a_fall_too_short_or_too_long_is_refused() {
    assert_eq!(
        error_of(&["drop.height=1e-4", "drop.gravity=9.8"]),
        "drop.height = 1e-4: with drop.gravity = 9.8 m/s² the fall takes 0.00451754 s; the fall time √(2h/g) must lie in [0.01, 100] s"
    );
    assert_eq!(
        error_of(&["drop.height=1e5", "drop.gravity=0.01"]),
        "drop.height = 100000: with drop.gravity = 0.01 m/s² the fall takes 4472.14 s; the fall time √(2h/g) must lie in [0.01, 100] s"
    );
}

#[test]
fn angles_and_phases_beyond_their_range_are_refused() {
    assert_eq!(
        error_of(&["manoeuvre.theta_deg=0.5"]),
        "manoeuvre.theta_deg = 0.5: must lie in [1, 180] degrees: the halves would fold onto each other"
    );
    assert_eq!(
        error_of(&["manoeuvre.phases=[1e-300, 0.5, 0.5]"]),
        "manoeuvre.phases[0] = 1e-300: each phase must take at least 0.001 of the fall"
    );
    assert_eq!(
        error_of(&["manoeuvre.phases=[0.4996, 9e-4, 0.4995]"]),
        "manoeuvre.phases[1] = 9e-4: each phase must take at least 0.001 of the fall"
    );
    assert_eq!(
        error_of(&["manoeuvre.phases=[0.2, 0.6, 0.3]"]),
        "manoeuvre.phases = [0.2, 0.6, 0.3]: fractions must sum to 1 (they sum to 1.1)"
    );
}

#[test]
fn every_count_has_a_maximum() {
    assert_eq!(
        error_of(&["exact.torque_samples=9223372036854775807"]),
        "exact.torque_samples = 9223372036854775807: must lie in [8, 100000]"
    );
    assert_eq!(error_of(&["exact.torque_samples=100001"]), "exact.torque_samples = 100001: must lie in [8, 100000]");
    assert!(load(&["exact.torque_samples=100000"]).is_ok());
    assert_eq!(error_of(&["optimize.nodes=1001"]), "optimize.nodes = 1001: must lie in [4, 1000]");
    assert_eq!(
        error_of(&["optimize.nodes=9223372036854775807"]),
        "optimize.nodes = 9223372036854775807: must lie in [4, 1000]"
    );
    assert!(load(&["optimize.nodes=1000"]).is_ok());
    assert_eq!(
        error_of(&["optimize.refine_iterations=1001"]),
        "optimize.refine_iterations = 1001: must lie in [0, 1000]"
    );
    assert!(load(&["optimize.refine_iterations=1000"]).is_ok());
    assert_eq!(error_of(&["optimize.smoothness=1e300"]), "optimize.smoothness = 1e300: must be at most 1e6");
    assert_eq!(error_of(&["exact.tolerance=0.1"]), "exact.tolerance = 0.1: must lie in [1e-14, 0.01] rad");
}
