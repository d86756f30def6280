//! Schedules from elsewhere (`simulate --schedule FILE.csv`): the lines named in messages are the
//! file's own whatever its line ends, times that do not start at 0 are said to be shifted, and
//! values too large for the engines are refused naming their line and column.
#![deny(clippy::float_cmp)]

use approx::assert_relative_eq;

use catflip::exchange::import::{parse_schedule, ImportError, FASTEST_TURN_SHARE, MAX_ANGLE_RAD};
use catflip::measure::import::measure_import;
use catflip::numeric::numfmt::sig;
use catflip::problem::Problem;

mod common;

/// `rows` rows of `t, q1, q2` over the fall from `t0`: joint 1 bends by `q1(u)`, `u` from 0 to 1.
fn rows(p: &Problem, n: usize, t0: f64, q1: impl Fn(f64) -> f64) -> Vec<String> {
    let fall = p.drop.fall_time();
    (0..n)
        .map(|k| {
            let u = k as f64 / (n - 1) as f64;
            format!("{:e},{:e},0", t0 + fall * u, q1(u))
        })
        .collect()
}

/// A bend of joint 1 and back, straight at both ends.
fn bend(u: f64) -> f64 {
    0.3 * (std::f64::consts::PI * u).sin().powi(2)
}

/// The warnings of `text` measured with `p`.
fn warnings(p: &Problem, text: &str) -> Vec<String> {
    let imported = parse_schedule(text, "f.csv").expect("reads");
    measure_import(p, imported).expect("measures").warnings
}

/// `text` (written with `\n`) with every line end `end`.
fn ended(text: &str, end: &str) -> String {
    text.replace('\n', end)
}

#[test]
fn lines_are_the_file_s_own_whatever_the_line_ends() {
    let p = Problem::default();
    let r = rows(&p, 8, 0.0, bend);
    // The header, four rows, a comment and a blank line, four rows.
    let text = format!("t,q1,q2\n{}\n# a note\n\n{}\n", r[..4].join("\n"), r[4..].join("\n"));
    let want: Vec<u64> = (2..6).chain(8..12).collect();
    let lf_warnings = warnings(&p, &text);
    for end in ["\n", "\r\n", "\r"] {
        let shown = end.escape_debug();
        let t = ended(&text, end);
        let s = parse_schedule(&t, "f.csv").expect("reads");
        let got: Vec<u64> = s.all_rows().map(|r| r.line).collect();
        assert_eq!(got, want, "line ends {shown}");
        assert_eq!(warnings(&p, &t), lf_warnings, "line ends {shown}");
        // A field that is not a number, on the second row after the blank line.
        let bad = ended(&text.replace(&r[5], "0.9,abc,0"), end);
        match parse_schedule(&bad, "f.csv").expect_err("refused") {
            ImportError::NotANumber { line, column, .. } => assert_eq!((line, column), (want[5], 2), "{shown}"),
            e => panic!("line ends {shown}: {e}"),
        }
        // A row with a field too many.
        let long = ended(&text.replace(&r[6], &format!("{},7", r[6])), end);
        match parse_schedule(&long, "f.csv").expect_err("refused") {
            ImportError::Csv { line, .. } => assert_eq!(line, want[6], "{shown}"),
            e => panic!("line ends {shown}: {e}"),
        }
        // A piece too short for the spline: its first and last lines.
        let short = ended(&format!("t,q1,q2\n{}\n", r[..3].join("\n")), end);
        match parse_schedule(&short, "f.csv").expect_err("refused") {
            ImportError::TooFewRows { first_line, last_line, .. } => {
                assert_eq!((first_line, last_line), (2, 4), "{shown}")
            }
            e => panic!("line ends {shown}: {e}"),
        }
    }
    // The rows' lines reach the warnings: the ends of a file of too few rows to judge them.
    let short = format!("t,q1,q2\n{}\n", rows(&p, 5, 0.0, bend).join("\n"));
    for end in ["\r\n", "\r"] {
        let w = warnings(&p, &ended(&short, end));
        assert!(w.iter().any(|w| w.starts_with("line 2: whether the schedule starts at rest")), "{w:?}");
        assert!(w.iter().any(|w| w.starts_with("line 6: whether the schedule ends at rest")), "{w:?}");
    }
}

