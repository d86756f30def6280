//! Exact first derivatives, with respect to the free control points, of the final orientation
//! and of the motor torques at sample instants.
//!
//! ## Final orientation: forward sensitivity of the Magnus integrator
//! The exact engine steps `R_{n+1} = R_n exp([σ_n]×)`, `σ_n = magnus6(h, Ω_{n,1}, Ω_{n,2}, Ω_{n,3})`
//! on the Gauss–Legendre nodes of each step, knot span by knot span ([`crate::engines::exact`]). Perturb
//! the rates: since `exp([σ + δσ]×) = exp([σ]×) exp([J_r(σ) δσ]×) + O(δ²)` with the right
//! Jacobian `J_r(φ) = 𝟙 − (1 − cos θ)/θ² [φ]× + (θ − sin θ)/θ³ [φ]×²`, `θ = |φ|`, a left
//! perturbation `R̃_n = exp([η_n]×) R_n` propagates as
//!
//! $$ η_{n+1} = η_n + R_{n+1} J_r(σ_n) \sum_k \frac{∂σ_n}{∂Ω_{n,k}} δΩ_{n,k}, $$
//!
//! the discrete form of `η̇ = R δΩ`. With `Ω = A(q) q̇` (linear in `q̇`),
//! `δΩ = Σ_j (∂Ω/∂q_j δq_j + ∂Ω/∂q̇_j δq̇_j)` and `δq_j = Σ_i N_i δc_{j,i}`. The partials of `Ω`
//! come from dual numbers through [`WholeCat::body_rate`], those of `σ` through [`magnus6`]: this is the
//! exact derivative of the integrator's own final orientation, not of a second discretisation.
//! The error `e = log(R_*ᵀ R(T))` of the target `R_*` then moves by
//! `δe = J_l⁻¹(e) R_*ᵀ η` (`log(exp([a]×) exp([e]×)) = e + J_l(e)⁻¹ a + O(a²)`,
//! `J_l⁻¹(φ) = 𝟙 − ½[φ]× + (1/θ² − (1 + cos θ)/(2θ sin θ))[φ]×²`).
//!
//! ## Torques
//! `τ(q, q̇, q̈)` from [`WholeCat::motor_torques`] at dual numbers seeded on `(q, q̇, q̈)` of every
//! coordinate ([`WholeCat::torque_partials`]: `Dual<6>` on two coordinates, `Dual<9>` on the
//! spherical joint's three, `Dual<12>` on four coordinates, up to `Dual<18>` on a cat with a tail and legs), chained through `N_i, N'_i, N''_i`.
//!
//! ## References
//! - J. Solà, J. Deray, D. Atchuthan, *A micro Lie theory for state estimation in robotics*
//!   (arXiv:1812.01537, 2018), eqs. (143)–(146) for `J_r`, `J_l⁻¹` of SO(3);
//! - S. Blanes, F. Casas, J. Ros, BIT 40 (2000) 434–450, for the Magnus scheme.

use nalgebra::{DMatrix, Matrix3, UnitQuaternion, Vector3};
use rayon::prelude::*;

use super::cat::{Partials, WholeCat, MAX_JOINTS};
use super::dual::Dual;
use super::dynamics::magnus6;
use super::spline::{BSpline, Basis};
use crate::model::skew;

/// Which control points are free: the first and last `fixed` of each joint are held at zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Control points per joint.
    pub control_points: usize,
    /// Control points held at zero at each end of each joint.
    pub fixed: usize,
    /// Number of joint coordinates (curves): 2, 3 on the spherical joint, up to 6 with appendages.
    pub joints: usize,
}

impl Layout {
    /// Free control points per joint.
    pub fn free(&self) -> usize {
        self.control_points - 2 * self.fixed
    }

    /// Number of variables (every joint coordinate's).
    pub fn variables(&self) -> usize {
        self.joints * self.free()
    }

    /// The variable of control point `i` of joint `j`, if it is free.
    pub fn variable(&self, j: usize, i: usize) -> Option<usize> {
        (i >= self.fixed && i < self.control_points - self.fixed).then(|| j * self.free() + i - self.fixed)
    }

