//! Sparse assembly of a QP in Clarabel's standard form, and its solve.
//!
//! Rows are collected as triplets, equalities (the zero cone) apart from inequalities (the
//! nonnegative cone), and joined once into one `CscMatrix`: `Ax + s = b`, `s ∈ {0}^{m₁} × ℝ₊^{m₂}`.
//! The profile QP, the refinement's step and the whole manoeuvre's subproblems are built on
//! [`Assembly`]; the retiming, whose rows include second-order cones, builds its own matrix from
//! [`Rows`] and calls [`solve_clarabel`] itself.

mod active_set;

use std::collections::HashSet;

use clarabel::solver::SupportedConeT;

use super::csc::from_triplets;
use super::error::ConicError;
use super::settings::QpSettings;
use super::solution::{QpStatus, SolveInfo};
use super::solve::solve_clarabel;

/// Rows of one cone, as triplets (shared with the retiming's assembly).
#[derive(Default)]
pub(crate) struct Rows {
    pub(crate) row: Vec<usize>,
    pub(crate) col: Vec<usize>,
    pub(crate) val: Vec<f64>,
    pub(crate) rhs: Vec<f64>,
}

impl Rows {
    /// Appends the row `Σ val·x_col (+ s) = rhs`.
    pub(crate) fn push(&mut self, entries: impl IntoIterator<Item = (usize, f64)>, rhs: f64) {
        self.push_where(entries, rhs, |_| true);
    }

    /// Appends the row `Σ val·x_col (+ s) = rhs`, leaving out zero coefficients.
    pub(crate) fn push_nonzero(&mut self, entries: impl IntoIterator<Item = (usize, f64)>, rhs: f64) {
        self.push_where(entries, rhs, |v| v != 0.0);
    }

    fn push_where(&mut self, entries: impl IntoIterator<Item = (usize, f64)>, rhs: f64, keep: impl Fn(f64) -> bool) {
        let r = self.rhs.len();
        for (c, v) in entries.into_iter().filter(|&(_, v)| keep(v)) {
            self.row.push(r);
            self.col.push(c);
            self.val.push(v);
        }
        self.rhs.push(rhs);
    }

    /// Number of rows.
    pub(crate) fn len(&self) -> usize {
        self.rhs.len()
    }

    /// The rows on the folded variables: repeated entries summed, zeros dropped, and the rows
    /// that became repeats (for equalities, `signless`, also negated repeats) or trivially
    /// true (`0 = 0`, `0 ≤ b ≥ 0`) left out.
    fn folded(&self, fold: &Fold, signless: bool) -> Rows {
        let mut out = Rows::default();
        let mut seen: HashSet<(Vec<(usize, u64)>, u64)> = HashSet::with_capacity(self.rhs.len());
        let mut start = 0;
        for (r, &rhs) in self.rhs.iter().enumerate() {
            let end = start + self.row[start..].iter().take_while(|&&i| i == r).count();
            let mut mapped: Vec<(usize, f64)> =
                (start..end).filter_map(|e| fold.map[self.col[e]].map(|(c, s)| (c, s * self.val[e]))).collect();
            start = end;
            mapped.sort_unstable_by_key(|e| e.0);
            let mut entries: Vec<(usize, f64)> = Vec::with_capacity(mapped.len());
            for (c, v) in mapped {
                match entries.last_mut() {
                    Some(last) if last.0 == c => last.1 += v,
                    _ => entries.push((c, v)),
                }
            }
            entries.retain(|e| e.1 != 0.0);
            let flip = signless && entries.first().is_some_and(|e| e.1 < 0.0);
            let sign = if flip { -1.0 } else { 1.0 };
            let rhs = sign * rhs + 0.0; // + 0.0 turns −0 into +0 for the key
            if entries.is_empty() && (rhs == 0.0 || (!signless && rhs > 0.0)) {
                continue;
            }
            let key = entries.iter().map(|&(c, v)| (c, (sign * v + 0.0).to_bits())).collect();
            if seen.insert((key, rhs.to_bits())) {
                out.push(entries.into_iter().map(|(c, v)| (c, sign * v)), rhs);
            }
        }
        out
    }
}

