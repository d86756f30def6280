//! One exact evaluation of a trajectory: what every command reports about it.
//!
//! For any trajectory (a library or optimised schedule, a retimed path, the whole optimum's
//! spline, a file read back) on any two-motor cat model, the exact engine gives
//! - the reorientation: signed twist about A's initial `+z` and swing of the spine axis (rad),
//!   from the adaptive Magnus integration ([`crate::engines::exact::flip`]) to
//!   `exact.tolerance`, with its error estimate and whether it met the tolerance;
//! - the peak motor torques per piece and joint ([`PeakTorques`], N·m; a three-phase schedule's
//!   pieces are its phases, [`Evaluation::phase_peaks`]) from Newton–Euler on the motion, sampled
//!   by the trajectory's own time scale ([`crate::engines::torque::piece_samples`]:
//!   `exact.torque_samples` per piece at least, 64 per radian the bend direction turns), with
//!   their stated accuracy, and the largest action–reaction gap;
//! - what it asks of the motors ([`MotorDemand`]): peak speed and power per joint, and with
//!   `[actuator]` limits each limit's worst usage and the least slow-down within them;
//! - the joint-rate jumps with their impulses ([`crate::engines::jumps`]);
//! - `momentum_max`: the largest `|H|` about the centre of mass along the motion, relative to a
//!   half's typical momentum `I* · max|q̇|` (`I*` the rear half's end-transverse inertia; zero in
//!   exact arithmetic); released with spin `L`, the largest `|R H − L|` (the momentum stays `L`),
//!   relative to `max(I* · max|q̇|, |L|)`.
//!
//! Released with spin (`[drop] angular_momentum`), the flip, the torques and the motor demand are
//! those of the spinning motion ([`crate::engines::spin`]). The paper's cat goes through the
//! two-cylinder engine (its numbers unchanged to the last digit), any other two-motor model
//! (`[cat] joint`, unequal halves) through the general core
//! ([`crate::engines::models::TwoMotorCat`]): [`Evaluation::new`] is the one place that chooses.

use std::time::Instant;

use nalgebra::Vector3;
use serde::Serialize;

use crate::engines::exact::{body_rate, body_rate_spinning, flip, momentum, Flip};
use crate::engines::jumps::{max_impulse, VelocityJump};
use crate::engines::models::TwoMotorCat;
use crate::engines::motors::{peaks_and_demand, MotorDemand};
use crate::engines::peaks::PhasePeaks;
use crate::engines::spin::SpinHistory;
use crate::engines::torque::{piece_samples, PeakTorques, TorqueSource};
use crate::model::motor::Motors;
use crate::model::Cylinder;
use crate::problem::settings::ExactSettings;
use crate::schedule::{JointState, Trajectory};

/// The exact engine's numbers on one trajectory.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Evaluation {
    /// Twist, swing (rad), steps, error estimate and convergence of the integration.
    pub flip: Flip,
    /// Peak motor torques per piece and joint (N·m, with when), the largest, the action–reaction
    /// gap and the peaks' stated accuracy.
    pub peaks: PeakTorques,
    /// Peak speed and power per joint, and the usage of each motor limit.
    pub motors: MotorDemand,
    /// Joint-rate jumps (impulses); empty when the trajectory's rates are continuous.
    pub jumps: Vec<VelocityJump>,
    /// Largest angular momentum along the motion relative to `I* · max|q̇|` (module docs).
    pub momentum_max: f64,
    /// Wall-clock time of the whole evaluation, s.
    pub run_time_s: f64,
}

impl Evaluation {
    /// Evaluates `traj` on `model` released with total angular momentum `spin` (N·m·s, world
    /// frame; zero for the zero-momentum flip) and driven by `motors`, with the exact engine's
    /// `settings`: the paper's cat through the two-cylinder engine, any other model through the
    /// general core. The rate jumps are judged against the trajectory's own
    /// [`Trajectory::boundary_rate_uncertainty`].
    pub fn new(
        model: &TwoMotorCat,
        traj: &impl Trajectory,
        spin: &Vector3<f64>,
        motors: &Motors,
        settings: &ExactSettings,
    ) -> Evaluation {
        let start = Instant::now();
        let jumps = model.velocity_jumps(traj, |k| traj.boundary_rate_uncertainty(k));
        let samples = piece_samples(traj, settings.torque_samples);
        let (flip, history) = released_on(model, traj, spin, settings.tolerance);
        let source = released_torques(model, history.as_ref());
        let (peaks, motors) = peaks_and_demand(&source, traj, &samples, motors);
        let momentum_max = momentum_on(model, traj, spin, history.as_ref(), settings.torque_samples);
        Evaluation { flip, peaks, motors, jumps, momentum_max, run_time_s: start.elapsed().as_secs_f64() }
    }

