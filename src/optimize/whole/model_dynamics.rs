//! The dynamics of any cat of two halves ([`Cat`]: unequal halves, the universal, no-twist or
//! spherical joint) written once over a [`Real`], so that the optimiser gets values at `f64` and
//! exact derivatives at [`Dual`](super::dual::Dual) for every model, as [`super::dynamics`] gives
//! them for the paper's cat. The joint's coordinates come as arrays of [`Joint::dof`] numbers,
//! `q: [T; N]` (two, or three on the spherical joint), so that nothing is allocated.
//!
//! ## Joint kinematics
//! Only the joint differs between the models. With B's spine `e(q) = R_AB ẑ` (A's frame),
//! `ė = ω_rel × e` and `ë = ω̇_rel × e + ω_rel × ė`:
//!
//! - **universal**, `R_AB = Rx(q1) Ry(q2)`: `e = (sin q2, −sin q1 cos q2, cos q1 cos q2)`,
//!   `ω_rel = q̇1 x̂ + q̇2 a₂`, `a₂ = Rx(q1) ŷ`, `ω̇_rel = q̈1 x̂ + q̈2 a₂ + q̇1 q̇2 x̂ × a₂`; motors
//!   on `x̂` and `a₂`;
//! - **no-twist**, `R_AB = exp([v]×)`, `v = (q1, q2, 0)`, `s = θ² = |v|²`:
//!   `e = (σ q2, −σ q1, 1 − a s)`, `ω_rel = J_l(v) v̇ = v̇ + a v × v̇ + b v × (v × v̇)`,
//!   `ω̇_rel = J_l(v) v̈ + ȧ v × v̇ + ḃ v × (v × v̇) + b v̇ × (v × v̇)` with `ȧ = 2 a_s (v·v̇)`,
//!   `ḃ = 2 b_s (v·v̇)`; motors on A's `x̂` and `ŷ`. The coefficients are functions of `s`:
//!   `σ = sin θ/θ`, `a = (1 − cos θ)/θ²`, `b = (θ − sin θ)/θ³`, `a_s = da/ds = (σ − 2a)/(2s)`,
//!   `b_s = db/ds = (a − 3b)/(2s)`; below `s = 1` they are their Taylor series in `s`
//!   ([`ExpSeries`]), so that dual numbers stay finite at the straight cat `q = 0`;
//! - **spherical**, `R_AB = exp([v]×) Rz(q3)`: the no-twist joint followed by a relative twist
//!   `q3` about B's spine. B is axisymmetric, so `R I_B Rᵀ` depends on `e` alone, and `e` is the
//!   no-twist joint's (independent of `q3`); `ω_rel = J_l(v) v̇ + q̇3 e`,
//!   `ω̇_rel = (the no-twist joint's) + q̈3 e + q̇3 (J_l(v) v̇) × e`; motors on A's `x̂`, `ŷ` and
//!   on `e`.
//!
//! ## Mass properties and Newton–Euler
//! B's centre from A's is `p = −(l_A/2) ẑ − (l_B/2) e`, the reduced mass `μ = m_A m_B/M`,
//! `R I_B Rᵀ v = I_tB v + (I_aB − I_tB)(e·v) e` (B axisymmetric) and
//!
//! $$ I_{lock} = I_A + R I_B R^\top + μ(|p|^2 𝟙 − p p^\top), \quad h = R I_B R^\top ω_{rel} + μ\, p × \dot p, $$
//!
//! `Ω = I_lock⁻¹(λ − h)` (`λ = Rᵀ L`, zero without spin) and
//! `Ω̇ = I_lock⁻¹(λ × Ω − İ_lock Ω − ḣ)` ([`crate::engines::reduction`]'s equations for two bodies).
//! B's centre sits at `(m_A/M) p` from the centre of mass, so its acceleration is
//! `a_B = (m_A/M)(p̈ + Ω̇ × p + 2 Ω × ṗ + Ω × (Ω × p))`, and the couple the joint transmits to B
//! about the joint point is `T = I'_B α_B + ω_B × I'_B ω_B − (l_B/2) e × m_B a_B`
//! (`ω_B = Ω + ω_rel`, `α_B = Ω̇ + ω̇_rel + Ω × ω_rel`), projected on the motor axes.
//!
//! Tests check at `f64` against the general core ([`crate::engines::models`],
//! [`crate::engines::reduction`]) and [`Joint`]'s own kinematics, on the paper's cat against
//! [`super::dynamics`], and at dual numbers against central differences.
//! All vectors in A's frame, SI units.
//!
//! ## References
//! - T. R. Kane and M. P. Scher (1969), the no-twist joint;
//! - J. Solà, J. Deray, D. Atchuthan, *A micro Lie theory for state estimation in robotics*
//!   (arXiv:1812.01537, 2018), the left Jacobian of SO(3).

