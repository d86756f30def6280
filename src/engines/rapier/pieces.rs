//! A [`Trajectory`] seen on one global clock: where each piece starts, the state at a time `t`,
//! and where its acceleration jumps.
//!
//! Times in s, angles in rad. At a boundary the later piece's formula is used (as
//! [`crate::schedule::Schedule::state`] does), so a step that ends on a boundary takes its target
//! from the piece that starts there.

use crate::schedule::{JointState, Trajectory};

/// A trajectory with its piece start times.
pub(crate) struct Pieces<'a, T: Trajectory> {
    traj: &'a T,
    durations: Vec<f64>,
    starts: Vec<f64>,
}

impl<'a, T: Trajectory> Pieces<'a, T> {
    pub fn new(traj: &'a T) -> Self {
        let durations = traj.piece_durations();
        let mut starts = Vec::with_capacity(durations.len());
        let mut t = 0.0;
        for d in &durations {
            starts.push(t);
            t += d;
        }
        Self { traj, durations, starts }
    }

    /// Durations of the pieces, s.
    pub fn durations(&self) -> &[f64] {
        &self.durations
    }

    /// Total duration, s.
    pub fn duration(&self) -> f64 {
        self.durations.iter().sum()
    }

    /// The shortest piece of positive length, s (`∞` if there is none).
    pub fn shortest(&self) -> f64 {
        self.durations.iter().copied().filter(|d| *d > 0.0).fold(f64::INFINITY, f64::min)
    }

    /// Start times of the pieces after the first: the inner boundaries, s.
    pub fn boundaries(&self) -> &[f64] {
        self.starts.get(1..).unwrap_or(&[])
    }

    /// The piece containing `t` (the later one at a boundary, never an empty one) and the local
    /// time, clamped to the piece.
    pub fn locate(&self, t: f64) -> (usize, f64) {
        let after = self.starts.partition_point(|&s| s <= t);
        let mut i = after.saturating_sub(1).min(self.durations.len().saturating_sub(1));
        while i > 0 && self.durations[i] <= 0.0 {
            i -= 1;
        }
        let d = self.durations.get(i).copied().unwrap_or(0.0);
        (i, (t - self.starts.get(i).copied().unwrap_or(0.0)).clamp(0.0, d))
    }

    /// The state at global time `t`.
    pub fn state(&self, t: f64) -> JointState {
        let (i, s) = self.locate(t);
        self.traj.piece_state(i, s)
    }

    /// Global times of the trajectory's [`Trajectory::acceleration_jumps`] where `‖Δq̈‖`
    /// exceeds `fraction` of the largest `‖q̈‖` seen on either side of any of them or at the
    /// pieces' quarters, sorted.
    pub fn acceleration_jumps(&self, fraction: f64) -> Vec<f64> {
        let norm = |a: [f64; 2]| a[0].hypot(a[1]);
        let mut jumps = Vec::new();
        let mut scale = 0.0f64;
        for (i, (&start, &d)) in self.starts.iter().zip(&self.durations).enumerate() {
            for f in [0.0, 0.25, 0.5, 0.75, 1.0] {
                scale = scale.max(norm(self.traj.piece_state(i, f * d).qdd));
            }
            for s in self.traj.acceleration_jumps(i) {
                let (before, after) = (self.traj.piece_state_before(i, s).qdd, self.traj.piece_state(i, s).qdd);
                scale = scale.max(norm(before)).max(norm(after));
                jumps.push((start + s, norm([after[0] - before[0], after[1] - before[1]])));
            }
        }
        let mut times: Vec<f64> = jumps.into_iter().filter(|&(_, j)| j > fraction * scale).map(|(t, _)| t).collect();
        times.sort_by(f64::total_cmp);
        times
    }
}
