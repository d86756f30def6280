//! A QP whose only binding inequalities are bounds on single variables, solved by its KKT
//! system on an active set of bounds.
//!
//! With a set `B` of variables held at one of their bounds and the rest `F` free, the optimum
//! of `min ½xᵀPx + qᵀx` s.t. `A_e x = b_e`, `P` positive definite, is the solution of
//!
//! $$ \begin{pmatrix} P_{FF} & A_{eF}ᵀ \\ A_{eF} & 0 \end{pmatrix}
//!    \begin{pmatrix} x_F \\ z \end{pmatrix}
//!    = \begin{pmatrix} −q_F − P_{FB} x_B \\ b_e − A_{eB} x_B \end{pmatrix}, $$
//!
//! solved with `P_FF = LLᵀ` (Cholesky) and the Schur complement `A_{eF} P_{FF}⁻¹ A_{eF}ᵀ` (LU),
//! refined once on its own residual. The set is chosen by the primal–dual active-set rule
//! (Hintermüller, Ito & Kunisch): a free variable beyond a bound is held there, a held one whose
//! multiplier has the wrong sign is freed, until neither happens. The point then meets the
//! whole QP's KKT conditions (primal feasibility of every row, the bounds' multipliers of the
//! right sign, complementarity by construction): it is the QP's optimum, exactly. A QP with a
//! dense `P` (the whole manoeuvre's energy step with its BFGS curvature, 464 variables on a cat
//! with a tail) costs Clarabel's interior-point method one dense factorisation per iteration,
//! often twice over with its iterative refinement; this costs one per active set, and the first
//! is usually the last.
//!
//! ## References
//! - M. Hintermüller, K. Ito, K. Kunisch, *The primal–dual active set strategy as a semismooth
//!   Newton method*, SIAM J. Optim. 13 (2003) 865–888.

use std::collections::{HashMap, HashSet};
use std::time::Instant;

use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

use super::{Assembly, Rows, Solved};
use crate::optimize::conic::solution::{QpStatus, SolveInfo};

/// Most active sets tried before the QP is left to Clarabel.
const MAX_SETS: usize = 40;

/// Largest residual of an answer's equalities and stationarity, relative to the data's size.
const ACCURACY: f64 = 1e-10;

/// A variable's tightest bounds, the lower and the upper one, when it has any.
#[derive(Clone, Copy, Default)]
struct Bounds {
    lower: Option<Bound>,
    upper: Option<Bound>,
}

impl Bounds {
    /// The bound a variable `held` so sits at; none when it is free.
    fn at(&self, held: Held) -> Option<Bound> {
        match held {
            Held::Lower => self.lower,
            Held::Upper => self.upper,
            Held::Free => None,
        }
    }
}

/// One bound `x_v ≤ value` (or `≥`) from the inequality row `row`, `coefficient · x_v ≤ rhs`.
#[derive(Clone, Copy)]
struct Bound {
    value: f64,
    row: usize,
    coefficient: f64,
}

/// Where a variable is: free, or held at its lower or upper bound.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Held {
    Free,
    Lower,
    Upper,
}

impl Assembly {
    /// The QP's optimum when the inequalities that bind there are bounds on single variables
    /// (module docs), with the equalities' multipliers first among the duals, then the
    /// inequalities' (zero but for the bound each held variable sits at: Clarabel's layout,
    /// [`Solved::duals`]); none when `P` is not positive definite, the equalities are
    /// dependent (or so nearly, with the held bounds, that the answer misses its own KKT
    /// conditions by more than [`ACCURACY`]), a row on several variables is violated, or no active
    /// set was found within [`MAX_SETS`], where only the whole QP can answer.
    pub(crate) fn solve_by_active_set(&self) -> Option<Solved> {
        let clock = Instant::now();
        let n = self.n;
        let bounds = bounds(&self.ineq, n)?;
        let mut kkt = Kkt::new(symmetric(&self.p, n), dense(&self.eq, n), &self.eq.rhs, &self.q)?;
        let mut held = vec![Held::Free; n];
        // The rule can cycle where `P` is far from diagonally dominant: a set seen before ends it.
        let mut seen = HashSet::new();
        while seen.len() < MAX_SETS && seen.insert(held.clone()) {
            let (x, z) = kkt.solve(&bounds, &held)?;
            // The objective's gradient with the equalities' multipliers: minus the bounds' share.
            let gradient = &kkt.p * &x + &kkt.q + kkt.a.transpose() * z.rows(0, kkt.a.nrows());
            let mut next = held.clone();
            for (v, b) in bounds.iter().enumerate() {
                next[v] = match held[v] {
                    Held::Free if b.lower.is_some_and(|l| x[v] < l.value) => Held::Lower,
                    Held::Free if b.upper.is_some_and(|u| x[v] > u.value) => Held::Upper,
                    // Held at its lower bound, the objective would go down going up: free it.
                    Held::Lower if gradient[v] < 0.0 => Held::Free,
                    Held::Upper if gradient[v] > 0.0 => Held::Free,
                    h => h,
                };
            }
            if next == held {
                let z = z.rows(0, kkt.a.nrows()).into_owned();
                return self.answer(&kkt, x, z, &bounds, &held, clock);
            }
            held = next;
        }
        None
    }

