//! One exact evaluation of a schedule: what every command reports about it.
//!
//! For a schedule on a cat, the exact engine gives
//! - the reorientation: signed twist about A's initial `+z` and swing of the spine axis (rad),
//!   from the adaptive Magnus integration ([`crate::engines::exact::flip`]) to
//!   `exact.tolerance`, with its error estimate and whether it met the tolerance;
//! - the peak motor torques per phase and joint ([`PhasePeaks`], N·m) from Newton–Euler on the
//!   zero-momentum motion, sampled by the schedule's own time scale
//!   ([`crate::engines::torque::piece_samples`]: `exact.torque_samples` per phase at least, 64
//!   per radian the bend direction turns), with their stated accuracy, and the largest
//!   action–reaction gap;
//! - what it asks of the motors ([`MotorDemand`]): peak speed and power per joint, and with
//!   `[actuator]` limits each limit's worst usage and the least slow-down within them;
//! - the joint-rate jumps (impulses `M(q) Δq̇`, N·m·s) larger than [`JUMP_TOLERANCE`];
//! - `momentum_max`: the largest `|H|` about the centre of mass along the motion, relative to a
//!   half's typical momentum `I* · max|q̇|` (`I*` the end-transverse inertia; zero in exact
//!   arithmetic); released with spin `L`, the largest `|R H − L|` (the momentum stays `L`),
//!   relative to `max(I* · max|q̇|, |L|)`.
//!
//! Released with spin (`[drop] angular_momentum`), the flip, the torques and the motor demand are
//! those of the spinning motion ([`crate::engines::spin`]).
//!
//! Any two-motor cat model (`[cat] joint`, unequal halves) is measured the same way by
//! [`Evaluation::of_model`]: the general core ([`crate::engines::models::TwoMotorCat`]) gives the
//! flip, the torques, the reduced mass matrix of the jumps and the momentum (relative to the rear
//! half's `I*`); the paper's cat goes through the two-cylinder engine, its numbers unchanged.
//!
//! [`CompareRow`] is the same evaluation as a row of the peak-torque table, with the peak
//! torque of the paper's model `I* · max|ω̇| = I* C_a |D| / T²` beside it.

use std::time::Instant;

use nalgebra::Vector3;
use serde::Serialize;

use crate::engines::exact::{body_rate, body_rate_spinning, flip, momentum, Flip};
use crate::engines::models::{ModelError, TwoMotorCat};
use crate::engines::motors::{peaks_and_demand, MotorDemand};
use crate::engines::peaks::PhasePeaks;
use crate::engines::spin::SpinHistory;
use crate::engines::torque::{piece_samples, velocity_jumps, velocity_jumps_with, TorqueSource, VelocityJump};
use crate::engines::JUMP_TOLERANCE;
use crate::model::motor::Motors;
use crate::model::Cylinder;
use crate::problem::settings::ExactSettings;
use crate::schedule::variant::Origin;
use crate::schedule::{JointState, Phase, Schedule, Trajectory};

/// The exact engine's numbers on one schedule.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Evaluation {
    /// Twist, swing (rad), steps, error estimate and convergence of the integration.
    pub flip: Flip,
    /// Peak motor torques per phase and joint, N·m.
    pub peaks: PhasePeaks,
    /// Largest gap between the joint torques from B's and A's sides, N·m.
    pub action_reaction_gap: f64,
    /// Stated relative accuracy of the peaks
    /// ([`crate::engines::torque::PeakTorques::accuracy`]).
    pub peak_accuracy: f64,
    /// Peak speed and power per joint, and the usage of each motor limit.
    pub motors: MotorDemand,
    /// Joint-rate jumps (impulses); empty when the schedule is smooth.
    pub jumps: Vec<VelocityJump>,
    /// Largest angular momentum along the motion relative to `I* · max|q̇|`.
    pub momentum_max: f64,
    /// Wall-clock time of the flip, torques and jumps, s.
    pub run_time_s: f64,
}

