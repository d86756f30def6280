//! The exact engine: how a prescribed joint trajectory reorients the cat (DESIGN.md §2).
//!
//! With zero angular momentum about the centre of mass, A's angular velocity `Ω` (A's frame)
//! follows from the joint motion alone. With `ω_rel = q̇1 x̂ + q̇2 Rx(q1) ŷ`, `p` B's centre
//! relative to A's and `μ = m/2`,
//!
//! $$ H = \big[I_A + R I_B R^\top - μ [p]_×^2\big] Ω + R I_B R^\top ω_{rel} + μ\, p × \dot p = 0, $$
//!
//! so `Ω = −I_lock⁻¹ (R I_B Rᵀ ω_rel + μ p × ṗ)`, linear in `q̇`: the reorientation depends on the
//! path in joint space, not on its timing. A's world orientation obeys `Ṙ = R [Ω]×`, integrated on
//! SO(3) with the sixth-order Magnus method on the three Gauss–Legendre nodes
//! `c = 1/2 − √15/10, 1/2, 1/2 + √15/10` ([`magnus6`]), `R_{n+1} = R_n exp([σ]×)`,
//! phase by phase, so steps never straddle a phase boundary where `q̇` may jump. Step counts are
//! doubled until the Richardson estimate `|x_{2n} − x_n| / 63` of twist and swing is below the
//! tolerance.
//!
//! ## References
//! - S. Blanes, F. Casas, J. Ros, *Improved high order integrators based on the Magnus
//!   expansion*, BIT 40 (2000) 434–450;
//! - R. Montgomery, *Gauge theory of the falling cat* (1993), for the mechanical connection.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use serde::Serialize;

use crate::model::{rot_x, Cylinder};
use crate::orientation::{SwingTwist, TwistTracker};
use crate::schedule::{JointState, Trajectory};

/// Relative angular velocity of B with respect to A, in A's frame: `q̇1 x̂ + q̇2 Rx(q1) ŷ`.
pub fn relative_rate(q: [f64; 2], qd: [f64; 2]) -> Vector3<f64> {
    let (s, c) = q[0].sin_cos();
    Vector3::new(qd[0], qd[1] * c, qd[1] * s)
}

/// Joint 2's axis `Rx(q1) ŷ` in A's frame.
pub fn joint2_axis(q1: f64) -> Vector3<f64> {
    rot_x(q1) * Vector3::y()
}

/// A's angular velocity `Ω` (A's frame) for joint angles `q` and rates `q̇` at zero momentum.
pub fn body_rate(cat: &Cylinder, q: [f64; 2], qd: [f64; 2]) -> Vector3<f64> {
    let cfg = cat.configuration(q);
    let w_rel = relative_rate(q, qd);
    let e = cfg.rotation * Vector3::z();
    let pd = -0.5 * cat.length * w_rel.cross(&e);
    let rhs = cfg.inertia_b * w_rel + cat.reduced_mass() * cfg.offset.cross(&pd);
    -solve_spd(&cfg.locked_inertia, &rhs)
}

/// Solves `M x = b` for a symmetric positive definite 3×3 `M`.
pub(crate) fn solve_spd(m: &Matrix3<f64>, b: &Vector3<f64>) -> Vector3<f64> {
    match m.cholesky() {
        Some(ch) => ch.solve(b),
        None => m.lu().solve(b).unwrap_or_else(|| Vector3::repeat(f64::NAN)),
    }
}

/// The result of integrating a schedule's reorientation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Flip {
    /// Signed twist of A about its initial spine axis, rad (continued through ±π).
    pub twist: f64,
    /// Swing of A's spine axis, rad.
    pub swing: f64,
    /// A's final orientation.
    #[serde(skip)]
    pub orientation: UnitQuaternion<f64>,
    /// Magnus steps per phase of the accepted result.
    pub steps_per_phase: usize,
    /// Richardson estimate of the error of twist and swing, rad.
    pub error_estimate: f64,
    /// Whether the estimate met the tolerance within the step budget.
    pub converged: bool,
}

/// One instant of an orientation history.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientationSample {
    /// Time, s.
    pub time: f64,
    /// A's orientation.
    pub orientation: UnitQuaternion<f64>,
    /// Twist (continued) and swing, rad.
    pub angles: SwingTwist,
}

/// Largest number of Magnus steps per phase that [`flip`] will try.
pub const MAX_STEPS_PER_PHASE: usize = 1 << 16;

