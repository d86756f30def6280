//! The zero-momentum dynamics of any tree of rigid bodies ([`Tree`]: a cat with a tail, legs) written
//! once over a [`Real`], so that the optimiser plans every joint of it with exact derivatives, as
//! [`super::model_dynamics`] does for the two-body cats.
//!
//! The equations are the general core's ([`crate::model::tree`] for the bodies' motion relative to
//! the base, [`crate::engines::reduction`] for the base's), here over dual numbers:
//!
//! - link by link, with `J, ω_rel, ω̇_rel` the joint's ([`rotation_of`],
//!   [`super::model_dynamics::joint_motion`]): `R_k = R_p J`, `w_k = w_p + R_p ω_rel`,
//!   `ẇ_k = ẇ_p + w_p × R_p ω_rel + R_p ω̇_rel`, `c_k = c_p + R_p a − R_k b` and its two
//!   derivatives; positions then from the centre of mass, `r_k = c_k − c̄`;
//! - `I_lock = Σ_k (R_k I_k R_kᵀ + m_k(|r_k|² 𝟙 − r_k r_kᵀ))`, `h = Σ_k (R_k I_k R_kᵀ w_k + m_k r_k × ṙ_k)`,
//!   `Ω = I_lock⁻¹(λ − h)` and `Ω̇ = I_lock⁻¹(λ × Ω − İ_lock Ω − ḣ)`;
//! - each joint's couple on the subtree it carries about its point `p`,
//!   `Σ_k (I'_k α_k + ω_k × I'_k ω_k + (r_k − p) × m_k a_k)` with `ω_k = Ω + w_k`,
//!   `α_k = Ω̇ + ẇ_k + Ω × w_k` and `a_k = r̈_k + Ω̇ × r_k + 2Ω × ṙ_k + Ω × (Ω × r_k)`, projected
//!   on the joint's motor axes; the motors of every joint in link order.
//!
//! Tests check at `f64` against the general core (to 1e-12) and at dual numbers against central
//! differences. All vectors in the base's frame (A's), SI units.
//!
//! ## References
//! - R. Featherstone, *Rigid Body Dynamics Algorithms* (2008), ch. 4 (kinematic trees);
//! - A. Griewank, A. Walther, *Evaluating Derivatives* (2nd ed., SIAM 2008), ch. 3 (forward mode).

use nalgebra::{Matrix3, Vector3};

use super::dual::{add, cross, dot, scale_by, solve3, sub, Real, V3};
use super::model_dynamics::{joint_motion, ExpSeries};
use crate::model::tree::Tree;
use crate::model::Joint;

/// A 3×3 matrix over a [`Real`], as its rows.
type M3<T> = [V3<T>; 3];

/// The matrix of `entry(i, j)`, written out: `array::from_fn` moves every dual number through a
/// copy (memory moves were 15 % of the tailed cat's interior-point optimisation, perf,
/// 2026-12-07, most of them from the products and their transposed copies).
fn written<T: Real>(entry: impl Fn(usize, usize) -> T) -> M3<T> {
    [
        [entry(0, 0), entry(0, 1), entry(0, 2)],
        [entry(1, 0), entry(1, 1), entry(1, 2)],
        [entry(2, 0), entry(2, 1), entry(2, 2)],
    ]
}

/// `A B`, `B`'s columns read in place.
fn product<T: Real>(a: &M3<T>, b: &M3<T>) -> M3<T> {
    written(|i, j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j])
}

/// `A Bᵀ`.
fn product_transposed<T: Real>(a: &M3<T>, b: &M3<T>) -> M3<T> {
    written(|i, j| dot(&a[i], &b[j]))
}

/// `A C` for a constant `C`: the numbers of `A` times `C` as constant duals, without the products
/// of their zero derivatives.
fn product_constant<T: Real>(a: &M3<T>, c: &Matrix3<f64>) -> M3<T> {
    written(|i, j| a[i][0] * c[(0, j)] + a[i][1] * c[(1, j)] + a[i][2] * c[(2, j)])
}

/// `M v`.
fn apply<T: Real>(m: &M3<T>, v: &V3<T>) -> V3<T> {
    [dot(&m[0], v), dot(&m[1], v), dot(&m[2], v)]
}

