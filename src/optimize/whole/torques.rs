//! The exact motor torques of a spline on any model, as the re-measurement and the knot
//! refinement read them: a two-motor [`TorqueSource`] (the paper's cat through the two-cylinder
//! engine, any other two-motor model through the general core, either released with spin), or
//! the general core's Newton–Euler on every coordinate of a tree's spline (the spherical joint, a
//! tail: [`crate::engines::reduction::joint_torques`] on [`SplineShape`]), one torque per motor.
//!
//! ## References
//! - R. Featherstone, *Rigid Body Dynamics Algorithms* (2008), ch. 4 (kinematic trees), for the
//!   general core's Newton–Euler on a tree;
//! - J. Kiefer, *Sequential minimax search for a maximum*, Proc. AMS 4 (1953) 502–506, for the
//!   golden-section refinement of the sampled peaks.

use super::spline::{BSpline, SplineShape};
use nalgebra::Vector3;
use rayon::prelude::*;

use crate::engines::motors::{LimitUse, MotorDemand, StretchPeak};
use crate::engines::reduction;
use crate::engines::shape::ShapeTrajectory;
use crate::engines::torque::{refine_peak, Peak, TorqueSource};
use crate::model::motor::Limit;
use crate::model::shape::ShapeState;
use crate::model::tree::Tree;
use crate::schedule::Trajectory;

/// Where a spline's exact torques come from.
pub enum ExactTorques<'a> {
    /// A two-motor model's source.
    TwoMotor(TorqueSource<'a>),
    /// The general core on every coordinate of a tree (the spherical joint, a tail, legs), every
    /// joint's motors in link order, at zero angular momentum.
    General(Tree),
}

impl ExactTorques<'_> {
    /// The motor torques at local time `s` of span `span`, one per motor, N·m.
    pub fn at(&self, spline: &BSpline, span: usize, s: f64) -> Vec<f64> {
        self.at_shape(spline, span, s, None)
    }

    /// [`ExactTorques::at`], given the shape there when the caller has it already (the general
    /// core uses it; the two-motor source evaluates its own state).
    fn at_shape(&self, spline: &BSpline, span: usize, s: f64, shape: Option<&ShapeState>) -> Vec<f64> {
        match (self, shape) {
            (ExactTorques::General(tree), Some(shape)) => general(tree, shape),
            (ExactTorques::General(tree), None) => general(tree, &SplineShape(spline).piece_shape(span, s)),
            (ExactTorques::TwoMotor(source), _) => {
                source.at(spline, span, s, &spline.piece_state(span, s)).tau.to_vec()
            }
        }
    }

    /// The motor torques at the end of the fall, `t = T` (the last span's basis there), N·m.
    pub fn at_end(&self, spline: &BSpline) -> Vec<f64> {
        let (last, end) = (spline.spans() - 1, spline.duration());
        match self {
            ExactTorques::TwoMotor(source) => {
                let d = Trajectory::piece_durations(spline)[last];
                source.at(spline, last, d, &spline.state(end)).tau.to_vec()
            }
            ExactTorques::General(tree) => general(tree, &spline.shape(end)),
        }
    }

    /// The largest peak `|τ_j|` of every motor over `spline`, and what `spline` asks of its
    /// motors, one entry per motor: the peaks of `|q̇_j|` and `|τ_j q̇_j|`, and with
    /// `torque_limit` (one limit on every motor, a cat beyond two motors) each motor's torque
    /// usage `max |τ_j| / τ_max` and the largest stretch `√(max |τ_j| / τ_max)` (the two-motor
    /// models' usage is [`crate::engines::motors::motor_demand_from`]'s). Every peak is found on
    /// `samples + 1` points per span, each sampled local maximum that could be the peak refined by
    /// golden section, as [`crate::engines::torque::peak_torques_on`] refines them; the torques
    /// and rates of a point are made once for all of them.
    pub fn peak_and_demand(&self, spline: &BSpline, samples: usize, torque_limit: Option<f64>) -> (Peak, MotorDemand) {
        let joints = spline.joints();
        // Channel c of a point: |τ_j|, |q̇_j| or |τ_j q̇_j| for the group c / J, joint j = c % J;
        // a rate's channel alone needs no torque.
        let value = |c: usize, tau: &[f64], qd: &[f64]| {
            let j = c % joints;
            match c / joints {
                0 => tau[j].abs(),
                1 => qd[j].abs(),
                _ => (tau[j] * qd[j]).abs(),
            }
        };
        let channels = |span: usize, s: f64| {
            let shape = SplineShape(spline).piece_shape(span, s);
            let tau = self.at_shape(spline, span, s, Some(&shape));
            (0..3 * joints).map(|c| value(c, &tau, &shape.qd)).collect()
        };
        let channel = |span: usize, s: f64, c: usize| {
            let shape = SplineShape(spline).piece_shape(span, s);
            let tau = if c / joints == 1 { Vec::new() } else { self.at_shape(spline, span, s, Some(&shape)) };
            value(c, &tau, &shape.qd)
        };
        let mut peaks = spline_peaks(spline, samples, channels, channel);
        let peak_power_w = peaks.split_off(2 * joints);
        let peak_speed_rad_s = peaks.split_off(joints);
        let torque = peaks;
        let peak =
            torque.iter().fold(Peak { value: 0.0, time: 0.0 }, |best, p| if p.value > best.value { *p } else { best });
        let limits: Vec<LimitUse> = torque_limit
            .map(|limit| {
                let usage = |(j, p): (usize, &Peak)| LimitUse {
                    limit: Limit::Torque,
                    joint: j + 1,
                    ratio: p.value / limit,
                    time: p.time,
                };
                torque.iter().enumerate().map(usage).collect()
            })
            .unwrap_or_default();
        let stretch = limits.iter().max_by(|a, b| a.ratio.total_cmp(&b.ratio)).map(|w| StretchPeak {
            value: w.ratio.sqrt(),
            time: w.time,
            joint: w.joint,
            limit: Limit::Torque,
        });
        (peak, MotorDemand { peak_speed_rad_s, peak_power_w, limits, stretch })
    }
}