use super::dual::{add, cross, dot, scale, scale_by, solve3, sub, Real, V3};
use crate::model::{Cat, Joint};

/// Below this `θ² = |q|²` the no-twist coefficients come from their Taylor series.
const SERIES_BELOW: f64 = 1.0;

/// Terms of each series: the last is below `1/27! < 1e-28` at `θ² < 1`.
const SERIES_TERMS: usize = 12;

/// The no-twist joint's coefficients at `s = θ²`: `σ`, `a`, `b`, `a_s`, `b_s` (module docs).
#[derive(Clone, Copy, Debug)]
pub struct ExpSeries<T> {
    /// `sin θ/θ`.
    pub sinc: T,
    /// `(1 − cos θ)/θ²`.
    pub a: T,
    /// `(θ − sin θ)/θ³`.
    pub b: T,
    /// `da/ds`.
    pub a_s: T,
    /// `db/ds`.
    pub b_s: T,
}

/// `1/f(k)` for `k < SERIES_TERMS`, with `f(k) = (2k + offset)!`, or `f(k) = (2k + offset)!/(k + 1)`
/// when `per_k` (computed once, at compile time: each evaluation of the series on dual numbers
/// only multiplies and adds).
const fn series(offset: u32, per_k: bool) -> [f64; SERIES_TERMS] {
    let mut out = [0.0; SERIES_TERMS];
    let mut k = 0;
    while k < SERIES_TERMS {
        let n = 2 * k as u32 + offset;
        let mut f = 1.0;
        let mut i = 1;
        while i <= n {
            f *= i as f64;
            i += 1;
        }
        if per_k {
            f /= (k + 1) as f64;
        }
        out[k] = 1.0 / f;
        k += 1;
    }
    out
}

/// `σ`'s coefficients `1/(2k+1)!`.
const SINC: [f64; SERIES_TERMS] = series(1, false);
/// `a`'s, `1/(2k+2)!`.
const A: [f64; SERIES_TERMS] = series(2, false);
/// `b`'s, `1/(2k+3)!`.
const B: [f64; SERIES_TERMS] = series(3, false);
/// `−a_s`'s, `(k+1)/(2k+4)!`.
const A_S: [f64; SERIES_TERMS] = series(4, true);
/// `−b_s`'s, `(k+1)/(2k+5)!`.
const B_S: [f64; SERIES_TERMS] = series(5, true);

/// `Σ_k c_k (−s)^k` by Horner's rule.
fn alternating<T: Real>(s: T, c: &[f64; SERIES_TERMS]) -> T {
    c.iter().rev().fold(T::cst(0.0), |acc, &ck| acc * -s + ck)
}

impl<T: Real> ExpSeries<T> {
    /// The coefficients at `s = θ² ≥ 0`.
    pub fn at(s: T) -> Self {
        if s.value() < SERIES_BELOW {
            // σ = Σ (−s)^k/(2k+1)!, a = Σ (−s)^k/(2k+2)!, b = Σ (−s)^k/(2k+3)!;
            // a_s = −Σ (k+1)(−s)^k/(2k+4)!, b_s = −Σ (k+1)(−s)^k/(2k+5)!.
            Self {
                sinc: alternating(s, &SINC),
                a: alternating(s, &A),
                b: alternating(s, &B),
                a_s: -alternating(s, &A_S),
                b_s: -alternating(s, &B_S),
            }
        } else {
            let theta = s.sqrt();
            let (sn, cs) = theta.sin_cos();
            let sinc = sn / theta;
            let a = (-cs + 1.0) / s;
            let b = (theta - sn) / (s * theta);
            let twice = s * 2.0;
            Self { sinc, a, b, a_s: (sinc - a * 2.0) / twice, b_s: (a - b * 3.0) / twice }
        }
    }
}

