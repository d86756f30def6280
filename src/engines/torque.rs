//! Joint torques by Newton–Euler on the floating two-body cat (DESIGN.md §2).
//!
//! With `Ω` from the momentum map ([`crate::engines::exact::body_rate`]), its rate follows from
//! differentiating `M Ω + K = 0` (`M = I_lock`, `K = R I_B Rᵀ ω_rel + μ p × ṗ`, all in A's frame):
//!
//! $$ \dot Ω = −M^{-1}\big(\dot M Ω + \dot K\big), \quad
//!    \dot{(R I_B R^\top)} = [ω_{rel}]_× R I_B R^\top − R I_B R^\top [ω_{rel}]_×, $$
//! $$ \dot M = \dot{(R I_B R^\top)} − μ\big(\[\dot p\]_×\[p\]_× + \[p\]_×\[\dot p\]_×\big), \quad
//!    \dot K = \dot{(R I_B R^\top)}\, ω_{rel} + R I_B R^\top \dot ω_{rel} + μ\, p × \ddot p. $$
//!
//! B's centre accelerates (inertially, A's components) at
//! `a_B = ½ (p̈ + Ω̇ × p + 2 Ω × ṗ + Ω × (Ω × p))`; the joint pushes B with `F = m a_B` at the
//! joint point `d_B = (l/2) R ẑ` from B's centre and with the couple
//!
//! $$ T = I'_B α_B + ω_B × I'_B ω_B − d_B × F, \quad ω_B = Ω + ω_{rel}, \;
//!    α_B = \dot Ω + \dot ω_{rel} + Ω × ω_{rel}. $$
//!
//! The motor torques are `τ_i = T · a_i` on joint 1's axis `a_1 = x̂` and joint 2's axis
//! `a_2 = Rx(q1) ŷ`. The same couple from A's side, `−(I_A Ω̇ + Ω × I_A Ω − d_A × m a_A)` with
//! `a_A = −a_B`, must agree (action = reaction): [`JointTorques::from_a`].
//!
//! ## References
//! - R. Featherstone, *Rigid Body Dynamics Algorithms* (2008), ch. 2;
//! - the paper §8, whose bound `I* · peak(dω/dt)` this replaces.

