//! A release with spin: the reorientation and the momentum in A's frame when the total angular
//! momentum `L` about the centre of mass is not zero (DESIGN.md §9).
//!
//! Falling freely, the cat's angular momentum about its centre of mass is constant in the world
//! frame. In A's frame it is `λ(t) = R(t)ᵀ L`, and the momentum balance of §2 becomes
//!
//! $$ I_{lock}(q)\, Ω + h(q, \dot q) = R^\top L, \qquad Ω = I_{lock}^{-1}\big(R^\top L − h\big), $$
//!
//! with `h = R_AB I_B R_ABᵀ ω_rel + μ p × ṗ` the momentum of the joint motion at zero base rate
//! (the bracket of [`crate::engines::exact`]). `Ω` now depends on `R`, so A's orientation obeys
//! the nonlinear `Ṙ = R [Ω(t, R)]×`. [`crate::engines::exact::rk4_on`] integrates it by the classical fourth-order
//! Runge–Kutta method on the quaternion `ṙ = ½ r ⊗ (0, Ω)`, normalised after each step (the
//! normalisation changes the result by the step's own error, so the order stays four).
//!
//! Differentiating `λ = Rᵀ L` gives `λ̇ = −[Ω]× λ = λ × Ω`, the term that the torques
//! ([`crate::engines::torque::kinematics_spinning`]) add to `Ω̇`. The torques at an instant then
//! need `λ` there, i.e. A's orientation: [`SpinHistory`] keeps the orientations of the accepted
//! adaptive integration and reaches any instant from the node before it by one Runge–Kutta step
//! (local error `O(h⁵)`, below the integration's own).
//!
//! Checks (tests/spin.rs): a rigid straight cat is a torque-free symmetric top (closed form);
//! `L` along a principal axis of the straight cat is a steady spin; `L = 0` reproduces the Magnus
//! engine; `|λ| = |L|` and `I_lock Ω + h = λ` along every motion; independent reference values.
//!
//! ## References
//! - H. Goldstein, *Classical Mechanics* (3rd ed., 2002), §5.6, the torque-free symmetric top;
//! - E. Hairer, C. Lubich, G. Wanner, *Geometric Numerical Integration* (2006), §IV.4, for
//!   projection onto the unit sphere after a step.

use nalgebra::{UnitQuaternion, Vector3};

use crate::engines::exact::{adaptive, adaptive_on, rk4_on, CylinderField, Flip, PieceNodes, RateField, Stepper};
use crate::model::Cylinder;
use crate::schedule::Trajectory;

/// A's orientation along a motion released with spin, at any instant: the accepted adaptive
/// integration's nodes, and one Runge–Kutta step from the node before the instant.
#[derive(Clone, Debug, PartialEq)]
pub struct SpinHistory {
    /// Total angular momentum `L`, world frame, N·m·s.
    pub spin: Vector3<f64>,
    /// Per piece, `(local time, R)` at every accepted step, the piece's start first.
    nodes: Vec<PieceNodes>,
}

impl SpinHistory {
    /// Integrates `traj` released with `spin` to `tolerance` ([`crate::engines::exact::flip_spinning`]) and
    /// keeps the orientations; returns the flip with them.
    pub fn new(cat: &Cylinder, traj: &impl Trajectory, spin: &Vector3<f64>, tolerance: f64) -> (Flip, SpinHistory) {
        let mut nodes = Vec::new();
        let flip = adaptive(cat, traj, Stepper::Spinning(*spin), tolerance, Some(&mut nodes));
        (flip, SpinHistory { spin: *spin, nodes })
    }

    /// [`SpinHistory::new`] on any [`RateField`] (another cat model's,
    /// [`crate::engines::models::TwoMotorCat::flip_spinning`]).
    pub fn new_on(field: &impl RateField, spin: &Vector3<f64>, tolerance: f64) -> (Flip, SpinHistory) {
        let mut nodes = Vec::new();
        let flip = adaptive_on(field, Stepper::Spinning(*spin), tolerance, Some(&mut nodes));
        (flip, SpinHistory { spin: *spin, nodes })
    }

    /// A's orientation at local time `s` of `piece`.
    pub fn orientation(&self, cat: &Cylinder, traj: &impl Trajectory, piece: usize, s: f64) -> UnitQuaternion<f64> {
        self.orientation_on(&CylinderField { cat, traj }, piece, s)
    }

    /// [`SpinHistory::orientation`] on the [`RateField`] the history was integrated on.
    pub fn orientation_on(&self, field: &impl RateField, piece: usize, s: f64) -> UnitQuaternion<f64> {
        let Some(nodes) = self.nodes.get(piece).filter(|n| !n.is_empty()) else {
            return UnitQuaternion::identity();
        };
        let k = nodes.partition_point(|(t, _)| *t <= s).saturating_sub(1);
        let (t, r) = nodes[k];
        let h = s - t;
        if h > 0.0 {
            rk4_on(field, piece, &self.spin, &r, t, h)
        } else {
            r
        }
    }

    /// The total angular momentum in A's frame, `λ = Rᵀ L`, at local time `s` of `piece`.
    pub fn body_momentum(&self, cat: &Cylinder, traj: &impl Trajectory, piece: usize, s: f64) -> Vector3<f64> {
        self.body_momentum_on(&CylinderField { cat, traj }, piece, s)
    }

    /// [`SpinHistory::body_momentum`] on the [`RateField`] the history was integrated on.
    pub fn body_momentum_on(&self, field: &impl RateField, piece: usize, s: f64) -> Vector3<f64> {
        self.orientation_on(field, piece, s).inverse_transform_vector(&self.spin)
    }
}
