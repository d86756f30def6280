//! The rapier3d scene of the two-cylinder cat: three dynamic bodies in one multibody.
//!
//! Body A is the multibody's floating root, B hangs from it through two revolute joints and a
//! tiny cross (see the module docs of [`crate::engines::rapier`] for the conventions). The scene has no
//! colliders and zero gravity; every body's mass properties are set explicitly.
//!
//! State is read from the multibody itself, not from the rigid bodies' copies: poses from the
//! links' `local_to_world`, velocities from the generalized velocities `v = (v_A, ω_A, q̇1, q̇2)`
//! (root linear velocity of A's centre and world angular velocity, then the joint rates) mapped
//! to the bodies at the current poses. After a step rapier leaves the rigid bodies' velocities
//! from the start of the last substep, whereas the generalized velocities are the ones it
//! integrated the poses with.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use rapier3d_f64::dynamics::{
    GenericJoint, IntegrationParameters, JointAxis, MotorModel, MultibodyJointHandle, RevoluteJointBuilder,
    RigidBodyBuilder, RigidBodyHandle,
};
use rapier3d_f64::math::{Pose, Rotation, Vector};
use rapier3d_f64::parry::mass_properties::MassProperties;
use rapier3d_f64::pipeline::PhysicsWorld;

use super::RapierError;
use crate::model::Cylinder;

/// Number of generalized velocities: the floating root's six, then `q̇1`, `q̇2`.
pub const NDOFS: usize = 8;

/// Gains of the joint motors, rapier's acceleration-based model.
///
/// Rapier's motor is an implicit spring–damper per joint coordinate, solved as a velocity
/// constraint whose effective mass is the coordinate's apparent inertia `1/(M⁻¹)_ii` (everything
/// else free, floating base included). In that model the gains are accelerations per unit error:
/// `stiffness = ω_n²` (1/s²) and `damping = 2 ζ ω_n` (1/s), so the joint torque is
/// `(1/(M⁻¹)_ii)(ω_n² e + 2ζω_n ė)` and the tracking error obeys `ë + 2ζω_n ė + ω_n² e = −q̈`
/// whatever the cat's size.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MotorGains {
    /// Natural frequency `ω_n`, rad/s.
    pub natural_frequency: f64,
    /// Damping ratio `ζ` (1 = critically damped).
    pub damping_ratio: f64,
    /// Rapier's stiffness `ω_n²`, 1/s².
    pub stiffness: f64,
    /// Rapier's damping `2ζω_n`, 1/s.
    pub damping: f64,
}

impl MotorGains {
    /// Gains with natural frequency `omega` (rad/s) and damping ratio `zeta`.
    pub fn new(omega: f64, zeta: f64) -> Self {
        Self { natural_frequency: omega, damping_ratio: zeta, stiffness: omega * omega, damping: 2.0 * zeta * omega }
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

/// Poses of A, the cross and B, and the generalized velocities, at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Snapshot {
    /// Centres of A, the cross, B, m.
    pub positions: [Vector3<f64>; 3],
    /// Orientations of A, the cross, B.
    pub rotations: [UnitQuaternion<f64>; 3],
    /// Generalized velocities `(v_A, ω_A, q̇1, q̇2)`.
    pub velocities: [f64; NDOFS],
    /// Joint coordinates `(q1, q2)` as rapier holds them, rad.
    pub q: [f64; 2],
}

/// Mass and principal inertia (about the body's own axes) of the three bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassModel {
    /// Masses of A, the cross, B, kg.
    pub mass: [f64; 3],
    /// Principal moments `(I_x, I_y, I_z)` of A, the cross, B, kg·m².
    pub inertia: [[f64; 3]; 3],
    /// Half length `l/2` of a half, m.
    pub half_length: f64,
}

