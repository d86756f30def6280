//! Shape trajectories: the shape coordinates of a model ([`ShapeState`]) piece by piece, as a
//! [`Trajectory`] gives `(q1, q2)`.
//!
//! Every two-coordinate [`Trajectory`] (the library schedules, whose paths and profiles are
//! defined on `(q1, q2)` for every two-coordinate joint, DESIGN.md §10) is a shape trajectory;
//! [`Held`] adds coordinates held at zero (a spherical joint's twist, a tail), and [`AsSpherical`]
//! expresses a universal-joint trajectory in the spherical joint's coordinates.

use crate::model::shape::ShapeState;
use crate::schedule::{JointState, Trajectory};

impl From<&JointState> for ShapeState {
    fn from(s: &JointState) -> ShapeState {
        ShapeState { q: s.q.to_vec(), qd: s.qd.to_vec(), qdd: s.qdd.to_vec() }
    }
}

/// A shape trajectory made of pieces, each smooth on its closed interval (as [`Trajectory`]).
pub trait ShapeTrajectory {
    /// Durations of the pieces, s.
    fn piece_durations(&self) -> Vec<f64>;
    /// The shape at local time `s` of a piece.
    fn piece_shape(&self, piece: usize, s: f64) -> ShapeState;
    /// Local times inside a piece where `q̈` may jump ([`Trajectory::acceleration_jumps`]).
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64>;

    /// The shape at global time `t`, clamped to the trajectory (the later piece at a boundary;
    /// [`locate`] on [`ShapeTrajectory::piece_durations`]).
    fn shape_at(&self, t: f64) -> ShapeState {
        let durations = self.piece_durations();
        if durations.is_empty() {
            return ShapeState::default();
        }
        let (piece, s) = locate(&durations, t);
        self.piece_shape(piece, s)
    }
}

/// The piece of `durations` (s) holding global time `t` (the later one at a boundary, the last
/// beyond the end) and the local time there, clamped to the piece.
pub fn locate(durations: &[f64], t: f64) -> (usize, f64) {
    let mut start = 0.0;
    for (i, d) in durations.iter().enumerate() {
        if t < start + d || i + 1 == durations.len() {
            return (i, (t - start).clamp(0.0, *d));
        }
        start += d;
    }
    (0, 0.0)
}

impl<T: Trajectory> ShapeTrajectory for T {
    fn piece_durations(&self) -> Vec<f64> {
        Trajectory::piece_durations(self)
    }
    fn piece_shape(&self, piece: usize, s: f64) -> ShapeState {
        ShapeState::from(&self.piece_state(piece, s))
    }
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64> {
        Trajectory::acceleration_jumps(self, piece)
    }
}

/// A two-coordinate trajectory driving a model of more coordinates with the rest held at zero:
/// `(q1, q2, 0, …)`, `.1` zeros. With one, a spherical joint's relative twist held (exactly the
/// no-twist joint, DESIGN.md §10); with a tail's and legs', the tail held straight behind the cat
/// and the legs standing out.
#[derive(Clone, Copy, Debug)]
pub struct Held<'a, T: Trajectory>(pub &'a T, pub usize);

impl<T: Trajectory> ShapeTrajectory for Held<'_, T> {
    fn piece_durations(&self) -> Vec<f64> {
        self.0.piece_durations()
    }
    fn piece_shape(&self, piece: usize, s: f64) -> ShapeState {
        let st = self.0.piece_state(piece, s);
        let held = |two: [f64; 2]| two.into_iter().chain(std::iter::repeat_n(0.0, self.1)).collect();
        ShapeState { q: held(st.q), qd: held(st.qd), qdd: held(st.qdd) }
    }
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64> {
        self.0.acceleration_jumps(piece)
    }
}

/// A universal-joint trajectory in the spherical joint's coordinates: `R_AB = Rx(q1) Ry(q2)`
/// split as `exp([v]×) Rz(τ)` (its swing–twist decomposition about `ẑ`,
/// [`crate::model::joint::spherical_coordinates`], the twist in `[−π, π]`), `q = (v1, v2, τ)`,
/// with the rates and accelerations that give the same `ω_rel` and `ω̇_rel`: with
/// `M = [J x̂ | J ŷ | e]`
/// ([`crate::model::joint::exp_rate`], `e = exp([v]×) ẑ`), `M (v̇1, v̇2, τ̇) = ω_rel` and
/// `M (v̈1, v̈2, τ̈) = ω̇_rel − J̇ v̇ − τ̇ (J v̇) × e`. `M` is invertible for bends below π
/// (`det M = sin|v|/|v|`). With `hold_twist` the relative twist is dropped (`τ = 0`): the same
/// bend path without the universal joint's twist, which separates what each costs.
#[derive(Clone, Copy, Debug)]
pub struct AsSpherical<'a, T: Trajectory> {
    /// The universal-joint trajectory.
    pub path: &'a T,
    /// Whether to hold the relative twist at zero.
    pub hold_twist: bool,
}

impl<T: Trajectory> ShapeTrajectory for AsSpherical<'_, T> {
    fn piece_durations(&self) -> Vec<f64> {
        self.path.piece_durations()
    }
    fn piece_shape(&self, piece: usize, s: f64) -> ShapeState {
        use crate::model::joint::{exp_accel, exp_rate, exp_so3, spherical_coordinates};
        use crate::model::Joint;
        use nalgebra::{Matrix3, Vector3};
        let st = self.path.piece_state(piece, s);
        let [v1, v2, tau] = spherical_coordinates(&Joint::Universal.rotation(&st.q), 0.0);
        let v = Vector3::new(v1, v2, 0.0);
        let e = exp_so3(&v) * Vector3::z();
        let m = Matrix3::from_columns(&[exp_rate(&v, &Vector3::x()), exp_rate(&v, &Vector3::y()), e]);
        let solve = |b: Vector3<f64>| m.lu().solve(&b).unwrap_or_else(|| Vector3::repeat(f64::NAN));
        let rate = solve(Joint::Universal.relative_rate(&st.q, &st.qd));
        let vd = Vector3::new(rate.x, rate.y, 0.0);
        let rest = exp_accel(&v, &vd, &Vector3::zeros()) + exp_rate(&v, &vd).cross(&e) * rate.z;
        let accel = solve(Joint::Universal.relative_accel(&st.q, &st.qd, &st.qdd) - rest);
        let keep = if self.hold_twist { 0.0 } else { 1.0 };
        ShapeState {
            q: vec![v.x, v.y, tau * keep],
            qd: vec![rate.x, rate.y, rate.z * keep],
            qdd: vec![accel.x, accel.y, accel.z * keep],
        }
    }
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64> {
        self.path.acceleration_jumps(piece)
    }
}