/// The joint's motion at one instant (A's frame), `N` its number of coordinates.
#[derive(Clone, Copy, Debug)]
pub struct JointMotion<T, const N: usize> {
    /// B's spine `e = R_AB ẑ`.
    pub spine: V3<T>,
    /// `ω_rel`.
    pub rate: V3<T>,
    /// `ω̇_rel` (zero when no accelerations were given).
    pub accel: V3<T>,
    /// The motor axes, one per coordinate.
    pub axes: [V3<T>; N],
}

/// Panics unless `joint` has `N` coordinates: the caller chose the array size, so a mismatch is a
/// programming error.
fn check_dof<const N: usize>(joint: Joint) {
    assert_eq!(N, joint.dof(), "the {joint} joint has {} coordinates, not {N}", joint.dof());
}

/// B's spine `e(q) = R_AB ẑ` on `joint` (the spherical joint's is the no-twist joint's, whatever
/// its twist `q3`).
///
/// # Panics
/// When `N` is not `joint`'s number of coordinates ([`Joint::dof`]).
pub fn spine<T: Real, const N: usize>(joint: Joint, q: [T; N]) -> V3<T> {
    check_dof::<N>(joint);
    match joint {
        Joint::Universal => {
            let (s1, c1) = q[0].sin_cos();
            let (s2, c2) = q[1].sin_cos();
            [s2, -(s1 * c2), c1 * c2]
        }
        Joint::NoTwist | Joint::Spherical => {
            let s = q[0] * q[0] + q[1] * q[1];
            let k = ExpSeries::at(s);
            [k.sinc * q[1], -(k.sinc * q[0]), -(k.a * s) + 1.0]
        }
        Joint::Hinge => {
            let (s1, c1) = q[0].sin_cos();
            [T::cst(0.0), -s1, c1]
        }
    }
}

/// The joint's motion through `(q, q̇)` and, when given, `q̈` (module docs).
///
/// # Panics
/// When `N` is not `joint`'s number of coordinates ([`Joint::dof`]).
pub fn joint_motion<T: Real, const N: usize>(
    joint: Joint,
    q: [T; N],
    qd: [T; N],
    qdd: Option<[T; N]>,
) -> JointMotion<T, N> {
    check_dof::<N>(joint);
    let (zero, one) = (T::cst(0.0), T::cst(1.0));
    let x = [one, zero, zero];
    match joint {
        Joint::Universal => {
            let (s1, c1) = q[0].sin_cos();
            let a2 = [zero, c1, s1];
            let rate = add(&scale(qd[0], &x), &scale(qd[1], &a2));
            let accel = qdd.map_or([zero; 3], |dd| {
                add(&add(&scale(dd[0], &x), &scale(dd[1], &a2)), &scale(qd[0] * qd[1], &[zero, -s1, c1]))
            });
            let axes = std::array::from_fn(|i| [x, a2][i]);
            JointMotion { spine: spine(joint, q), rate, accel, axes }
        }
        Joint::NoTwist | Joint::Spherical => {
            let (v, vd) = ([q[0], q[1], zero], [qd[0], qd[1], zero]);
            let k = ExpSeries::at(dot(&v, &v));
            // J_l(v) u = u + a v × u + b v × (v × u).
            let jl = |u: V3<T>| {
                let c = cross(&v, &u);
                add(&add(&u, &scale(k.a, &c)), &scale(k.b, &cross(&v, &c)))
            };
            let spine = [k.sinc * q[1], -(k.sinc * q[0]), -(k.a * dot(&v, &v)) + 1.0];
            let bend = jl(vd);
            let twisting = joint == Joint::Spherical;
            let c = cross(&v, &vd);
            let accel = qdd.map_or([zero; 3], |dd| {
                let along = dot(&v, &vd) * 2.0;
                let d = add(&scale(along * k.a_s, &c), &scale(along * k.b_s, &cross(&v, &c)));
                let bent = add(&add(&jl([dd[0], dd[1], zero]), &d), &scale(k.b, &cross(&vd, &c)));
                if twisting {
                    add(&add(&bent, &scale(dd[2], &spine)), &scale(qd[2], &cross(&bend, &spine)))
                } else {
                    bent
                }
            });
            let rate = if twisting { add(&bend, &scale(qd[2], &spine)) } else { bend };
            let axes = std::array::from_fn(|i| [x, [zero, one, zero], spine][i]);
            JointMotion { spine, rate, accel, axes }
        }
        Joint::Hinge => {
            let rate = scale(qd[0], &x);
            let accel = qdd.map_or([zero; 3], |dd| scale(dd[0], &x));
            JointMotion { spine: spine(joint, q), rate, accel, axes: std::array::from_fn(|_| x) }
        }
    }
}

