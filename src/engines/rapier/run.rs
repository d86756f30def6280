//! One schedule through rapier: the stepping loop and what it measures.

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Serialize, Serializer};

use super::measure::{angular_momentum, JumpWindow, TorqueEstimator, TorqueSample};
use super::pieces::{Pieces, ACCEL_JUMP_FRACTION};
use super::saturation::{available_torque, bounds_torque, MotorSaturation, SaturationTracker};
use super::scene::{CatScene, MotorGains};
use super::{RapierError, RapierOptions, MAX_STEPS, MIN_STEPS_PER_PHASE};
use crate::engines::models::TwoMotorCat;
use crate::engines::peaks::PhasePeaks;
use crate::engines::torque::{joint_torques, joint_torques_spinning};
use crate::model::orientation::{swing_twist, TwistTracker};
use crate::problem::settings::{RapierSettings, TimeStep};
use crate::schedule::{JointState, Phase, Trajectory};

/// Torque samples within this many steps of a rough piece boundary (where `q̇` or `q̈` jumps,
/// [`Pieces::rough`]) are left out of the per-phase peaks: two for the stencil, two for the
/// servo to settle after a jump of `q̈` (it shrinks an error about twentyfold per step); and as
/// many after the start of the run ([`settling`]).
const BOUNDARY_STEPS: f64 = 4.0;

/// Whether a torque sample at `t` falls within [`BOUNDARY_STEPS`] steps of a rough boundary
/// (`rough`, s) or of the start of a run at step `dt`, and so is left out of the peaks. The cat
/// starts from rest: where `q̈` jumps there, the first steps are the servo's transient, as after
/// a rough boundary, not the plan's torque (a cat with a tail and legs whose plan starts at its
/// peak torque: its cat joint's first motor read 0.2103 N·m at the second step against the plan's
/// 0.1990 there, 5.7 % high, its peak 4.9 % above the plan's at 0.2 ms and at 0.1 ms alike, and
/// within 4e-5 N·m of the plan from the fourth step on). A plan that peaks at the start is then
/// read five steps in, an error of first order in the step that the extrapolation removes (what
/// is left of the transient there does not shrink with the step, but the servo has shrunk it
/// twentyfold a step since). The end needs no margin: the run stops there
/// with the servo on its plan, and a torque that peaks at the end (the spherical joint's third
/// motor may) is read up to the last step before it, again an error of first order.
pub(super) fn settling(t: f64, rough: &[f64], dt: f64) -> bool {
    let margin = BOUNDARY_STEPS * dt;
    t <= margin || rough.iter().any(|b| (t - b).abs() <= margin)
}

/// Half-width, in steps, of the window whose samples make up the motors' answer to a jump of
/// `q̇`: the stencil's two steps and four for the servo's transient.
const JUMP_STEPS: f64 = 6.0;

/// Torque samples within this many steps of a jump of `q̈` inside a piece are left out of the
/// peaks: the stencil's two steps and the servo's ringing, which overshoots by about a tenth of
/// the torque's jump two steps after it and has decayed to a fiftieth of it six steps after
/// (measured on a retimed path, dt = 54 µs … 434 µs; see the module docs).
const ACCEL_JUMP_STEPS: f64 = 6.0;

/// One sample of the orientation history.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TwistSample {
    /// Time, s.
    pub t: f64,
    /// Twist of A about its initial spine axis (continued), rad.
    pub twist: f64,
    /// Swing of A's spine axis, rad.
    pub swing: f64,
}

/// Peak joint torques per piece, from samples whose stencil lies inside the piece, N·m.
#[derive(Clone, Debug, PartialEq, Serialize, Default)]
pub struct TorquePeaks {
    /// `max |τ_i|` per piece of the trajectory (for a [`crate::schedule::Schedule`]: bend,
    /// twist, unbend), joints 1 and 2.
    pub per_piece: Vec<[f64; 2]>,
    /// The largest of the above.
    pub max: f64,
}

impl TorquePeaks {
    fn new(pieces: usize) -> Self {
        Self { per_piece: vec![[0.0; 2]; pieces], max: 0.0 }
    }

    fn add(&mut self, piece: usize, tau: [f64; 2]) {
        if let Some(slot) = self.per_piece.get_mut(piece) {
            for (s, t) in slot.iter_mut().zip(tau) {
                *s = s.max(t.abs());
                self.max = self.max.max(t.abs());
            }
        }
    }