    /// The answer at `(x, z)` (`z` the equalities' multipliers) with the variables `held` moved
    /// onto their bounds exactly, when it meets the KKT conditions there: every inequality row,
    /// the equalities and stationarity to [`ACCURACY`], the bounds' multipliers (from the
    /// objective's gradient at the returned point, on the rows that hold them) of the right sign.
    fn answer(
        &self,
        kkt: &Kkt,
        mut x: DVector<f64>,
        z: DVector<f64>,
        bounds: &[Bounds],
        held: &[Held],
        clock: Instant,
    ) -> Option<Solved> {
        // Held variables onto their bounds exactly (the solve meets them to round-off): how far
        // each was counts as a residual of its equality.
        let mut moved: f64 = 0.0;
        for (v, b) in bounds.iter().enumerate() {
            if let Some(bound) = b.at(held[v]) {
                moved = moved.max((x[v] - bound.value).abs());
                x[v] = bound.value;
            }
        }
        let gradient = &kkt.p * &x + &kkt.q + kkt.a.transpose() * &z;
        let mut lhs = vec![0.0; self.ineq.len()];
        for ((&i, &j), &v) in self.ineq.row.iter().zip(&self.ineq.col).zip(&self.ineq.val) {
            lhs[i] += v * x[j];
        }
        let mut duals = z.as_slice().to_vec();
        duals.resize(self.eq.len() + self.ineq.len(), 0.0);
        let mut holding = vec![false; self.ineq.len()];
        for (v, b) in bounds.iter().enumerate() {
            if let Some(Bound { row, coefficient, .. }) = b.at(held[v]) {
                // Px + q + Aᵀz = 0 on the variable: its row's coefficient times z = −gradient.
                duals[self.eq.len() + row] = -gradient[v] / coefficient;
                holding[row] = true;
                if duals[self.eq.len() + row] < -ACCURACY * (1.0 + kkt.q.amax()) {
                    return None;
                }
            }
        }
        // A held variable sits on its row exactly; every other row must hold as it is.
        if lhs.iter().zip(&self.ineq.rhs).zip(&holding).any(|((l, r), &h)| !h && l > r) {
            return None;
        }
        let objective = 0.5 * x.dot(&(&kkt.p * &x)) + kkt.q.dot(&x);
        let primal = (&kkt.b - &kkt.a * &x).amax().max(moved);
        let dual = (0..self.n).filter(|&v| held[v] == Held::Free).map(|v| gradient[v].abs()).fold(0.0, f64::max);
        // Near-dependent equalities (held bounds that all but fix a row) leave a Schur complement
        // that solves to noise: the answer must meet its own KKT conditions.
        let (rhs, pull) = (kkt.b.amax(), kkt.q.amax().max((&kkt.p * &x).amax()));
        if !(primal <= ACCURACY * (1.0 + rhs) && dual <= ACCURACY * (1.0 + pull)) {
            return None;
        }
        Some(Solved {
            x: x.as_slice().to_vec(),
            duals,
            status: QpStatus::Solved,
            objective,
            info: SolveInfo {
                iterations: 0,
                solve_time_s: clock.elapsed().as_secs_f64(),
                primal_residual: primal,
                dual_residual: dual,
                duality_gap: 0.0,
                relative_gap: 0.0,
            },
        })
    }
}

