//! The exact engine: how a prescribed joint trajectory reorients the cat (DESIGN.md §2).
//!
//! With zero angular momentum about the centre of mass, A's angular velocity `Ω` (A's frame)
//! follows from the joint motion alone. With `ω_rel = q̇1 x̂ + q̇2 Rx(q1) ŷ`, `p` B's centre
//! relative to A's and `μ = m/2`,
//!
//! $$ H = \big[I_A + R I_B R^\top - μ \[p\]_×^2\big] Ω + R I_B R^\top ω_{rel} + μ\, p × \dot p = 0, $$
//!
//! so `Ω = −I_lock⁻¹ (R I_B Rᵀ ω_rel + μ p × ṗ)`, linear in `q̇`: the reorientation depends on the
//! path in joint space, not on its timing. A's world orientation obeys `Ṙ = R [Ω]×`, integrated on
//! SO(3) with the sixth-order Magnus method on the three Gauss–Legendre nodes
//! `c = 1/2 − √15/10, 1/2, 1/2 + √15/10` ([`magnus6`]), `R_{n+1} = R_n exp([σ]×)`,
//! phase by phase, so steps never straddle a phase boundary where `q̇` may jump. Each phase's
//! step count is doubled until the Richardson estimate of its orientation error is below its
//! share of the tolerance.
//!
//! Released with total angular momentum `L` (world frame, constant; DESIGN.md §9) the momentum in
//! A's frame is `λ = Rᵀ L` and `I_lock Ω + h = λ`, so `Ω = I_lock⁻¹ (Rᵀ L − h)` depends on `R` as
//! well as on the joint motion: the Magnus step no longer applies, and [`Stepper::Spinning`]
//! takes the classical fourth-order Runge–Kutta step on the unit quaternion instead
//! ([`crate::engines::spin`]), with the same segments, doubling and Richardson estimate (divisor
//! 15). The twist and swing then depend on the timing too, not only on the path.
//!
//! The integrator steps a [`RateField`], A's angular velocity piece by piece: the two-cylinder
//! cat on a [`Trajectory`] here, any model on a shape trajectory in
//! [`crate::engines::models`], with the same segments, doubling and estimate.
//!
//! ## References
//! - S. Blanes, F. Casas, J. Ros, *Improved high order integrators based on the Magnus
//!   expansion*, BIT 40 (2000) 434–450;
//! - R. Montgomery, *Gauge theory of the falling cat* (1993), for the mechanical connection.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use serde::Serialize;

use crate::model::orientation::{SwingTwist, TwistTracker};
use crate::model::{rot_x, Cylinder};
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
///
/// Written for speed with B's axis `e = R ẑ`: for the symmetric cylinder
/// `R I_B Rᵀ = I_t 𝟙 + (I_a − I_t) e eᵀ` and `−[p]×² = |p|² 𝟙 − p pᵀ`, so no rotation matrix is
/// formed ([`Cylinder::configuration`] is the general form; a test checks they agree).
pub fn body_rate(cat: &Cylinder, q: [f64; 2], qd: [f64; 2]) -> Vector3<f64> {
    let (m, rhs) = locked_and_shape_momentum(cat, q, qd);
    -solve_spd(&m, &rhs)
}

/// A's angular velocity `Ω = I_lock⁻¹ (λ − h)` (A's frame) when the total angular momentum in
/// A's frame is `λ = Rᵀ L` (DESIGN.md §9); [`body_rate`] is `λ = 0`.
pub fn body_rate_spinning(cat: &Cylinder, q: [f64; 2], qd: [f64; 2], lambda: &Vector3<f64>) -> Vector3<f64> {
    let (m, rhs) = locked_and_shape_momentum(cat, q, qd);
    solve_spd(&m, &(lambda - rhs))
}

