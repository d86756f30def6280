//! The robustness check with real motors and sensors: every trial a rapier run in which the
//! schedule is tracked by a controller (issue 21 §2), optionally ending on the ground (§4).
//!
//! The plan is the schedule on the step grid `h = T/⌈T/robust.dt_s⌉` with the feed-forward the
//! *nominal* cat needs (the problem's cat and release spin: what the plan would command), shared
//! by every trial ([`crate::engines::rapier::Plan`]). Trial `k` draws its cat, its spin and its
//! two joints' gain factors from its own stream ([`super::draw`]), and runs
//! [`crate::engines::rapier::track()`] with a [`FeedForwardPd`] whose gains are the servo's
//! (`robust.servo_hz`, `robust.servo_damping` on the nominal cat, [`PdGains::servo`]) times its
//! factors, the problem's actuators, and an attitude sensor `robust.attitude_latency_s` late with
//! `robust.attitude_noise_deg` of noise per axis (its own stream, seeded from the trial's). The
//! landing error is measured at the schedule's end exactly as the exact engine's
//! (`landing_figures`).
//!
//! What the trials add to the exact engine's check: the servo's tracking error, the torque the
//! actuators delivered and how often they saturated, and with `robust.landing` the touch-down
//! (time, first part, impact speed, feet-down angles; [`crate::engines::rapier::ground`]). The
//! worst trial is run again keeping its poses, for a filmstrip. Every number depends on the seed
//! only: the trials are independent, collected in order.

use nalgebra::Vector3;
use rayon::prelude::*;
use serde::Serialize;

use super::{draw, landing_figures, nominal_draw, summarise, Draw, Engine, Percentiles, Robustness, Trial};
use crate::engines::rapier::{
    track, AttitudeSensor, FeedForwardPd, Feedback, FeedbackPlan, FeedbackSettings, Landing, Part, PdGains, Plan,
    RapierError, RapierOptions, Snapshot, Touchdown, TrackOptions, TrackedRun, MAX_STEPS,
};
use crate::model::Cylinder;
use crate::problem::Problem;
use crate::schedule::Trajectory;

/// Panels of the worst trial's filmstrip.
pub const FILM_PANELS: usize = 6;

/// What one tracked trial measured besides its attitude.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TrackFigures {
    /// `max_k |q_k − q*(t_k)|` per joint, degrees.
    pub tracking_error_deg: [f64; 2],
    /// Largest torque applied per joint, N·m.
    pub peak_torque_nm: [f64; 2],
    /// Fraction of the steps each joint's actuator saturated.
    pub saturated: [f64; 2],
    /// The touch-down (with `robust.landing`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub touchdown: Option<Touchdown>,
    /// The feedback's largest joint correction `|δq_r|` per joint, degrees (feedback trials).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub correction_deg: Option<[f64; 2]>,
}

/// The landings of the tracked trials.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LandingSummary {
    /// Fraction of the trials that touched down on their feet.
    pub on_its_feet: f64,
    /// Touch-down time percentiles, s (none without a touch-down).
    pub time_s: Option<Percentiles>,
    /// Impact speed percentiles, m/s.
    pub impact_speed: Option<Percentiles>,
    /// Percentiles of the larger of the two halves' feet-down angles, degrees.
    pub feet_down_deg: Option<Percentiles>,
    /// How many trials touched first with each part (parts that never did left out).
    pub first_part: Vec<(Part, usize)>,
    /// Trials that had not touched down by the end of the run.
    pub no_touchdown: usize,
    /// The verdict in words.
    pub verdict: String,
}

/// The tracked trials' summary beyond the landing error.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrackingSummary {
    /// Rapier's step, s.
    pub dt_s: f64,
    /// Steps of the schedule.
    pub steps: usize,
    /// The servo's gains before the trials' factors.
    pub gains: PdGains,
    /// Percentiles of the larger joint's tracking error, degrees.
    pub tracking_error_deg: Percentiles,
    /// Trials in which an actuator saturated at least once.
    pub saturated_trials: usize,
    /// Largest torque applied in any trial, N·m.
    pub peak_torque_nm: f64,
    /// The landings, with `robust.landing`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub landing: Option<LandingSummary>,
    /// The feedback's regulator (feedback trials).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub feedback: Option<FeedbackSummary>,
}