use nalgebra::{Matrix2, Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use crate::engines::exact::{joint2_axis, relative_rate, solve_spd};
use crate::engines::models::TwoMotorCat;
use crate::engines::reduction;
use crate::engines::spin::SpinHistory;
use crate::model::{skew, Cylinder};
use crate::numeric::roots::golden_max;
use crate::schedule::{JointState, Trajectory};

/// Everything Newton–Euler needs at one instant, in A's frame.
#[derive(Clone, Copy, Debug)]
pub struct Kinematics {
    /// A's angular velocity `Ω`, rad/s.
    pub omega: Vector3<f64>,
    /// A's angular acceleration `Ω̇`, rad/s².
    pub omega_dot: Vector3<f64>,
    /// `ω_rel`, rad/s.
    pub omega_rel: Vector3<f64>,
    /// `ω̇_rel` (derivative of A-frame components), rad/s².
    pub omega_rel_dot: Vector3<f64>,
    /// B's centre relative to A's, m.
    pub offset: Vector3<f64>,
    /// Its rate of change in A's frame, m/s.
    pub offset_dot: Vector3<f64>,
    /// Its second derivative in A's frame, m/s².
    pub offset_ddot: Vector3<f64>,
    /// B's inertia in A's frame.
    pub inertia_b: Matrix3<f64>,
    /// B's spine axis `R ẑ` in A's frame.
    pub axis_b: Vector3<f64>,
}

/// The kinematics of the zero-momentum motion through the joint state `s`.
pub fn kinematics(cat: &Cylinder, s: &JointState) -> Kinematics {
    kinematics_with(cat, s, None)
}

/// The kinematics of the motion through `s` when the total angular momentum in A's frame is
/// `λ = Rᵀ L` (DESIGN.md §9): `Ω = M⁻¹(λ − K)` and, with `λ̇ = λ × Ω`,
/// `Ω̇ = M⁻¹(λ × Ω − Ṁ Ω − K̇)` ([`crate::engines::spin`]).
pub fn kinematics_spinning(cat: &Cylinder, s: &JointState, lambda: &Vector3<f64>) -> Kinematics {
    kinematics_with(cat, s, Some(lambda))
}

fn kinematics_with(cat: &Cylinder, s: &JointState, lambda: Option<&Vector3<f64>>) -> Kinematics {
    let cfg = cat.configuration(s.q);
    let mu = cat.reduced_mass();
    let half = 0.5 * cat.length;
    let w_rel = relative_rate(s.q, s.qd);
    let a2 = joint2_axis(s.q[0]);
    let w_rel_dot = Vector3::x() * s.qdd[0] + a2 * s.qdd[1] + Vector3::x().cross(&a2) * (s.qd[0] * s.qd[1]);
    let e = cfg.rotation * Vector3::z();
    let e_dot = w_rel.cross(&e);
    let e_ddot = w_rel_dot.cross(&e) + w_rel.cross(&e_dot);
    let (p, pd, pdd) = (cfg.offset, -half * e_dot, -half * e_ddot);
    let ib = cfg.inertia_b;
    let ib_dot = skew(&w_rel) * ib - ib * skew(&w_rel);
    let m = cfg.locked_inertia;
    let k = ib * w_rel + mu * p.cross(&pd);
    let omega = match lambda {
        None => -solve_spd(&m, &k),
        Some(l) => solve_spd(&m, &(l - k)),
    };
    let m_dot = ib_dot - mu * (skew(&pd) * skew(&p) + skew(&p) * skew(&pd));
    let k_dot = ib_dot * w_rel + ib * w_rel_dot + mu * p.cross(&pdd);
    let omega_dot = match lambda {
        None => -solve_spd(&m, &(m_dot * omega + k_dot)),
        Some(l) => solve_spd(&m, &(l.cross(&omega) - (m_dot * omega + k_dot))),
    };
    Kinematics {
        omega,
        omega_dot,
        omega_rel: w_rel,
        omega_rel_dot: w_rel_dot,
        offset: p,
        offset_dot: pd,
        offset_ddot: pdd,
        inertia_b: ib,
        axis_b: e,
    }
}

/// The joint's action on B at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointTorques {
    /// Motor torques `(τ1, τ2)` on B about joint 1's and joint 2's axes, N·m.
    pub tau: [f64; 2],
    /// The same from A's side (action = reaction), N·m.
    pub from_a: [f64; 2],
    /// The whole couple the joint applies to B, A's frame, N·m.
    pub couple: Vector3<f64>,
    /// The force the joint applies to B, A's frame, N.
    pub force: Vector3<f64>,
}

/// Joint torques of the zero-momentum motion through the joint state `s`.
pub fn joint_torques(cat: &Cylinder, s: &JointState) -> JointTorques {
    torques_of(cat, s, &kinematics(cat, s))
}

/// Joint torques of the motion through `s` with total angular momentum `λ = Rᵀ L` in A's frame.
pub fn joint_torques_spinning(cat: &Cylinder, s: &JointState, lambda: &Vector3<f64>) -> JointTorques {
    torques_of(cat, s, &kinematics_spinning(cat, s, lambda))
}

/// The motor torques of a cat released without spin, `τ(q, q̇, q̈) = M(q) q̈ + c(q, q̇)` (N·m, `c`
/// homogeneous quadratic in `q̇`): what a retiming samples along a path
/// ([`crate::optimize::retime`]). The paper's cat ([`Cylinder`], its half) goes through the
/// two-cylinder engine ([`joint_torques`]); a [`TwoMotorCat`] through the same engine when it is
/// the paper's cat, else through the general core ([`TwoMotorCat::joint_torques`]).
pub trait ZeroMomentumTorques: Sync {
    /// `(τ1, τ2)` on the joint's motor axes through `state`, N·m.
    fn motor_torques(&self, state: &JointState) -> [f64; 2];
}

impl ZeroMomentumTorques for Cylinder {
    fn motor_torques(&self, state: &JointState) -> [f64; 2] {
        joint_torques(self, state).tau
    }
}

impl ZeroMomentumTorques for TwoMotorCat {
    fn motor_torques(&self, state: &JointState) -> [f64; 2] {
        match self.cat().paper() {
            Some(half) => half.motor_torques(state),
            None => {
                let t = self.joint_torques(state);
                [t.tau[0], t.tau[1]]
            }
        }
    }
}

