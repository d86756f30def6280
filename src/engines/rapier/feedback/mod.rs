//! Feedback on the attitude that corrects the flip (issue 21 §3): time-varying LQR on the
//! reduced dynamics linearised along the plan, fed by a Kalman filter that estimates the
//! attitude error and the unknown release spin from the late, noisy attitude sensor.
//!
//! # LQR along the plan, and a re-plan on top of it
//!
//! The plan is optimal for the nominal cat; a trial's cat differs by its mass (which only
//! rescales the spin's effect: `I_lock` and `h` both scale with `m`, so at zero momentum the
//! flip is mass-free) and by its release spin. These are small perturbations of the plan, so the
//! linearisation along it is the model a re-plan would locally solve anyway. Its Riccati sweep
//! is done once per check, not per trial ([`lqr_gains`]; `benches/feedback.rs` on the paper's
//! schedule at 1 kHz, a quiet two-core machine: 0.87 ms from the release, 0.44 ms from mid-fall,
//! the linearisation 14.1–14.7 ms, its instants and nodes in parallel), and the loop then costs a
//! 2 × 10 product per control step (a trial 217 ms against the open loop's 188 ms).
//!
//! Measured on the paper's whole optimum (`catflip robust problems/paper.toml --schedule
//! results/paper/schedules/whole-optimum.csv --set robust.engine=both --set robust.landing=true
//! --set robust.controller=both`, the filter's spin prior 0.001 N·m·s): 95th percentile 1.50°
//! (twist 1.32°, swing 0.94°) against the
//! open loop's 45.97°. The largest errors are swing the linear model does not predict: the
//! largest spins need joint corrections of 10–15°, where the second-order coupling of twist
//! into swing is no longer small.
//!
//! # The re-plan (`robust.feedback_replan_hz`)
//!
//! Those errors are what a re-plan of the rest of the fall from the current estimate is for. Two
//! re-plans were possible; this one is argued against the other:
//!
//! - **The whole optimiser, warm-started from the plan** ([`crate::optimize::whole`]) minimises
//!   the peak torque over the spline coefficients of the *whole* fall subject to an exact flip,
//!   each iteration a Clarabel subproblem on the exact engine's forward sensitivities. On the
//!   paper's cat it takes 1.2–1.9 s from its starts (README); even a warm start that converged
//!   in a few iterations would be a hundred times the 10 ms, and its answer (a new
//!   torque-optimal flip of a nominal cat) is not the question asked mid-fall (land this cat,
//!   with this spin, from here).
//! - **One iteration of iterative LQR on the exact reduced dynamics of the attitude error**
//!   ([`Regulator::replan`]; Li and Todorov 2004, with Tassa et al.'s box-constrained
//!   inputs). The cost is the regulator's own `J` above, from node `c` (now) to `T`; the
//!   dynamics are the nonlinear error dynamics `ė = f(t, x)` relative to the plan
//!   ([`error_rate`]: `Ω` of the engine, no linearisation), whose linearisation at `x = 0` is
//!   exactly the plan's node. From the estimate `x̂_c`, the policy in force is rolled out
//!   (the motion the regulator now expects), the dynamics linearised about that motion
//!   ([`linearise`], with the roll-out's defects as affine terms), the Riccati sweep re-solved
//!   about it with the bound `|u| ≤ a` (gains `K_i` and offsets `κ_i`: `u = −K_i x − κ_i`), and
//!   the step searched so that the expected cost falls. Warm-starting is the point: each re-plan
//!   starts from the policy the last one left, so successive re-plans are successive Newton-type
//!   iterations on the shrinking horizon — the *real-time iteration* of nonlinear MPC (Diehl,
//!   Bock and Schlöder 2005): one iteration per sampling instant, carried over between instants,
//!   rather than a converged solve each time.
//!
//! The second is chosen. It re-uses the plan's attitudes `R*` (no new integration of the exact
//! engine: the motion is described relative to the plan), so its cost is per remaining node:
//! one roll-out (13 rate evaluations a node, with the linearisation), one 10 × 10 Riccati step,
//! and at most four roll-outs of the line search. Measured (`cargo bench --bench feedback --
//! replan`, the paper's schedule at 1 kHz, a state off the plan of the size a 2σ spin leaves,
//! the two-core machine shared with another job): 1.8 ms from mid-fall, 4.6 ms from the release,
//! within the 10 ms; in the loop (the 1,562 re-plans of a 20-trial check at 50 Hz, each timed) median
//! 1.9 ms, 95th percentile 4.0 ms. From the plan's own state (`x̂ = 0`) the roll-out is the plan, the
//! nodes and gains come back to the bit and the offsets are zero (`tests/replan.rs`), so a cat
//! that follows the plan is not disturbed by re-planning.
//!
//! **In the loop.** Every `1/(feedback_replan_hz · Δ)` control steps (rounded to a whole number; not
//! at the release, where the plan's own gains are in force) the controller re-plans from its
//! predicted present state, then acts on the new policy in the same step (the compute time, below
//! a re-plan's interval at 50 Hz, is not simulated). The filter predicts with the nodes in force
//! (the re-plan's from its node on, the earlier ones kept for the sensor's latency). At 0 Hz, the
//! default, the loop is the LQR along the plan above, bit for bit.
//!
//! Measured on the same trials as above (`… --set robust.engine=rapier --set robust.landing=true
//! --set robust.controller=feedback --set robust.feedback_replan_hz=50`): 95th percentile 0.79°
//! (largest 1.47°, swing at most 1.14°) against 1.50° (5.54°, 4.18°) with the gains along the
//! plan; 0.78° at 100 Hz; 0.75° and 0.74° on seeds 2 and 3 (1.78° and 1.77° without re-plans).
//!
//! # The linearised reduced dynamics
//!
//! A's attitude obeys `Ṙ = R [Ω]×` with `Ω = I_lock(q)⁻¹ (Rᵀ L − h(q, q̇))`
//! ([`crate::engines::exact::body_rate_spinning`]). Along the plan `(q*, q̇*, R*)` on the nominal
//! cat with the nominal spin `L₀`, write `R = R* exp([e]×)` (the error in A's frame),
//! `q = q* + δq` and `L/s = L₀ + d` (`s` the mass factor: `d` is the spin the nominal model
//! needs to explain the trial). To first order
//!
//! $$ \dot e = \big(−[Ω^*]_× + I_{lock}^{-1} [λ^*]_×\big)\, e + \frac{∂Ω}{∂q} δq + \frac{∂Ω}{∂\dot q} δ\dot q + I_{lock}^{-1} R^{*\top} d, \qquad δ\ddot q = u, \qquad \dot d = 0, $$
//!
//! `λ* = R*ᵀ L₀`, the Jacobians by central differences of the engine's `Ω` on the control grid
//! `t_i = i Δ` (`Δ = 1/rate`, a whole number of the run's steps). The state
//! `x = (e, δq, δq̇, d) ∈ ℝ¹⁰` is discretised over `Δ` (Euler for `e`, exact for the double
//! integrator with `u` held), and the finite-horizon LQR
//!
//! $$ J = x_N^\top Q_f x_N + \sum_i \frac{Δ}{T}\Big(\frac{|e_i|^2}{θ_e^2} + \frac{|δq_i|^2}{θ_q^2} + \frac{(0.1\,{\rm s})^2 |δ\dot q_i|^2}{θ_q^2} + \frac{|u_i|^2}{a^2}\Big), \quad Q_f = {\rm diag}(θ_e^{-2}, θ_q^{-2}, (0.1\,{\rm s})^2 θ_q^{-2}, 0) $$
//!
//! (Bryson's scales: `θ_e` the attitude error, `θ_q` the joint correction, `a` its acceleration)
//! gives `u_i = −K_i x_i` by the backward Riccati sweep. The spin `d` is uncontrollable but
//! known to the regulator: its columns of `K` are the feed-forward that aims the flip at where
//! the spin will have carried the cat by `T`.
//!
//! **End of the fall.** As the cat straightens, `∂Ω/∂q` vanishes and the attitude is no longer
//! controllable. The input weight `|u|²/a²` keeps `(R + ΓᵀPΓ)` at least `Δ/(T a²)`, so the
//! gains stay bounded (measured in the tests) instead of blowing up; the terminal weights on
//! `δq, δq̇` bring the joints back to the plan's end pose.
//!
//! # The estimator
//!
//! The joints are measured exactly; the attitude `δ` late with noise `σ` per axis. A Kalman
//! filter on `z = (e, d)` runs at every step of the run *in the sensor's time*: it predicts with
//! the model above (the measured `δq, δq̇` as known inputs, process noise on `e` for the
//! linearisation's error and a slow walk on `d`) and updates with `y = log(R*(t_j)ᵀ R̃_j) = e_j + σ n`.
//! At each control step the estimate is carried from `t_j = t − δ` to `t` through the same model
//! with the recorded joints (a Smith predictor), so the regulator acts on the present.
//!
//! The prior on `d` (`robust.feedback_spin_prior_nms`, also the scale of its slow walk) is a
//! tuning, not the spins' spread: a prior as wide as the spins lets the filter read the
//! sensor's early noise as spin, which the regulator's feed-forward columns then act on at full
//! gain. On the paper's whole optimum the 95th percentile falls from 3.07° at a prior of 0.01
//! N·m·s to 1.50° at 0.001, and rises again to 4.98° at 0.0001, where the spin goes uncorrected
//! (README, "Feedback that corrects the flip", for the whole scan and two validation seeds).
//!
//! # Actuation, joint limits and saturation
//!
//! `u` moves a reference `(δq_r, δq̇_r)` (the double integrator the LQR assumes), which the
//! joint servo of [`super::FeedForwardPd`] tracks: `τ = τ^{ff} + J u + k_p (q* + δq_r − q) +
//! k_d (q̇* + δq̇_r − q̇)` with `J = I*/2`. `|u| ≤ a`; the reference keeps `|δq_r| ≤ 3 θ_q`, the
//! joint limit of the correction (the model's joints have none of their own; its rate is zeroed
//! at the bound), so the corrected motion stays near the plan the linearisation is of; and it runs at most [`MAX_LAG`]
//! ahead of the joint it drives (anti-windup when the actuators saturate and the joint cannot
//! follow: the run clamps the torque, the filter sees the joint where it really is).
//!
//! ## References
//! - B. D. O. Anderson, J. B. Moore, *Optimal Control: Linear Quadratic Methods* (1990), ch. 2;
//! - A. E. Bryson, Y.-C. Ho, *Applied Optimal Control* (1975), for the weights' scales;
//! - O. J. M. Smith, *Closer control of loops with dead time*, Chem. Eng. Prog. 53 (1957);
//! - W. Li, E. Todorov, *Iterative linear quadratic regulator design for nonlinear biological
//!   movement systems*, ICINCO (2004);
//! - Y. Tassa, N. Mansard, E. Todorov, *Control-limited differential dynamic programming*, ICRA
//!   (2014);
//! - M. Diehl, H. G. Bock, J. P. Schlöder, *A real-time iteration scheme for nonlinear
//!   optimization in optimal feedback control*, SIAM J. Control Optim. 43 (2005).

