//! The report's static figures: smoothing profiles, joint torques, the flip over time, and
//! run time against error. Each samples the library's own formulas and hands a [`LinePlot`] to
//! [`line_plot`].

use std::path::{Path, PathBuf};

use super::animation::model_of;
use super::chart::{line_plot, Band, LinePlot, RefLine, Scale};
use super::{PlotError, Series};
use crate::engines::models::TwoMotorCat;
use crate::engines::torque::ZeroMomentumTorques;
use crate::problem::Problem;
use crate::schedule::{Phase, Schedule, Trajectory};

/// Points over the whole manoeuvre at which [`torques_plot`] evaluates the torques.
pub const TORQUE_SAMPLES: usize = 1500;

/// Points over the twist phase at which [`profiles_plot`] evaluates each rate.
const PROFILE_SAMPLES: usize = 400;

/// Plots circulation-rate curves `ω(s)` (rad/s against s, time since the twist phase began) as
/// `dir/profiles.{png,svg}`, titled with the problem's name.
pub fn plot_profiles(dir: &Path, problem_name: &str, curves: &[Series]) -> Result<Vec<PathBuf>, PlotError> {
    let plot = LinePlot::new(
        "profiles",
        format!("Circulation rate of the twist phase, problem \u{201c}{problem_name}\u{201d}"),
        "time since the twist phase began (s)",
        "circulation rate ω (rad/s)",
        curves.to_vec(),
    );
    line_plot(dir, &plot)
}

/// The circulation rate `ω(s) = D/T₂ · V(s/T₂)` of each schedule over its twist phase, as
/// [`plot_profiles`] draws it.
pub fn profiles_plot(
    dir: &Path,
    problem: &Problem,
    schedules: &[(String, Schedule)],
) -> Result<Vec<PathBuf>, PlotError> {
    let curves: Vec<Series> = schedules.iter().map(|(name, s)| Series::new(name.clone(), rate_curve(s))).collect();
    plot_profiles(dir, &problem.name, &curves)
}

/// `(s, ω(s))` on `PROFILE_SAMPLES + 1` points of the twist phase.
fn rate_curve(schedule: &Schedule) -> Vec<(f64, f64)> {
    let t2 = schedule.durations[1];
    (0..=PROFILE_SAMPLES)
        .map(|k| {
            let u = k as f64 / PROFILE_SAMPLES as f64;
            (u * t2, schedule.circulation / t2 * schedule.profile.at(u).rate)
        })
        .collect()
}

/// The motor torques `τ₁` and `τ₂` (N·m, on the problem's joint's motor axes) of each schedule
/// over the whole manoeuvre on the problem's cat, as
/// `dir/torques_joint1.{png,svg}` and `dir/torques_joint2.{png,svg}`, with the phases marked.
///
/// Each phase is sampled by its own formula on its closed interval (about
/// [`TORQUE_SAMPLES`] points in all), so a torque that jumps at a phase boundary is drawn as a
/// jump, not smoothed over.
pub fn torques_plot(
    dir: &Path,
    problem: &Problem,
    schedules: &[(String, &dyn Trajectory)],
) -> Result<Vec<PathBuf>, PlotError> {
    let cat = model_of(problem, dir)?;
    let sampled: Vec<(&str, TorqueCurve)> =
        schedules.iter().map(|(name, s)| (name.as_str(), torque_curve(&cat, *s))).collect();
    let bands = schedules.first().map(|(_, s)| phase_bands(*s)).unwrap_or_default();
    let axes = ["1", "2"].iter().zip(["τ₁", "τ₂"]).zip(problem.cat.joint.motor_axis_names());
    let mut files = Vec::new();
    for (j, ((number, symbol), axis)) in axes.enumerate() {
        let about = format!("about {axis} axis");
        let series = sampled
            .iter()
            .map(|(name, points)| Series::new(*name, points.iter().map(|(t, tau)| (*t, tau[j])).collect()))
            .collect();
        let mut plot = LinePlot::new(
            format!("torques_joint{number}"),
            format!("Joint {number} motor torque ({about}), problem \u{201c}{}\u{201d}", problem.name),
            "time t (s)",
            format!("torque {symbol} on B (N·m)"),
            series,
        );
        plot.bands = bands.clone();
        files.extend(line_plot(dir, &plot)?);
    }
    Ok(files)
}

/// `(t, [τ₁, τ₂])` samples, s and N·m.
type TorqueCurve = Vec<(f64, [f64; 2])>;

/// `(t, [τ₁, τ₂])` on `cat` at zero angular momentum, piece by piece (phase by phase for a
/// schedule), both ends of each piece included.
fn torque_curve(cat: &TwoMotorCat, schedule: &dyn Trajectory) -> TorqueCurve {
    let durations = schedule.piece_durations();
    let total: f64 = durations.iter().sum();
    let mut out = Vec::with_capacity(TORQUE_SAMPLES + 2 * durations.len() + 4);
    let mut t0 = 0.0;
    for (piece, &dur) in durations.iter().enumerate() {
        let n = ((TORQUE_SAMPLES as f64 * dur / total).round() as usize).max(2);
        out.extend((0..=n).map(|k| {
            let s = dur * k as f64 / n as f64;
            (t0 + s, cat.motor_torques(&schedule.piece_state(piece, s)))
        }));
        t0 += dur;
    }
    out
}

