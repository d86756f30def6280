//! Where the two halves are at given instants: what the animation draws.
//!
//! A's world orientation `R_A(t)` comes from the exact engine (on the paper's cat released
//! without spin [`crate::engines::exact::fall_history`], on any other cat or release the general
//! core's [`TwoMotorCat::fall_history`]), interpolated between its samples; B's is
//! `R_B = R_A · R_AB(q(t))` with the model's joint. The centres are placed so that the common
//! centre of mass stays at the origin: with `p = R_A [(0,0,−l_A/2) − R_AB (0,0,l_B/2)]` the vector
//! from A's centre to B's, `c_A = −m_B/(m_A+m_B) p` and `c_B = +m_A/(m_A+m_B) p` (`∓p/2` for equal
//! halves). World frame = A's body frame at `t = 0`; metres, radians.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

use crate::engines::exact::OrientationSample;
use crate::engines::models::{fall_history_on, TwoMotorCat};
use crate::engines::shape::ShapeTrajectory;
use crate::model::cat::Appendages;
use crate::model::tree::Tree;
use crate::schedule::{Phase, Trajectory};

/// Magnus steps over the whole fall of the orientation history the poses are interpolated from
/// (600 per phase of a three-phase schedule; [`TwoMotorCat::picture_history`]).
const HISTORY_STEPS: usize = 1800;

/// One half's place in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyPose {
    /// Centre of mass, m.
    pub centre: Vector3<f64>,
    /// Orientation: body-frame vectors to world-frame vectors.
    pub rotation: Matrix3<f64>,
}

impl BodyPose {
    /// A point given in the body frame, in the world frame.
    pub fn point(&self, local: Vector3<f64>) -> Vector3<f64> {
        self.centre + self.rotation * local
    }
}

/// The whole cat at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CatPose {
    /// Time, s.
    pub time: f64,
    /// The phase at that time (the later one at a boundary).
    pub phase: Option<Phase>,
    /// A's twist (continued), rad.
    pub twist: f64,
    /// A's swing, rad.
    pub swing: f64,
    /// The front half.
    pub a: BodyPose,
    /// The rear half.
    pub b: BodyPose,
    /// A tail, when the model has one (`tree_poses`).
    pub tail: Option<BodyPose>,
    /// The front and hind legs' rods, when the model has them (`tree_poses`), each turned so that
    /// its `z` is the rod's axis.
    pub legs: Option<[BodyPose; 2]>,
}

/// The cat's pose at each of `times` (s, clamped to the manoeuvre), released without spin.
pub fn cat_poses(cat: &TwoMotorCat, schedule: &impl Trajectory, times: &[f64]) -> Vec<CatPose> {
    cat_poses_spinning(cat, &Vector3::zeros(), schedule, times)
}

/// [`cat_poses`] for a release with total angular momentum `spin` (N·m·s, world frame).
pub fn cat_poses_spinning(
    cat: &TwoMotorCat,
    spin: &Vector3<f64>,
    schedule: &impl Trajectory,
    times: &[f64],
) -> Vec<CatPose> {
    let model = cat.cat();
    let samples = cat.picture_history(schedule, spin, HISTORY_STEPS);
    let (front, rear) = (model.front, model.rear);
    // The shares of A's-centre-to-B's-centre vector from the centre of mass to each centre.
    let share_a = rear.mass / (front.mass + rear.mass);
    let share_b = front.mass / (front.mass + rear.mass);
    let total = schedule.total_duration();
    times
        .iter()
        .map(|&t| {
            let t = t.clamp(0.0, total);
            let (orientation, twist, swing) = interpolate(&samples, t);
            let r_ab = model.joint.rotation(&schedule.state_at(t).q);
            let r_a = orientation.to_rotation_matrix().into_inner();
            let offset = Vector3::new(0.0, 0.0, -0.5 * front.length) - r_ab * Vector3::new(0.0, 0.0, 0.5 * rear.length);
            let p = r_a * offset;
            CatPose {
                time: t,
                phase: schedule.phase_at(t),
                twist,
                swing,
                a: BodyPose { centre: -share_a * p, rotation: r_a },
                b: BodyPose { centre: share_b * p, rotation: r_a * r_ab },
                tail: None,
                legs: None,
            }
        })
        .collect()
}

/// The poses of a tree of bodies at each of `times` (s, clamped to the trajectory), released
/// without spin: the cat's halves (bodies 0 and 1) and, as body 2, a tail. A's orientation comes
/// from the general core on the tree ([`crate::engines::models::fall_history_on`]); every body is
/// placed by the tree's relative motion at `traj`'s shape ([`Tree::motion`]: its rotation in A's
/// frame and its centre from the whole tree's centre of mass), turned by A's orientation.
pub fn tree_poses(tree: &Tree, appendages: &Appendages, traj: &impl ShapeTrajectory, times: &[f64]) -> Vec<CatPose> {
    // Bodies 0 and 1 are the halves, then the tail, then the legs (Cat::tree_with); a leg's
    // rod lies along its frame's y, turned onto z by Rx(−90°).
    let leg_axis = Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0);
    let n = tree.bodies().len();
    let samples = fall_history_on(tree, traj, &Vector3::zeros(), HISTORY_STEPS);
    let total: f64 = traj.piece_durations().iter().sum();
    times
        .iter()
        .map(|&t| {
            let t = t.clamp(0.0, total);
            let (orientation, twist, swing) = interpolate(&samples, t);
            let r_a = orientation.to_rotation_matrix().into_inner();
            let motion = tree.motion(&traj.shape_at(t));
            let body = |k: usize| BodyPose {
                centre: r_a * motion.bodies[k].position,
                rotation: r_a * motion.bodies[k].rotation,
            };
            CatPose {
                time: t,
                phase: None,
                twist,
                swing,
                a: body(0),
                b: body(1),
                tail: appendages.tail.map(|_| body(2)),
                legs: appendages
                    .legs
                    .map(|_| [n - 2, n - 1].map(|k| BodyPose { rotation: body(k).rotation * leg_axis, ..body(k) })),
            }
        })
        .collect()
}

/// A's orientation, twist and swing at `t`, between the two samples around it.
fn interpolate(samples: &[OrientationSample], t: f64) -> (UnitQuaternion<f64>, f64, f64) {
    let after = samples.partition_point(|s| s.time <= t);
    let (lo, hi) = match (after.checked_sub(1).and_then(|i| samples.get(i)), samples.get(after)) {
        (Some(lo), Some(hi)) => (lo, hi),
        (Some(only), None) | (None, Some(only)) => (only, only),
        (None, None) => return (UnitQuaternion::identity(), 0.0, 0.0),
    };
    let dt = hi.time - lo.time;
    let f = if dt > 0.0 { ((t - lo.time) / dt).clamp(0.0, 1.0) } else { 0.0 };
    // Neighbouring samples differ by a small angle, where normalised linear interpolation
    // agrees with slerp to third order and, unlike slerp's ratio of small sines, stays unit.
    let q = lo.orientation.nlerp(&hi.orientation, f);
    let mix = |a: f64, b: f64| a + f * (b - a);
    (q, mix(lo.angles.twist, hi.angles.twist), mix(lo.angles.swing, hi.angles.swing))
}
