//! Runs and verifications of a shape trajectory on a tree of bodies in rapier
//! ([`super::tree_scene`]): the cats beyond two motors (a spherical joint's third motor, a tail),
//! measured as the two-body cat is (module docs of [`crate::engines::rapier`]) and judged by the
//! same step refinement and verdict ([`super::verify`]).
//!
//! Each step's motors aim at the trajectory's shape at the step's end ([`TreeScene::aim`]); the
//! cat starts at the trajectory's first shape and rates with zero momentum. A run measures:
//! - the base's (A's) orientation at the end, its twist and swing as the two-body run's;
//! - the largest tracking error of each link: the angle between the relative rotation reached
//!   and the planned `R(q(t_k))`;
//! - the drift of the total angular momentum, relative to the largest momentum of the shape
//!   motion, `max_t |h(t)|` (the momentum the bodies would carry relative to A with A held
//!   still, [`crate::engines::reduction::locked_and_shape_momentum`]);
//! - each motor's torque, from Newton–Euler on the bodies it drives (the link's subtree and joint
//!   bodies; the universal joint's second motor leaves the cross out) about the joint point
//!   `P`: `τ = a · (Ḣ_P + v_P × p)`, by central differences of the momenta at the second-order
//!   velocities `(v_k + v_{k+1})/2`, as the two-body run's; samples within four steps of the
//!   start are left out of the peaks, as the two-body run's are (the servo's transient where the
//!   cat starts from rest: `run.rs`'s `settling`).
//!
//! With one torque limit on every motor ([`crate::model::motor::MotorsBeyond::TorqueLimit`]) the
//! universal and no-twist joints' motors are bounded by it ([`TreeScene::bound_motors`]) and each
//! step where the plan's torque (the general core's at the step's end) exceeds it counts as
//! saturated ([`super::saturation`]); the verdict then says so, as the two-body verification does.
//! A spherical joint's motors are not its ball's axes in rapier, and are not bounded: refused.
//!
//! So far the scene runs no spin, and smooth trajectories (`q`, `q̇`, `q̈`
//! continuous at the joins and inside the pieces, as the whole optimiser's splines are): a jump
//! would need the two-body run's exclusion windows ([`RapierError::TreeScope`] otherwise). A step
//! that leaves fewer than [`super::MIN_STEPS_PER_PHASE`] steps in the trajectory is refused
//! ([`RapierError::TooCoarse`]), as the two-body run refuses one in its shortest phase.

use nalgebra::{UnitQuaternion, Vector3};
use serde::Serialize;

use super::refinement::{convergences, judge, refine, saturated};
use super::run::{settling, MomentumDrift};
use super::saturation::{MotorSaturation, SaturationTracker};
use super::tree_scene::{bounds_motors, momenta, TreeScene, TreeSnapshot, UNBOUNDED_SPHERICAL};
use super::verdict::{RunRecord, StepSource, Verification};
use super::{MotorGains, RapierError, RapierOptions, Reference};
use crate::engines::reduction::{self, locked_and_shape_momentum};
use crate::engines::shape::{locate, ShapeTrajectory};
use crate::model::motor::{motors_beyond, MotorsBeyond};
use crate::model::orientation::TwistTracker;
use crate::model::shape::ShapeState;
use crate::model::tree::Tree;
use crate::problem::settings::{RapierSettings, TimeStep};

/// Continuity asked of a trajectory's joins, relative to the largest `|q|`, `|q̇|`, `|q̈|` there.
const SMOOTH: f64 = 1e-9;

/// One rapier run of a tree.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TreeRun {
    /// Step, s.
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// A's orientation at the end.
    #[serde(skip)]
    pub orientation: UnitQuaternion<f64>,
    /// Twist at the end, rad.
    pub twist: f64,
    /// Swing at the end, rad.
    pub swing: f64,
    /// Each motor's peak `|τ|`, N·m, in the shape's coordinate order.
    pub peak_torque: Vec<f64>,
    /// Each link's largest tracking error, rad.
    pub tracking_error: Vec<f64>,
    /// With a torque limit, the motors whose bound fell short of the plan's torque (DESIGN.md §9,
    /// [`super::saturation`]); empty with ideal motors.
    pub saturation: Vec<MotorSaturation>,
    /// Angular-momentum drift, relative to the shape motion's largest momentum.
    pub momentum: MomentumDrift,
}

