//! The cat the whole-manoeuvre optimiser plans for: one seam for the paper's cat and every other
//! two-motor model (DESIGN.md §10).
//!
//! [`WholeCat::Paper`] is the paper's cat (two equal halves on the universal joint), which runs
//! through exactly the functions the optimiser was written with: [`super::dynamics`] for the
//! model and its derivatives, [`crate::engines::exact`] and [`crate::engines::torque`] for the
//! re-measurement and [`crate::engines::calibrate::calibrate_spinning`] for the starts, so its
//! results are bit-identical to the optimiser before the seam. [`WholeCat::Model`] is any other
//! two-motor [`Cat`] (unequal halves, the no-twist joint): [`super::model_dynamics`] for the model,
//! the general core [`TwoMotorCat`] for the flip, the torques and the calibration.
//! [`WholeCat::new`] chooses the branch by [`Cat::paper`].
//!
//! What depends on the joint is here too: the bend `β`, the angle between the spines, with
//! `cos β = e_z` for B's spine `e = R_AB ẑ`: `cos q1 cos q2` on the universal joint, `cos |q|` on
//! the no-twist joint ([`WholeCat::bend_cosine`]).

use nalgebra::Vector3;

use super::dual::{Real, V3};
use super::dynamics;
use super::model_dynamics::{self, ExpSeries};
use super::settings::WholeError;
use crate::engines::calibrate::{calibrate_model, calibrate_spinning, Calibration};
use crate::engines::exact::{self, Flip};
use crate::engines::models::TwoMotorCat;
use crate::engines::spin::SpinHistory;
use crate::engines::torque::TorqueSource;
use crate::model::{Cat, Cylinder, Joint};
use crate::schedule::{paper_circulation, Schedule, ScheduleError, Trajectory};

/// The optimiser's cat: the paper's, or another two-motor model (module docs).
#[derive(Clone, Debug, PartialEq)]
pub enum WholeCat {
    /// The paper's cat, one of its two equal halves (the two-cylinder engine).
    Paper(Cylinder),
    /// Any other two-motor model (the general core).
    Model(TwoMotorCat),
}

impl From<Cylinder> for WholeCat {
    /// The paper's cat of two halves `half`.
    fn from(half: Cylinder) -> WholeCat {
        WholeCat::Paper(half)
    }
}

impl From<&Cylinder> for WholeCat {
    /// The paper's cat of two halves `half`.
    fn from(half: &Cylinder) -> WholeCat {
        WholeCat::Paper(*half)
    }
}

impl From<&WholeCat> for WholeCat {
    /// A copy, so that the optimiser's entry points take a cat by reference too.
    fn from(cat: &WholeCat) -> WholeCat {
        cat.clone()
    }
}

impl From<&TwoMotorCat> for WholeCat {
    /// The model's branch: the paper's cat when it is one ([`Cat::paper`]).
    fn from(model: &TwoMotorCat) -> WholeCat {
        match model.cat().paper() {
            Some(half) => WholeCat::Paper(*half),
            None => WholeCat::Model(model.clone()),
        }
    }
}

impl WholeCat {
    /// `cat`'s branch ([`Cat::paper`] chooses), refused when its joint has not two motors
    /// (naming `cat.joint`).
    pub fn new(cat: Cat) -> Result<WholeCat, WholeError> {
        let model = TwoMotorCat::new(cat).map_err(|e| WholeError::BadFieldValue {
            field: "cat.joint",
            value: format!("\"{}\"", cat.joint),
            reason: format!("the whole optimiser plans two motors ({e}): use \"universal\" or \"no-twist\""),
        })?;
        Ok(WholeCat::from(&model))
    }

    /// The model as a [`Cat`].
    pub fn cat(&self) -> Cat {
        match self {
            WholeCat::Paper(half) => Cat::from(*half),
            WholeCat::Model(m) => *m.cat(),
        }
    }

