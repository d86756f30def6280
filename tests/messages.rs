//! Errors name what the user wrote: the field, the `--set`, the flag; never a Rust type name
//! (issue 9, "Messages").
#![deny(clippy::float_cmp)]

use std::process::Command;

use catflip::problem::Problem;

fn catflip(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_catflip")).args(args).output().expect("the binary runs");
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).trim().to_string())
}

/// The message with which `text` (as `test.toml`) and `overrides` are refused.
fn error_of(text: &str, overrides: &[&str]) -> String {
    let owned = overrides.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let refused = Problem::from_toml(text, "test.toml", &owned).err();
    refused.map(|e| e.to_string()).unwrap_or_else(|| panic!("{overrides:?} loaded"))
}

#[test]
fn a_bad_set_value_is_blamed_on_the_set_not_the_file() {
    assert_eq!(
        error_of("", &["cat.mass=abc"]),
        "--set cat.mass=abc: invalid type: string \"abc\", expected a number in `cat.mass`"
    );
    assert_eq!(
        error_of("", &["manoeuvre.profile=cycloidal", "optimize.nodes=1.5"]),
        "--set optimize.nodes=1.5: invalid type: floating point `1.5`, expected a whole number in `optimize.nodes`"
    );
    // The same value in the file is the file's.
    assert_eq!(
        error_of("[cat]\nmass = \"abc\"\n", &["cat.length=2"]),
        "problem file test.toml: invalid type: string \"abc\", expected a number in `cat.mass`"
    );
}

#[test]
fn sections_are_named_as_the_file_names_them() {
    assert_eq!(error_of("", &["cat=5"]), "--set cat=5: invalid type: integer `5`, expected the [cat] section in `cat`");
    assert_eq!(
        error_of("drop = 3\n", &[]),
        "problem file test.toml: invalid type: integer `3`, expected the [drop] section in `drop`"
    );
    for section in ["manoeuvre", "exact", "rapier", "optimize"] {
        let e = error_of(&format!("{section} = 1\n"), &[]);
        assert!(e.contains(&format!("expected the [{section}] section")), "{e}");
        assert!(!e.contains("struct"), "{e}");
    }
}

#[test]
fn cli_time_steps_are_checked_and_named() {
    let (code, err) = catflip(&["simulate", "problems/paper.toml", "--engine", "rapier", "--dt", "nan"]);
    assert_eq!((code, err.as_str()), (1, "error: --dt NaN: must be a finite, positive time step in seconds"));
    let (code, err) = catflip(&["simulate", "problems/paper.toml", "--engine", "rapier", "--dt=-1e300"]);
    assert_eq!((code, err.as_str()), (1, "error: --dt -1e300: must be a finite, positive time step in seconds"));
    let (code, err) = catflip(&["simulate", "problems/paper.toml", "--dt", "0"]);
    assert_eq!(
        (code, err.as_str()),
        (
            1,
            "error: --dt 0: --dt is the time step of --engine rapier; the exact engine chooses its own steps (exact.tolerance)"
        )
    );
}

#[test]
fn a_straight_cat_optimises_without_internal_names() {
    // The bend of a straight cat does not move: before, its refinement was handed a trust radius
    // of zero ("trust_radius = 0: must be positive").
    let mut p = Problem::default();
    p.manoeuvre.theta_deg = 180.0;
    p.manoeuvre.circulation = catflip::problem::Circulation::Angle(1.0);
    let resolved = catflip::engines::circulation::Resolved::new(&p).expect("a given circulation resolves");
    if let Err(e) = catflip::optimize::optimize(&resolved) {
        assert!(!e.to_string().contains('_'), "internal name in {e}");
    }
}

#[test]
fn the_calibration_status_reads_in_words() {
    assert_eq!(
        catflip::numeric::roots::RootStatus::NotAtRoot.to_string(),
        "the bracket closed on a jump, not on a root"
    );
}

#[test]
fn echoed_values_are_shortened() {
    assert_eq!(error_of("", &["cat.mass=1e300"]), "cat.mass = 1e300: must lie in [1e-6, 1e6] kg");
    assert_eq!(
        error_of("", &["optimize.smoothness=-1e300"]),
        "optimize.smoothness = -1e300: must be a finite, non-negative weight"
    );
}

#[test]
fn every_echoed_number_is_shortened() {
    for (set, start) in [
        ("manoeuvre.circulation=1e300", "manoeuvre.circulation = 1e300: must be at most"),
        ("exact.tolerance=1e-300", "exact.tolerance = 1e-300: is below"),
        ("rapier.cross_mass_fraction=1e300", "rapier.cross_mass_fraction = 1e300: must be at most"),
    ] {
        let e = error_of("", &[set]);
        assert!(e.starts_with(start) && e.len() < 200, "{set}: {e}");
    }
}

/// Issue 18, "Messages": a step too fine to run, the paper's C at a straight cat and a bend limit
/// that leaves no start are each said in one line, in the user's terms.
#[test]
fn impossible_settings_are_named_in_the_users_terms() {
    let (code, e) = catflip(&["simulate", "problems/paper.toml", "--engine", "rapier", "--dt", "1e-300"]);
    let e = e.lines().last().unwrap_or_default().to_string();
    assert!(code != 0 && e.contains("1.42857e300 steps") && e.len() < 300, "{e}");
    let (code, e) = catflip(&["simulate", "problems/paper.toml", "--set", "manoeuvre.theta_deg=180"]);
    assert!(code != 0 && e.contains("manoeuvre.theta_deg = 180") && e.contains("calibrated"), "{e}");
    let (code, e) =
        catflip(&["optimize", "problems/paper.toml", "--whole", "--set", "optimize.whole.min_angle_deg=179"]);
    assert!(
        code != 0 && e.contains("no start could be built") && e.contains("lower optimize.whole.min_angle_deg"),
        "{e}"
    );
    assert!(!e.contains("none of the 0"), "{e}");
}