/// The mass properties the dynamics need, from a [`Cat`].
struct MassProperties {
    /// `l_A/2`, `l_B/2`, m.
    front_half: f64,
    rear_half: f64,
    /// A's transverse and axial moments, kg·m².
    front_moments: [f64; 2],
    /// B's transverse moment and axial minus transverse, kg·m².
    rear_transverse: f64,
    rear_excess: f64,
    /// `μ = m_A m_B/M`, kg.
    reduced: f64,
    /// `m_A/M`.
    front_share: f64,
    /// `m_B`, kg.
    rear_mass: f64,
}

impl MassProperties {
    fn of(cat: &Cat) -> Self {
        let (a, b) = (cat.front, cat.rear);
        let total = a.mass + b.mass;
        Self {
            front_half: 0.5 * a.length,
            rear_half: 0.5 * b.length,
            front_moments: [a.transverse(), a.axial()],
            rear_transverse: b.transverse(),
            rear_excess: b.axial() - b.transverse(),
            reduced: a.mass * b.mass / total,
            front_share: a.mass / total,
            rear_mass: b.mass,
        }
    }

    /// `R I_B Rᵀ v` for B's spine `e`.
    fn rear<T: Real>(&self, e: V3<T>, v: V3<T>) -> V3<T> {
        add(&scale_by(self.rear_transverse, &v), &scale(dot(&e, &v) * self.rear_excess, &e))
    }

    /// B's centre from A's, `p = −(l_A/2) ẑ − (l_B/2) e`.
    fn offset<T: Real>(&self, e: V3<T>) -> V3<T> {
        let p = scale_by(-self.rear_half, &e);
        [p[0], p[1], p[2] + -self.front_half]
    }

    /// The rows of `I_lock` at spine `e` and offset `p`.
    fn locked<T: Real>(&self, e: V3<T>, p: V3<T>) -> [V3<T>; 3] {
        let [t, z] = self.front_moments;
        let front = [t, t, z];
        let pp = dot(&p, &p) * self.reduced;
        std::array::from_fn(|i| {
            let mut unit = [T::cst(0.0); 3];
            unit[i] = T::cst(1.0);
            // Column i of I_lock applied to the unit vector: I_A eᵢ + R I_B Rᵀ eᵢ + μ(|p|² eᵢ − p pᵢ).
            let inertia = add(&scale_by(front[i], &unit), &self.rear(e, unit));
            add(&inertia, &sub(&scale(pp, &unit), &scale(p[i] * self.reduced, &p)))
        })
    }
}

/// What the base does along the motion: `Ω`, and `Ω̇` when accelerations were given.
struct BaseMotion<T, const N: usize> {
    joint: JointMotion<T, N>,
    offset: V3<T>,
    offset_rate: V3<T>,
    omega: V3<T>,
}

/// `Ω = I_lock⁻¹(λ − h)` with the joint's motion (module docs).
fn base<T: Real, const N: usize>(
    m: &MassProperties,
    joint: JointMotion<T, N>,
    lambda: Option<V3<T>>,
) -> (BaseMotion<T, N>, [V3<T>; 3]) {
    let e = joint.spine;
    let offset = m.offset(e);
    let offset_rate = scale_by(-m.rear_half, &cross(&joint.rate, &e));
    let locked = m.locked(e, offset);
    let h = add(&m.rear(e, joint.rate), &scale_by(m.reduced, &cross(&offset, &offset_rate)));
    let rhs = lambda.map_or_else(|| scale_by(-1.0, &h), |l| sub(&l, &h));
    let omega = solve3(&locked, &rhs);
    (BaseMotion { joint, offset, offset_rate, omega }, locked)
}

