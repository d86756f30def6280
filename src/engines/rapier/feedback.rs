//! Feedback on the attitude that corrects the flip (issue 21 §3): time-varying LQR on the
//! reduced dynamics linearised along the plan, fed by a Kalman filter that estimates the
//! attitude error and the unknown release spin from the late, noisy attitude sensor.
//!
//! # Why LQR and not a re-plan
//!
//! The plan is optimal for the nominal cat; a trial's cat differs by its mass (which only
//! rescales the spin's effect: `I_lock` and `h` both scale with `m`, so at zero momentum the
//! flip is mass-free) and by its release spin. These are small perturbations of the plan, so the
//! linearisation along it is the model a re-plan would locally solve anyway. Its Riccati sweep
//! is done once per check, not per trial ([`lqr_gains`]; `benches/feedback.rs` on the paper's
//! schedule at 1 kHz, a quiet two-core machine: 0.87 ms from the release, 0.44 ms from mid-fall,
//! the linearisation 14.1–14.7 ms, its instants and nodes in parallel), and the loop then costs a
//! 2 × 10 product per control step (a trial 217 ms against the open loop's 188 ms). A shrinking-horizon re-plan with the whole
//! optimiser would be a nonlinear solve per step.
//!
//! Measured on the paper's whole optimum (`catflip robust problems/paper.toml --schedule
//! results/paper/schedules/whole-optimum.csv --set robust.engine=both --set robust.landing=true
//! --set robust.controller=both`, the filter's spin prior 0.001 N·m·s): 95th percentile 1.50°
//! (twist 1.32°, swing 0.94°) against the
//! open loop's 45.97°. The largest errors are swing the linear model does not predict: the
//! largest spins need joint corrections of 10–15°, where the second-order coupling of twist
//! into swing is no longer small.
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
//! - O. J. M. Smith, *Closer control of loops with dead time*, Chem. Eng. Prog. 53 (1957).

use std::ops::{AddAssign, SubAssign};

use nalgebra::{Matrix3, Matrix3x2, SMatrix, SVector, UnitQuaternion, Vector3};
use rayon::prelude::*;
use serde::Serialize;

use super::control::{AttitudeEstimate, Controller, JointReading, PdGains, Plan};
use super::pieces::Pieces;
use crate::engines::exact::body_rate_spinning;
use crate::engines::spin::SpinHistory;
use crate::model::Cylinder;
use crate::schedule::Trajectory;

/// Largest lead of the reference over the joint it drives, rad (anti-windup; 2°).
pub const MAX_LAG: f64 = 2.0 * std::f64::consts::PI / 180.0;
/// The time scale that weighs the joint rate against the joint angle, s.
const RATE_SCALE: f64 = 0.1;
/// Process noise of the attitude error in the filter, rad/√s: the linearisation's error.
const ATTITUDE_WALK: f64 = 0.01;
/// Instants per parallel task of the linearisation (one Runge–Kutta step, four rate
/// evaluations, each): a task holds thousands of evaluations, not one.
const INSTANTS_PER_TASK: usize = 512;
/// Nodes per parallel task of the linearisation (eleven rate evaluations each).
const NODES_PER_TASK: usize = 64;
/// Smallest measurement noise the filter assumes, rad (a noiseless sensor still rounds).
const MIN_NOISE: f64 = 1e-5;

type State = SVector<f64, 10>;
type Square = SMatrix<f64, 10, 10>;
type Input = SMatrix<f64, 10, 2>;
/// A gain `K_i`: `u = −K_i x`.
pub type Gain = SMatrix<f64, 2, 10>;
type Filter = SMatrix<f64, 6, 6>;

/// The feedback's settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FeedbackSettings {
    /// Rate of the regulator (a new `u` from the current estimate), Hz.
    pub rate_hz: f64,
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

/// The plan linearised at one control node `t_i` (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// `∂ė/∂e = −[Ω*]× + I_lock⁻¹ [λ*]×`.
    pub a: Matrix3<f64>,
    /// `∂Ω/∂q`.
    pub bq: Matrix3x2<f64>,
    /// `∂Ω/∂q̇`.
    pub bqd: Matrix3x2<f64>,
    /// `I_lock⁻¹ R*ᵀ`, the spin's way in.
    pub g: Matrix3<f64>,
}

