//! Exact first derivatives of the final orientation and of the torques for a release with spin
//! (DESIGN.md §9), in a lifted (sparse) form.
//!
//! ## Dynamics and integrator
//! Released with total angular momentum `L` (world frame), A's body rate is
//! `Ω = I_lock(q)⁻¹(Rᵀ L − h(q, q̇))` ([`crate::engines::spin`]): it depends on `R`, so the
//! zero-momentum Magnus product and its sensitivity ([`super::sensitivity`]) no longer apply.
//! The loop integrates `ṙ = ½ r ⊗ (0, Ω(t, r))` on the unit quaternion with the exact engine's
//! classical Runge–Kutta step ([`crate::engines::exact::rk4_on`]: `Ω` at the normalised stage
//! quaternion, the result normalised), `steps` steps on the widest knot span and proportionally
//! fewer on narrower ones, never across a knot. The step is written once over [`Real`], so at
//! [`Dual`] it returns the exact derivative of this discrete map, not of a second discretisation.
//!
//! ## Sensitivity, span by span
//! Within span `s` only `p + 1 = 4` control points per joint act, and the orientation at the span's
//! start `r_s` carries every earlier one. With the left (world-frame) perturbation
//! `r̃ = exp(η/2) ⊗ r`, i.e. `δr = ½ (0, η) ⊗ r` and `η = 2 vec(δr ⊗ r̄)`, one pass over the span at
//! `Dual<11>` (3 directions for `η_s`, 8 for the span's control points) gives the transition
//!
//! $$ η_{s+1} = Φ_s\, η_s + B_s\, δc_s, \qquad η_0 = 0, $$
//!
//! and the final error's Jacobian `∂e/∂c = J_l⁻¹(e) R_*ᵀ Ψ_S` with `Ψ_{s+1} = Φ_s Ψ_s + B_s`
//! (dense, 3 × variables), as in [`super::sensitivity`].
//!
//! ## Torques
//! A torque sample at `t_k` in span `s` needs `λ_k = R(t_k)ᵀ L`: one Runge–Kutta step from the
//! node before `t_k` (as [`crate::engines::spin::SpinHistory`] does), at `Dual<11>` too; then
//! `τ(q, q̇, q̈, λ)` ([`WholeCat::motor_torques_spinning`]) at `Dual<11>` gives
//! `∂τ_k/∂η_s` and `∂τ_k/∂c_s`. Eliminating the `η` would make every torque row dense in all
//! earlier control points (a lower-triangular block: 940 rows × 232 columns on the default
//! spline, whose KKT factorisation is dense). Kept as variables ([`Lift`]), `η_1 … η_{S−1}` are
//! `3(S − 1)` extra unknowns of the convex subproblem with the transitions as sparse equality
//! rows: the same linearisation exactly (elimination recovers the dense rows), and every torque
//! row has at most 8 + 3 entries. Gradient entries `v ≥ variables` of a [`TorqueSample`] refer to
//! these lifted unknowns ([`Lift::variable`]).
//!
//! ## References
//! - J. Solà, J. Deray, D. Atchuthan, *A micro Lie theory for state estimation in robotics*
//!   (arXiv:1812.01537, 2018), for the left perturbation and `J_l⁻¹`;
//! - J. T. Betts, *Practical Methods for Optimal Control* (2nd ed., SIAM 2010), §4.4, multiple
//!   shooting: the lifted state keeps the Jacobian sparse.

use nalgebra::{DMatrix, Matrix3, Quaternion, UnitQuaternion, Vector3};

use super::cat::WholeCat;
use super::dual::{add, cross, dot, scale, scale_by, sub, Dual, Real, V3};
use super::sensitivity::{left_jacobian_inverse, FinalOrientation, GridPoint, Layout, TorqueSample};
use super::spline::{BSpline, Basis};

/// Directions of the span's dual numbers: `η_s` (3) and the span's 4 control points per joint.
const DIRS: usize = 11;

/// The number of a span's control-point direction.
fn local(j: usize, m: usize) -> usize {
    3 + 4 * j + m
}

