//! The joint controller of a tracked run ([`mod@super::track`]): the seam a controller plugs into,
//! and the plan-tracking one, feed-forward of the planned torques plus joint PD.
//!
//! # The seam
//!
//! At each step `[t_k, t_k + h]` a [`Controller`] gets the time `t_k`, the joints' measured state
//! `(q, q̇)` (encoders: exact, no delay) and an estimate of A's attitude that is `δ` old and
//! noisy ([`AttitudeEstimate`], built by the run from its own history); it returns the joint
//! torques `(τ1, τ2)`, N·m, held over the step (zero-order hold). The run saturates them at the
//! actuators' limits and applies them; the controller never sees rapier.
//!
//! # Feed-forward plus PD
//!
//! [`FeedForwardPd`] commands
//!
//! $$ τ_j = τ^{ff}_j(t_k + h/2) + k_{p,j}\,(q^*_j(t_k) − q_j) + k_{d,j}\,(\dot q^*_j(t_k) − \dot q_j), $$
//!
//! with `q*` the schedule and `τ^ff` the torque the plan needs on the *nominal* cat
//! (Newton–Euler of the exact engine, [`crate::engines::torque`]; with the nominal release spin
//! when there is one), taken at the step's midpoint, where a held torque best matches a smooth
//! one. Both are tabulated once on the run's step grid ([`Plan`]) and shared by every trial.
//! The gains are those of a second-order servo on the straight cat's joint inertia:
//! `k_p = J ω_n²`, `k_d = 2 ζ ω_n J` with `J = I*/2` (`I*` a half's end-transverse inertia: at
//! `q = 0` with the base free and no momentum, each half turns by half the joint angle about the
//! joint, so `E = ¼ I* q̇²`). It ignores the attitude: a feedback controller on the attitude is
//! another implementation of the trait.
//!
//! ## References
//! - DESIGN.md §2 (the torques) and §9 (motors); issue 21 §2.

use nalgebra::{UnitQuaternion, Vector3};
use serde::Serialize;

use crate::engines::evaluate::{released_on, released_torques};
use crate::engines::models::TwoMotorCat;
use crate::model::Cylinder;
use crate::schedule::{JointState, Trajectory};

use super::pieces::Pieces;

/// The joints as their encoders read them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointReading {
    /// Joint angles, rad.
    pub q: [f64; 2],
    /// Joint rates, rad/s.
    pub qd: [f64; 2],
}

/// What the attitude sensor tells the controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttitudeEstimate {
    /// When the attitude was measured, s (the latency before now).
    pub measured_at: f64,
    /// A's world orientation then, with the sensor's noise.
    pub orientation: UnitQuaternion<f64>,
}

/// A joint controller: the torques to hold over the step that starts at `t`.
pub trait Controller {
    /// Joint torques `(τ1, τ2)`, N·m, from the time, the joints' reading and the attitude
    /// estimate.
    fn torques(&mut self, t: f64, joints: &JointReading, attitude: &AttitudeEstimate) -> [f64; 2];
}

/// A schedule on a run's step grid: the planned joint states at `t_k = k h` and the nominal
/// cat's feed-forward torques at the midpoints `t_k + h/2`.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The step, s.
    pub dt: f64,
    /// Planned state at each `t_k`, `k = 0 … n`.
    pub states: Vec<JointState>,
    /// Planned torques at each `t_k + h/2`, `k = 0 … n − 1`, N·m.
    pub feedforward: Vec<[f64; 2]>,
}

impl Plan {
    /// The plan of `traj` on `nominal` released with `spin` (world frame, N·m·s; the exact
    /// engine integrates the attitude the spinning torques need to `tolerance`), on `n` steps.
    pub fn new(nominal: &Cylinder, traj: &impl Trajectory, spin: &Vector3<f64>, tolerance: f64, n: usize) -> Plan {
        let pieces = Pieces::new(traj);
        let duration = pieces.duration();
        let dt = duration / n.max(1) as f64;
        let at = |k: usize| if k >= n { duration } else { k as f64 * dt };
        let states = (0..=n).map(|k| pieces.state(at(k))).collect();
        let model = TwoMotorCat::paper(*nominal);
        let (_, history) = released_on(&model, traj, spin, tolerance);
        let source = released_torques(&model, history.as_ref());
        let feedforward = (0..n)
            .map(|k| {
                let (piece, s) = pieces.locate((k as f64 + 0.5) * dt);
                let state = traj.piece_state(piece, s);
                source.at(traj, piece, s, &state).tau
            })
            .collect();
        Plan { dt, states, feedforward }
    }

    /// Number of steps.
    pub fn steps(&self) -> usize {
        self.feedforward.len()
    }

    /// The planned state at step `k` (the last one beyond the plan: the cat holds its end pose).
    pub fn state(&self, k: usize) -> JointState {
        self.states[k.min(self.states.len() - 1)]
    }

    /// The feed-forward torque of step `k` (none beyond the plan).
    pub fn feedforward(&self, k: usize) -> [f64; 2] {
        self.feedforward.get(k).copied().unwrap_or([0.0; 2])
    }
}

/// Joint PD gains, per joint.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PdGains {
    /// Stiffness `k_p`, N·m/rad.
    pub kp: [f64; 2],
    /// Damping `k_d`, N·m·s/rad.
    pub kd: [f64; 2],
}

impl PdGains {
    /// The servo of natural frequency `hz` (Hz) and damping ratio `zeta` on `cat`'s straight
    /// joint inertia `J = I*/2` (module docs), both joints alike.
    pub fn servo(cat: &Cylinder, hz: f64, zeta: f64) -> PdGains {
        let j = 0.5 * cat.end_transverse();
        let w = std::f64::consts::TAU * hz;
        PdGains { kp: [j * w * w; 2], kd: [2.0 * zeta * w * j; 2] }
    }

    /// Each joint's gains scaled by its factor.
    pub fn scaled(&self, factor: [f64; 2]) -> PdGains {
        PdGains {
            kp: std::array::from_fn(|j| self.kp[j] * factor[j]),
            kd: std::array::from_fn(|j| self.kd[j] * factor[j]),
        }
    }
}

/// Feed-forward of the plan plus joint PD (module docs); ignores the attitude.
#[derive(Clone, Debug)]
pub struct FeedForwardPd<'a> {
    plan: &'a Plan,
    gains: PdGains,
}

impl<'a> FeedForwardPd<'a> {
    /// Tracks `plan` with `gains` (zero gains: feed-forward alone).
    pub fn new(plan: &'a Plan, gains: PdGains) -> Self {
        Self { plan, gains }
    }
}

impl Controller for FeedForwardPd<'_> {
    fn torques(&mut self, t: f64, joints: &JointReading, _attitude: &AttitudeEstimate) -> [f64; 2] {
        let k = (t / self.plan.dt).round().max(0.0) as usize;
        let (target, ff) = (self.plan.state(k), self.plan.feedforward(k));
        std::array::from_fn(|j| {
            ff[j] + self.gains.kp[j] * (target.q[j] - joints.q[j]) + self.gains.kd[j] * (target.qd[j] - joints.qd[j])
        })
    }
}