/// A substitution `x_i = s_i y_{c_i}` (or `x_i = 0`) of the variables by fewer ones: solving on a
/// subspace that holds an optimum, such as the reversal-symmetric profiles of the rest-to-rest
/// QP.
pub(crate) struct Fold {
    /// `(c_i, s_i)` for each original variable, `None` for one fixed at zero.
    pub(crate) map: Vec<Option<(usize, f64)>>,
    /// Number of new variables `y`.
    pub(crate) n: usize,
}

impl Fold {
    /// The original variables `x` of new ones `y`.
    pub(crate) fn expand(&self, y: &[f64]) -> Vec<f64> {
        self.map.iter().map(|m| m.map_or(0.0, |(c, s)| s * y[c])).collect()
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
                // ½ xᵀPx = weight (aᵀx)²  ⇒  P = 2 weight a aᵀ, of which Clarabel takes the
                // upper triangle.
                if i <= j {
                    self.p.row.push(i);
                    self.p.col.push(j);
                    self.p.val.push(2.0 * weight * a * b);
                }
            }
        }
    }

    /// Adds `½ weight · xᵀ M x` to the objective, `M` symmetric over the first `M.nrows()`
    /// variables (upper triangle; exact zeros left out).
    pub(crate) fn quadratic_cost(&mut self, m: &nalgebra::DMatrix<f64>, weight: f64) {
        for j in 0..m.ncols() {
            for i in 0..=j {
                if m[(i, j)] != 0.0 {
                    self.p.row.push(i);
                    self.p.col.push(j);
                    self.p.val.push(weight * m[(i, j)]);
                }
            }
        }
    }

    /// Adds `½ value · Σ x_col²` over the first `n` variables to the objective (`value·𝟙` on
    /// `P`'s diagonal; nothing when `value` is zero).
    pub(crate) fn identity_cost(&mut self, n: usize, value: f64) {
        if value != 0.0 {
            for j in 0..n {
                self.p.row.push(j);
                self.p.col.push(j);
                self.p.val.push(value);
            }
        }
    }

    /// The equality `Σ val·x_col = rhs`.
    pub(crate) fn equal(&mut self, entries: impl IntoIterator<Item = (usize, f64)>, rhs: f64) {
        self.eq.push(entries, rhs);
    }

    /// Number of equality rows so far: the index of the next one among [`Solved::duals`].
    pub(crate) fn equalities(&self) -> usize {
        self.eq.len()
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
        self.sides_at_most(entries, constant, [true, true], bound);
    }

    /// The sides `[+, −]` of [`Assembly::abs_at_most`] that `sides` keeps (the others screened
    /// out as never binding, [`active_sides`]): `± (Σ val·x_col + constant) ≤ x_bound`.
    pub(crate) fn sides_at_most<I>(&mut self, entries: I, constant: f64, sides: [bool; 2], bound: usize)
    where
        I: Iterator<Item = (usize, f64)> + Clone,
    {
        for (sign, _) in [1.0, -1.0].into_iter().zip(sides).filter(|(_, side)| *side) {
            self.side_at_most(entries.clone(), constant, sign, bound);
        }
    }

    /// One side `sign · (Σ val·x_col + constant) ≤ x_bound` (`sign` = ±1); returns its index
    /// among the inequalities (its multiplier is `duals[equalities + index]`, [`Solved::duals`]).
    pub(crate) fn side_at_most(
        &mut self,
        entries: impl Iterator<Item = (usize, f64)>,
        constant: f64,
        sign: f64,
        bound: usize,
    ) -> usize {
        let index = self.ineq.len();
        self.at_most(entries.map(|(c, v)| (c, sign * v)).chain([(bound, -1.0)]), -sign * constant);
        index
    }

    /// The same QP on the variables of `fold`: its objective restricted to the subspace and its
    /// distinct constraint rows.
    pub(crate) fn fold(self, fold: &Fold) -> Assembly {
        let mut folded = Assembly::new(fold.n);
        for (i, &q) in self.q.iter().enumerate() {
            if let Some((c, s)) = fold.map[i] {
                folded.q[c] += s * q;
            }
        }
        for e in 0..self.p.val.len() {
            let (i, j) = (self.p.row[e], self.p.col[e]);
            if let (Some((a, s)), Some((b, t))) = (fold.map[i], fold.map[j]) {
                // An off-diagonal entry stands for P_ij + P_ji: both land on the diagonal.
                let both = if a == b && i != j { 2.0 } else { 1.0 };
                folded.p.row.push(a.min(b));
                folded.p.col.push(a.max(b));
                folded.p.val.push(both * s * t * self.p.val[e]);
            }
        }
        folded.eq = self.eq.folded(fold, true);
        folded.ineq = self.ineq.folded(fold, false);
        folded
    }

    /// Solves with Clarabel; returns the primal iterate and Clarabel's account, whatever the
    /// status.
    pub(crate) fn solve(self, settings: &QpSettings) -> Result<Solved, ConicError> {
        let (m_eq, m_ineq) = (self.eq.rhs.len(), self.ineq.rhs.len());
        let Assembly { n, q, p, eq, ineq } = self;
        let p = from_triplets(n, n, &p.row, &p.col, &p.val);
        let mut row = eq.row;
        row.extend(ineq.row.iter().map(|r| r + m_eq));
        let mut col = eq.col;
        col.extend(ineq.col);
        let mut val = eq.val;
        val.extend(ineq.val);
        let a = from_triplets(m_eq + m_ineq, n, &row, &col, &val);
        let mut b = eq.rhs;
        b.extend(ineq.rhs);
        let mut cones = Vec::with_capacity(2);
        if m_eq > 0 {
            cones.push(SupportedConeT::ZeroConeT(m_eq));
        }
        if m_ineq > 0 {
            cones.push(SupportedConeT::NonnegativeConeT(m_ineq));
        }
        let (solver, solve_time) = solve_clarabel(settings, &p, &q, &a, &b, &cones)?;
        let (sol, info) = (&solver.solution, &solver.info);
        Ok(Solved {
            x: sol.x.clone(),
            duals: sol.z.clone(),
            status: sol.status.into(),
            objective: sol.obj_val,
            info: SolveInfo {
                iterations: sol.iterations,
                solve_time_s: solve_time,
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
    /// Clarabel's multipliers `z`, one per row, the equalities first in the order they were
    /// added, then the inequalities (`Px + q + Aᵀz = 0` at the optimum); after
    /// [`Assembly::fold`], which drops and merges rows, they are the folded rows'.
    pub(crate) duals: Vec<f64>,
    pub(crate) status: QpStatus,
    pub(crate) objective: f64,
    pub(crate) info: SolveInfo,
}

/// Screening of the rows `±(τ + gᵀδ) ≤ t` of a minimax step (the refinement's linearised step,
/// the whole manoeuvre's subproblems): given
/// each sample's `(τ, r)`, where `r = Σ|g_k| Δ` bounds `|gᵀδ|` within the trust box
/// `|δ_k| ≤ Δ`, the optimal peak is at least `L = max (|τ| − r)`, and a side whose largest
/// value (`τ + r` for `+`, `r − τ` for `−`) is below `L` holds at every point with `t ≥ L`,
/// which the row attaining `L` enforces. The sides `[+, −]` that can be active: leaving the
/// others out changes neither the feasible set nor the step. Exact, and it makes the late,
/// small-radius steps cheap.
pub(crate) fn active_sides(spans: &[(f64, f64)]) -> Vec<[bool; 2]> {
    let floor = spans.iter().map(|(tau, r)| tau.abs() - r).fold(f64::NEG_INFINITY, f64::max);
    spans.iter().map(|(tau, r)| [tau + r >= floor, r - tau >= floor]).collect()
}