type D = Dual<DIRS>;
/// A quaternion `(w, x, y, z)` over a [`Real`].
type Q<T> = [T; 4];

fn qmul<T: Real>(a: Q<T>, b: Q<T>) -> Q<T> {
    let (av, bv) = ([a[1], a[2], a[3]], [b[1], b[2], b[3]]);
    let v = add(&add(&scale(a[0], &bv), &scale(b[0], &av)), &cross(&av, &bv));
    [a[0] * b[0] - dot(&av, &bv), v[0], v[1], v[2]]
}

fn qadd<T: Real>(a: Q<T>, b: Q<T>, k: f64) -> Q<T> {
    [a[0] + b[0] * k, a[1] + b[1] * k, a[2] + b[2] * k, a[3] + b[3] * k]
}

fn normalised<T: Real>(y: Q<T>) -> Q<T> {
    let n = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]).sqrt();
    [y[0] / n, y[1] / n, y[2] / n, y[3] / n]
}

/// `Rᵀ l` for the unit quaternion `u`: `l − 2w (v × l) + 2 v × (v × l)`.
fn inverse_rotate<T: Real>(u: Q<T>, l: &Vector3<f64>) -> V3<T> {
    let v = [u[1], u[2], u[3]];
    let l = [T::cst(l.x), T::cst(l.y), T::cst(l.z)];
    let vl = cross(&v, &l);
    add(&sub(&l, &scale_by(2.0, &scale(u[0], &vl))), &scale_by(2.0, &cross(&v, &vl)))
}

/// The joint state at one instant of the span as duals on the span's control points.
#[derive(Clone, Copy)]
struct LocalState {
    q: [D; 2],
    qd: [D; 2],
    qdd: [D; 2],
}

fn local_state(spline: &BSpline, basis: &Basis) -> LocalState {
    let st = spline.state_from(basis);
    let seed = |j: usize, d: usize, value: f64| {
        let mut x = D::cst(value);
        for (m, n) in basis.values[d].iter().enumerate() {
            x.eps[local(j, m)] = *n;
        }
        x
    };
    LocalState {
        q: [seed(0, 0, st.q[0]), seed(1, 0, st.q[1])],
        qd: [seed(0, 1, st.qd[0]), seed(1, 1, st.qd[1])],
        qdd: [seed(0, 2, st.qdd[0]), seed(1, 2, st.qdd[1])],
    }
}

/// `ṙ = ½ r ⊗ (0, Ω)` with `Ω` at the normalised `r`.
fn rate(cat: &WholeCat, spin: &Vector3<f64>, st: &LocalState, y: Q<D>) -> Q<D> {
    let lambda = inverse_rotate(normalised(y), spin);
    let w = cat.body_rate_spinning(st.q, st.qd, lambda);
    let r = qmul(y, [D::cst(0.0), w[0], w[1], w[2]]);
    r.map(|x| x * 0.5)
}

/// One classical Runge–Kutta step `h` ([`crate::engines::exact::rk4_on`]) from `y` at `t` in
/// span `span`, normalised.
fn step(cat: &WholeCat, spline: &BSpline, spin: &Vector3<f64>, span: usize, y: Q<D>, t: f64, h: f64) -> Q<D> {
    let at = |t: f64| local_state(spline, &spline.basis(span, t));
    let (a, b, c) = (at(t), at(t + 0.5 * h), at(t + h));
    let k1 = rate(cat, spin, &a, y);
    let k2 = rate(cat, spin, &b, qadd(y, k1, 0.5 * h));
    let k3 = rate(cat, spin, &b, qadd(y, k2, 0.5 * h));
    let k4 = rate(cat, spin, &c, qadd(y, k3, h));
    let sum = qadd(qadd(qadd(k1, k2, 2.0), k3, 2.0), k4, 1.0);
    normalised(qadd(y, sum, h / 6.0))
}

