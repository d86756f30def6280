//! Where the two halves are at given instants: what the animation draws.
//!
//! A's world orientation `R_A(t)` comes from the exact engine ([`crate::engines::exact::history`]),
//! interpolated between its samples; B's is `R_B = R_A · R_AB(q(t))`. The centres are placed so that
//! the common centre of mass (the midpoint, the halves having equal masses) stays at the origin:
//! with `p = R_A [(0,0,−l/2) − R_AB (0,0,l/2)]` the vector from A's centre to B's,
//! `c_A = −p/2` and `c_B = +p/2`. World frame = A's body frame at `t = 0`; metres, radians.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

use crate::engines::exact::{fall_history, OrientationSample};
use crate::model::{joint_rotation, Cylinder};
use crate::schedule::{Phase, Trajectory};

/// Magnus steps over the whole fall of the orientation history the poses are interpolated from
/// (600 per phase of a three-phase schedule; [`fall_history`]).
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
}

/// The cat's pose at each of `times` (s, clamped to the manoeuvre).
pub fn cat_poses(cat: &Cylinder, schedule: &impl Trajectory, times: &[f64]) -> Vec<CatPose> {
    let samples = fall_history(cat, schedule, HISTORY_STEPS);
    let total = schedule.total_duration();
    times
        .iter()
        .map(|&t| {
            let t = t.clamp(0.0, total);
            let (orientation, twist, swing) = interpolate(&samples, t);
            let r_ab = joint_rotation(schedule.state_at(t).q);
            let r_a = orientation.to_rotation_matrix().into_inner();
            let p = r_a * cat.offset(&r_ab);
            CatPose {
                time: t,
                phase: schedule.phase_at(t),
                twist,
                swing,
                a: BodyPose { centre: -0.5 * p, rotation: r_a },
                b: BodyPose { centre: 0.5 * p, rotation: r_a * r_ab },
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