    /// Each variable's share of the trust radius: the narrowest knot span in its control point's
    /// support over the widest span of the spline (1 on uniform knots). A control point moved by
    /// `δ` changes the rate by `O(δ/h)` on spans `h` wide, where the torque is nonlinear in
    /// the rate: on knots refined where a torque switches, a radius fit for the wide spans made
    /// the ratio test reject step after step near the optimum.
    pub fn trust_scales(&self, spline: &BSpline) -> Vec<f64> {
        let widths: Vec<f64> = (0..spline.spans()).map(|s| spline.span_bounds(s)).map(|(a, b)| b - a).collect();
        let widest = widths.iter().copied().fold(0.0, f64::max);
        let p = spline.degree;
        let mut scales = vec![1.0; self.variables()];
        for j in 0..self.joints {
            for i in self.fixed..self.control_points - self.fixed {
                if let Some(v) = self.variable(j, i) {
                    // Control point i's support is spans i − p ..= i (those that exist).
                    let narrowest = (i.saturating_sub(p)..=i.min(widths.len() - 1))
                        .map(|s| widths[s])
                        .fold(f64::INFINITY, f64::min);
                    scales[v] = (narrowest / widest).min(1.0);
                }
            }
        }
        scales
    }

    /// The current value of every variable.
    pub fn values(&self, spline: &BSpline) -> Vec<f64> {
        (0..self.joints)
            .flat_map(|j| spline.coefficients[j][self.fixed..self.control_points - self.fixed].to_vec())
            .collect()
    }

    /// The spline moved by `step` on the free control points.
    pub fn moved(&self, spline: &BSpline, step: &[f64]) -> BSpline {
        let mut out = spline.clone();
        for j in 0..self.joints {
            for i in self.fixed..self.control_points - self.fixed {
                if let Some(v) = self.variable(j, i) {
                    out.coefficients[j][i] += step[v];
                }
            }
        }
        out
    }

    /// `(variable, ∂x/∂c)` for a quantity with partials `dq[j]`, `dqd[j]`, `dqdd[j]` with respect to
    /// joint `j`'s angle, rate and acceleration (one per joint coordinate), chained through `basis`.
    fn chain(&self, basis: &Basis, dq: &[f64], dqd: &[f64], dqdd: &[f64], out: &mut Vec<(usize, f64)>) {
        for j in 0..self.joints {
            for (m, ((n, nd), ndd)) in basis.values[0].iter().zip(&basis.values[1]).zip(&basis.values[2]).enumerate() {
                if let Some(v) = self.variable(j, basis.first + m) {
                    out.push((v, dq[j] * n + dqd[j] * nd + dqdd[j] * ndd));
                }
            }
        }
    }
}

/// The final orientation, its error from the target and the error's Jacobian.
#[derive(Clone, Debug, PartialEq)]
pub struct FinalOrientation {
    /// A's final orientation `R(T)`.
    pub orientation: UnitQuaternion<f64>,
    /// `e = log(R_*ᵀ R(T))`, rad.
    pub error: Vector3<f64>,
    /// `∂e/∂x`, 3 × variables, rad per rad.
    pub jacobian: DMatrix<f64>,
}

/// `(1 − cos θ)/θ²` and `(θ − sin θ)/θ³`, by series near zero.
fn right_jacobian(phi: &Vector3<f64>) -> Matrix3<f64> {
    let t2 = phi.norm_squared();
    let t = t2.sqrt();
    let (a, b) = if t < 1e-4 {
        (0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0)
    } else {
        ((1.0 - t.cos()) / t2, (t - t.sin()) / (t2 * t))
    };
    let k = skew(phi);
    Matrix3::identity() - a * k + b * k * k
}

/// `J_l(φ)⁻¹`, by series near zero.
pub fn left_jacobian_inverse(phi: &Vector3<f64>) -> Matrix3<f64> {
    let t2 = phi.norm_squared();
    let t = t2.sqrt();
    let c = if t < 1e-4 { 1.0 / 12.0 + t2 / 720.0 } else { 1.0 / t2 - (1.0 + t.cos()) / (2.0 * t * t.sin()) };
    let k = skew(phi);
    Matrix3::identity() - 0.5 * k + c * k * k
}

/// The basis at a Magnus node and the body rate there with its partials in `(q, q̇)`.
type NodeRate = (Basis, [Partials; 3]);