mod linear;
mod replan;
mod riccati;

use std::ops::{AddAssign, SubAssign};

use nalgebra::{Matrix3, SMatrix, SVector, Vector2, Vector3};
use serde::Serialize;

use super::control::{AttitudeEstimate, Controller, JointReading, PdGains, Plan};
use crate::model::Cylinder;
use crate::schedule::Trajectory;

pub use linear::{error_rate, linearise, Linearisation, Node, PlanPoint, State};
pub use replan::Regulator;
pub use riccati::{lqr_gains, Gain};

/// Largest lead of the reference over the joint it drives, rad (anti-windup; 2°).
pub const MAX_LAG: f64 = 2.0 * std::f64::consts::PI / 180.0;
/// Process noise of the attitude error in the filter, rad/√s: the linearisation's error.
const ATTITUDE_WALK: f64 = 0.01;
/// Smallest measurement noise the filter assumes, rad (a noiseless sensor still rounds).
const MIN_NOISE: f64 = 1e-5;

type Filter = SMatrix<f64, 6, 6>;

/// The feedback's settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FeedbackSettings {
    /// Rate of the regulator (a new `u` from the current estimate), Hz.
    pub rate_hz: f64,
    /// Rate of the re-plan of the rest of the fall, Hz (0: never; module docs). Left out of the
    /// JSON when 0, so a check that never re-plans reports as it did before re-plans existed.
    #[serde(skip_serializing_if = "never_replans")]
    pub replan_hz: f64,
    /// Attitude error scale `θ_e`, rad.
    pub attitude: f64,
    /// Joint correction scale `θ_q`, rad.
    pub joint: f64,
    /// Joint acceleration scale and bound `a`, rad/s².
    pub accel: f64,
    /// Standard deviation of the filter's prior on the spin `d`, N·m·s per axis.
    pub spin_prior: f64,
    /// The sensor's noise per axis, rad (what the filter assumes).
    pub sensor_noise: f64,
}