/// Integrates A's orientation with `steps` Magnus steps per phase, calling `observe` at the
/// start and after every step; returns the final orientation and (continued) angles.
pub fn integrate(
    cat: &Cylinder,
    schedule: &impl Trajectory,
    steps: usize,
    mut observe: impl FnMut(&OrientationSample),
) -> (UnitQuaternion<f64>, SwingTwist) {
    let steps = steps.max(1);
    let c = 15f64.sqrt() / 10.0;
    let mut r = UnitQuaternion::identity();
    let mut tracker = TwistTracker::default();
    let mut angles = tracker.update(&r);
    observe(&OrientationSample { time: 0.0, orientation: r, angles });
    let mut t0 = 0.0;
    for (piece, duration) in schedule.piece_durations().into_iter().enumerate() {
        let h = duration / steps as f64;
        let rate = |s: f64| {
            let st = schedule.piece_state(piece, s);
            body_rate(cat, st.q, st.qd)
        };
        for k in 0..steps {
            let s = k as f64 * h;
            let sigma = magnus6(h, rate(s + (0.5 - c) * h), rate(s + 0.5 * h), rate(s + (0.5 + c) * h));
            r = UnitQuaternion::new_normalize(*(r * UnitQuaternion::from_scaled_axis(sigma)).quaternion());
            angles = tracker.update(&r);
            observe(&OrientationSample { time: t0 + s + h, orientation: r, angles });
        }
        t0 += duration;
    }
    (r, angles)
}

/// The sixth-order Magnus exponent of one step of `Ṙ = R [Ω]×` from the rates at the three
/// Gauss–Legendre nodes (Blanes, Casas & Ros 2000, eq. for `Ω^{[6]}`, written for the
/// right-invariant form in vector notation, `[[a]×, [b]×] = [a × b]×`).
pub fn magnus6(h: f64, w1: Vector3<f64>, w2: Vector3<f64>, w3: Vector3<f64>) -> Vector3<f64> {
    let a1 = h * w2;
    let a2 = (15f64.sqrt() * h / 3.0) * (w3 - w1);
    let a3 = (10.0 * h / 3.0) * (w3 - 2.0 * w2 + w1);
    let c1 = a1.cross(&a2);
    let c2 = a1.cross(&(c1 - 2.0 * a3)) / 60.0;
    a1 + a3 / 12.0 - (20.0 * a1 + a3 + c1).cross(&(c2 - a2)) / 240.0
}

/// Richardson divisor `2^p − 1` of the sixth-order scheme.
const RICHARDSON: f64 = 63.0;

/// The final twist and swing of a schedule, to `tolerance` rad (Richardson estimate).
pub fn flip(cat: &Cylinder, schedule: &impl Trajectory, tolerance: f64) -> Flip {
    let mut steps = 8;
    let (_, mut coarse) = integrate(cat, schedule, steps, |_| {});
    loop {
        let (r, fine) = integrate(cat, schedule, 2 * steps, |_| {});
        let err = (fine.twist - coarse.twist).abs().max((fine.swing - coarse.swing).abs()) / RICHARDSON;
        steps *= 2;
        let converged = err <= tolerance;
        if converged || steps >= MAX_STEPS_PER_PHASE {
            return Flip {
                twist: fine.twist,
                swing: fine.swing,
                orientation: r,
                steps_per_phase: steps,
                error_estimate: err,
                converged,
            };
        }
        coarse = fine;
    }
}

/// The orientation history with `steps` Magnus steps per phase.
pub fn history(cat: &Cylinder, schedule: &impl Trajectory, steps: usize) -> Vec<OrientationSample> {
    let mut out = Vec::with_capacity(3 * steps + 1);
    integrate(cat, schedule, steps, |s| out.push(*s));
    out
}

/// Total angular momentum about the centre of mass, in A's frame, of the motion `(q, q̇)` with
/// A turning at `omega`: `I_lock Ω + R I_B Rᵀ ω_rel + μ p × ṗ`.
pub fn momentum(cat: &Cylinder, state: &JointState, omega: &Vector3<f64>) -> Vector3<f64> {
    let cfg = cat.configuration(state.q);
    let w_rel = relative_rate(state.q, state.qd);
    let e = cfg.rotation * Vector3::z();
    let pd = -0.5 * cat.length * w_rel.cross(&e);
    cfg.locked_inertia * omega + cfg.inertia_b * w_rel + cat.reduced_mass() * cfg.offset.cross(&pd)
}
