//! The zero-momentum reduction of a tree of rigid bodies, written once for every model
//! (DESIGN.md §2, §9, §10): the base's angular velocity and the torques each joint transmits.
//!
//! With the bodies' motion relative to the base A ([`Tree::motion`]: `R_k`, `r_k` from the centre
//! of mass, `w_k` relative to A, all in A's frame) and A turning at `Ω`, body `k` turns at
//! `ω_k = Ω + w_k` and its centre moves at `ṙ_k + Ω × r_k`, so the angular momentum about the
//! centre of mass, in A's frame, is
//!
//! $$ H = I_{lock} Ω + h, \quad I_{lock} = Σ_k \big(I'_k − m_k \[r_k\]_×^2\big), \quad
//!    h = Σ_k \big(I'_k w_k + m_k\, r_k × \dot r_k\big), \quad I'_k = R_k I_k R_k^\top. $$
//!
//! Released with total momentum `L` (world frame), `λ = Rᵀ L` in A's frame and
//! `Ω = I_lock⁻¹ (λ − h)` ([`body_rate`]; `λ = 0` is the zero-momentum flip). Its rate follows
//! from `λ̇ = λ × Ω`:
//!
//! $$ \dot Ω = I_{lock}^{-1}\big(λ × Ω − \dot I_{lock} Ω − \dot h\big), \quad
//!    \dot I_{lock} = Σ_k \big(\[w_k\]_× I'_k − I'_k \[w_k\]_× − m_k(\[\dot r_k\]_×\[r_k\]_× + \[r_k\]_×\[\dot r_k\]_×)\big), $$
//! $$ \dot h = Σ_k \big(\dot I'_k w_k + I'_k \dot w_k + m_k\, r_k × \ddot r_k\big). $$
//!
//! Body `k` then has the angular acceleration `α_k = Ω̇ + ẇ_k + Ω × w_k` and its centre the
//! inertial acceleration `a_k = r̈_k + Ω̇ × r_k + 2 Ω × ṙ_k + Ω × (Ω × r_k)` (A's components).
//! In free fall a joint is the only thing acting on the subtree `S` it carries, so the couple it
//! transmits to `S` about the joint point `P` and its force are
//!
//! $$ T = Σ_{k∈S} \big(I'_k α_k + ω_k × I'_k ω_k + (r_k − r_P) × m_k a_k\big), \quad
//!    F = Σ_{k∈S} m_k a_k, $$
//!
//! and the motor torques are `T`'s projections on the joint's motor axes
//! ([`crate::model::Joint::motor_axes`]). The rest of the tree receives `−T` (action =
//! reaction): the same sum over the bodies outside `S`, negated, is [`LinkTorques::from_base_side`],
//! and the two agree exactly when `Ḣ = 0`, which makes them a check of `Ω̇`.
//!
//! ## References
//! - R. Montgomery, *Gauge theory of the falling cat* (1993), the mechanical connection;
//! - R. Featherstone, *Rigid Body Dynamics Algorithms* (2008), ch. 2 and 9 (floating bases).

use nalgebra::{Matrix2, Matrix3, Vector3};

use crate::engines::exact::solve_spd;
use crate::model::shape::ShapeState;
use crate::model::tree::{Tree, TreeMotion};

/// `I_lock` and `h` of a tree's motion (the module's equations).
pub fn locked_and_shape_momentum(tree: &Tree, motion: &TreeMotion) -> (Matrix3<f64>, Vector3<f64>) {
    let mut m = Matrix3::zeros();
    let mut h = Vector3::zeros();
    for (b, k) in tree.bodies().iter().zip(&motion.bodies) {
        let rx = k.position.cross_matrix();
        m += k.inertia - rx * rx * b.mass;
        h += k.inertia * k.rate + k.position.cross(&k.velocity) * b.mass;
    }
    (m, h)
}

/// A's angular velocity `Ω = I_lock⁻¹ (λ − h)`, A's frame, at `shape` with the total angular
/// momentum `λ` in A's frame (zero for the zero-momentum flip).
pub fn body_rate(tree: &Tree, shape: &ShapeState, lambda: &Vector3<f64>) -> Vector3<f64> {
    let (m, h) = locked_and_shape_momentum(tree, &tree.motion(shape));
    solve_spd(&m, &(lambda - h))
}

/// The total angular momentum about the centre of mass, A's frame, of the motion at `shape` with
/// A turning at `omega`, summed body by body from their inertial velocities.
pub fn momentum(tree: &Tree, shape: &ShapeState, omega: &Vector3<f64>) -> Vector3<f64> {
    let motion = tree.motion(shape);
    tree.bodies()
        .iter()
        .zip(&motion.bodies)
        .map(|(b, k)| {
            k.inertia * (omega + k.rate) + k.position.cross(&(k.velocity + omega.cross(&k.position))) * b.mass
        })
        .sum()
}