/// Where the joint torques along a trajectory come from: the paper's cat at zero momentum or
/// released with spin (whose orientations a [`SpinHistory`] holds), or another two-coordinate
/// model ([`crate::engines::models`]), likewise.
#[derive(Clone, Copy, Debug)]
pub struct TorqueSource<'a> {
    body: Body<'a>,
}

#[derive(Clone, Copy, Debug)]
enum Body<'a> {
    Paper { cat: &'a Cylinder, spin: Option<&'a SpinHistory> },
    Model { cat: &'a TwoMotorCat, spin: Option<&'a SpinHistory> },
}

impl<'a> TorqueSource<'a> {
    /// Zero angular momentum ([`joint_torques`]).
    pub fn zero_momentum(cat: &'a Cylinder) -> Self {
        Self { body: Body::Paper { cat, spin: None } }
    }

    /// A release with spin ([`joint_torques_spinning`] at the history's orientation).
    pub fn spinning(cat: &'a Cylinder, history: &'a SpinHistory) -> Self {
        Self { body: Body::Paper { cat, spin: Some(history) } }
    }

    /// `model` at zero angular momentum: the paper's cat through the two-cylinder engine
    /// ([`TorqueSource::zero_momentum`]), any other through the general core ([`TorqueSource::model`]).
    pub fn of(model: &'a TwoMotorCat) -> Self {
        match model.cat().paper() {
            Some(half) => Self::zero_momentum(half),
            None => Self::model(model),
        }
    }

    /// A two-coordinate model at zero angular momentum ([`TwoMotorCat::joint_torques`]).
    pub fn model(cat: &'a TwoMotorCat) -> Self {
        Self { body: Body::Model { cat, spin: None } }
    }

    /// A two-coordinate model released with spin when `history` is given, else at zero momentum
    /// ([`TorqueSource::model_spinning`], [`TorqueSource::model`]).
    pub fn model_released(cat: &'a TwoMotorCat, history: Option<&'a SpinHistory>) -> Self {
        Self { body: Body::Model { cat, spin: history } }
    }

    /// A two-coordinate model released with spin ([`TwoMotorCat::joint_torques_spinning`] at the
    /// orientation of `history`, integrated on the model by [`TwoMotorCat::flip_spinning`]).
    pub fn model_spinning(cat: &'a TwoMotorCat, history: &'a SpinHistory) -> Self {
        Self { body: Body::Model { cat, spin: Some(history) } }
    }

    /// The torques at local time `s` of `piece`, where the joints are in `state`.
    pub fn at(&self, traj: &impl Trajectory, piece: usize, s: f64, state: &JointState) -> JointTorques {
        match self.body {
            Body::Paper { cat, spin: None } => joint_torques(cat, state),
            Body::Paper { cat, spin: Some(h) } => {
                joint_torques_spinning(cat, state, &h.body_momentum(cat, traj, piece, s))
            }
            Body::Model { cat, spin } => {
                let t = match spin {
                    None => cat.joint_torques(state),
                    Some(h) => cat.joint_torques_spinning(state, &h.body_momentum_on(&cat.field(traj), piece, s)),
                };
                JointTorques {
                    tau: [t.tau[0], t.tau[1]],
                    from_a: [t.from_base_side[0], t.from_base_side[1]],
                    couple: t.couple,
                    force: t.force,
                }
            }
        }
    }
}

/// Newton–Euler on B (and on A, for action = reaction) with the base motion `k`.
fn torques_of(cat: &Cylinder, s: &JointState, k: &Kinematics) -> JointTorques {
    let half = 0.5 * cat.length;
    let (w, wd, p) = (k.omega, k.omega_dot, k.offset);
    let a_b = 0.5 * (k.offset_ddot + wd.cross(&p) + 2.0 * w.cross(&k.offset_dot) + w.cross(&w.cross(&p)));
    let force = cat.mass * a_b;
    let w_b = w + k.omega_rel;
    let alpha_b = wd + k.omega_rel_dot + w.cross(&k.omega_rel);
    let d_b = half * k.axis_b;
    let couple = k.inertia_b * alpha_b + w_b.cross(&(k.inertia_b * w_b)) - d_b.cross(&force);
    let ia = cat.inertia();
    let d_a = Vector3::new(0.0, 0.0, -half);
    let on_a = ia * wd + w.cross(&(ia * w)) - d_a.cross(&(-force));
    let axes = [Vector3::x(), joint2_axis(s.q[0])];
    JointTorques { tau: axes.map(|a| couple.dot(&a)), from_a: axes.map(|a| -on_a.dot(&a)), couple, force }
}

