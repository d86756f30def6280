//! Verification of schedules in rapier3d (f64): an independent multibody simulator tracks the
//! joint trajectory with motors, and we measure how the cat turns (DESIGN.md §6).
//!
//! (Documentation in progress.)

mod measure;
mod scene;

pub use measure::{angular_momentum, kinetic_energy, observed_orders, TorqueEstimator, TorqueSample};
pub use scene::{BodyState, CatScene, MassModel, MotorGains, Snapshot, NDOFS};

use nalgebra::UnitQuaternion;
use serde::{Serialize, Serializer};

use crate::model::Cylinder;
use crate::orientation::TwistTracker;
use crate::problem::ProblemError;
use crate::schedule::{Phase, Schedule};
use crate::settings::RapierSettings;

/// Why a rapier run could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RapierError {
    /// The settings are out of range.
    #[error(transparent)]
    Settings(#[from] ProblemError),
    /// Rapier refused to build a joint.
    #[error("rapier refused {0}")]
    JointRejected(&'static str),
    /// Part of the scene was not found where it was built.
    #[error("rapier lost {0}")]
    Missing(&'static str),
    /// The schedule has no positive, finite duration.
    #[error("the schedule's duration {0} s is not positive and finite")]
    BadDuration(f64),
    /// The requested step needs more steps than a run allows.
    #[error("dt = {dt} s over {duration} s needs {steps} steps, more than the {max} allowed")]
    TooManySteps {
        /// Requested step, s.
        dt: f64,
        /// Duration, s.
        duration: f64,
        /// Steps needed.
        steps: f64,
        /// Limit.
        max: usize,
    },
    /// The simulation produced non-finite numbers.
    #[error("the simulation diverged at t = {0} s")]
    Diverged(f64),
}

/// Most steps a run may take.
pub const MAX_STEPS: usize = 20_000_000;

/// One sample of the orientation history.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TwistSample {
    /// Time, s.
    pub t: f64,
    /// Twist of A about its initial spine axis (continued), rad.
    pub twist: f64,
    /// Swing of A's spine axis, rad.
    pub swing: f64,
}

/// Peak joint torques per phase, N·m.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Default)]
pub struct PhasePeaks {
    /// `max |τ_i|` in the bend phase, per joint.
    pub bend: [f64; 2],
    /// In the twist phase.
    pub twist: [f64; 2],
    /// In the unbend phase.
    pub unbend: [f64; 2],
    /// Over everything.
    pub max: f64,
}

impl PhasePeaks {
    fn add(&mut self, phase: Phase, tau: [f64; 2]) {
        let slot = match phase {
            Phase::Bend => &mut self.bend,
            Phase::Twist => &mut self.twist,
            Phase::Unbend => &mut self.unbend,
        };
        for i in 0..2 {
            slot[i] = slot[i].max(tau[i].abs());
            self.max = self.max.max(tau[i].abs());
        }
    }
}

/// Angular-momentum bookkeeping of a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MomentumDrift {
    /// `max_k |H_k − H_0|`, N·m·s.
    pub max_abs: f64,
    /// Reference momentum `I* · max|q̇|`, N·m·s.
    pub reference: f64,
    /// `max_abs / reference`.
    pub max_rel: f64,
}

/// Everything measured in one rapier run.
#[derive(Clone, Debug, Serialize)]
pub struct RapierRun {
    /// The step asked for, s.
    pub dt_requested: f64,
    /// The step used, `T / ceil(T / dt_requested)`, s.
    pub dt: f64,
    /// Number of steps.
    pub steps: usize,
    /// Motor gains.
    pub gains: MotorGains,
    /// Gauss–Seidel sweeps per step.
    pub pgs_iterations: usize,
    /// A's final orientation, serialised as `[w, x, y, z]`.
    #[serde(serialize_with = "quat_wxyz")]
    pub orientation: UnitQuaternion<f64>,
    /// Final twist, rad.
    pub twist: f64,
    /// Final swing, rad.
    pub swing: f64,
    /// Twist and swing along the run.
    pub twist_history: Vec<TwistSample>,
    /// Joint angles reached at the end, rad.
    pub final_q: [f64; 2],
    /// `max_t |q_sim − q_sched|` per joint, rad.
    pub tracking_error: [f64; 2],
    /// Angular-momentum drift.
    pub momentum: MomentumDrift,
    /// Peak joint torques.
    pub peak_torque: PhasePeaks,
    /// Joint torques along the run.
    pub torque_history: Vec<TorqueSample>,
}

fn quat_wxyz<S: Serializer>(q: &UnitQuaternion<f64>, s: S) -> Result<S::Ok, S::Error> {
    [q.w, q.i, q.j, q.k].serialize(s)
}

