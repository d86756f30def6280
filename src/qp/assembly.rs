//! Sparse assembly of both QPs in Clarabel's standard form, and the call to Clarabel.
//!
//! Rows are collected as triplets, equalities (the zero cone) apart from inequalities (the
//! nonnegative cone), and joined once into one `CscMatrix`: `Ax + s = b`, `s ∈ {0}^{m₁} × ℝ₊^{m₂}`.
//! The constraints on the node rates that both QPs share (integral, boundary, rate, jerk, trust
//! box) are written here once, on `v = offset + x`.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSolver, IPSolver, SupportedConeT};

use super::settings::QpSettings;
use super::solution::{QpStatus, SolveInfo};
use super::QpError;
use crate::settings::Boundary;

/// Rows of one cone, as triplets.
#[derive(Default)]
struct Rows {
    row: Vec<usize>,
    col: Vec<usize>,
    val: Vec<f64>,
    rhs: Vec<f64>,
}

impl Rows {
    /// Appends the row `Σ val·x_col (+ s) = rhs`.
    fn push(&mut self, entries: impl IntoIterator<Item = (usize, f64)>, rhs: f64) {
        let r = self.rhs.len();
        for (c, v) in entries {
            self.row.push(r);
            self.col.push(c);
            self.val.push(v);
        }
        self.rhs.push(rhs);
    }
}

/// A QP under construction: `n` variables, the objective, and the constraint rows.
pub(crate) struct Assembly {
    n: usize,
    q: Vec<f64>,
    p: Rows,
    eq: Rows,
    ineq: Rows,
}

impl Assembly {
    pub(crate) fn new(n: usize) -> Self {
        Self { n, q: vec![0.0; n], p: Rows::default(), eq: Rows::default(), ineq: Rows::default() }
    }

    /// Sets the linear objective coefficient of variable `col`.
    pub(crate) fn linear_cost(&mut self, col: usize, value: f64) {
        self.q[col] = value;
    }

    /// Adds `weight · (Σ val·x_col)²` to `½xᵀPx` (upper triangle, repeated entries summed).
    pub(crate) fn square_cost(&mut self, entries: &[(usize, f64)], weight: f64) {
        for &(i, a) in entries {
            for &(j, b) in entries {
                if i <= j {
                    let both = if i == j { 1.0 } else { 2.0 };
                    // ½ xᵀPx = weight (aᵀx)²  ⇒  P = 2 weight a aᵀ; both triangles fold into one.
                    self.p.row.push(i);
                    self.p.col.push(j);
                    self.p.val.push(weight * a * b * both);
                }
            }
        }
    }

    /// The equality `Σ val·x_col = rhs`.
    pub(crate) fn equal(&mut self, entries: impl IntoIterator<Item = (usize, f64)>, rhs: f64) {
        self.eq.push(entries, rhs);
    }

    /// The inequality `Σ val·x_col ≤ rhs`.
    pub(crate) fn at_most(&mut self, entries: impl IntoIterator<Item = (usize, f64)>, rhs: f64) {
        self.ineq.push(entries, rhs);
    }

    /// `lower ≤ Σ val·x_col ≤ upper`, as two inequality rows.
    pub(crate) fn between(&mut self, entries: &[(usize, f64)], lower: f64, upper: f64) {
        self.at_most(entries.iter().copied(), upper);
        self.at_most(entries.iter().map(|&(c, v)| (c, -v)), -lower);
    }

    /// `|Σ val·x_col + constant| ≤ x_bound`, as two inequality rows.
    pub(crate) fn abs_at_most<I>(&mut self, entries: I, constant: f64, bound: usize)
    where
        I: Iterator<Item = (usize, f64)> + Clone,
    {
        self.at_most(entries.clone().chain([(bound, -1.0)]), -constant);
        self.at_most(entries.map(|(c, v)| (c, -v)).chain([(bound, -1.0)]), constant);
    }

