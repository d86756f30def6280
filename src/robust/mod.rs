//! Will the schedule land the cat on its feet, and how often? A seeded Monte Carlo of the
//! open-loop schedule on cats drawn around the problem's, released with random spin.
//!
//! Each trial `k` draws, from its own SplitMix64 stream (seed `robust.seed`, stream `k`), the
//! factors of each half's mass, length and radius (uniform in `1 ± p/100`, both halves alike;
//! [`Draw`] records the `[cat]` shorthand's values, each half's own scaled by the same factors on
//! unequal halves, [`drawn_cat`]) and the release spin `L = L₀ + σ n`, `n` three standard
//! normals (world frame, `L₀ = drop.angular_momentum`). The joints then follow the schedule
//! exactly (ideal tracking: the motors are the planned ones), and the exact engine
//! ([`crate::engines::evaluate::released_on`], spinning when `L ≠ 0`) gives A's attitude `R` at
//! the end of the fall. Its **landing error** is the angle of `R_*⁻¹ R` to the target
//! `R_* = Rz(π)`, the half turn about the initial spine; its twist part is `|twist| − 180°`
//! and its swing part the spine's swing (DESIGN.md §2).
//!
//! With `robust.engine = "rapier"` (or `"both"`, side by side) each trial is instead a rapier
//! run in which a controller tracks the schedule through the actuators, with an attitude sensor
//! that is late and noisy, and optionally falls onto the ground ([`tracked`]): the same draws
//! (plus each joint's servo gain factor, drawn after them, so the sizes and spins stay those of
//! the exact check), the same landing error.
//!
//! The trials run in parallel; every number depends on the seed only, not on the thread count.
//! With `robust.controller = "feedback"` (or `"both"`) the tracked trials are run (again, on
//! the same draws and sensor noise) with feedback on the attitude
//! ([`crate::engines::rapier::feedback`]: time-varying LQR with a Kalman filter), reported as
//! its own engine beside the open loop. The exact engine's check runs on every two-motor cat
//! (unequal halves, the no-twist joint: the general core); the tracked rapier trials on the
//! paper's cat only. Its Markdown, CSV and plots are [`crate::report::robust`]'s.

pub mod tracked;

use std::f64::consts::PI;

use nalgebra::{UnitQuaternion, Vector3};
use rayon::prelude::*;
use serde::Serialize;

use crate::engines::evaluate::released_on;
use crate::engines::models::{ModelError, TwoMotorCat};
use crate::model::{Cat, Cylinder};
use crate::numeric::random::SplitMix64;
use crate::problem::robust::RobustSettings;
use crate::problem::Problem;
use crate::schedule::Trajectory;

/// What one trial drew.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Draw {
    /// Trial index.
    pub trial: usize,
    /// Mass of each half, kg (of the `[cat]` shorthand on unequal halves, [`drawn_cat`]).
    pub mass: f64,
    /// Length of each half, m (likewise).
    pub length: f64,
    /// Radius, m (likewise).
    pub radius: f64,
    /// Release spin, world frame, N·m·s.
    pub angular_momentum_nms: [f64; 3],
    /// Factors of each joint's servo gains (rapier's tracked trials only).
    pub gain: [f64; 2],
}

/// How one trial landed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Trial {
    /// What it drew.
    pub draw: Draw,
    /// Angle between A's final attitude and the target half turn, degrees.
    pub landing_error_deg: f64,
    /// `|twist| − 180°`, degrees (signed: negative is short of the half turn).
    pub twist_error_deg: f64,
    /// Swing of the spine, degrees.
    pub swing_deg: f64,
    /// Whether the exact engine met its tolerance (rapier's trials: always).
    pub converged: bool,
    /// What rapier's tracked run measured besides the attitude (absent for the exact engine).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tracked: Option<tracked::TrackFigures>,
}

