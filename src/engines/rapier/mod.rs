//! Verification of schedules in rapier3d (f64): an independent multibody simulator tracks the
//! joint trajectory with motors, and we measure how the cat turns (DESIGN.md §6).
//!
//! # Scene
//!
//! Zero gravity and no colliders (a tracked run that asks for a landing, [`mod@track`] with
//! [`ground`], adds gravity, colliders and the ground to its own scene only). Falling freely, the centre of mass follows the ballistic
//! parabola and gravity exerts no torque about it, so the rotation about the centre of mass is
//! the same as in weightlessness: simulating the falling frame with `g = 0` loses nothing.
//!
//! Three dynamic bodies form one rapier multibody (reduced coordinates):
//! - **A**, the root, floating (six free DoFs), centre at the origin, identity orientation;
//! - **the cross** of the universal joint, a tiny body (mass `f · m̄` with
//!   `f = rapier.cross_mass_fraction` and `m̄` the halves' mean mass, inertia of a solid sphere of
//!   their mean radius), centre at
//!   the joint point. Rapier's multibody joints with two free angular axes hit a `todo!()`, so the
//!   universal joint is two revolute joints with this body between them;
//! - **B**, the rear half.
//!
//! Joint 1 is revolute about A's `x` at A's local point `(0, 0, −l_A/2)` (the cross's origin);
//! joint 2 is revolute about the cross's `y`, at B's local point `(0, 0, +l_B/2)`. So
//! `R_AB(q) = Rx(q1) · Ry(q2)` (DESIGN.md §1): at `q = (0.3, 0)` B's axis is `Rx(0.3) ẑ` in A's
//! frame. Each body's body frame is at its centre of mass with `z` along the spine; mass
//! properties are set explicitly: `diag(m(3r² + l²)/12, m(3r² + l²)/12, m r²/2)` for each half,
//! with each half's own `m`, `l`, `r` (DESIGN.md §10: the halves may differ; the paper's cat has
//! `l_A = l_B = l`). The exact engine's side of a verification
//! (time scales, motor demand, spin history) is the two-cylinder engine for the paper's cat and
//! the general core ([`crate::engines::models::TwoMotorCat`]) for any other.
//! Sleeping is off, and rapier's default damping of multibody DoFs (0.1 on every angular DoF,
//! the floating root's included) is zeroed: it would bleed angular momentum.
//!
//! **The no-twist joint** (Kane and Scher's, `R_AB = exp([q1, q2, 0]×)`) is a rapier spherical
//! multibody joint (three free angular DoFs, which rapier implements; two hit the `todo!()`) from
//! A's `(0, 0, −l_A/2)` to **the ball**, a tiny body like the cross, welded to B at B's
//! `(0, 0, +l_B/2)` by a fixed joint ([`Layout::Ball`]). Its generalized velocities are
//! the relative angular velocity `ω_rel` in A's frame, and rapier turns the joint by
//! `R_rel ← exp(h ω_rel) R_rel` per step; so its three motors act about A's `x`, `y` and `z`, and
//! their generalized forces are the couple's components on A's axes. The motors cannot hold a
//! rotation vector (rapier's angular coordinates there are the integral of `ω_rel`, not an
//! angle), so each step aims the two about `x` and `y` at `w = log(R(q(t_{k+1})) R_relᵀ)/h`, the
//! relative rate that carries the present rotation onto the schedule's over the step, with the
//! same gains ([`CatScene::set_plan`]); any drift is taken out at the next step. The one about `z`
//! holds the joint's constraint: a no-twist joint's rates satisfy `ω_rel·(ẑ + e) = 0` (`e` B's
//! spine in A's frame), so it aims at the `ω_z` that keeps it for the step's `ω_x, ω_y`, less
//! the twist already there over `h` (`untwisting_rate` in `scene.rs`; the run records the largest
//! twist, [`RapierRun::spine_twist_max`]). The joint's coordinates are read back as the rotation
//! vector of `R_A⁻¹ R_B`, and its motor torques are the couple on {ball, B} about the joint point
//! projected on A's `x` and `y` (DESIGN.md §10). With motor limits the bounds go to the motors
//! about `x` and `y`, at the joint's coordinate rates `q̇` (least squares from `ω_rel`); the one
//! about `z` is the joint's constraint, not a motor, and stays unbounded, so a clipped motor
//! leaves the halves untwisted (to `O(h²)`). This scene does not build the spherical joint's
//! third motor ([`RapierError::UnsupportedJoint`]): the tree scene does (below).
//!
//! # Motors
//!
//! Each joint has rapier's acceleration-based motor: per step, an implicit (backward-Euler)
//! spring–damper on the joint coordinate, solved as a velocity constraint whose effective mass is
//! the coordinate's apparent inertia `1/(M⁻¹)_ii` (floating base free). With rapier's stiffness
//! `k` and damping `c` (accelerations per unit error) and one solver substep of length `h`,
//!
//! $$ \frac{v^+ - v}{h} = -k\,\big(q + h v^+ - q_t - h v_t\big) - c\,(v^+ - v_t)
//!    \quad(\text{plus the free dynamics}), $$
//!
//! so the spring acts on the end-of-step position `q⁺ = q + h v⁺` against `q_t + h v_t`. We set,
//! at the step from `t_k` to `t_{k+1}`, the targets from the schedule at `t_{k+1}`:
//! `v_t = q̇(t_{k+1})` and `q_t = q(t_{k+1}) − h q̇(t_{k+1})`, so that the spring pulls `q⁺` to
//! exactly `q(t_{k+1})` (without the shift the joint would lead the schedule by `h q̇`).
//!
//! Gains: `k = ω_n²`, `c = 2ζω_n` with `ω_n = α / h` (default `α = 20`, `ζ = 1`). Scaling with
//! the step keeps the discrete servo the same at every `dt` (backward Euler puts the critically
//! damped servo's double pole at `z = 1/(1 + α)`, ≈ 0.048: an error shrinks about twentyfold per
//! step), and the acceleration-based
//! model scales the torque by the joint's apparent inertia, so the choice does not depend on the
//! cat's size either. Softer gains are worse, not more physical: a PD servo without acceleration
//! feed-forward answers a jump of `q̈` with a 13.5 % torque overshoot (critically damped, at
//! `t = 2/ω_n`) and lags by `q̈/ω_n²`; at `α ≳ 10` both are below the step's resolution. The
//! implicit motor is stable at any gain. Rapier's velocity solver runs one substep per step (so
//! the targets are fresh at every substep) with enough Gauss–Seidel sweeps (default 8) to settle
//! the coupling of the two motor rows.
//!
//! With motor limits ([`RapierOptions::motors`]) each motor's torque is bounded at every step by
//! what the actuator has at the joint's speed, and the steps where the schedule needs more are
//! counted ([`saturation`]); ideal motors are unbounded.
//!
//! # Measurements
//!
//! Rapier holds, after step `k`, the poses `x_k` and the generalized velocities `v_k` with which
//! they were reached (symplectic Euler, `x_k = x_{k−1} ⊕ h v_k`). Body velocities are mapped
//! from `v` at the current poses (see [`scene`]).
//!
//! - **Orientation**: A's world orientation, split into twist and swing by
//!   [`crate::model::orientation`], the twist continued with a [`crate::model::orientation::TwistTracker`].
//! - **Joint angles**: rapier's joint coordinates (checked in the tests against the bodies'
//!   relative rotations); tracking error `max_k |q_k − q(t_k)|`.
//! - **Angular momentum** about the common centre of mass `c` of A, the cross and B, from the
//!   state `(x_k, v_k)`: `H = Σ R I Rᵀ ω + m (x − c) × (v − v_c)`; its drift `max_k |H_k − H_0|`,
//!   absolute and relative to `I* · max|q̇|` (`I*` the end-transverse inertia, `|q̇|` Euclidean).
//! - **Joint torques**, inferred from motion (rapier does not write back the impulses of a
//!   multibody's internal motors). Joint 1 drives the subsystem {cross, B}, joint 2 drives {B};
//!   both act at the joint point `P`. For a subsystem `S` with angular momentum `H_P` about the
//!   moving point `P` and linear momentum `p_S`, the couple the joint applies is
//!
//! $$ T = \dot H_P + v_P × p_S, \qquad τ_1 = a_1 · T_{\{C,B\}}, \quad τ_2 = a_2 · T_{\{B\}}, $$
//!
//!   with `a_1` A's `x` and `a_2` the cross's `y` in the world (Featherstone 2008, §2.12:
//!   the rate of a moment of momentum about a moving point). The velocity at `t_k` is
//!   `v̄_k = (v_k + v_{k+1})/2` (second order, as `v_k` belongs to `t_{k−½}`), body velocities
//!   are mapped from it at `x_k`, and `Ḣ_P(t_k) = (H̄_{k+1} − H̄_{k−1}) / 2h`. A torque sample
//!   thus depends on the motion over `[t_{k−2}, t_{k+2}]`. Samples within four steps of a phase
//!   boundary or of the start of the run (the stencil, and the servo settling after a jump of
//!   `q̈`; the cat starts from rest: `run.rs`'s `settling`) are kept out of the per-phase peaks,
//!   which are thereby comparable with the exact engine's one-sided values.
//!   Inside a piece, a jump of `q̈` (a trajectory reports them, [`crate::schedule::Trajectory::acceleration_jumps`]:
//!   the certified retiming's grid nodes) leaves the servo ringing for about eight steps, with
//!   an overshoot of about a tenth of the torque jump at every step size (measured on the
//!   retimed paper path at r = 0.05 m: 7.83 → 7.55 N·m against the exact 6.68 → 6.44 N·m as `h`
//!   falls from 434 to 54 µs); samples within six steps of a jump larger than 1 % of the
//!   largest `‖q̈‖` are kept out of the peaks too, and the fraction excluded is kept with the run ([`RapierRun::acceleration_jump_excluded`]; not in the reports).
//!   Samples within six steps of a jump of `q̇` (the paper's cosine profile ends at `2ω0`, so
//!   unbending starts with one) are reported apart ([`JumpTorque`]): the motors answer a jump
//!   with an impulse, a spike whose height grows as `1/h` while its area `Σ (τ − τ_smooth) h`
//!   converges to the generalized impulse `M(q) Δq̇`.
//!
//! # Accuracy
//!
//! Rapier's multibody integrator is first order: a free body's angular momentum drifts by
//! `O(h)` (its gyroscopic and Coriolis terms are taken semi-implicitly), and with zero momentum
//! the twist is a geometric phase of the joint path, so that drift, not the (tiny) tracking error,
//! sets the twist error. On the paper problem at `h` = 1 ms the drift reaches 1.4–1.6 % of
//! `I* max|q̇|` and the twist is off by 4.7° (cycloidal profile) to 12.4° (the paper's); both
//! halve with `h`. [`dt_sweep`] measures the convergence and [`extrapolate`] removes the
//! leading error (Richardson, order 1). Gravity-free stepping at 60 Hz is far outside the
//! asymptotic range for this manoeuvre.
//!
//! So no rapier number stands alone: [`verify`] chooses the first step from the trajectory's own
//! time scales ([`time_scales`]), halves it until the Richardson estimate of rapier's own error
//! meets the tolerances of [`crate::problem::settings::RapierSettings`], and ends in a [`Verdict`]
//! (`verified`, `not verified` with the quantity and the gap, or `inconclusive` with why).
//!
//! # Trees of bodies
//!
//! The cats beyond two motors (the spherical joint's three, a tail's one or two more, the legs'
//! hinges) run in the tree scene ([`tree_scene`]): any [`crate::model::tree::Tree`] in one
//! multibody, every link built as this scene builds its joint (two revolutes and a cross, a ball
//! welded to the child, all three of its motors aimed on the spherical joint, or a hinge's
//! revolute welded to the child), driven along a shape trajectory of any
//! number of coordinates and measured and verified as here ([`tree_run`]: the same step
//! refinement and verdict, each motor's torque from Newton–Euler on the bodies it drives). On a
//! two-body cat it runs as this scene does (`tests/rapier_tree.rs`). So far it runs ideal motors,
//! no spin and smoothly joined trajectories (the whole optimiser's splines).
//!
//! # Tracked runs
//!
//! The verification drives the joints with rapier's motors. A tracked run ([`mod@track`]) instead
//! leaves the joints free and applies explicit joint torques from a [`Controller`] ([`control`]:
//! the seam, and feed-forward plus PD), saturated at the actuators' limits, with an attitude
//! sensor that is late and noisy: the robustness check's trials ([`crate::robust`]).
//!
//! # Trajectories
//!
//! Every run takes any [`crate::schedule::Trajectory`]: pieces smooth on their closed
//! intervals, rates possibly jumping between them. Torque peaks are kept per piece
//! (`TorquePeaks` in [`RapierRun`]; the per-phase view of a three-piece schedule is its `phase_peaks`), and
//! samples near any piece boundary or rate jump are treated as described above for phases.
//!
//! ## References
//! - rapier documentation, <https://rapier.rs/docs/> and <https://docs.rs/rapier3d-f64/0.36>
//!   (multibody joints, joint motors, `IntegrationParameters`);
//! - R. Featherstone, *Rigid Body Dynamics Algorithms*, Springer (2008), ch. 2 and 4;
//! - DESIGN.md §1, §2 and §6.

