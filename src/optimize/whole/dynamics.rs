//! The exact engine's formulas written once over a [`Real`], so that the same code gives values
//! at `f64` and exact derivatives at [`Dual`](super::dual::Dual).
//!
//! - [`body_rate`]: A's angular velocity `Ω = −I_lock⁻¹(R I_B Rᵀ ω_rel + μ p × ṗ)` at zero
//!   momentum (DESIGN.md §2; [`crate::engines::exact::body_rate`]), with B's axis `e = R ẑ`,
//!   `R I_B Rᵀ = I_t 𝟙 + (I_a − I_t) e eᵀ` and `−[p]×² = |p|² 𝟙 − p pᵀ`;
//! - [`motor_torques`]: Newton–Euler on B ([`crate::engines::torque`]'s module docs give the equations),
//!   `τ_i = T · a_i` on joint 1's axis `x̂` and joint 2's axis `Rx(q1) ŷ`;
//! - [`magnus6`]: the sixth-order Magnus exponent of one step ([`crate::engines::exact::magnus6`]).
//!
//! They are the reference engine's formulas, not new physics: tests check at `f64` that they agree
//! with [`crate::engines::exact`] and [`crate::engines::torque`] to round-off, and at dual numbers that their
//! derivatives agree with central finite differences. All vectors in A's frame, SI units.

use super::dual::{add, cross, dot, scale, scale_by, solve3, sub, Real, V3};
use crate::model::Cylinder;

/// Mass properties a generic evaluation needs.
struct Halves {
    half: f64,
    transverse: f64,
    axial_minus_transverse: f64,
    reduced_mass: f64,
    mass: f64,
}

impl Halves {
    fn of(cat: &Cylinder) -> Self {
        Self {
            half: 0.5 * cat.length,
            transverse: cat.transverse(),
            axial_minus_transverse: cat.axial() - cat.transverse(),
            reduced_mass: cat.reduced_mass(),
            mass: cat.mass,
        }
    }

    /// `R I_B Rᵀ v = I_t v + (I_a − I_t)(e·v) e`.
    fn inertia_b<T: Real>(&self, e: V3<T>, v: V3<T>) -> V3<T> {
        add(&scale_by(self.transverse, &v), &scale(dot(&e, &v) * self.axial_minus_transverse, &e))
    }

    /// Rows of `I_lock = I_A + R I_B Rᵀ + μ(|p|² 𝟙 − p pᵀ)`.
    fn locked<T: Real>(&self, e: V3<T>, p: V3<T>) -> [V3<T>; 3] {
        let (it, d, mu) = (self.transverse, self.axial_minus_transverse, self.reduced_mass);
        let pp = dot(&p, &p) * mu;
        let diag = [pp + 2.0 * it, pp + 2.0 * it, pp + (2.0 * it + d)];
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let off = e[i] * e[j] * d - p[i] * p[j] * mu;
                if i == j {
                    diag[i] + off
                } else {
                    off
                }
            })
        })
    }
}

/// B's axis `e = Rx(q1) Ry(q2) ẑ` and `ω_rel = q̇1 x̂ + q̇2 Rx(q1) ŷ`, with `sin q1, cos q1`.
fn joint_kinematics<T: Real>(q: [T; 2], qd: [T; 2]) -> (V3<T>, V3<T>, T, T) {
    let (s1, c1) = q[0].sin_cos();
    let (s2, c2) = q[1].sin_cos();
    let e = [s2, -(s1 * c2), c1 * c2];
    let w_rel = [qd[0], qd[1] * c1, qd[1] * s1];
    (e, w_rel, s1, c1)
}

/// A's angular velocity `Ω` (A's frame) for joint angles `q` and rates `q̇` at zero momentum.
pub fn body_rate<T: Real>(cat: &Cylinder, q: [T; 2], qd: [T; 2]) -> V3<T> {
    let h = Halves::of(cat);
    let (e, w_rel, _, _) = joint_kinematics(q, qd);
    let p = [e[0] * -h.half, e[1] * -h.half, (e[2] + 1.0) * -h.half];
    let pd = scale_by(-h.half, &cross(&w_rel, &e));
    let rhs = add(&h.inertia_b(e, w_rel), &scale_by(h.reduced_mass, &cross(&p, &pd)));
    scale_by(-1.0, &solve3(&h.locked(e, p), &rhs))
}

