//! The first time step of a verification, from the trajectory's own time scales.
//!
//! Rapier's integrator is first order: over a step `h` it takes the velocities as constant, so
//! its error per step grows with how far things move in a step. Whatever the cat's size, mass or
//! drop, these are the rates that set it (all from the exact zero-momentum motion, DESIGN.md §2,
//! sampled at [`SAMPLES_PER_PIECE`] intervals of every piece):
//!
//! | scale | bound on `h` | why |
//! |---|---|---|
//! | shortest piece `T_min` | `T_min / N` | every piece needs many steps: torque samples within four steps of a boundary where `q̇` or `q̈` jumps are not measured; pieces joined where the motion is smooth (a spline's knots) count as one, unless the motors have limits ([`time_scales_within`]) |
//! | joint rate `max‖q̇‖` | `δ / max‖q̇‖` | the motors follow `q` step by step: a step must not sweep more than `δ` of the joint path |
//! | body rate `max‖Ω‖` | `δ / max‖Ω‖` | A's own rotation per step (the gyroscopic terms are taken semi-implicitly) |
//! | its rate `max‖Ω̇‖` | `√(δ / max‖Ω̇‖)` | the rotation that the change of `Ω` alone makes within a step |
//! | torque `t_τ = max‖τ‖ / max‖τ̇‖` | `t_τ / M` | the torque must not change by more than a fraction of its peak within a step |
//!
//! with `N` = [`STEPS_PER_PIECE`], `δ` = [`ANGLE_PER_STEP`] rad and `M` = [`STEPS_PER_TORQUE_TIME`].
//! The first step is the smallest bound. It aims at rapier's asymptotic range (an observed order
//! near 1), not at the tolerance: the halving that follows ([`crate::engines::rapier::verify`]) reaches
//! the tolerance, and since its runs' steps add up to about twice the finest run's whatever the
//! start, a first step that is too coarse costs little (one short run, or a divergence that is
//! recorded and halved), while one that is too fine costs directly. The bounds therefore lean
//! coarse: `M` is small because a torque-optimal schedule's torque switches between `±τ_max`
//! (bang-bang), where `max‖τ̇‖` measures the switch, not the plateau whose peak is verified.
//! On the paper problem the body rate (paper cosine: ‖Ω‖ ≈ 23 rad/s) or the joint rate (rest-to-rest
//! profiles, ‖q̇‖ ≈ 18 rad/s) decides, at 0.43–0.75 ms. `δ` is set by that problem's measured
//! asymptotic range (`cargo run --release --example rapier_convergence`): steps of about 1 ms
//! (`δ` = 0.02) are pre-asymptotic there (the twist error changes sign between 4 and 2 ms and the
//! momentum drift halves only below 1 ms), so a verification starting there spent its first run
//! on a pair that could not pass. The scales depend on the cat's shape, not
//! its size or mass, and on the schedule's timing: a fall ten times shorter gets steps ten times
//! shorter.

use serde::Serialize;

use nalgebra::Vector3;

use super::pieces::Pieces;
use super::pieces::ACCEL_JUMP_FRACTION;
use super::saturation::bounds_torque;
use crate::engines::models::TwoMotorCat;
use crate::engines::reduction;
use crate::engines::shape::ShapeTrajectory;
use crate::model::motor::Motors;
use crate::model::tree::Tree;
use crate::schedule::{JointState, Trajectory};

/// Sampling intervals per piece when the scales are measured.
pub const SAMPLES_PER_PIECE: usize = 64;
/// Fewest steps per piece of the first run.
pub const STEPS_PER_PIECE: f64 = 40.0;
/// Largest joint-path or body rotation per step of the first run, rad.
pub const ANGLE_PER_STEP: f64 = 0.01;
/// Fewest steps per torque time scale of the first run.
pub const STEPS_PER_TORQUE_TIME: f64 = 2.0;

/// Which time scale set the first step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StepLimit {
    /// The shortest piece.
    ShortestPiece,
    /// The fastest joint rate.
    JointRate,
    /// A's fastest rotation.
    BodyRate,
    /// The fastest change of A's rotation rate.
    BodyAcceleration,
    /// The torque's time scale.
    Torque,
}

impl std::fmt::Display for StepLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StepLimit::ShortestPiece => "shortest piece",
            StepLimit::JointRate => "joint rate",
            StepLimit::BodyRate => "body rate",
            StepLimit::BodyAcceleration => "body acceleration",
            StepLimit::Torque => "torque time scale",
        })
    }
}

/// The trajectory's time scales and the first step they give.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TimeScales {
    /// Shortest piece of positive length, s; pieces joined where the motion is smooth (`q̇` and
    /// `q̈` continuous, as at a spline's knots) count as one.
    pub shortest_piece: f64,
    /// `max ‖q̇‖`, rad/s.
    pub max_joint_rate: f64,
    /// `max ‖Ω‖` of A, rad/s.
    pub max_body_rate: f64,
    /// `max ‖Ω̇‖` of A, rad/s².
    pub max_body_acceleration: f64,
    /// `max ‖τ‖ / max ‖τ̇‖` within pieces, s (`∞` for a torque-free trajectory).
    pub torque_time: f64,
    /// The smallest of the bounds, s.
    pub first_step: f64,
    /// The bound that set it.
    pub limited_by: StepLimit,
}

/// Measures the time scales of `traj` on the exact zero-momentum motion of `model`: the paper's
/// cat through the two-cylinder engine, any other model through the general core. The motors
/// are ideal ([`time_scales_within`]).
pub fn time_scales(model: &TwoMotorCat, traj: &impl Trajectory) -> TimeScales {
    time_scales_within(model, traj, &Motors::ideal())
}