    /// The model in words ([`Cat::describe`]).
    pub fn describe(&self) -> String {
        self.cat().describe()
    }

    /// The joint.
    pub fn joint(&self) -> Joint {
        match self {
            WholeCat::Paper(_) => Joint::Universal,
            WholeCat::Model(m) => m.cat().joint,
        }
    }

    /// A's angular velocity (A's frame) through `(q, q̇)` at zero momentum.
    pub fn body_rate<T: Real>(&self, q: [T; 2], qd: [T; 2]) -> V3<T> {
        match self {
            WholeCat::Paper(c) => dynamics::body_rate(c, q, qd),
            WholeCat::Model(m) => model_dynamics::body_rate(m.cat(), q, qd),
        }
    }

    /// A's angular velocity with the total momentum `λ = Rᵀ L` in A's frame.
    pub fn body_rate_spinning<T: Real>(&self, q: [T; 2], qd: [T; 2], lambda: V3<T>) -> V3<T> {
        match self {
            WholeCat::Paper(c) => dynamics::body_rate_spinning(c, q, qd, lambda),
            WholeCat::Model(m) => model_dynamics::body_rate_spinning(m.cat(), q, qd, lambda),
        }
    }

    /// The motor torques `(τ1, τ2)`, N·m, through `(q, q̇, q̈)` at zero momentum.
    pub fn motor_torques<T: Real>(&self, q: [T; 2], qd: [T; 2], qdd: [T; 2]) -> [T; 2] {
        match self {
            WholeCat::Paper(c) => dynamics::motor_torques(c, q, qd, qdd),
            WholeCat::Model(m) => model_dynamics::motor_torques(m.cat(), q, qd, qdd),
        }
    }

    /// The motor torques with the total momentum `λ = Rᵀ L` in A's frame.
    pub fn motor_torques_spinning<T: Real>(&self, q: [T; 2], qd: [T; 2], qdd: [T; 2], lambda: V3<T>) -> [T; 2] {
        match self {
            WholeCat::Paper(c) => dynamics::motor_torques_spinning(c, q, qd, qdd, lambda),
            WholeCat::Model(m) => model_dynamics::motor_torques_spinning(m.cat(), q, qd, qdd, lambda),
        }
    }

    /// B's spine `e = R_AB ẑ` in A's frame at `q`.
    pub fn spine(&self, q: [f64; 2]) -> [f64; 3] {
        model_dynamics::spine(self.joint(), q)
    }

    /// The cosine of the bend, `cos β = e_z`, and its gradient in `q`: `cos q1 cos q2` on the
    /// universal joint, `cos |q|` (gradient `−(sin θ/θ) q`) on the no-twist joint.
    pub fn bend_cosine(&self, q: [f64; 2]) -> (f64, [f64; 2]) {
        match self.joint() {
            Joint::Universal => {
                let (s1, c1) = q[0].sin_cos();
                let (s2, c2) = q[1].sin_cos();
                (c1 * c2, [-s1 * c2, -c1 * s2])
            }
            Joint::NoTwist | Joint::Spherical => {
                let s = q[0] * q[0] + q[1] * q[1];
                let k = ExpSeries::at(s);
                (1.0 - k.a * s, [-k.sinc * q[0], -k.sinc * q[1]])
            }
        }
    }

    /// The flip of `traj` at zero momentum, to `tolerance` rad.
    pub fn flip(&self, traj: &impl Trajectory, tolerance: f64) -> Flip {
        match self {
            WholeCat::Paper(c) => exact::flip(c, traj, tolerance),
            WholeCat::Model(m) => m.flip(traj, tolerance),
        }
    }

    /// The flip of `traj` released with total angular momentum `spin` (N·m·s, world frame).
    pub fn flip_spinning(&self, traj: &impl Trajectory, spin: &Vector3<f64>, tolerance: f64) -> Flip {
        match self {
            WholeCat::Paper(c) => exact::flip_spinning(c, traj, spin, tolerance),
            WholeCat::Model(m) => m.flip_released(traj, spin, tolerance),
        }
    }

