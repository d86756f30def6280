//! The exact motor torques of a spline on any model, as the re-measurement and the knot
//! refinement read them: a two-motor [`TorqueSource`] (the paper's cat through the two-cylinder
//! engine, any other two-motor model through the general core, either released with spin), or
//! the general core's Newton–Euler on every coordinate of a tree's spline (the spherical joint, a
//! tail: [`crate::engines::reduction::joint_torques`] on [`SplineShape`]), one torque per motor.

use super::spline::{BSpline, SplineShape};
use nalgebra::Vector3;

use crate::engines::motors::MotorDemand;
use crate::engines::reduction;
use crate::engines::shape::ShapeTrajectory;
use crate::engines::torque::{refine_peak, Peak, TorqueSource};
use crate::model::shape::ShapeState;
use crate::model::tree::Tree;
use crate::schedule::Trajectory;

/// Where a spline's exact torques come from.
pub enum ExactTorques<'a> {
    /// A two-motor model's source.
    TwoMotor(TorqueSource<'a>),
    /// The general core on every coordinate of a tree (the spherical joint, a tail), every
    /// joint's motors in link order, at zero angular momentum.
    General(Tree),
}

impl ExactTorques<'_> {
    /// The motor torques at local time `s` of span `span`, one per motor, N·m.
    pub fn at(&self, spline: &BSpline, span: usize, s: f64) -> Vec<f64> {
        match self {
            ExactTorques::TwoMotor(source) => source.at(spline, span, s, &spline.piece_state(span, s)).tau.to_vec(),
            ExactTorques::General(tree) => general(tree, &SplineShape(spline).piece_shape(span, s)),
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
            ExactTorques::General(tree) => general(tree, &spline.shape_from(&spline.basis(spline.span_of(end), end))),
        }
    }

    /// The largest peak `|τ_j|` of every motor over `spline`: `samples + 1` points per span, every
    /// sampled local maximum that could be the peak refined by golden section, as
    /// [`crate::engines::torque::peak_torques_on`] refines them.
    pub fn peak(&self, spline: &BSpline, samples: usize) -> Peak {
        let motors = self.at(spline, 0, 0.0).len();
        (0..motors)
            .map(|j| spline_peak(spline, samples, |span, s| self.at(spline, span, s)[j].abs()))
            .fold(Peak { value: 0.0, time: 0.0 }, |best, p| if p.value > best.value { p } else { best })
    }

    /// What `spline` asks of ideal motors, one entry per motor: the peaks of `|q̇_j|` and
    /// `|τ_j q̇_j|`, found as [`ExactTorques::peak`] finds the torque's (the motor limits' usage
    /// is the two-motor [`crate::engines::motors::motor_demand_from`]'s).
    pub fn ideal_demand(&self, spline: &BSpline, samples: usize) -> MotorDemand {
        let rate = |span: usize, s: f64, j: usize| SplineShape(spline).piece_shape(span, s).qd[j];
        let joints = 0..spline.joints();
        MotorDemand {
            peak_speed_rad_s: joints
                .clone()
                .map(|j| spline_peak(spline, samples, |span, s| rate(span, s, j).abs()))
                .collect(),
            peak_power_w: joints
                .map(|j| spline_peak(spline, samples, |span, s| (self.at(spline, span, s)[j] * rate(span, s, j)).abs()))
                .collect(),
            limits: Vec::new(),
            stretch: None,
        }
    }
}

/// Every joint's motor torques of `tree` at `shape` (zero angular momentum), in link order.
fn general(tree: &Tree, shape: &ShapeState) -> Vec<f64> {
    reduction::joint_torques(tree, shape, &Vector3::zeros()).into_iter().flat_map(|l| l.tau).collect()
}

/// The peak of `f(span, s) ≥ 0` over `spline` from `samples + 1` points per span, every sampled
/// local maximum that could be the peak refined by golden section, as
/// [`crate::engines::torque::peak_torques_on`] refines them; its time global, s.
fn spline_peak(spline: &BSpline, samples: usize, f: impl Fn(usize, f64) -> f64) -> Peak {
    let mut best = Peak { value: 0.0, time: 0.0 };
    let mut t0 = 0.0;
    for (span, d) in Trajectory::piece_durations(spline).into_iter().enumerate() {
        let h = d / samples as f64;
        let values: Vec<f64> = (0..=samples).map(|k| f(span, h * k as f64)).collect();
        let (s, value) = refine_peak(&values, h, &|s| f(span, s));
        if value > best.value {
            best = Peak { value, time: t0 + s };
        }
        t0 += d;
    }
    best
}
