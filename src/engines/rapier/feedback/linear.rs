//! The attitude error's reduced dynamics relative to the plan, exact and linearised about any
//! motion near it (the plan itself, or a re-plan's expected motion; [`super`]'s docs for the
//! derivation).
//!
//! The state is `x = (e, δq, δq̇, d) ∈ ℝ¹⁰` in the plan's coordinates: `R = R* exp([e]×)` (A's
//! frame), `q = q* + δq`, and the spin the nominal model needs `L/s = L₀ + d` (world frame). The
//! error obeys
//!
//! $$ \dot e = f(t, x) = J_r(e)^{-1}\big(Ω(q, \dot q, e^{-[e]_×} R^{*\top}(L_0 + d)) − e^{-[e]_×}\,Ω^*\big), $$
//!
//! `J_r` the right Jacobian of SO(3). [`linearise`] gives its Jacobians at a point `x̄`
//! ([`Node`]): `∂f/∂q`, `∂f/∂q̇` by central differences of the engine's `Ω` (as along the plan),
//! `∂f/∂d = J_r⁻¹ I_lock⁻¹ e^{−[ē]×} R*ᵀ` exactly (`Ω` is affine in the momentum), and
//!
//! $$ \frac{∂f}{∂e} = J_r(ē)^{-1}\big(I_{lock}^{-1}[\bar λ]_× − [e^{-[ē]_×}Ω^*]_×\big) J_r(ē) + \frac{∂}{∂e}\Big(J_r(e)^{-1}\Big)\,\bar g, \qquad \bar g = \bar Ω − e^{-[ē]_×}Ω^*, $$
//!
//! since `e^{−[ē+δ]×} v ≈ e^{−[ē]×} v + [e^{−[ē]×} v]× J_r(ē) δ`; the last term (the derivative of
//! `J_r⁻¹` applied to a fixed vector: no engine call) by central differences. At `x̄ = 0` both
//! Jacobians of the exponential are the identity, `ḡ = 0`, and the node is the plan's
//! `∂f/∂e = −[Ω*]× + I_lock⁻¹ [λ*]×`, to the bit.
//!
//! ## References
//! - J. Solà, J. Deray, D. Atchuthan, *A micro Lie theory for state estimation in robotics*
//!   (2018), eqs. (143)–(146), the right Jacobian of SO(3) and its inverse.

use nalgebra::{Matrix3, Matrix3x2, SVector, UnitQuaternion, Vector2, Vector3};
use rayon::prelude::*;

use super::super::control::Plan;
use super::super::pieces::Pieces;
use crate::engines::exact::body_rate_spinning;
use crate::engines::spin::SpinHistory;
use crate::model::Cylinder;
use crate::schedule::Trajectory;

/// Instants per parallel task of the linearisation (one Runge–Kutta step, four rate
/// evaluations, each): a task holds thousands of evaluations, not one.
const INSTANTS_PER_TASK: usize = 512;
/// Nodes per parallel task of the linearisation (eleven rate evaluations each).
const NODES_PER_TASK: usize = 64;
/// Step of the central differences, rad and rad/s.
const EPS: f64 = 1e-6;
/// Below this angle the SO(3) Jacobians use their series, rad.
const SMALL_ANGLE: f64 = 0.1;

/// The regulator's and filter's state `(e, δq, δq̇, d)`.
pub type State = SVector<f64, 10>;

/// The plan at one control node: what the error dynamics need of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanPoint {
    /// Planned joints `q*`, rad.
    pub q: [f64; 2],
    /// Planned joint rates `q̇*`, rad/s.
    pub qd: [f64; 2],
    /// Planned attitude `R*`.
    pub attitude: UnitQuaternion<f64>,
    /// A's planned body rate `Ω*`, rad/s.
    pub omega: Vector3<f64>,
}

