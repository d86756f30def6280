//! Joint-rate jumps between the pieces of any [`Trajectory`], with the impulse each needs: the one
//! jump computation every command, file and engine uses.
//!
//! At the boundary after piece `k` the rates may jump from `q̇⁻` (piece `k`'s end) to `q̇⁺` (piece
//! `k + 1`'s start). The joint then delivers an impulse, not a torque: the impulsive couple the
//! joint transmits to B, projected on the motor axes as the torques are, N·m·s. Over an instant
//! only the terms linear in the velocity change contribute, and at `q̇ = 0` those are exactly the
//! couple's acceleration terms, so the impulse is the couple at `q̇ = 0` with `q̈ = Δq̇`
//! ([`crate::engines::models::TwoMotorCat::motor_impulse`]); on the universal joint, whose motor
//! axes are its joint axes, it is the generalised impulse `M(q) Δq̇` of the reduced zero-momentum
//! mass matrix ([`generalised_impulse`]).
//!
//! A jump is reported when `|Δq̇|` exceeds both [`JUMP_TOLERANCE`] times the rates of the two
//! adjoining pieces (the largest `|q̇|` at their quarters and ends, at least 1 rad/s), so that
//! round-off of a fast piece is not taken for a jump, and the rates' own uncertainty at that
//! boundary (zero for rates from a formula or a file; for a spline through imported rows, the
//! spline's estimate, [`crate::exchange::ImportedSchedule::boundary_rate_uncertainty`]). Pieces
//! of zero length have no boundary of their own.

use serde::Serialize;

use crate::engines::models::TwoMotorCat;
use crate::engines::torque::reduced_mass_matrix;
use crate::engines::JUMP_TOLERANCE;
use crate::model::Cylinder;
use crate::schedule::{JointState, Trajectory};

/// A jump of the joint rates at a piece boundary (for a three-phase schedule the pieces are the
/// phases: bend 0, twist 1, unbend 2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct VelocityJump {
    /// Time from the trajectory's start, s.
    pub time: f64,
    /// The piece that ends there (0-based; the next one starts there).
    pub after_piece: usize,
    /// Joint rates just before, rad/s.
    pub rates_before: [f64; 2],
    /// Joint rates just after, rad/s.
    pub rates_after: [f64; 2],
    /// The impulse the motors must deliver, N·m·s (module docs).
    pub impulse: [f64; 2],
}

/// A boundary where the joint rates jump: the piece that ends there (0-based), the time from the
/// trajectory's start (s), and the states on both sides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RateJump {
    /// The piece that ends there.
    pub after_piece: usize,
    /// Time from the trajectory's start, s.
    pub time: f64,
    /// The state at the end of piece `after_piece`.
    pub before: JointState,
    /// The state at the start of the next piece.
    pub after: JointState,
}

/// The boundaries of `traj` where the rates jump (module docs), the rate difference after piece
/// `k` uncertain by `uncertainty(k)` rad/s: the one detection behind [`velocity_jumps`] and the
/// simulator's rough boundaries.
pub fn rate_jumps(traj: &impl Trajectory, uncertainty: impl Fn(usize) -> f64) -> Vec<RateJump> {
    let durations = traj.piece_durations();
    let speed = |piece: usize, f: f64| {
        let qd = traj.piece_state(piece, f * durations[piece]).qd;
        qd[0].hypot(qd[1])
    };
    let mut out = Vec::new();
    let mut time = 0.0;
    for k in 0..durations.len().saturating_sub(1) {
        time += durations[k];
        if durations[k] <= 0.0 || durations[k + 1] <= 0.0 {
            continue;
        }
        let before = traj.piece_state(k, durations[k]);
        let after = traj.piece_state(k + 1, 0.0);
        let dq = [after.qd[0] - before.qd[0], after.qd[1] - before.qd[1]];
        let scale = [0.25, 0.5, 0.75, 1.0].iter().map(|&f| speed(k, f).max(speed(k + 1, 1.0 - f))).fold(1.0, f64::max);
        if dq[0].hypot(dq[1]) > (JUMP_TOLERANCE * scale).max(uncertainty(k)) {
            out.push(RateJump { after_piece: k, time, before, after });
        }
    }
    out
}

/// The rate jumps of `traj` ([`rate_jumps`]) with the motors' impulse `impulse(q, Δq̇)`.
pub fn velocity_jumps(
    impulse: impl Fn([f64; 2], [f64; 2]) -> [f64; 2],
    traj: &impl Trajectory,
    uncertainty: impl Fn(usize) -> f64,
) -> Vec<VelocityJump> {
    rate_jumps(traj, uncertainty)
        .into_iter()
        .map(|j| {
            let dq = [j.after.qd[0] - j.before.qd[0], j.after.qd[1] - j.before.qd[1]];
            VelocityJump {
                time: j.time,
                after_piece: j.after_piece,
                rates_before: j.before.qd,
                rates_after: j.after.qd,
                impulse: impulse(j.after.q, dq),
            }
        })
        .collect()
}

impl TwoMotorCat {
    /// The impulse the motors deliver when the joint rates jump by `dq` at `q`: the paper's cat's
    /// through the two-cylinder engine ([`generalised_impulse`]), any other's through the general
    /// core ([`TwoMotorCat::motor_impulse`]).
    pub fn jump_impulse(&self, q: [f64; 2], dq: [f64; 2]) -> [f64; 2] {
        match self.cat().paper() {
            Some(half) => generalised_impulse(half, q, dq),
            None => self.motor_impulse(q, dq),
        }
    }

    /// The rate jumps of `traj` on this model ([`velocity_jumps`] with
    /// [`TwoMotorCat::jump_impulse`]), the rate difference after piece `k` uncertain by
    /// `uncertainty(k)` rad/s.
    pub fn velocity_jumps(&self, traj: &impl Trajectory, uncertainty: impl Fn(usize) -> f64) -> Vec<VelocityJump> {
        velocity_jumps(|q, dq| self.jump_impulse(q, dq), traj, uncertainty)
    }
}

/// The paper's cat's generalised impulse `M(q) Δq̇`, N·m·s, of a jump `dq` of the joint rates at
/// `q` (on the universal joint the motors' impulse).
pub fn generalised_impulse(cat: &Cylinder, q: [f64; 2], dq: [f64; 2]) -> [f64; 2] {
    let impulse = reduced_mass_matrix(cat, q) * nalgebra::Vector2::new(dq[0], dq[1]);
    [impulse[0], impulse[1]]
}

/// The largest impulse of any jump, N·m·s (0 when none).
pub fn max_impulse(jumps: &[VelocityJump]) -> f64 {
    jumps.iter().flat_map(|j| j.impulse).map(f64::abs).fold(0.0, f64::max)
}