/// The plan linearised on the control grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Linearisation {
    /// Run steps per control step.
    pub stride: usize,
    /// The control step `Δ`, s.
    pub dt: f64,
    /// The schedule's duration `T`, s.
    pub duration: f64,
    /// The nodes `t_i = min(i Δ, T)`, `i = 0 … N`.
    pub nodes: Vec<Node>,
    /// The nominal attitude `R*(t_k)` at every run step `k` (the control nodes' among them; the
    /// filter compares each reading with the plan at the reading's own instant).
    pub attitudes: Vec<UnitQuaternion<f64>>,
}

impl Linearisation {
    /// Linearises `plan` (of `traj` on `nominal` released with `spin`, the exact engine's
    /// attitude to `tolerance`) at `rate_hz`.
    pub fn new(
        nominal: &Cylinder,
        traj: &(impl Trajectory + Sync),
        spin: &Vector3<f64>,
        tolerance: f64,
        plan: &Plan,
        rate_hz: f64,
    ) -> Linearisation {
        let n = plan.steps();
        let stride = ((1.0 / (rate_hz * plan.dt)).round() as usize).clamp(1, n.max(1));
        let pieces = Pieces::new(traj);
        let duration = pieces.duration();
        let (_, history) = SpinHistory::new(nominal, traj, spin, tolerance);
        // Each instant and node from the history alone, so in parallel (the same bits at any
        // number of threads).
        let attitudes: Vec<_> = (0..n + 1)
            .into_par_iter()
            .with_min_len(INSTANTS_PER_TASK)
            .map(|k| {
                let t = if k >= n { duration } else { k as f64 * plan.dt };
                let (piece, s) = pieces.locate(t);
                history.orientation(nominal, traj, piece, s)
            })
            .collect();
        let nodes = (0..n.div_ceil(stride) + 1)
            .into_par_iter()
            .with_min_len(NODES_PER_TASK)
            .map(|i| {
                let k = (i * stride).min(n);
                node(nominal, plan.state(k).q, plan.state(k).qd, attitudes[k], spin)
            })
            .collect();
        Linearisation { stride, dt: stride as f64 * plan.dt, duration, nodes, attitudes }
    }

    /// The nominal attitude at run step `k`.
    fn planned(&self, k: usize) -> UnitQuaternion<f64> {
        self.attitudes[k.min(self.attitudes.len() - 1)]
    }

    /// The node in force at run step `k`.
    fn at_step(&self, k: usize) -> &Node {
        &self.nodes[(k / self.stride).min(self.nodes.len() - 1)]
    }
}

fn node(cat: &Cylinder, q: [f64; 2], qd: [f64; 2], attitude: UnitQuaternion<f64>, spin: &Vector3<f64>) -> Node {
    let lambda = attitude.inverse() * spin;
    let rate = |q: [f64; 2], qd: [f64; 2], l: &Vector3<f64>| body_rate_spinning(cat, q, qd, l);
    let omega = rate(q, qd, &lambda);
    const EPS: f64 = 1e-6;
    let column = |f: &dyn Fn(f64) -> Vector3<f64>| (f(EPS) - f(-EPS)) / (2.0 * EPS);
    let mut bq = Matrix3x2::zeros();
    let mut bqd = Matrix3x2::zeros();
    for j in 0..2 {
        let shifted = |x: [f64; 2], h: f64| {
            let mut y = x;
            y[j] += h;
            y
        };
        bq.set_column(j, &column(&|h| rate(shifted(q, h), qd, &lambda)));
        bqd.set_column(j, &column(&|h| rate(q, shifted(qd, h), &lambda)));
    }
    // Ω is affine in λ: its columns are I_lock⁻¹'s.
    let mut inv = Matrix3::zeros();
    for k in 0..3 {
        inv.set_column(k, &(rate(q, qd, &(lambda + Vector3::ith(k, 1.0))) - omega));
    }
    let a = -omega.cross_matrix() + inv * lambda.cross_matrix();
    let g = inv * attitude.to_rotation_matrix().matrix().transpose();
    Node { a, bq, bqd, g }
}

