//! The retiming program's data: the path sampled on its grid, and the boundary conditions its
//! tangents imply (module docs).

use serde::{Deserialize, Serialize};

use super::solution::RetimeSolution;
use super::{bad, positive, RetimeError, RetimeSettings, Split};
use crate::model::Cylinder;
use crate::schedule::{JointState, Trajectory};
use crate::torque::joint_torques;

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

/// One smooth piece of the path, sampled at `N + 1` equally spaced nodes `s_k = k S/N`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PathPiece {
    /// Its extent `S` in the path parameter (for a trajectory piece, its original duration, s).
    pub length: f64,
    /// The nodes, `s = 0` first and `s = S` last.
    pub nodes: Vec<PathNode>,
}

impl PathPiece {
    /// Samples piece `piece` of a trajectory on `intervals` equal intervals of its local time,
    /// with `a` and `b` from Newton–Euler at `(q, 0, q')` and `(q, q', q'')`.
    pub fn sample(
        cat: &Cylinder,
        path: &impl Trajectory,
        piece: usize,
        length: f64,
        intervals: usize,
    ) -> Result<PathPiece, RetimeError> {
        let nodes = (0..=intervals)
            .map(|k| {
                let s = if k == intervals { length } else { length * k as f64 / intervals as f64 };
                let st = path.piece_state(piece, s);
                let a = joint_torques(cat, &JointState { q: st.q, qd: [0.0; 2], qdd: st.qd }).tau;
                let b = joint_torques(cat, &st).tau;
                let node = PathNode { a, b, tangent: st.qd };
                let finite = |v: [f64; 2]| v.iter().all(|x| x.is_finite());
                if !finite(st.q) || !finite(st.qdd) {
                    return Err(RetimeError::NonFinitePath { piece, s, what: "q or q''" });
                }
                match [("a", a), ("b", b), ("q'", st.qd)].into_iter().find(|(_, v)| !finite(*v)) {
                    Some((what, _)) => Err(RetimeError::NonFinitePath { piece, s, what }),
                    None => Ok(node),
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(PathPiece { length, nodes })
    }

    /// Number of intervals `N`.
    pub fn intervals(&self) -> usize {
        self.nodes.len().saturating_sub(1)
    }

    /// Grid spacing `Δs = S/N`.
    pub fn spacing(&self) -> f64 {
        self.length / self.intervals() as f64
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
        cat: &Cylinder,
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
        let problem = PathProblem { pieces, duration, settings };
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
        for (i, p) in self.pieces.iter().enumerate() {
            positive("piece length", p.length)?;
            if p.intervals() < 2 {
                return Err(bad("piece nodes", p.nodes.len(), "a piece needs at least 3 nodes (2 intervals)"));
            }
            for (k, n) in p.nodes.iter().enumerate() {
                let s = p.spacing() * k as f64;
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
                let s = self.length();
                Some(self.pieces.iter().map(|p| self.duration * p.length / s).collect())
            }
            Split::Free => None,
        }
    }

    /// Solves with Clarabel. A solve that ends without a solution is not an error: its status
    /// says how it ended.
    pub fn solve(&self) -> Result<RetimeSolution, RetimeError> {
        self.validate()?;
        super::assembly::solve(self)
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