impl MassModel {
    /// The cat's bodies with a cross of mass `fraction · m`; the cross's inertia is that of a
    /// solid sphere of the cat's radius, `2/5 m_c r²` (tiny, but a valid positive inertia).
    pub fn new(cat: &Cylinder, fraction: f64) -> Self {
        let (t, a) = (cat.transverse(), cat.axial());
        let mc = fraction * cat.mass;
        let ic = 0.4 * mc * cat.radius * cat.radius;
        Self {
            mass: [cat.mass, mc, cat.mass],
            inertia: [[t, t, a], [ic, ic, ic], [t, t, a]],
            half_length: 0.5 * cat.length,
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
        self.positions[0] + self.rotations[0] * Vector3::new(0.0, 0.0, -masses.half_length)
    }

    /// Joint 1's axis (A's x) and joint 2's axis (the cross's y), world frame.
    pub fn joint_axes(&self) -> [Vector3<f64>; 2] {
        [self.rotations[0] * Vector3::x(), self.rotations[1] * Vector3::y()]
    }

    /// The bodies' velocities for generalized velocities `v` at this snapshot's poses:
    /// `ω_C = ω_A + q̇1 a1`, `ω_B = ω_C + q̇2 a2`, `v_C = v_A + ω_A × (P − x_A)`,
    /// `v_B = v_C + ω_B × (x_B − P)` with `P` the joint point (the cross's centre).
    pub fn bodies_with(&self, masses: &MassModel, v: &[f64; NDOFS]) -> [BodyState; 3] {
        let p = self.joint_point(masses);
        let [a1, a2] = self.joint_axes();
        let v_a = Vector3::new(v[0], v[1], v[2]);
        let w_a = Vector3::new(v[3], v[4], v[5]);
        let w_c = w_a + v[6] * a1;
        let w_b = w_c + v[7] * a2;
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

/// The cat in a rapier world, ready to step.
pub struct CatScene {
    world: PhysicsWorld,
    /// Link ids of A, the cross, B in the multibody.
    links: [usize; 3],
    joints: [MultibodyJointHandle; 2],
    masses: MassModel,
    gains: Option<MotorGains>,
}

fn to_na(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

fn from_na(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn rot_to_na(r: Rotation) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(r.w, r.x, r.y, r.z))
}

fn rot_from_na(r: &UnitQuaternion<f64>) -> Rotation {
    Rotation::from_xyzw(r.i, r.j, r.k, r.w)
}

impl CatScene {
    /// Builds the scene at joint angles `q0`, at rest, with time step `dt` (one solver substep
    /// per step, `pgs_iterations` Gauss–Seidel sweeps of the velocity solver). With `gains`,
    /// both joints carry motors holding `q0`; without, the joints are free.
    pub fn new(
        cat: &Cylinder,
        cross_mass_fraction: f64,
        dt: f64,
        pgs_iterations: usize,
        gains: Option<MotorGains>,
        q0: [f64; 2],
    ) -> Result<Self, RapierError> {
        let masses = MassModel::new(cat, cross_mass_fraction);
        let h = masses.half_length;
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::ZERO;
        world.integration_parameters = IntegrationParameters {
            dt,
            num_solver_iterations: 1,
            num_internal_pgs_iterations: pgs_iterations.max(1),
            ..IntegrationParameters::default()
        };

        // Initial poses at q0: A at the origin, the cross at the joint point, B beyond it.
        let r_c = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), q0[0]);
        let r_b = r_c * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), q0[1]);
        let joint = Vector3::new(0.0, 0.0, -h);
        let x_b = joint - r_b * Vector3::new(0.0, 0.0, h);
        let poses = [(Vector3::zeros(), UnitQuaternion::identity()), (joint, r_c), (x_b, r_b)];
        let bodies: [RigidBodyHandle; 3] = std::array::from_fn(|i| {
            let mprops = MassProperties::new(Vector::ZERO, masses.mass[i], Vector::from_array(masses.inertia[i]));
            let body = RigidBodyBuilder::dynamic()
                .pose(Pose::from_parts(from_na(&poses[i].0), rot_from_na(&poses[i].1)))
                .additional_mass_properties(mprops)
                .can_sleep(false)
                .build();
            world.bodies.insert(body)
        });