/// Trial `k`'s draw around `problem` with `settings`.
pub fn draw(problem: &Problem, settings: &RobustSettings, k: usize) -> Draw {
    let mut g = SplitMix64::new(settings.seed ^ (k as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
    let factor = |g: &mut SplitMix64, pct: f64| 1.0 + g.uniform(-pct, pct) / 100.0;
    let (mass, length, radius) =
        (factor(&mut g, settings.mass_pct), factor(&mut g, settings.length_pct), factor(&mut g, settings.radius_pct));
    let l0 = problem.drop.angular_momentum;
    let angular_momentum_nms = std::array::from_fn(|i| l0[i] + settings.spin_sigma_nms * g.normal());
    // Drawn after the sizes and the spin, so that those stay what they were before the gains.
    let gain = [factor(&mut g, settings.gain_pct), factor(&mut g, settings.gain_pct)];
    Draw {
        trial: k,
        mass: problem.cat.mass * mass,
        length: problem.cat.length * length,
        radius: problem.cat.radius * radius,
        angular_momentum_nms,
        gain,
    }
}

/// The cat of `draw` around `problem`'s: on the paper's cat its halves are the drawn `[cat]`;
/// on any other model each half's mass, length and radius are scaled by the factors the draw
/// applied to the `[cat]` shorthand (both halves alike), on the problem's joint.
pub fn drawn_cat(problem: &Problem, draw: &Draw) -> Cat {
    let drawn = Cylinder { mass: draw.mass, length: draw.length, radius: draw.radius };
    if problem.cat.is_paper() {
        return Cat::from(drawn);
    }
    let s = &problem.cat;
    let scaled = |c: Cylinder| Cylinder {
        mass: c.mass * (draw.mass / s.mass),
        length: c.length * (draw.length / s.length),
        radius: c.radius * (draw.radius / s.radius),
    };
    Cat { front: scaled(s.front()), rear: scaled(s.rear()), joint: s.joint }
}

/// Runs `traj` open loop on the cat and spin of `draw` (the paper's cat through the
/// two-cylinder engine, any other two-motor model through the general core); refused when the
/// problem's joint has not two motors.
pub fn trial(problem: &Problem, traj: &(impl Trajectory + Sync), draw: Draw) -> Result<Trial, ModelError> {
    let cat = drawn_cat(problem, &draw);
    let spin = Vector3::from(draw.angular_momentum_nms);
    let flip = match cat.paper() {
        Some(half) => released_on(&TwoMotorCat::paper(*half), traj, &spin, problem.exact.tolerance).0,
        None => TwoMotorCat::new(cat)?.flip_released(traj, &spin, problem.exact.tolerance),
    };
    let (landing_error_deg, twist_error_deg, swing_deg) = landing_figures(&flip.orientation, flip.twist, flip.swing);
    Ok(Trial { draw, landing_error_deg, twist_error_deg, swing_deg, converged: flip.converged, tracked: None })
}

/// Percentiles of one landing figure, degrees.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Percentiles {
    /// Median.
    pub p50: f64,
    /// 90th percentile.
    pub p90: f64,
    /// 95th percentile.
    pub p95: f64,
    /// 99th percentile.
    pub p99: f64,
    /// Largest.
    pub max: f64,
}

impl Percentiles {
    /// Of `values` (nearest-rank percentiles of the sorted values; not empty).
    pub fn of(values: &[f64]) -> Percentiles {
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        let rank = |p: f64| v[((p / 100.0 * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1];
        Percentiles { p50: rank(50.0), p90: rank(90.0), p95: rank(95.0), p99: rank(99.0), max: rank(100.0) }
    }
}

/// Which engine a check's trials ran through.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Engine {
    /// The exact engine, ideal tracking.
    Exact,
    /// Rapier, tracked by the controller through the actuators ([`tracked`]).
    Rapier,
    /// Rapier, the plan corrected by feedback on the attitude
    /// ([`crate::engines::rapier::feedback`]).
    RapierFeedback,
}

impl Engine {
    /// In words, for tables.
    pub fn describe(self) -> &'static str {
        match self {
            Engine::Exact => "exact engine, ideal tracking",
            Engine::Rapier => "rapier, tracked with motors",
            Engine::RapierFeedback => "rapier, attitude feedback",
        }
    }

    /// Its name in the CSV.
    pub fn key(self) -> &'static str {
        match self {
            Engine::Exact => "exact",
            Engine::Rapier => "rapier",
            Engine::RapierFeedback => "rapier-feedback",
        }
    }
}