/// A's angular velocity `Ω = I_lock⁻¹(λ − h)` (A's frame) when the total angular momentum in A's
/// frame is `λ = Rᵀ L` ([`crate::engines::exact::body_rate_spinning`]).
pub fn body_rate_spinning<T: Real>(cat: &Cylinder, q: [T; 2], qd: [T; 2], lambda: V3<T>) -> V3<T> {
    let h = Halves::of(cat);
    let (e, w_rel, _, _) = joint_kinematics(q, qd);
    let p = [e[0] * -h.half, e[1] * -h.half, (e[2] + 1.0) * -h.half];
    let pd = scale_by(-h.half, &cross(&w_rel, &e));
    let rhs = add(&h.inertia_b(e, w_rel), &scale_by(h.reduced_mass, &cross(&p, &pd)));
    solve3(&h.locked(e, p), &sub(&lambda, &rhs))
}

/// Motor torques `(τ1, τ2)`, N·m, of the zero-momentum motion through `(q, q̇, q̈)`.
pub fn motor_torques<T: Real>(cat: &Cylinder, q: [T; 2], qd: [T; 2], qdd: [T; 2]) -> [T; 2] {
    motor_torques_with(cat, q, qd, qdd, None)
}

/// Motor torques `(τ1, τ2)`, N·m, through `(q, q̇, q̈)` when the total angular momentum in A's
/// frame is `λ = Rᵀ L`: `Ω = I_lock⁻¹(λ − h)` and, with `λ̇ = λ × Ω`,
/// `Ω̇ = I_lock⁻¹(λ × Ω − İ_lock Ω − ḣ)` ([`crate::engines::torque::kinematics_spinning`]).
pub fn motor_torques_spinning<T: Real>(cat: &Cylinder, q: [T; 2], qd: [T; 2], qdd: [T; 2], lambda: V3<T>) -> [T; 2] {
    motor_torques_with(cat, q, qd, qdd, Some(lambda))
}

/// [`motor_torques`] (`lambda` none: zero momentum) or [`motor_torques_spinning`].
fn motor_torques_with<T: Real>(cat: &Cylinder, q: [T; 2], qd: [T; 2], qdd: [T; 2], lambda: Option<V3<T>>) -> [T; 2] {
    let h = Halves::of(cat);
    let (e, w_rel, s1, c1) = joint_kinematics(q, qd);
    let a2 = [T::cst(0.0), c1, s1];
    let x_cross_a2 = [T::cst(0.0), -s1, c1];
    let x = [T::cst(1.0), T::cst(0.0), T::cst(0.0)];
    let w_rel_dot = add(&add(&scale(qdd[0], &x), &scale(qdd[1], &a2)), &scale(qd[0] * qd[1], &x_cross_a2));
    let e_dot = cross(&w_rel, &e);
    let e_ddot = add(&cross(&w_rel_dot, &e), &cross(&w_rel, &e_dot));
    let p = [e[0] * -h.half, e[1] * -h.half, (e[2] + 1.0) * -h.half];
    let (pd, pdd) = (scale_by(-h.half, &e_dot), scale_by(-h.half, &e_ddot));
    let mu = h.reduced_mass;
    let locked = h.locked(e, p);
    let shape = add(&h.inertia_b(e, w_rel), &scale_by(mu, &cross(&p, &pd)));
    let omega = match lambda {
        None => scale_by(-1.0, &solve3(&locked, &shape)),
        Some(l) => solve3(&locked, &sub(&l, &shape)),
    };
    // (d/dt R I_B Rᵀ) v = ω_rel × (I_B v) − I_B (ω_rel × v).
    let ib_dot = |v: V3<T>| sub(&cross(&w_rel, &h.inertia_b(e, v)), &h.inertia_b(e, cross(&w_rel, &v)));
    // Ṁ Ω = İ_B Ω − μ (ṗ × (p × Ω) + p × (ṗ × Ω)).
    let m_dot_omega =
        sub(&ib_dot(omega), &scale_by(mu, &add(&cross(&pd, &cross(&p, &omega)), &cross(&p, &cross(&pd, &omega)))));
    let k_dot = add(&add(&ib_dot(w_rel), &h.inertia_b(e, w_rel_dot)), &scale_by(mu, &cross(&p, &pdd)));
    let omega_dot = match lambda {
        None => scale_by(-1.0, &solve3(&locked, &add(&m_dot_omega, &k_dot))),
        Some(l) => solve3(&locked, &sub(&cross(&l, &omega), &add(&m_dot_omega, &k_dot))),
    };
    let a_b = scale_by(
        0.5,
        &add(
            &add(&pdd, &cross(&omega_dot, &p)),
            &add(&scale_by(2.0, &cross(&omega, &pd)), &cross(&omega, &cross(&omega, &p))),
        ),
    );
    let force = scale_by(h.mass, &a_b);
    let w_b = add(&omega, &w_rel);
    let alpha_b = add(&add(&omega_dot, &w_rel_dot), &cross(&omega, &w_rel));
    let d_b = scale_by(h.half, &e);
    let couple = sub(&add(&h.inertia_b(e, alpha_b), &cross(&w_b, &h.inertia_b(e, w_b))), &cross(&d_b, &force));
    [couple[0], dot(&couple, &a2)]
}

