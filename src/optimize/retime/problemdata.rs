//! The retiming program's data: the path sampled on its grid, and the boundary conditions its
//! tangents imply (module docs).

use serde::{Deserialize, Serialize};

use super::{bad, positive, RetimeError, RetimeSettings, Split};
use crate::engines::torque::ZeroMomentumTorques;
use crate::schedule::{JointState, Trajectory};

/// The path at one grid node: the coefficients of `τ = a s̈ + b ṡ²` and the tangent.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PathNode {
    /// `a = M(q) q'`, per joint, N·m per unit of `s̈` (N·m·s² when `s` is a time).
    pub a: [f64; 2],
    /// `b = M(q) q'' + c(q, q')`, per joint, N·m per unit of `ṡ²`.
    pub b: [f64; 2],
    /// `q' = dq/ds`, rad per unit of `s`: decides rest and continuity at the ends of a piece.
    pub tangent: [f64; 2],
}

/// One smooth piece of the path, sampled at `N + 1` nodes `0 = s_0 < s_1 < … < s_N = S`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PathPiece {
    /// Its extent `S` in the path parameter (for a trajectory piece, its original duration, s).
    pub length: f64,
    /// The nodes' path parameters `s_k`, increasing from 0 to `S`.
    pub grid: Vec<f64>,
    /// The path at the nodes.
    pub nodes: Vec<PathNode>,
    /// The path at the interval midpoints `(s_k + s_{k+1})/2`, where the torque is bounded too
    /// (there `x = (x_k + x_{k+1})/2` exactly); none when absent (ends only).
    pub midpoints: Option<Vec<PathNode>>,
}

/// Points per interval of the quadrature that grades the grid ([`PathPiece::sample`]).
const GRADING_POINTS: usize = 16;

impl PathPiece {
    /// A piece on the uniform grid `s_k = k S/N` of its nodes.
    pub fn uniform(length: f64, nodes: Vec<PathNode>) -> PathPiece {
        let n = nodes.len().saturating_sub(1).max(1);
        let grid = (0..nodes.len()).map(|k| if k == n { length } else { length * k as f64 / n as f64 }).collect();
        PathPiece { length, grid, nodes, midpoints: None }
    }

    /// Samples piece `piece` of a trajectory on `intervals` intervals of its local time, with
    /// `a` and `b` from Newton–Euler at `(q, 0, q')` and `(q, q', q'')`.
    ///
    /// The grid is graded: equally spaced in `½ s/S + ½ ℓ(s)/L`, with `ℓ(s) = ∫|q'|` the joint
    /// path's arc length and `L` the piece's. A path timed by a profile that starts with a
    /// vanishing rate (the paper's cosine has `q' ∝ s²`) covers little of its arc early on,
    /// where its optimal `ṡ` is large and steep; half the nodes follow the arc, so the joint
    /// motion is resolved evenly, half follow `s`, so no interval of `s` is left coarse.
    pub fn sample(
        cat: &impl ZeroMomentumTorques,
        path: &impl Trajectory,
        piece: usize,
        length: f64,
        intervals: usize,
    ) -> Result<PathPiece, RetimeError> {
        Self::sample_on(cat, path, piece, length, graded_grid(path, piece, length, intervals))
    }

    /// [`PathPiece::sample`] on the given grid (increasing from 0 to `length`).
    pub(crate) fn sample_on(
        cat: &impl ZeroMomentumTorques,
        path: &impl Trajectory,
        piece: usize,
        length: f64,
        grid: Vec<f64>,
    ) -> Result<PathPiece, RetimeError> {
        let node = |s: f64| -> Result<PathNode, RetimeError> {
            let st = path.piece_state(piece, s);
            let a = cat.motor_torques(&JointState { q: st.q, qd: [0.0; 2], qdd: st.qd });
            let b = cat.motor_torques(&st);
            let finite = |v: [f64; 2]| v.iter().all(|x| x.is_finite());
            if !finite(st.q) || !finite(st.qdd) {
                return Err(RetimeError::NonFinitePath { piece, s, what: "q or q''" });
            }
            match [("a", a), ("b", b), ("q'", st.qd)].into_iter().find(|(_, v)| !finite(*v)) {
                Some((what, _)) => Err(RetimeError::NonFinitePath { piece, s, what }),
                None => Ok(PathNode { a, b, tangent: st.qd }),
            }
        };
        let nodes = grid.iter().map(|&s| node(s)).collect::<Result<Vec<_>, _>>()?;
        let midpoints = grid.windows(2).map(|g| node(0.5 * (g[0] + g[1]))).collect::<Result<Vec<_>, _>>()?;
        Ok(PathPiece { length, grid, nodes, midpoints: Some(midpoints) })
    }