mod bodies;
pub mod control;
pub mod feedback;
pub mod ground;
mod measure;
mod pieces;
mod refinement;
mod run;
pub mod saturation;
pub mod scene;
mod spin;
mod timescale;
pub mod track;
pub mod tree_run;
pub mod tree_scene;
mod verdict;
mod verify;
mod verify_text;

pub use bodies::{BodyState, Layout, MassModel, Snapshot};
pub use control::{AttitudeEstimate, Controller, FeedForwardPd, JointReading, PdGains, Plan};
pub use feedback::{lqr_gains, Feedback, FeedbackLog, FeedbackPlan, FeedbackSettings, Linearisation, Regulator};
pub use ground::{Landing, Part, Touchdown};
pub use measure::{angular_momentum, kinetic_energy, observed_orders, TorqueEstimator, TorqueSample};
pub use run::{
    dt_sweep, extrapolate, simulate, simulate_with, swing_vector, Extrapolated, JumpTorque, MomentumDrift, RapierRun,
    TwistSample,
};
pub use saturation::{available_torque, MotorSaturation, SATURATION_TOLERANCE};
pub use scene::{CatScene, MotorGains};
pub use spin::{spin_free, SpinRun, SpinTest};
pub use timescale::{
    time_scales, time_scales_within, tree_time_scales, StepLimit, TimeScales, ANGLE_PER_STEP, SAMPLES_PER_PIECE,
    STEPS_PER_PIECE, STEPS_PER_TORQUE_TIME,
};
pub use track::{track, AttitudeSensor, TrackOptions, TrackedRun};
pub use verdict::{
    Convergence, Failure, Quantity, Reference, RunRecord, Status, StepSource, Verdict, Verification, ASYMPTOTIC,
    MIN_RUNS,
};
pub use verify::{verify, verify_with};

