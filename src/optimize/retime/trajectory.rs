//! The retimed trajectory `q(t) = q(s(t))` and its re-measurement by the exact engine.
//!
//! On piece `i`, interval `k`, `s(t) = s_k + ṡ_k τ + u_k τ²/2` exactly (piecewise constant
//! `s̈`), so `q̇ = q' ṡ` is continuous and `q̈ = q' s̈ + q'' ṡ²` jumps where `s̈` does: the exact
//! torques of this trajectory at the grid nodes are the program's. The trajectory reports the
//! inner nodes as [`Trajectory::acceleration_jumps`] and gives both one-sided states there
//! ([`Trajectory::piece_state_before`]), so that peaks include the one-sided limits of `|τ|`.

use serde::Serialize;

use super::{PathProblem, PieceTiming, RetimeError, RetimeSettings, RetimeSolution};
use crate::engines::evaluate::Evaluation;
use crate::engines::exact::Flip;
use crate::engines::torque::{PeakTorques, ZeroMomentumTorques};
use crate::model::motor::Motors;
use crate::model::Cylinder;
use crate::problem::settings::ExactSettings;
use crate::schedule::{JointState, Trajectory};

/// A path with new timings: the pieces are the path's, each run in its [`PieceTiming`].
#[derive(Clone, Debug, PartialEq)]
pub struct RetimedTrajectory<P> {
    /// The path, parametrised by the local time of its own pieces.
    pub path: P,
    /// The timing of each piece.
    pub timings: Vec<PieceTiming>,
}

impl<P: Trajectory> Trajectory for RetimedTrajectory<P> {
    fn piece_durations(&self) -> Vec<f64> {
        self.timings.iter().map(PieceTiming::duration).collect()
    }

    fn piece_state(&self, piece: usize, t: f64) -> JointState {
        self.compose(piece, self.timings[piece].at(t))
    }

    /// Every inner grid node: `s̈` is constant per interval, so `q̈` jumps at each.
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64> {
        self.timings[piece].inner_node_times().to_vec()
    }

    fn piece_state_before(&self, piece: usize, t: f64) -> JointState {
        self.compose(piece, self.timings[piece].at_before(t))
    }
}

impl<P: Trajectory> RetimedTrajectory<P> {
    /// The joint state of piece `piece` at the path state `(s, ṡ, s̈)`.
    fn compose(&self, piece: usize, (s, sd, sdd): (f64, f64, f64)) -> JointState {
        let p = self.path.piece_state(piece, s);
        JointState { q: p.q, qd: p.qd.map(|d| d * sd), qdd: [0, 1].map(|j| p.qd[j] * sdd + p.qdd[j] * sd * sd) }
    }
}

/// A path retimed: the program's solution and, when it solved, the timed trajectory.
#[derive(Clone, Debug, PartialEq)]
pub struct Retiming<P> {
    /// The program's solution.
    pub solution: RetimeSolution,
    /// The timed trajectory; `None` unless the solution [`RetimeStatus::is_solved`].
    ///
    /// [`RetimeStatus::is_solved`]: super::RetimeStatus::is_solved
    pub trajectory: Option<RetimedTrajectory<P>>,
}

/// The retimed trajectory measured by the exact engine.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Remeasurement {
    /// Exact peak torques of the retimed trajectory, per piece and joint (dense evaluation).
    pub peaks: PeakTorques,
    /// `peaks.max − lower_bound`: how far the exact peak of this timing lies above the certified
    /// bound of the discrete problem, N·m.
    pub gap_to_bound: f64,
    /// The retimed trajectory's flip (a geometric phase: the same up to the tolerance).
    pub flip: Flip,
}

/// Retimes a trajectory's path to a total `duration` (s): samples it, solves the program, and
/// builds the timed trajectory (module docs).
pub fn retime<P: Trajectory + Clone>(
    cat: &impl ZeroMomentumTorques,
    path: &P,
    duration: f64,
    settings: RetimeSettings,
) -> Result<Retiming<P>, RetimeError> {
    let problem = PathProblem::from_trajectory(cat, path, duration, settings)?;
    Retiming::solve(&problem, path)
}

impl<P: Trajectory + Clone> Retiming<P> {
    /// Solves `problem`, the program of `path`'s path, and times `path` by its solution.
    pub(crate) fn solve(problem: &PathProblem, path: &P) -> Result<Retiming<P>, RetimeError> {
        let solution = problem.solve()?;
        let trajectory = solution
            .status
            .is_solved()
            .then(|| RetimedTrajectory { path: path.clone(), timings: solution.timings.clone() });
        Ok(Retiming { solution, trajectory })
    }
}

impl<P: Trajectory> Retiming<P> {
    /// Measures the retimed trajectory on the paper's cat of `cat` at zero angular momentum as
    /// every trajectory is ([`Evaluation::new`]), with at least `samples + 1` torque samples per
    /// piece and the flip to `tolerance` rad, and its distance to the certified bound (a
    /// convergence study's finer sampling than a problem's `[exact]`). `None` when there is no
    /// trajectory.
    pub fn remeasure(&self, cat: &Cylinder, samples: usize, tolerance: f64) -> Option<Remeasurement> {
        let traj = self.trajectory.as_ref()?;
        let settings = ExactSettings { tolerance, torque_samples: samples };
        let e = Evaluation::of_paper(cat, traj, &nalgebra::Vector3::zeros(), &Motors::ideal(), &settings);
        Some(Remeasurement { gap_to_bound: e.peaks.max - self.solution.lower_bound, peaks: e.peaks, flip: e.flip })
    }
}