    /// Number of intervals `N`.
    pub fn intervals(&self) -> usize {
        self.nodes.len().saturating_sub(1)
    }

    /// Width `s_{k+1} − s_k` of interval `k`.
    pub fn spacing(&self, k: usize) -> f64 {
        self.grid[k + 1] - self.grid[k]
    }

    /// The largest tangent norm on the piece: the scale below which a tangent counts as zero.
    fn tangent_scale(&self) -> f64 {
        self.nodes.iter().map(|n| norm(n.tangent)).fold(0.0, f64::max)
    }
}

/// The retiming program of the module docs: a sampled path, a total duration and the settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PathProblem {
    /// The pieces, in order.
    pub pieces: Vec<PathPiece>,
    /// Total duration `T`, s.
    pub duration: f64,
    /// Split, limits and solver settings (`intervals` is used only when sampling a trajectory).
    pub settings: RetimeSettings,
    /// With [`Split::Kept`], the pieces' durations are in proportion to these (one per piece,
    /// e.g. the original phases' durations when the path parameter is not a time); `None`: to
    /// the pieces' lengths.
    #[serde(default)]
    pub kept: Option<Vec<f64>>,
}

/// Relative size below which a tangent is zero (the joints rest whatever `ṡ`).
const ZERO_TANGENT: f64 = 1e-9;
/// `1 − cos` of the largest angle between two tangents that still counts as no kink.
const STRAIGHT_JOIN: f64 = 1e-9;

/// What holds at one junction: the start of the path, between two pieces, or its end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Junction {
    /// The node before the junction (the last of the previous piece) must be at rest.
    pub(crate) rest_before: bool,
    /// The node after it (the first of the next piece) must be at rest.
    pub(crate) rest_after: bool,
    /// The joint rates are continuous across it: `x_after |q'_after|² = x_before |q'_before|²`,
    /// given as `(|q'_before|², |q'_after|²)`.
    pub(crate) continuous: Option<(f64, f64)>,
}

impl PathProblem {
    /// The program for a trajectory's path, every piece timed anew within a total `duration`.
    pub fn from_trajectory(
        cat: &impl ZeroMomentumTorques,
        path: &impl Trajectory,
        duration: f64,
        settings: RetimeSettings,
    ) -> Result<PathProblem, RetimeError> {
        settings.validate()?;
        positive("duration", duration)?;
        let lengths = path.piece_durations();
        if lengths.is_empty() {
            return Err(bad("path", "no pieces", "must have at least one piece"));
        }
        for &l in &lengths {
            positive("piece duration", l)?;
        }
        let pieces = lengths
            .iter()
            .enumerate()
            .map(|(i, &l)| PathPiece::sample(cat, path, i, l, settings.intervals))
            .collect::<Result<Vec<_>, _>>()?;
        let problem = PathProblem { pieces, duration, settings, kept: None };
        problem.validate()?;
        Ok(problem)
    }