/// Whether a re-plan rate means never (serde's skip: the field is left out at 0 Hz).
fn never_replans(hz: &f64) -> bool {
    hz.to_bits() == 0f64.to_bits()
}

/// The regulator and filter shared by every trial: the linearisation and its gains.
#[derive(Clone, Debug, PartialEq)]
pub struct FeedbackPlan {
    /// The plan linearised.
    pub linearisation: Linearisation,
    /// `K_i`, `i = 0 … N − 1`.
    pub gains: Vec<Gain>,
    /// The settings.
    pub settings: FeedbackSettings,
}

impl FeedbackPlan {
    /// The regulator of `plan` ([`Linearisation::new`], [`lqr_gains`] from the release).
    pub fn new(
        nominal: &Cylinder,
        traj: &(impl Trajectory + Sync),
        spin: &Vector3<f64>,
        tolerance: f64,
        plan: &Plan,
        settings: FeedbackSettings,
    ) -> FeedbackPlan {
        let linearisation = Linearisation::new(nominal, traj, spin, tolerance, plan, settings.rate_hz);
        let gains = lqr_gains(&linearisation, &settings, 0);
        FeedbackPlan { linearisation, gains, settings }
    }

    /// The largest entry of any gain (bounded at the end of the fall; module docs).
    pub fn largest_gain(&self) -> f64 {
        self.gains.iter().map(|k| k.amax()).fold(0.0, f64::max)
    }