/// The locked inertia `I_lock(q)` and the momentum `h = R I_B Rᵀ ω_rel + μ p × ṗ` of the joint
/// motion at zero base rate, A's frame ([`body_rate`]'s docs).
fn locked_and_shape_momentum(cat: &Cylinder, q: [f64; 2], qd: [f64; 2]) -> (Matrix3<f64>, Vector3<f64>) {
    let (s1, c1) = q[0].sin_cos();
    let (s2, c2) = q[1].sin_cos();
    // e = Rx(q1) Ry(q2) ẑ
    let e = Vector3::new(s2, -s1 * c2, c1 * c2);
    let w_rel = Vector3::new(qd[0], qd[1] * c1, qd[1] * s1);
    let half = 0.5 * cat.length;
    let p = Vector3::new(-half * e.x, -half * e.y, -half * (1.0 + e.z));
    let pd = -half * w_rel.cross(&e);
    let (it, ia, mu) = (cat.transverse(), cat.axial(), cat.reduced_mass());
    let d = ia - it;
    let rhs = it * w_rel + (d * e.dot(&w_rel)) * e + mu * p.cross(&pd);
    let pp = p.norm_squared();
    let mut m = Matrix3::from_diagonal_element(2.0 * it + mu * pp) + (d * e) * e.transpose() - (mu * p) * p.transpose();
    m[(2, 2)] += d;
    (m, rhs)
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
    /// Most Magnus steps of any phase in the accepted result.
    pub steps_per_phase: usize,
    /// Richardson estimate of the orientation error (bounds the twist and swing errors), rad.
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

/// Largest number of steps per phase that [`flip`] will try.
pub const MAX_STEPS_PER_PHASE: usize = 1 << 16;

/// How one step advances A's orientation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stepper {
    /// Zero angular momentum: `Ω` depends on the joint motion alone and the sixth-order Magnus
    /// step ([`magnus6`]) integrates `Ṙ = R [Ω]×` exactly up to its order.
    Magnus,
    /// A release with total angular momentum `L` (world frame): `Ω = I_lock⁻¹ (Rᵀ L − h)`
    /// depends on `R` too, and the classical fourth-order Runge–Kutta step on the unit
    /// quaternion ([`rk4_on`]) integrates it.
    Spinning(Vector3<f64>),
}

impl Stepper {
    /// The stepper of a release with angular momentum `spin`: Magnus when it is zero.
    pub fn for_spin(spin: &Vector3<f64>) -> Stepper {
        if spin.norm_squared() > 0.0 {
            Stepper::Spinning(*spin)
        } else {
            Stepper::Magnus
        }
    }

    /// Richardson divisor `2^p − 1` of the scheme's order `p`.
    fn richardson(self) -> f64 {
        match self {
            Stepper::Magnus => 63.0,
            Stepper::Spinning(_) => 15.0,
        }
    }

    /// A's orientation one step `h` on from `r` at local time `s` of `piece`.
    pub fn step(
        self,
        cat: &Cylinder,
        schedule: &impl Trajectory,
        piece: usize,
        r: &UnitQuaternion<f64>,
        s: f64,
        h: f64,
    ) -> UnitQuaternion<f64> {
        self.step_on(&CylinderField { cat, traj: schedule }, piece, r, s, h)
    }

    /// [`Stepper::step`] on any [`RateField`].
    pub fn step_on(
        self,
        field: &impl RateField,
        piece: usize,
        r: &UnitQuaternion<f64>,
        s: f64,
        h: f64,
    ) -> UnitQuaternion<f64> {
        match self {
            Stepper::Magnus => {
                let c = 15f64.sqrt() / 10.0;
                let rate = |s: f64| field.body_rate(piece, s);
                let sigma = magnus6(h, rate(s + (0.5 - c) * h), rate(s + 0.5 * h), rate(s + (0.5 + c) * h));
                UnitQuaternion::new_normalize(*(r * UnitQuaternion::from_scaled_axis(sigma)).quaternion())
            }
            Stepper::Spinning(spin) => rk4_on(field, piece, &spin, r, s, h),
        }
    }
}

/// A's angular velocity along a trajectory, piece by piece: what the integrator steps. The
/// two-cylinder cat on a [`Trajectory`] is one such field (the functions of this module); a
/// general model on a shape trajectory is another ([`crate::engines::models`]).
pub trait RateField {
    /// Durations of the pieces, s ([`Trajectory::piece_durations`]).
    fn piece_durations(&self) -> Vec<f64>;
    /// Where `q̈` may jump inside a piece ([`Trajectory::acceleration_jumps`]).
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64>;
    /// `Ω` (A's frame) at zero angular momentum, at local time `s` of `piece`.
    fn body_rate(&self, piece: usize, s: f64) -> Vector3<f64>;
    /// `Ω = I_lock⁻¹ (λ − h)` with the total angular momentum `λ` in A's frame.
    fn body_rate_spinning(&self, piece: usize, s: f64, lambda: &Vector3<f64>) -> Vector3<f64>;
    /// [`RateField::body_rate_spinning`] at one instant as a function of `λ`: what does not
    /// depend on the attitude (the joint state, `I_lock` and its factor, `h`) is computed once,
    /// for the Runge–Kutta stages that share the instant. The same numbers as
    /// `body_rate_spinning(piece, s, λ)`.
    fn spinning_rates(&self, piece: usize, s: f64) -> impl Fn(&Vector3<f64>) -> Vector3<f64> + '_ {
        move |lambda| self.body_rate_spinning(piece, s, lambda)
    }
}