/// The error dynamics linearised at one control node `t_i` about a point `x̄` (module docs):
/// `ė ≈ c + A e + B_q δq + B_q̇ δq̇ + G d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// `∂f/∂e` (along the plan `−[Ω*]× + I_lock⁻¹ [λ*]×`).
    pub a: Matrix3<f64>,
    /// `∂f/∂q`.
    pub bq: Matrix3x2<f64>,
    /// `∂f/∂q̇`.
    pub bqd: Matrix3x2<f64>,
    /// `∂f/∂d`, the spin's way in (along the plan `I_lock⁻¹ R*ᵀ`).
    pub g: Matrix3<f64>,
    /// The affine term `f(x̄) − A ē − B_q δq̄ − B_q̇ δq̄̇ − G d̄`, rad/s (zero along the plan).
    pub c: Vector3<f64>,
}

impl Node {
    /// `ė` of the model at `x`.
    pub fn rate(&self, x: &State) -> Vector3<f64> {
        let (e, dq, dqd, d) = parts(x);
        self.c + self.a * e + self.bq * dq + self.bqd * dqd + self.g * d
    }
}

/// `x`'s parts `(e, δq, δq̇, d)`.
pub(super) fn parts(x: &State) -> (Vector3<f64>, Vector2<f64>, Vector2<f64>, Vector3<f64>) {
    (x.fixed_rows::<3>(0).into(), x.fixed_rows::<2>(3).into(), x.fixed_rows::<2>(5).into(), x.fixed_rows::<3>(7).into())
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
    /// The nodes `t_i = min(i Δ, T)`, `i = 0 … N`, along the plan.
    pub nodes: Vec<Node>,
    /// The plan at the nodes.
    pub points: Vec<PlanPoint>,
    /// The nominal attitude `R*(t_k)` at every run step `k` (the control nodes' among them; the
    /// filter compares each reading with the plan at the reading's own instant).
    pub attitudes: Vec<UnitQuaternion<f64>>,
    /// The nominal cat.
    pub cat: Cylinder,
    /// The nominal release spin `L₀`, world frame, N·m·s.
    pub spin: Vector3<f64>,
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
        let (points, nodes) = (0..n.div_ceil(stride) + 1)
            .into_par_iter()
            .with_min_len(NODES_PER_TASK)
            .map(|i| {
                let k = (i * stride).min(n);
                let (q, qd, attitude) = (plan.state(k).q, plan.state(k).qd, attitudes[k]);
                let omega = body_rate_spinning(nominal, q, qd, &(attitude.inverse() * spin));
                let point = PlanPoint { q, qd, attitude, omega };
                (point, linearise(nominal, &point, spin, &State::zeros()).0)
            })
            .unzip();
        Linearisation {
            stride,
            dt: stride as f64 * plan.dt,
            duration,
            nodes,
            points,
            attitudes,
            cat: *nominal,
            spin: *spin,
        }
    }

    /// The nominal attitude at run step `k`.
    pub(super) fn planned(&self, k: usize) -> UnitQuaternion<f64> {
        self.attitudes[k.min(self.attitudes.len() - 1)]
    }

    /// The index of the node in force at run step `k`.
    pub(super) fn node_of(&self, k: usize) -> usize {
        (k / self.stride).min(self.nodes.len() - 1)
    }
}

/// `exp(−[φ]×) v` (Rodrigues; exactly `v` at `φ = 0`).
pub(super) fn rotate_back(phi: &Vector3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let t2 = phi.norm_squared();
    let (a, b) = if t2 < SMALL_ANGLE * SMALL_ANGLE {
        (1.0 - t2 / 6.0 * (1.0 - t2 / 20.0), 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0))
    } else {
        let t = t2.sqrt();
        (t.sin() / t, (1.0 - t.cos()) / t2)
    };
    let pv = phi.cross(v);
    v - pv * a + phi.cross(&pv) * b
}

/// `J_r(φ)⁻¹ v = v + ½ φ × v + β(|φ|) φ × (φ × v)`, `β(θ) = 1/θ² − (1 + cos θ)/(2θ sin θ)`.
pub(super) fn jr_inv_apply(phi: &Vector3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let pv = phi.cross(v);
    v + pv * 0.5 + phi.cross(&pv) * beta(phi.norm_squared())
}