/// The discrete model over `Δ` at `node`: `x⁺ = F x + Γ u`.
fn discrete(node: &Node, dt: f64) -> (Square, Input) {
    let mut f = Square::identity();
    f.fixed_view_mut::<3, 3>(0, 0).add_assign(&(node.a * dt));
    f.fixed_view_mut::<3, 2>(0, 3).copy_from(&(node.bq * dt));
    f.fixed_view_mut::<3, 2>(0, 5).copy_from(&(node.bqd * dt));
    f.fixed_view_mut::<3, 3>(0, 7).copy_from(&(node.g * dt));
    for j in 0..2 {
        f[(3 + j, 5 + j)] = dt;
    }
    let mut gamma = Input::zeros();
    gamma.fixed_view_mut::<3, 2>(0, 0).copy_from(&(node.bqd * (0.5 * dt * dt)));
    for j in 0..2 {
        gamma[(3 + j, j)] = 0.5 * dt * dt;
        gamma[(5 + j, j)] = dt;
    }
    (f, gamma)
}

/// The state weights `(running, terminal)` and the input weight of `settings` (module docs).
fn weights(settings: &FeedbackSettings, dt: f64, duration: f64) -> (Square, Square, f64) {
    let mut terminal = Square::zeros();
    for i in 0..3 {
        terminal[(i, i)] = settings.attitude.powi(-2);
    }
    for j in 0..2 {
        terminal[(3 + j, 3 + j)] = settings.joint.powi(-2);
        terminal[(5 + j, 5 + j)] = (RATE_SCALE / settings.joint).powi(2);
    }
    let share = dt / duration.max(dt);
    (terminal * share, terminal, share * settings.accel.powi(-2))
}

/// The gains `K_i` for the nodes `from … N − 1` (the backward Riccati sweep from `T`; module
/// docs): `gains[i − from]` is node `i`'s. A gain the sweep cannot form (a singular `R + ΓᵀPΓ`,
/// impossible with `accel` finite) is zero: no correction rather than a wrong one.
pub fn lqr_gains(lin: &Linearisation, settings: &FeedbackSettings, from: usize) -> Vec<Gain> {
    let (running, mut p, r) = weights(settings, lin.dt, lin.duration);
    let last = lin.nodes.len().saturating_sub(1);
    let mut gains = vec![Gain::zeros(); last.saturating_sub(from)];
    for i in (from..last).rev() {
        let (f, gamma) = discrete(&lin.nodes[i], lin.dt);
        let pg = p * gamma;
        let s = gamma.transpose() * pg + SMatrix::<f64, 2, 2>::identity() * r;
        let k = s.try_inverse().map_or(Gain::zeros(), |inv| inv * pg.transpose() * f);
        p = running + f.transpose() * p * (f - gamma * k);
        p = 0.5 * (p + p.transpose());
        gains[i - from] = k;
    }
    gains
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
}

/// What the feedback did over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FeedbackLog {
    /// Largest `|δq_r|` per joint, rad.
    pub largest_correction: [f64; 2],
    /// The filter's spin estimate `d` at the last control step, N·m·s (world frame).
    pub spin_estimate: [f64; 3],
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
            log: FeedbackLog::default(),
        }
    }

    /// What the feedback did so far.
    pub fn log(&self) -> FeedbackLog {
        self.log
    }

    /// `ė` of the model at run step `k` for the attitude error `e` and spin `d`.
    fn e_rate(&self, k: usize, e: &Vector3<f64>, d: &Vector3<f64>) -> Vector3<f64> {
        let n = self.fb.linearisation.at_step(k);
        let j = self.joints.get(k).copied().unwrap_or([0.0; 4]);
        n.a * e + n.bq * nalgebra::Vector2::new(j[0], j[1]) + n.bqd * nalgebra::Vector2::new(j[2], j[3]) + n.g * d
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
            let n = self.fb.linearisation.at_step(k);
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
        let Some(gain) = self.fb.gains.get(i) else { return [0.0; 2] };
        let h = self.plan.dt;
        let mut e = self.z.fixed_rows::<3>(0).into_owned();
        let d = self.z.fixed_rows::<3>(3).into_owned();
        for s in self.filtered_to.unwrap_or(k)..k {
            e += self.e_rate(s, &e, &d) * h;
        }
        let r = self.reference;
        let x = State::from_column_slice(&[e.x, e.y, e.z, r[0], r[1], r[2], r[3], d.x, d.y, d.z]);
        let u = -(gain * x);
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