/// The equality-constrained QP with `P` factored once: each active set adds its held variables
/// as equalities `x_v = bound`, whose columns of `P⁻¹` are kept from one set to the next.
struct Kkt {
    p: DMatrix<f64>,
    a: DMatrix<f64>,
    b: DVector<f64>,
    q: DVector<f64>,
    cholesky: Cholesky<f64, Dyn>,
    /// `P⁻¹q` and `P⁻¹A_eᵀ`.
    p_inv_q: DVector<f64>,
    p_inv_at: DMatrix<f64>,
    /// `P⁻¹e_v` of the variables held so far.
    columns: HashMap<usize, DVector<f64>>,
}

impl Kkt {
    /// `P` factored; none when it is not positive definite.
    fn new(p: DMatrix<f64>, a: DMatrix<f64>, b: &[f64], q: &[f64]) -> Option<Kkt> {
        let cholesky = p.clone().cholesky()?;
        let q = DVector::from_column_slice(q);
        let p_inv_q = cholesky.solve(&q);
        let p_inv_at = cholesky.solve(&a.transpose());
        Some(Kkt { p, a, b: DVector::from_column_slice(b), q, cholesky, p_inv_q, p_inv_at, columns: HashMap::new() })
    }

    /// The solution `x` and the multipliers `z` (the equalities', then each held variable's in
    /// the order of the variables) with the variables `held` at their bounds: `x = −P⁻¹(q + Eᵀz)`
    /// and `Ex = d`, `E` the equalities and the held variables' rows, by the Schur complement
    /// `EP⁻¹Eᵀ`, refined once on the residual.
    fn solve(&mut self, bounds: &[Bounds], held: &[Held]) -> Option<(DVector<f64>, DVector<f64>)> {
        let n = self.p.nrows();
        let rows: Vec<(usize, f64)> = (0..n).filter_map(|v| bounds[v].at(held[v]).map(|b| (v, b.value))).collect();
        for &(v, _) in &rows {
            if !self.columns.contains_key(&v) {
                let mut e = DVector::zeros(n);
                e[v] = 1.0;
                self.columns.insert(v, self.cholesky.solve(&e));
            }
        }
        let m = self.a.nrows();
        let k = m + rows.len();
        // P⁻¹Eᵀ, E and d.
        let mut w = DMatrix::zeros(n, k);
        w.columns_mut(0, m).copy_from(&self.p_inv_at);
        let mut d = DVector::zeros(k);
        d.rows_mut(0, m).copy_from(&self.b);
        for (i, &(v, value)) in rows.iter().enumerate() {
            w.set_column(m + i, &self.columns[&v]);
            d[m + i] = value;
        }
        // E y for a vector y: the equalities' rows, then the held entries.
        let apply = |y: &DVector<f64>| -> DVector<f64> {
            let mut out = DVector::zeros(k);
            out.rows_mut(0, m).copy_from(&(&self.a * y));
            for (i, &(v, _)) in rows.iter().enumerate() {
                out[m + i] = y[v];
            }
            out
        };
        let mut schur = DMatrix::zeros(k, k);
        for c in 0..k {
            schur.set_column(c, &apply(&w.column(c).into_owned()));
        }
        let schur = schur.lu();
        // x = P⁻¹r − P⁻¹Eᵀz with E x = s: z = S⁻¹(E P⁻¹r − s).
        let solve = |p_inv_r: DVector<f64>, s: &DVector<f64>| -> Option<(DVector<f64>, DVector<f64>)> {
            let z = if k == 0 { DVector::zeros(0) } else { schur.solve(&(apply(&p_inv_r) - s))? };
            Some((p_inv_r - &w * &z, z))
        };
        let (mut x, mut z) = solve(-&self.p_inv_q, &d)?;
        // One refinement on the KKT residual (r, s) = (−q − Eᵀz − Px, d − Ex).
        let mut et_z = self.a.transpose() * z.rows(0, m);
        for (i, &(v, _)) in rows.iter().enumerate() {
            et_z[v] += z[m + i];
        }
        let r = -&self.q - et_z - &self.p * &x;
        let (dx, dz) = solve(self.cholesky.solve(&r), &(&d - apply(&x)))?;
        x += dx;
        z += dz;
        x.iter().chain(z.iter()).all(|v| v.is_finite()).then_some((x, z))
    }
}