impl Evaluation {
    /// Evaluates `schedule` on `cat` released with total angular momentum `spin` (N·m·s, world
    /// frame; zero for the zero-momentum flip) and driven by `motors`, with the exact engine's
    /// `settings`.
    pub fn new(
        cat: &Cylinder,
        schedule: &Schedule,
        spin: &Vector3<f64>,
        motors: &Motors,
        settings: &ExactSettings,
    ) -> Evaluation {
        let start = Instant::now();
        let (flip, history) = released_flip(cat, schedule, spin, settings.tolerance);
        let jumps = velocity_jumps(cat, schedule, JUMP_TOLERANCE);
        let momentum_max = momentum_check(cat, schedule, history.as_ref(), settings.torque_samples);
        let source = torque_source(cat, history.as_ref());
        Evaluation::measured((flip, jumps, momentum_max), &source, schedule, motors, settings, start)
    }

    /// [`Evaluation::new`] for any two-motor model `cat`: the paper's cat through
    /// [`Evaluation::new`] (the two-cylinder engine, its numbers to the last digit), any other
    /// model through the general core ([`TwoMotorCat`]), at zero angular momentum or released
    /// with `spin`.
    pub fn of_model(
        cat: &TwoMotorCat,
        schedule: &Schedule,
        spin: &Vector3<f64>,
        motors: &Motors,
        settings: &ExactSettings,
    ) -> Result<Evaluation, ModelError> {
        if let Some(half) = cat.cat().paper() {
            return Ok(Evaluation::new(half, schedule, spin, motors, settings));
        }
        let start = Instant::now();
        let jumps = velocity_jumps_with(|q, dq| cat.motor_impulse(q, dq), schedule, JUMP_TOLERANCE);
        let (flip, history) = released_on_model(cat, schedule, spin, settings.tolerance);
        let momentum = momentum_on_model(cat, schedule, spin, history.as_ref(), settings.torque_samples);
        let source = TorqueSource::model_released(cat, history.as_ref());
        Ok(Evaluation::measured((flip, jumps, momentum), &source, schedule, motors, settings, start))
    }

    /// The evaluation with the engine's `(flip, jumps, momentum_max)`: the peaks and the motor
    /// demand sampled from `source`, the run time since `start`.
    fn measured(
        (flip, jumps, momentum_max): (Flip, Vec<VelocityJump>, f64),
        source: &TorqueSource,
        schedule: &Schedule,
        motors: &Motors,
        settings: &ExactSettings,
        start: Instant,
    ) -> Evaluation {
        let samples = piece_samples(schedule, settings.torque_samples);
        let (peaks, motors) = peaks_and_demand(source, schedule, &samples, motors);
        Evaluation {
            flip,
            peaks: PhasePeaks::from_peaks(&peaks),
            action_reaction_gap: peaks.action_reaction_gap,
            peak_accuracy: peaks.accuracy,
            motors,
            jumps,
            momentum_max,
            run_time_s: start.elapsed().as_secs_f64(),
        }
    }

    /// Signed twist, degrees.
    pub fn twist_deg(&self) -> f64 {
        self.flip.twist.to_degrees()
    }

    /// Swing, degrees.
    pub fn swing_deg(&self) -> f64 {
        self.flip.swing.to_degrees()
    }

    /// Largest generalised impulse of a jump, N·m·s (0 when none).
    pub fn max_impulse(&self) -> f64 {
        self.jumps.iter().flat_map(|j| j.impulse).map(f64::abs).fold(0.0, f64::max)
    }
}

/// Largest `|H|` of the zero-momentum motion on `samples + 1` points per phase, relative to
/// `I* · max|q̇|` (absolute when the cat never moves).
pub fn momentum_max(cat: &Cylinder, schedule: &impl Trajectory, samples: usize) -> f64 {
    momentum_max_by(|st| momentum(cat, st, &body_rate(cat, st.q, st.qd)), cat.end_transverse(), schedule, samples)
}

