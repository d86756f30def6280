//! The primal-dual Newton system of one interior-point iteration, condensed and factored once
//! for the step and its second-order corrections.
//!
//! Unknowns `x = (c, t)` (the free control points and the peak bound), rows `g_r(x) ≥ 0` with
//! slacks `s_r > 0` and multipliers `z_r`, equality rows `a_i·x` of the flip with multipliers
//! `λ_i`. With `Σ = diag(z/s)`, `A` the rows' Jacobian and `W` the Lagrangian's Hessian (the
//! torques' curvature, [`super::curvature`]), the slacks and multipliers eliminated:
//!
//! $$ \begin{bmatrix} W + AᵀΣA + δI & -Eᵀ \\ E & 0 \end{bmatrix}
//!    \begin{bmatrix} d_x \\ d_λ \end{bmatrix} =
//!    \begin{bmatrix} -∇f + Eᵀλ + Aᵀ(μ/s - Σ r) \\ -c \end{bmatrix}, $$
//!
//! with `r = g − s` and `c` the rows' residuals (`r` and `c` replaced by their corrected sums in a
//! second-order correction), then `d_s = A d_x + r` and `d_z = μ/s − z − Σ d_s`. The `(c, t)`
//! block, banded but for `t` ([`super::banded`]), is factored by Cholesky once `δ` (on the
//! control points) makes it positive definite, after IPOPT's inertia correction: from a third of
//! the last `δ` (none below `10⁻¹⁰`), else from `10⁻⁴`, by factors of four (IPOPT tries none
//! first and grows by eight). The few equality rows enter by their Schur complement `E H⁻¹ Eᵀ`.
//!
//! ## References
//! - A. Wächter, L. T. Biegler, *On the implementation of an interior-point filter line-search
//!   algorithm for large-scale nonlinear programming*, Math. Program. 106 (2006) 25–57, §3.1.

use nalgebra::{DMatrix, DVector};

use super::banded::{Arrow, ArrowCholesky};

/// The smallest regularisation tried after none sufficed.
const FIRST_REGULARISATION: f64 = 1e-4;
/// The largest regularisation before the system counts as singular.
const MAX_REGULARISATION: f64 = 1e20;

/// The inequality rows `g_r(x) = g_r + t_r t + Σ a_rv c_v` at the current iterate, by rows.
#[derive(Clone, Debug, Default)]
pub(crate) struct Rows {
    /// Each row's value `g_r`.
    pub(crate) values: Vec<f64>,
    /// Each row's coefficient of the peak bound `t`.
    pub(crate) t: Vec<f64>,
    /// Where each row's control-point entries start in `entries` (one more than the rows).
    pub(crate) start: Vec<usize>,
    /// `(variable, coefficient)` of every row, row after row.
    pub(crate) entries: Vec<(usize, f64)>,
}

impl Rows {
    /// Number of rows.
    pub(crate) fn len(&self) -> usize {
        self.values.len()
    }

    /// Row `r`'s control-point entries.
    pub(crate) fn row(&self, r: usize) -> &[(usize, f64)] {
        &self.entries[self.start[r]..self.start[r + 1]]
    }

    /// `∇g_r · d` for a direction `d = (d_c, d_t)` whose last entry is `d_t`.
    pub(crate) fn dot(&self, r: usize, d: &DVector<f64>) -> f64 {
        let n = d.len() - 1;
        self.t[r] * d[n] + self.row(r).iter().map(|&(v, a)| a * d[v]).sum::<f64>()
    }

    /// Adds `Aᵀ y` to `out` (`out` over `(c, t)`).
    pub(crate) fn add_transposed(&self, y: &[f64], out: &mut DVector<f64>) {
        let n = out.len() - 1;
        for (r, &yr) in y.iter().enumerate() {
            out[n] += self.t[r] * yr;
            for &(v, a) in self.row(r) {
                out[v] += a * yr;
            }
        }
    }
}

/// The order of the unknowns in the factored matrix: control point `i` of coordinate `j` at
/// `i J + j` (time first, so that a sample's support is a band of half-width `(p + 1) J − 1`),
/// the peak bound last.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Order {
    pub(crate) joints: usize,
    pub(crate) free: usize,
}

impl Order {
    fn position(&self, v: usize) -> usize {
        (v % self.free) * self.joints + v / self.free
    }

    fn variables(&self) -> usize {
        self.joints * self.free
    }

    /// The band's half-width for a spline of degree `degree`.
    fn width(&self, degree: usize) -> usize {
        ((degree + 1) * self.joints - 1).min(self.variables().saturating_sub(1))
    }

    /// `x` (control points in the layout's order, then `t`) in the matrix's order.
    fn permuted(&self, x: &DVector<f64>) -> DVector<f64> {
        let n = self.variables();
        let mut out = DVector::zeros(n + 1);
        for v in 0..n {
            out[self.position(v)] = x[v];
        }
        out[n] = x[n];
        out
    }