/// One band per phase, named, when the pieces are the manoeuvre's three phases; none otherwise
/// (a whole-manoeuvre trajectory has no phases).
fn phase_bands(schedule: &dyn Trajectory) -> Vec<Band> {
    let d = schedule.piece_durations();
    if d.len() != Phase::ALL.len() {
        return Vec::new();
    }
    let mut from = 0.0;
    Phase::ALL
        .iter()
        .zip(d)
        .map(|(p, di)| {
            let band = Band { from, to: from + di, label: p.name().to_string() };
            from += di;
            band
        })
        .collect()
}

/// Twist and swing of the front half A (degrees) over time from the exact engine on the problem's
/// cat with `steps` Magnus steps over the whole fall ([`TwoMotorCat::picture_history`]), as
/// `dir/flip.{png,svg}`, with the ±180° target dashed.
pub fn flip_plot(
    dir: &Path,
    problem: &Problem,
    name: &str,
    schedule: &impl Trajectory,
    steps: usize,
) -> Result<Vec<PathBuf>, PlotError> {
    if steps == 0 {
        return Err(PlotError::BadArgument { path: dir.join("flip"), reason: "steps must be at least 1".into() });
    }
    let samples = model_of(problem, dir)?.picture_history(schedule, &nalgebra::Vector3::zeros(), steps);
    let twist: Vec<(f64, f64)> = samples.iter().map(|s| (s.time, s.angles.twist.to_degrees())).collect();
    let swing: Vec<(f64, f64)> = samples.iter().map(|s| (s.time, s.angles.swing.to_degrees())).collect();
    let end = |c: &[(f64, f64)]| c.last().map_or(f64::NAN, |p| p.1);
    let mut plot = LinePlot::new(
        "flip",
        format!("Reorientation of the front half A, problem \u{201c}{}\u{201d} ({})", problem.name, name),
        "time t (s)",
        "angle (degrees)",
        vec![
            Series::new(format!("twist (end {:.2}°)", end(&twist)), twist),
            Series::new(format!("swing (end {:.2}°)", end(&swing)), swing),
        ],
    );
    plot.bands = phase_bands(schedule);
    plot.ref_lines = [180.0, -180.0].map(|y| RefLine { y, label: format!("target {y:+}°") }).to_vec();
    line_plot(dir, &plot)
}

/// Run time (s) against error, log–log, one series per engine, as `dir/error_vs_time.{png,svg}`.
///
/// `points` are `(engine, run time in s, error)`, the error being the flip's (twist and swing)
/// absolute error against the reference, rad. Points with a non-positive time or error cannot
/// be shown on log axes and are left out.
pub fn error_vs_time_plot(dir: &Path, points: &[(String, f64, f64)]) -> Result<Vec<PathBuf>, PlotError> {
    let mut series: Vec<Series> = Vec::new();
    for (engine, time, error) in points {
        match series.iter_mut().find(|s| &s.name == engine) {
            Some(s) => s.points.push((*error, *time)),
            None => series.push(Series::new(engine.clone(), vec![(*error, *time)])),
        }
    }
    for s in &mut series {
        s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let mut plot = LinePlot::new(
        "error_vs_time",
        "Run time against error, per engine",
        "error of the flip against the reference (rad)",
        "run time (s)",
        series,
    );
    plot.scale = Scale::LogLog;
    plot.markers = true;
    line_plot(dir, &plot)
}

/// Both motor torques of one trajectory over time (N·m), as `dir/<stem>.{png,svg}`, on their own
/// scale: the whole-manoeuvre optimum's torques are far below the library schedules' and vanish on
/// a shared axis.
pub fn trajectory_torques_plot(
    dir: &Path,
    problem: &Problem,
    stem: &str,
    name: &str,
    trajectory: &dyn Trajectory,
) -> Result<Vec<PathBuf>, PlotError> {
    let curve = torque_curve(&model_of(problem, dir)?, trajectory);
    let series = ["τ₁", "τ₂"]
        .iter()
        .zip(problem.cat.joint.motor_axis_names())
        .enumerate()
        .map(|(j, (symbol, axis))| {
            Series::new(
                format!("{symbol} (joint {}, about {axis})", j + 1),
                curve.iter().map(|(t, tau)| (*t, tau[j])).collect(),
            )
        })
        .collect();
    let mut plot = LinePlot::new(
        stem,
        format!("Motor torques of {name}, problem \u{201c}{}\u{201d}", problem.name),
        "time t (s)",
        "torque on B (N·m)",
        series,
    );
    plot.bands = phase_bands(trajectory);
    line_plot(dir, &plot)
}