/// The two-cylinder cat on a joint trajectory: [`body_rate`] and [`body_rate_spinning`].
pub(crate) struct CylinderField<'a, T: Trajectory> {
    pub(crate) cat: &'a Cylinder,
    pub(crate) traj: &'a T,
}

impl<T: Trajectory> RateField for CylinderField<'_, T> {
    fn piece_durations(&self) -> Vec<f64> {
        self.traj.piece_durations()
    }
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64> {
        self.traj.acceleration_jumps(piece)
    }
    fn body_rate(&self, piece: usize, s: f64) -> Vector3<f64> {
        let st = self.traj.piece_state(piece, s);
        body_rate(self.cat, st.q, st.qd)
    }
    fn body_rate_spinning(&self, piece: usize, s: f64, lambda: &Vector3<f64>) -> Vector3<f64> {
        let st = self.traj.piece_state(piece, s);
        body_rate_spinning(self.cat, st.q, st.qd, lambda)
    }
    fn spinning_rates(&self, piece: usize, s: f64) -> impl Fn(&Vector3<f64>) -> Vector3<f64> + '_ {
        let st = self.traj.piece_state(piece, s);
        let (m, rhs) = locked_and_shape_momentum(self.cat, st.q, st.qd);
        let factor = m.cholesky();
        // solve_spd's steps, the factor kept.
        move |lambda| {
            let b = lambda - rhs;
            match &factor {
                Some(ch) => ch.solve(&b),
                None => m.lu().solve(&b).unwrap_or_else(|| Vector3::repeat(f64::NAN)),
            }
        }
    }
}

/// `ṙ = ½ r ⊗ (0, Ω)` at one instant, for the (not necessarily unit) quaternion `r`, with
/// `Ω = I_lock⁻¹ (Rᵀ L − h)` at the normalised `r` (`rates`: [`RateField::spinning_rates`]).
fn quaternion_rate(
    rates: &impl Fn(&Vector3<f64>) -> Vector3<f64>,
    spin: &Vector3<f64>,
    r: &Quaternion<f64>,
) -> Quaternion<f64> {
    let unit = UnitQuaternion::new_normalize(*r);
    let lambda = unit.inverse_transform_vector(spin);
    let omega = rates(&lambda);
    r * Quaternion::from_parts(0.0, omega) * 0.5
}

/// One classical Runge–Kutta step `h` of A's orientation from `r` at local time `s` of `piece`
/// of any [`RateField`], released with total angular momentum `spin` (world frame), normalised
/// at the end.
pub fn rk4_on(
    field: &impl RateField,
    piece: usize,
    spin: &Vector3<f64>,
    r: &UnitQuaternion<f64>,
    s: f64,
    h: f64,
) -> UnitQuaternion<f64> {
    let y = *r.quaternion();
    // k2 and k3 share their instant: the joint motion there is evaluated once.
    let (start, middle, end) =
        (field.spinning_rates(piece, s), field.spinning_rates(piece, s + 0.5 * h), field.spinning_rates(piece, s + h));
    let k1 = quaternion_rate(&start, spin, &y);
    let k2 = quaternion_rate(&middle, spin, &(y + k1 * (0.5 * h)));
    let k3 = quaternion_rate(&middle, spin, &(y + k2 * (0.5 * h)));
    let k4 = quaternion_rate(&end, spin, &(y + k3 * h));
    UnitQuaternion::new_normalize(y + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0))
}

/// Integrates A's orientation with `steps` Magnus steps per phase, calling `observe` at the
/// start and after every step; returns the final orientation and (continued) angles.
pub fn integrate(
    cat: &Cylinder,
    schedule: &impl Trajectory,
    steps: usize,
    observe: impl FnMut(&OrientationSample),
) -> (UnitQuaternion<f64>, SwingTwist) {
    integrate_with(cat, schedule, Stepper::Magnus, steps, observe)
}

/// [`integrate`] with the given stepper.
pub fn integrate_with(
    cat: &Cylinder,
    schedule: &impl Trajectory,
    stepper: Stepper,
    steps: usize,
    observe: impl FnMut(&OrientationSample),
) -> (UnitQuaternion<f64>, SwingTwist) {
    integrate_on(&CylinderField { cat, traj: schedule }, stepper, steps, observe)
}