/// Largest `|H(st)|` on `samples + 1` points per phase of `schedule`, relative to
/// `inertia · max|q̇|` (absolute when the cat never moves): [`momentum_max`] for any model's
/// momentum `h`.
pub fn momentum_max_by(
    h: impl Fn(&JointState) -> Vector3<f64>,
    inertia: f64,
    schedule: &impl Trajectory,
    samples: usize,
) -> f64 {
    let (mut h_max, mut qd_max) = (0.0f64, 0.0f64);
    for (piece, dur) in schedule.piece_durations().into_iter().enumerate() {
        for k in 0..=samples {
            let st = schedule.piece_state(piece, dur * k as f64 / samples as f64);
            h_max = h_max.max(h(&st).norm());
            qd_max = qd_max.max(st.qd[0].hypot(st.qd[1]));
        }
    }
    let reference = inertia * qd_max;
    if reference > 0.0 {
        h_max / reference
    } else {
        h_max
    }
}

/// The flip of `traj` released with angular momentum `spin` (world frame, N·m·s) to `tolerance`,
/// with the orientation history its torques need when `spin` is not zero
/// ([`crate::engines::exact::flip`] at zero, the Magnus engine).
pub fn released_flip(
    cat: &Cylinder,
    traj: &impl Trajectory,
    spin: &Vector3<f64>,
    tolerance: f64,
) -> (Flip, Option<SpinHistory>) {
    if spin.norm_squared() > 0.0 {
        let (f, history) = SpinHistory::new(cat, traj, spin, tolerance);
        (f, Some(history))
    } else {
        (flip(cat, traj, tolerance), None)
    }
}

/// [`released_flip`] on any two-motor model through the general core: the flip of `traj`
/// released with `spin` (world frame, N·m·s; zero: the Magnus engine) to `tolerance`, with the
/// orientation history its torques need when spinning.
pub fn released_on_model(
    cat: &TwoMotorCat,
    traj: &impl Trajectory,
    spin: &Vector3<f64>,
    tolerance: f64,
) -> (Flip, Option<SpinHistory>) {
    if spin.norm_squared() > 0.0 {
        let (flip, history) = cat.flip_spinning(traj, spin, tolerance);
        return (flip, Some(history));
    }
    (cat.flip(traj, tolerance), None)
}

/// [`momentum_check`] on any two-motor model, of the motion [`released_on_model`] found (its
/// `history` when released with `spin`), on `samples + 1` points per piece: `max|H|` relative to
/// `I*·max|q̇|` at zero momentum, else `max|R H − L|` relative to `max(I*·max|q̇|, |L|)`, `I*`
/// the rear half's end-transverse inertia.
pub fn momentum_on_model(
    cat: &TwoMotorCat,
    traj: &impl Trajectory,
    spin: &Vector3<f64>,
    history: Option<&SpinHistory>,
    samples: usize,
) -> f64 {
    let reference = cat.cat().rear.end_transverse();
    match history {
        Some(history) => {
            let field = cat.field(traj);
            let world = |piece: usize, s: f64, st: &JointState| {
                let r = history.orientation_on(&field, piece, s);
                r * cat.momentum(st, &cat.body_rate_spinning(st, &r.inverse_transform_vector(spin)))
            };
            momentum_error_by(world, spin, reference, traj, samples)
        }
        None => momentum_max_by(|st| cat.momentum(st, &cat.body_rate(st)), reference, traj, samples),
    }
}

/// The torques of the motion [`released_flip`] found: spinning with its history, else at zero
/// momentum.
pub fn torque_source<'a>(cat: &'a Cylinder, history: Option<&'a SpinHistory>) -> TorqueSource<'a> {
    match history {
        Some(h) => TorqueSource::spinning(cat, h),
        None => TorqueSource::zero_momentum(cat),
    }
}

/// The momentum check of that motion: [`momentum_max`] at zero momentum, else
/// [`momentum_error_spinning`].
pub fn momentum_check(cat: &Cylinder, traj: &impl Trajectory, history: Option<&SpinHistory>, samples: usize) -> f64 {
    match history {
        Some(h) => momentum_error_spinning(cat, traj, h, samples),
        None => momentum_max(cat, traj, samples),
    }
}