/// `M v` for a constant `v`, as [`product_constant`].
fn apply_constant<T: Real>(m: &M3<T>, v: &Vector3<f64>) -> V3<T> {
    let entry = |i: usize| m[i][0] * v.x + m[i][1] * v.y + m[i][2] * v.z;
    [entry(0), entry(1), entry(2)]
}

/// A constant matrix.
fn constant<T: Real>(m: &Matrix3<f64>) -> M3<T> {
    std::array::from_fn(|i| std::array::from_fn(|j| T::cst(m[(i, j)])))
}

/// The joint's rotation `J(q)` of the child's frame in the parent's ([`Joint::rotation`]):
/// `Rx(q1) Ry(q2)`, `exp([v]×) = 𝟙 + σ [v]× + a [v]×²` with `v = (q1, q2, 0)`, and that times
/// `Rz(q3)` on the spherical joint.
pub fn rotation_of<T: Real>(joint: Joint, q: &[T]) -> M3<T> {
    let (zero, one) = (T::cst(0.0), T::cst(1.0));
    match joint {
        Joint::Universal => {
            let (s1, c1) = q[0].sin_cos();
            let (s2, c2) = q[1].sin_cos();
            [[c2, zero, s2], [s1 * s2, c1, -(s1 * c2)], [-(c1 * s2), s1, c1 * c2]]
        }
        Joint::NoTwist | Joint::Spherical => {
            let (x, y) = (q[0], q[1]);
            let k = ExpSeries::at(x * x + y * y);
            // [v]× = [[0, 0, y], [0, 0, −x], [−y, x, 0]]; [v]×² = v vᵀ − |v|² 𝟙.
            let s = x * x + y * y;
            let bend = [
                [one + k.a * (x * x - s), k.a * x * y, k.sinc * y],
                [k.a * x * y, one + k.a * (y * y - s), -(k.sinc * x)],
                [-(k.sinc * y), k.sinc * x, one - k.a * s],
            ];
            if joint == Joint::NoTwist {
                return bend;
            }
            let (s3, c3) = q[2].sin_cos();
            product(&bend, &[[c3, -s3, zero], [s3, c3, zero], [zero, zero, one]])
        }
        Joint::Hinge => {
            let (s1, c1) = q[0].sin_cos();
            [[one, zero, zero], [zero, c1, -s1], [zero, s1, c1]]
        }
    }
}

/// A joint's relative rate and, given `qdd`, acceleration (parent frame; zero without) and motor
/// axes over a slice of its coordinates.
fn joint_kinematics<T: Real>(joint: Joint, q: &[T], qd: &[T], qdd: Option<&[T]>) -> (V3<T>, V3<T>, Vec<V3<T>>) {
    fn on<T: Real, const N: usize>(joint: Joint, q: &[T], qd: &[T], qdd: Option<&[T]>) -> (V3<T>, V3<T>, Vec<V3<T>>) {
        let take = |x: &[T]| -> [T; N] { std::array::from_fn(|j| x[j]) };
        let m = joint_motion(joint, take(q), take(qd), qdd.map(take));
        (m.rate, m.accel, m.axes.to_vec())
    }
    match joint.dof() {
        1 => on::<T, 1>(joint, q, qd, qdd),
        2 => on::<T, 2>(joint, q, qd, qdd),
        _ => on::<T, 3>(joint, q, qd, qdd),
    }
}

/// One body's motion relative to the base (module docs), its inertia turned into the base's frame.
#[derive(Clone, Copy)]
struct Moving<T> {
    rotation: M3<T>,
    inertia: M3<T>,
    position: V3<T>,
    velocity: V3<T>,
    acceleration: V3<T>,
    rate: V3<T>,
    rate_dot: V3<T>,
}

/// A joint's point and motor axes (base frame, the point from the centre of mass).
type JointPoint<T> = (V3<T>, Vec<V3<T>>);