use nalgebra::Vector3;

use crate::model::motor::Motors;
use crate::problem::ProblemError;

/// First-order Richardson extrapolation with step ratio `r = dt_c/dt_f > 1` of a coarse value
/// `c` and a fine one `f` (numbers or vectors): `x_f + (x_f − x_c)/(r − 1)`.
pub fn richardson<V>(c: V, f: V, r: f64) -> V
where
    V: std::ops::Sub<Output = V> + std::ops::Add<Output = V> + std::ops::Mul<f64, Output = V> + Copy,
{
    f + (f - c) * (1.0 / (r - 1.0))
}

/// Each motor's peak extrapolated on its own ([`richardson`]) from two runs' peaks `coarse` and
/// `fine` (each motor's, in the same order; [`RunRecord::motor_peaks_nm`]), their steps `r`
/// apart. The peak torque at `dt → 0` is the largest of them ([`largest`]): the largest raw peak
/// can pass from one motor to another as the step shrinks (a servo's ripple, first order in the
/// step, lifting a motor that does not peak in the plan above one that does), and an
/// extrapolation across that change lands on neither (a cat with a tail and legs: 2.0 % below the
/// plan's peak by the largest raw peak, 0.0075 % motor by motor).
pub fn richardson_peaks(coarse: &[f64], fine: &[f64], r: f64) -> Vec<f64> {
    coarse.iter().zip(fine).map(|(c, f)| richardson(*c, *f, r)).collect()
}

