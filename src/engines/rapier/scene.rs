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
    FixedJointBuilder, GenericJoint, IntegrationParameters, JointAxis, MotorModel, MultibodyJointHandle,
    RevoluteJointBuilder, RigidBodyBuilder, RigidBodyHandle, SphericalJointBuilder,
};
use rapier3d_f64::math::{Pose, Rotation, Vector};
use rapier3d_f64::parry::mass_properties::MassProperties;
use rapier3d_f64::pipeline::PhysicsWorld;

use super::bodies::{Layout, MassModel, Snapshot, NDOFS};
use super::RapierError;
use crate::model::orientation::swing_twist;
use crate::model::{Cat, Joint};
use crate::schedule::JointState;

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

/// The cat in a rapier world, ready to step.
pub struct CatScene {
    pub(super) world: PhysicsWorld,
    /// The rigid bodies of A, the cross, B.
    pub(super) bodies: [RigidBodyHandle; 3],
    /// Link ids of A, the cross, B in the multibody.
    links: [usize; 3],
    joints: [MultibodyJointHandle; 2],
    masses: MassModel,
    gains: Option<MotorGains>,
    layout: Layout,
}

/// An empty world without gravity (the falling frame) stepping by `dt` with one solver substep of
/// `pgs_iterations` Gauss–Seidel sweeps.
pub(super) fn falling_world(dt: f64, pgs_iterations: usize) -> PhysicsWorld {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::ZERO;
    world.integration_parameters = IntegrationParameters {
        dt,
        num_solver_iterations: 1,
        num_internal_pgs_iterations: pgs_iterations.max(1),
        ..IntegrationParameters::default()
    };
    world
}

pub(super) fn to_na(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

pub(super) fn from_na(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

pub(super) fn rot_to_na(r: Rotation) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(r.w, r.x, r.y, r.z))
}

pub(super) fn rot_from_matrix(m: &Matrix3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(*m))
}

/// The ball joint's three motor axes, its angular coordinates in A's frame.
pub(super) const BALL_AXES: [JointAxis; 3] = [JointAxis::AngX, JointAxis::AngY, JointAxis::AngZ];

/// The ball joint's relative rate `ω_rel` (A's frame), its generalized velocities.
fn ball_rate(snap: &Snapshot) -> Vector3<f64> {
    Vector3::new(snap.velocities[6], snap.velocities[7], snap.velocities[8])
}

/// The rate about A's `z` that keeps the ball a no-twist joint over the next step of `h` s, at
/// B's rotation `now` relative to A and relative rate `rate` (A's frame). A no-twist joint's
/// relative rates satisfy `ω·(ẑ + e) = 0` with `e = now ẑ` B's spine in A's frame, and the twist
/// `ψ` of `now` about the spine (its swing–twist decomposition `now = S(e) Rz(ψ)`,
/// [`swing_twist`]; zero on a no-twist joint) moves at
/// `ψ̇ = ω·(ẑ + e)/(1 + e_z)`; so `ω_z = −(ω_x e_x + ω_y e_y)/(1 + e_z) − ψ/h` keeps the joint's
/// constraint and takes out any twist left. The motor about `z` then carries the couple the
/// constraint needs, whatever the bounded motors about `x` and `y` deliver. `rate`'s `x` and `y`
/// are the rates the step ends with, as far as they are known before it (the motors' aim, or
/// the present rate of a motor held back by its bound: the constraint then lags one step, and
/// the twist it leaves, `O(h²)` per step, goes at the next).
/// `None` when the halves are folded flat (`1 + e_z` below 1e-9), where the twist is undefined.
pub(super) fn untwisting_rate(now: &UnitQuaternion<f64>, rate: &Vector3<f64>, h: f64) -> Option<f64> {
    let e = now * Vector3::z();
    (1.0 + e.z > 1e-9).then(|| -(rate.x * e.x + rate.y * e.y) / (1.0 + e.z) - swing_twist(now).twist / h)
}

