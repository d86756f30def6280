//! The final measurement of a trajectory by the reference engines, never by the optimiser's
//! model: flip by [`crate::engines::exact::flip`], peak by [`crate::engines::torque::peak_torques`], energy by
//! Gauss–Legendre quadrature of [`crate::engines::torque::joint_torques`], the bend's shape, and
//! what it asks of the motors by [`crate::engines::motors::motor_demand`].

use std::f64::consts::{PI, TAU};

use serde::Serialize;

use super::spline::BSpline;
use crate::engines::exact::{flip, Flip};
use crate::engines::motors::{motor_demand, MotorDemand};
use crate::engines::torque::{joint_torques, peak_torques, piece_samples};
use crate::model::motor::Motors;
use crate::model::Cylinder;
use crate::schedule::Trajectory;

/// Samples per knot span of the peak search (each peak then refined by golden section).
pub const PEAK_SAMPLES_PER_SPAN: usize = 64;

/// What the reference engines say of a trajectory.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Measurement {
    /// The flip.
    pub flip: Flip,
    /// `| |twist| − π |`, rad.
    pub twist_error: f64,
    /// Peak `|τ|`, N·m.
    pub peak: f64,
    /// Its time, s.
    pub peak_time: f64,
    /// `∫ τ·τ dt`, N²·m²·s.
    pub energy: f64,
    /// Largest bend, rad.
    pub max_bend: f64,
    /// Turns of the bend direction about A's axis.
    pub bend_turns: f64,
    /// What it asks of the motors.
    pub motors: MotorDemand,
}

/// Measures `spline` driven by `motors` (flip to `tolerance` rad).
pub fn measure(cat: &Cylinder, spline: &BSpline, motors: &Motors, tolerance: f64) -> Measurement {
    let flip = flip(cat, spline, tolerance);
    let peaks = peak_torques(cat, spline, PEAK_SAMPLES_PER_SPAN);
    let (peak, peak_time) = peaks.per_piece.iter().flatten().map(|p| (p.value, p.time)).fold((0.0, 0.0), |best, p| {
        if p.0 > best.0 {
            p
        } else {
            best
        }
    });
    // Five-point Gauss–Legendre on four parts of every span.
    let (a, b) = ((245.0 - 14.0 * 70f64.sqrt()).sqrt() / 21.0, (245.0 + 14.0 * 70f64.sqrt()).sqrt() / 21.0);
    let (wa, wb) = ((322.0 + 13.0 * 70f64.sqrt()) / 900.0, (322.0 - 13.0 * 70f64.sqrt()) / 900.0);
    let rule = [(-b, wb), (-a, wa), (0.0, 128.0 / 225.0), (a, wa), (b, wb)];
    let mut energy = 0.0;
    for (piece, d) in spline.piece_durations().into_iter().enumerate() {
        let h = d / 4.0;
        for part in 0..4 {
            for &(x, w) in &rule {
                let s = h * (part as f64 + 0.5 * (1.0 + x));
                let tau = joint_torques(cat, &spline.piece_state(piece, s)).tau;
                energy += 0.5 * h * w * (tau[0] * tau[0] + tau[1] * tau[1]);
            }
        }
    }
    let (mut max_bend, mut turned, mut last): (f64, f64, Option<f64>) = (0.0, 0.0, None);
    let n = 64 * spline.spans();
    for k in 0..=n {
        let q = spline.state(spline.duration() * k as f64 / n as f64).q;
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let axis = [s2, -s1 * c2, c1 * c2];
        let bend = axis[2].clamp(-1.0, 1.0).acos();
        max_bend = max_bend.max(bend);
        if bend > 1f64.to_radians() {
            let dir = axis[1].atan2(axis[0]);
            if let Some(prev) = last {
                let mut d = dir - prev;
                d -= TAU * (d / TAU).round();
                turned += d;
            }
            last = Some(dir);
        }
    }
    Measurement {
        twist_error: (flip.twist.abs() - PI).abs(),
        flip,
        peak,
        peak_time,
        energy,
        max_bend,
        bend_turns: turned / TAU,
        motors: motor_demand(cat, spline, &piece_samples(spline, PEAK_SAMPLES_PER_SPAN), motors),
    }
}