/// `2 vec(δr ⊗ r̄)` of direction `d` of the dual quaternion `y` (value `r`).
fn tangent(y: &Q<D>, d: usize) -> Vector3<f64> {
    let dr: Q<f64> = y.map(|x| x.eps[d]);
    let conj = [y[0].re, -y[1].re, -y[2].re, -y[3].re];
    let p = qmul(dr, conj);
    Vector3::new(2.0 * p[1], 2.0 * p[2], 2.0 * p[3])
}

/// One span's transition `η_{s+1} = Φ_s η_s + B_s δ`: `Φ_s` and the columns of `B_s` as
/// `(variable, column)`.
pub type Transition = (Matrix3<f64>, Vec<(usize, Vector3<f64>)>);

/// The lifted attitude perturbations `η_1 … η_{S−1}` at the starts of spans `1 … S−1` and their
/// transitions (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Lift {
    /// The control-point variables; lifted unknowns are numbered from here.
    pub offset: usize,
    /// Per span `s`: `Φ_s` and the columns of `B_s` as `(variable, column)`.
    pub transitions: Vec<Transition>,
}

impl Lift {
    /// The number of lifted unknowns, `3(S − 1)`.
    pub fn unknowns(&self) -> usize {
        3 * self.transitions.len().saturating_sub(1)
    }

    /// The unknown of component `i` of `η_s` (none for `s = 0`, where `η_0 = 0`).
    pub fn variable(&self, s: usize, i: usize) -> Option<usize> {
        (s >= 1).then(|| self.offset + 3 * (s - 1) + i)
    }

    /// `step` followed by the `η` it implies, by the transitions.
    pub fn extend(&self, step: &[f64]) -> Vec<f64> {
        let mut out = step.to_vec();
        let mut eta = Vector3::zeros();
        for (phi, b) in self.transitions.iter().take(self.transitions.len().saturating_sub(1)) {
            eta = phi * eta + b.iter().fold(Vector3::zeros(), |acc, (v, col)| acc + col * step[*v]);
            out.extend(eta.iter());
        }
        out
    }

    /// The transitions as equality rows `η_{s+1} − Φ_s η_s − B_s δ = 0`, `(entries, 0)`.
    pub fn rows(&self) -> Vec<Vec<(usize, f64)>> {
        let mut rows = Vec::new();
        for (s, (phi, b)) in self.transitions.iter().enumerate().take(self.transitions.len().saturating_sub(1)) {
            for i in 0..3 {
                let mut row = vec![(self.offset + 3 * s + i, 1.0)];
                for k in 0..3 {
                    if let Some(v) = self.variable(s, k) {
                        row.push((v, -phi[(i, k)]));
                    }
                }
                row.extend(b.iter().map(|(v, col)| (*v, -col[i])));
                rows.push(row);
            }
        }
        rows
    }
}

/// What one pass of the spinning model gives.
#[derive(Clone, Debug)]
pub struct SpinPass {
    /// The final orientation, its error from the target and the error's (dense) Jacobian.
    pub orientation: FinalOrientation,
    /// Torques on the grid, their gradients in the lifted form (module docs).
    pub samples: Vec<TorqueSample>,
    /// The lifted unknowns' transitions.
    pub lift: Lift,
}