    /// The flip released with `spin` and the orientations its torques need.
    pub fn spin_history(&self, traj: &impl Trajectory, spin: &Vector3<f64>, tolerance: f64) -> (Flip, SpinHistory) {
        match self {
            WholeCat::Paper(c) => SpinHistory::new(c, traj, spin, tolerance),
            WholeCat::Model(m) => m.flip_spinning(traj, spin, tolerance),
        }
    }

    /// Where the exact torques come from: zero momentum, or the motion of `history`.
    pub fn torque_source<'a>(&'a self, history: Option<&'a SpinHistory>) -> TorqueSource<'a> {
        match (self, history) {
            (WholeCat::Paper(c), None) => TorqueSource::zero_momentum(c),
            (WholeCat::Paper(c), Some(h)) => TorqueSource::spinning(c, h),
            (WholeCat::Model(m), None) => TorqueSource::model(m),
            (WholeCat::Model(m), Some(h)) => TorqueSource::model_spinning(m, h),
        }
    }

    /// The circulation that turns `schedule` by ±π released with `spin`, to `tolerance` rad.
    pub fn calibrate(&self, schedule: &Schedule, spin: &Vector3<f64>, tolerance: f64) -> Calibration {
        match self {
            WholeCat::Paper(c) => calibrate_spinning(c, schedule, spin, tolerance),
            WholeCat::Model(m) => calibrate_model(m, schedule, spin, tolerance),
        }
    }

    /// The paper's `π/C` at the angle `theta` between the halves (of the mean half,
    /// [`Cat::mean_half`], when the halves differ: a start for the calibration only).
    pub fn paper_circulation(&self, theta: f64) -> Result<f64, ScheduleError> {
        match self {
            WholeCat::Paper(c) => paper_circulation(c, theta),
            WholeCat::Model(m) => paper_circulation(&m.cat().mean_half(), theta),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HALF: Cylinder = Cylinder { mass: 1.0, length: 1.0, radius: 0.1 };

    #[test]
    fn the_paper_cat_takes_the_paper_branch_and_others_the_model() {
        assert_eq!(WholeCat::new(Cat::from(HALF)).ok(), Some(WholeCat::Paper(HALF)));
        let kane = WholeCat::new(Cat::equal(HALF, Joint::NoTwist)).unwrap_or_else(|e| panic!("{e}"));
        assert!(matches!(kane, WholeCat::Model(_)), "{kane:?}");
        let e = WholeCat::new(Cat::equal(HALF, Joint::Spherical)).map(|_| ()).unwrap_err();
        assert!(e.to_string().starts_with("cat.joint = \"spherical\""), "{e}");
    }

    #[test]
    fn the_bend_is_the_angle_between_the_spines_with_its_gradient() {
        for joint in [Joint::Universal, Joint::NoTwist] {
            let cat = WholeCat::new(Cat::equal(HALF, joint)).unwrap_or_else(|e| panic!("{e}"));
            for q in [[0.0, 0.0], [1e-3, -2e-3], [0.4, -0.9], [1.7, 0.6]] {
                let (c, g) = cat.bend_cosine(q);
                assert!((c - cat.spine(q)[2]).abs() < 1e-15, "{joint}: {c} at {q:?}");
                if joint == Joint::NoTwist {
                    assert!((c - q[0].hypot(q[1]).cos()).abs() < 1e-15, "the no-twist bend is |q|");
                }
                for k in 0..2 {
                    let step = 1e-6;
                    let mut p = q;
                    p[k] += step;
                    let mut m = q;
                    m[k] -= step;
                    let fd = (cat.bend_cosine(p).0 - cat.bend_cosine(m).0) / (2.0 * step);
                    assert!((g[k] - fd).abs() < 1e-9, "{joint}: ∂/∂q{k} {} against {fd}", g[k]);
                }
            }
        }
    }
}
