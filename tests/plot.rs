//! The plots and the animation: files appear, are well-formed images of the requested size,
//! carry their text (drawn with the embedded font, no system font needed), and bad input gets a
//! specific error instead of a panic.

mod common;

use std::path::{Path, PathBuf};

use catflip::engines::models::TwoMotorCat;
use catflip::engines::resolved::Resolved;
use catflip::problem::manoeuvre::ProfileKind;
use catflip::problem::Problem;
use catflip::report::plot::{
    cat_poses, error_vs_time_plot, flip_animation, flip_filmstrip, flip_plot, line_plot, profiles_plot, torques_plot,
    LinePlot, PlotError, Series, FILMSTRIP_PANELS, PNG_SIZE,
};
use catflip::schedule::profile::Profile;
use catflip::schedule::{Schedule, Trajectory};
use nalgebra::Vector3;

use common::paper;

/// A fresh folder under the system's temporary directory, unique to this test and run.
fn temp_dir(name: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
    let dir = std::env::temp_dir().join(format!("catflip-plot-{name}-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn schedules(base: &Schedule) -> Vec<(String, Schedule)> {
    [ProfileKind::PaperCosine, ProfileKind::Cycloidal, ProfileKind::BangBang]
        .iter()
        .map(|&k| (k.name().to_string(), base.with_profile(Profile::library(k))))
        .collect()
}

/// Width and height from a PNG's IHDR chunk, after checking the signature.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).expect("png readable");
    assert!(bytes.len() > 33, "{} is too short for a PNG: {} bytes", path.display(), bytes.len());
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{} lacks the PNG signature", path.display());
    assert_eq!(&bytes[12..16], b"IHDR", "{}: first chunk is not IHDR", path.display());
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    (be(16), be(20))
}

fn svg_text(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("svg readable as UTF-8");
    assert!(text.contains("<svg"), "{} is not an SVG", path.display());
    text
}

/// Checks a PNG + SVG pair named `stem` is among `files` and returns the SVG's text.
fn check_pair(files: &[PathBuf], dir: &Path, stem: &str) -> String {
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    assert!(files.contains(&png) && files.contains(&svg), "{stem}: files reported {files:?}");
    assert_eq!(png_size(&png), PNG_SIZE, "{}", png.display());
    svg_text(&svg)
}

#[test]
fn profiles_plot_writes_png_and_svg_with_labels() {
    let dir = temp_dir("profiles");
    let (problem, schedule) = paper();
    let files = profiles_plot(&dir, &problem, &schedules(&schedule)).expect("profiles plot");
    assert_eq!(files.len(), 2);
    let svg = check_pair(&files, &dir, "profiles");
    assert!(svg.contains("circulation rate ω (rad/s)"), "y-axis label missing from the SVG");
    assert!(svg.contains("\u{201c}paper\u{201d}"), "title should name the problem");
    for name in ["paper-cosine", "cycloidal", "bang-bang"] {
        assert!(svg.contains(name), "legend entry {name} missing");
    }
}

#[test]
fn legend_says_which_curve_is_drawn_under_another() {
    // The same schedule under two names: the first is painted first, then covered by the second.
    let dir = temp_dir("legend");
    let (problem, schedule) = paper();
    let mut shown = schedules(&schedule);
    shown.push(("bang-bang-again".to_string(), schedule.with_profile(Profile::library(ProfileKind::BangBang))));
    let files = profiles_plot(&dir, &problem, &shown).expect("profiles plot");
    let svg = check_pair(&files, &dir, "profiles");
    assert!(svg.contains(">\nunder bang-bang-again\n<"), "the hidden bang-bang should be noted in the legend");
    assert_eq!(svg.matches("under ").count(), 1, "only the hidden curve is noted");
}

#[test]
fn torques_plot_writes_one_pair_per_joint() {
    let dir = temp_dir("torques");
    let (problem, schedule) = paper();
    let shown = schedules(&schedule);
    let curves: Vec<(String, &dyn Trajectory)> = shown.iter().map(|(n, s)| (n.clone(), s as &dyn Trajectory)).collect();
    let files = torques_plot(&dir, &problem, &curves).expect("torques plot");
    assert_eq!(files.len(), 4);
    for (stem, label) in [("torques_joint1", "torque τ₁ on B (N·m)"), ("torques_joint2", "torque τ₂ on B (N·m)")]
    {
        let svg = check_pair(&files, &dir, stem);
        assert!(svg.contains(label), "{stem}: axis label {label:?} missing");
        for phase in ["bend", "twist", "unbend"] {
            assert!(svg.contains(&format!(">\n{phase}\n<")), "{stem}: phase label {phase:?} missing");
        }
    }
}

#[test]
fn flip_plot_marks_the_target() {
    let dir = temp_dir("flip");
    let (problem, schedule) = paper();
    let files = flip_plot(&dir, &problem, "cycloidal", &schedule, 64).expect("flip plot");
    let svg = check_pair(&files, &dir, "flip");
    for label in ["angle (degrees)", "time t (s)", "target +180°", "target -180°", "twist (end", "swing (end"] {
        assert!(svg.contains(label), "flip plot lacks {label:?}");
    }
    let zero = flip_plot(&dir, &problem, "cycloidal", &schedule, 0);
    assert!(matches!(zero, Err(PlotError::BadArgument { .. })), "steps = 0 should be refused, got {zero:?}");
}

#[test]
fn error_vs_time_is_log_log_and_skips_unplottable_points() {
    let dir = temp_dir("bench");
    let points: Vec<(String, f64, f64)> = vec![
        ("exact".into(), 1e-4, 1e-6),
        ("exact".into(), 4e-4, 1e-9),
        ("exact".into(), 1e-3, 0.0), // zero error: cannot be shown on a log axis
        ("rapier".into(), 2e-2, 1e-3),
        ("rapier".into(), 8e-2, 2e-4),
    ];
    let files = error_vs_time_plot(&dir, &points).expect("bench plot");
    let svg = check_pair(&files, &dir, "error_vs_time");
    assert!(svg.contains("run time (s)") && svg.contains("rapier") && svg.contains("exact"));
    assert!(svg.contains("10⁻"), "log axes should be labelled in powers of ten");

    let only_zero = vec![("exact".to_string(), 1e-3, 0.0)];
    match error_vs_time_plot(&dir, &only_zero) {
        Err(PlotError::NoData { reason, .. }) => assert!(reason.contains("positive"), "reason: {reason}"),
        other => panic!("expected NoData, got {other:?}"),
    }
}

#[test]
fn empty_series_list_is_a_clear_error() {
    let dir = temp_dir("empty");
    let (problem, _) = paper();
    let err = profiles_plot(&dir, &problem, &[]).expect_err("nothing to plot");
    assert!(matches!(err, PlotError::NoData { .. }), "got {err:?}");
    let message = err.to_string();
    assert!(message.contains("profiles") && message.contains("no series"), "message: {message}");
    assert!(!dir.join("profiles.png").exists(), "no file should be written");

    let nan = LinePlot::new("nan", "t", "x (m)", "y (m)", vec![Series::new("s", vec![(f64::NAN, 1.0)])]);
    assert!(matches!(line_plot(&dir, &nan), Err(PlotError::NoData { .. })));
    assert!(matches!(torques_plot(&dir, &problem, &[]), Err(PlotError::NoData { .. })));
}

/// Counts the images of a GIF by walking its blocks; returns (width, height, frames, loops).
fn gif_frames(bytes: &[u8]) -> (u16, u16, usize, bool) {
    assert_eq!(&bytes[..6], b"GIF89a", "not a GIF89a file");
    let le = |i: usize| u16::from_le_bytes([bytes[i], bytes[i + 1]]);
    let table = |flags: u8| if flags & 0x80 != 0 { 3 * (2usize << (flags & 7)) } else { 0 };
    let skip_sub_blocks = |mut i: usize| {
        while bytes[i] != 0 {
            i += bytes[i] as usize + 1;
        }
        i + 1
    };
    let (width, height) = (le(6), le(8));
    let mut i = 13 + table(bytes[10]);
    let (mut frames, mut loops) = (0, false);
    loop {
        match bytes[i] {
            0x21 => {
                loops |= bytes[i + 1] == 0xFF && &bytes[i + 3..i + 14] == b"NETSCAPE2.0";
                i = skip_sub_blocks(i + 2);
            }
            0x2C => {
                frames += 1;
                i = skip_sub_blocks(i + 10 + table(bytes[i + 9]) + 1);
            }
            0x3B => return (width, height, frames, loops),
            b => panic!("unexpected GIF block 0x{b:02X} at byte {i}"),
        }
    }
}

#[test]
fn animation_has_the_frames_asked_and_a_filmstrip() {
    let dir = temp_dir("anim");
    let (problem, schedule) = paper();
    let schedule = schedule.with_profile(Profile::library(ProfileKind::Cycloidal));
    let gif = dir.join("flip.gif");
    let files = flip_animation(&gif, &problem, "cycloidal", &schedule, 8).expect("animation");
    assert_eq!(files, vec![gif.clone(), dir.join("flip_filmstrip.png")]);
    let bytes = std::fs::read(&gif).expect("gif readable");
    assert_eq!(gif_frames(&bytes), (600, 600, 8, true), "(width, height, frames, looping)");
    let (w, h) = png_size(&files[1]);
    assert_eq!(w % FILMSTRIP_PANELS as u32, 0, "filmstrip width {w} is not a whole number of panels");
    assert!(w > 3 * h, "filmstrip should be a strip: {w} × {h}");

    let one = flip_animation(&dir.join("one.gif"), &problem, "cycloidal", &schedule, 1);
    assert!(matches!(one, Err(PlotError::BadArgument { .. })), "1 frame should be refused, got {one:?}");
}

#[test]
fn poses_keep_the_centre_of_mass_and_the_joint_together() {
    let (problem, schedule) = paper();
    let total = schedule.duration();
    let times: Vec<f64> = (0..=20).map(|k| total * k as f64 / 20.0).collect();
    let model = TwoMotorCat::new(problem.cat.model()).expect("a two-motor cat");
    let poses = cat_poses(&model, &schedule, &times);
    let half = 0.5 * problem.cat.length;
    for p in &poses {
        let com = 0.5 * (p.a.centre + p.b.centre);
        assert!(com.norm() < 1e-12, "t = {}: centre of mass at {com:?}", p.time);
        let joint_a = p.a.point(Vector3::new(0.0, 0.0, -half));
        let joint_b = p.b.point(Vector3::new(0.0, 0.0, half));
        assert!(
            (joint_a - joint_b).norm() < 1e-12,
            "t = {}: joint halves apart by {}",
            p.time,
            (joint_a - joint_b).norm()
        );
    }
    // Belly (A's +y) starts up; at the end its height is cos(twist), up to the swing's tilt.
    let (first, last) = (poses[0], poses[poses.len() - 1]);
    assert!(((first.a.rotation * Vector3::y()).y - 1.0).abs() < 1e-12, "first pose {first:?}");
    let belly = (last.a.rotation * Vector3::y()).y;
    let tol = last.swing.sin() + (1.0 - last.swing.cos()) + 1e-9;
    assert!(
        (belly - last.twist.cos()).abs() <= tol,
        "belly height {belly} vs cos(twist) {} (tol {tol})",
        last.twist.cos()
    );
    assert!(belly < 0.0, "after the flip the belly should face down, height {belly}");
}

/// Unequal halves on the no-twist joint: the poses keep the mass-weighted centre of mass at the
/// origin and the joint's two anchors (A's rear end, B's front end, each at its own half-length)
/// together, turn B by the model's own `R_AB = exp([q1, q2, 0]×)`, and end at the general core's
/// final twist (DESIGN.md §10).
#[test]
fn poses_of_another_model_are_that_models() {
    let text = std::fs::read_to_string("problems/unequal-halves.toml").expect("the preset");
    let problem = Problem::from_toml(&text, "unequal-halves.toml", &["cat.joint=\"no-twist\"".into()]).expect("valid");
    let r = Resolved::new(&problem).expect("calibrated");
    let model = r.model();
    let (front, rear) = (problem.cat.front(), problem.cat.rear());
    let total = r.schedule.duration();
    let times: Vec<f64> = (0..=40).map(|k| total * k as f64 / 40.0).collect();
    let poses = cat_poses(model, &r.schedule, &times);
    for p in &poses {
        let com = (front.mass * p.a.centre + rear.mass * p.b.centre) / (front.mass + rear.mass);
        assert!(com.norm() < 1e-12, "t = {}: centre of mass at {com:?}", p.time);
        let joint_a = p.a.point(Vector3::new(0.0, 0.0, -0.5 * front.length));
        let joint_b = p.b.point(Vector3::new(0.0, 0.0, 0.5 * rear.length));
        assert!((joint_a - joint_b).norm() < 1e-12, "t = {}: anchors apart by {}", p.time, (joint_a - joint_b).norm());
        let q = r.schedule.state_at(p.time).q;
        let r_ab = p.a.rotation.transpose() * p.b.rotation;
        let expected = problem.cat.joint.rotation(&q);
        assert!((r_ab - expected).norm() < 1e-12, "t = {}: R_AB off by {}", p.time, (r_ab - expected).norm());
    }
    // The last pose ends where the general core's adaptive flip does (the history's fixed steps
    // agree with it to well below the 1e-6 rad asked here).
    let flip = model.flip(&r.schedule, 1e-12);
    let last = poses[poses.len() - 1];
    assert!((last.twist - flip.twist).abs() < 1e-6, "pose twist {} vs flip {}", last.twist, flip.twist);
    assert!((last.swing - flip.swing).abs() < 1e-6, "pose swing {} vs flip {}", last.swing, flip.swing);
}

/// The filmstrip alone, of an unequal cat: one PNG of six panels and the title row.
#[test]
fn a_filmstrip_of_unequal_halves_is_written() {
    let text = std::fs::read_to_string("problems/unequal-halves.toml").expect("the preset");
    let problem = Problem::from_toml(&text, "unequal-halves.toml", &[]).expect("valid");
    let r = Resolved::new(&problem).expect("calibrated");
    let dir = temp_dir("unequal_filmstrip");
    let path = flip_filmstrip(&dir.join("strip.png"), &problem, "calibrated", &r.schedule).expect("filmstrip");
    let (w, h) = png_size(&path);
    assert_eq!(w % FILMSTRIP_PANELS as u32, 0, "width {w} is not {FILMSTRIP_PANELS} panels");
    assert!(h > 300, "height {h}");
}
