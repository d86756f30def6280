//! The three-phase manoeuvre as joint trajectories `q(t)`, `q̇(t)`, `q̈(t)` (DESIGN.md §3).
//!
//! - bend, `0 ≤ t ≤ T1`: `q1 = β P_b(t/T1)`, `q2 = 0`, with the paper's harmonic
//!   `P_b(u) = (1 − cos πu)/2` unless retimed ([`crate::optimize::refine`]);
//! - twist, `s = t − T1`: the bend direction `φ(s) = D P(s/T2)` circulates along the bend path:
//!   the paper's joint circle `(β cos φ, β sin φ)`, or the cone
//!   `q1 = atan2(sin β cos φ, cos β)` (continued through ±π), `q2 = asin(sin β sin φ)`, on which
//!   B's axis `Rx(q1) Ry(q2) ẑ = (sin β sin φ, −sin β cos φ, cos β)` keeps the angle β to A's;
//! - unbend, `u = t − T1 − T2`: `q = q_s + (q_e − q_s)(1 − P_u(u/T3))` from the end-of-twist
//!   `q_e` to the straight configuration `q_s = (2πk₁, 2πk₂)` nearest to it
//!   ([`nearest_straight`]; `q_s = 0` on the joint circle and on a cone of bend up to 90°), the
//!   paper's `(1 + cos(π u/T3))/2` for the harmonic `P_u`.
//!
//! Angles in rad, times in s. Each phase is evaluated with its own formula on its closed
//! interval, so one-sided values at the boundaries are available and velocity jumps can be
//! reported, not smeared.

pub mod profile;
pub mod variant;

use std::f64::consts::PI;

use crate::problem::manoeuvre::BendPath;
use crate::schedule::profile::{Profile, ProfilePoint};

/// Joint angles, rates and accelerations at one instant.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct JointState {
    /// `(q1, q2)`, rad.
    pub q: [f64; 2],
    /// `(q̇1, q̇2)`, rad/s.
    pub qd: [f64; 2],
    /// `(q̈1, q̈2)`, rad/s².
    pub qdd: [f64; 2],
}

/// One of the manoeuvre's three phases.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Phase {
    /// Bending from straight to the bend β.
    Bend,
    /// Circulating the bend direction.
    Twist,
    /// Straightening.
    Unbend,
}

impl Phase {
    /// The three phases in order.
    pub const ALL: [Phase; 3] = [Phase::Bend, Phase::Twist, Phase::Unbend];

    /// The phase's index in [`Phase::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Bend => "bend",
            Phase::Twist => "twist",
            Phase::Unbend => "unbend",
        }
    }
}

/// A joint trajectory made of pieces, each smooth on its closed interval; rates may jump
/// between pieces. Engines integrate piece by piece and never step across a boundary.
pub trait Trajectory {
    /// Durations of the pieces, s, in order.
    fn piece_durations(&self) -> Vec<f64>;
    /// State at local time `s ∈ [0, duration]` of a piece, by that piece's own formula.
    fn piece_state(&self, piece: usize, s: f64) -> JointState;

    /// Local times inside piece `piece` (strictly between its ends) where `q̈` may jump while
    /// `q` and `q̇` stay continuous: the piece is smooth between them. None by default (a
    /// trajectory smooth on each closed piece); a retimed path
    /// ([`crate::optimize::retime::RetimedTrajectory`]) has one at every grid node. The torque
    /// jumps there too, so a peak may be a one-sided limit: [`crate::engines::torque::peak_torques`]
    /// evaluates both, and rapier keeps its motors' transients there out of its peaks.
    fn acceleration_jumps(&self, _piece: usize) -> Vec<f64> {
        Vec::new()
    }

    /// The left limit of the state at local time `s` of a piece: [`Trajectory::piece_state`]
    /// except at an [`Trajectory::acceleration_jumps`] instant, where `piece_state` takes the
    /// later side.
    fn piece_state_before(&self, piece: usize, s: f64) -> JointState {
        self.piece_state(piece, s)
    }

    /// The uncertainty of the rate difference at the boundary after piece `k`, rad/s: zero for
    /// rates from a formula or a file (the default), an estimate for rates interpolated from
    /// rows ([`crate::engines::jumps`] reports a jump only beyond it).
    fn boundary_rate_uncertainty(&self, _k: usize) -> f64 {
        0.0
    }

    /// Total duration, s.
    fn total_duration(&self) -> f64 {
        self.piece_durations().iter().sum()
    }

    /// The piece containing global time `t` (the later one at a boundary; clamped to the
    /// trajectory) and the local time in it.
    fn locate_piece(&self, t: f64) -> (usize, f64) {
        let d = self.piece_durations();
        let mut start = 0.0;
        for (i, &di) in d.iter().enumerate() {
            if t < start + di || i + 1 == d.len() {
                return (i, (t - start).clamp(0.0, di));
            }
            start += di;
        }
        (0, 0.0)
    }