fn beta(t2: f64) -> f64 {
    if t2 < SMALL_ANGLE * SMALL_ANGLE {
        1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2 * t2 * t2 / 1_209_600.0
    } else {
        let t = t2.sqrt();
        1.0 / t2 - (1.0 + t.cos()) / (2.0 * t * t.sin())
    }
}

/// `J_r(φ)⁻¹` as a matrix.
pub(super) fn jr_inv(phi: &Vector3<f64>) -> Matrix3<f64> {
    let k = phi.cross_matrix();
    Matrix3::identity() + k * 0.5 + k * k * beta(phi.norm_squared())
}

/// `J_r(φ) = I − (1 − cos θ)/θ² [φ]× + (θ − sin θ)/θ³ [φ]×²`.
pub(super) fn jr(phi: &Vector3<f64>) -> Matrix3<f64> {
    let t2 = phi.norm_squared();
    let (a, b) = if t2 < SMALL_ANGLE * SMALL_ANGLE {
        (0.5 - t2 / 24.0 * (1.0 - t2 / 30.0), 1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0))
    } else {
        let t = t2.sqrt();
        ((1.0 - t.cos()) / t2, (t - t.sin()) / (t2 * t))
    };
    let k = phi.cross_matrix();
    Matrix3::identity() - k * a + k * k * b
}

/// The error rate `ė = f(x)` at `point` (module docs): the exact reduced dynamics, no linearisation.
pub fn error_rate(cat: &Cylinder, point: &PlanPoint, spin: &Vector3<f64>, x: &State) -> Vector3<f64> {
    let (e, dq, dqd, d) = parts(x);
    let q = [point.q[0] + dq[0], point.q[1] + dq[1]];
    let qd = [point.qd[0] + dqd[0], point.qd[1] + dqd[1]];
    let lambda = rotate_back(&e, &(point.attitude.inverse() * (spin + d)));
    let omega = body_rate_spinning(cat, q, qd, &lambda);
    jr_inv_apply(&e, &(omega - rotate_back(&e, &point.omega)))
}

/// The error dynamics at `point` linearised about `x̄` (module docs), and `f(x̄)`.
pub fn linearise(cat: &Cylinder, point: &PlanPoint, spin: &Vector3<f64>, xbar: &State) -> (Node, Vector3<f64>) {
    let (e, dq, dqd, d) = parts(xbar);
    let q = [point.q[0] + dq[0], point.q[1] + dq[1]];
    let qd = [point.qd[0] + dqd[0], point.qd[1] + dqd[1]];
    let lambda = rotate_back(&e, &(point.attitude.inverse() * (spin + d)));
    let rate = |q: [f64; 2], qd: [f64; 2], l: &Vector3<f64>| body_rate_spinning(cat, q, qd, l);
    let omega = rate(q, qd, &lambda);
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
    let plan_rate = rotate_back(&e, &point.omega);
    let mut a = -plan_rate.cross_matrix() + inv * lambda.cross_matrix();
    let mut g = inv * point.attitude.to_rotation_matrix().matrix().transpose();
    let gbar = omega - plan_rate;
    let f = jr_inv_apply(&e, &gbar);
    if e != Vector3::zeros() {
        let jinv = jr_inv(&e);
        let mut djinv = Matrix3::zeros();
        for k in 0..3 {
            let at = |h: f64| jr_inv_apply(&(e + Vector3::ith(k, h)), &gbar);
            djinv.set_column(k, &((at(EPS) - at(-EPS)) / (2.0 * EPS)));
        }
        a = jinv * a * jr(&e) + djinv;
        bq = jinv * bq;
        bqd = jinv * bqd;
        // exp(−[ē]×) R*ᵀ: the columns of R*ᵀ turned back by ē.
        let mut back = Matrix3::zeros();
        for k in 0..3 {
            back.set_column(k, &rotate_back(&e, &(point.attitude.inverse() * Vector3::ith(k, 1.0))));
        }
        g = jinv * inv * back;
    }
    let c = f - a * e - bq * dq - bqd * dqd - g * d;
    (Node { a, bq, bqd, g, c }, f)
}