/// [`integrate_with`] on any [`RateField`].
pub fn integrate_on(
    field: &impl RateField,
    stepper: Stepper,
    steps: usize,
    mut observe: impl FnMut(&OrientationSample),
) -> (UnitQuaternion<f64>, SwingTwist) {
    let mut state = PieceState::start();
    observe(&OrientationSample { time: 0.0, orientation: state.r, angles: state.angles });
    for (piece, duration) in field.piece_durations().into_iter().enumerate() {
        let parts = [((0.0, duration), steps)];
        state = integrate_segments(field, stepper, piece, &parts, 1, state, &mut observe);
    }
    (state.r, state.angles)
}

/// Where an integration stands at a piece boundary.
#[derive(Clone, Copy, Debug)]
struct PieceState {
    r: UnitQuaternion<f64>,
    tracker: TwistTracker,
    angles: SwingTwist,
    time: f64,
}

impl PieceState {
    fn start() -> Self {
        let r = UnitQuaternion::identity();
        let mut tracker = TwistTracker::default();
        let angles = tracker.update(&r);
        PieceState { r, tracker, angles, time: 0.0 }
    }
}

/// Advances `state` across the local times `span = (a, b)` of one piece with `steps` steps;
/// `state.time` is the piece's start and stays so.
fn integrate_span(
    field: &impl RateField,
    stepper: Stepper,
    piece: usize,
    (a, b): (f64, f64),
    steps: usize,
    mut state: PieceState,
    observe: &mut impl FnMut(&OrientationSample),
) -> PieceState {
    let steps = steps.max(1);
    let h = (b - a) / steps as f64;
    for k in 0..steps {
        let s = a + k as f64 * h;
        state.r = stepper.step_on(field, piece, &state.r, s, h);
        state.angles = state.tracker.update(&state.r);
        observe(&OrientationSample { time: state.time + s + h, orientation: state.r, angles: state.angles });
    }
    state
}

/// The smooth segments of a piece: the spans between its [`Trajectory::acceleration_jumps`],
/// each with its share of [`FIRST_STEPS`] steps (at least one), so that every step lies
/// where the integrand is smooth and the scheme's order (and the Richardson divisor) holds.
fn segments(field: &impl RateField, piece: usize, duration: f64) -> Vec<((f64, f64), usize)> {
    let mut cuts: Vec<f64> =
        field.acceleration_jumps(piece).into_iter().filter(|s| *s > 0.0 && *s < duration).collect();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let bounds: Vec<f64> = std::iter::once(0.0).chain(cuts).chain(std::iter::once(duration)).collect();
    bounds
        .windows(2)
        .map(|w| ((w[0], w[1]), ((FIRST_STEPS as f64 * (w[1] - w[0]) / duration).ceil() as usize).max(1)))
        .collect()
}

/// Advances `state` across one piece, segment by segment (`(span, steps)`, spans covering the
/// piece from 0), with `multiple` times each segment's step count, calling `observe` after every
/// step.
fn integrate_segments(
    field: &impl RateField,
    stepper: Stepper,
    piece: usize,
    segments: &[((f64, f64), usize)],
    multiple: usize,
    mut state: PieceState,
    observe: &mut impl FnMut(&OrientationSample),
) -> PieceState {
    let t0 = state.time;
    for &(span, steps) in segments {
        state = integrate_span(field, stepper, piece, span, steps * multiple, state, observe);
    }
    state.time = t0 + segments.last().map_or(0.0, |s| s.0 .1);
    state
}

/// Steps of a smooth piece in [`flip`]'s first try.
const FIRST_STEPS: usize = 4;

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

/// The final twist and swing of a schedule at zero angular momentum, to `tolerance` rad: each
/// piece's steps are doubled until the Richardson estimate of its orientation error,
/// `angle(R_n⁻¹ R_{2n}) / 63`, is below its share of the tolerance (a planar piece, whose
/// rotations commute, converges at once). A piece whose `q̈` jumps inside
/// ([`Trajectory::acceleration_jumps`]) is stepped segment by segment: a step across a jump
/// would be of second order only, and the estimate, which assumes the sixth, would be too small.
pub fn flip(cat: &Cylinder, schedule: &impl Trajectory, tolerance: f64) -> Flip {
    adaptive(cat, schedule, Stepper::Magnus, tolerance, None)
}