    /// [`Evaluation::new`] on the paper's cat of `half`.
    pub fn of_paper(
        half: &Cylinder,
        traj: &impl Trajectory,
        spin: &Vector3<f64>,
        motors: &Motors,
        settings: &ExactSettings,
    ) -> Evaluation {
        Evaluation::new(&TwoMotorCat::paper(*half), traj, spin, motors, settings)
    }

    /// The peaks per phase of a three-phase schedule (its pieces are bend, twist, unbend).
    pub fn phase_peaks(&self) -> PhasePeaks {
        PhasePeaks::from_peaks(&self.peaks)
    }

    /// The peak motor torque over the whole trajectory, N·m.
    pub fn peak(&self) -> f64 {
        self.peaks.max
    }

    /// When the peak motor torque occurs, s from the trajectory's start.
    pub fn peak_time(&self) -> f64 {
        let peaks = self.peaks.per_piece.iter().flatten();
        peaks.fold((f64::NEG_INFINITY, 0.0), |best, p| if p.value > best.0 { (p.value, p.time) } else { best }).1
    }

    /// Signed twist, degrees.
    pub fn twist_deg(&self) -> f64 {
        self.flip.twist.to_degrees()
    }

    /// Swing, degrees.
    pub fn swing_deg(&self) -> f64 {
        self.flip.swing.to_degrees()
    }

    /// Largest impulse of a jump, N·m·s (0 when none).
    pub fn max_impulse(&self) -> f64 {
        max_impulse(&self.jumps)
    }
}

/// The flip of `traj` on `model` released with angular momentum `spin` (world frame, N·m·s) to
/// `tolerance`, with the orientation history its torques need when `spin` is not zero: the
/// paper's cat through the two-cylinder engine ([`crate::engines::exact::flip`] at zero, the
/// Magnus engine), any other through the general core.
pub fn released_on(
    model: &TwoMotorCat,
    traj: &impl Trajectory,
    spin: &Vector3<f64>,
    tolerance: f64,
) -> (Flip, Option<SpinHistory>) {
    let spins = spin.norm_squared() > 0.0;
    match (model.cat().paper(), spins) {
        (Some(cat), false) => (flip(cat, traj, tolerance), None),
        (Some(cat), true) => {
            let (f, history) = SpinHistory::new(cat, traj, spin, tolerance);
            (f, Some(history))
        }
        (None, false) => (model.flip(traj, tolerance), None),
        (None, true) => {
            let (f, history) = model.flip_spinning(traj, spin, tolerance);
            (f, Some(history))
        }
    }
}

/// The torques of the motion [`released_on`] found: spinning with its history, else at zero
/// momentum.
pub fn released_torques<'a>(model: &'a TwoMotorCat, history: Option<&'a SpinHistory>) -> TorqueSource<'a> {
    match (model.cat().paper(), history) {
        (Some(cat), Some(h)) => TorqueSource::spinning(cat, h),
        (Some(cat), None) => TorqueSource::zero_momentum(cat),
        (None, history) => TorqueSource::model_released(model, history),
    }
}

/// The momentum check of the motion [`released_on`] found (its `history` when released with
/// `spin`), on `samples + 1` points per piece: `max|H|` relative to `I*·max|q̇|` at zero
/// momentum, else `max|R H − L|` relative to `max(I*·max|q̇|, |L|)`, `I*` the rear half's
/// end-transverse inertia.
pub fn momentum_on(
    model: &TwoMotorCat,
    traj: &impl Trajectory,
    spin: &Vector3<f64>,
    history: Option<&SpinHistory>,
    samples: usize,
) -> f64 {
    match (model.cat().paper(), history) {
        (Some(cat), Some(h)) => momentum_error_spinning(cat, traj, h, samples),
        (Some(cat), None) => momentum_max(cat, traj, samples),
        (None, Some(history)) => {
            let field = model.field(traj);
            let world = |piece: usize, s: f64, st: &JointState| {
                let r = history.orientation_on(&field, piece, s);
                r * model.momentum(st, &model.body_rate_spinning(st, &r.inverse_transform_vector(spin)))
            };
            momentum_error_by(world, spin, model.cat().rear.end_transverse(), traj, samples)
        }
        (None, None) => momentum_max_by(
            |st| model.momentum(st, &model.body_rate(st)),
            model.cat().rear.end_transverse(),
            traj,
            samples,
        ),
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