/// The feedback's regulator and what it did over the trials.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FeedbackSummary {
    /// Its settings (the filter's noise is the sensor's).
    pub settings: FeedbackSettings,
    /// The regulator's step, s.
    pub control_dt_s: f64,
    /// The interval between re-plans of the rest of the fall, s (none: the gains solved once
    /// along the plan).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub replan_dt_s: Option<f64>,
    /// The largest entry of any gain `K_i` along the plan (bounded to the end of the fall).
    pub largest_gain: f64,
    /// Percentiles of the larger joint's largest correction, degrees.
    pub correction_deg: Percentiles,
}

/// Poses for the pictures: the worst trial along its fall, and touch-downs.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// The worst trial's index.
    pub worst_trial: usize,
    /// Its poses at [`FILM_PANELS`] instants (and its touch-down, with a landing), s.
    pub worst: Vec<(f64, Snapshot)>,
    /// Touch-down poses, labelled (the nominal cat's, the worst trial's).
    pub touchdowns: Vec<(String, f64, Snapshot)>,
}

/// Everything a tracked trial shares: the plan, the servo, the run's options, and the
/// feedback's regulator when one is asked for.
struct Setup {
    plan: Plan,
    gains: PdGains,
    options: TrackOptions,
    nominal: Cylinder,
    feedback: Option<FeedbackPlan>,
}

impl Setup {
    fn new(problem: &Problem, traj: &(impl Trajectory + Sync)) -> Result<Setup, RapierError> {
        let s = &problem.robust;
        let duration = traj.total_duration();
        let steps = (duration / s.dt_s).ceil();
        if !(steps.is_finite() && steps >= 1.0) {
            return Err(RapierError::BadDuration(duration));
        }
        if steps > MAX_STEPS as f64 {
            return Err(RapierError::TooManySteps { dt: s.dt_s, duration, steps, max: MAX_STEPS });
        }
        let plan = Plan::new(&problem.cat.half(), traj, &problem.drop.spin(), problem.exact.tolerance, steps as usize);
        let landing = s.landing.then_some(Landing {
            height: problem.drop.height,
            gravity: problem.drop.gravity,
            feet_down_deg: s.feet_down_deg,
        });
        let options = TrackOptions {
            cross_mass_fraction: problem.rapier.cross_mass_fraction,
            pgs_iterations: RapierOptions::default().pgs_iterations,
            motors: problem.actuator.motors(),
            spin: Vector3::zeros(),
            sensor: AttitudeSensor { latency: s.attitude_latency_s, noise: s.attitude_noise_deg.to_radians(), seed: 0 },
            landing,
            keep_poses_at: Vec::new(),
        };
        let feedback = s.controller.feedback().then(|| {
            let settings = FeedbackSettings {
                rate_hz: s.feedback_hz,
                replan_hz: s.feedback_replan_hz,
                attitude: s.feedback_attitude_deg.to_radians(),
                joint: s.feedback_joint_deg.to_radians(),
                accel: s.feedback_accel,
                spin_prior: s.feedback_spin_prior_nms,
                sensor_noise: s.attitude_noise_deg.to_radians(),
            };
            FeedbackPlan::new(&problem.cat.half(), traj, &problem.drop.spin(), problem.exact.tolerance, &plan, settings)
        });
        let gains = PdGains::servo(&problem.cat.half(), s.servo_hz, s.servo_damping);
        Ok(Setup { plan, gains, options, nominal: problem.cat.half(), feedback })
    }