    /// The state at global time `t`, by [`Trajectory::locate_piece`].
    fn state_at(&self, t: f64) -> JointState {
        let (piece, s) = self.locate_piece(t);
        self.piece_state(piece, s)
    }

    /// The manoeuvre's phase at global time `t` when the pieces are its three phases (bend,
    /// twist, unbend), else `None` (e.g. a whole-manoeuvre spline, which bends and circulates
    /// at once).
    fn phase_at(&self, t: f64) -> Option<Phase> {
        (self.piece_durations().len() == Phase::ALL.len()).then(|| Phase::ALL[self.locate_piece(t).0])
    }
}

/// A trajectory run backwards in time: `q_r(t) = q(T − t)`.
#[derive(Clone, Copy, Debug)]
pub struct Reversed<'a, T: Trajectory>(pub &'a T);

impl<T: Trajectory> Trajectory for Reversed<'_, T> {
    fn piece_durations(&self) -> Vec<f64> {
        let mut d = self.0.piece_durations();
        d.reverse();
        d
    }
    fn piece_state(&self, piece: usize, s: f64) -> JointState {
        // The later side backwards is the earlier side forwards.
        let d = self.0.piece_durations();
        let i = d.len() - 1 - piece;
        let st = self.0.piece_state_before(i, d[i] - s);
        JointState { q: st.q, qd: st.qd.map(|v| -v), qdd: st.qdd }
    }
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64> {
        let d = self.0.piece_durations();
        let i = d.len() - 1 - piece;
        self.0.acceleration_jumps(i).iter().rev().map(|s| d[i] - s).collect()
    }
    fn piece_state_before(&self, piece: usize, s: f64) -> JointState {
        let d = self.0.piece_durations();
        let i = d.len() - 1 - piece;
        let st = self.0.piece_state(i, d[i] - s);
        JointState { q: st.q, qd: st.qd.map(|v| -v), qdd: st.qdd }
    }
}

impl Trajectory for Schedule {
    fn piece_durations(&self) -> Vec<f64> {
        self.durations.to_vec()
    }
    fn piece_state(&self, piece: usize, s: f64) -> JointState {
        self.phase_state(Phase::ALL[piece.min(2)], s)
    }
    /// The breakpoints of the phase's timing profile (a piecewise profile's acceleration, and so
    /// `q̈`, may jump there: the QP's and the refinement's piecewise-linear rates at every node).
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64> {
        let phase = Phase::ALL[piece.min(2)];
        let d = self.durations[phase.index()];
        self.timing(phase).inner_breakpoints().map(|u| u * d).collect()
    }
    fn piece_state_before(&self, piece: usize, s: f64) -> JointState {
        self.phase_state_with(Phase::ALL[piece.min(2)], s, Profile::at_before)
    }
}

/// A complete manoeuvre: bend, twist along a path with a profile, unbend.
#[derive(Clone, Debug, PartialEq)]
pub struct Schedule {
    /// Durations `T1, T2, T3`, s.
    pub durations: [f64; 3],
    /// The bend `β = π − θ`, rad.
    pub bend: f64,
    /// The path of the bend direction through the joint.
    pub path: BendPath,
    /// Shape of the circulation rate.
    pub profile: Profile,
    /// Circulation `D = ∫ω ds`, rad.
    pub circulation: f64,
    /// Timing of the bend, `q1 = β P_b(t/T1)`: the paper's [`Profile::harmonic`] unless retimed.
    pub bend_profile: Profile,
    /// Timing of the unbend, `q = q_e (1 − P_u(u/T3))`: [`Profile::harmonic`] unless retimed.
    pub unbend_profile: Profile,
}

impl Schedule {
    /// Total duration, s.
    pub fn duration(&self) -> f64 {
        self.durations.iter().sum()
    }

    /// Start time of a phase, s.
    pub fn phase_start(&self, phase: Phase) -> f64 {
        self.durations[..phase.index()].iter().sum()
    }

    /// The state at local time `s ∈ [0, T_phase]` of a phase, by that phase's own formula.
    pub fn phase_state(&self, phase: Phase, s: f64) -> JointState {
        self.phase_state_with(phase, s, Profile::at)
    }

    /// The profile that times `phase`.
    pub(crate) fn timing(&self, phase: Phase) -> &Profile {
        match phase {
            Phase::Bend => &self.bend_profile,
            Phase::Twist => &self.profile,
            Phase::Unbend => &self.unbend_profile,
        }
    }