/// The bodies' motion and each joint's point and motor axes; without `qdd` (A's rate needs none)
/// the accelerations are left at zero, every other quantity the same to the last bit.
fn motion<T: Real>(tree: &Tree, q: &[T], qd: &[T], qdd: Option<&[T]>) -> (Vec<Moving<T>>, Vec<JointPoint<T>>) {
    let zero = [T::cst(0.0); 3];
    let identity = constant(&Matrix3::identity());
    let mut bodies = Vec::with_capacity(tree.bodies().len());
    bodies.push(Moving {
        rotation: identity,
        inertia: constant(&tree.bodies()[0].inertia),
        position: zero,
        velocity: zero,
        acceleration: zero,
        rate: zero,
        rate_dot: zero,
    });
    let mut links = Vec::with_capacity(tree.links().len());
    for (i, l) in tree.links().iter().enumerate() {
        let p = &bodies[l.parent];
        let range = tree.coordinates(i);
        let (jq, jqd) = (&q[range.clone()], &qd[range.clone()]);
        let jqdd = qdd.map(|x| &x[range]);
        let rotation = product(&p.rotation, &rotation_of(l.joint, jq));
        let (rel, rel_dot, axes) = joint_kinematics(l.joint, jq, jqd, jqdd);
        let w_rel = apply(&p.rotation, &rel);
        let rate = add(&p.rate, &w_rel);
        let (a, b) = (apply_constant(&p.rotation, &l.at_parent), apply_constant(&rotation, &l.at_child));
        let point = add(&p.position, &a);
        let inertia = product_transposed(&product_constant(&rotation, &tree.bodies()[i + 1].inertia), &rotation);
        let velocity = sub(&add(&p.velocity, &cross(&p.rate, &a)), &cross(&rate, &b));
        let (rate_dot, acceleration) = if qdd.is_some() {
            let rate_dot = add(&add(&p.rate_dot, &cross(&p.rate, &w_rel)), &apply(&p.rotation, &rel_dot));
            let acceleration = sub(
                &sub(
                    &add(&add(&p.acceleration, &cross(&p.rate_dot, &a)), &cross(&p.rate, &cross(&p.rate, &a))),
                    &cross(&rate_dot, &b),
                ),
                &cross(&rate, &cross(&rate, &b)),
            );
            (rate_dot, acceleration)
        } else {
            (zero, zero)
        };
        links.push((point, axes.iter().map(|x| apply(&p.rotation, x)).collect()));
        bodies.push(Moving { rotation, inertia, position: sub(&point, &b), velocity, acceleration, rate, rate_dot });
    }
    let total = tree.mass();
    let mean = |f: fn(&Moving<T>) -> &V3<T>| {
        bodies.iter().zip(tree.bodies()).fold(zero, |s, (m, b)| add(&s, &scale_by(b.mass / total, f(m))))
    };
    let (c, cd) = (mean(|m| &m.position), mean(|m| &m.velocity));
    let cdd = if qdd.is_some() { mean(|m| &m.acceleration) } else { zero };
    for m in &mut bodies {
        m.position = sub(&m.position, &c);
        m.velocity = sub(&m.velocity, &cd);
        m.acceleration = sub(&m.acceleration, &cdd);
    }
    for l in &mut links {
        l.0 = sub(&l.0, &c);
    }
    (bodies, links)
}

/// `I_lock` and `h` of the bodies' motion.
fn locked<T: Real>(tree: &Tree, bodies: &[Moving<T>]) -> (M3<T>, V3<T>) {
    let mut m = [[T::cst(0.0); 3]; 3];
    let mut h = [T::cst(0.0); 3];
    for (k, b) in bodies.iter().zip(tree.bodies()) {
        let r = &k.position;
        let rr = dot(r, r);
        for (i, row) in m.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                let diagonal = if i == j { rr } else { T::cst(0.0) };
                *x = *x + k.inertia[i][j] + (diagonal - r[i] * r[j]) * b.mass;
            }
        }
        h = add(&add(&h, &apply(&k.inertia, &k.rate)), &scale_by(b.mass, &cross(r, &k.velocity)));
    }
    (m, h)
}

/// A's angular velocity `Ω = I_lock⁻¹(λ − h)` (A's frame) through `(q, q̇)` with the total
/// momentum `λ` in A's frame; `q` holds [`Tree::dof`] coordinates.
pub fn body_rate<T: Real>(tree: &Tree, q: &[T], qd: &[T], lambda: V3<T>) -> V3<T> {
    let (bodies, _) = motion(tree, q, qd, None);
    let (m, h) = locked(tree, &bodies);
    solve3(&m, &sub(&lambda, &h))
}