/// A trajectory on one global clock.
struct Clock<'a, T: ShapeTrajectory> {
    traj: &'a T,
    durations: Vec<f64>,
}

impl<'a, T: ShapeTrajectory> Clock<'a, T> {
    fn new(traj: &'a T) -> Self {
        Self { traj, durations: traj.piece_durations() }
    }

    fn duration(&self) -> f64 {
        self.durations.iter().sum()
    }

    /// The shape at global time `t` ([`ShapeTrajectory::shape_at`], on the durations kept).
    fn shape(&self, t: f64) -> ShapeState {
        let (piece, s) = locate(&self.durations, t);
        self.traj.piece_shape(piece, s)
    }

    /// The first instant (global time) where `q`, `q̇` or `q̈` jumps, if any: at a join, or inside
    /// a piece where the trajectory says `q̈` may jump.
    fn first_jump(&self) -> Option<f64> {
        let mut start = 0.0;
        for (i, d) in self.durations.iter().enumerate() {
            if i > 0 {
                let (a, b) = (self.traj.piece_shape(i - 1, self.durations[i - 1]), self.traj.piece_shape(i, 0.0));
                let jumps = [(&a.q, &b.q), (&a.qd, &b.qd), (&a.qdd, &b.qdd)].iter().any(|(x, y)| {
                    let scale = x.iter().chain(y.iter()).fold(1.0f64, |m, v| m.max(v.abs()));
                    x.iter().zip(y.iter()).any(|(u, v)| (u - v).abs() > SMOOTH * scale)
                });
                if jumps {
                    return Some(start);
                }
            }
            if let Some(s) = self.traj.acceleration_jumps(i).first() {
                return Some(start + s);
            }
            start += d;
        }
        None
    }
}

/// Refuses what the tree scene does not run (module docs).
fn in_scope(tree: &Tree, clock: &Clock<impl ShapeTrajectory>, opts: &RapierOptions) -> Result<(), RapierError> {
    match motors_beyond(&opts.motors) {
        MotorsBeyond::Other => {
            return Err(RapierError::TreeScope(
                "runs ideal motors or one torque limit on every motor only, so far: remove the other [actuator] limits"
                    .into(),
            ))
        }
        MotorsBeyond::TorqueLimit(_) if !bounds_motors(tree) => {
            return Err(RapierError::TreeScope(UNBOUNDED_SPHERICAL.into()))
        }
        _ => {}
    }
    if opts.spin.norm_squared() > 0.0 {
        return Err(RapierError::TreeScope("runs a release without spin only, so far".into()));
    }
    let duration = clock.duration();
    if !(duration.is_finite() && duration > 0.0) {
        return Err(RapierError::BadDuration(duration));
    }
    let shape = clock.shape(0.0);
    if shape.len() != tree.dof() {
        return Err(RapierError::TreeScope(format!(
            "has {} joint coordinates; the trajectory has {}",
            tree.dof(),
            shape.len()
        )));
    }
    if let Some(t) = clock.first_jump() {
        return Err(RapierError::TreeScope(format!(
            "runs smooth trajectories only, so far: q, q̇ or q̈ jumps at t = {t} s"
        )));
    }
    Ok(())
}

/// Each motor's couple `a · (Ḣ_P + v_P × p)` parts at one record: `(H_P, v_P × p, a)` per motor.
type Couples = Vec<(Vector3<f64>, Vector3<f64>, Vector3<f64>)>;