        let revolute = |axis: Vector, anchor1: Vector, anchor2: Vector, q: f64| -> GenericJoint {
            let mut b = RevoluteJointBuilder::new(axis).local_anchor1(anchor1).local_anchor2(anchor2);
            if let Some(g) = gains {
                b = b.motor_model(MotorModel::AccelerationBased).motor(q, 0.0, g.stiffness, g.damping);
            }
            b.build().into()
        };
        let j1 = revolute(Vector::X, Vector::new(0.0, 0.0, -h), Vector::ZERO, q0[0]);
        let j2 = revolute(Vector::Y, Vector::ZERO, Vector::new(0.0, 0.0, h), q0[1]);
        let h1 = world
            .multibody_joints
            .insert(bodies[0], bodies[1], j1, true)
            .ok_or(RapierError::JointRejected("joint 1 (A to the cross)"))?;
        let h2 = world
            .multibody_joints
            .insert(bodies[1], bodies[2], j2, true)
            .ok_or(RapierError::JointRejected("joint 2 (the cross to B)"))?;

        // The layout every reader relies on: A is the floating root (DoFs 0..6), then the
        // cross (DoF 6) and B (DoF 7).
        let mut links = [0; 3];
        {
            let mb = world.multibody_joints.get(h2).map(|(mb, _)| mb).ok_or(RapierError::Missing("the multibody"))?;
            if mb.ndofs() != NDOFS {
                return Err(RapierError::Missing("eight degrees of freedom (a floating root and two revolute joints)"));
            }
            for (i, handle) in bodies.iter().enumerate() {
                let id =
                    world.multibody_joints.rigid_body_link(*handle).ok_or(RapierError::Missing("a body's link"))?.id;
                let link = mb.link(id).ok_or(RapierError::Missing("a link"))?;
                if link.assembly_id() != [0, 6, 7][i] {
                    return Err(RapierError::Missing("the expected order of its degrees of freedom"));
                }
                links[i] = id;
            }
        }

