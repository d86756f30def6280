//! The retiming program in Clarabel's standard form, `A x + s = b`, `s ∈ {0}^{m₁} × ℝ₊^{m₂} ×
//! SOC(3)^{m₃}`, built from triplets, and the call to Clarabel.
//!
//! Variables (normalised, module docs): the peak `c` first, then per piece with `N` intervals
//! the node values `X_0…X_N` (`x = v² X`, `v = S/T`), `Y_0…Y_N` (`Y ≤ √X`), the interval values
//! `U_0…U_{N−1}` (`u = U v²/S`) and `W_0…W_{N−1}` (`W ≥ 2/(Y_k + Y_{k+1})`, time per unit of `σ`).

use clarabel::algebra::CscMatrix;
use clarabel::solver::SupportedConeT;

use super::problemdata::{PathPiece, PathProblem, Scales};
use super::solution::{RawSolution, RetimeSolution};
use super::RetimeError;
use crate::optimize::conic::{from_triplets, solve_clarabel, Rows};

/// Column indices of one piece's variables.
#[derive(Clone, Copy)]
struct Columns {
    base: usize,
    n: usize,
}

impl Columns {
    fn x(self, k: usize) -> usize {
        self.base + k
    }
    fn y(self, k: usize) -> usize {
        self.base + self.n + 1 + k
    }
    fn u(self, k: usize) -> usize {
        self.base + 2 * (self.n + 1) + k
    }
    fn w(self, k: usize) -> usize {
        self.base + 2 * (self.n + 1) + self.n + k
    }
    fn width(n: usize) -> usize {
        4 * n + 2
    }
}

impl PathProblem {
    /// Solves with Clarabel. A solve that ends without a solution is not an error: its status
    /// says how it ended.
    pub fn solve(&self) -> Result<RetimeSolution, RetimeError> {
        self.validate()?;
        solve(self)
    }
}

/// Builds the program of `problem` and solves it.
pub(crate) fn solve(problem: &PathProblem) -> Result<RetimeSolution, RetimeError> {
    let sc = Scales::new(problem);
    let v2 = sc.speed * sc.speed;
    let mut columns = Vec::with_capacity(problem.pieces.len());
    let mut n_vars = 1;
    for p in &problem.pieces {
        columns.push(Columns { base: n_vars, n: p.intervals() });
        n_vars += Columns::width(p.intervals());
    }
    let (mut eq, mut ineq, mut soc) = (Rows::default(), Rows::default(), Rows::default());
    let peak = 0;
    let junctions = problem.junctions();
    for (i, (p, &col)) in problem.pieces.iter().zip(&columns).enumerate() {
        let rest = [junctions[i].rest_after, junctions[i + 1].rest_before];
        add_piece(p, col, rest, &sc, &mut eq, &mut ineq, &mut soc);
        if let Some(r) = problem.settings.rate_limit {
            for k in 0..=col.n {
                ineq.push_nonzero([(col.x(k), 1.0)], r * r / v2);
            }
        }
        if let Some(a) = problem.settings.accel_limit {
            let bound = a * sc.length / v2;
            for k in 0..col.n {
                ineq.push_nonzero([(col.u(k), 1.0)], bound);
                ineq.push_nonzero([(col.u(k), -1.0)], bound);
            }
        }
    }
    // Boundary conditions at the junctions.
    for (j, junction) in junctions.iter().enumerate() {
        let before = (j > 0).then(|| (columns[j - 1], columns[j - 1].n));
        let after = (j < columns.len()).then(|| (columns[j], 0));
        if let (Some((cb, kb)), Some((ca, ka)), Some((tb, ta))) = (before, after, junction.continuous) {
            let m = tb.max(ta);
            eq.push_nonzero([(ca.x(ka), ta / m), (cb.x(kb), -tb / m)], 0.0);
        }
        for (node, rest) in [(before, junction.rest_before), (after, junction.rest_after)] {
            if let (Some((c, k)), true) = (node, rest) {
                eq.push_nonzero([(c.x(k), 1.0)], 0.0);
                eq.push_nonzero([(c.y(k), 1.0)], 0.0);
            }
        }
    }
    // Durations: Σ Δσ W ≤ T_group / T.
    let total = sc.length;
    let duration_row = |p: &PathPiece, c: Columns| {
        let widths: Vec<f64> = (0..c.n).map(|k| p.spacing(k) / total).collect();
        (0..c.n).map(move |k| (c.w(k), widths[k]))
    };
    match problem.piece_targets() {
        Some(targets) => {
            for ((p, &c), t) in problem.pieces.iter().zip(&columns).zip(targets) {
                ineq.push_nonzero(duration_row(p, c), t / problem.duration);
            }
        }
        None => ineq.push_nonzero(problem.pieces.iter().zip(&columns).flat_map(|(p, &c)| duration_row(p, c)), 1.0),
    }

    let mut q = vec![0.0; n_vars];
    q[peak] = 1.0;
    let raw = clarabel_solve(n_vars, &q, eq, ineq, soc, problem)?;
    Ok(RetimeSolution::new(problem, &sc, &columns.iter().map(|c| (c.base, c.n)).collect::<Vec<_>>(), raw))
}