/// Integrates the orientation with `steps` Magnus steps per knot span (on the widest span; fewer
/// on narrower ones, [`BSpline::by_width`]), as
/// [`crate::engines::exact::integrate`] does, and its exact derivative (module docs).
pub fn final_orientation(
    cat: &WholeCat,
    spline: &BSpline,
    layout: &Layout,
    steps: usize,
    target: &UnitQuaternion<f64>,
) -> FinalOrientation {
    let c = 15f64.sqrt() / 10.0;
    let nodes = [0.5 - c, 0.5, 0.5 + c];
    let mut r = UnitQuaternion::identity();
    let mut eta = DMatrix::<f64>::zeros(3, layout.variables());
    let mut columns: Vec<(usize, f64)> = Vec::new();
    let widest = spline.widest_span();
    // Every step's rates and their partials at its three nodes, `(h, nodes)` in step order: each
    // depends on its instant only, so they are computed in parallel; the propagation below is
    // sequential.
    let grid: Vec<(usize, f64, usize, f64)> = (0..spline.spans())
        .flat_map(|span| {
            let (t0, t1) = spline.span_bounds(span);
            let steps = spline.by_width(span, widest, steps, 1);
            let h = (t1 - t0) / steps as f64;
            (0..steps).map(move |n| (span, t0, n, h))
        })
        .collect();
    let rates: Vec<(f64, [NodeRate; 3])> = grid
        .par_iter()
        .with_min_len(16)
        .map(|&(span, t0, n, h)| {
            (
                h,
                nodes.map(|c| {
                    let basis = spline.basis(span, t0 + (n as f64 + c) * h);
                    let [q, qd, _] = spline.values::<MAX_JOINTS>(&basis);
                    let joints = layout.joints;
                    let rate = cat.rate_partials(&q[..joints], &qd[..joints]);
                    (basis, rate)
                }),
            )
        })
        .collect();
    for (h, at) in &rates {
        let h = *h;
        let w: [[Dual<9>; 3]; 3] =
            std::array::from_fn(|k| std::array::from_fn(|i| Dual::input(at[k].1[i].value, 3 * k + i)));
        let sigma = magnus6(h, w[0], w[1], w[2]);
        let sigma_re = Vector3::new(sigma[0].re, sigma[1].re, sigma[2].re);
        r = UnitQuaternion::new_normalize(*(r * UnitQuaternion::from_scaled_axis(sigma_re)).quaternion());
        let m = r.to_rotation_matrix().into_inner() * right_jacobian(&sigma_re);
        for (k, (basis, omega)) in at.iter().enumerate() {
            let ds = Matrix3::from_fn(|i, l| sigma[i].eps[3 * k + l]);
            let p = m * ds;
            // Column of ∂Ω/∂c for each free control point touching this node.
            for comp in 0..3 {
                columns.clear();
                let [dq, dqd, dqdd] = &omega[comp].d;
                layout.chain(basis, dq, dqd, dqdd, &mut columns);
                for &(v, g) in &columns {
                    for row in 0..3 {
                        eta[(row, v)] += p[(row, comp)] * g;
                    }
                }
            }
        }
    }
    let error = (target.inverse() * r).scaled_axis();
    let map = left_jacobian_inverse(&error) * target.inverse().to_rotation_matrix().into_inner();
    FinalOrientation { orientation: r, error, jacobian: DMatrix::from_fn(3, 3, |i, j| map[(i, j)]) * eta }
}

/// Motor torques at one instant with their gradients.
#[derive(Clone, Debug, PartialEq)]
pub struct TorqueSample {
    /// Time, s.
    pub time: f64,
    /// Quadrature weight for `∫ τ·τ dt`, s (zero on a peak grid).
    pub weight: f64,
    /// `(τ1, …)`, one per motor, N·m.
    pub tau: Vec<f64>,
    /// `∂τ_j/∂x` as `(variable, value)`, one list per motor, N·m per rad.
    pub gradient: Vec<Vec<(usize, f64)>>,
    /// `(q̇1, …)`, rad/s.
    pub rate: Vec<f64>,
    /// `∂q̇_j/∂x`, in the same entries as `gradient` (zero for the other joints' points), 1/s.
    pub rate_gradient: Vec<Vec<(usize, f64)>>,
}

/// The cosine of the bend, `e_z` (B's axis on A's; [`WholeCat::bend_cosine`]), with its gradient.
#[derive(Clone, Debug, PartialEq)]
pub struct BendSample {
    /// `cos β`.
    pub cos_bend: f64,
    /// `∂ cos β/∂x`.
    pub gradient: Vec<(usize, f64)>,
}

/// An instant of a sample grid: span, time, quadrature weight.
pub type GridPoint = (usize, f64, f64);

