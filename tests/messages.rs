//! Errors name what the user wrote: the field, the `--set`, the flag; never a Rust type name
//! (issue 9, "Messages").
#![deny(clippy::float_cmp)]

mod common;

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
    // Written with a space, a negative step is a value, not an unknown flag `-1`.
    let (code, err) = catflip(&["simulate", "problems/paper.toml", "--engine", "rapier", "--dt", "-1"]);
    assert_eq!((code, err.as_str()), (1, "error: --dt -1: must be a finite, positive time step in seconds"));
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
    let resolved = catflip::engines::resolved::Resolved::new(&p).expect("a given circulation resolves");
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

/// `catflip ARGS` under a file-size limit of `blocks` 512-byte blocks (`ulimit -f`, with SIGXFSZ
/// ignored so that a write past it fails with EFBIG as a full disk fails with ENOSPC). Unlike
/// permission bits, the limit holds for root too.
fn catflip_limited(blocks: u32, args: &[&str]) -> (i32, String) {
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    let script =
        format!("ulimit -f {blocks}; trap '' XFSZ; exec '{}' {}", env!("CARGO_BIN_EXE_catflip"), quoted.join(" "));
    let out = Command::new("sh").args(["-c", &script]).output().expect("sh runs");
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).trim().to_string())
}