    /// [`Schedule::phase_state`] with the phase's timing profile read by `at` (its value, or its
    /// left limit at a breakpoint): the profile times the phase's progress variable.
    fn phase_state_with(&self, phase: Phase, s: f64, at: fn(&Profile, f64) -> ProfilePoint) -> JointState {
        let t = self.durations[phase.index()];
        let p = at(self.timing(phase), s / t);
        let d = self.progress_distance(phase);
        self.progress_state(phase, d * p.position, d * p.rate / t, d * p.accel / (t * t))
    }

    /// The distance `∫φ̇` a phase's progress variable covers ([`Schedule::progress_state`]).
    pub fn progress_distance(&self, phase: Phase) -> f64 {
        match phase {
            Phase::Bend => self.bend,
            Phase::Twist => self.circulation,
            Phase::Unbend => 1.0,
        }
    }

    /// The joint state at a phase's progress variable `φ` with its rates: joint 1's angle in the
    /// bend (`φ ∈ [0, β]`), the bend direction on the bend path in the twist (`φ ∈ [0, D]`), the
    /// fraction straightened in the unbend (`φ ∈ [0, 1]`, along [`Schedule::unbend_line`]).
    pub fn progress_state(&self, phase: Phase, phi: f64, phid: f64, phidd: f64) -> JointState {
        match phase {
            Phase::Bend => JointState { q: [phi, 0.0], qd: [phid, 0.0], qdd: [phidd, 0.0] },
            Phase::Twist => self.path_state(phi, phid, phidd),
            Phase::Unbend => {
                let (straight, e) = self.unbend_line();
                JointState {
                    q: [0, 1].map(|j| straight[j] + e[j] * (1.0 - phi)),
                    qd: e.map(|x| -x * phid),
                    qdd: e.map(|x| -x * phidd),
                }
            }
        }
    }

    /// The straight line the unbend follows, `q = straight + e (1 − f)` for the fraction `f`
    /// straightened: from the twist's end towards the nearest straight pose.
    pub fn unbend_line(&self) -> ([f64; 2], [f64; 2]) {
        let end = self.phase_state(Phase::Twist, self.durations[1]).q;
        let straight = nearest_straight(end);
        (straight, [end[0] - straight[0], end[1] - straight[1]])
    }

    /// The state at global time `t`; at a phase boundary the later phase's formula is used.
    pub fn state(&self, t: f64) -> JointState {
        let (phase, s) = self.locate(t);
        self.phase_state(phase, s)
    }

    /// The phase containing global time `t` (the later one at a boundary) and the local time.
    pub fn locate(&self, t: f64) -> (Phase, f64) {
        let [t1, t2, t3] = self.durations;
        if t < t1 {
            (Phase::Bend, t.max(0.0))
        } else if t < t1 + t2 {
            (Phase::Twist, t - t1)
        } else {
            (Phase::Unbend, (t - t1 - t2).min(t3))
        }
    }

    /// Joint state on the bend path at direction `φ` with its derivatives.
    pub fn path_state(&self, phi: f64, phid: f64, phidd: f64) -> JointState {
        let b = self.bend;
        let (sp, cp) = phi.sin_cos();
        match self.path {
            BendPath::JointCircle => JointState {
                q: [b * cp, b * sp],
                qd: [-b * sp * phid, b * cp * phid],
                qdd: [-b * (sp * phidd + cp * phid * phid), b * (cp * phidd - sp * phid * phid)],
            },
            BendPath::Cone => {
                let (sb, cb) = b.sin_cos();
                let (y, x) = (sb * cp, cb);
                // Continue atan2 through ±π when x < 0 (bend beyond 90°).
                let q1 = if x >= 0.0 { y.atan2(x) } else { PI - y.atan2(-x) };
                let q2 = (sb * sp).clamp(-1.0, 1.0).asin();
                let den = cb * cb + sb * sb * cp * cp;
                let e = (1.0 - sb * sb * sp * sp).max(0.0).sqrt();
                let g1 = -cb * sb * sp / den;
                let g1p = (-cb * sb * cp * den - 2.0 * cb * sb.powi(3) * sp * sp * cp) / (den * den);
                let g2 = sb * cp / e;
                let g2p = -sb * sp * cb * cb / e.powi(3);
                JointState {
                    q: [q1, q2],
                    qd: [g1 * phid, g2 * phid],
                    qdd: [g1p * phid * phid + g1 * phidd, g2p * phid * phid + g2 * phidd],
                }
            }
        }
    }
}