/// The base's motion with the relative motion it goes with.
#[derive(Clone, Debug, PartialEq)]
pub struct Dynamics {
    /// The bodies' and joints' motion relative to A ([`Tree::motion`]).
    pub motion: TreeMotion,
    /// `Ω`, rad/s.
    pub omega: Vector3<f64>,
    /// `Ω̇`, rad/s².
    pub omega_dot: Vector3<f64>,
}

/// `Ω` and `Ω̇` at `shape` with total momentum `λ` in A's frame (the module's equations).
pub fn dynamics(tree: &Tree, shape: &ShapeState, lambda: &Vector3<f64>) -> Dynamics {
    let motion = tree.motion(shape);
    let (m, h) = locked_and_shape_momentum(tree, &motion);
    let omega = solve_spd(&m, &(lambda - h));
    let mut m_dot = Matrix3::zeros();
    let mut h_dot = Vector3::zeros();
    for (b, k) in tree.bodies().iter().zip(&motion.bodies) {
        let wx = k.rate.cross_matrix();
        let i_dot = wx * k.inertia - k.inertia * wx;
        let (rx, vx) = (k.position.cross_matrix(), k.velocity.cross_matrix());
        m_dot += i_dot - (vx * rx + rx * vx) * b.mass;
        h_dot += i_dot * k.rate + k.inertia * k.rate_dot + k.position.cross(&k.acceleration) * b.mass;
    }
    let omega_dot = solve_spd(&m, &(lambda.cross(&omega) - m_dot * omega - h_dot));
    Dynamics { motion, omega, omega_dot }
}

/// What one joint transmits to the subtree it carries.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkTorques {
    /// The couple's projections on the motor axes, N·m.
    pub tau: Vec<f64>,
    /// The same from the rest of the tree (action = reaction), N·m.
    pub from_base_side: Vec<f64>,
    /// The couple about the joint point, A's frame, N·m.
    pub couple: Vector3<f64>,
    /// The force, A's frame, N.
    pub force: Vector3<f64>,
}

/// Every joint's torques at `shape` with total momentum `λ` in A's frame, link by link.
pub fn joint_torques(tree: &Tree, shape: &ShapeState, lambda: &Vector3<f64>) -> Vec<LinkTorques> {
    torques_on(tree, &dynamics(tree, shape, lambda))
}

/// Every joint's torques, link by link, from the tree's dynamics `d` at a shape ([`dynamics`]),
/// for a caller that needs `Ω` and `Ω̇` too.
pub fn torques_on(tree: &Tree, d: &Dynamics) -> Vec<LinkTorques> {
    let (w, wd) = (d.omega, d.omega_dot);
    // Each body's momentum rate about a point, and its inertial force.
    let per_body: Vec<(Vector3<f64>, Vector3<f64>, Vector3<f64>)> = tree
        .bodies()
        .iter()
        .zip(&d.motion.bodies)
        .map(|(b, k)| {
            let omega_k = w + k.rate;
            let alpha_k = wd + k.rate_dot + w.cross(&k.rate);
            let a_k =
                k.acceleration + wd.cross(&k.position) + 2.0 * w.cross(&k.velocity) + w.cross(&w.cross(&k.position));
            (k.inertia * alpha_k + omega_k.cross(&(k.inertia * omega_k)), k.position, a_k * b.mass)
        })
        .collect();
    d.motion
        .links
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let inside = tree.subtree(i);
            let about = |keep: bool| -> (Vector3<f64>, Vector3<f64>) {
                per_body
                    .iter()
                    .zip(&inside)
                    .filter(|(_, s)| **s == keep)
                    .fold((Vector3::zeros(), Vector3::zeros()), |(t, f), ((spin, r, ma), _)| {
                        (t + spin + (r - l.point).cross(ma), f + ma)
                    })
            };
            let (couple, force) = about(true);
            let (rest, _) = about(false);
            LinkTorques {
                tau: l.axes.iter().map(|a| couple.dot(a)).collect(),
                from_base_side: l.axes.iter().map(|a| -rest.dot(a)).collect(),
                couple,
                force,
            }
        })
        .collect()
}

/// The mass matrix `M` of a quadratic kinetic energy `E(q̇) = ½ q̇ᵀ M q̇` from three of its
/// values: `M₁₁ = 2E(1,0)`, `M₂₂ = 2E(0,1)`, `M₁₂ = E(1,1) − E(1,0) − E(0,1)`.
pub fn polarised_mass_matrix(energy: impl Fn([f64; 2]) -> f64) -> Matrix2<f64> {
    let e1 = energy([1.0, 0.0]);
    let e2 = energy([0.0, 1.0]);
    let off = energy([1.0, 1.0]) - e1 - e2;
    Matrix2::new(2.0 * e1, off, off, 2.0 * e2)
}