fn couples(scene: &TreeScene, snap: &TreeSnapshot) -> Couples {
    let n = scene.tree().bodies().len();
    let mut out = Vec::new();
    for i in 0..scene.tree().links().len() {
        let joint_body = &snap.bodies[n + i];
        let (p, v_p) = (joint_body.position, joint_body.linvel);
        for (axis, driven) in scene.motors_of(i, snap) {
            let (mut h, mut lin) = (Vector3::zeros(), Vector3::zeros());
            for (b, _) in snap.bodies.iter().zip(&driven).filter(|(_, d)| **d) {
                h += b.inertia * b.angvel + b.mass * (b.position - p).cross(&b.linvel);
                lin += b.mass * b.linvel;
            }
            out.push((h, v_p.cross(&lin), axis));
        }
    }
    out
}

/// Runs `traj` on `tree` in rapier at the step `settings.dt` (automatic: the first step of
/// [`super::tree_time_scales`]), module docs.
pub fn simulate_tree(
    tree: &Tree,
    traj: &impl ShapeTrajectory,
    settings: &RapierSettings,
    opts: &RapierOptions,
) -> Result<TreeRun, RapierError> {
    settings.validate()?;
    opts.validate()?;
    let clock = Clock::new(traj);
    in_scope(tree, &clock, opts)?;
    let duration = clock.duration();
    let requested = match settings.dt {
        TimeStep::Fixed(dt) => dt,
        TimeStep::Auto => super::tree_time_scales(tree, traj).first_step,
    };
    let n = super::run::step_count(duration, requested)?;
    // The trajectory is smooth: its shortest phase is the whole of it.
    super::run::resolves(duration, requested)?;
    let dt = duration / n as f64;
    let time = |k: usize| if k == n { duration } else { k as f64 * dt };
    let gains = MotorGains::new(opts.bandwidth_per_step / dt, opts.damping_ratio);
    let start = clock.shape(0.0);
    let mut scene = TreeScene::new(tree, settings.cross_mass_fraction, dt, opts.pgs_iterations, gains, &start.q)?;
    scene.start_at_zero_momentum(&start.q, &start.qd)?;
    // With a torque limit, every motor bounded by it, and the steps where the plan needs more.
    let bounds = match motors_beyond(&opts.motors) {
        MotorsBeyond::TorqueLimit(limit) => Some(scene.bound_motors(limit)?),
        _ => None,
    };
    let mut saturation = SaturationTracker::default();

    let motors = tree.dof();
    let mut tracker = TwistTracker::default();
    let mut peaks = vec![0.0f64; motors];
    let mut tracking = vec![0.0f64; tree.links().len()];
    let (mut h0, mut drift, mut last_h, mut reference) = (None, 0.0f64, Vector3::zeros(), 0.0f64);
    // The previous record (for the velocities at its time) and the last three records' couples.
    let mut pending: Option<(f64, TreeSnapshot)> = None;
    let mut window: Vec<(f64, Couples)> = Vec::with_capacity(4);
    let mut last = None;
    for k in 0..=n {
        let t = time(k);
        let target = clock.shape(t);
        reference = reference.max(locked_and_shape_momentum(tree, &tree.motion(&target)).1.norm());
        if k > 0 {
            scene.aim(&target)?;
            if let Some(bound) = &bounds {
                let need: Vec<f64> = reduction::joint_torques(tree, &target, &Vector3::zeros())
                    .into_iter()
                    .flat_map(|l| l.tau)
                    .collect();
                saturation.step(t, bound, &need);
            }
            scene.step();
        }
        let snap = scene.snapshot()?;
        let finite = snap.velocities.iter().all(|v| v.is_finite())
            && snap.bodies.iter().all(|b| b.position.iter().chain(b.rotation.coords.iter()).all(|v| v.is_finite()));
        if !finite {
            return Err(RapierError::Diverged(t));
        }
        let h = momenta(&snap.bodies).angular;
        drift = drift.max((h - *h0.get_or_insert(h)).norm());
        last_h = h;
        for (i, (l, e)) in tree.links().iter().zip(tracking.iter_mut()).enumerate() {
            let reached = snap.bodies[l.parent].rotation.inverse() * snap.bodies[i + 1].rotation;
            let planned = UnitQuaternion::from_matrix(&l.joint.rotation(&target.q[tree.coordinates(i)]));
            *e = e.max(reached.angle_to(&planned));
        }
        let st = tracker.update(&snap.bodies[0].rotation);
        last = Some((snap.bodies[0].rotation, st));
        // Torques at the previous record, from the velocities around it.
        if let Some((t_prev, mut prev)) = pending.replace((t, snap.clone())) {
            let v: Vec<f64> = prev.velocities.iter().zip(&snap.velocities).map(|(a, b)| 0.5 * (a + b)).collect();
            prev.velocities = v;
            scene.map_velocities(&mut prev);
            window.push((t_prev, couples(&scene, &prev)));
            if window.len() > 3 {
                window.remove(0);
            }
            // The trajectory is smooth: only its start is rough.
            if let [(ta, a), (tm, m), (tb, b)] = &window[..] {
                if !settling(*tm, &[], dt) {
                    for (j, peak) in peaks.iter_mut().enumerate() {
                        let dh = (b[j].0 - a[j].0) / (tb - ta);
                        *peak = peak.max(m[j].2.dot(&(dh + m[j].1)).abs());
                    }
                }
            }
        }
    }
    let (orientation, angles) = last.ok_or(RapierError::Missing("a final state"))?;
    Ok(TreeRun {
        dt,
        steps: n,
        orientation,
        twist: angles.twist,
        swing: angles.swing,
        peak_torque: peaks,
        tracking_error: tracking,
        saturation: saturation.finish(),
        momentum: MomentumDrift {
            max_abs: drift,
            reference,
            max_rel: if reference > 0.0 { drift / reference } else { drift },
            last: [last_h.x, last_h.y, last_h.z],
        },
    })
}

