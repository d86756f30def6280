//! The three bodies of the rapier cat as nalgebra values: their masses, one body's state, and a
//! snapshot of the whole multibody (poses and generalized velocities).
//!
//! Shared by the scene that fills them ([`super::scene`]) and the measurements made on them
//! ([`super::measure`]). World frame, SI units; the generalized velocities are
//! `v = (v_A, ω_A, …)`: A's centre's linear velocity, A's world angular velocity, then the joint's
//! rates, which depend on the scene's [`Layout`]: `(q̇1, q̇2)` of the universal joint's two
//! revolutes, or the relative angular velocity `ω_rel` (A's frame) of the ball joint.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

use crate::model::Cat;

/// Most generalized velocities a scene has: the floating root's six, then three of the ball
/// joint (the universal joint's scene uses the first eight, [`Layout::ndofs`]).
pub const NDOFS: usize = 9;

/// How the scene joins B to A (module docs of [`crate::engines::rapier`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// The universal joint: revolute about A's `x` to the cross, revolute about the cross's `y`
    /// to B; generalized joint velocities `(q̇1, q̇2)`.
    Universal,
    /// The no-twist joint: a spherical joint from A to the ball, a tiny body welded to B at the
    /// joint point; generalized joint velocities `ω_rel` in A's frame.
    Ball,
}

impl Layout {
    /// Number of generalized velocities: 8 (universal), 9 (ball).
    pub fn ndofs(self) -> usize {
        match self {
            Layout::Universal => 8,
            Layout::Ball => 9,
        }
    }

    /// The bodies each motor drives (indices into A, the cross or ball, B): on the universal
    /// joint motor 1 drives {cross, B} and motor 2 drives {B}; on the ball joint both motors are
    /// projections of the couple on {ball, B}.
    pub fn driven(self) -> [&'static [usize]; 2] {
        match self {
            Layout::Universal => [&[1, 2], &[2]],
            Layout::Ball => [&[1, 2], &[1, 2]],
        }
    }
}

/// One body's pose and velocity, in the world frame (nalgebra types).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    /// Centre of mass, m.
    pub position: Vector3<f64>,
    /// Orientation of the body frame.
    pub rotation: UnitQuaternion<f64>,
    /// Velocity of the centre of mass, m/s.
    pub linvel: Vector3<f64>,
    /// Angular velocity, rad/s.
    pub angvel: Vector3<f64>,
}

/// Poses of A, the cross (or ball) and B, and the generalized velocities, at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Snapshot {
    /// Centres of A, the cross, B, m.
    pub positions: [Vector3<f64>; 3],
    /// Orientations of A, the cross, B.
    pub rotations: [UnitQuaternion<f64>; 3],
    /// Generalized velocities `(v_A, ω_A, joint rates)`; the first [`Layout::ndofs`] are used.
    pub velocities: [f64; NDOFS],
    /// Joint coordinates `(q1, q2)`, rad: rapier's revolute angles (universal), or the rotation
    /// vector of B relative to A, `log(R_A⁻¹ R_B)`, its `x` and `y` (no-twist).
    pub q: [f64; 2],
    /// How B is joined to A.
    pub layout: Layout,
}

/// Mass and principal inertia (about the body's own axes) of the three bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassModel {
    /// Masses of A, the cross, B, kg.
    pub mass: [f64; 3],
    /// Principal moments `(I_x, I_y, I_z)` of A, the cross, B, kg·m².
    pub inertia: [[f64; 3]; 3],
    /// Half lengths `l_A/2` of the front half and `l_B/2` of the rear half, m: the joint point
    /// is A's `(0, 0, −l_A/2)` and B's `(0, 0, +l_B/2)`.
    pub half_lengths: [f64; 2],
}

impl MassModel {
    /// The cat's halves with a cross of mass `fraction · m̄` (`m̄` the mean of the halves'
    /// masses); the cross's inertia is that of a solid sphere of the mean radius `r̄`,
    /// `2/5 m_c r̄²` (tiny, but a valid positive inertia). Only the halves' sizes enter, not the
    /// joint: the scene decides which joints it builds. For the paper's cat (equal halves of
    /// mass `m` and radius `r`) this is `f m` and `2/5 f m r²`.
    pub fn new(cat: &Cat, fraction: f64) -> Self {
        let (front, rear) = (cat.front, cat.rear);
        let mean = cat.mean_half();
        let mc = fraction * mean.mass;
        let ic = 0.4 * mc * mean.radius * mean.radius;
        let principal = |c: &crate::model::Cylinder| [c.transverse(), c.transverse(), c.axial()];
        Self {
            mass: [front.mass, mc, rear.mass],
            inertia: [principal(&front), [ic, ic, ic], principal(&rear)],
            half_lengths: [0.5 * front.length, 0.5 * rear.length],
        }
    }