/// `per_span` equally spaced instants per span, both ends of the fall included (weight zero).
pub fn uniform_grid(spline: &BSpline, per_span: usize) -> Vec<GridPoint> {
    let mut out = Vec::new();
    for s in 0..spline.spans() {
        let (a, b) = spline.span_bounds(s);
        out.extend((0..per_span).map(|k| (s, a + (b - a) * k as f64 / per_span as f64, 0.0)));
    }
    let last = spline.spans() - 1;
    out.push((last, spline.duration(), 0.0));
    out
}

/// Three-point Gauss–Legendre instants on `parts` equal parts of every span, with weights.
pub fn gauss_grid(spline: &BSpline, parts: usize) -> Vec<GridPoint> {
    let c = 15f64.sqrt() / 10.0;
    let rule = [(0.5 - c, 5.0 / 18.0), (0.5, 8.0 / 18.0), (0.5 + c, 5.0 / 18.0)];
    let mut out = Vec::new();
    for s in 0..spline.spans() {
        let (a, b) = spline.span_bounds(s);
        let h = (b - a) / parts as f64;
        for p in 0..parts {
            out.extend(rule.iter().map(|&(x, w)| (s, a + (p as f64 + x) * h, w * h)));
        }
    }
    out
}

/// Torques and their gradients on a grid (each instant on its own, in parallel): [`grid_partials`]
/// chained to the control points by [`chained_samples`].
pub fn torque_samples(cat: &WholeCat, spline: &BSpline, layout: &Layout, grid: &[GridPoint]) -> Vec<TorqueSample> {
    chained_samples(spline, layout, grid, &grid_partials(cat, spline, layout.joints, grid))
}

/// Each instant's motor torques with their partials in `(q, q̇, q̈)` ([`WholeCat::torque_partials`]),
/// `joints` coordinates, in parallel.
pub fn grid_partials(cat: &WholeCat, spline: &BSpline, joints: usize, grid: &[GridPoint]) -> Vec<Vec<Partials>> {
    grid.par_iter()
        .with_min_len(16)
        .map(|&(span, time, _)| {
            let [q, qd, qdd] = spline.values::<MAX_JOINTS>(&spline.basis(span, time));
            cat.torque_partials(&q[..joints], &qd[..joints], &qdd[..joints])
        })
        .collect()
}

/// The samples on `grid` from each instant's torque `partials` ([`grid_partials`]): their
/// gradients on the layout's variables through the spline's basis.
pub fn chained_samples(
    spline: &BSpline,
    layout: &Layout,
    grid: &[GridPoint],
    partials: &[Vec<Partials>],
) -> Vec<TorqueSample> {
    grid.par_iter()
        .zip(partials)
        .with_min_len(16)
        .map(|(&(span, time, weight), tau)| {
            let basis = spline.basis(span, time);
            let joints = layout.joints;
            let [_, qd, _] = spline.values::<MAX_JOINTS>(&basis);
            let width = joints * basis.values[0].len();
            let gradient = tau
                .iter()
                .map(|t| {
                    let mut g = Vec::with_capacity(width);
                    let [dq, dqd, dqdd] = &t.d;
                    layout.chain(&basis, dq, dqd, dqdd, &mut g);
                    g
                })
                .collect();
            let zero = [0.0; MAX_JOINTS];
            let rate_gradient = (0..joints)
                .map(|j| {
                    let mut unit = zero;
                    unit[j] = 1.0;
                    let mut g = Vec::with_capacity(width);
                    layout.chain(&basis, &zero, &unit, &zero, &mut g);
                    g
                })
                .collect();
            let tau = tau.iter().map(|t| t.value).collect();
            TorqueSample { time, weight, tau, gradient, rate: qd[..joints].to_vec(), rate_gradient }
        })
        .collect()
}

/// The bend's cosine and its gradient on a grid.
pub fn bend_samples(cat: &WholeCat, spline: &BSpline, layout: &Layout, grid: &[GridPoint]) -> Vec<BendSample> {
    grid.iter()
        .map(|&(span, time, _)| {
            let basis = spline.basis(span, time);
            let [q, _, _] = spline.values::<MAX_JOINTS>(&basis);
            let (cos_bend, dq) = cat.bend_cosine(&q[..layout.joints]);
            let zero = [0.0; MAX_JOINTS];
            let mut gradient = Vec::new();
            layout.chain(&basis, &dq, &zero, &zero, &mut gradient);
            BendSample { cos_bend, gradient }
        })
        .collect()
}
