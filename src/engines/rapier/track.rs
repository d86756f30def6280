//! A tracked run: the schedule in rapier driven by a [`Controller`] through real motors and
//! sensors, rather than by rapier's own position motors (issue 21 §2).
//!
//! The scene is the verification's ([`super::scene`]) with free joints (no rapier motors). At
//! each step `[t_k, t_{k+1}]`, `h = T/n`:
//!
//! 1. the encoders read `(q, q̇)` (rapier's joint coordinates and rates, exact);
//! 2. the attitude sensor gives A's orientation `δ` earlier, `R_A(t_{k−d})` with
//!    `d = round(δ/h)` whole steps (the release attitude before the release), times a noise rotation `exp([σ n]×)` in
//!    A's frame, `n` three standard normals drawn per step from the run's own stream;
//! 3. the controller returns `τ`; each joint's is clamped to what its actuator has at the
//!    measured rate ([`super::available_torque`]: torque limit, DC envelope, power; none →
//!    unbounded), and the step counts as saturated for that joint when the command exceeded the
//!    bound by more than [`super::SATURATION_TOLERANCE`] of it;
//! 4. the torques are applied as equal and opposite couples on the bodies each joint connects
//!    ([`CatScene::apply_joint_torques`]) and rapier steps.
//!
//! The cat is released with total angular momentum `L` ([`CatScene::start_with_momentum`]) at
//! the schedule's initial state. The run ends at `T` and reports A's attitude there (twist and
//! swing as the verification does), the tracking error `max_k |q_k − q*(t_k)|`, the largest
//! torque applied and the saturated fraction of the steps. With a [`Landing`] the scene also
//! has gravity, colliders and the ground ([`super::ground`]); the first touch is recorded, and a
//! run whose cat has not touched down by `T` goes on, the controller still called (the plan holds
//! its end state and has no feed-forward there), until it does (at most [`MAX_EXTRA`] of `T` more).
//!
//! Rapier's integrator is first order: its momentum leak biases the attitude by `O(h)` (about
//! 0.5° of twist at `h` = 0.1 ms on the paper's optimum, measured against the verification).
//!
//! ## References
//! - issue 21 §2 and §4; DESIGN.md §6 and §9.

use nalgebra::{UnitQuaternion, Vector3};
use serde::Serialize;

use super::control::{AttitudeEstimate, Controller, JointReading, Plan};
use super::ground::{Ground, Landing, Touchdown};
use super::saturation::{available_torque, SATURATION_TOLERANCE};
use super::scene::CatScene;
use super::{RapierError, Snapshot};
use crate::model::motor::Motors;
use crate::model::orientation::TwistTracker;
use crate::model::{Cat, Cylinder};
use crate::numeric::random::SplitMix64;

/// Longest a landing run goes on after the schedule's end, as a fraction of its duration.
pub const MAX_EXTRA: f64 = 0.5;

/// The attitude sensor.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct AttitudeSensor {
    /// Latency `δ`, s.
    pub latency: f64,
    /// Noise `σ` per axis, rad.
    pub noise: f64,
    /// Seed of the noise stream.
    pub seed: u64,
}

/// What a tracked run is given besides the cat, the plan and the controller.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackOptions {
    /// Mass of the universal joint's cross as a fraction of a half's (`rapier.cross_mass_fraction`).
    pub cross_mass_fraction: f64,
    /// Gauss–Seidel sweeps per step.
    pub pgs_iterations: usize,
    /// The actuators (ideal: unbounded).
    pub motors: Motors,
    /// Total angular momentum at release, world frame, N·m·s.
    pub spin: Vector3<f64>,
    /// The attitude sensor.
    pub sensor: AttitudeSensor,
    /// The ground, if the fall ends on it.
    pub landing: Option<Landing>,
    /// Instants at which to keep the bodies' poses (e.g. for a filmstrip), s.
    pub keep_poses_at: Vec<f64>,
}

/// What a tracked run measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrackedRun {
    /// The step, s.
    pub dt: f64,
    /// A's orientation at the schedule's end, serialised as `[w, x, y, z]`.
    #[serde(serialize_with = "super::run::quat_wxyz")]
    pub orientation: UnitQuaternion<f64>,
    /// Twist about A's initial `+z` at the end, rad (continued).
    pub twist: f64,
    /// Swing of A's spine at the end, rad.
    pub swing: f64,
    /// `max_k |q_k − q*(t_k)|` per joint, rad.
    pub tracking_error: [f64; 2],
    /// Largest `|τ_j|` applied, N·m.
    pub peak_torque: [f64; 2],
    /// Fraction of the steps in which joint `j`'s command exceeded its actuator's bound.
    pub saturated: [f64; 2],
    /// The touch-down, with a landing that happened.
    pub touchdown: Option<Touchdown>,
    /// The kept poses, at the steps nearest to the instants asked for, and the touch-down's.
    #[serde(skip)]
    pub poses: Vec<(f64, Snapshot)>,
}