/// Every torque of `tree` at `shape` (zero angular momentum): each joint's motors in link order.
fn general(tree: &Tree, shape: &ShapeState) -> Vec<f64> {
    reduction::joint_torques(tree, shape, &Vector3::zeros()).into_iter().flat_map(|l| l.tau).collect()
}

/// The peak of each channel of `f(span, s)` (all `≥ 0`) over `spline`: every channel sampled at
/// once on `samples + 1` points per span, each sampled local maximum that could be its peak
/// refined by golden section on that channel alone (`channel(span, s, c)`, the value of
/// `f(span, s)[c]`), as [`crate::engines::torque::peak_torques_on`]
/// refines them; the times global, s. The spans are searched in parallel and their peaks
/// compared in order, so the result does not depend on the threads.
fn spline_peaks(
    spline: &BSpline,
    samples: usize,
    f: impl Fn(usize, f64) -> Vec<f64> + Sync,
    channel: impl Fn(usize, f64, usize) -> f64 + Sync,
) -> Vec<Peak> {
    let durations = Trajectory::piece_durations(spline);
    let starts: Vec<f64> = durations
        .iter()
        .scan(0.0, |t0, d| {
            let start = *t0;
            *t0 += d;
            Some(start)
        })
        .collect();
    let per_span: Vec<Vec<Peak>> = durations
        .par_iter()
        .zip(&starts)
        .enumerate()
        .map(|(span, (d, t0))| {
            let h = d / samples as f64;
            let rows: Vec<Vec<f64>> = (0..=samples).map(|k| f(span, h * k as f64)).collect();
            (0..rows[0].len())
                .map(|c| {
                    let values: Vec<f64> = rows.iter().map(|r| r[c]).collect();
                    let (s, value) = refine_peak(&values, h, &|s| channel(span, s, c));
                    Peak { value, time: t0 + s }
                })
                .collect()
        })
        .collect();
    let mut best: Vec<Peak> = Vec::new();
    for peaks in per_span {
        best.resize(peaks.len(), Peak { value: 0.0, time: 0.0 });
        for (peak, candidate) in best.iter_mut().zip(peaks) {
            if candidate.value > peak.value {
                *peak = candidate;
            }
        }
    }
    best
}