/// `P` from its upper triangle's entries (repeated entries summed).
fn symmetric(rows: &Rows, n: usize) -> DMatrix<f64> {
    let mut p = DMatrix::zeros(n, n);
    for ((&i, &j), &v) in rows.row.iter().zip(&rows.col).zip(&rows.val) {
        p[(i, j)] += v;
        if i != j {
            p[(j, i)] += v;
        }
    }
    p
}

/// The rows `rows` as a dense matrix over `n` variables (repeated entries summed).
fn dense(rows: &Rows, n: usize) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(rows.len(), n);
    for ((&i, &j), &v) in rows.row.iter().zip(&rows.col).zip(&rows.val) {
        m[(i, j)] += v;
    }
    m
}

/// Each variable's tightest bounds among the inequality rows on it alone (`c·x_v ≤ r`); none
/// when a bound cannot be met (a lower one above an upper one).
fn bounds(ineq: &Rows, n: usize) -> Option<Vec<Bounds>> {
    let mut bounds = vec![Bounds::default(); n];
    let mut start = 0;
    for (row, &rhs) in ineq.rhs.iter().enumerate() {
        let end = start + ineq.row[start..].iter().take_while(|&&r| r == row).count();
        if let [e] = (start..end).collect::<Vec<_>>()[..] {
            let (v, c) = (ineq.col[e], ineq.val[e]);
            let (b, bound) = (&mut bounds[v], Bound { value: rhs / c, row, coefficient: c });
            if c > 0.0 && b.upper.is_none_or(|u| bound.value < u.value) {
                b.upper = Some(bound);
            } else if c < 0.0 && b.lower.is_none_or(|l| bound.value > l.value) {
                b.lower = Some(bound);
            }
        }
        start = end;
    }
    let consistent = bounds.iter().all(|b| match (b.lower, b.upper) {
        (Some(l), Some(u)) => l.value <= u.value,
        _ => true,
    });
    consistent.then_some(bounds)
}

#[cfg(test)]
mod tests {
    use nalgebra::DVector;
    use proptest::prelude::*;

    use super::super::{Assembly, Solved};
    use crate::optimize::conic::QpSettings;