/// A's angular velocity (A's frame) through `(q, q̇)` at zero momentum.
///
/// # Panics
/// When `N` is not `cat.joint`'s number of coordinates ([`Joint::dof`]).
pub fn body_rate<T: Real, const N: usize>(cat: &Cat, q: [T; N], qd: [T; N]) -> V3<T> {
    let m = MassProperties::of(cat);
    base(&m, joint_motion(cat.joint, q, qd, None), None).0.omega
}

/// A's angular velocity `Ω = I_lock⁻¹(λ − h)` (A's frame) with the total momentum `λ = Rᵀ L` in
/// A's frame.
///
/// # Panics
/// When `N` is not `cat.joint`'s number of coordinates ([`Joint::dof`]).
pub fn body_rate_spinning<T: Real, const N: usize>(cat: &Cat, q: [T; N], qd: [T; N], lambda: V3<T>) -> V3<T> {
    let m = MassProperties::of(cat);
    base(&m, joint_motion(cat.joint, q, qd, None), Some(lambda)).0.omega
}

/// The motor torques, one per coordinate (`τ1, τ2`, and `τ3` about B's spine on the spherical
/// joint), N·m, through `(q, q̇, q̈)` at zero momentum.
///
/// # Panics
/// When `N` is not `cat.joint`'s number of coordinates ([`Joint::dof`]).
pub fn motor_torques<T: Real, const N: usize>(cat: &Cat, q: [T; N], qd: [T; N], qdd: [T; N]) -> [T; N] {
    torques(cat, [q, qd, qdd], None)
}

/// The motor torques, one per coordinate, N·m, with the total momentum `λ = Rᵀ L` in A's frame
/// (`λ̇ = λ × Ω`).
///
/// # Panics
/// When `N` is not `cat.joint`'s number of coordinates ([`Joint::dof`]).
pub fn motor_torques_spinning<T: Real, const N: usize>(
    cat: &Cat,
    q: [T; N],
    qd: [T; N],
    qdd: [T; N],
    lambda: V3<T>,
) -> [T; N] {
    torques(cat, [q, qd, qdd], Some(lambda))
}