    /// Each joint's peak over the pieces (their largest is [`TorquePeaks::max`]), which a step
    /// refinement extrapolates motor by motor ([`super::richardson_peaks`]). Not piece by piece:
    /// a piece of the whole optimum is one span of its spline, a few samples wide, whose peak
    /// jumps as the samples move with the step.
    pub fn per_motor(&self) -> Vec<f64> {
        (0..2).map(|j| self.per_piece.iter().map(|p| p[j]).fold(0.0, f64::max)).collect()
    }

    /// The peaks of one phase of a three-piece trajectory (a schedule); `None` for another
    /// number of pieces.
    pub fn phase(&self, phase: Phase) -> Option<[f64; 2]> {
        (self.per_piece.len() == Phase::ALL.len()).then(|| self.per_piece[phase.index()])
    }

    /// The per-phase view of a three-piece trajectory (a schedule) in the type both engines
    /// report; `None` for another number of pieces.
    pub fn phase_peaks(&self) -> Option<PhasePeaks> {
        Some(PhasePeaks {
            bend: self.phase(Phase::Bend)?,
            twist: self.phase(Phase::Twist)?,
            unbend: self.phase(Phase::Unbend)?,
            max: self.max,
        })
    }
}

/// The motors' answer to a jump of the schedule's joint rates: an impulse, seen as a spike.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct JumpTorque {
    /// Time of the jump, s.
    pub time: f64,
    /// Largest `|τ_i|` of the samples within six steps of the jump, N·m (grows as `1/dt`).
    pub peak: [f64; 2],
    /// `Σ (τ_i − τ_smooth) dt` over those samples, N·m·s, with the smooth torque interpolated
    /// across the window: the generalized impulse the motors delivered.
    pub impulse: [f64; 2],
}

/// Angular-momentum bookkeeping of a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MomentumDrift {
    /// `max_k |H_k − H_0|`, N·m·s.
    pub max_abs: f64,
    /// Reference momentum `I* · max_t |q̇(t)|`, N·m·s.
    pub reference: f64,
    /// `max_abs / reference`; `max_abs` itself for a trajectory that does not move (reference
    /// zero), as the exact engine's `momentum_max`.
    pub max_rel: f64,
    /// `H` at the end, world frame, N·m·s.
    pub last: [f64; 3],
}

/// Everything measured in one rapier run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RapierRun {
    /// The step asked for, s.
    pub dt_requested: f64,
    /// The step used, `T / ceil(T / dt_requested)`, so that the last step ends on `T`, s.
    pub dt: f64,
    /// Number of steps.
    pub steps: usize,
    /// Motor gains.
    pub gains: MotorGains,
    /// Gauss–Seidel sweeps per step.
    pub pgs_iterations: usize,
    /// A's final orientation, serialised as `[w, x, y, z]`.
    #[serde(serialize_with = "quat_wxyz")]
    pub orientation: UnitQuaternion<f64>,
    /// Final twist about A's initial `+z`, rad (signed, continued).
    pub twist: f64,
    /// Final swing of A's spine axis, rad.
    pub swing: f64,
    /// Twist and swing along the run.
    pub twist_history: Vec<TwistSample>,
    /// Joint angles reached at the end, rad.
    pub final_q: [f64; 2],
    /// `max_k |q_k − q(t_k)|` per joint, rad.
    pub tracking_error: [f64; 2],
    /// Angular-momentum drift.
    pub momentum: MomentumDrift,
    /// Peak joint torques per piece.
    pub peak_torque: TorquePeaks,
    /// Largest `|τ_i|` of all samples, boundary and jump samples included, N·m.
    pub peak_torque_all: f64,
    /// Jumps of `q̈` inside pieces whose neighbourhood is kept out of the peaks (those of the
    /// trajectory's [`Trajectory::acceleration_jumps`] above `ACCEL_JUMP_FRACTION`).
    pub acceleration_jumps: usize,
    /// Fraction of the torque samples left out of the peaks for being near one of them.
    pub acceleration_jump_excluded: f64,
    /// The motors' spikes at the schedule's rate jumps.
    pub jumps: Vec<JumpTorque>,
    /// Joint torques along the run.
    pub torque_history: Vec<TorqueSample>,
    /// The joints whose motors saturated ([`super::saturation`]); empty when none did, or when
    /// the motors bound no torque (then absent from JSON).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub saturation: Vec<MotorSaturation>,
    /// On the ball joint (the no-twist joint), the largest twist of B about its spine relative
    /// to A over the run, rad (the twist of `R_A⁻¹ R_B` by [`swing_twist`]): how well rapier held the
    /// joint's constraint. `None` (absent from JSON) on the universal joint.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spine_twist_max: Option<f64>,
}