    /// Solves with Clarabel; returns the primal iterate and Clarabel's account, whatever the
    /// status.
    pub(crate) fn solve(self, settings: &QpSettings) -> Result<Solved, QpError> {
        let settings = settings.clarabel()?;
        let (m_eq, m_ineq) = (self.eq.rhs.len(), self.ineq.rhs.len());
        let Assembly { n, q, p, eq, ineq } = self;
        let p = CscMatrix::new_from_triplets(n, n, p.row, p.col, p.val);
        let mut row = eq.row;
        row.extend(ineq.row.iter().map(|r| r + m_eq));
        let mut col = eq.col;
        col.extend(ineq.col);
        let mut val = eq.val;
        val.extend(ineq.val);
        let a = CscMatrix::new_from_triplets(m_eq + m_ineq, n, row, col, val);
        let mut b = eq.rhs;
        b.extend(ineq.rhs);
        let mut cones = Vec::with_capacity(2);
        if m_eq > 0 {
            cones.push(SupportedConeT::ZeroConeT(m_eq));
        }
        if m_ineq > 0 {
            cones.push(SupportedConeT::NonnegativeConeT(m_ineq));
        }
        let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings)
            .map_err(|e| QpError::Setup(e.to_string()))?;
        solver.solve();
        let (sol, info) = (&solver.solution, &solver.info);
        Ok(Solved {
            x: sol.x.clone(),
            status: sol.status.into(),
            objective: sol.obj_val,
            info: SolveInfo {
                iterations: sol.iterations,
                solve_time_s: sol.solve_time,
                primal_residual: sol.r_prim,
                dual_residual: sol.r_dual,
                duality_gap: info.gap_abs,
                relative_gap: info.gap_rel,
            },
        })
    }
}

/// Clarabel's answer, in the normalised variables.
pub(crate) struct Solved {
    pub(crate) x: Vec<f64>,
    pub(crate) status: QpStatus,
    pub(crate) objective: f64,
    pub(crate) info: SolveInfo,
}

/// The constraints on normalised node rates `v = offset + x` (the first `nodes` variables `x`)
/// that both QPs share; see the module docs. Limits are normalised, `None` for none.
pub(crate) struct NodeConstraints<'a> {
    pub(crate) nodes: usize,
    pub(crate) boundary: Boundary,
    /// `\hat R`.
    pub(crate) rate_limit: Option<f64>,
    /// `\hat J`.
    pub(crate) jerk_limit: Option<f64>,
    /// Box `|x_k| ≤ trust` on the step.
    pub(crate) trust: Option<f64>,
    /// Current rates when `x` is a step; `None` when `x` is the rates themselves.
    pub(crate) offset: Option<&'a [f64]>,
}

impl NodeConstraints<'_> {
    fn offset(&self, k: usize) -> f64 {
        self.offset.map_or(0.0, |o| o[k])
    }

    /// Adds the rows to `asm`.
    pub(crate) fn add_to(&self, asm: &mut Assembly) {
        let n = self.nodes;
        let h = 1.0 / (n - 1) as f64;
        let weight = |k: usize| if k == 0 || k == n - 1 { 0.5 * h } else { h };

        // Trapezoid integral of v is one.
        let current: f64 = (0..n).map(|k| weight(k) * self.offset(k)).sum();
        asm.equal((0..n).map(|k| (k, weight(k))), 1.0 - current);

        // Boundary conditions.
        asm.equal([(0, 1.0)], -self.offset(0));
        if self.boundary == Boundary::RestToRest {
            asm.equal([(n - 1, 1.0)], -self.offset(n - 1));
        }

        // Rate limit and trust box, one pair of rows per node.
        if self.rate_limit.is_some() || self.trust.is_some() {
            for k in 0..n {
                let (mut lower, mut upper) = (f64::NEG_INFINITY, f64::INFINITY);
                if let Some(r) = self.rate_limit {
                    lower = -r - self.offset(k);
                    upper = r - self.offset(k);
                }
                if let Some(t) = self.trust {
                    lower = lower.max(-t);
                    upper = upper.min(t);
                }
                asm.between(&[(k, 1.0)], lower, upper);
            }
        }

        // Jerk limit, as change of acceleration per step, ĥ Ĵ; zero acceleration outside.
        if let Some(j) = self.jerk_limit {
            let step = h * j;
            let accel = |k: usize| (self.offset(k + 1) - self.offset(k)) / h;
            asm.between(&[(0, -1.0 / h), (1, 1.0 / h)], -step - accel(0), step - accel(0));
            for k in 1..n - 1 {
                let change = accel(k) - accel(k - 1);
                let stencil = [(k - 1, 1.0 / h), (k, -2.0 / h), (k + 1, 1.0 / h)];
                asm.between(&stencil, -step - change, step - change);
            }
            let last = accel(n - 2);
            asm.between(&[(n - 2, -1.0 / h), (n - 1, 1.0 / h)], -step - last, step - last);
        }
    }
}