/// Every joint's motor torques, in link order, N·m, through `(q, q̇, q̈)` with the total momentum
/// `λ` in A's frame (module docs).
pub fn motor_torques<T: Real>(tree: &Tree, q: &[T], qd: &[T], qdd: &[T], lambda: V3<T>) -> Vec<T> {
    let (bodies, links) = motion(tree, q, qd, Some(qdd));
    let (m, h) = locked(tree, &bodies);
    let w = solve3(&m, &sub(&lambda, &h));
    // İ_lock Ω and ḣ, body by body: d/dt (R I Rᵀ) v = w × (R I Rᵀ v) − R I Rᵀ (w × v).
    let mut rhs = cross(&lambda, &w);
    for (k, b) in bodies.iter().zip(tree.bodies()) {
        let (r, v) = (&k.position, &k.velocity);
        let turning = |x: &V3<T>| sub(&cross(&k.rate, &apply(&k.inertia, x)), &apply(&k.inertia, &cross(&k.rate, x)));
        let m_dot_w = sub(&turning(&w), &scale_by(b.mass, &add(&cross(v, &cross(r, &w)), &cross(r, &cross(v, &w)))));
        let h_dot = add(
            &add(&turning(&k.rate), &apply(&k.inertia, &k.rate_dot)),
            &scale_by(b.mass, &cross(r, &k.acceleration)),
        );
        rhs = sub(&rhs, &add(&m_dot_w, &h_dot));
    }
    let w_dot = solve3(&m, &rhs);
    let loads: Vec<(V3<T>, V3<T>)> = bodies
        .iter()
        .zip(tree.bodies())
        .map(|(k, b)| {
            let omega = add(&w, &k.rate);
            let alpha = add(&add(&w_dot, &k.rate_dot), &cross(&w, &k.rate));
            let a = add(
                &add(&add(&k.acceleration, &cross(&w_dot, &k.position)), &scale_by(2.0, &cross(&w, &k.velocity))),
                &cross(&w, &cross(&w, &k.position)),
            );
            let spin = add(&apply(&k.inertia, &alpha), &cross(&omega, &apply(&k.inertia, &omega)));
            (spin, scale_by(b.mass, &a))
        })
        .collect();
    let mut out = Vec::with_capacity(q.len());
    for (i, (point, axes)) in links.iter().enumerate() {
        let inside = tree.subtree(i);
        let couple = loads
            .iter()
            .zip(&bodies)
            .zip(&inside)
            .filter(|(_, s)| **s)
            .fold([T::cst(0.0); 3], |c, (((spin, f), k), _)| add(&add(&c, spin), &cross(&sub(&k.position, point), f)));
        out.extend(axes.iter().map(|x| dot(&couple, x)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engines::reduction;
    use crate::model::cat::Appendages;
    use crate::model::shape::ShapeState;
    use crate::model::{Cat, Cylinder};
    use crate::optimize::whole::dual::Dual;

    const FRONT: Cylinder = Cylinder { mass: 0.8, length: 0.8, radius: 0.1 };
    const REAR: Cylinder = Cylinder { mass: 1.2, length: 1.1, radius: 0.13 };
    const TAIL: Cylinder = Cylinder { mass: 0.15, length: 0.9, radius: 0.02 };
    const LAMBDA: [f64; 3] = [0.03, -0.02, 0.05];

    /// Unequal halves on `joint` with a tail on `tail`'s joint hung from the rear half's end.
    fn tailed(joint: Joint, tail: Joint) -> Tree {
        Cat { front: FRONT, rear: REAR, joint }.tree_with_tail(&TAIL, tail)
    }

    const LEG: Cylinder = Cylinder { mass: 0.1, length: 0.4, radius: 0.03 };

    /// Unequal halves on `joint` with legs, and with a tail on `tail`'s joint when given.
    fn legged(joint: Joint, tail: Option<Joint>) -> Tree {
        let appendages = Appendages { tail: tail.map(|j| (TAIL, j)), legs: Some([LEG; 2]) };
        Cat { front: FRONT, rear: REAR, joint }.tree_with(&appendages)
    }

    /// Every joint for the cat and every joint for the tail (the hinge too), and legs with and
    /// without a tail.
    fn trees() -> Vec<Tree> {
        let tails = Joint::ALL.into_iter().chain([Joint::Hinge]);
        let mut out: Vec<Tree> =
            Joint::ALL.iter().flat_map(|&joint| tails.clone().map(move |tail| tailed(joint, tail))).collect();
        out.extend([legged(Joint::NoTwist, None), legged(Joint::Universal, Some(Joint::Hinge))]);
        out
    }

    /// A shape of `n` coordinates: bends up to ~1.5 rad, rates and accelerations of a few per s.
    fn shape(n: usize, k: f64) -> ShapeState {
        let f = |a: f64, b: f64| (0..n).map(|j| a * ((j as f64 + 1.0) * b + k).sin()).collect();
        ShapeState { q: f(1.2, 0.7), qd: f(2.1, 1.3), qdd: f(3.4, 0.4) }
    }

    #[test]
    fn agrees_with_the_general_core() {
        for tree in trees() {
            for k in [0.0, 0.9, 2.3] {
                let s = shape(tree.dof(), k);
                for lambda in [[0.0; 3], LAMBDA] {
                    let l = Vector3::from(lambda);
                    let w = reduction::body_rate(&tree, &s, &l);
                    let ours = body_rate(&tree, &s.q, &s.qd, lambda);
                    for (a, b) in ours.iter().zip(w.iter()) {
                        assert!((a - b).abs() <= 1e-12 * w.norm().max(1.0), "Ω {ours:?} against {w}");
                    }
                    let want: Vec<f64> =
                        reduction::joint_torques(&tree, &s, &l).into_iter().flat_map(|t| t.tau).collect();
                    let ours = motor_torques(&tree, &s.q, &s.qd, &s.qdd, lambda);
                    let size = want.iter().fold(1.0f64, |m, x| m.max(x.abs()));
                    assert_eq!(ours.len(), want.len());
                    for (a, b) in ours.iter().zip(&want) {
                        assert!((a - b).abs() <= 1e-12 * size, "τ {ours:?} against {want:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_rotation_is_the_joints() {
        // Below a bend of 1 rad the no-twist coefficients are series, above closed forms: both.
        // Entries of order one, the same formula up to rounding: 1e-15.
        for joint in Joint::ALL.into_iter().chain([Joint::Hinge]) {
            for q in [[0.4, -1.1, 0.8], [1e-3, 2e-3, -0.3]] {
                let ours = rotation_of(joint, &q[..joint.dof()]);
                let want = joint.rotation(&q[..joint.dof()]);
                for (i, row) in ours.iter().enumerate() {
                    for (j, x) in row.iter().enumerate() {
                        assert!((x - want[(i, j)]).abs() < 1e-15, "{joint}: {ours:?} against {want}");
                    }
                }
            }
        }
    }

    #[test]
    fn dual_derivatives_match_central_differences() {
        // Step 1e-6, truncation ~1e-12, round-off ~1e-10: 1e-7 absolute, as model_dynamics.rs.
        // Bent past 1 rad (the closed forms) and nearly straight (the series), on three trees
        // (one with legs: 4 coordinates, 12 of the 15 directions).
        for (tree, bend) in [
            (tailed(Joint::NoTwist, Joint::Universal), 1.2),
            (tailed(Joint::Spherical, Joint::NoTwist), 1e-3),
            (legged(Joint::NoTwist, None), 1.2),
        ] {
            let n = tree.dof();
            let mut s = shape(n, 0.5);
            s.q.iter_mut().for_each(|q| *q *= bend);
            let x: Vec<f64> = s.q.iter().chain(&s.qd).chain(&s.qdd).copied().collect();
            let outputs = |x: &[Dual<15>]| {
                let (q, rest) = x.split_at(n);
                let (qd, qdd) = rest.split_at(n);
                let lambda = LAMBDA.map(Dual::cst);
                let mut out = motor_torques(&tree, q, qd, qdd, lambda);
                out.extend(body_rate(&tree, q, qd, lambda));
                out
            };
            let seeded: Vec<Dual<15>> = x.iter().enumerate().map(|(k, &v)| Dual::input(v, k)).collect();
            let dual = outputs(&seeded);
            let step = 1e-6;
            for k in 0..3 * n {
                let shifted = |sign: f64| {
                    let y: Vec<Dual<15>> = x
                        .iter()
                        .enumerate()
                        .map(|(j, &v)| Dual::cst(if j == k { v + sign * step } else { v }))
                        .collect();
                    outputs(&y)
                };
                let (plus, minus) = (shifted(1.0), shifted(-1.0));
                for (o, d) in dual.iter().enumerate() {
                    let fd = (plus[o].re - minus[o].re) / (2.0 * step);
                    assert!((d.eps[k] - fd).abs() <= 1e-7, "output {o}, input {k}: {} against {fd}", d.eps[k]);
                }
            }
        }
    }
}