    /// World inertia `R I Rᵀ` of body `i` at orientation `r`.
    pub fn world_inertia(&self, i: usize, r: &UnitQuaternion<f64>) -> Matrix3<f64> {
        let m = r.to_rotation_matrix().into_inner();
        m * Matrix3::from_diagonal(&Vector3::from(self.inertia[i])) * m.transpose()
    }

    /// Total mass, kg.
    pub fn total(&self) -> f64 {
        self.mass.iter().sum()
    }
}

impl Snapshot {
    /// The joint point (joint 1 and joint 2 share it), world frame.
    pub fn joint_point(&self, masses: &MassModel) -> Vector3<f64> {
        self.positions[0] + self.rotations[0] * Vector3::new(0.0, 0.0, -masses.half_lengths[0])
    }

    /// The motor axes, world frame: joint 1's (A's x) and joint 2's (the cross's y) on the
    /// universal joint, A's x and y on the no-twist joint.
    pub fn joint_axes(&self) -> [Vector3<f64>; 2] {
        match self.layout {
            Layout::Universal => [self.rotations[0] * Vector3::x(), self.rotations[1] * Vector3::y()],
            Layout::Ball => [self.rotations[0] * Vector3::x(), self.rotations[0] * Vector3::y()],
        }
    }

    /// The bodies' velocities for generalized velocities `v` at this snapshot's poses:
    /// `ω_C = ω_A + q̇1 a1`, `ω_B = ω_C + q̇2 a2` (universal) or `ω_C = ω_B = ω_A + R_A ω_rel`
    /// (ball), `v_C = v_A + ω_A × (P − x_A)`, `v_B = v_C + ω_B × (x_B − P)` with `P` the joint
    /// point (the cross's or the ball's centre).
    pub fn bodies_with(&self, masses: &MassModel, v: &[f64; NDOFS]) -> [BodyState; 3] {
        let p = self.joint_point(masses);
        let v_a = Vector3::new(v[0], v[1], v[2]);
        let w_a = Vector3::new(v[3], v[4], v[5]);
        let (w_c, w_b) = match self.layout {
            Layout::Universal => {
                let [a1, a2] = self.joint_axes();
                let w_c = w_a + v[6] * a1;
                (w_c, w_c + v[7] * a2)
            }
            Layout::Ball => {
                let w = w_a + self.rotations[0] * Vector3::new(v[6], v[7], v[8]);
                (w, w)
            }
        };
        let v_c = v_a + w_a.cross(&(p - self.positions[0]));
        let v_b = v_c + w_b.cross(&(self.positions[2] - p));
        let vel = [(v_a, w_a), (v_c, w_c), (v_b, w_b)];
        std::array::from_fn(|i| BodyState {
            position: self.positions[i],
            rotation: self.rotations[i],
            linvel: vel[i].0,
            angvel: vel[i].1,
        })
    }

    /// The bodies' states with this snapshot's own generalized velocities.
    pub fn bodies(&self, masses: &MassModel) -> [BodyState; 3] {
        self.bodies_with(masses, &self.velocities)
    }

    /// Whether every number of the snapshot is finite.
    pub fn is_finite(&self) -> bool {
        self.velocities.iter().all(|v| v.is_finite())
            && self.positions.iter().all(|p| p.iter().all(|v| v.is_finite()))
            && self.rotations.iter().all(|r| r.coords.iter().all(|v| v.is_finite()))
    }

    /// Joint angles from the bodies' relative rotations: `R_A⁻¹ R_C = Rx(q1)`,
    /// `R_C⁻¹ R_B = Ry(q2)` (a second reading of the joint coordinates).
    pub fn q_from_rotations(&self) -> [f64; 2] {
        let rel1 = self.rotations[0].inverse() * self.rotations[1];
        let rel2 = self.rotations[1].inverse() * self.rotations[2];
        let m1 = rel1.to_rotation_matrix().into_inner();
        let m2 = rel2.to_rotation_matrix().into_inner();
        [m1[(2, 1)].atan2(m1[(1, 1)]), m2[(0, 2)].atan2(m2[(0, 0)])]
    }
}