/// Runs `plan` on `cat` with `controller` (module docs).
pub fn track(
    cat: &Cylinder,
    plan: &Plan,
    controller: &mut (impl Controller + ?Sized),
    opts: &TrackOptions,
) -> Result<TrackedRun, RapierError> {
    let (n, dt) = (plan.steps(), plan.dt);
    if n == 0 || !(dt.is_finite() && dt > 0.0) {
        return Err(RapierError::BadDuration(dt * n as f64));
    }
    let start = plan.state(0);
    let mut scene = CatScene::new(&Cat::from(*cat), opts.cross_mass_fraction, dt, opts.pgs_iterations, None, start.q)?;
    scene.start_with_momentum(start.qd, &opts.spin)?;
    let ground = opts.landing.as_ref().map(|l| Ground::add(&mut scene, cat, l)).transpose()?;
    let extra = if ground.is_some() { (MAX_EXTRA * n as f64).ceil() as usize } else { 0 };
    let masses = *scene.masses();
    let mut noise = SplitMix64::new(opts.sensor.seed);
    let delay = (opts.sensor.latency / dt).round() as usize;
    let mut keep: Vec<usize> = opts.keep_poses_at.iter().map(|t| ((t / dt).round().max(0.0) as usize).min(n)).collect();
    keep.sort_unstable();

    let mut snap = scene.snapshot()?;
    let mut attitudes = vec![snap.rotations[0]];
    let mut tracker = TwistTracker::default();
    tracker.update(&snap.rotations[0]);
    let (mut tracking, mut peak, mut saturated) = ([0.0f64; 2], [0.0f64; 2], [0usize; 2]);
    let mut end = None;
    let mut touchdown = None;
    let mut poses = Vec::new();
    if keep.first() == Some(&0) {
        poses.push((0.0, snap));
    }
    for k in 0..n + extra {
        let t = k as f64 * dt;
        let joints = JointReading { q: snap.q, qd: [snap.velocities[6], snap.velocities[7]] };
        let seen = attitudes[k.saturating_sub(delay)];
        let n3 = Vector3::new(noise.normal(), noise.normal(), noise.normal());
        let attitude = AttitudeEstimate {
            measured_at: k.saturating_sub(delay) as f64 * dt,
            orientation: seen * UnitQuaternion::from_scaled_axis(opts.sensor.noise * n3),
        };
        let command = controller.torques(t, &joints, &attitude);
        let tau: [f64; 2] = std::array::from_fn(|j| {
            let Some(bound) = available_torque(&opts.motors.joints[j], joints.qd[j]) else { return command[j] };
            if command[j].abs() - bound > SATURATION_TOLERANCE * bound.max(f64::MIN_POSITIVE) && k < n {
                saturated[j] += 1;
            }
            command[j].clamp(-bound, bound)
        });
        for (p, t) in peak.iter_mut().zip(tau) {
            *p = p.max(t.abs());
        }
        let before = ground.is_some().then(|| snap.bodies(&masses));
        scene.apply_joint_torques(tau, &snap)?;
        scene.step();
        snap = scene.snapshot()?;
        let now = (k + 1) as f64 * dt;
        if !snap.is_finite() {
            return Err(RapierError::Diverged(now));
        }
        attitudes.push(snap.rotations[0]);
        let st = tracker.update(&snap.rotations[0]);
        if k < n {
            let target = plan.state(k + 1);
            for (e, (q, q_plan)) in tracking.iter_mut().zip(snap.q.iter().zip(target.q)) {
                *e = e.max((q - q_plan).abs());
            }
            if keep.binary_search(&(k + 1)).is_ok() {
                poses.push((now, snap));
            }
            if k + 1 == n {
                end = Some((snap.rotations[0], st));
            }
        }
        if let (Some(g), Some(before), None) = (&ground, &before, &touchdown) {
            touchdown = g.touchdown(&scene, before, &snap, now, dt);
            if let Some(td) = &touchdown {
                poses.push((td.time, snap));
            }
        }
        if k + 1 >= n && (ground.is_none() || touchdown.is_some()) {
            break;
        }
    }
    let (orientation, angles) = end.ok_or(RapierError::Missing("a final state"))?;
    Ok(TrackedRun {
        dt,
        orientation,
        twist: angles.twist,
        swing: angles.swing,
        tracking_error: tracking,
        peak_torque: peak,
        saturated: saturated.map(|s| s as f64 / n as f64),
        touchdown,
        poses,
    })
}