    /// `min ½|M x|² + ½ρ|x|² + qᵀx` (`M` with `n` columns, `ρ = 0.1`) with the equalities
    /// `eq` (coefficients on the first variables, right-hand side), the box `|x_v| ≤ radius`
    /// and one row on the first two variables, `x₀ + x₁ ≤ cap`.
    struct Qp<'a> {
        m: &'a [f64],
        q: &'a [f64],
        eq: &'a [(Vec<f64>, f64)],
        radius: f64,
        cap: f64,
    }

    impl Qp<'_> {
        fn assembly(&self) -> Assembly {
            let n = self.q.len();
            let mut asm = Assembly::new(n);
            for row in self.m.chunks(n) {
                asm.square_cost(&row.iter().copied().enumerate().collect::<Vec<_>>(), 0.5);
            }
            asm.identity_cost(n, 0.1);
            for (v, &c) in self.q.iter().enumerate() {
                asm.linear_cost(v, c);
            }
            for (coefficients, rhs) in self.eq {
                asm.equal(coefficients.iter().copied().enumerate(), *rhs);
            }
            for v in 0..n {
                asm.between(&[(v, 1.0)], -self.radius, self.radius);
            }
            asm.at_most([(0, 1.0), (1, 1.0)], self.cap);
            asm
        }

        /// The largest violation of the KKT conditions at `s` ([`kkt_violation`]).
        fn kkt_violation(&self, s: &Solved) -> f64 {
            kkt_violation(&self.assembly(), s)
        }
    }

    /// The largest violation of the KKT conditions of `asm` at `s` (its point and multipliers,
    /// rows in the assembly's order, Clarabel's signs): stationarity `Px + q + Aᵀz = 0`, the
    /// equalities, the inequalities `a·x ≤ b`, their multipliers' signs, complementarity.
    fn kkt_violation(asm: &Assembly, s: &Solved) -> f64 {
        let n = asm.n;
        let p = super::symmetric(&asm.p, n);
        let x = DVector::from_column_slice(&s.x);
        let mut stationarity = &p * &x + DVector::from_column_slice(&asm.q);
        let mut worst: f64 = 0.0;
        for (rows, offset, inequality) in [(&asm.eq, 0, false), (&asm.ineq, asm.eq.len(), true)] {
            let mut lhs = vec![0.0; rows.len()];
            for ((&i, &j), &v) in rows.row.iter().zip(&rows.col).zip(&rows.val) {
                lhs[i] += v * x[j];
                stationarity[j] += v * s.duals[offset + i];
            }
            for (i, (l, r)) in lhs.iter().zip(&rows.rhs).enumerate() {
                let (z, slack) = (s.duals[offset + i], r - l);
                worst =
                    if inequality { worst.max(-slack).max(-z).max((z * slack).abs()) } else { worst.max(slack.abs()) };
            }
        }
        worst.max(stationarity.amax())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Whatever binds, an answer meets the QP's KKT conditions to round-off, and Clarabel
        /// finds the same objective to its own tolerance (1e-8 on the gap: the point itself
        /// only to about 1e-6).
        #[test]
        fn an_answer_is_the_qps_optimum(
            m in proptest::collection::vec(-1.0f64..1.0, 6 * 8),
            q in proptest::collection::vec(-2.0f64..2.0, 8),
            eq in proptest::collection::vec((proptest::collection::vec(-1.0f64..1.0, 8), -0.5f64..0.5), 0..3),
            radius in 0.05f64..2.0,
        ) {
            let qp = Qp { m: &m, q: &q, eq: &eq, radius, cap: 100.0 };
            let Some(direct) = qp.assembly().solve_by_active_set() else {
                // A box that cannot meet the equalities, or a set the rule did not settle.
                return Ok(());
            };
            prop_assert!(qp.kkt_violation(&direct) < 1e-10, "KKT violated by {}", qp.kkt_violation(&direct));
            let clarabel = qp.assembly().solve(&QpSettings::default()).expect("a QP");
            prop_assert!(clarabel.status.is_solved());
            prop_assert!((direct.objective - clarabel.objective).abs() < 1e-7 * (1.0 + clarabel.objective.abs()));
        }
    }

    /// The box binds at the unconstrained minimiser, which lies far outside it: the bounds'
    /// active set is found (`P` diagonally dominant, where the rule settles), and it is an
    /// optimum.
    #[test]
    fn a_binding_box_is_found() {
        let n = 6;
        let m: Vec<f64> =
            (0..n * n).map(|k| if k % (n + 1) == 0 { 1.0 } else { 0.05 * ((k * 7 % 5) as f64 - 2.0) }).collect();
        let q = [3.0, -2.0, 1.5, 0.2, -0.1, 4.0];
        let eq = [(vec![1.0; 6], 0.3)];
        let qp = Qp { m: &m, q: &q, eq: &eq, radius: 0.5, cap: 100.0 };
        let direct = qp.assembly().solve_by_active_set().expect("bounds only bind");
        let held = direct.x.iter().filter(|x| (x.abs() - 0.5).abs() < 1e-12).count();
        assert!(held >= 2, "{:?}", direct.x);
        assert!(qp.kkt_violation(&direct) < 1e-10, "KKT violated by {}", qp.kkt_violation(&direct));
    }

    /// A box that all but fixes an equality's variables (the first row can reach its 0.228 only
    /// with every variable near its bound of 0.096): with those bounds held the Schur complement
    /// is nearly singular and solved to noise (a KKT residual of 1e12, found by the property test
    /// above); such an answer is refused, or it is the optimum.
    #[test]
    fn nearly_dependent_equalities_give_the_optimum_or_none() {
        let m = [
            0.6244389311289258,
            -0.5866354173075581,
            -0.6018158209521731,
            0.14762009522453462,
            -0.7544645031945024,
            -0.6639483201855283,
            0.7862167266743489,
            -0.03611668759658208,
            0.0,
            0.9543407355367991,
            0.030851984549858377,
            -0.2145681408616859,
            0.5805587678799653,
            0.818268062376138,
            0.1049822896552421,
            0.0,
            -0.1306832419225893,
            -0.6814679502691284,
            0.761189738366684,
            -0.7541759864224975,
            0.9923451787525738,
            -0.7781422158084695,
            -0.4381361675156497,
            -0.5988336634584611,
            -0.12768155456005606,
            -0.6102666358750839,
            -0.35572352064758184,
            0.8890543044888217,
            0.010575651843480657,
            -0.6321147359630183,
            0.5745455682124653,
            -0.8599169859247521,
            -0.022428487236407856,
            0.32755285696118247,
            0.11111752066629968,
            0.3558507626384388,
            0.6527192503325929,
            0.6253170630013729,
            -0.36738507042280577,
            0.9460343081103777,
            -0.006449367817249321,
            -0.41288721976203213,
            0.019422694195146882,
            0.39223252564448935,
            0.08413680715073382,
            0.2704869820348091,
            -0.2583583916278204,
            0.5083114298326835,
        ];
        let q = [0.0, -0.0897770880618255, -0.6736672767833177, 0.0, 0.0, -0.9126628186739661, 0.0, 0.8729876075793155];
        let eq = [
            (
                vec![
                    0.0,
                    0.9292992341704338,
                    0.29924335948921615,
                    0.0,
                    -0.4748046740765005,
                    0.0,
                    -0.900869191963746,
                    0.0,
                ],
                0.22825865230328324,
            ),
            (
                vec![
                    0.808362267900333,
                    -0.13357087220489744,
                    -0.29984819668554613,
                    0.9771555856964226,
                    0.9698377419691194,
                    -0.7171982240189483,
                    -0.3780489300804093,
                    0.7060578254059281,
                ],
                0.3414233702076676,
            ),
        ];
        let qp = Qp { m: &m, q: &q, eq: &eq, radius: 0.09633688712510412, cap: 100.0 };
        if let Some(direct) = qp.assembly().solve_by_active_set() {
            assert!(qp.kkt_violation(&direct) < 1e-10, "KKT violated by {}", qp.kkt_violation(&direct));
        }
    }

    /// Bounds written with any coefficient, on one side only, and repeated (a looser row beside
    /// the tightest): the multipliers land on the rows that hold, scaled by their coefficients.
    #[test]
    fn bounds_of_any_coefficient_and_repeats_are_held_on_their_tightest_row() {
        let mut asm = Assembly::new(3);
        asm.identity_cost(3, 1.0);
        for (v, c) in [(0, -2.0), (1, 1.0), (2, 0.5)] {
            asm.linear_cost(v, c);
        }
        // x₀ ≤ 0.3 written 2x₀ ≤ 0.6, and x₀ ≤ 0.5 beside it; x₁ ≥ −0.2 written −0.5x₁ ≤ 0.1;
        // x₂ free of bounds.
        asm.at_most([(0, 2.0)], 0.6);
        asm.at_most([(0, 1.0)], 0.5);
        asm.at_most([(1, -0.5)], 0.1);
        asm.equal([(0, 1.0), (1, 1.0), (2, 1.0)], 0.0);
        let s = asm.solve_by_active_set().expect("bounds only");
        assert!(kkt_violation(&asm, &s) < 1e-12, "KKT violated by {}", kkt_violation(&asm, &s));
        assert_eq!((s.x[0], s.x[1]), (0.3, -0.2), "both held at their bounds");
        assert!(s.duals[1] > 0.0 && s.duals[2] == 0.0 && s.duals[3] > 0.0, "{:?}", s.duals);
    }

    /// A row on several variables that binds, or a `P` that is not positive definite, is left to
    /// the whole QP.
    #[test]
    fn what_it_cannot_answer_it_leaves_to_clarabel() {
        let m: Vec<f64> = (0..16).map(|k| if k % 5 == 0 { 1.0 } else { 0.0 }).collect();
        let q = [-1.0, -1.0, 0.0, 0.0];
        // Unconstrained x = (0.91, 0.91, 0, 0): x₀ + x₁ ≤ 1 binds; ≤ 3 does not.
        assert!(Qp { m: &m, q: &q, eq: &[], radius: 2.0, cap: 1.0 }.assembly().solve_by_active_set().is_none());
        assert!(Qp { m: &m, q: &q, eq: &[], radius: 2.0, cap: 3.0 }.assembly().solve_by_active_set().is_some());
        let mut flat = Assembly::new(2);
        flat.linear_cost(0, 1.0);
        flat.between(&[(0, 1.0)], -1.0, 1.0);
        assert!(flat.solve_by_active_set().is_none(), "P = 0");
    }
}