/// One engine's check.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Robustness {
    /// Problem name.
    pub problem: String,
    /// What was run: the problem's own schedule, or an imported file.
    pub schedule: String,
    /// The settings.
    pub settings: RobustSettings,
    /// The engine of the trials.
    pub engine: Engine,
    /// The nominal cat's landing (no draw: the problem's cat and spin).
    pub nominal: Trial,
    /// Landing error percentiles, degrees.
    pub landing_error_deg: Percentiles,
    /// `| |twist| − 180° |` percentiles, degrees.
    pub twist_error_deg: Percentiles,
    /// Swing percentiles, degrees.
    pub swing_deg: Percentiles,
    /// Fraction of the trials within `tolerance_deg`.
    pub within: f64,
    /// Trials whose exact engine did not meet its tolerance.
    pub not_converged: usize,
    /// The worst trials, worst first (at most [`WORST`]).
    pub worst: Vec<Trial>,
    /// Every trial, in order.
    #[serde(skip)]
    pub trials: Vec<Trial>,
    /// The verdict in words.
    pub verdict: String,
    /// Rapier's tracked trials: tracking, saturation and (with `landing`) touch-down figures.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tracking: Option<tracked::TrackingSummary>,
    /// Rapier's tracked trials: the poses a filmstrip of the worst trial and the touch-down
    /// frames are drawn from.
    #[serde(skip)]
    pub film: Option<tracked::Film>,
    /// Whether the problem's halves differ (then a [`Draw`]'s sizes are the `[cat]` shorthand's).
    #[serde(skip)]
    pub unequal_halves: bool,
}

/// Worst trials reported.
pub const WORST: usize = 5;

/// The problem's own cat and spin, gains as set: trial 0's place without a draw.
pub fn nominal_draw(problem: &Problem) -> Draw {
    Draw {
        trial: 0,
        mass: problem.cat.mass,
        length: problem.cat.length,
        radius: problem.cat.radius,
        angular_momentum_nms: problem.drop.angular_momentum,
        gain: [1.0; 2],
    }
}

/// Runs the check of `traj` (named `schedule`) on `problem` with its `[robust]` settings,
/// through the exact engine (ideal tracking), on any two-motor cat.
pub fn robustness(
    problem: &Problem,
    traj: &(impl Trajectory + Sync),
    schedule: &str,
) -> Result<Robustness, ModelError> {
    let settings = problem.robust;
    let nominal = trial(problem, traj, nominal_draw(problem))?;
    let trials = (0..settings.trials)
        .into_par_iter()
        .map(|k| trial(problem, traj, draw(problem, &settings, k)))
        .collect::<Result<Vec<Trial>, _>>()?;
    Ok(summarise(problem, schedule, Engine::Exact, nominal, trials))
}