/// Kinetic energy of the zero-momentum motion `(q, q̇)` about the centre of mass, J.
pub fn kinetic_energy(cat: &Cylinder, q: [f64; 2], qd: [f64; 2]) -> f64 {
    let cfg = cat.configuration(q);
    let w_rel = relative_rate(q, qd);
    let omega = crate::engines::exact::body_rate(cat, q, qd);
    let e = cfg.rotation * Vector3::z();
    let pd = -0.5 * cat.length * w_rel.cross(&e);
    let w_b = omega + w_rel;
    let v_rel = pd + omega.cross(&cfg.offset);
    0.5 * omega.dot(&(cat.inertia() * omega))
        + 0.5 * w_b.dot(&(cfg.inertia_b * w_b))
        + 0.5 * cat.reduced_mass() * v_rel.norm_squared()
}

/// The reduced (zero-momentum) mass matrix `M(q)` with `E = ½ q̇ᵀ M q̇`, by polarisation.
pub fn reduced_mass_matrix(cat: &Cylinder, q: [f64; 2]) -> Matrix2<f64> {
    reduction::polarised_mass_matrix(|qd| kinetic_energy(cat, q, qd))
}

/// The peak `|τ_i|` of one joint in one phase and when it occurs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Peak {
    /// `max |τ_i|`, N·m.
    pub value: f64,
    /// Time of the peak, s.
    pub time: f64,
}

/// Peak joint torques per piece (phase) and joint.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PeakTorques {
    /// `[piece][joint]`; for a [`crate::schedule::Schedule`] the pieces are bend, twist, unbend.
    pub per_piece: Vec<[Peak; 2]>,
    /// The largest of all, N·m.
    pub max: f64,
    /// Largest disagreement between the two sides' torques seen while sampling, N·m.
    pub action_reaction_gap: f64,
    /// The peaks' stated accuracy: the largest relative change of a peak when every other
    /// sample is dropped ([`peak_torques_on`]); ≈ 1e-15 when the sampling resolves every peak.
    /// Conservative: it is the halved grid's error, which bounds the full grid's in practice.
    pub accuracy: f64,
}

/// Samples per radian the joint direction turns in a piece ([`piece_samples`]): the torque of
/// a twist phase oscillates once per turn of the bend direction, so its peaks are as far apart
/// in time as the circulation is fast; 64 per radian put ≥ 400 samples on each oscillation.
pub const SAMPLES_PER_RADIAN: f64 = 64.0;

/// Most samples per piece ([`piece_samples`]): a circulation of ~300 rad reaches it.
pub const MAX_PIECE_SAMPLES: usize = 20_000;

/// Samples per piece by the trajectory's own time scale: at least `floor`, and
/// [`SAMPLES_PER_RADIAN`] per radian the bend direction turns in the piece, at most
/// [`MAX_PIECE_SAMPLES`]. The bend direction is the azimuth `atan2(e_y, e_x)` of B's axis
/// `e = R_AB(q) ẑ = (sin q2, −sin q1 cos q2, cos q1 cos q2)` about A's axis, found on a coarse
/// pass of `floor` points (both bend paths turn it by the circulation in the twist phase).
pub fn piece_samples(traj: &impl Trajectory, floor: usize) -> Vec<usize> {
    use std::f64::consts::{PI, TAU};
    let floor = floor.max(2);
    traj.piece_durations()
        .into_iter()
        .enumerate()
        .map(|(piece, dur)| {
            let azimuth = |k: usize| {
                let q = traj.piece_state(piece, dur * k as f64 / floor as f64).q;
                (-q[0].sin() * q[1].cos()).atan2(q[1].sin())
            };
            let mut turned = 0.0;
            let mut last = azimuth(0);
            for k in 1..=floor {
                let a = azimuth(k);
                // The turn between neighbouring samples, wrapped to (−π, π].
                turned += ((a - last + PI).rem_euclid(TAU) - PI).abs();
                last = a;
            }
            let wanted = (SAMPLES_PER_RADIAN * turned).ceil();
            if wanted.is_finite() {
                (wanted as usize).clamp(floor, MAX_PIECE_SAMPLES.max(floor))
            } else {
                floor
            }
        })
        .collect()
}

