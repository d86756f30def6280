//! Torque-free tumbling: the cat spinning about a non-principal axis with no external torque, so
//! its angular momentum about the centre of mass must stay constant (the model is rapier's own
//! `gyroscopic` test; the cat here is an articulated body in reduced coordinates).

use nalgebra::Vector3;
use serde::Serialize;

use super::bodies::NDOFS;
use super::measure::{angular_momentum, kinetic_energy};
use super::scene::{CatScene, MotorGains};
use super::{RapierError, RapierOptions, MAX_STEPS};
use crate::model::{Cat, Cylinder};
use crate::problem::settings::{RapierSettings, TimeStep};

/// A torque-free spin: the cat at joint angles `q`, turning rigidly at `omega`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpinTest {
    /// Joint angles, rad.
    pub q: [f64; 2],
    /// Initial angular velocity of the whole cat (every body), world frame, rad/s.
    pub omega: Vector3<f64>,
    /// Simulated time, s.
    pub duration: f64,
    /// Motors hold `q` (a rigid cat) when true; the joints are free when false.
    pub hold_joints: bool,
}

impl Default for SpinTest {
    fn default() -> Self {
        Self { q: [0.6, -0.4], omega: Vector3::new(1.0, 2.0, 3.0), duration: 2.0, hold_joints: true }
    }
}

/// What a torque-free spin conserved.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SpinRun {
    /// Step used, s.
    pub dt: f64,
    /// Number of steps.
    pub steps: usize,
    /// Angular momentum about the centre of mass at the start, world frame, N·m·s.
    pub initial_momentum: [f64; 3],
    /// `max_k |H_k − H_0|`, N·m·s.
    pub max_drift: f64,
    /// `max_drift / |H_0|`.
    pub max_rel_drift: f64,
    /// Kinetic energy at the start, J.
    pub initial_energy: f64,
    /// `max_k |E_k − E_0| / E_0` (held joints do no work).
    pub max_rel_energy_drift: f64,
    /// `max_k |q_k − q|` per joint, rad.
    pub max_joint_deviation: [f64; 2],
    /// Angle between A's angular velocity at the start and at the end, rad: non-zero proves the
    /// body tumbled (a spin about a principal axis would keep it).
    pub angvel_turn: f64,
}

/// Runs a torque-free spin with the step `settings.dt` (`T / ceil(T / dt)` exactly); an automatic
/// step turns the cat by at most [`super::ANGLE_PER_STEP`] per step, with at least 1000 steps.
pub fn spin_free(
    cat: &Cylinder,
    settings: &RapierSettings,
    test: &SpinTest,
    opts: &RapierOptions,
) -> Result<SpinRun, RapierError> {
    settings.validate()?;
    opts.validate()?;
    if !(test.duration.is_finite() && test.duration > 0.0) {
        return Err(RapierError::BadDuration(test.duration));
    }
    let requested = match settings.dt {
        TimeStep::Fixed(dt) => dt,
        TimeStep::Auto => (super::ANGLE_PER_STEP / test.omega.norm()).min(test.duration / 1000.0),
    };
    let steps_f = (test.duration / requested).ceil();
    if steps_f.is_nan() || steps_f > MAX_STEPS as f64 {
        let (dt, duration) = (requested, test.duration);
        return Err(RapierError::TooManySteps { dt, duration, steps: steps_f, max: MAX_STEPS });
    }
    let n = (steps_f as usize).max(1);
    let dt = test.duration / n as f64;
    let gains = test.hold_joints.then(|| MotorGains::new(opts.bandwidth_per_step / dt, opts.damping_ratio));
    let mut scene =
        CatScene::new(&Cat::from(*cat), settings.cross_mass_fraction, dt, opts.pgs_iterations, gains, test.q)?;
    let masses = *scene.masses();

    // Rigid rotation about the centre of mass: v_A = ω × (x_A − c), joint rates zero.
    let snap = scene.snapshot()?;
    let c = (0..3).map(|i| masses.mass[i] * snap.positions[i]).sum::<Vector3<f64>>() / masses.total();
    let lin = test.omega.cross(&(snap.positions[0] - c));
    let mut v = [0.0; NDOFS];
    v[..3].copy_from_slice(lin.as_slice());
    v[3..6].copy_from_slice(test.omega.as_slice());
    scene.set_velocities(&v)?;

    let start = scene.snapshot()?;
    let bodies = start.bodies(&masses);
    let h0 = angular_momentum(&masses, &bodies);
    let e0 = kinetic_energy(&masses, &bodies);
    let w0 = bodies[0].angvel;
    let (mut drift, mut e_drift, mut dev) = (0.0f64, 0.0f64, [0.0f64; 2]);
    let mut w_end = w0;
    for k in 1..=n {
        scene.step();
        let s = scene.snapshot()?;
        if !s.is_finite() {
            return Err(RapierError::Diverged(k as f64 * dt));
        }
        let b = s.bodies(&masses);
        drift = drift.max((angular_momentum(&masses, &b) - h0).norm());
        e_drift = e_drift.max((kinetic_energy(&masses, &b) - e0).abs());
        for (d, (q, q0)) in dev.iter_mut().zip(s.q.iter().zip(test.q)) {
            *d = d.max((q - q0).abs());
        }
        w_end = b[0].angvel;
    }
    let norm = h0.norm();
    Ok(SpinRun {
        dt,
        steps: n,
        initial_momentum: [h0.x, h0.y, h0.z],
        max_drift: drift,
        max_rel_drift: if norm > 0.0 { drift / norm } else { f64::NAN },
        initial_energy: e0,
        max_rel_energy_drift: if e0 > 0.0 { e_drift / e0 } else { f64::NAN },
        max_joint_deviation: dev,
        angvel_turn: w0.angle(&w_end),
    })
}