/// Verifies `traj` on `tree` in rapier against the exact engine's `reference` (its flip and the
/// largest of its motors' peaks): the step refinement and the verdict of [`super::verify`], on
/// [`simulate_tree`]'s runs, each motor's peak extrapolated on its own and the largest judged.
/// `Err` when the settings are invalid or the tree scene does not run the trajectory (module
/// docs); every way a run can fail is a verdict.
pub fn verify_tree(
    tree: &Tree,
    traj: &impl ShapeTrajectory,
    settings: &RapierSettings,
    reference: &Reference,
    opts: &RapierOptions,
) -> Result<Verification, RapierError> {
    settings.validate()?;
    let clock = Clock::new(traj);
    in_scope(tree, &clock, opts)?;
    let scales = super::tree_time_scales(tree, traj);
    let (first, source) = match settings.dt {
        TimeStep::Fixed(dt) => (dt, StepSource::Fixed),
        TimeStep::Auto => (scales.first_step, StepSource::Auto),
    };
    let mut refined = refine(settings, reference, clock.duration(), first, |dt| {
        let run = simulate_tree(tree, traj, &settings.with_dt(dt), opts)?;
        Ok((record(&run), run))
    })?;
    let finest = refined.finest.take();
    let mut quantities = convergences(&refined.runs, reference, settings);
    let verdict = match &finest {
        // A bounded motor fell short of the plan's torque (with a torque limit): as the two-body
        // verification says it.
        Some(run) if !run.saturation.is_empty() => {
            saturated(&mut quantities, &refined.runs, &run.saturation, [run.twist, run.swing, run.dt], reference)
        }
        _ => judge(&quantities, reference, refined.runs.len(), &refined.why_stopped, &refined.failures),
    };
    Ok(refined.verification(verdict, quantities, (source, scales), settings, None))
}

fn record(run: &TreeRun) -> RunRecord {
    let mut record = RunRecord::new(
        run.dt,
        run.steps,
        [run.twist, run.swing],
        &run.orientation,
        run.peak_torque.clone(),
        run.tracking_error.clone(),
        run.momentum.max_rel,
    );
    record.saturation = run.saturation.clone();
    record
}