pub(super) fn quat_wxyz<S: Serializer>(q: &UnitQuaternion<f64>, s: S) -> Result<S::Ok, S::Error> {
    [q.w, q.i, q.j, q.k].serialize(s)
}

/// Runs a trajectory in rapier with the default [`RapierOptions`], at `settings.dt` (the
/// automatic choice is [`super::time_scales`]' first step).
pub fn simulate(
    cat: &TwoMotorCat,
    traj: &impl Trajectory,
    settings: &RapierSettings,
) -> Result<RapierRun, RapierError> {
    simulate_with(cat, traj, settings, &RapierOptions::default())
}

/// Runs a trajectory at each step of `dts` (e.g. 1/60 … 1/8000 s) with the default options.
pub fn dt_sweep(
    cat: &TwoMotorCat,
    traj: &impl Trajectory,
    settings: &RapierSettings,
    dts: &[f64],
) -> Result<Vec<RapierRun>, RapierError> {
    dts.iter().map(|&dt| simulate(cat, traj, &settings.with_dt(dt))).collect()
}

/// The schedule's motor torques at `target`, N·m, at zero angular momentum or with the total
/// momentum `lambda` in A's frame: the paper's cat through the two-cylinder engine, any other
/// model through the general core.
fn planned_torques(cat: &TwoMotorCat, target: &JointState, lambda: Option<&Vector3<f64>>) -> [f64; 2] {
    match (cat.cat().paper(), lambda) {
        (Some(half), Some(l)) => joint_torques_spinning(half, target, l).tau,
        (Some(half), None) => joint_torques(half, target).tau,
        (None, Some(l)) => two(&cat.joint_torques_spinning(target, l).tau),
        (None, None) => two(&cat.joint_torques(target).tau),
    }
}

/// The two motor torques of a two-motor model's link.
fn two(tau: &[f64]) -> [f64; 2] {
    [tau[0], tau[1]]
}

/// The steps of a run of `duration` s at the `requested` step (at least one), or
/// [`RapierError::TooManySteps`].
pub(super) fn step_count(duration: f64, requested: f64) -> Result<usize, RapierError> {
    let steps = (duration / requested).ceil();
    if steps.is_nan() || steps > MAX_STEPS as f64 {
        return Err(RapierError::TooManySteps { dt: requested, duration, steps, max: MAX_STEPS });
    }
    Ok((steps as usize).max(1))
}

/// Refuses a `requested` step that leaves fewer than [`MIN_STEPS_PER_PHASE`] steps in the
/// `shortest` smooth stretch of a trajectory, s ([`RapierError::TooCoarse`]).
pub(super) fn resolves(shortest: f64, requested: f64) -> Result<(), RapierError> {
    if shortest / requested < MIN_STEPS_PER_PHASE as f64 {
        return Err(RapierError::TooCoarse {
            dt: requested,
            phase: shortest,
            steps: shortest / requested,
            min: MIN_STEPS_PER_PHASE,
        });
    }
    Ok(())
}