/// Newton–Euler on B about the joint point (module docs).
fn torques<T: Real, const N: usize>(cat: &Cat, [q, qd, qdd]: [[T; N]; 3], lambda: Option<V3<T>>) -> [T; N] {
    let m = MassProperties::of(cat);
    let (b, locked) = base(&m, joint_motion(cat.joint, q, qd, Some(qdd)), lambda);
    let (j, p, pd, w) = (b.joint, b.offset, b.offset_rate, b.omega);
    let e = j.spine;
    let e_rate = cross(&j.rate, &e);
    let pdd = scale_by(-m.rear_half, &add(&cross(&j.accel, &e), &cross(&j.rate, &e_rate)));
    // d/dt (R I_B Rᵀ) v = ω_rel × (R I_B Rᵀ v) − R I_B Rᵀ (ω_rel × v).
    let rear_rate = |v: V3<T>| sub(&cross(&j.rate, &m.rear(e, v)), &m.rear(e, cross(&j.rate, &v)));
    let locked_rate_omega =
        sub(&rear_rate(w), &scale_by(m.reduced, &add(&cross(&pd, &cross(&p, &w)), &cross(&p, &cross(&pd, &w)))));
    let h_rate = add(&add(&rear_rate(j.rate), &m.rear(e, j.accel)), &scale_by(m.reduced, &cross(&p, &pdd)));
    let spin_term = lambda.map_or([T::cst(0.0); 3], |l| cross(&l, &w));
    let w_dot = solve3(&locked, &sub(&spin_term, &add(&locked_rate_omega, &h_rate)));
    let relative =
        add(&add(&pdd, &cross(&w_dot, &p)), &add(&scale_by(2.0, &cross(&w, &pd)), &cross(&w, &cross(&w, &p))));
    let force = scale_by(m.rear_mass * m.front_share, &relative);
    let w_b = add(&w, &j.rate);
    let alpha_b = add(&add(&w_dot, &j.accel), &cross(&w, &j.rate));
    let spin_rate = add(&m.rear(e, alpha_b), &cross(&w_b, &m.rear(e, w_b)));
    let couple = sub(&spin_rate, &cross(&scale_by(m.rear_half, &e), &force));
    j.axes.map(|axis| dot(&couple, &axis))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engines::{models, reduction};
    use crate::model::shape::ShapeState;
    use crate::model::Cylinder;
    use crate::optimize::whole::dual::Dual;
    use crate::optimize::whole::dynamics;
    use nalgebra::Vector3;

    /// A state `(q, q̇, q̈)` of a joint of `N` coordinates.
    type Point<const N: usize> = ([f64; N], [f64; N], [f64; N]);

    const FRONT: Cylinder = Cylinder { mass: 0.8, length: 0.8, radius: 0.1 };
    const REAR: Cylinder = Cylinder { mass: 1.2, length: 1.1, radius: 0.13 };
    /// States at the straight cat, small bends (the series), and large ones (the closed forms).
    const POINTS: [Point<2>; 5] = [
        ([0.0, 0.0], [1.1, -0.4], [-2.0, 3.0]),
        ([1e-3, -2e-3], [0.7, 0.9], [1.5, -0.5]),
        ([0.3, -0.7], [1.1, 0.4], [-2.0, 3.0]),
        ([2.2, 0.9], [-0.6, 1.7], [0.5, -1.5]),
        ([-1.0, 1.3], [0.2, -2.4], [4.0, 0.7]),
    ];
    /// [`POINTS`] on the spherical joint, each with a nonzero twist `q3`, `q̇3` and `q̈3`.
    const TWISTED_POINTS: [Point<3>; 5] = [
        ([0.0, 0.0, 0.4], [1.1, -0.4, 0.8], [-2.0, 3.0, 1.2]),
        ([1e-3, -2e-3, -0.9], [0.7, 0.9, -1.3], [1.5, -0.5, 2.5]),
        ([0.3, -0.7, 1.7], [1.1, 0.4, 0.6], [-2.0, 3.0, -0.8]),
        ([2.2, 0.9, -2.6], [-0.6, 1.7, 2.1], [0.5, -1.5, -3.0]),
        ([-1.0, 1.3, 3.0], [0.2, -2.4, -0.5], [4.0, 0.7, 1.1]),
    ];
    const LAMBDA: [f64; 3] = [0.03, -0.02, 0.05];

    /// The unequal halves on `joint`.
    fn cat(joint: Joint) -> Cat {
        Cat { front: FRONT, rear: REAR, joint }
    }

    /// The unequal halves on the two-coordinate joints.
    fn cats() -> [Cat; 2] {
        [Joint::Universal, Joint::NoTwist].map(cat)
    }

    /// The general core's shape state at `point`.
    fn shape<const N: usize>((q, qd, qdd): Point<N>) -> ShapeState {
        ShapeState { q: q.to_vec(), qd: qd.to_vec(), qdd: qdd.to_vec() }
    }

    /// A two-coordinate point on the spherical joint with no twist.
    fn untwisted((q, qd, qdd): Point<2>) -> Point<3> {
        let z = |a: [f64; 2]| [a[0], a[1], 0.0];
        (z(q), z(qd), z(qdd))
    }

    /// The largest magnitude in `a`.
    fn largest(a: &[f64]) -> f64 {
        a.iter().fold(0.0, |m, x| m.max(x.abs()))
    }

    /// `|a − b| ≤ 1e-12 max(|b|, scale)` componentwise, `scale` the size of the quantity.
    fn close(a: &[f64], b: &[f64], scale: f64, what: &str) {
        assert_eq!(a.len(), b.len(), "{what}: {a:?} against {b:?}");
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() <= 1e-12 * y.abs().max(scale), "{what}: {a:?} against {b:?}");
        }
    }

    /// The general core's answer (which refuses a state of another size than the joint's).
    fn core<T>(answer: Result<T, models::ModelError>) -> T {
        answer.unwrap_or_else(|e| panic!("{e}"))
    }

    /// Ω, Ω with λ, τ and τ with λ of `cat` at `points` against the general core.
    fn check_against_core<const N: usize>(cat: &Cat, points: &[Point<N>]) {
        let lambda = Vector3::from(LAMBDA);
        for &(q, qd, qdd) in points {
            let st = shape((q, qd, qdd));
            let at = |what: &str| format!("{}: {what} at {q:?}", cat.joint);
            let w = core(models::body_rate(cat, &st));
            close(&body_rate(cat, q, qd), w.as_slice(), w.norm(), &at("Ω"));
            let w = reduction::body_rate(&cat.tree(), &st, &lambda);
            close(&body_rate_spinning(cat, q, qd, LAMBDA), w.as_slice(), w.norm(), &at("Ω with λ"));
            let t = core(models::joint_torques(cat, &st)).tau;
            close(&motor_torques(cat, q, qd, qdd), &t, largest(&t), &at("τ"));
            let t = core(models::joint_torques_spinning(cat, &st, &lambda)).tau;
            close(&motor_torques_spinning(cat, q, qd, qdd, LAMBDA), &t, largest(&t), &at("τ with λ"));
        }
    }

    #[test]
    fn agrees_with_the_general_core_on_unequal_halves_and_every_joint() {
        for cat in cats() {
            check_against_core(&cat, &POINTS);
        }
        check_against_core(&cat(Joint::Spherical), &TWISTED_POINTS);
    }

    #[test]
    fn agrees_with_the_paper_dynamics_on_the_paper_cat() {
        let cat = Cat::from(FRONT);
        for (q, qd, qdd) in POINTS {
            let w = dynamics::body_rate(&FRONT, q, qd);
            let scale = Vector3::from(w).norm();
            close(&body_rate(&cat, q, qd), &w, scale, "Ω");
            let t = dynamics::motor_torques_spinning(&FRONT, q, qd, qdd, LAMBDA);
            close(&motor_torques_spinning(&cat, q, qd, qdd, LAMBDA), &t, t[0].abs().max(t[1].abs()), "τ");
        }
    }

    /// `joint`'s spine, motion and axes at `points` against [`Joint`]'s own (`f64`, nalgebra).
    fn check_joint<const N: usize>(joint: Joint, points: &[Point<N>]) {
        for &(q, qd, qdd) in points {
            let at = |what: &str| format!("{joint}: {what} at {q:?}");
            let e = joint.rotation(&q) * Vector3::z();
            close(&spine(joint, q), e.as_slice(), 1.0, &at("e"));
            let motion = joint_motion(joint, q, qd, Some(qdd));
            close(&motion.spine, e.as_slice(), 1.0, &at("the motion's e"));
            let rate = joint.relative_rate(&q, &qd);
            close(&motion.rate, rate.as_slice(), rate.norm(), &at("ω_rel"));
            let accel = joint.relative_accel(&q, &qd, &qdd);
            close(&motion.accel, accel.as_slice(), accel.norm(), &at("ω̇_rel"));
            let axes = joint.motor_axes(&q);
            assert_eq!(axes.len(), N, "{}", at("the number of motor axes"));
            for (axis, expected) in motion.axes.iter().zip(&axes) {
                close(axis, expected.as_slice(), 1.0, &at("a motor axis"));
            }
            close(&joint_motion(joint, q, qd, None).accel, &[0.0; 3], 0.0, &at("ω̇_rel without q̈"));
        }
    }

    #[test]
    fn the_joint_motion_is_the_joints() {
        for cat in cats() {
            check_joint(cat.joint, &POINTS);
        }
        check_joint(Joint::Spherical, &TWISTED_POINTS);
    }

    #[test]
    fn the_spherical_joint_without_twist_is_the_no_twist_joint() {
        // The same motion of B: Ω and the first two torques agree, and the third is the couple
        // the no-twist joint's constraint transmits about B's spine.
        let (spherical, no_twist) = (cat(Joint::Spherical), cat(Joint::NoTwist));
        for point in POINTS {
            let (q, qd, qdd) = point;
            let (q3, qd3, qdd3) = untwisted(point);
            let at = |what: &str| format!("{what} at {q:?}");
            let w = body_rate(&no_twist, q, qd);
            close(&body_rate(&spherical, q3, qd3), &w, Vector3::from(w).norm(), &at("Ω"));
            let w = body_rate_spinning(&no_twist, q, qd, LAMBDA);
            close(&body_rate_spinning(&spherical, q3, qd3, LAMBDA), &w, Vector3::from(w).norm(), &at("Ω with λ"));
            let (e, st) = (Vector3::from(spine(Joint::NoTwist, q)), shape(point));
            let tau = motor_torques(&spherical, q3, qd3, qdd3);
            let t = motor_torques(&no_twist, q, qd, qdd);
            close(&tau[..2], &t, largest(&t), &at("τ1, τ2"));
            let couple = core(models::joint_torques(&no_twist, &st)).couple;
            close(&tau[2..], &[couple.dot(&e)], couple.norm(), &at("τ3 against the no-twist joint's couple·e"));
            let tau = motor_torques_spinning(&spherical, q3, qd3, qdd3, LAMBDA);
            let t = motor_torques_spinning(&no_twist, q, qd, qdd, LAMBDA);
            close(&tau[..2], &t, largest(&t), &at("τ1, τ2 with λ"));
            let couple = core(models::joint_torques_spinning(&no_twist, &st, &Vector3::from(LAMBDA))).couple;
            close(&tau[2..], &[couple.dot(&e)], couple.norm(), &at("τ3 against the no-twist joint's couple·e with λ"));
        }
    }

    #[test]
    #[should_panic(expected = "the spherical joint has 3 coordinates, not 2")]
    fn two_coordinates_on_the_spherical_joint_are_refused() {
        body_rate(&cat(Joint::Spherical), [0.1, 0.2], [0.3, 0.4]);
    }

    #[test]
    #[should_panic(expected = "the no-twist joint has 2 coordinates, not 3")]
    fn three_coordinates_on_the_no_twist_joint_are_refused() {
        motor_torques(&cat(Joint::NoTwist), [0.1, 0.2, 0.3], [0.0; 3], [0.0; 3]);
    }

    #[test]
    fn series_and_closed_forms_meet_at_the_switch() {
        let all = |k: ExpSeries<f64>| [k.sinc, k.a, k.b, k.a_s, k.b_s];
        let below = all(ExpSeries::at(SERIES_BELOW * (1.0 - 1e-15)));
        let above = all(ExpSeries::at(SERIES_BELOW));
        close(&below, &above, 0.0, "the coefficients either side of the switch");
    }

    /// The outputs `(τ, Ω)` of the inputs `x = (q, q̇, q̈)`, `M = 3N` of them, at any `Real`.
    fn outputs<T: Real, const N: usize, const M: usize>(cat: &Cat, x: [T; M]) -> Vec<T> {
        let part = |k: usize| -> [T; N] { std::array::from_fn(|i| x[k * N + i]) };
        let tau = motor_torques_spinning(cat, part(0), part(1), part(2), LAMBDA.map(T::cst));
        tau.into_iter().chain(body_rate(cat, part(0), part(1))).collect()
    }

    /// The dual derivatives of [`outputs`] at `points` against central differences. As
    /// dynamics.rs's test: step 1e-6, truncation ~1e-12, round-off ~1e-10: 1e-7 absolute.
    fn check_derivatives<const N: usize, const M: usize>(cat: &Cat, points: &[Point<N>]) {
        assert_eq!(M, 3 * N, "one direction per input");
        let step = 1e-6;
        for &(q, qd, qdd) in points {
            let x: [f64; M] = std::array::from_fn(|k| [q, qd, qdd][k / N][k % N]);
            let dual = outputs::<_, N, M>(cat, std::array::from_fn(|k| Dual::<M>::input(x[k], k)));
            for k in 0..M {
                let shifted = |sign: f64| {
                    let mut y = x;
                    y[k] += sign * step;
                    outputs::<f64, N, M>(cat, y)
                };
                let (plus, minus) = (shifted(1.0), shifted(-1.0));
                for (o, d) in dual.iter().enumerate() {
                    let fd = (plus[o] - minus[o]) / (2.0 * step);
                    assert!(
                        (d.eps[k] - fd).abs() <= 1e-7,
                        "{}: output {o}, input {k} at {q:?}: {} against {fd}",
                        cat.joint,
                        d.eps[k]
                    );
                }
            }
        }
    }

    #[test]
    fn dual_derivatives_match_central_differences() {
        for cat in cats() {
            check_derivatives::<2, 6>(&cat, &POINTS);
        }
        check_derivatives::<3, 9>(&cat(Joint::Spherical), &TWISTED_POINTS);
    }
}
