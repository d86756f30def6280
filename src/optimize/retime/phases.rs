//! A three-phase schedule's joint path parametrised by each phase's progress variable, the
//! path the retiming of a [`Schedule`] works on ([`retime_schedule`]).
//!
//! Parametrised by its own local time, a phase that starts or ends at rest has `q' = q̇ = 0`
//! there, to second order for the library's smooth profiles (`q' ∝ s²`). The optimal `ṡ` of a
//! retiming is then singular at such an end (`ṡ → ∞` while the joints barely move), and the
//! discrete program is so badly scaled that interior-point solvers stop at different values:
//! on the paper's path with the split free, Clarabel's "solved" optima spread over 2 × 10⁻³
//! (relative) as its equilibration or regularisation changes, and ECOS reports a third value,
//! each with a duality gap near 10⁻⁸. The progress variables of
//! [`Schedule::progress_state`] (joint 1's angle in the bend, the bend direction in
//! the twist, the fraction straightened in the unbend) move the joints at a rate that never
//! vanishes on the phase, so `q'` stays away from zero and the program is well posed; the
//! path, and with it the flip, is the same. A phase that does not move (no bend, no
//! circulation) keeps its local time.

use super::problemdata::graded_grid;
use super::{PathPiece, PathProblem, RetimeError, RetimeSettings, Retiming};
use crate::engines::torque::ZeroMomentumTorques;
use crate::schedule::{JointState, Phase, Schedule, Trajectory};

/// A schedule's path with every moving phase parametrised by `|φ|`, its progress variable
/// (module docs); each piece lasts, in this parameter, the distance its phase covers.
#[derive(Clone, Debug, PartialEq)]
pub struct PhasePath {
    /// The schedule whose path this is.
    pub schedule: Schedule,
}

impl PhasePath {
    /// The sign of `φ`'s travel in a phase, or `None` when the phase does not move (then its
    /// piece keeps the schedule's local time).
    fn direction(&self, phase: Phase) -> Option<f64> {
        let d = self.schedule.progress_distance(phase);
        (d != 0.0 && d.is_finite()).then(|| d.signum())
    }

    /// `|φ|` at the schedule's local time `t` of `phase` (its own local time when it does not
    /// move).
    fn progress(&self, phase: Phase, t: f64) -> f64 {
        let s = &self.schedule;
        match self.direction(phase) {
            Some(_) => s.progress_distance(phase).abs() * s.timing(phase).at(t / s.durations[phase.index()]).position,
            None => t,
        }
    }
}

impl Trajectory for PhasePath {
    fn piece_durations(&self) -> Vec<f64> {
        Phase::ALL
            .iter()
            .map(|&p| match self.direction(p) {
                Some(_) => self.schedule.progress_distance(p).abs(),
                None => self.schedule.durations[p.index()],
            })
            .collect()
    }

    /// At `s` along piece `piece`: `q`, `q' = dq/ds` and `q'' = d²q/ds²`, on the schedule's
    /// own path ([`Schedule::progress_state`] at `φ = ±s`, `φ̇ = ±1`, `φ̈ = 0`).
    fn piece_state(&self, piece: usize, s: f64) -> JointState {
        let phase = Phase::ALL[piece];
        match self.direction(phase) {
            Some(sign) => self.schedule.progress_state(phase, sign * s, sign, 0.0),
            None => self.schedule.piece_state(piece, s),
        }
    }
}

/// Retimes a three-phase schedule along its path parametrised by [`PhasePath`], to its own
/// duration; with the phases' durations kept, each phase keeps the schedule's. The grid is the
/// one [`PathPiece::sample`] grades on the schedule's own timing (half the nodes equally spaced
/// in time, half in arc length), carried to `φ`: the same points of the path.
pub fn retime_schedule(
    cat: &impl ZeroMomentumTorques,
    schedule: &Schedule,
    settings: RetimeSettings,
) -> Result<Retiming<PhasePath>, RetimeError> {
    settings.validate()?;
    let path = PhasePath { schedule: schedule.clone() };
    let lengths = path.piece_durations();
    let pieces = Phase::ALL
        .iter()
        .zip(&lengths)
        .map(|(&phase, &length)| {
            let i = phase.index();
            let times = graded_grid(schedule, i, schedule.durations[i], settings.intervals);
            let mut grid: Vec<f64> = times.iter().map(|&t| path.progress(phase, t)).collect();
            // The ends exactly, whatever the profile's rounding.
            let last = grid.len() - 1;
            (grid[0], grid[last]) = (0.0, length);
            PathPiece::sample_on(cat, &path, i, length, grid)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let problem =
        PathProblem { pieces, duration: schedule.duration(), settings, kept: Some(schedule.durations.to_vec()) };
    Retiming::solve(&problem, &path)
}