#[test]
fn times_that_do_not_start_at_zero_are_warned_with_the_shift() {
    let p = Problem::default();
    let zero = format!("t,q1,q2\n{}\n", rows(&p, 9, 0.0, bend).join("\n"));
    let early = format!("t,q1,q2\n{}\n", rows(&p, 9, -1.0, bend).join("\n"));
    let measured = |text: &str| measure_import(&p, parse_schedule(text, "f.csv").expect("reads")).expect("measures");
    let (a, b) = (measured(&zero), measured(&early));
    assert!(!a.warnings.iter().any(|w| w.contains("times start")), "{:?}", a.warnings);
    let said: Vec<&String> = b.warnings.iter().filter(|w| w.contains("times start")).collect();
    assert_eq!(said.len(), 1, "{:?}", b.warnings);
    let w = said[0];
    assert!(w.starts_with("line 2, column `t`: the times start at -1 s") && w.contains("shifted by +1 s"), "{w}");
    // The file's last time, and where it falls from the start.
    let fall = p.drop.fall_time();
    let last = format!("{:e}", -1.0 + fall).parse::<f64>().expect("a number");
    assert!(w.contains(&format!("the last, {} s on line 10", sig(last, 15))), "{w}");
    // Shifted, the schedule is the same.
    assert_relative_eq!(a.measured.exact.flip.twist, b.measured.exact.flip.twist, max_relative = 1e-9);
}

#[test]
fn values_too_large_for_the_engines_name_their_line_and_column() {
    let p = Problem::default();
    let fall = p.drop.fall_time();
    let tau = FASTEST_TURN_SHARE * fall;
    let (rate_limit, accel_limit) = (MAX_ANGLE_RAD / tau, MAX_ANGLE_RAD / (tau * tau));
    // Quintic Hermite rows, at rest; `edit(k)` gives row k's (qd1, qd2, qdd1, qdd2).
    let file = |edit: &dyn Fn(usize) -> [f64; 4]| {
        let mut text = String::from("t,q1,q2,qd1,qd2,qdd1,qdd2\n");
        for k in 0..6 {
            let [a, b, c, d] = edit(k);
            text += &format!("{:e},0,0,{a:e},{b:e},{c:e},{d:e}\n", fall * k as f64 / 5.0);
        }
        text
    };
    // 1e200 rad/s on row 3 (line 5), 1e300 rad/s² on row 2 (line 4): the first line is named.
    let huge = file(&|k| match k {
        2 => [0.0, 0.0, 0.0, 1e300],
        3 => [1e200, 0.0, 0.0, 0.0],
        _ => [0.0; 4],
    });
    let e = parse_schedule(&huge, "huge.csv").expect_err("refused");
    match &e {
        ImportError::AbsurdRate { line, column, name, .. } => {
            assert_eq!((*line, *column, name.as_str()), (4, 7, "qdd2"))
        }
        e => panic!("{e}"),
    }
    let m = e.to_string();
    assert!(m.contains("line 4, column 7 (`qdd2`)") && m.contains("rad/s²") && m.len() < 300, "{m}");
    let e = parse_schedule(&file(&|k| if k == 3 { [0.0, 1e200, 0.0, 0.0] } else { [0.0; 4] }), "f.csv")
        .expect_err("refused");
    match &e {
        ImportError::AbsurdRate { line, column, name, .. } => {
            assert_eq!((*line, *column, name.as_str()), (5, 5, "qd2"))
        }
        e => panic!("{e}"),
    }
    // Just inside the limits the engines give numbers (however poor the schedule).
    let near = file(&|k| if k == 3 { [0.9 * rate_limit, 0.0, 0.9 * accel_limit, 0.0] } else { [0.0; 4] });
    let m = measure_import(&p, parse_schedule(&near, "near.csv").expect("reads")).expect("measured");
    assert!(m.measured.exact.flip.twist.is_finite());
    // An angle of 1e308 rad: its turns in scientific notation, the message short.
    let e =
        parse_schedule("t,q1,q2\n0,0,0\n0.1,1e308,0\n0.2,0,0\n0.3,0,0\n", "f.csv").expect_err("refused").to_string();
    let digits = e.split(|c: char| !c.is_ascii_digit()).map(str::len).max().unwrap_or(0);
    assert!(e.contains("line 3, column 2") && digits < 10 && e.len() < 200, "{} bytes: {e}", e.len());
}

#[test]
fn the_ends_say_how_the_cat_is_released_and_lands() {
    // From rest, straight, to a bend of 0.3 rad still moving at the end.
    let p = Problem::default();
    let text = format!("t,q1,q2\n{}\n", rows(&p, 9, 0.0, |u| 0.3 * u * u).join("\n"));
    let w = warnings(&p, &text);
    assert!(w.iter().any(|w| w.contains("ends bent") && w.contains("the cat lands straight")), "{w:?}");
    assert!(w.iter().any(|w| w.contains("ends moving") && w.contains("the cat lands at rest")), "{w:?}");
    let moving = format!("t,q1,q2\n{}\n", rows(&p, 9, 0.0, |u| 0.3 * (1.0 - (1.0 - u).powi(2))).join("\n"));
    let w2 = warnings(&p, &moving);
    assert!(w2.iter().any(|w| w.contains("starts moving") && w.contains("the cat is released at rest")), "{w2:?}");
    assert!(w.iter().chain(&w2).all(|w| !w.contains("is lands")), "{w:?} {w2:?}");
}