        let mut scene = Self { world, links, joints: [h1, h2], masses, gains };
        {
            let (mb, _) = scene.multibody_mut()?;
            // Put the joint coordinates at q0 (they start at zero), then place the bodies.
            let mut disp = [0.0; NDOFS];
            disp[6] = q0[0];
            disp[7] = q0[1];
            mb.apply_displacements(&disp);
            // Rapier's default damping (0.1 on every angular DoF, the root's included) would
            // bleed angular momentum: the cat is undamped.
            mb.damping_mut().fill(0.0);
        }
        scene.sync_bodies()?;
        Ok(scene)
    }

    fn multibody_mut(&mut self) -> Result<(&mut rapier3d_f64::dynamics::Multibody, usize), RapierError> {
        self.world.multibody_joints.get_mut(self.joints[1]).ok_or(RapierError::Missing("the multibody"))
    }

    fn multibody(&self) -> Result<&rapier3d_f64::dynamics::Multibody, RapierError> {
        self.world.multibody_joints.get(self.joints[1]).map(|(mb, _)| mb).ok_or(RapierError::Missing("the multibody"))
    }

    /// Runs forward kinematics and writes the poses to the rigid bodies.
    fn sync_bodies(&mut self) -> Result<(), RapierError> {
        let world = &mut self.world;
        let (mb, _) = world.multibody_joints.get_mut(self.joints[1]).ok_or(RapierError::Missing("the multibody"))?;
        mb.forward_kinematics(&world.bodies, true);
        mb.update_rigid_bodies(&mut world.bodies, true);
        Ok(())
    }

    /// The bodies' mass model.
    pub fn masses(&self) -> &MassModel {
        &self.masses
    }

    /// The motor gains, if the joints have motors.
    pub fn gains(&self) -> Option<MotorGains> {
        self.gains
    }

    /// The time step, s.
    pub fn dt(&self) -> f64 {
        self.world.integration_parameters.dt
    }

    /// Sets the motors' target positions and velocities (no-op without motors).
    pub fn set_targets(&mut self, pos: [f64; 2], vel: [f64; 2]) -> Result<(), RapierError> {
        let Some(g) = self.gains else { return Ok(()) };
        for i in 0..2 {
            let (mb, id) =
                self.world.multibody_joints.get_mut(self.joints[i]).ok_or(RapierError::Missing("a joint"))?;
            let link = mb.link_mut(id).ok_or(RapierError::Missing("a link"))?;
            link.joint.data.set_motor(JointAxis::AngX, pos[i], vel[i], g.stiffness, g.damping);
        }
        Ok(())
    }

    /// Sets the generalized velocities `(v_A, ω_A, q̇1, q̇2)`.
    pub fn set_velocities(&mut self, v: &[f64; NDOFS]) -> Result<(), RapierError> {
        let (mb, _) = self.multibody_mut()?;
        if mb.ndofs() != NDOFS {
            return Err(RapierError::Missing("a floating root with two joints (wrong DoF count)"));
        }
        mb.generalized_velocity_mut().copy_from_slice(v);
        Ok(())
    }

    /// Sets the joint rates `q̇` and gives the whole cat the rigid motion that makes its linear
    /// and angular momentum zero: angular velocity `ω = −I_lock⁻¹ H` about the centre of mass `c`
    /// (`I_lock` the locked inertia about `c`), velocity `−p/M` of `c`.
    pub fn start_at_zero_momentum(&mut self, qd: [f64; 2]) -> Result<(), RapierError> {
        let mut v = [0.0; NDOFS];
        v[6] = qd[0];
        v[7] = qd[1];
        let snap = Snapshot { velocities: v, ..self.snapshot()? };
        let bodies = snap.bodies(&self.masses);
        let total = self.masses.total();
        let mut c = Vector3::zeros();
        let mut p = Vector3::zeros();
        for (b, m) in bodies.iter().zip(self.masses.mass) {
            c += m * b.position / total;
            p += m * b.linvel;
        }
        let h = super::measure::angular_momentum(&self.masses, &bodies);
        let mut locked = Matrix3::zeros();
        for (i, b) in bodies.iter().enumerate() {
            let r = b.position - c;
            locked += self.masses.world_inertia(i, &b.rotation)
                + self.masses.mass[i] * (Matrix3::identity() * r.norm_squared() - r * r.transpose());
        }
        let omega = locked
            .cholesky()
            .map(|ch| -ch.solve(&h))
            .ok_or(RapierError::Missing("a positive definite locked inertia"))?;
        let lin = -p / total + omega.cross(&(bodies[0].position - c));
        v[..3].copy_from_slice(lin.as_slice());
        v[3..6].copy_from_slice(omega.as_slice());
        self.set_velocities(&v)
    }

    /// Advances one step.
    pub fn step(&mut self) {
        self.world.step();
    }

    /// The current poses, generalized velocities and joint coordinates.
    pub fn snapshot(&self) -> Result<Snapshot, RapierError> {
        let mb = self.multibody()?;
        if mb.ndofs() != NDOFS {
            return Err(RapierError::Missing("a floating root with two joints (wrong DoF count)"));
        }
        let mut positions = [Vector3::zeros(); 3];
        let mut rotations = [UnitQuaternion::identity(); 3];
        let mut q = [0.0; 2];
        for (i, id) in self.links.iter().enumerate() {
            let link = mb.link(*id).ok_or(RapierError::Missing("a link"))?;
            let pose = link.local_to_world();
            positions[i] = to_na(pose.translation);
            rotations[i] = rot_to_na(pose.rotation);
            if i > 0 {
                // A revolute joint's free coordinate is its angular x (the joint axis).
                q[i - 1] = link.joint().coords()[3];
            }
        }
        let mut velocities = [0.0; NDOFS];
        velocities.copy_from_slice(mb.generalized_velocity().as_slice());
        Ok(Snapshot { positions, rotations, velocities, q })
    }
}