/// [`time_scales`] for a run whose joint motors have `motors`' limits. With limits that bound a
/// torque every piece boundary counts for the shortest piece, smooth or not: a schedule planned
/// on its motors' limits (the least-fall-time optimum on a DC envelope) touches them by the
/// tracking error, which grows with the step, and the finer first step keeps that within
/// [`super::SATURATION_TOLERANCE`] (on `problems/servo.toml` the optimum's spline joined into
/// one piece gave a first step of 1.1 ms, where its motors fell short by 1e-3 N·m).
pub fn time_scales_within(model: &TwoMotorCat, traj: &impl Trajectory, motors: &Motors) -> TimeScales {
    let join_smooth = !bounds_torque(motors);
    match model.cat().paper() {
        Some(cat) => scales_of(traj, join_smooth, |st| {
            let kin = crate::engines::torque::kinematics(cat, st);
            (kin.omega, kin.omega_dot, crate::engines::torque::joint_torques(cat, st).tau)
        }),
        None => scales_of(traj, join_smooth, |st| {
            let (omega, omega_dot) = model.body_motion(st);
            let tau = model.joint_torques(st).tau;
            (omega, omega_dot, [tau[0], tau[1]])
        }),
    }
}

/// The time scales of `traj` from `motion(st) = (Ω, Ω̇, τ)` at each sample; with `join_smooth`,
/// pieces joined where the motion is smooth count as one for the shortest piece.
fn scales_of(
    traj: &impl Trajectory,
    join_smooth: bool,
    motion: impl Fn(&JointState) -> (Vector3<f64>, Vector3<f64>, [f64; 2]),
) -> TimeScales {
    let durations = traj.piece_durations();
    let pieces = Pieces::new(traj);
    let rough =
        if join_smooth { pieces.rough(ACCEL_JUMP_FRACTION) } else { vec![true; durations.len().saturating_sub(1)] };
    sampled(&durations, pieces.shortest_smooth(&rough), |piece, s| {
        let st = traj.piece_state(piece, s);
        let (omega, omega_dot, tau) = motion(&st);
        Sample { qd: st.qd.to_vec(), omega, omega_dot, tau: tau.to_vec() }
    })
}

/// The time scales of a shape trajectory on a tree of bodies (any number of coordinates and
/// motors), from the exact zero-momentum motion of `tree` ([`crate::engines::reduction`]): the
/// table's bounds with `‖q̇‖` and `‖τ‖` over every coordinate and motor. Its pieces must join
/// smoothly (the whole optimiser's splines do): the shortest piece is the whole duration.
pub fn tree_time_scales(tree: &Tree, traj: &impl ShapeTrajectory) -> TimeScales {
    let durations = traj.piece_durations();
    let zero = Vector3::zeros();
    sampled(&durations, durations.iter().sum(), |piece, s| {
        let shape = traj.piece_shape(piece, s);
        let d = reduction::dynamics(tree, &shape, &zero);
        let tau = reduction::torques_on(tree, &d).into_iter().flat_map(|l| l.tau).collect();
        Sample { qd: shape.qd, omega: d.omega, omega_dot: d.omega_dot, tau }
    })
}

/// One sample of a trajectory's motion: the joint rates, A's `Ω` and `Ω̇`, the motor torques.
struct Sample {
    qd: Vec<f64>,
    omega: Vector3<f64>,
    omega_dot: Vector3<f64>,
    tau: Vec<f64>,
}

/// Euclidean norm (by `hypot`, as the two-motor scales always were).
fn norm(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0, f64::hypot)
}

/// The time scales from [`SAMPLES_PER_PIECE`] samples of every piece of `durations` and the
/// shortest smooth stretch `shortest`.
fn sampled(durations: &[f64], shortest: f64, sample: impl Fn(usize, f64) -> Sample) -> TimeScales {
    let (mut qd_max, mut w_max, mut wd_max, mut tau_max, mut taud_max) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (piece, &d) in durations.iter().enumerate().filter(|(_, d)| **d > 0.0) {
        let h = d / SAMPLES_PER_PIECE as f64;
        let mut prev: Option<Vec<f64>> = None;
        for k in 0..=SAMPLES_PER_PIECE {
            let st = sample(piece, k as f64 * h);
            qd_max = qd_max.max(norm(st.qd.iter().copied()));
            w_max = w_max.max(st.omega.norm());
            wd_max = wd_max.max(st.omega_dot.norm());
            tau_max = tau_max.max(norm(st.tau.iter().copied()));
            if let Some(p) = &prev {
                taud_max = taud_max.max(norm(st.tau.iter().zip(p).map(|(a, b)| a - b)) / h);
            }
            prev = Some(st.tau);
        }
    }
    let torque_time = if taud_max > 0.0 { tau_max / taud_max } else { f64::INFINITY };
    let over = |scale: f64, rate: f64| if rate > 0.0 { scale / rate } else { f64::INFINITY };
    let bounds = [
        (shortest / STEPS_PER_PIECE, StepLimit::ShortestPiece),
        (over(ANGLE_PER_STEP, qd_max), StepLimit::JointRate),
        (over(ANGLE_PER_STEP, w_max), StepLimit::BodyRate),
        (over(ANGLE_PER_STEP, wd_max).sqrt(), StepLimit::BodyAcceleration),
        (torque_time / STEPS_PER_TORQUE_TIME, StepLimit::Torque),
    ];
    let (first_step, limited_by) = bounds
        .iter()
        .copied()
        .filter(|(b, _)| !b.is_nan())
        .fold((f64::INFINITY, StepLimit::ShortestPiece), |a, b| if b.0 < a.0 { b } else { a });
    TimeScales {
        shortest_piece: shortest,
        max_joint_rate: qd_max,
        max_body_rate: w_max,
        max_body_acceleration: wd_max,
        torque_time,
        first_step,
        limited_by,
    }
}