/// The rows of one piece: the dynamics `X_{k+1} − X_k = 2 Δσ U_k`, the torque bounds at both
/// ends of every interval, and the two cones per node and interval. A node at rest (`rest`: the
/// first, the last) has `X = Y = 0` as equalities instead of its cone and `Y ≥ 0`, which would
/// pin the slack to the cone's boundary and leave Clarabel without an interior.
fn add_piece(p: &PathPiece, c: Columns, rest: [bool; 2], sc: &Scales, eq: &mut Rows, ineq: &mut Rows, soc: &mut Rows) {
    let v2 = sc.speed * sc.speed;
    for k in 0..c.n {
        let dsigma = p.spacing(k) / sc.length;
        eq.push_nonzero([(c.x(k + 1), 1.0), (c.x(k), -1.0), (c.u(k), -2.0 * dsigma)], 0.0);
        // the torque at node e, and at the midpoint where x = (x_k + x_{k+1})/2
        let mid = p.midpoints.as_ref().map(|m| (&m[k], [(c.x(k), 0.5), (c.x(k + 1), 0.5)]));
        let ends = [k, k + 1].map(|e| (&p.nodes[e], [(c.x(e), 1.0), (c.x(e), 0.0)]));
        for (node, x) in ends.into_iter().chain(mid) {
            for j in 0..2 {
                let a = node.a[j] * v2 / (sc.length * sc.torque);
                let b = node.b[j] * v2 / sc.torque;
                if a == 0.0 && b == 0.0 {
                    continue;
                }
                for sign in [1.0, -1.0] {
                    let xs = x.map(|(col, w)| (col, sign * b * w));
                    ineq.push_nonzero([(c.u(k), sign * a), xs[0], xs[1], (0, -1.0)], 0.0);
                }
            }
        }
        // ‖(2√2, W − Y_k − Y_{k+1})‖ ≤ W + Y_k + Y_{k+1}
        soc.push_nonzero([(c.w(k), -1.0), (c.y(k), -1.0), (c.y(k + 1), -1.0)], 0.0);
        soc.push_nonzero([], 2.0 * std::f64::consts::SQRT_2);
        soc.push_nonzero([(c.w(k), -1.0), (c.y(k), 1.0), (c.y(k + 1), 1.0)], 0.0);
    }
    for k in 0..=c.n {
        if (k == 0 && rest[0]) || (k == c.n && rest[1]) {
            continue;
        }
        // ‖(2Y, X − 1)‖ ≤ X + 1, and Y ≥ 0.
        soc.push_nonzero([(c.x(k), -1.0)], 1.0);
        soc.push_nonzero([(c.y(k), -2.0)], 0.0);
        soc.push_nonzero([(c.x(k), -1.0)], -1.0);
        ineq.push_nonzero([(c.y(k), -1.0)], 0.0);
    }
}

/// Joins the rows and runs Clarabel; returns its iterate and account, whatever the status.
fn clarabel_solve(
    n: usize,
    q: &[f64],
    eq: Rows,
    ineq: Rows,
    soc: Rows,
    problem: &PathProblem,
) -> Result<RawSolution, RetimeError> {
    let (m_eq, m_ineq, m_soc) = (eq.len(), ineq.len(), soc.len());
    let (mut row, mut col, mut val, mut b) = (eq.row, eq.col, eq.val, eq.rhs);
    row.extend(ineq.row.iter().map(|r| r + m_eq));
    row.extend(soc.row.iter().map(|r| r + m_eq + m_ineq));
    col.extend(ineq.col.iter().chain(&soc.col));
    val.extend(ineq.val.iter().chain(&soc.val));
    b.extend(ineq.rhs.iter().chain(&soc.rhs));
    let a = from_triplets(m_eq + m_ineq + m_soc, n, &row, &col, &val);
    let p = CscMatrix::zeros((n, n));
    let mut cones = Vec::with_capacity(2 + m_soc / 3);
    if m_eq > 0 {
        cones.push(SupportedConeT::ZeroConeT(m_eq));
    }
    if m_ineq > 0 {
        cones.push(SupportedConeT::NonnegativeConeT(m_ineq));
    }
    cones.extend((0..m_soc / 3).map(|_| SupportedConeT::SecondOrderConeT(3)));
    let (solver, solve_time) = solve_clarabel(&problem.settings.solver, &p, q, &a, &b, &cones)?;
    let (sol, info) = (&solver.solution, &solver.info);
    Ok(RawSolution {
        x: sol.x.clone(),
        status: sol.status.into(),
        iterations: sol.iterations,
        primal_objective: info.cost_primal,
        dual_objective: info.cost_dual,
        primal_residual: sol.r_prim,
        dual_residual: sol.r_dual,
        solve_time_s: solve_time,
    })
}
