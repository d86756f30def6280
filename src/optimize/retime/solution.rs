//! What a retiming returns: how the solve ended, the peak and its certified lower bound, and the
//! timing of every piece (`x = ṡ²` at the nodes, `u = s̈` per interval, the node times).

use serde::Serialize;

use super::problemdata::{PathNode, PathPiece, PathProblem, Scales};
use crate::optimize::conic::QpStatus;

/// How the retiming's solve ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RetimeStatus {
    /// Solved to the requested tolerances.
    Solved,
    /// Solved to Clarabel's reduced tolerances.
    AlmostSolved,
    /// No timing meets the constraints (e.g. a rate limit too low for the duration); Clarabel
    /// holds a certificate.
    Infeasible,
    /// Clarabel stopped without a solution or certificate, for the reason given.
    Stopped(QpStatus),
}

impl From<QpStatus> for RetimeStatus {
    fn from(s: QpStatus) -> Self {
        match s {
            QpStatus::Solved => RetimeStatus::Solved,
            QpStatus::AlmostSolved => RetimeStatus::AlmostSolved,
            QpStatus::PrimalInfeasible | QpStatus::AlmostPrimalInfeasible => RetimeStatus::Infeasible,
            other => RetimeStatus::Stopped(other),
        }
    }
}

impl std::fmt::Display for RetimeStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RetimeStatus::Solved => write!(f, "solved"),
            RetimeStatus::AlmostSolved => write!(f, "almost solved (reduced tolerances)"),
            RetimeStatus::Infeasible => write!(f, "infeasible: no timing meets the constraints"),
            RetimeStatus::Stopped(s) => write!(f, "not solved: Clarabel stopped with {s:?}"),
        }
    }
}

impl RetimeStatus {
    /// Whether the solution exists, to full or reduced accuracy.
    pub fn is_solved(self) -> bool {
        matches!(self, RetimeStatus::Solved | RetimeStatus::AlmostSolved)
    }
}

/// The timing of one piece: `s(t)` with `s̈` constant on every grid interval.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PieceTiming {
    /// The nodes' path parameters `s_k`, from 0 to the piece's extent `S`.
    pub grid: Vec<f64>,
    /// `x_k = ṡ²` at the nodes.
    pub speed_squared: Vec<f64>,
    /// `u_k = s̈` on interval `k`, `(x_{k+1} − x_k)/(2Δs_k)`.
    pub accel: Vec<f64>,
    /// Local time of each node, s: `t_0 = 0`, `t_{k+1} = t_k + 2Δs_k/(√x_k + √x_{k+1})`.
    pub times: Vec<f64>,
}

impl PieceTiming {
    /// The timing of node values `x` on `grid` (clamped at zero; `u` and the times follow from
    /// them, so the timing is consistent whatever the solver's residuals).
    /// `grid` and `x` have one value per node.
    pub fn from_speed_squared(grid: Vec<f64>, x: &[f64]) -> PieceTiming {
        let x: Vec<f64> = x.iter().map(|v| v.max(0.0)).collect();
        let h: Vec<f64> = grid.windows(2).map(|g| g[1] - g[0]).collect();
        let accel = x.windows(2).zip(&h).map(|(w, h)| (w[1] - w[0]) / (2.0 * h)).collect();
        let mut times = Vec::with_capacity(x.len());
        times.push(0.0);
        for (w, h) in x.windows(2).zip(&h) {
            let t = times[times.len() - 1] + 2.0 * h / (w[0].sqrt() + w[1].sqrt());
            times.push(t);
        }
        PieceTiming { grid, speed_squared: x, accel, times }
    }

    /// Duration of the piece, s.
    pub fn duration(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// The same motion slowed by the factor `1/λ` in time: `x λ²`, `u λ²`, times `/λ`.
    fn slowed(&self, lambda: f64) -> PieceTiming {
        let l2 = lambda * lambda;
        PieceTiming {
            grid: self.grid.clone(),
            speed_squared: self.speed_squared.iter().map(|x| x * l2).collect(),
            accel: self.accel.iter().map(|u| u * l2).collect(),
            times: self.times.iter().map(|t| t / lambda).collect(),
        }
    }

    /// `(s, ṡ, s̈)` at local time `t` (clamped to the piece): on interval `k`,
    /// `s = s_k + ṡ_k τ + u_k τ²/2`, `τ = t − t_k`. At a node, the later interval's.
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        self.on_interval(t, |times, t| times.partition_point(|&tk| tk <= t))
    }

    /// As [`PieceTiming::at`], but at a node the earlier interval's: the left limit (`s̈` jumps
    /// at the nodes; `s` and `ṡ` do not).
    pub fn at_before(&self, t: f64) -> (f64, f64, f64) {
        self.on_interval(t, |times, t| times.partition_point(|&tk| tk < t))
    }

    /// The inner nodes' local times, s: where `s̈` may jump.
    pub fn inner_node_times(&self) -> &[f64] {
        let n = self.times.len();
        if n < 3 {
            &[]
        } else {
            &self.times[1..n - 1]
        }
    }

    /// `(s, ṡ, s̈)` on the interval `after(times, t) − 1` (clamped to the intervals).
    fn on_interval(&self, t: f64, after: impl Fn(&[f64], f64) -> usize) -> (f64, f64, f64) {
        let Some(last) = self.accel.len().checked_sub(1) else {
            return (0.0, 0.0, 0.0); // no interval: nothing moves
        };
        let t = t.clamp(0.0, self.duration());
        let k = after(&self.times, t).saturating_sub(1).min(last);
        let tau = t - self.times[k];
        let (v, u) = (self.speed_squared[k].sqrt(), self.accel[k]);
        let s = (self.grid[k] + v * tau + 0.5 * u * tau * tau).clamp(self.grid[k], self.grid[k + 1]);
        (s, (v + u * tau).max(0.0), u)
    }
}