    /// Control steps between re-plans: `feedback_replan_hz` rounded to a whole number of them
    /// (none at 0 Hz).
    pub fn replan_every(&self) -> Option<usize> {
        let r = self.settings.replan_hz;
        (r > 0.0).then(|| ((1.0 / (r * self.linearisation.dt)).round() as usize).max(1))
    }
}

/// What the feedback did over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FeedbackLog {
    /// Largest `|δq_r|` per joint, rad.
    pub largest_correction: [f64; 2],
    /// The filter's spin estimate `d` at the last control step, N·m·s (world frame).
    pub spin_estimate: [f64; 3],
    /// Re-plans of the rest of the fall.
    pub replans: usize,
}

/// The feedback controller of one run (module docs).
#[derive(Clone, Debug)]
pub struct Feedback<'a> {
    plan: &'a Plan,
    fb: &'a FeedbackPlan,
    servo: PdGains,
    inertia: f64,
    /// Measured `(δq, δq̇)` at every step so far.
    joints: Vec<[f64; 4]>,
    /// The filter's mean `(e, d)`, covariance and the sensor step they are at.
    z: SVector<f64, 6>,
    cov: Filter,
    filtered_to: Option<usize>,
    reference: [f64; 4],
    u: [f64; 2],
    /// The run's own regulator once it has re-planned (the plan's until then).
    regulator: Option<Regulator>,
    /// Control steps between re-plans (none: never).
    replan_every: Option<usize>,
    log: FeedbackLog,
}