/// The percentiles, the worst trials and the verdict of one engine's trials.
pub(crate) fn summarise(
    problem: &Problem,
    schedule: &str,
    engine: Engine,
    nominal: Trial,
    trials: Vec<Trial>,
) -> Robustness {
    let settings = problem.robust;
    let errors: Vec<f64> = trials.iter().map(|t| t.landing_error_deg).collect();
    let twist: Vec<f64> = trials.iter().map(|t| t.twist_error_deg.abs()).collect();
    let swing: Vec<f64> = trials.iter().map(|t| t.swing_deg).collect();
    let inside = errors.iter().filter(|e| **e <= settings.tolerance_deg).count();
    let within = inside as f64 / trials.len().max(1) as f64;
    let mut worst = trials.clone();
    worst.sort_by(|a, b| b.landing_error_deg.total_cmp(&a.landing_error_deg));
    worst.truncate(WORST);
    let not_converged = trials.iter().filter(|t| !t.converged).count();
    let landing_error_deg = Percentiles::of(&errors);
    let verdict = format!(
        "lands within {}° in {:.1} % of {} trials (95th percentile {:.2}°; nominal cat {:.2}°)",
        settings.tolerance_deg,
        100.0 * within,
        trials.len(),
        landing_error_deg.p95,
        nominal.landing_error_deg
    );
    Robustness {
        problem: problem.name.clone(),
        schedule: schedule.to_string(),
        settings,
        engine,
        nominal,
        landing_error_deg,
        twist_error_deg: Percentiles::of(&twist),
        swing_deg: Percentiles::of(&swing),
        within,
        not_converged,
        worst,
        trials,
        verdict,
        tracking: None,
        film: None,
        unequal_halves: !problem.cat.model().has_equal_halves(),
    }
}

/// The landing error of A's final attitude `r` with its continued twist and swing (rad):
/// the angle of `R_*⁻¹ R` to the target `R_* = Rz(π)`, `|twist| − 180°` and the swing, degrees.
pub(crate) fn landing_figures(r: &UnitQuaternion<f64>, twist: f64, swing: f64) -> (f64, f64, f64) {
    let target = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), PI);
    ((target.inverse() * r).angle().to_degrees(), twist.abs().to_degrees() - 180.0, swing.to_degrees())
}

/// The check as `[robust] engine` asks: the exact engine's, rapier's tracked one, or both.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RobustReport {
    /// One check per engine run, exact first.
    pub checks: Vec<Robustness>,
    /// The command that regenerates the report (empty when none was given, and then left out
    /// of the JSON).
    #[serde(skip_serializing_if = "String::is_empty")]
    pub command: String,
}

/// The least and the most a schedule given to `robust` may last, as multiples of the fall: each
/// trial runs it to its end, so one of a thousand falls (times in milliseconds) would run for
/// hours, warned of and then waited on.
pub const FALL_MULTIPLES: [f64; 2] = [0.5, 2.0];

/// Refuses, in words, a schedule `traj` whose duration is outside [`FALL_MULTIPLES`] of the
/// problem's fall.
pub fn fits_the_fall(problem: &Problem, traj: &impl Trajectory) -> Result<(), String> {
    use crate::numeric::numfmt::{echo, sig};
    let (lasts, fall) = (traj.total_duration(), problem.drop.fall_time());
    let [least, most] = FALL_MULTIPLES;
    if (least * fall..=most * fall).contains(&lasts) {
        return Ok(());
    }
    Err(format!(
        "the schedule lasts {} s, the fall {} s (drop.height = {} m, drop.gravity = {} m/s²): robust runs each trial to the schedule's end, so a schedule more than {most} or less than {least} times the fall is refused; write its times in seconds over this fall",
        sig(lasts, 6),
        sig(fall, 6),
        echo(problem.drop.height),
        echo(problem.drop.gravity)
    ))
}

/// Runs the engines `problem.robust.engine` names on `traj` (named `schedule`).
pub fn check(
    problem: &Problem,
    traj: &(impl Trajectory + Sync),
    schedule: &str,
) -> Result<RobustReport, crate::engines::rapier::RapierError> {
    problem.validate_robust_draws()?;
    let engine = problem.robust.engine;
    if engine.rapier() {
        problem.require_paper_cat(
            "robust.engine = \"rapier\" or \"both\" (its tracked rapier scene; \"exact\" runs on every two-motor cat)",
        )?;
    }
    let mut checks = Vec::new();
    if engine.exact() {
        checks.push(robustness(problem, traj, schedule)?);
    }
    if engine.rapier() {
        checks.extend(tracked::tracked_robustness(problem, traj, schedule)?);
    }
    Ok(RobustReport { checks, command: String::new() })
}
