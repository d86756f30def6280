//! A [`Trajectory`] seen on one global clock: where each piece starts, the state at a time `t`,
//! and where its acceleration jumps.
//!
//! Times in s, angles in rad. At a boundary the later piece's formula is used (as
//! [`crate::schedule::Schedule::state`] does), so a step that ends on a boundary takes its target
//! from the piece that starts there.

use crate::engines::jumps::rate_jumps;
use crate::schedule::{JointState, Trajectory};

fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}

/// Jumps of `q̈` smaller than this fraction of the trajectory's largest `‖q̈‖` are not kept out of
/// the peaks: their transient, about a tenth of the jump, is within the verification's
/// resolution, and a fine grid of them (a retimed path has one at every node) would otherwise
/// leave few samples at the coarse steps.
pub const ACCEL_JUMP_FRACTION: f64 = 0.01;

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
        let (jumps, scale) = self.inner_acceleration_jumps();
        let mut times: Vec<f64> = jumps.into_iter().filter(|&(_, j)| j > fraction * scale).map(|(t, _)| t).collect();
        times.sort_by(f64::total_cmp);
        times
    }

    /// The jumps of `q̈` inside the pieces, `(global time, ‖Δq̈‖)`, and the largest `‖q̈‖` seen on
    /// either side of any of them or at the pieces' quarters.
    fn inner_acceleration_jumps(&self) -> (Vec<(f64, f64)>, f64) {
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
        (jumps, scale)
    }

    /// Which inner boundaries (piece `i` starts at boundary `i − 1`) are rough: the joint rates
    /// jump there ([`crate::engines::jumps::rate_jumps`]) or the accelerations jump by
    /// more than `fraction` of the largest `‖q̈‖` ([`Pieces::acceleration_jumps`]' scale), as
    /// they do between the phases of a schedule. A boundary that is not rough joins two pieces
    /// of one smooth motion, as a cubic spline's knots do (`q̈` continuous): the servo sees no
    /// jump there.
    pub fn rough(&self, fraction: f64) -> Vec<bool> {
        let rates = rate_jumps(self.traj, |k| self.traj.boundary_rate_uncertainty(k));
        let (_, scale) = self.inner_acceleration_jumps();
        (1..self.durations.len())
            .map(|i| {
                let before = self.traj.piece_state(i - 1, self.durations[i - 1]).qdd;
                let after = self.traj.piece_state(i, 0.0).qdd;
                rates.iter().any(|j| j.after_piece + 1 == i)
                    || norm([after[0] - before[0], after[1] - before[1]]) > fraction * scale
            })
            .collect()
    }

    /// The inner boundaries marked in `rough` ([`Pieces::rough`]), s.
    pub fn rough_boundaries(&self, rough: &[bool]) -> Vec<f64> {
        self.boundaries().iter().zip(rough).filter(|(_, r)| **r).map(|(b, _)| *b).collect()
    }

    /// The shortest stretch of positive length between consecutive rough boundaries (or the
    /// ends), the sum of its pieces' durations, s (`∞` if there is none). With every boundary
    /// rough, the shortest piece of positive length.
    pub fn shortest_smooth(&self, rough: &[bool]) -> f64 {
        let mut shortest = f64::INFINITY;
        let mut stretch: Option<f64> = None;
        for (i, &d) in self.durations.iter().enumerate() {
            if i > 0 && rough.get(i - 1).copied().unwrap_or(true) {
                if let Some(len) = stretch.take().filter(|len| *len > 0.0) {
                    shortest = shortest.min(len);
                }
            }
            stretch = Some(stretch.map_or(d, |len| len + d));
        }
        if let Some(len) = stretch.filter(|len| *len > 0.0) {
            shortest = shortest.min(len);
        }
        shortest
    }
}