impl<'a> Feedback<'a> {
    /// Feedback along `plan` with `fb`'s regulator; the servo `servo` on the nominal cat
    /// `nominal` tracks the corrected reference.
    pub fn new(plan: &'a Plan, fb: &'a FeedbackPlan, servo: PdGains, nominal: &Cylinder) -> Self {
        let mut cov = Filter::zeros();
        let noise = fb.settings.sensor_noise.max(MIN_NOISE);
        for i in 0..3 {
            cov[(i, i)] = noise * noise;
            cov[(3 + i, 3 + i)] = fb.settings.spin_prior.powi(2).max(f64::MIN_POSITIVE);
        }
        Feedback {
            plan,
            fb,
            servo,
            inertia: 0.5 * nominal.end_transverse(),
            joints: Vec::with_capacity(plan.steps() + 1),
            z: SVector::zeros(),
            cov,
            filtered_to: None,
            reference: [0.0; 4],
            u: [0.0; 2],
            regulator: None,
            replan_every: fb.replan_every(),
            log: FeedbackLog::default(),
        }
    }

    /// The linearisation in force at run step `k`.
    fn node(&self, k: usize) -> &Node {
        let i = self.fb.linearisation.node_of(k);
        self.regulator.as_ref().map_or(&self.fb.linearisation.nodes[i], |r| &r.nodes[i])
    }

    /// What the feedback did so far.
    pub fn log(&self) -> FeedbackLog {
        self.log
    }

    /// `ė` of the model at run step `k` for the attitude error `e` and spin `d`.
    fn e_rate(&self, k: usize, e: &Vector3<f64>, d: &Vector3<f64>) -> Vector3<f64> {
        let n = self.node(k);
        let j = self.joints.get(k).copied().unwrap_or([0.0; 4]);
        n.c + n.a * e + n.bq * Vector2::new(j[0], j[1]) + n.bqd * Vector2::new(j[2], j[3]) + n.g * d
    }

    /// The filter from its step to sensor step `j`, then its update with the reading there.
    fn filter(&mut self, j: usize, attitude: &AttitudeEstimate) {
        let h = self.plan.dt;
        let start = match self.filtered_to {
            Some(done) if done >= j => return,
            Some(done) => done,
            None => j,
        };
        let walk = ATTITUDE_WALK * ATTITUDE_WALK * h;
        let drift = (self.fb.settings.spin_prior.powi(2) / self.fb.linearisation.duration.max(h)) * h;
        for k in start..j {
            let n = *self.node(k);
            let e = self.z.fixed_rows::<3>(0).into_owned();
            let d = self.z.fixed_rows::<3>(3).into_owned();
            let next = e + self.e_rate(k, &e, &d) * h;
            self.z.fixed_rows_mut::<3>(0).copy_from(&next);
            let mut f = Filter::identity();
            f.fixed_view_mut::<3, 3>(0, 0).add_assign(&(n.a * h));
            f.fixed_view_mut::<3, 3>(0, 3).copy_from(&(n.g * h));
            self.cov = f * self.cov * f.transpose();
            for i in 0..3 {
                self.cov[(i, i)] += walk;
                self.cov[(3 + i, 3 + i)] += drift;
            }
        }
        let planned = self.fb.linearisation.planned(j);
        let y = (planned.inverse() * attitude.orientation).scaled_axis();
        let noise = self.fb.settings.sensor_noise.max(MIN_NOISE);
        let s = self.cov.fixed_view::<3, 3>(0, 0) + Matrix3::identity() * (noise * noise);
        if let Some(s_inv) = s.try_inverse() {
            let gain = self.cov.fixed_view::<6, 3>(0, 0) * s_inv;
            let innovation = y - self.z.fixed_rows::<3>(0);
            self.z += gain * innovation;
            let mut keep = Filter::identity();
            keep.fixed_view_mut::<6, 3>(0, 0).sub_assign(&gain);
            self.cov = keep * self.cov;
            self.cov = 0.5 * (self.cov + self.cov.transpose());
        }
        self.filtered_to = Some(j);
    }

