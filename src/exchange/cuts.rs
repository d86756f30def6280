//! A trajectory's pieces cut where its acceleration jumps, so that every piece of a schedule
//! file is smooth (C⁶ within it, as its interpolation needs).
//!
//! A profile stored as segments of acceleration ([`crate::schedule::profile::Profile::breakpoints`]) may
//! jump in `q̈` where a segment starts: a bang-bang or trapezoid law, the QP's piecewise-linear
//! rate, a retimed bend. A schedule file with rows only on a grid would smooth such a jump over
//! one interval and lose the torque on its near side (0.75 % of the peak torque of the paper's
//! whole-manoeuvre optimum at 1 kHz). Cut there, the file writes the instant twice (`end`/`start`,
//! as at a phase boundary) with both one-sided accelerations.
//!
//! One-sided values at a cut are the segment's own formula evaluated `δ = 10⁻¹² T` inside it
//! (`T` the phase's duration): `q̈` is smooth within a segment, so this moves `q` by `q̇δ`, `q̇` by
//! `q̈δ` and `q̈` by `q⃛δ`, all at round-off.

use crate::schedule::{JointState, Phase, Schedule, Trajectory};

/// Fraction of a phase's duration by which one-sided values at a cut are taken inside the piece.
const INSIDE: f64 = 1e-12;

/// `inner`'s pieces cut at interior instants.
#[derive(Clone, Debug)]
pub struct CutTrajectory<'a, T: Trajectory> {
    inner: &'a T,
    /// `(inner piece, local start, local end)` of each piece, in order.
    pieces: Vec<(usize, f64, f64)>,
    /// Durations of the inner pieces.
    inner_durations: Vec<f64>,
}

impl<'a, T: Trajectory> CutTrajectory<'a, T> {
    /// `inner` with piece `k` cut at the local times `cuts[k]` (outside `(0, T_k)` ignored).
    pub fn new(inner: &'a T, cuts: &[Vec<f64>]) -> Self {
        let inner_durations = inner.piece_durations();
        let mut pieces = Vec::new();
        for (k, &d) in inner_durations.iter().enumerate() {
            let mut at: Vec<f64> = cuts.get(k).map_or(Vec::new(), |c| c.clone());
            at.retain(|&c| c > INSIDE * d && c < d * (1.0 - INSIDE));
            at.sort_by(f64::total_cmp);
            let mut a = 0.0;
            for c in at.into_iter().chain(std::iter::once(d)) {
                pieces.push((k, a, c));
                a = c;
            }
        }
        CutTrajectory { inner, pieces, inner_durations }
    }

    /// The inner piece each piece comes from.
    pub fn origin(&self, piece: usize) -> usize {
        self.pieces[piece].0
    }
}

impl<T: Trajectory> Trajectory for CutTrajectory<'_, T> {
    fn piece_durations(&self) -> Vec<f64> {
        self.pieces.iter().map(|&(_, a, b)| b - a).collect()
    }

    fn piece_state(&self, piece: usize, s: f64) -> JointState {
        let (k, a, b) = self.pieces[piece];
        let d = self.inner_durations[k];
        let local = (a + s).clamp(a, b);
        let nudge = INSIDE * d;
        let local = if local <= a && a > 0.0 {
            a + nudge
        } else if local >= b && b < d {
            b - nudge
        } else {
            local
        };
        self.inner.piece_state(k, local)
    }
}

/// Where a three-phase schedule's acceleration jumps inside a phase: those of each phase's timing
/// profile's segment starts where the normalised acceleration changes by more than `10⁻⁹` of its
/// size, as local times of bend, twist and unbend.
pub fn acceleration_cuts(schedule: &Schedule) -> Vec<Vec<f64>> {
    Phase::ALL
        .iter()
        .map(|&phase| {
            let profile = match phase {
                Phase::Bend => &schedule.bend_profile,
                Phase::Twist => &schedule.profile,
                Phase::Unbend => &schedule.unbend_profile,
            };
            let d = schedule.durations[phase.index()];
            profile
                .breakpoints()
                .filter(|&u| {
                    let (before, after) = (profile.at(u - INSIDE).accel, profile.at(u).accel);
                    (after - before).abs() > 1e-9 * before.abs().max(after.abs()).max(1.0)
                })
                .map(|u| u * d)
                .collect()
        })
        .collect()
}