/// Options of the run that are not problem settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunOptions {
    /// `ω_n · dt` of the motors.
    pub bandwidth_per_step: f64,
    /// Damping ratio.
    pub damping_ratio: f64,
    /// Gauss–Seidel sweeps per step.
    pub pgs_iterations: usize,
    /// Most history samples kept.
    pub history: usize,
    /// Whether the position target is shifted by `−dt·q̇` (see the module docs).
    pub shift_target: bool,
    /// Solver substeps per step.
    pub substeps: usize,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self { bandwidth_per_step: 1.0, damping_ratio: 1.0, pgs_iterations: 8, history: 2000, shift_target: true, substeps: 1 }
    }
}

/// Runs a schedule in rapier with the default options.
pub fn simulate(cat: &Cylinder, schedule: &Schedule, settings: &RapierSettings) -> Result<RapierRun, RapierError> {
    simulate_with(cat, schedule, settings, &RunOptions::default())
}

/// Runs a schedule in rapier.
pub fn simulate_with(
    cat: &Cylinder,
    schedule: &Schedule,
    settings: &RapierSettings,
    opts: &RunOptions,
) -> Result<RapierRun, RapierError> {
    settings.validate()?;
    let duration = schedule.duration();
    if !(duration.is_finite() && duration > 0.0) {
        return Err(RapierError::BadDuration(duration));
    }
    let steps_f = (duration / settings.dt).ceil();
    if !(steps_f <= MAX_STEPS as f64) {
        return Err(RapierError::TooManySteps { dt: settings.dt, duration, steps: steps_f, max: MAX_STEPS });
    }
    let n = (steps_f as usize).max(1);
    let dt = duration / n as f64;
    let gains = MotorGains::new(opts.bandwidth_per_step / dt, opts.damping_ratio);
    let start = schedule.state(0.0);
    let mut scene = CatScene::new(cat, settings.cross_mass_fraction, dt, opts.substeps, opts.pgs_iterations, Some(gains), start.q)?;
    let masses = *scene.masses();

    let reference = cat.end_transverse()
        * (0..=n)
            .map(|k| schedule.state(k as f64 * dt).qd.iter().fold(0.0f64, |a, v| a.max(v.abs())))
            .fold(0.0f64, f64::max);

    let stride = n.div_ceil(opts.history.max(1)).max(1);
    let mut tracker = TwistTracker::default();
    let mut torques = TorqueEstimator::default();
    let mut peaks = PhasePeaks::default();
    let mut twist_history = Vec::new();
    let mut torque_history = Vec::new();
    let mut tracking = [0.0f64; 2];
    let mut h0 = None;
    let mut drift = 0.0f64;
    let mut last = (UnitQuaternion::identity(), 0.0, 0.0, [0.0; 2]);

    for k in 0..=n {
        let t = if k == n { duration } else { k as f64 * dt };
        if k > 0 {
            let h = dt / opts.substeps.max(1) as f64;
            let t0 = t - dt;
            let (pos, vel) = if opts.shift_target {
                let tq = t0 + 0.5 * dt + 0.5 * h;
                let sv = schedule.state(t0 + 0.5 * dt).qd;
                let sq = schedule.state(tq).q;
                ([sq[0] - h * sv[0], sq[1] - h * sv[1]], sv)
            } else {
                let target = schedule.state(t);
                (target.q, target.qd)
            };
            scene.set_targets(pos, vel)?;
            scene.step();
        }
        let snap = scene.snapshot()?;
        if !snap.velocities.iter().all(|v| v.is_finite()) || !snap.positions[2].iter().all(|v| v.is_finite()) {
            return Err(RapierError::Diverged(t));
        }
        let bodies = snap.bodies(&masses);
        let h = angular_momentum(&masses, &bodies);
        let h0v = *h0.get_or_insert(h);
        drift = drift.max((h - h0v).norm());
        let st = tracker.update(&snap.rotations[0]);
        let sched = schedule.state(t).q;
        for i in 0..2 {
            tracking[i] = tracking[i].max((snap.q[i] - sched[i]).abs());
        }
        if k % stride == 0 || k == n {
            twist_history.push(TwistSample { t, twist: st.twist, swing: st.swing });
        }
        if let Some(sample) = torques.push(&masses, t, &snap) {
            peaks.add(schedule.locate(sample.t).0, sample.tau);
            if k % stride == 0 {
                torque_history.push(sample);
            }
        }
        last = (snap.rotations[0], st.twist, st.swing, snap.q);
    }

    Ok(RapierRun {
        dt_requested: settings.dt,
        dt,
        steps: n,
        gains,
        pgs_iterations: opts.pgs_iterations,
        orientation: last.0,
        twist: last.1,
        swing: last.2,
        twist_history,
        final_q: last.3,
        tracking_error: tracking,
        momentum: MomentumDrift {
            max_abs: drift,
            reference,
            max_rel: if reference > 0.0 { drift / reference } else { f64::NAN },
        },
        peak_torque: peaks,
        torque_history,
    })
}