    /// The inverse of [`Self::permuted`].
    fn unpermuted(&self, y: &DVector<f64>) -> DVector<f64> {
        let n = self.variables();
        let mut out = DVector::zeros(n + 1);
        for v in 0..n {
            out[v] = y[self.position(v)];
        }
        out[n] = y[n];
        out
    }
}

/// The factored Newton system of one iterate.
pub(crate) struct Newton {
    order: Order,
    factor: ArrowCholesky,
    /// `H⁻¹ Eᵀ`, one column per equality row, in the layout's order.
    spread: DMatrix<f64>,
    /// The Schur complement `E H⁻¹ Eᵀ`, inverted.
    schur_inverse: DMatrix<f64>,
    /// `Eᵀ` over `(c, t)`, in the layout's order.
    equality_t: DMatrix<f64>,
    /// The regularisation `δ` that made the block positive definite.
    pub(crate) regularisation: f64,
}

/// A Newton direction: `d_x` over `(c, t)`, `d_λ`, and the slacks' `d_s`.
pub(crate) struct Direction {
    pub(crate) x: DVector<f64>,
    pub(crate) lambda: DVector<f64>,
    pub(crate) s: Vec<f64>,
}

impl Newton {
    /// Factors `W + AᵀΣA + δI` (`curvature` the entries of `W` on the control points, in the
    /// layout's order, each symmetric pair given in full; the spline of degree `degree`) with
    /// the least `δ` found from `last` (module docs), and the Schur complement of the equality
    /// rows `equality` (each over the control points); none when no `δ` up to 10²⁰ factors or the
    /// complement is singular.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn factor(
        order: Order,
        degree: usize,
        curvature: &[(usize, usize, f64)],
        rows: &Rows,
        slacks: &[f64],
        duals: &[f64],
        equality: &[Vec<f64>],
        last: f64,
    ) -> Option<Newton> {
        let n = order.variables();
        let mut h = Arrow::zeros(n, order.width(degree));
        for &(v, u, a) in curvature {
            h.add(order.position(v), order.position(u), a);
        }
        // Each row's positions in the matrix, found once a row (not once an entry pair).
        let mut positions = Vec::new();
        for r in 0..rows.len() {
            let sigma = duals[r] / slacks[r];
            let (t, row) = (rows.t[r], rows.row(r));
            h.add(n, n, sigma * t * t);
            positions.clear();
            positions.extend(row.iter().map(|&(v, _)| order.position(v)));
            for (&(_, a), &pv) in row.iter().zip(&positions) {
                h.add(n, pv, sigma * a * t);
                for (&(_, b), &pu) in row.iter().zip(&positions) {
                    h.add(pv, pu, sigma * a * b);
                }
            }
        }
        let mut delta = if last > 0.0 { last / 3.0 } else { 0.0 };
        if delta < 1e-6 * FIRST_REGULARISATION {
            // Below 1e-10: none.
            delta = 0.0;
        }
        let factor = loop {
            if let Some(f) = h.cholesky(delta) {
                break f;
            }
            delta = if delta == 0.0 { FIRST_REGULARISATION } else { 4.0 * delta };
            if delta > MAX_REGULARISATION {
                return None;
            }
        };
        let k = equality.len();
        let equality_t = DMatrix::from_fn(n + 1, k, |v, i| if v < n { equality[i][v] } else { 0.0 });
        let mut spread = DMatrix::zeros(n + 1, k);
        for i in 0..k {
            let column = order.unpermuted(&factor.solve(&order.permuted(&equality_t.column(i).into_owned())));
            spread.set_column(i, &column);
        }
        let schur = equality_t.transpose() * &spread;
        let schur_inverse = if k == 0 { DMatrix::zeros(0, 0) } else { schur.try_inverse()? };
        Some(Newton { order, factor, spread, schur_inverse, equality_t, regularisation: delta })
    }

    /// The direction for the barrier parameter `mu` with the rows' residuals `row_residual`
    /// (`g − s`, or a correction's sum) and the equality rows' `equality_residual`, at the
    /// multipliers `lambda` and `duals` (module docs).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn direction(
        &self,
        rows: &Rows,
        slacks: &[f64],
        duals: &[f64],
        mu: f64,
        row_residual: &[f64],
        equality_residual: &[f64],
        lambda: &DVector<f64>,
    ) -> Direction {
        let nx = self.equality_t.nrows();
        let mut rhs = &self.equality_t * lambda;
        rhs[nx - 1] -= 1.0;
        let weights: Vec<f64> =
            (0..rows.len()).map(|r| mu / slacks[r] - duals[r] / slacks[r] * row_residual[r]).collect();
        rows.add_transposed(&weights, &mut rhs);
        let free = self.order.unpermuted(&self.factor.solve(&self.order.permuted(&rhs)));
        let c = DVector::from_column_slice(equality_residual);
        let d_lambda = &self.schur_inverse * (-c - self.equality_t.transpose() * &free);
        let x = free + &self.spread * &d_lambda;
        let s = (0..rows.len()).map(|r| rows.dot(r, &x) + row_residual[r]).collect();
        Direction { x, lambda: d_lambda, s }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numeric::random::SplitMix64;

    /// The condensed direction solves the full primal-dual Newton system (module docs) of a
    /// small random problem: `W d_x − Eᵀ d_λ − Aᵀ d_z = −(∇f − Eᵀλ − Aᵀz)`, `E d_x = −c`,
    /// `A d_x − d_s = −r`, `Z d_s + S d_z = μ − S z`, solved densely.
    #[test]
    fn the_condensed_direction_solves_the_full_newton_system() {
        let mut rng = SplitMix64::new(11);
        let order = Order { joints: 2, free: 3 };
        let (n, m, k) = (order.variables(), 7, 2);
        let nx = n + 1;
        // A positive definite W on the control points (so that no regularisation enters).
        let g = DMatrix::from_fn(n, n, |_, _| rng.uniform(-1.0, 1.0));
        let w = &g * g.transpose() + DMatrix::identity(n, n);
        let curvature: Vec<(usize, usize, f64)> =
            (0..n).flat_map(|v| (0..n).map(move |u| (v, u))).map(|(v, u)| (v, u, w[(v, u)])).collect();
        let mut rows = Rows { start: vec![0], ..Rows::default() };
        for _ in 0..m {
            rows.values.push(rng.uniform(0.1, 1.0));
            rows.t.push(if rng.unit() < 0.7 { 1.0 } else { 0.0 });
            rows.entries.extend((0..n).map(|v| (v, rng.uniform(-1.0, 1.0))));
            rows.start.push(rows.entries.len());
        }
        let slacks: Vec<f64> = (0..m).map(|_| rng.uniform(0.05, 1.0)).collect();
        let duals: Vec<f64> = (0..m).map(|_| rng.uniform(0.05, 1.0)).collect();
        let equality: Vec<Vec<f64>> = (0..k).map(|_| (0..n).map(|_| rng.uniform(-1.0, 1.0)).collect()).collect();
        let residual: Vec<f64> = (0..m).map(|_| rng.uniform(-0.1, 0.1)).collect();
        let c: Vec<f64> = (0..k).map(|_| rng.uniform(-0.1, 0.1)).collect();
        let lambda = DVector::from_fn(k, |_, _| rng.uniform(-1.0, 1.0));
        let mu = 1e-2;
        let newton = Newton::factor(order, 3, &curvature, &rows, &slacks, &duals, &equality, 0.0).expect("factors");
        assert!(newton.regularisation <= 0.0, "no regularisation: {}", newton.regularisation);
        let d = newton.direction(&rows, &slacks, &duals, mu, &residual, &c, &lambda);
        // The full system over (d_x, d_λ, d_s, d_z).
        let size = nx + k + 2 * m;
        let mut a = DMatrix::zeros(size, size);
        let mut b = DVector::zeros(size);
        let row_of = |r: usize| DVector::from_fn(nx, |v, _| if v == n { rows.t[r] } else { rows.row(r)[v].1 });
        // ∇f − Eᵀλ − Aᵀz with ∇f = e_t.
        let mut gradient = DVector::zeros(nx);
        gradient[n] = 1.0;
        for i in 0..k {
            for v in 0..n {
                gradient[v] -= equality[i][v] * lambda[i];
                a[(v, nx + i)] = -equality[i][v];
                a[(nx + i, v)] = equality[i][v];
            }
            b[nx + i] = -c[i];
        }
        for v in 0..n {
            for u in 0..n {
                a[(v, u)] = w[(v, u)];
            }
        }
        for r in 0..m {
            let ar = row_of(r);
            gradient -= &ar * duals[r];
            let (srow, zcol) = (nx + k + r, nx + k + m + r);
            for v in 0..nx {
                a[(v, zcol)] = -ar[v];
                a[(srow, v)] = ar[v];
            }
            a[(srow, nx + k + r)] = -1.0;
            b[srow] = -residual[r];
            // Z d_s + S d_z = μ − S z.
            a[(zcol, nx + k + r)] = duals[r];
            a[(zcol, zcol)] = slacks[r];
            b[zcol] = mu - slacks[r] * duals[r];
        }
        for v in 0..nx {
            b[v] = -gradient[v];
        }
        let full = a.lu().solve(&b).expect("a regular system");
        let worst_x = (0..nx).map(|v| (full[v] - d.x[v]).abs()).fold(0.0, f64::max);
        let worst_l = (0..k).map(|i| (full[nx + i] - d.lambda[i]).abs()).fold(0.0, f64::max);
        let worst_s = (0..m).map(|r| (full[nx + k + r] - d.s[r]).abs()).fold(0.0, f64::max);
        assert!(worst_x < 1e-10 && worst_l < 1e-10 && worst_s < 1e-10, "{worst_x:.1e} {worst_l:.1e} {worst_s:.1e}");
    }
}