/// Runs a trajectory in rapier (module docs: scene, motors, measurements) on `cat`: the paper's
/// cat or any other on the universal joint (unequal halves); another joint is refused
/// ([`RapierError::UnsupportedJoint`]).
pub fn simulate_with(
    cat: &TwoMotorCat,
    traj: &impl Trajectory,
    settings: &RapierSettings,
    opts: &RapierOptions,
) -> Result<RapierRun, RapierError> {
    settings.validate()?;
    opts.validate()?;
    let pieces = Pieces::new(traj);
    let duration = pieces.duration();
    if !(duration.is_finite() && duration > 0.0) {
        return Err(RapierError::BadDuration(duration));
    }
    let requested = match settings.dt {
        TimeStep::Fixed(dt) => dt,
        TimeStep::Auto => super::time_scales_within(cat, traj, &opts.motors).first_step,
    };
    let n = step_count(duration, requested)?;
    // Boundaries where the motion is smooth (a spline's knots) are not the servo's business.
    let rough = pieces.rough(ACCEL_JUMP_FRACTION);
    resolves(pieces.shortest_smooth(&rough), requested)?;
    let dt = duration / n as f64;
    let time = |k: usize| if k == n { duration } else { k as f64 * dt };
    let gains = MotorGains::new(opts.bandwidth_per_step / dt, opts.damping_ratio);
    let start = pieces.state(0.0);
    let mut scene =
        CatScene::new(cat.cat(), settings.cross_mass_fraction, dt, opts.pgs_iterations, Some(gains), start.q)?;
    scene.start_with_momentum(start.qd, &opts.spin)?;
    let masses = *scene.masses();

    let mut windows: Vec<JumpWindow> = cat
        .velocity_jumps(traj, |k| traj.boundary_rate_uncertainty(k))
        .iter()
        .map(|j| JumpWindow::new(j.time, JUMP_STEPS * dt))
        .collect();
    let boundaries = pieces.rough_boundaries(&rough);
    let accel_jumps = pieces.acceleration_jumps(ACCEL_JUMP_FRACTION);
    let accel_margin = ACCEL_JUMP_STEPS * dt;
    let near_accel_jump = |t: f64| {
        let i = accel_jumps.partition_point(|&j| j < t - accel_margin);
        accel_jumps.get(i).is_some_and(|&j| j <= t + accel_margin)
    };
    let mut accel_excluded = 0usize;
    // The motors' torque bounds, when their limits bound any torque (ideal motors: untouched).
    let bounded = bounds_torque(&opts.motors).then_some(opts.motors);
    let mut saturation = SaturationTracker::default();

    let stride = n.div_ceil(opts.history.max(1)).max(1);
    let mut tracker = TwistTracker::default();
    let mut torques = TorqueEstimator::default();
    let mut peaks = TorquePeaks::new(pieces.durations().len());
    let mut peak_all = 0.0f64;
    let mut torque_count = 0usize;
    let mut twist_history = Vec::with_capacity(n / stride + 2);
    let mut torque_history = Vec::with_capacity(n / stride + 2);
    let mut tracking = [0.0f64; 2];
    let mut h0 = None;
    let mut drift = 0.0f64;
    let mut last_h = nalgebra::Vector3::zeros();
    let mut last = None;

    // The largest joint rate of the schedule, over the steps' instants.
    let mut qd_max = 0.0f64;
    let mut spine_twist_max = None;

    for k in 0..=n {
        let t = time(k);
        // The schedule at t: the targets of the step that ends there and the tracking reference.
        let target = pieces.state(t);
        qd_max = qd_max.max(target.qd[0].hypot(target.qd[1]));
        if k > 0 {
            // Each motor's torque at rapier's joint rate at the start of the step, against the
            // schedule's own torque at its end (released with spin, at rapier's current attitude).
            let limited = match &bounded {
                Some(motors) => {
                    let rate = scene.joint_rates()?;
                    let bound: [Option<f64>; 2] = std::array::from_fn(|j| available_torque(&motors.joints[j], rate[j]));
                    let lambda = if opts.spin.norm_squared() > 0.0 {
                        Some(scene.snapshot()?.rotations[0].inverse_transform_vector(&opts.spin))
                    } else {
                        None
                    };
                    Some((bound, planned_torques(cat, &target, lambda.as_ref())))
                }
                None => None,
            };
            let reaching = limited.map_or([true; 2], |(bound, _)| bound.map(|b| b.is_none()));
            // Targets from the schedule at the end of the step, the position shifted by −h q̇ so
            // that the motor's spring pulls the end-of-step position onto q(t_{k+1}).
            scene.set_plan(&target, reaching)?;
            if let Some((bound, need)) = limited {
                scene.set_max_forces(bound)?;
                saturation.step(t, &bound, &need);
            }
            scene.step();
        }
        let snap = scene.snapshot()?;
        if !snap.is_finite() {
            return Err(RapierError::Diverged(t));
        }
        let h = angular_momentum(&masses, &snap.bodies(&masses));
        drift = drift.max((h - *h0.get_or_insert(h)).norm());
        last_h = h;
        if snap.layout == super::bodies::Layout::Ball {
            let twist = swing_twist(&(snap.rotations[0].inverse() * snap.rotations[2])).twist.abs();
            spine_twist_max = Some(spine_twist_max.map_or(twist, |m: f64| m.max(twist)));
        }
        let st = tracker.update(&snap.rotations[0]);
        for (e, (q, s)) in tracking.iter_mut().zip(snap.q.iter().zip(target.q)) {
            *e = e.max((q - s).abs());
        }
        if k % stride == 0 || k == n {
            twist_history.push(TwistSample { t, twist: st.twist, swing: st.swing });
        }
        if let Some(sample) = torques.push(&masses, t, &snap) {
            peak_all = peak_all.max(sample.tau[0].abs()).max(sample.tau[1].abs());
            let mut in_jump = false;
            for w in &mut windows {
                in_jump |= w.offer(&sample);
            }
            if !in_jump && !settling(sample.t, &boundaries, dt) {
                if near_accel_jump(sample.t) {
                    accel_excluded += 1;
                } else {
                    peaks.add(pieces.locate(sample.t).0, sample.tau);
                }
            }
            if torque_count % stride == 0 {
                torque_history.push(sample);
            }
            torque_count += 1;
        }
        last = Some((snap.rotations[0], st, snap.q));
    }
    let (orientation, angles, final_q) = last.ok_or(RapierError::Missing("a final state"))?;
    let reference = cat.cat().rear.end_transverse() * qd_max;

    Ok(RapierRun {
        dt_requested: requested,
        dt,
        steps: n,
        gains,
        pgs_iterations: opts.pgs_iterations,
        orientation,
        twist: angles.twist,
        swing: angles.swing,
        twist_history,
        final_q,
        tracking_error: tracking,
        momentum: MomentumDrift {
            max_abs: drift,
            reference,
            max_rel: if reference > 0.0 { drift / reference } else { drift },
            last: [last_h.x, last_h.y, last_h.z],
        },
        peak_torque: peaks,
        peak_torque_all: peak_all,
        acceleration_jumps: accel_jumps.len(),
        acceleration_jump_excluded: if torque_count > 0 { accel_excluded as f64 / torque_count as f64 } else { 0.0 },
        jumps: windows
            .iter()
            .map(|w| {
                let (peak, impulse) = w.finish(dt);
                JumpTorque { time: w.time, peak, impulse }
            })
            .collect(),
        torque_history,
        saturation: saturation.finish(),
        spine_twist_max,
    })
}