/// Peak torques of a trajectory with `samples + 1` points on every piece ([`peak_torques_on`]).
pub fn peak_torques(cat: &Cylinder, traj: &impl Trajectory, samples: usize) -> PeakTorques {
    let n = vec![samples; traj.piece_durations().len()];
    peak_torques_on(cat, traj, &n)
}

/// Peak torques of a trajectory: `samples[i] + 1` equally spaced points on piece `i`, then every
/// sampled local maximum of `|τ_j|` that could still be the peak is refined by golden-section
/// search between its neighbours.
///
/// Between samples `h` apart, a smooth `|τ|` exceeds the larger of two neighbouring samples by
/// at most `h² max|τ''| / 8`; `τ''` is estimated by the second difference at each local
/// maximum, and every local maximum within that bound of the best sample is refined (not only
/// the best one, which on a fast twist phase may be the wrong oscillation). The peak's
/// accuracy is stated a posteriori as [`PeakTorques::accuracy`]: the relative change of each
/// peak when every other sample is dropped and the same search is repeated. At a piece's
/// [`Trajectory::acceleration_jumps`] (a retimed path's grid nodes) `τ` is smooth only between
/// the jumps, and its supremum may be a one-sided limit, or a maximum inside a segment much
/// shorter than the samples' spacing (a retimed path's grid is graded, finest where the path's
/// rate vanishes), that no equally spaced sample comes near: each segment is then also sampled
/// at its ends (each from its own side) and `SEGMENT_SAMPLES − 1` (4 − 1) inner points, and its
/// largest inner sample refined by golden-section search.
pub fn peak_torques_on(cat: &Cylinder, traj: &impl Trajectory, samples: &[usize]) -> PeakTorques {
    peak_torques_from(&TorqueSource::zero_momentum(cat), traj, samples)
}

/// [`peak_torques_on`] with the torques of `source`.
pub fn peak_torques_from(source: &TorqueSource, traj: &impl Trajectory, samples: &[usize]) -> PeakTorques {
    let mut peaks = PeakCollector::default();
    for (piece, dur) in traj.piece_durations().into_iter().enumerate() {
        peaks.push(piece_peaks_from(source, traj, piece, samples.get(piece).copied().unwrap_or(2)), dur);
    }
    peaks.finish()
}

/// [`peak_torques_from`]'s pieces gathered one by one, the peaks' times made global.
#[derive(Default)]
pub(crate) struct PeakCollector {
    per_piece: Vec<[Peak; 2]>,
    gap: f64,
    accuracy: f64,
    t0: f64,
}

impl PeakCollector {
    /// The next piece's peaks; `dur` its duration, s.
    pub(crate) fn push(&mut self, found: PiecePeaks, dur: f64) {
        self.gap = self.gap.max(found.action_reaction_gap);
        self.accuracy = self.accuracy.max(found.accuracy);
        let t0 = self.t0;
        self.per_piece.push(found.peaks.map(|p| Peak { value: p.value, time: t0 + p.time }));
        self.t0 += dur;
    }

    pub(crate) fn finish(self) -> PeakTorques {
        let max = self.per_piece.iter().flatten().map(|p| p.value).fold(0.0, f64::max);
        PeakTorques { per_piece: self.per_piece, max, action_reaction_gap: self.gap, accuracy: self.accuracy }
    }
}

/// The equally spaced samples of one piece that its peaks ([`piece_peaks_from`]) and its motor
/// demand ([`crate::engines::motors::motor_demand_from`]) start from: `n + 1` points `k h`,
/// `h = T_piece / n`, `n` = the samples asked for, at least 4, each with its joint state and
/// torques. Sampled once when both are wanted ([`crate::engines::motors::peaks_and_demand`]).
pub(crate) struct PieceSamples {
    /// The piece's duration, s.
    pub dur: f64,
    /// The spacing `h`, s.
    pub h: f64,
    /// `(s, state, torques)` at `s = k h`, `k = 0..=n`.
    pub points: Vec<(f64, JointState, JointTorques)>,
    /// Where `q̈` jumps inside the piece ([`Trajectory::acceleration_jumps`]), the smooth
    /// segments between the jumps, each on its own samples; none for a smooth piece.
    pub segments: Vec<Segment>,
}