    /// Runs one draw (its sensor noise seeded by `noise_seed`) under the open loop or the
    /// feedback, keeping poses at `keep`.
    fn run(
        &self,
        d: &Draw,
        noise_seed: u64,
        keep: Vec<f64>,
        feedback: bool,
    ) -> Result<(Trial, TrackedRun), RapierError> {
        let cat = Cylinder { mass: d.mass, length: d.length, radius: d.radius };
        let mut options = self.options.clone();
        options.spin = Vector3::from(d.angular_momentum_nms);
        options.sensor.seed = noise_seed;
        options.keep_poses_at = keep;
        let servo = self.gains.scaled(d.gain);
        let (run, correction_deg) = match self.feedback.as_ref().filter(|_| feedback) {
            Some(fb) => {
                let mut controller = Feedback::new(&self.plan, fb, servo, &self.nominal);
                let run = track(&cat, &self.plan, &mut controller, &options)?;
                (run, Some(controller.log().largest_correction.map(f64::to_degrees)))
            }
            None => (track(&cat, &self.plan, &mut FeedForwardPd::new(&self.plan, servo), &options)?, None),
        };
        let (landing_error_deg, twist_error_deg, swing_deg) = landing_figures(&run.orientation, run.twist, run.swing);
        let figures = TrackFigures {
            tracking_error_deg: run.tracking_error.map(f64::to_degrees),
            peak_torque_nm: run.peak_torque,
            saturated: run.saturated,
            touchdown: run.touchdown,
            correction_deg,
        };
        let trial =
            Trial { draw: *d, landing_error_deg, twist_error_deg, swing_deg, converged: true, tracked: Some(figures) };
        Ok((trial, run))
    }
}

/// The seed of trial `k`'s sensor noise (`None`: the nominal cat's), apart from its draws.
fn noise_seed(seed: u64, k: Option<usize>) -> u64 {
    let k = k.map_or(u64::MAX, |k| k as u64);
    (seed ^ 0xA076_1D64_78BD_642F).wrapping_add(k.wrapping_mul(0xE703_7ED1_A0B4_28DB))
}

/// The checks of `traj` (named `schedule`) on `problem` through rapier's tracked runs, one per
/// controller `robust.controller` names (open loop first), on the same draws and sensor noise.
pub fn tracked_robustness(
    problem: &Problem,
    traj: &(impl Trajectory + Sync),
    schedule: &str,
) -> Result<Vec<Robustness>, RapierError> {
    let setup = Setup::new(problem, traj)?;
    let c = problem.robust.controller;
    let mut checks = Vec::new();
    for feedback in [false, true] {
        if (feedback && c.feedback()) || (!feedback && c.open_loop()) {
            checks.push(controlled(problem, traj, schedule, &setup, feedback)?);
        }
    }
    Ok(checks)
}