/// The straight configuration `(2πk₁, 2πk₂)` nearest to `q` (each `k` rounds `q/2π`): the
/// unbend goes there, so it straightens by the short way from the configuration reached.
///
/// `(q1, q2)` and `(q1 + 2πk₁, q2 + 2πk₂)` are the same configuration, so every such point is
/// the straight cat. The cone path continues `q1` through ±π when the bend exceeds 90°; from
/// e.g. `q1 = 3.5747` rad, unbending to `q1 = 0` would fold the halves onto each other
/// (`q1 = π`) on the way, while unbending to `2π` moves joint 1 on by only 2.7085 rad, the
/// same as unbending from the equivalent `q1 = −2.7085` rad, without a jump in the joint
/// angle. (The family `(q1 ± π, π − q2)` puts B's axis in the same direction but turns B by π
/// about its own axis, `Rx(q1 ± π) Ry(π − q2) = Rx(q1) Ry(q2) Rz(π)`: not the same
/// configuration, so it is no start for the unbend.)
pub fn nearest_straight(q: [f64; 2]) -> [f64; 2] {
    q.map(|v| 2.0 * PI * (v / (2.0 * PI)).round())
}

/// Why a schedule cannot be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ScheduleError {
    /// The paper's `C` is not positive, so `π/C` is no circulation.
    #[error("manoeuvre.circulation = \"paper\": {}, so π/C is no circulation; bend more (lower manoeuvre.theta_deg) or set manoeuvre.circulation = \"calibrated\" or a number of radians", self.detail())]
    NonPositiveC(f64, f64),
    /// The paper's `π/C` is beyond [`crate::problem::manoeuvre::MAX_CIRCULATION`].
    #[error("manoeuvre.circulation = \"paper\": {}; bend more (lower manoeuvre.theta_deg) or give a circulation", self.detail())]
    CirculationTooLarge(f64, f64),
}

impl ScheduleError {
    /// Why there is no `π/C`, in a few words: its own message's, and the calibration's (which
    /// starts from it).
    pub fn detail(&self) -> String {
        use crate::numeric::numfmt::{echo, num};
        match self {
            ScheduleError::NonPositiveC(c, theta) => format!(
                "the paper's C = 1 − I_zz sin(θ/2)/I_yy = {} is not positive at manoeuvre.theta_deg = {}",
                num(*c),
                echo(*theta)
            ),
            ScheduleError::CirculationTooLarge(d, c) => format!(
                "π/C = {} rad (C = {}: the cat is nearly straight) exceeds the {} rad a schedule may circulate",
                num(*d),
                num(*c),
                crate::problem::manoeuvre::MAX_CIRCULATION
            ),
        }
    }
}

impl Schedule {
    /// The schedule of a problem's manoeuvre with a given circulation `D`, rad.
    pub fn new(problem: &crate::problem::Problem, circulation: f64) -> Schedule {
        Schedule::from_manoeuvre(&problem.manoeuvre, problem.drop.fall_time(), circulation)
    }

    /// The schedule of manoeuvre `m` over a fall of `fall_time` s with circulation `D`, rad: the
    /// phases split the fall time, the twist phase uses `m`'s library profile, bend and unbend the
    /// harmonic one.
    pub fn from_manoeuvre(m: &crate::problem::Manoeuvre, fall_time: f64, circulation: f64) -> Schedule {
        let t = fall_time;
        Schedule {
            durations: m.phases.map(|f| f * t),
            bend: m.bend(),
            path: m.bend_path,
            profile: Profile::library(m.profile),
            circulation,
            bend_profile: Profile::harmonic(),
            unbend_profile: Profile::harmonic(),
        }
    }

    /// The same schedule with another profile.
    pub fn with_profile(&self, profile: Profile) -> Schedule {
        Schedule { profile, ..self.clone() }
    }

    /// The same schedule with another circulation.
    pub fn with_circulation(&self, circulation: f64) -> Schedule {
        Schedule { circulation, ..self.clone() }
    }
}

/// The paper's circulation `π / C` with `C = 1 − I_zz sin(θ/2) / I_yy` (the code's form),
/// `I_yy = I_xx cos²(θ/2) + I_zz sin²(θ/2)` per half, evaluated with the correct inertia.
pub fn paper_circulation(cat: &crate::model::Cylinder, theta: f64) -> Result<f64, ScheduleError> {
    let c = paper_c(cat.transverse(), cat.axial(), theta);
    if c <= 0.0 {
        Err(ScheduleError::NonPositiveC(c, theta.to_degrees()))
    } else if PI / c > crate::problem::manoeuvre::MAX_CIRCULATION {
        Err(ScheduleError::CirculationTooLarge(PI / c, c))
    } else {
        Ok(PI / c)
    }
}

/// The code's `C = 1 − I_zz sin(θ/2) / I_yy` for transverse and axial moments of a half.
pub fn paper_c(transverse: f64, axial: f64, theta: f64) -> f64 {
    let bent = crate::model::BentMoments::new(transverse, axial, theta);
    1.0 - axial * (0.5 * theta).sin() / bent.yy
}