/// The no-twist joint's coordinate rates `q̇` at `q` from its relative rate `ω` (A's frame): the
/// least-squares solution of `ω = J(q) q̇`, `J`'s columns [`Joint::relative_rate`] of the unit
/// rates (exact when `ω` keeps the joint untwisted). `None` when `J` loses rank (a bend of 2π).
fn no_twist_rates(q: [f64; 2], w: &Vector3<f64>) -> Option<[f64; 2]> {
    let j = [Joint::NoTwist.relative_rate(&q, &[1.0, 0.0]), Joint::NoTwist.relative_rate(&q, &[0.0, 1.0])];
    let normal = nalgebra::Matrix2::new(j[0].dot(&j[0]), j[0].dot(&j[1]), j[1].dot(&j[0]), j[1].dot(&j[1]));
    let x = normal.cholesky()?.solve(&nalgebra::Vector2::new(j[0].dot(w), j[1].dot(w)));
    Some([x.x, x.y])
}

pub(super) fn rot_from_na(r: &UnitQuaternion<f64>) -> Rotation {
    Rotation::from_xyzw(r.i, r.j, r.k, r.w)
}

impl CatScene {
    /// Builds the scene at joint angles `q0`, at rest, with time step `dt` (one solver substep
    /// per step, `pgs_iterations` Gauss–Seidel sweeps of the velocity solver). With `gains`,
    /// both joints carry motors holding `q0`; without, the joints are free. The halves may
    /// differ; the joint must be the universal one ([`RapierError::UnsupportedJoint`]).
    pub fn new(
        cat: &Cat,
        cross_mass_fraction: f64,
        dt: f64,
        pgs_iterations: usize,
        gains: Option<MotorGains>,
        q0: [f64; 2],
    ) -> Result<Self, RapierError> {
        let layout = match cat.joint {
            Joint::Universal => Layout::Universal,
            Joint::NoTwist => Layout::Ball,
            Joint::Spherical | Joint::Hinge => return Err(RapierError::UnsupportedJoint(cat.joint)),
        };
        let masses = MassModel::new(cat, cross_mass_fraction);
        let [h_a, h_b] = masses.half_lengths;
        let mut world = falling_world(dt, pgs_iterations);

        // Initial poses at q0: A at the origin, the cross (turned by Rx(q1)) or the ball (turned
        // with B) at the joint point, B beyond it.
        let (r_c, r_b) = match layout {
            Layout::Universal => {
                let r_c = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), q0[0]);
                (r_c, r_c * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), q0[1]))
            }
            Layout::Ball => {
                let r_b = rot_from_matrix(&cat.joint.rotation(&q0));
                (r_b, r_b)
            }
        };
        let joint = Vector3::new(0.0, 0.0, -h_a);
        let x_b = joint - r_b * Vector3::new(0.0, 0.0, h_b);
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

        let (j1, j2): (GenericJoint, GenericJoint) = match layout {
            Layout::Universal => {
                let revolute = |axis: Vector, anchor1: Vector, anchor2: Vector, q: f64| -> GenericJoint {
                    let mut b = RevoluteJointBuilder::new(axis).local_anchor1(anchor1).local_anchor2(anchor2);
                    if let Some(g) = gains {
                        b = b.motor_model(MotorModel::AccelerationBased).motor(q, 0.0, g.stiffness, g.damping);
                    }
                    b.build().into()
                };
                (
                    revolute(Vector::X, Vector::new(0.0, 0.0, -h_a), Vector::ZERO, q0[0]),
                    revolute(Vector::Y, Vector::ZERO, Vector::new(0.0, 0.0, h_b), q0[1]),
                )
            }
            Layout::Ball => {
                let mut b = SphericalJointBuilder::new().local_anchor1(Vector::new(0.0, 0.0, -h_a));
                if let Some(g) = gains {
                    for axis in BALL_AXES {
                        b = b.motor_model(axis, MotorModel::AccelerationBased).motor(
                            axis,
                            0.0,
                            0.0,
                            g.stiffness,
                            g.damping,
                        );
                    }
                }
                (b.build().into(), FixedJointBuilder::new().local_anchor2(Vector::new(0.0, 0.0, h_b)).build().into())
            }
        };
        let h1 = world
            .multibody_joints
            .insert(bodies[0], bodies[1], j1, true)
            .ok_or(RapierError::JointRejected("joint 1 (A to the cross or ball)"))?;
        let h2 = world
            .multibody_joints
            .insert(bodies[1], bodies[2], j2, true)
            .ok_or(RapierError::JointRejected("joint 2 (the cross or ball to B)"))?;

        // The layout every reader relies on: A is the floating root (DoFs 0..6), then the
        // cross (DoF 6) and B (DoF 7), or the ball (DoFs 6..9) and B welded to it.
        let mut links = [0; 3];
        {
            let mb = world.multibody_joints.get(h2).map(|(mb, _)| mb).ok_or(RapierError::Missing("the multibody"))?;
            if mb.ndofs() != layout.ndofs() {
                return Err(RapierError::Missing("the degrees of freedom of a floating root and the joint"));
            }
            let ids = match layout {
                Layout::Universal => [0, 6, 7],
                Layout::Ball => [0, 6, 9],
            };
            for (i, handle) in bodies.iter().enumerate() {
                let id =
                    world.multibody_joints.rigid_body_link(*handle).ok_or(RapierError::Missing("a body's link"))?.id;
                let link = mb.link(id).ok_or(RapierError::Missing("a link"))?;
                if link.assembly_id() != ids[i] {
                    return Err(RapierError::Missing("the expected order of its degrees of freedom"));
                }
                links[i] = id;
            }
        }

        let mut scene = Self { world, bodies, links, joints: [h1, h2], masses, gains, layout };
        {
            let (mb, _) = scene.multibody_mut()?;
            // Put the joint coordinates at q0 (they start at zero), then place the bodies: the
            // revolute angles, or the ball's rotation vector (the no-twist joint's is (q1, q2, 0)).
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

    /// How B is joined to A.
    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// Aims the motors at the schedule's `target`, the state at the end of the next step (module
    /// docs of [`crate::engines::rapier`]): on the universal joint each revolute's spring at
    /// `q − h q̇` with velocity `q̇`. On the ball joint the motors about A's `x` and `y` aim at the
    /// relative rotation that carries the present one onto `R(q)` over the step,
    /// `w = log(R(q) R_relᵀ)/h` (A's frame), as the velocity of each angular coordinate, its
    /// spring at the present coordinate (so that it acts on `h (v⁺ − w)`); the motor about `z`
    /// holds the joint's no-twist constraint (`untwisting_rate`) for the rates the step ends
    /// with: the aim of a motor `reaching` it (unbounded), the present rate of a bounded one,
    /// which the bound may hold back. No-op without motors.
    pub fn set_plan(&mut self, target: &JointState, reaching: [bool; 2]) -> Result<(), RapierError> {
        let h = self.dt();
        match self.layout {
            Layout::Universal => {
                let pos = [target.q[0] - h * target.qd[0], target.q[1] - h * target.qd[1]];
                self.set_targets(pos, target.qd)
            }
            Layout::Ball => {
                let Some(g) = self.gains else { return Ok(()) };
                let snap = self.snapshot()?;
                let now = snap.rotations[0].inverse() * snap.rotations[2];
                let goal = rot_from_matrix(&Joint::NoTwist.rotation(&target.q));
                let mut w = (goal * now.inverse()).scaled_axis() / h;
                // The rates about x and y the step ends with: an unbounded motor's aim, a bounded
                // one's present rate.
                let present = ball_rate(&snap);
                let ends = Vector3::new(
                    if reaching[0] { w.x } else { present.x },
                    if reaching[1] { w.y } else { present.y },
                    0.0,
                );
                w.z = untwisting_rate(&now, &ends, h)
                    .ok_or(RapierError::Missing("a twist of the no-twist joint (its halves folded flat)"))?;
                let (mb, id) =
                    self.world.multibody_joints.get_mut(self.joints[0]).ok_or(RapierError::Missing("a joint"))?;
                let link = mb.link_mut(id).ok_or(RapierError::Missing("a link"))?;
                let coords = link.joint().coords();
                for (i, axis) in BALL_AXES.into_iter().enumerate() {
                    link.joint.data.set_motor(axis, coords[3 + i], w[i], g.stiffness, g.damping);
                }
                Ok(())
            }
        }
    }

    /// Sets the revolute motors' target positions and velocities (no-op without motors; the
    /// universal joint's scene; the ball's are aimed by [`CatScene::set_plan`]).
    pub fn set_targets(&mut self, pos: [f64; 2], vel: [f64; 2]) -> Result<(), RapierError> {
        let Some(g) = self.gains else { return Ok(()) };
        if self.layout != Layout::Universal {
            return Err(RapierError::UnsupportedJoint(Joint::NoTwist));
        }
        for i in 0..2 {
            let (mb, id) =
                self.world.multibody_joints.get_mut(self.joints[i]).ok_or(RapierError::Missing("a joint"))?;
            let link = mb.link_mut(id).ok_or(RapierError::Missing("a link"))?;
            link.joint.data.set_motor(JointAxis::AngX, pos[i], vel[i], g.stiffness, g.damping);
        }
        Ok(())
    }

    /// Bounds each joint motor's torque, N·m (`None`: unbounded), for the next steps: rapier clamps
    /// the motor's impulse per step to `max_force · dt` whatever the motor model (see
    /// [`super::saturation`]).
    /// On the ball joint the bounds go to its motors about A's `x` and `y` (its angular DoFs are
    /// the relative rate in A's frame, so their generalized forces are the couple's components
    /// on A's axes: the no-twist joint's motor torques, DESIGN.md §10); the motor about A's `z`,
    /// which holds the joint without twist ([`CatScene::set_plan`]), stays unbounded: it is the
    /// joint's own constraint, not a motor.
    pub fn set_max_forces(&mut self, bound: [Option<f64>; 2]) -> Result<(), RapierError> {
        let motors: [(usize, JointAxis); 2] = match self.layout {
            Layout::Universal => [(0, JointAxis::AngX), (1, JointAxis::AngX)],
            Layout::Ball => [(0, JointAxis::AngX), (0, JointAxis::AngY)],
        };
        for ((joint, axis), b) in motors.into_iter().zip(bound) {
            let (mb, id) =
                self.world.multibody_joints.get_mut(self.joints[joint]).ok_or(RapierError::Missing("a joint"))?;
            let link = mb.link_mut(id).ok_or(RapierError::Missing("a link"))?;
            link.joint.data.set_motor_max_force(axis, b.unwrap_or(f64::MAX));
        }
        Ok(())
    }

    /// The joint rates `(q̇1, q̇2)`, rad/s: the revolutes' rates, or the no-twist joint's
    /// coordinate rates from the ball's relative rate (least squares, `no_twist_rates`).
    pub fn joint_rates(&self) -> Result<[f64; 2], RapierError> {
        match self.layout {
            Layout::Universal => {
                let v = self.multibody()?.generalized_velocity();
                match (v.get(6), v.get(7)) {
                    (Some(a), Some(b)) => Ok([*a, *b]),
                    _ => Err(RapierError::Missing("a floating root with two joints (wrong DoF count)")),
                }
            }
            Layout::Ball => {
                let snap = self.snapshot()?;
                no_twist_rates(snap.q, &ball_rate(&snap))
                    .ok_or(RapierError::Missing("the no-twist joint's rates (a bend of 2π)"))
            }
        }
    }

    /// Sets the generalized velocities `(v_A, ω_A, joint rates)` (the first [`Layout::ndofs`]).
    pub fn set_velocities(&mut self, v: &[f64; NDOFS]) -> Result<(), RapierError> {
        let n = self.layout.ndofs();
        let (mb, _) = self.multibody_mut()?;
        if mb.ndofs() != n {
            return Err(RapierError::Missing("the degrees of freedom of a floating root and the joint"));
        }
        mb.generalized_velocity_mut().copy_from_slice(&v[..n]);
        Ok(())
    }

    /// Sets the joint rates `q̇` and gives the whole cat the rigid motion that makes its linear
    /// and angular momentum zero: angular velocity `ω = −I_lock⁻¹ H` about the centre of mass `c`
    /// (`I_lock` the locked inertia about `c`), velocity `−p/M` of `c`.
    pub fn start_at_zero_momentum(&mut self, qd: [f64; 2]) -> Result<(), RapierError> {
        self.start_with_momentum(qd, &Vector3::zeros())
    }

    /// [`CatScene::start_at_zero_momentum`] with total angular momentum `spin` about the centre
    /// of mass (world frame, N·m·s) instead of zero: `ω = I_lock⁻¹ (L − H)`.
    pub fn start_with_momentum(&mut self, qd: [f64; 2], spin: &Vector3<f64>) -> Result<(), RapierError> {
        let now = self.snapshot()?;
        let mut v = [0.0; NDOFS];
        match self.layout {
            Layout::Universal => {
                v[6] = qd[0];
                v[7] = qd[1];
            }
            Layout::Ball => v[6..9].copy_from_slice(Joint::NoTwist.relative_rate(&now.q, &qd).as_slice()),
        }
        let snap = Snapshot { velocities: v, ..now };
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
            .map(|ch| ch.solve(&(spin - h)))
            .ok_or(RapierError::Missing("a positive definite locked inertia"))?;
        let lin = -p / total + omega.cross(&(bodies[0].position - c));
        v[..3].copy_from_slice(lin.as_slice());
        v[3..6].copy_from_slice(omega.as_slice());
        self.set_velocities(&v)
    }

    /// Applies joint torques `(τ1, τ2)`, N·m, for the next step as equal and opposite couples:
    /// `+τ1 a1` on the cross and `−τ1 a1` on A (joint 1 drives {cross, B}), `+τ2 a2` on B and
    /// `−τ2 a2` on the cross, with `a1` A's `x` and `a2` the cross's `y` at the poses of `now`
    /// (this scene's current [`CatScene::snapshot`]). They replace the previous step's torques.
    pub fn apply_joint_torques(&mut self, tau: [f64; 2], now: &Snapshot) -> Result<(), RapierError> {
        if self.layout != Layout::Universal {
            return Err(RapierError::UnsupportedJoint(Joint::NoTwist));
        }
        let [a1, a2] = now.joint_axes();
        let couples = [-tau[0] * a1, tau[0] * a1 - tau[1] * a2, tau[1] * a2];
        for (handle, couple) in self.bodies.iter().zip(couples) {
            let body = self.world.bodies.get_mut(*handle).ok_or(RapierError::Missing("a body"))?;
            body.reset_torques(false);
            body.add_torque(from_na(&couple), false);
        }
        Ok(())
    }

    /// Advances one step.
    pub fn step(&mut self) {
        self.world.step();
    }

    /// The current poses, generalized velocities and joint coordinates.
    pub fn snapshot(&self) -> Result<Snapshot, RapierError> {
        let mb = self.multibody()?;
        let n = self.layout.ndofs();
        if mb.ndofs() != n {
            return Err(RapierError::Missing("the degrees of freedom of a floating root and the joint"));
        }
        let mut positions = [Vector3::zeros(); 3];
        let mut rotations = [UnitQuaternion::identity(); 3];
        let mut q = [0.0; 2];
        for (i, id) in self.links.iter().enumerate() {
            let link = mb.link(*id).ok_or(RapierError::Missing("a link"))?;
            let pose = link.local_to_world();
            positions[i] = to_na(pose.translation);
            rotations[i] = rot_to_na(pose.rotation);
            if i > 0 && self.layout == Layout::Universal {
                // A revolute joint's free coordinate is its angular x (the joint axis).
                q[i - 1] = link.joint().coords()[3];
            }
        }
        if self.layout == Layout::Ball {
            // The no-twist joint's coordinates are the rotation vector of B relative to A.
            let r = (rotations[0].inverse() * rotations[2]).scaled_axis();
            q = [r.x, r.y];
        }
        let mut velocities = [0.0; NDOFS];
        velocities[..n].copy_from_slice(mb.generalized_velocity().as_slice());
        Ok(Snapshot { positions, rotations, velocities, q, layout: self.layout })
    }
}