/// A phase boundary written once (a de-duplication of the times keeping one of its two rows) is
/// said, with the `phase` column and, without it, from the accelerations' jump inside one
/// interval; the file as catflip writes it says nothing of the kind (a QA run's peak torque rose
/// by 37 % on such a file, silently).
#[test]
fn a_phase_boundary_written_once_is_warned_of() {
    let p = Problem::default();
    let csv = common::paper_csv();
    let header: Vec<&str> = csv.lines().next().unwrap_or_default().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("column {name}"));
    let (phase, boundary) = (at("phase"), at("boundary"));
    let said = |w: &[String]| w.iter().any(|w| w.contains("catflip writes each phase boundary's time twice"));
    assert!(!said(&warnings(&p, &csv)), "the file as written");
    // Every `end` row dropped: one row per boundary time, the next phase's.
    let once: Vec<&str> = csv.lines().filter(|l| l.split(',').nth(boundary) != Some("end")).collect();
    assert!(once.len() < csv.lines().count(), "the schedule has boundaries");
    let w = warnings(&p, &(once.join("\n") + "\n"));
    assert!(w.iter().any(|w| w.contains("the phase changes from \"bend\" to \"twist\"")), "{w:?}");
    // Without the phase and boundary columns, the accelerations say it.
    let bare: Vec<String> = once
        .iter()
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            let kept: Vec<&str> =
                cells.iter().enumerate().filter(|(i, _)| *i != phase && *i != boundary).map(|(_, c)| *c).collect();
            kept.join(",")
        })
        .collect();
    let w = warnings(&p, &(bare.join("\n") + "\n"));
    assert!(w.iter().any(|w| w.contains("jumps within one interval")) && said(&w), "{w:?}");
}

/// A jerk-limited profile (continuous `q̈`, the jerk switching between rows) is not a boundary
/// written once: its kink leaves a residual of the trapezoid rule, isolated as a jump's is, but
/// changes `q̈` as its neighbours do (a review found it warned of).
#[test]
fn a_jerk_limited_profile_is_not_taken_for_a_boundary_written_once() {
    let p = Problem::default();
    let fall = p.drop.fall_time();
    // Jerk +J, −J, +J over the quarters, halves and quarter of the fall: q̈ continuous, zero at
    // both ends, q̇ from rest to rest; 1001 intervals, so the switches fall inside intervals.
    let jerk = 400.0;
    let switches = [0.0, 0.25 * fall, 0.75 * fall, fall];
    let signs = [1.0, -1.0, 1.0];
    let state = |t: f64| {
        let (mut q, mut qd, mut qdd) = (0.0, 0.0, 0.0);
        for (k, s) in signs.iter().enumerate() {
            let (t0, t1) = (switches[k], switches[k + 1]);
            let d = t.min(t1) - t0;
            if d <= 0.0 {
                break;
            }
            let j = s * jerk;
            q += qd * d + qdd * d * d / 2.0 + j * d.powi(3) / 6.0;
            qd += qdd * d + j * d * d / 2.0;
            qdd += j * d;
        }
        (q, qd, qdd)
    };
    let n = 1001;
    let mut text = String::from("t_s,q1_rad,q2_rad,qd1_rad_s,qd2_rad_s,qdd1_rad_s2,qdd2_rad_s2\n");
    for k in 0..=n {
        let t = fall * k as f64 / n as f64;
        let (q, qd, qdd) = state(t);
        text += &format!("{t:e},{q:e},0,{qd:e},0,{qdd:e},0\n");
    }
    let w = warnings(&p, &text);
    assert!(!w.iter().any(|w| w.contains("jumps within one interval")), "{w:?}");
    // The same profile with q̈ stepping up by 50 rad/s² at row 500's time, written once (that
    // row holds the value after the step, as a de-duplication keeping the `start` row leaves
    // it): said.
    let step = fall * 500.0 / n as f64;
    let mut stepped = String::from("t_s,q1_rad,q2_rad,qd1_rad_s,qd2_rad_s,qdd1_rad_s2,qdd2_rad_s2\n");
    for k in 0..=n {
        let t = fall * k as f64 / n as f64;
        let (mut q, mut qd, mut qdd) = state(t);
        if k >= 500 {
            let d = t - step;
            (q, qd, qdd) = (q + 25.0 * d * d, qd + 50.0 * d, qdd + 50.0);
        }
        stepped += &format!("{t:e},{q:e},0,{qd:e},0,{qdd:e},0\n");
    }
    let w = warnings(&p, &stepped);
    assert!(
        w.iter().any(|w| w.starts_with("lines 501 and 502: column `qdd1_rad_s2` jumps within one interval")),
        "{w:?}"
    );
}