    /// The regulator's input at run step `k` (a control step).
    fn regulate(&mut self, k: usize) -> [f64; 2] {
        let i = k / self.fb.linearisation.stride;
        if i >= self.fb.gains.len() {
            return [0.0; 2];
        }
        let h = self.plan.dt;
        let mut e = self.z.fixed_rows::<3>(0).into_owned();
        let d = self.z.fixed_rows::<3>(3).into_owned();
        for s in self.filtered_to.unwrap_or(k)..k {
            e += self.e_rate(s, &e, &d) * h;
        }
        let r = self.reference;
        let x = State::from_column_slice(&[e.x, e.y, e.z, r[0], r[1], r[2], r[3], d.x, d.y, d.z]);
        if self.replan_every.is_some_and(|every| i > 0 && i % every == 0) {
            let fb = self.fb;
            let regulator = self.regulator.get_or_insert_with(|| Regulator::of(fb));
            regulator.replan(&fb.linearisation, &fb.settings, i, &x);
            self.log.replans += 1;
        }
        let u = match &self.regulator {
            Some(r) => r.input(i, &x),
            None => -(self.fb.gains[i] * x),
        };
        self.log.spin_estimate = [d.x, d.y, d.z];
        let a = self.fb.settings.accel;
        [u[0].clamp(-a, a), u[1].clamp(-a, a)]
    }

    /// Advances the reference over one step with `u`, within the bounds (module docs).
    fn advance_reference(&mut self, measured: [f64; 4]) {
        let h = self.plan.dt;
        let bound = 3.0 * self.fb.settings.joint;
        for (j, joint) in measured.iter().take(2).enumerate() {
            let (mut q, mut qd) = (self.reference[j], self.reference[2 + j]);
            q += h * qd + 0.5 * h * h * self.u[j];
            qd += h * self.u[j];
            let lead = q - joint;
            let bounded = lead.abs() > MAX_LAG || q.abs() > bound;
            let held = if lead.abs() > MAX_LAG { joint + MAX_LAG.copysign(lead) } else { q }.clamp(-bound, bound);
            // At a bound the reference stops there (its rate towards it zeroed).
            if bounded && (held - q) * qd <= 0.0 {
                qd = 0.0;
            }
            self.reference[j] = held;
            self.reference[2 + j] = qd;
            self.log.largest_correction[j] = self.log.largest_correction[j].max(held.abs());
        }
    }
}

impl Controller for Feedback<'_> {
    fn torques(&mut self, t: f64, joints: &JointReading, attitude: &AttitudeEstimate) -> [f64; 2] {
        let h = self.plan.dt;
        let k = (t / h).round().max(0.0) as usize;
        let (target, ff) = (self.plan.state(k), self.plan.feedforward(k));
        let measured = [
            joints.q[0] - target.q[0],
            joints.q[1] - target.q[1],
            joints.qd[0] - target.qd[0],
            joints.qd[1] - target.qd[1],
        ];
        self.joints.resize(k, measured);
        self.joints.push(measured);
        let j = ((attitude.measured_at / h).round().max(0.0) as usize).min(k);
        self.filter(j, attitude);
        if k >= self.plan.steps() {
            self.u = [0.0; 2];
            self.reference[2] = 0.0;
            self.reference[3] = 0.0;
        } else if k % self.fb.linearisation.stride == 0 {
            self.u = self.regulate(k);
        }
        let r = self.reference;
        let tau = std::array::from_fn(|j| {
            ff[j]
                + self.inertia * self.u[j]
                + self.servo.kp[j] * (target.q[j] + r[j] - joints.q[j])
                + self.servo.kd[j] * (target.qd[j] + r[2 + j] - joints.qd[j])
        });
        if k < self.plan.steps() {
            self.advance_reference(measured);
        }
        tau
    }
}
