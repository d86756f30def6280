//! Errors name what the user wrote: the field, the `--set`, the flag; never a Rust type name
//! (issue 9, "Messages").
#![deny(clippy::float_cmp)]

use std::process::Command;

use catflip::problem::Problem;

fn catflip(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_catflip")).args(args).output().expect("the binary runs");
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).trim().to_string())
}

fn error_of(text: &str, overrides: &[&str]) -> String {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    match Problem::from_toml(text, "test.toml", &o) {
        Ok(p) => panic!("expected an error, loaded {p:?}"),
        Err(e) => e.to_string(),
    }
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
    if let Err(e) = catflip::optimize::optimize(&p) {
        assert!(!e.to_string().contains('_'), "internal name in {e}");
    }
}

#[test]
fn the_calibration_status_reads_in_words() {
    assert_eq!(catflip::roots::RootStatus::NotAtRoot.to_string(), "the bracket closed on a jump, not on a root");
}

#[test]
fn echoed_values_are_shortened() {
    assert_eq!(error_of("", &["cat.mass=1e300"]), "cat.mass = 1e300: must lie in [1e-6, 1e6] kg");
    assert_eq!(
        error_of("", &["optimize.smoothness=-1e300"]),
        "optimize.smoothness = -1e300: must be a finite, non-negative weight"
    );
}