/// [`flip`] for a release with total angular momentum `spin` (N·m·s, world frame): the same
/// adaptive integration with the stepper [`Stepper::for_spin`] chooses (Magnus when `spin` is
/// zero, the same numbers as [`flip`]; otherwise fourth-order Runge–Kutta, divisor 15).
pub fn flip_spinning(cat: &Cylinder, schedule: &impl Trajectory, spin: &Vector3<f64>, tolerance: f64) -> Flip {
    adaptive(cat, schedule, Stepper::for_spin(spin), tolerance, None)
}

/// A piece's accepted orientations, `(local time, R)`, its start first.
pub type PieceNodes = Vec<(f64, UnitQuaternion<f64>)>;

/// The adaptive integration behind [`flip`]; with `nodes`, the accepted run's orientations
/// `(local time, R)` of every piece (its start included) are pushed there, piece by piece.
pub(crate) fn adaptive(
    cat: &Cylinder,
    schedule: &impl Trajectory,
    stepper: Stepper,
    tolerance: f64,
    nodes: Option<&mut Vec<PieceNodes>>,
) -> Flip {
    adaptive_on(&CylinderField { cat, traj: schedule }, stepper, tolerance, nodes)
}

/// The adaptive integration behind [`flip`] (step doubling and Richardson estimate) on any
/// [`RateField`]: one integrator for every model.
pub fn adaptive_on(
    field: &impl RateField,
    stepper: Stepper,
    tolerance: f64,
    mut nodes: Option<&mut Vec<PieceNodes>>,
) -> Flip {
    let durations = field.piece_durations();
    let share = tolerance / durations.len().max(1) as f64;
    let mut state = PieceState::start();
    let (mut error_estimate, mut steps_used, mut converged) = (0.0, 0, true);
    for (piece, duration) in durations.into_iter().enumerate() {
        let parts = segments(field, piece, duration);
        let first: usize = parts.iter().map(|p| p.1).sum();
        let mut multiple = 1;
        let mut coarse = integrate_segments(field, stepper, piece, &parts, multiple, state, &mut |_| {});
        loop {
            let mut kept = Vec::new();
            let t0 = state.time;
            let mut keep = |o: &OrientationSample| {
                if nodes.is_some() {
                    kept.push((o.time - t0, o.orientation));
                }
            };
            let fine = integrate_segments(field, stepper, piece, &parts, 2 * multiple, state, &mut keep);
            let err = (coarse.r.inverse() * fine.r).angle() / stepper.richardson();
            multiple *= 2;
            let steps = first * multiple;
            if err <= share || steps >= MAX_STEPS_PER_PHASE {
                converged &= err <= share;
                error_estimate += err;
                steps_used = steps_used.max(steps);
                if let Some(out) = nodes.as_deref_mut() {
                    kept.insert(0, (0.0, state.r));
                    out.push(kept);
                }
                state = fine;
                break;
            }
            coarse = fine;
        }
    }
    Flip {
        twist: state.angles.twist,
        swing: state.angles.swing,
        orientation: state.r,
        steps_per_phase: steps_used,
        error_estimate,
        converged,
    }
}

/// The orientation history with `steps` Magnus steps per phase.
pub fn history(cat: &Cylinder, schedule: &impl Trajectory, steps: usize) -> Vec<OrientationSample> {
    history_with(cat, schedule, Stepper::Magnus, steps)
}

/// [`history`] with the given stepper.
pub fn history_with(
    cat: &Cylinder,
    schedule: &impl Trajectory,
    stepper: Stepper,
    steps: usize,
) -> Vec<OrientationSample> {
    let mut out = Vec::with_capacity(3 * steps + 1);
    integrate_with(cat, schedule, stepper, steps, |s| out.push(*s));
    out
}

/// Fewest Magnus steps per piece of a [`fall_history`].
pub const MIN_HISTORY_PIECE_STEPS: usize = 8;

/// [`history`] with about `steps` Magnus steps over the whole trajectory, shared equally between
/// its pieces (at least [`MIN_HISTORY_PIECE_STEPS`] each): the same density whether the trajectory
/// is three phases or a spline of a hundred spans.
pub fn fall_history(cat: &Cylinder, traj: &impl Trajectory, steps: usize) -> Vec<OrientationSample> {
    fall_history_with(cat, traj, Stepper::Magnus, steps)
}

/// [`fall_history`] with the given stepper.
pub fn fall_history_with(
    cat: &Cylinder,
    traj: &impl Trajectory,
    stepper: Stepper,
    steps: usize,
) -> Vec<OrientationSample> {
    let pieces = traj.piece_durations().len().max(1);
    history_with(cat, traj, stepper, steps.div_ceil(pieces).max(MIN_HISTORY_PIECE_STEPS))
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