fn controlled(
    problem: &Problem,
    traj: &(impl Trajectory + Sync),
    schedule: &str,
    setup: &Setup,
    feedback: bool,
) -> Result<Robustness, RapierError> {
    let settings = problem.robust;
    // A diverged run names its trial, its controller and the step.
    let named = |trial: String| {
        move |e: RapierError| match e {
            RapierError::Diverged(at) => RapierError::TrialDiverged {
                trial,
                controller: if feedback { "attitude feedback" } else { "open loop" },
                at,
                dt: settings.dt_s,
            },
            other => other,
        }
    };
    let trials = (0..settings.trials)
        .into_par_iter()
        .map(|k| {
            let d = draw(problem, &settings, k);
            let run = setup.run(&d, noise_seed(settings.seed, Some(k)), Vec::new(), feedback);
            run.map(|r| r.0).map_err(named(format!("trial {}", k + 1)))
        })
        .collect::<Result<Vec<Trial>, RapierError>>()?;
    let (nominal, nominal_run) = setup
        .run(&nominal_draw(problem), noise_seed(settings.seed, None), Vec::new(), feedback)
        .map_err(named("the nominal cat".to_string()))?;
    let engine = if feedback { Engine::RapierFeedback } else { Engine::Rapier };
    let mut check = summarise(problem, schedule, engine, nominal, trials);

    let figures: Vec<TrackFigures> = check.trials.iter().filter_map(|t| t.tracked).collect();
    let worst_tracking: Vec<f64> =
        figures.iter().map(|f| f.tracking_error_deg[0].max(f.tracking_error_deg[1])).collect();
    let landing = settings.landing.then(|| landing_summary(&figures, settings.feet_down_deg));
    check.tracking = Some(TrackingSummary {
        dt_s: setup.plan.dt,
        steps: setup.plan.steps(),
        gains: setup.gains,
        tracking_error_deg: Percentiles::of(&worst_tracking),
        saturated_trials: figures.iter().filter(|f| f.saturated.iter().any(|s| *s > 0.0)).count(),
        peak_torque_nm: figures.iter().map(|f| f.peak_torque_nm[0].max(f.peak_torque_nm[1])).fold(0.0, f64::max),
        landing,
        feedback: setup.feedback.as_ref().filter(|_| feedback).map(|fb| FeedbackSummary {
            settings: fb.settings,
            control_dt_s: fb.linearisation.dt,
            replan_dt_s: fb.replan_every().map(|every| every as f64 * fb.linearisation.dt),
            largest_gain: fb.largest_gain(),
            correction_deg: Percentiles::of(
                &figures.iter().filter_map(|f| f.correction_deg).map(|c| c[0].max(c[1])).collect::<Vec<f64>>(),
            ),
        }),
    });

    // The worst trial again, keeping its poses.
    if let Some(w) = check.worst.first() {
        let k = w.draw.trial;
        let duration = traj.total_duration();
        let at = (0..FILM_PANELS).map(|i| duration * i as f64 / (FILM_PANELS - 1) as f64).collect();
        let (_, run) = setup.run(&w.draw, noise_seed(settings.seed, Some(k)), at, feedback)?;
        let mut touchdowns = Vec::new();
        let mut worst = run.poses.clone();
        if let Some(td) = run.touchdown {
            worst.retain(|p| p.0 <= td.time || (p.0 - td.time).abs() < setup.plan.dt);
            if let Some(pose) = run.poses.iter().find(|p| (p.0 - td.time).abs() <= setup.plan.dt) {
                touchdowns.push((format!("trial {k} (worst)"), td.time, pose.1));
            }
        }
        if let Some(td) = nominal_run.touchdown {
            if let Some(pose) = nominal_run.poses.iter().find(|p| (p.0 - td.time).abs() <= setup.plan.dt) {
                touchdowns.insert(0, ("nominal cat".to_string(), td.time, pose.1));
            }
        }
        check.film = Some(Film { worst_trial: k, worst, touchdowns });
    }
    Ok(check)
}

fn landing_summary(figures: &[TrackFigures], feet_down_deg: f64) -> LandingSummary {
    let downs: Vec<Touchdown> = figures.iter().filter_map(|f| f.touchdown).collect();
    let n = figures.len().max(1) as f64;
    let feet = downs.iter().filter(|d| d.on_its_feet).count();
    let of = |f: &dyn Fn(&Touchdown) -> f64| {
        let v: Vec<f64> = downs.iter().map(f).collect();
        (!v.is_empty()).then(|| Percentiles::of(&v))
    };
    let parts = [Part::FrontPaw, Part::HindPaw, Part::FrontBody, Part::RearBody];
    let first_part =
        parts.iter().map(|p| (*p, downs.iter().filter(|d| d.part == *p).count())).filter(|(_, c)| *c > 0).collect();
    let on_its_feet = feet as f64 / n;
    LandingSummary {
        on_its_feet,
        time_s: of(&|d| d.time),
        impact_speed: of(&|d| d.impact_speed),
        feet_down_deg: of(&|d| d.feet_down_deg[0].max(d.feet_down_deg[1])),
        first_part,
        no_touchdown: figures.len() - downs.len(),
        verdict: format!(
            "lands on its feet (both halves' feet within {feet_down_deg}° of down at touch-down) in {:.1} % of {} trials",
            100.0 * on_its_feet,
            figures.len()
        ),
    }
}