/// Clarabel's answer in the normalised variables.
pub(crate) struct RawSolution {
    pub(crate) x: Vec<f64>,
    pub(crate) status: QpStatus,
    pub(crate) iterations: u32,
    pub(crate) primal_objective: f64,
    pub(crate) dual_objective: f64,
    pub(crate) primal_residual: f64,
    pub(crate) dual_residual: f64,
    pub(crate) solve_time_s: f64,
}

/// The solution of a [`PathProblem`]. Unless the status [`RetimeStatus::is_solved`], the peak,
/// bound and gap are NaN and there are no timings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RetimeSolution {
    /// How the solve ended.
    pub status: RetimeStatus,
    /// Interior-point iterations.
    pub iterations: u32,
    /// The program's primal objective: the peak `|τ|` at the grid nodes, N·m.
    pub peak: f64,
    /// The dual objective: a certified lower bound on the discrete problem's optimum for this
    /// path (up to the dual residual), N·m.
    pub lower_bound: f64,
    /// `peak − lower_bound`, N·m.
    pub gap: f64,
    /// The peak of the program's torques (nodes and midpoints) for the timings below (at most `peak`: a piece with slack in its
    /// duration is slowed to fill it), N·m.
    pub discrete_peak: f64,
    /// Clarabel's relative primal residual (normalised program).
    pub primal_residual: f64,
    /// Clarabel's relative dual residual (normalised program).
    pub dual_residual: f64,
    /// Setup and solve time as Clarabel measured it, s.
    pub solve_time_s: f64,
    /// The timing of every piece.
    pub timings: Vec<PieceTiming>,
}

impl RetimeSolution {
    /// Reads the timings out of Clarabel's iterate (`columns`: each piece's first column and
    /// interval count) and slows every piece, or group of pieces joined by rate continuity, that
    /// finished early until it fills its duration.
    pub(crate) fn new(problem: &PathProblem, sc: &Scales, columns: &[(usize, usize)], raw: RawSolution) -> Self {
        let status = RetimeStatus::from(raw.status);
        let mut out = RetimeSolution {
            status,
            iterations: raw.iterations,
            peak: f64::NAN,
            lower_bound: f64::NAN,
            gap: f64::NAN,
            discrete_peak: f64::NAN,
            primal_residual: raw.primal_residual,
            dual_residual: raw.dual_residual,
            solve_time_s: raw.solve_time_s,
            timings: Vec::new(),
        };
        if !status.is_solved() {
            return out;
        }
        out.peak = raw.primal_objective * sc.torque;
        out.lower_bound = raw.dual_objective * sc.torque;
        out.gap = out.peak - out.lower_bound;
        let v2 = sc.speed * sc.speed;
        let timings: Vec<PieceTiming> = problem
            .pieces
            .iter()
            .zip(columns)
            .map(|(p, &(base, n))| {
                let x: Vec<f64> = raw.x[base..=base + n].iter().map(|v| v * v2).collect();
                PieceTiming::from_speed_squared(p.grid.clone(), &x)
            })
            .collect();
        out.timings = fill_durations(problem, timings);
        out.discrete_peak =
            problem.pieces.iter().zip(&out.timings).map(|(p, t)| sampled_peak(p, t)).fold(0.0, f64::max);
        out
    }

    /// The pieces' durations, s.
    pub fn durations(&self) -> Vec<f64> {
        self.timings.iter().map(PieceTiming::duration).collect()
    }
}

/// The peak `|a u_k + b x|` of a timing at the nodes and midpoints where the program bounds it.
fn sampled_peak(p: &PathPiece, t: &PieceTiming) -> f64 {
    let tau = |n: &PathNode, u: f64, x: f64| (0..2).map(|j| (n.a[j] * u + n.b[j] * x).abs()).fold(0.0, f64::max);
    let x = &t.speed_squared;
    (0..t.accel.len())
        .map(|k| {
            let u = t.accel[k];
            let ends = tau(&p.nodes[k], u, x[k]).max(tau(&p.nodes[k + 1], u, x[k + 1]));
            p.midpoints.as_ref().map_or(ends, |m| ends.max(tau(&m[k], u, 0.5 * (x[k] + x[k + 1]))))
        })
        .fold(0.0, f64::max)
}

/// Slows timings that finished early: with [`super::Split::Free`] all pieces together to the
/// total; with [`super::Split::Kept`] each group of pieces joined by rate continuity by the
/// largest factor that keeps every piece of the group within its target (a lone piece then
/// takes its target exactly). Slowing a motion by `1/λ` scales its torques by `λ² ≤ 1`.
fn fill_durations(problem: &PathProblem, timings: Vec<PieceTiming>) -> Vec<PieceTiming> {
    let junctions = problem.junctions();
    let n = timings.len();
    // groups: consecutive pieces joined by continuity
    let mut group = vec![0usize; n];
    for i in 1..n {
        group[i] = group[i - 1] + usize::from(junctions[i].continuous.is_none());
    }
    let lambda: Vec<f64> = match problem.piece_targets() {
        None => {
            let total: f64 = timings.iter().map(PieceTiming::duration).sum();
            vec![total / problem.duration; n]
        }
        Some(targets) => {
            let ratio: Vec<f64> = timings.iter().zip(&targets).map(|(t, target)| t.duration() / target).collect();
            (0..n).map(|i| (0..n).filter(|&m| group[m] == group[i]).map(|m| ratio[m]).fold(0.0, f64::max)).collect()
        }
    };
    timings.iter().zip(lambda).map(|(t, l)| if l > 0.0 && l.is_finite() { t.slowed(l) } else { t.clone() }).collect()
}