/// A smooth segment `[a, b]` of a piece between acceleration jumps (or the piece's ends), on
/// [`SEGMENT_SAMPLES`] equal parts: `(s, state, torques)` at `s = a + k (b − a)/m`, the last
/// point `b` taken from the segment's own side (the left limit).
pub(crate) struct Segment {
    /// The segment's ends, local times of the piece, s.
    pub a: f64,
    /// See `a`.
    pub b: f64,
    /// The samples, `m + 1` of them.
    pub points: Vec<(f64, JointState, JointTorques)>,
}

impl Segment {
    /// Local time of sample `k`, s.
    pub fn at(&self, k: usize) -> f64 {
        self.a + (self.b - self.a) * k as f64 / SEGMENT_SAMPLES as f64
    }
}

impl PieceSamples {
    /// Piece `piece` of `traj` on `samples` intervals (at least 4), torques from `source`.
    pub(crate) fn new(source: &TorqueSource, traj: &impl Trajectory, piece: usize, samples: usize) -> Self {
        let dur = traj.piece_durations().get(piece).copied().unwrap_or(0.0);
        Self::of_duration(source, traj, piece, dur, samples)
    }

    /// [`PieceSamples::new`] with the piece's duration `dur` (s) known.
    pub(crate) fn of_duration(
        source: &TorqueSource,
        traj: &impl Trajectory,
        piece: usize,
        dur: f64,
        samples: usize,
    ) -> Self {
        let n = samples.max(4);
        let h = dur / n as f64;
        let points = (0..=n)
            .map(|k| {
                let s = k as f64 * h;
                let st = traj.piece_state(piece, s);
                (s, st, source.at(traj, piece, s, &st))
            })
            .collect();
        let jumps = traj.acceleration_jumps(piece);
        let segments = if jumps.is_empty() {
            Vec::new()
        } else {
            let ends: Vec<f64> = std::iter::once(0.0).chain(jumps).chain(std::iter::once(dur)).collect();
            ends.windows(2)
                .map(|w| {
                    let (a, b, m) = (w[0], w[1], SEGMENT_SAMPLES);
                    let points = (0..=m)
                        .map(|k| {
                            let (s, st) = if k == m {
                                (b, traj.piece_state_before(piece, b))
                            } else {
                                let s = a + (b - a) * k as f64 / m as f64;
                                (s, traj.piece_state(piece, s))
                            };
                            (s, st, source.at(traj, piece, s, &st))
                        })
                        .collect();
                    Segment { a, b, points }
                })
                .collect()
        };
        Self { dur, h, points, segments }
    }
}

/// Equal parts of each smooth segment between a piece's acceleration jumps that
/// [`piece_peaks`] samples before refining its largest inner sample.
const SEGMENT_SAMPLES: usize = 4;

/// The peaks of one piece ([`piece_peaks`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PiecePeaks {
    /// Per joint; times from the piece's start, s.
    pub peaks: [Peak; 2],
    /// As [`PeakTorques::action_reaction_gap`], on this piece.
    pub action_reaction_gap: f64,
    /// As [`PeakTorques::accuracy`], on this piece.
    pub accuracy: f64,
}

/// The peaks of piece `piece` alone with `samples + 1` points (at least 5), found as
/// [`peak_torques_on`] finds them.
pub fn piece_peaks(cat: &Cylinder, traj: &impl Trajectory, piece: usize, samples: usize) -> PiecePeaks {
    piece_peaks_from(&TorqueSource::zero_momentum(cat), traj, piece, samples)
}

/// [`piece_peaks`] with the torques of `source`.
pub fn piece_peaks_from(source: &TorqueSource, traj: &impl Trajectory, piece: usize, samples: usize) -> PiecePeaks {
    piece_peaks_sampled(source, traj, piece, &PieceSamples::new(source, traj, piece, samples))
}