/// The largest of `values`; NaN when any is not a number (an extrapolation that is not a number
/// is said so, never dropped), 0 when there are none.
pub fn largest(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m: f64, v| if m.is_nan() || v.is_nan() { f64::NAN } else { m.max(*v) })
}

/// Why a rapier run could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RapierError {
    /// The settings are out of range.
    #[error(transparent)]
    Settings(#[from] ProblemError),
    /// The cat model cannot run the schedule.
    #[error(transparent)]
    Model(#[from] crate::engines::models::ModelError),
    /// An option of the run is out of range.
    #[error("{field} = {value}: {reason}")]
    BadOption {
        /// Which option.
        field: &'static str,
        /// Its value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// The scene has no joint of this kind (or this use of it): it builds the universal and the
    /// no-twist joints, and only the universal joint's scene takes applied joint torques.
    #[error("cat.joint = \"{0}\": rapier's scene builds the universal joint (two revolute joints and a cross) and the no-twist joint (a ball joint) for tracked schedules, not this joint or this use of it, so far; the exact engine runs it (`simulate --engine exact`)")]
    UnsupportedJoint(crate::model::Joint),
    /// A body of a tree whose inertia is not diagonal in its own frame ([`tree_scene`]).
    #[error("body {0} of the tree has an inertia that is not diagonal in its own frame: rapier's tree scene takes bodies with their principal axes along their frames (cylinders, rods)")]
    NotPrincipal(usize),
    /// What the tree scene does not run so far ([`tree_run`]).
    #[error("rapier's scene of a tree of bodies {0}")]
    TreeScope(String),
    /// Rapier refused to build a joint.
    #[error("rapier refused {0}")]
    JointRejected(&'static str),
    /// Part of the scene was not found where it was built.
    #[error("rapier's multibody lacks {0}")]
    Missing(&'static str),
    /// The schedule has no positive, finite duration.
    #[error("the schedule's duration {0} s is not positive and finite")]
    BadDuration(f64),
    /// The requested step needs more steps than a run allows.
    #[error("dt = {dt} s over {duration} s needs {steps:.3e} steps, more than the {max} allowed")]
    TooManySteps {
        /// Requested step, s.
        dt: f64,
        /// Duration, s.
        duration: f64,
        /// Steps needed.
        steps: f64,
        /// The limit, [`MAX_STEPS`].
        max: usize,
    },
    /// The verification made no usable run at all, so rapier has no number to report.
    #[error("rapier has no result for this schedule: {0}")]
    NoResult(String),
    /// The simulation produced non-finite numbers.
    #[error("the simulation diverged (non-finite state) at t = {0} s")]
    Diverged(f64),
    /// A tracked trial of the robustness check diverged: which one, under which controller, when,
    /// at which step.
    #[error("robust: {trial} ({controller}) diverged in rapier (non-finite state) at t = {at:.4} s with robust.dt_s = {dt:e} s: the tracked scene is unstable at this step; {remedy} (on the paper's cat trials diverge from 5e-4 s open loop and from 4e-4 s with feedback)", remedy = crate::problem::robust::SERVO_REMEDY)]
    TrialDiverged {
        /// "trial K" (from 1) or "the nominal cat".
        trial: String,
        /// "open loop" or "attitude feedback".
        controller: &'static str,
        /// When, s.
        at: f64,
        /// The rapier step, s.
        dt: f64,
    },
    /// The step is too coarse to resolve the shortest phase.
    #[error("rapier.dt = {dt} s leaves only {steps:.1} steps in the shortest phase ({phase} s); at least {min} are needed to measure its torques")]
    TooCoarse {
        /// Requested step, s.
        dt: f64,
        /// Duration of the shortest phase, s.
        phase: f64,
        /// Steps it would get.
        steps: f64,
        /// The least accepted, [`MIN_STEPS_PER_PHASE`].
        min: usize,
    },
}

/// Fewest steps a phase may get: torque samples within a few steps of a phase boundary are left
/// out of the peaks, so a phase needs many more than that.
pub const MIN_STEPS_PER_PHASE: usize = 10;

/// Most steps a run may take.
pub const MAX_STEPS: usize = 20_000_000;

/// Options of a rapier run that are not `[rapier]` settings (those are in
/// [`crate::problem::settings::RapierSettings`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RapierOptions {
    /// `α = ω_n · dt`: the motors' natural frequency in units of the step rate.
    pub bandwidth_per_step: f64,
    /// The motors' damping ratio `ζ`.
    pub damping_ratio: f64,
    /// Gauss–Seidel sweeps of the velocity solver per step.
    pub pgs_iterations: usize,
    /// Most samples kept in each history (the run is decimated evenly to fit).
    pub history: usize,
    /// The joints' motors (a problem's `[actuator]`, [`crate::problem::Problem`]): their limits
    /// bound the torque of rapier's motors, and a verification reports when the schedule needed
    /// more ([`saturation`]). Ideal by default.
    pub motors: Motors,
    /// Total angular momentum at release, world frame, N·m·s (a problem's
    /// `drop.angular_momentum`): the scene starts with the rigid rotation that gives the cat this
    /// momentum ([`scene::CatScene::start_with_momentum`]). Zero by default.
    pub spin: Vector3<f64>,
}

impl Default for RapierOptions {
    fn default() -> Self {
        Self {
            bandwidth_per_step: 20.0,
            damping_ratio: 1.0,
            pgs_iterations: 8,
            history: 2000,
            motors: Motors::ideal(),
            spin: Vector3::zeros(),
        }
    }
}

impl RapierOptions {
    /// The default options with `motors`.
    pub fn within(motors: Motors) -> Self {
        Self { motors, ..Self::default() }
    }

    /// The default options for `problem`: its motors and its release spin.
    pub fn for_problem(problem: &crate::problem::Problem) -> Self {
        Self { motors: problem.actuator.motors(), spin: problem.drop.spin(), ..Self::default() }
    }

    fn validate(&self) -> Result<(), RapierError> {
        let bad = |field, value: f64, reason| Err(RapierError::BadOption { field, value, reason });
        if !(self.bandwidth_per_step.is_finite() && self.bandwidth_per_step > 0.0) {
            return bad("bandwidth_per_step", self.bandwidth_per_step, "must be positive and finite");
        }
        if !(self.damping_ratio.is_finite() && self.damping_ratio >= 0.0) {
            return bad("damping_ratio", self.damping_ratio, "must be non-negative and finite");
        }
        if self.pgs_iterations == 0 || self.pgs_iterations > 1000 {
            return bad("pgs_iterations", self.pgs_iterations as f64, "must be between 1 and 1000");
        }
        Ok(())
    }
}