/// First-order Richardson extrapolation of two runs of one schedule to `dt → 0`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Extrapolated {
    /// The two steps used, coarse then fine, s.
    pub dt: [f64; 2],
    /// Extrapolated twist, rad.
    pub twist: f64,
    /// Extrapolated swing, rad (the swing's rotation vector is extrapolated, then its length
    /// taken: the angle itself is not smooth where it passes through zero).
    pub swing: f64,
    /// Extrapolated overall peak torque, N·m: the largest of each motor's peak extrapolated on
    /// its own ([`super::richardson_peaks`]).
    pub peak_torque: f64,
}

/// The swing's rotation vector `(x, y, 0)` of an orientation `r` with twist `twist` (rad):
/// `log(r · Rz(−twist))`, the swing–twist split `r = S · Rz(twist)`. Its length is the swing
/// angle; unlike that length it is smooth in the step, so rapier's runs are compared and
/// extrapolated through it (the length is not smooth where the vector passes near zero).
pub fn swing_vector(r: &UnitQuaternion<f64>, twist: f64) -> nalgebra::Vector3<f64> {
    let untwist = UnitQuaternion::from_axis_angle(&nalgebra::Vector3::z_axis(), -twist);
    (r * untwist).scaled_axis()
}

/// Extrapolates `x(0) ≈ x_f + (x_f − x_c)/(r − 1)`, `r = dt_c/dt_f`, which removes the leading
/// `O(dt)` error of rapier's first-order integrator (the order [`dt_sweep`] measures); `None`
/// if the steps are equal.
pub fn extrapolate(a: &RapierRun, b: &RapierRun) -> Option<Extrapolated> {
    let (c, f) = if a.dt >= b.dt { (a, b) } else { (b, a) };
    let r = c.dt / f.dt;
    if r.is_nan() || r <= 1.0 + 1e-9 {
        return None;
    }
    let (sc, sf) = (swing_vector(&c.orientation, c.twist), swing_vector(&f.orientation, f.twist));
    Some(Extrapolated {
        dt: [c.dt, f.dt],
        twist: super::richardson(c.twist, f.twist, r),
        swing: super::richardson(sc, sf, r).norm(),
        peak_torque: super::largest(&super::richardson_peaks(
            &c.peak_torque.per_motor(),
            &f.peak_torque.per_motor(),
            r,
        )),
    })
}