/// [`piece_peaks_from`] from the piece's samples, already taken.
pub(crate) fn piece_peaks_sampled(
    source: &TorqueSource,
    traj: &impl Trajectory,
    piece: usize,
    sampled: &PieceSamples,
) -> PiecePeaks {
    let h = sampled.h;
    let tau = |s: f64| source.at(traj, piece, s, &traj.piece_state(piece, s));
    let mut gap: f64 = 0.0;
    let mut accuracy: f64 = 0.0;
    let n = sampled.points.len();
    let mut values = [Vec::with_capacity(n), Vec::with_capacity(n)];
    for (_, _, jt) in &sampled.points {
        for (j, v) in values.iter_mut().enumerate() {
            gap = gap.max((jt.tau[j] - jt.from_a[j]).abs());
            v.push(jt.tau[j].abs());
        }
    }
    let mut peaks = [0, 1].map(|j| {
        let f = |s: f64| tau(s).tau[j].abs();
        let (s, value) = refine_peak(&values[j], h, &f);
        let halved: Vec<f64> = values[j].iter().copied().step_by(2).collect();
        let (_, coarse) = refine_peak(&halved, 2.0 * h, &f);
        if value > 0.0 {
            accuracy = accuracy.max((value - coarse).abs() / value);
        }
        Peak { value, time: s }
    });
    // Where q̈ jumps inside the piece, τ is smooth only between the jumps, and its supremum may
    // be a one-sided limit or a maximum inside a segment shorter than the samples' spacing
    // (none for a smooth piece): each segment is searched on its own, both ends taken from
    // their side.
    for seg in &sampled.segments {
        let m = seg.points.len() - 1;
        let mut v = [Vec::with_capacity(m + 1), Vec::with_capacity(m + 1)];
        for (_, _, jt) in &seg.points {
            for (j, vj) in v.iter_mut().enumerate() {
                gap = gap.max((jt.tau[j] - jt.from_a[j]).abs());
                vj.push(jt.tau[j].abs());
            }
        }
        for (j, p) in peaks.iter_mut().enumerate() {
            let (k, &best) = v[j].iter().enumerate().max_by(|x, y| x.1.total_cmp(y.1)).unwrap_or((0, &0.0));
            let (mut s, mut value) = (seg.at(k), best);
            if k > 0 && k < m {
                let f = |x: f64| tau(x).tau[j].abs();
                let (sg, vg) = golden_max(f, seg.at(k - 1), seg.at(k + 1), 40);
                if vg > value {
                    (s, value) = (sg, vg);
                }
            }
            if value > p.value {
                *p = Peak { value, time: s };
            }
        }
    }
    PiecePeaks { peaks, action_reaction_gap: gap, accuracy }
}

/// The refined maximum `(s, value)` of samples `v` (spacing `h`, at least 3) of `f`
/// ([`peak_torques_on`]).
pub(crate) fn refine_peak(v: &[f64], h: f64, f: &impl Fn(f64) -> f64) -> (f64, f64) {
    let n = v.len() - 1;
    // Second difference at k (one-sided at the ends), times h²/8: the most a smooth function
    // can exceed its samples near k.
    let miss = |k: usize| {
        let c = k.clamp(1, n - 1);
        (v[c - 1] - 2.0 * v[c] + v[c + 1]).abs() / 8.0
    };
    // Rising strictly into k (so a plateau counts once) and not rising after it; a zero
    // torque has no peak to refine.
    let is_local_max = |k: usize| v[k] > 0.0 && (k == 0 || v[k] > v[k - 1]) && (k == n || v[k] >= v[k + 1]);
    let (k_best, best) =
        v.iter().copied().enumerate().fold((0, f64::NEG_INFINITY), |a, (k, x)| if x > a.1 { (k, x) } else { a });
    let mut peak = (k_best as f64 * h, best);
    for k in (0..=n).filter(|&k| is_local_max(k) && v[k] + miss(k) >= best) {
        let lo = k.saturating_sub(1) as f64 * h;
        let hi = (k + 1).min(n) as f64 * h;
        let (s, value) = golden_max(f, lo, hi, 40);
        let candidate = if value > v[k] { (s, value) } else { (k as f64 * h, v[k]) };
        if candidate.1 > peak.1 {
            peak = candidate;
        }
    }
    peak
}