/// A fresh folder for test `tag`.
fn scratch(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("catflip-messages-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("a scratch folder");
    d
}

/// Issue 18, "Messages": a write that fails (here on a file-size limit, as on a full disk) is
/// said with the path the user will find (`OUT/NAME/…`, never the hidden scratch folder) and the
/// OS error in words (before: `ImageError(IoError(Custom { kind: Other, error: "File too large
/// (os error 27)" }))` for a PNG, and `OUT/.paper.partial-PID/plots/flip.gif` for a run).
#[test]
fn a_failed_write_names_the_users_path_and_the_os_error() {
    let dir = scratch("write");
    let sweep = dir.join("w.toml");
    std::fs::write(
        &sweep,
        "name = \"w\"\n[base]\nname = \"tiny\"\n[base.exact]\ntolerance = 1e-8\ntorque_samples = 40\n\
         [[axis]]\nfield = \"cat.radius\"\nvalues = [0.1, 0.2]\n[compute]\npeaks = true\npaper_flip = true\ncalibrated = false\n",
    )
    .expect("writable");
    let out = dir.join("out");
    let out_s = out.display().to_string();
    // 8 kB: the sweep's tables (2 kB) are written, its first PNG (50 kB) is not.
    let (code, e) = catflip_limited(16, &["sweep", &sweep.display().to_string(), "--out", &out_s, "--quiet"]);
    assert_eq!(code, 1, "{e}");
    assert!(e.starts_with(&format!("error: cannot write {out_s}/w/plots/")) && e.contains(".png"), "{e}");
    assert!(e.ends_with("File too large (os error 27)") && !e.contains('\n'), "{e}");
    assert!(!e.contains("Error(") && !e.contains('{'), "Rust Debug text: {e}");
    let (code, e) = catflip_limited(1, &["run", "problems/paper.toml", "--out", &out_s, "--quiet"]);
    let e = e.lines().last().unwrap_or_default();
    assert_eq!(code, 1, "{e}");
    // `run` names the problem file, as each of its errors does (it takes several).
    let want = format!("error: problems/paper.toml: cannot write {out_s}/paper/");
    assert!(e.starts_with(&want) && !e.contains(".partial-"), "{e}");
    assert!(e.ends_with("File too large (os error 27)"), "{e}");
    let left: Vec<_> = std::fs::read_dir(&out).expect("the folder").filter_map(Result::ok).collect();
    assert!(left.is_empty(), "left behind: {left:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 18, "Messages": an error in a sweep's base problem is said once (it was printed twice,
/// the sweep's message repeating its cause).
#[test]
fn a_sweep_base_problem_error_is_said_once() {
    let dir = scratch("base");
    std::fs::write(dir.join("bad.toml"), "[cat]\nmass = -1\n").expect("writable");
    let sweep = dir.join("s.toml");
    std::fs::write(
        &sweep,
        "base = \"bad.toml\"\n[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1]\n[compute]\npeaks = true\n",
    )
    .expect("writable");
    let (code, e) = catflip(&["sweep", &sweep.display().to_string(), "--out", &dir.join("out").display().to_string()]);
    assert_eq!((code, e.as_str()), (1, "error: the sweep's base problem: cat.mass = -1: must be positive"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The paper's schedule as a CSV at 1 kHz (`t_s` written in plain decimals), every time field
/// through `retime` as text.
fn paper_csv_retimed(retime: impl Fn(&str) -> String) -> String {
    let csv = common::paper_csv();
    let mut lines = csv.lines();
    let mut text = lines.next().unwrap_or_default().to_string() + "\n";
    for line in lines {
        let (t, rest) = line.split_once(',').unwrap_or((line, ""));
        text += &format!("{},{rest}\n", retime(t));
    }
    text
}

/// Issue 18, "Messages": times near 1e15 s, written in full, are held to 0.125 s in double
/// precision, so rows 1 ms apart run together. Before, the error showed two equal times ("t =
/// 1000000000000000 s after t = 1000000000000000 s: times must increase"); times near 1e9 s,
/// accepted, moved the rows unsaid.
#[test]
fn times_far_from_zero_are_refused_or_warned_by_their_rounding() {
    use catflip::exchange::import::parse_schedule;
    use catflip::exchange::ImportError;
    // 1e15 + t written as text: `100000000000000` then t's decimals (t < 10).
    let far = paper_csv_retimed(|t| format!("100000000000000{t}"));
    assert!(far.lines().nth(2).is_some_and(|l| l.starts_with("1000000000000000.001")), "{far:.200}");
    match parse_schedule(&far, "far.csv").expect_err("refused") {
        e @ ImportError::TimesUnresolved { .. } => {
            let e = e.to_string();
            assert!(e.starts_with("far.csv: column `t_s`: times near 1e15 s are held in double precision"), "{e}");
            assert!(
                e.contains("times the rows' mean spacing") && e.ends_with("from the start of the fall (t = 0)"),
                "{e}"
            );
        }
        e => panic!("{e}"),
    }
    let dir = scratch("far");
    let path = dir.join("far.csv");
    std::fs::write(&path, &far).expect("writable");
    let (code, e) = catflip(&["simulate", "problems/paper.toml", "--schedule", &path.display().to_string()]);
    assert!(code == 1 && !e.contains("must increase") && e.contains("times near 1e15 s"), "{e}");
    // Near 1e9 s the rows move by 1e-7 s: accepted, with a warning naming the column.
    let p = Problem::default();
    let near = paper_csv_retimed(|t| format!("{}", 1e9 + t.parse::<f64>().expect("a time")));
    let imported = parse_schedule(&near, "near.csv").expect("reads");
    let r = catflip::report::import::evaluate(&p, &imported).expect("evaluates");
    assert!(r.warnings.iter().any(|w| w.contains("column `t_s`: times near 1e9 s")), "{:?}", r.warnings);
    // From zero, nothing is said.
    let zero = paper_csv_retimed(str::to_string);
    let r =
        catflip::report::import::evaluate(&p, &parse_schedule(&zero, "zero.csv").expect("reads")).expect("evaluates");
    assert!(!r.warnings.iter().any(|w| w.contains("double precision")), "{:?}", r.warnings);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 18, "Messages": a schedule compressed to 1e-200 s, given to rapier, was blamed on
/// "a positive definite locked inertia" (rapier's start at zero momentum, at rates of 1e200 rad/s);
/// it is refused on its time column, whatever the engine.
#[test]
fn a_compressed_schedule_is_refused_on_its_times_for_every_engine() {
    let tiny = paper_csv_retimed(|t| format!("{:e}", 1e-200 * t.parse::<f64>().expect("a time")));
    let dir = scratch("tiny");
    let path = dir.join("tiny.csv");
    std::fs::write(&path, &tiny).expect("writable");
    for engine in ["exact", "rapier"] {
        let (code, e) = catflip(&[
            "simulate",
            "problems/paper.toml",
            "--schedule",
            &path.display().to_string(),
            "--engine",
            engine,
        ]);
        let e = e.lines().last().unwrap_or_default();
        assert!(code == 1 && e.contains("column `t_s`") && e.contains("times must be in seconds"), "{engine}: {e}");
        assert!(!e.contains("locked inertia"), "{engine}: {e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