/// The sixth-order Magnus exponent of one step from the rates at the three Gauss–Legendre nodes
/// (the formula of [`crate::engines::exact::magnus6`]).
pub fn magnus6<T: Real>(h: f64, w1: V3<T>, w2: V3<T>, w3: V3<T>) -> V3<T> {
    let a1 = scale_by(h, &w2);
    let a2 = scale_by(15f64.sqrt() * h / 3.0, &sub(&w3, &w1));
    let a3 = scale_by(10.0 * h / 3.0, &add(&sub(&w3, &scale_by(2.0, &w2)), &w1));
    let c1 = cross(&a1, &a2);
    let c2 = scale_by(1.0 / 60.0, &cross(&a1, &sub(&c1, &scale_by(2.0, &a3))));
    let bracket = cross(&add(&add(&scale_by(20.0, &a1), &a3), &c1), &sub(&c2, &a2));
    sub(&add(&a1, &scale_by(1.0 / 12.0, &a3)), &scale_by(1.0 / 240.0, &bracket))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::whole::dual::Dual;
    use crate::schedule::JointState;
    use approx::assert_relative_eq;
    use nalgebra::Vector3;

    const CAT: Cylinder = Cylinder { mass: 1.3, length: 0.9, radius: 0.17 };
    const POINTS: [([f64; 2], [f64; 2], [f64; 2]); 3] = [
        ([0.3, -0.7], [1.1, 0.4], [-2.0, 3.0]),
        ([2.2, 0.9], [-0.6, 1.7], [0.5, -1.5]),
        ([-1.0, 1.3], [0.2, -2.4], [4.0, 0.7]),
    ];

    #[test]
    fn agrees_with_the_reference_engine() {
        for (q, qd, qdd) in POINTS {
            let w = body_rate(&CAT, q, qd);
            let reference = crate::engines::exact::body_rate(&CAT, q, qd);
            assert_relative_eq!(Vector3::from(w), reference, epsilon = 1e-13);
            let tau = motor_torques(&CAT, q, qd, qdd);
            let reference = crate::engines::torque::joint_torques(&CAT, &JointState { q, qd, qdd }).tau;
            assert_relative_eq!(tau[0], reference[0], epsilon = 1e-12);
            assert_relative_eq!(tau[1], reference[1], epsilon = 1e-12);
        }
        let w = [Vector3::new(0.1, 0.2, -0.3), Vector3::new(0.4, -0.1, 0.2), Vector3::new(-0.2, 0.3, 0.5)];
        let sigma = magnus6(0.3, w[0].into(), w[1].into(), w[2].into());
        assert_relative_eq!(
            Vector3::from(sigma),
            crate::engines::exact::magnus6(0.3, w[0], w[1], w[2]),
            epsilon = 1e-15
        );
    }

    #[test]
    fn dual_derivatives_match_central_differences() {
        // Central differences with step 1e-6 have truncation error ~1e-12·f''' and round-off
        // ~1e-10/1e-6·|f|: 1e-7 absolute covers both at these O(1) values.
        let step = 1e-6;
        for (q, qd, qdd) in POINTS {
            let x = [q[0], q[1], qd[0], qd[1], qdd[0], qdd[1]];
            let d: [Dual<6>; 6] = std::array::from_fn(|k| Dual::input(x[k], k));
            let tau = motor_torques(&CAT, [d[0], d[1]], [d[2], d[3]], [d[4], d[5]]);
            let w = body_rate(&CAT, [d[0], d[1]], [d[2], d[3]]);
            for k in 0..6 {
                let at = |sign: f64| {
                    let mut y = x;
                    y[k] += sign * step;
                    (
                        motor_torques(&CAT, [y[0], y[1]], [y[2], y[3]], [y[4], y[5]]),
                        body_rate(&CAT, [y[0], y[1]], [y[2], y[3]]),
                    )
                };
                let ((tp, wp), (tm, wm)) = (at(1.0), at(-1.0));
                for j in 0..2 {
                    assert_relative_eq!(tau[j].eps[k], (tp[j] - tm[j]) / (2.0 * step), epsilon = 1e-7);
                }
                for i in 0..3 {
                    assert_relative_eq!(w[i].eps[k], (wp[i] - wm[i]) / (2.0 * step), epsilon = 1e-7);
                }
            }
        }
    }
}