/// Largest `|R (I_lock Ω + h) − L|` (the world-frame momentum's departure from the release's)
/// on `samples + 1` points per phase of a motion released with spin, relative to
/// `max(I* · max|q̇|, |L|)`: the exact engine's "L constant" check.
pub fn momentum_error_spinning(
    cat: &Cylinder,
    schedule: &impl Trajectory,
    history: &SpinHistory,
    samples: usize,
) -> f64 {
    let world = |piece: usize, s: f64, st: &JointState| {
        let r = history.orientation(cat, schedule, piece, s);
        let lambda = r.inverse_transform_vector(&history.spin);
        let w = body_rate_spinning(cat, st.q, st.qd, &lambda);
        r * momentum(cat, st, &w)
    };
    momentum_error_by(world, &history.spin, cat.end_transverse(), schedule, samples)
}

/// Largest `|world(piece, s, q) − L|` on `samples + 1` points per phase, relative to
/// `max(inertia · max|q̇|, |L|)`, with `world` the motion's momentum in the world frame: the "L
/// constant" check of any model.
fn momentum_error_by(
    world: impl Fn(usize, f64, &JointState) -> Vector3<f64>,
    spin: &Vector3<f64>,
    inertia: f64,
    schedule: &impl Trajectory,
    samples: usize,
) -> f64 {
    let (mut err, mut qd_max) = (0.0f64, 0.0f64);
    for (piece, dur) in schedule.piece_durations().into_iter().enumerate() {
        for k in 0..=samples {
            let s = dur * k as f64 / samples as f64;
            let st = schedule.piece_state(piece, s);
            err = err.max((world(piece, s, &st) - spin).norm());
            qd_max = qd_max.max(st.qd[0].hypot(st.qd[1]));
        }
    }
    err / (inertia * qd_max).max(spin.norm())
}

/// One row of the peak-torque table: an evaluation with the schedule's profile data.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareRow {
    /// Problem name.
    pub problem: String,
    /// Profile name.
    pub profile: String,
    /// Where the profile comes from: `paper`, `library`, `qp`, `refined` or `refined-all-phases`.
    pub origin: Origin,
    /// Whether the rate is zero at both ends of the twist phase.
    pub rest_to_rest: bool,
    /// Peak-acceleration coefficient `max|A|` of the normalised profile.
    pub accel_coefficient: f64,
    /// Peak torque in the paper's model `I* · max|ω̇|`, N·m.
    pub model_peak_nm: f64,
    /// Exact peak torques per phase and joint, N·m.
    pub exact_peak_nm: PhasePeaks,
    /// Number of velocity jumps (impulses).
    pub velocity_jumps: usize,
    /// Largest generalised impulse of a jump, N·m·s (0 when none).
    pub max_impulse_nms: f64,
    /// Signed twist, degrees.
    pub twist_deg: f64,
    /// Swing, degrees.
    pub swing_deg: f64,
    /// Circulation, rad.
    pub circulation_rad: f64,
    /// Peak speed and power per joint, and each motor limit's usage.
    pub motors: MotorDemand,
}

impl CompareRow {
    /// The row of `schedule` (made by `origin`) on `cat`, from its evaluation `e`.
    pub fn new(problem: &str, cat: &Cylinder, schedule: &Schedule, origin: Origin, e: &Evaluation) -> CompareRow {
        let coefficient = schedule.profile.peak_accel_coefficient();
        let t2 = schedule.durations[Phase::Twist.index()];
        CompareRow {
            problem: problem.to_string(),
            profile: schedule.profile.name().to_string(),
            origin,
            rest_to_rest: schedule.profile.is_rest_to_rest(),
            accel_coefficient: coefficient,
            model_peak_nm: cat.end_transverse() * coefficient * schedule.circulation.abs() / (t2 * t2),
            exact_peak_nm: e.peaks,
            velocity_jumps: e.jumps.len(),
            max_impulse_nms: e.max_impulse(),
            twist_deg: e.twist_deg(),
            swing_deg: e.swing_deg(),
            circulation_rad: schedule.circulation,
            motors: e.motors.clone(),
        }
    }
}