    /// Checks every field; names the first one that is wrong.
    pub fn validate(&self) -> Result<(), RetimeError> {
        positive("duration", self.duration)?;
        self.settings.validate()?;
        if self.pieces.is_empty() {
            return Err(bad("pieces", 0, "must hold at least one piece"));
        }
        if let Some(kept) = &self.kept {
            if kept.len() != self.pieces.len() {
                return Err(bad("kept durations", kept.len(), "must give one per piece"));
            }
            for &d in kept {
                positive("kept duration", d)?;
            }
        }
        for (i, p) in self.pieces.iter().enumerate() {
            positive("piece length", p.length)?;
            if p.intervals() < 2 {
                return Err(bad("piece nodes", p.nodes.len(), "a piece needs at least 3 nodes (2 intervals)"));
            }
            if p.grid.len() != p.nodes.len() {
                return Err(bad("piece grid", p.grid.len(), "must have one point per node"));
            }
            let ends =
                p.grid[0].to_bits() == 0.0f64.to_bits() && p.grid[p.grid.len() - 1].to_bits() == p.length.to_bits();
            if !ends || p.grid.windows(2).any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater)) {
                return Err(bad(
                    "piece grid",
                    format!("{:?}…", &p.grid[..3]),
                    "must increase from 0 to the piece's length",
                ));
            }
            if p.midpoints.as_ref().is_some_and(|m| m.len() != p.intervals()) {
                return Err(bad(
                    "piece midpoints",
                    p.midpoints.as_ref().map_or(0, Vec::len),
                    "must have one per interval",
                ));
            }
            let mids = p.midpoints.iter().flatten().zip(p.grid.windows(2).map(|g| 0.5 * (g[0] + g[1])));
            for (n, s) in p.nodes.iter().zip(p.grid.iter().copied()).chain(mids) {
                for (what, v) in [("a", n.a), ("b", n.b), ("q'", n.tangent)] {
                    if !v.iter().all(|x| x.is_finite()) {
                        return Err(RetimeError::NonFinitePath { piece: i, s, what });
                    }
                }
            }
        }
        Ok(())
    }

    /// The whole path's extent `Σ S_i`.
    pub fn length(&self) -> f64 {
        self.pieces.iter().map(|p| p.length).sum()
    }

    /// The duration each piece must take with [`Split::Kept`], `T S_i / S`; `None` with
    /// [`Split::Free`].
    pub fn piece_targets(&self) -> Option<Vec<f64>> {
        match self.settings.split {
            Split::Kept => {
                let weights: Vec<f64> = match &self.kept {
                    Some(w) => w.clone(),
                    None => self.pieces.iter().map(|p| p.length).collect(),
                };
                let s: f64 = weights.iter().sum();
                Some(weights.iter().map(|w| self.duration * w / s).collect())
            }
            Split::Free => None,
        }
    }

    /// The `P + 1` junctions of `P` pieces (module docs: rest at the ends and at kinks,
    /// continuity across straight joins).
    pub(crate) fn junctions(&self) -> Vec<Junction> {
        let n = self.pieces.len();
        let end = |i: usize, last: bool| {
            let p = &self.pieces[i];
            let t = if last { p.nodes[p.nodes.len() - 1].tangent } else { p.nodes[0].tangent };
            (t, norm(t) > ZERO_TANGENT * p.tangent_scale())
        };
        (0..=n)
            .map(|j| {
                let before = (j > 0).then(|| end(j - 1, true));
                let after = (j < n).then(|| end(j, false));
                match (before, after) {
                    (Some((tb, true)), Some((ta, true))) if straight(tb, ta) => {
                        Junction { rest_before: false, rest_after: false, continuous: Some((dot(tb, tb), dot(ta, ta))) }
                    }
                    _ => Junction {
                        rest_before: before.is_some_and(|b| b.1),
                        rest_after: after.is_some_and(|a| a.1),
                        continuous: None,
                    },
                }
            })
            .collect()
    }
}

/// The normalisation of the module docs.
#[derive(Clone, Copy)]
pub(crate) struct Scales {
    /// Whole path extent `S`.
    pub(crate) length: f64,
    /// Speed unit `v = S/T`.
    pub(crate) speed: f64,
    /// Torque unit `τ₀`, N·m.
    pub(crate) torque: f64,
}

impl Scales {
    pub(crate) fn new(problem: &PathProblem) -> Scales {
        let length = problem.length();
        let speed = length / problem.duration;
        let v2 = speed * speed;
        let torque = problem
            .pieces
            .iter()
            .flat_map(|p| &p.nodes)
            .flat_map(|n| (0..2).map(move |j| n.a[j].abs() * v2 / length + n.b[j].abs() * v2))
            .fold(0.0, f64::max);
        Scales { length, speed, torque: if torque > 0.0 { torque } else { 1.0 } }
    }
}

/// The graded grid of [`PathPiece::sample`]: `N + 1` points equally spaced in
/// `½ s/S + ½ ℓ(s)/L`, `ℓ` by the trapezoid rule on `16 N` points, inverted linearly.
pub(crate) fn graded_grid(path: &impl Trajectory, piece: usize, length: f64, intervals: usize) -> Vec<f64> {
    let m = GRADING_POINTS * intervals;
    let fine: Vec<f64> = (0..=m).map(|i| if i == m { length } else { length * i as f64 / m as f64 }).collect();
    let speed: Vec<f64> = fine.iter().map(|&s| norm(path.piece_state(piece, s).qd)).collect();
    let mut arc = vec![0.0; m + 1];
    for i in 0..m {
        arc[i + 1] = arc[i] + 0.5 * (speed[i] + speed[i + 1]) * (fine[i + 1] - fine[i]);
    }
    let total = arc[m];
    let measure: Vec<f64> = (0..=m)
        .map(|i| {
            let along = if total > 0.0 && total.is_finite() { arc[i] / total } else { fine[i] / length };
            0.5 * fine[i] / length + 0.5 * along
        })
        .collect();
    let mut grid = Vec::with_capacity(intervals + 1);
    grid.push(0.0);
    let mut i = 0;
    for k in 1..intervals {
        let target = k as f64 / intervals as f64;
        while measure[i + 1] < target {
            i += 1;
        }
        let f = (target - measure[i]) / (measure[i + 1] - measure[i]);
        grid.push(fine[i] + f * (fine[i + 1] - fine[i]));
    }
    grid.push(length);
    grid
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}

/// Whether two non-zero tangents point the same way (no kink between them).
fn straight(a: [f64; 2], b: [f64; 2]) -> bool {
    dot(a, b) >= (1.0 - STRAIGHT_JOIN) * norm(a) * norm(b)
}