/// Integrates A's orientation released with `spin` ([`crate::engines::exact::rk4_on`], `steps`
/// on the widest span) with its exact derivative, and the torques on `grid` (points in span and
/// time order) with theirs (module docs).
pub fn spin_pass(
    cat: &WholeCat,
    spline: &BSpline,
    layout: &Layout,
    steps: usize,
    target: &UnitQuaternion<f64>,
    spin: &Vector3<f64>,
    grid: &[GridPoint],
) -> SpinPass {
    assert_eq!(layout.joints, 2, "a release with spin is planned for the two-motor cats only");
    let n = layout.variables();
    let mut lift = Lift { offset: n, transitions: Vec::with_capacity(spline.spans()) };
    let mut psi = DMatrix::<f64>::zeros(3, n);
    let mut r: Q<f64> = [1.0, 0.0, 0.0, 0.0];
    let mut samples = Vec::with_capacity(grid.len());
    let mut next = 0;
    let widest = spline.widest_span();
    for span in 0..spline.spans() {
        let (t0, t1) = spline.span_bounds(span);
        let count = spline.by_width(span, widest, steps, 1);
        let h = (t1 - t0) / count as f64;
        let first = span;
        // δr = ½ (0, η) ⊗ r for the three directions of η_s.
        let mut y: Q<D> = r.map(D::cst);
        for i in 0..3 {
            let mut e = [0.0; 4];
            e[i + 1] = 0.5;
            let d = qmul(e, r);
            for (c, x) in y.iter_mut().zip(d) {
                c.eps[i] = x;
            }
        }
        for k in 0..count {
            let tk = t0 + k as f64 * h;
            let last = k + 1 == count;
            while next < grid.len() && grid[next].0 == span && (grid[next].1 < tk + h || last) {
                let (_, time, weight) = grid[next];
                let at = if time > tk { step(cat, spline, spin, span, y, tk, time - tk) } else { y };
                samples.push(torque_sample(cat, spline, layout, &lift, spin, span, first, time, weight, at));
                next += 1;
            }
            y = step(cat, spline, spin, span, y, tk, h);
        }
        r = y.map(|x| x.re);
        let phi = Matrix3::from_columns(&[tangent(&y, 0), tangent(&y, 1), tangent(&y, 2)]);
        let mut b = Vec::new();
        for j in 0..2 {
            for m in 0..4 {
                if let Some(v) = layout.variable(j, first + m) {
                    b.push((v, tangent(&y, local(j, m))));
                }
            }
        }
        let phi_d = DMatrix::from_fn(3, 3, |i, k| phi[(i, k)]);
        psi = phi_d * psi;
        for (v, col) in &b {
            for i in 0..3 {
                psi[(i, *v)] += col[i];
            }
        }
        lift.transitions.push((phi, b));
    }
    let orientation = UnitQuaternion::new_normalize(Quaternion::new(r[0], r[1], r[2], r[3]));
    let error = (target.inverse() * orientation).scaled_axis();
    let map = left_jacobian_inverse(&error) * target.inverse().to_rotation_matrix().into_inner();
    let jacobian = DMatrix::from_fn(3, 3, |i, j| map[(i, j)]) * psi;
    SpinPass { orientation: FinalOrientation { orientation, error, jacobian }, samples, lift }
}

/// The torque sample at `time` of `span` with A's orientation `at` there.
#[allow(clippy::too_many_arguments)]
fn torque_sample(
    cat: &WholeCat,
    spline: &BSpline,
    layout: &Layout,
    lift: &Lift,
    spin: &Vector3<f64>,
    span: usize,
    first: usize,
    time: f64,
    weight: f64,
    at: Q<D>,
) -> TorqueSample {
    let basis = spline.basis(span, time);
    let st = local_state(spline, &basis);
    let lambda = inverse_rotate(at, spin);
    let tau = cat.motor_torques_spinning(st.q, st.qd, st.qdd, lambda);
    let gradient = tau.map(|t| {
        let mut g: Vec<(usize, f64)> = (0..3).filter_map(|i| lift.variable(span, i).map(|v| (v, t.eps[i]))).collect();
        for j in 0..2 {
            for m in 0..4 {
                if let Some(v) = layout.variable(j, first + m) {
                    g.push((v, t.eps[local(j, m)]));
                }
            }
        }
        g
    });
    // In the same entries as `gradient` (zero for η and the other joint's points).
    let rate_gradient = [0, 1].map(|joint| {
        let mut g: Vec<(usize, f64)> = (0..3).filter_map(|i| lift.variable(span, i).map(|v| (v, 0.0))).collect();
        for j in 0..2 {
            for m in 0..4 {
                if let Some(v) = layout.variable(j, first + m) {
                    g.push((v, if j == joint { basis.values[1][m] } else { 0.0 }));
                }
            }
        }
        g
    });
    TorqueSample {
        time,
        weight,
        tau: tau.map(|t| t.re).to_vec(),
        gradient: gradient.to_vec(),
        rate: vec![st.qd[0].re, st.qd[1].re],
        rate_gradient: rate_gradient.to_vec(),
    }
}
