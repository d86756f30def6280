//! The rapier3d scene of any tree of rigid bodies ([`crate::model::tree::Tree`]): the cats beyond two
//! motors (the spherical joint's third motor, a tail, legs) in one multibody.
//!
//! Body 0 (the front half A) is the floating root; each link hangs its child from its parent as
//! the two-body scene ([`super::scene`]) hangs B from A, through a tiny **joint body** at the joint
//! point (mass `f · m̄`, `f = rapier.cross_mass_fraction` and `m̄` the bodies' mean mass,
//! isotropic inertia `f` times the bodies' mean smallest principal moment):
//! - a universal joint is two revolutes, about the parent's `x` to the joint body (the cross)
//!   and about the cross's `y` to the child;
//! - a no-twist or spherical joint is a ball joint from the parent to the joint body (the ball),
//!   which is welded to the child. Its generalized velocities are `ω_rel` in the parent's frame,
//!   so its three motors act about the parent's axes. Each step aims them at
//!   `w = log(R(q(t_{k+1})) R_relᵀ)/h`, the relative rate that carries the present relative
//!   rotation onto the schedule's over the step, as the two-body scene's ball does; on the
//!   spherical joint all three aim there (its relative twist is the third motor's), on the
//!   no-twist joint the one about `z` holds the joint's constraint instead (as the two-body scene's does, [`super::scene`]);
//! - a hinge (an appendage's) is a revolute about the parent's `x` to the joint body, which is
//!   welded to the child.
//!
//! Bodies' velocities are mapped from the multibody's generalized velocities at the present poses
//! (rapier leaves the rigid bodies' own copies at the start of the last substep): for a link with
//! parent `p`, joint body `j` and child `c` at the joint point `P`,
//! `ω_j = ω_p + q̇1 a1` and `ω_c = ω_j + q̇2 a2` (universal: `a1` the parent's `x`, `a2` the cross's
//! `y`), `ω_j = ω_c = ω_p + R_p ω_rel` (ball), or `ω_j = ω_c = ω_p + q̇1 a1` (hinge); `v_j = v_p + ω_p × (P − x_p)`,
//! `v_c = v_j + ω_c × (x_c − P)`. The scene has no colliders and no gravity (the falling frame,
//! as the two-body scene), and rapier's default damping of the multibody's DoFs is zeroed.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use rapier3d_f64::dynamics::{
    FixedJointBuilder, GenericJoint, JointAxis, MotorModel, Multibody, MultibodyJointHandle, RevoluteJointBuilder,
    RigidBodyBuilder, RigidBodyHandle, SphericalJointBuilder,
};
use rapier3d_f64::math::{Pose, Vector};
use rapier3d_f64::parry::mass_properties::MassProperties;
use rapier3d_f64::pipeline::PhysicsWorld;

use super::scene::{
    falling_world, from_na, rot_from_matrix, rot_from_na, rot_to_na, to_na, untwisting_rate, MotorGains, BALL_AXES,
};
use super::RapierError;
use crate::model::shape::ShapeState;
use crate::model::tree::{Body, Tree};
use crate::model::Joint;

/// One body's mass, world pose and velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreeBody {
    /// Mass, kg.
    pub mass: f64,
    /// Inertia about the centre, world frame, kg·m².
    pub inertia: Matrix3<f64>,
    /// Centre of mass, m.
    pub position: Vector3<f64>,
    /// Orientation.
    pub rotation: UnitQuaternion<f64>,
    /// Velocity of the centre, m/s.
    pub linvel: Vector3<f64>,
    /// Angular velocity, rad/s.
    pub angvel: Vector3<f64>,
}

/// The whole scene at one instant: the tree's bodies, then one joint body per link.
#[derive(Clone, Debug, PartialEq)]
pub struct TreeSnapshot {
    /// The tree's bodies (the base first), then link `i`'s joint body at `tree.bodies().len() + i`.
    pub bodies: Vec<TreeBody>,
    /// Generalized velocities: the root's `(v, ω)`, then the joints' rates.
    pub velocities: Vec<f64>,
}

/// How one link is built.
#[derive(Clone, Copy, Debug)]
struct Built {
    joint: Joint,
    /// Rapier link ids of the joint body and the child.
    link_ids: [usize; 2],
    /// Where their joints' rates start in the generalized velocities.
    dofs: [usize; 2],
}

/// A tree of bodies in a rapier world, its joints driven by motors, ready to step.
pub struct TreeScene {
    world: PhysicsWorld,
    /// Rigid bodies: the tree's, then the joint bodies.
    handles: Vec<RigidBodyHandle>,
    /// Each rigid body's link id in the multibody.
    link_ids: Vec<usize>,
    built: Vec<Built>,
    /// Any joint of the multibody (it reaches the whole multibody).
    any_joint: MultibodyJointHandle,
    tree: Tree,
    /// Mass and principal inertia of each rigid body (own frame).
    masses: Vec<(f64, Vector3<f64>)>,
    gains: MotorGains,
}

/// Whether rapier can bound `tree`'s motors by a torque limit ([`TreeScene::bound_motors`]): its
/// universal, no-twist and hinge joints' motors are their joints' axes in rapier, a spherical
/// joint's are not.
pub fn bounds_motors(tree: &Tree) -> bool {
    tree.links().iter().all(|l| l.joint != Joint::Spherical)
}

/// Why a tree with a spherical joint runs no motor limit ([`bounds_motors`]).
pub const UNBOUNDED_SPHERICAL: &str = "bounds the universal, no-twist and hinge joints' motors only: the spherical joint's motors are not its ball's axes in rapier (they are the parent's x, y and the child's spine)";

/// The multibody of `world` that `joint` belongs to.
fn multibody_in(world: &mut PhysicsWorld, joint: MultibodyJointHandle) -> Result<&mut Multibody, RapierError> {
    world.multibody_joints.get_mut(joint).map(|(mb, _)| mb).ok_or(RapierError::Missing("the multibody"))
}

/// Refuses a shape of `len` coordinates that is not `tree`'s.
fn sized(tree: &Tree, len: usize) -> Result<(), RapierError> {
    if len == tree.dof() {
        return Ok(());
    }
    Err(RapierError::TreeScope(format!("has {} joint coordinates; the shape given has {len}", tree.dof())))
}

/// The principal moments of a body whose inertia is diagonal in its own frame.
fn principal(body: &Body, index: usize) -> Result<Vector3<f64>, RapierError> {
    let i = body.inertia;
    let off = i[(0, 1)].abs() + i[(0, 2)].abs() + i[(1, 2)].abs();
    if off > 1e-12 * i.diagonal().amax() {
        return Err(RapierError::NotPrincipal(index));
    }
    Ok(i.diagonal())
}

/// The mass and the isotropic moment (kg, kg·m²) of every joint body of `tree`'s scene (module
/// docs): `fraction` of the bodies' mean mass and of their mean smallest principal moment. The
/// model files of a tree ([`crate::exchange::tree_model`]) give the universal joint's cross the same.
pub fn joint_body(tree: &Tree, fraction: f64) -> Result<(f64, f64), RapierError> {
    let n = tree.bodies().len() as f64;
    let mut smallest = 0.0;
    for (k, b) in tree.bodies().iter().enumerate() {
        smallest += principal(b, k)?.min();
    }
    Ok((fraction * tree.mass() / n, fraction * smallest / n))
}

impl TreeScene {
    /// Builds the scene at rest at `shape.q` (the tree's [`Tree::dof`] coordinates), with time
    /// step `dt`, one solver substep and `pgs_iterations` Gauss–Seidel sweeps, the motors holding
    /// `shape.q` with `gains`; the joint bodies' masses are `fraction` of the mean body's.
    pub fn new(
        tree: &Tree,
        fraction: f64,
        dt: f64,
        pgs_iterations: usize,
        gains: MotorGains,
        q0: &[f64],
    ) -> Result<Self, RapierError> {
        sized(tree, q0.len())?;
        let n = tree.bodies().len();
        let mut masses = Vec::with_capacity(n + tree.links().len());
        for (k, b) in tree.bodies().iter().enumerate() {
            masses.push((b.mass, principal(b, k)?));
        }
        let (mass, moment) = joint_body(tree, fraction)?;
        for _ in tree.links() {
            masses.push((mass, Vector3::repeat(moment)));
        }
        let mut world = falling_world(dt, pgs_iterations);
        // Straight poses (every coordinate zero): the joints then turn them to q0.
        let mut centres = vec![Vector3::zeros(); n];
        let mut points = Vec::with_capacity(tree.links().len());
        for (i, l) in tree.links().iter().enumerate() {
            let point = centres[l.parent] + l.at_parent;
            centres[i + 1] = point - l.at_child;
            points.push(point);
        }
        let handles: Vec<RigidBodyHandle> = centres
            .iter()
            .chain(&points)
            .zip(&masses)
            .map(|(x, (m, inertia))| {
                let mprops = MassProperties::new(Vector::ZERO, *m, from_na(inertia));
                let body = RigidBodyBuilder::dynamic()
                    .pose(Pose::from_parts(from_na(x), rot_from_na(&UnitQuaternion::identity())))
                    .additional_mass_properties(mprops)
                    .can_sleep(false)
                    .build();
                world.bodies.insert(body)
            })
            .collect();
        let motor = |b: GenericJoint, axes: &[JointAxis]| -> GenericJoint {
            let mut b = b;
            for &axis in axes {
                b.set_motor_model(axis, MotorModel::AccelerationBased);
                b.set_motor(axis, 0.0, 0.0, gains.stiffness, gains.damping);
            }
            b
        };
        let mut any_joint = None;
        for (i, l) in tree.links().iter().enumerate() {
            let (parent, cross, child) = (handles[l.parent], handles[n + i], handles[i + 1]);
            let (a, b) = (from_na(&l.at_parent), from_na(&l.at_child));
            let (first, second): (GenericJoint, GenericJoint) = match l.joint {
                Joint::Universal => (
                    motor(RevoluteJointBuilder::new(Vector::X).local_anchor1(a).build().into(), &[JointAxis::AngX]),
                    motor(RevoluteJointBuilder::new(Vector::Y).local_anchor2(b).build().into(), &[JointAxis::AngX]),
                ),
                Joint::NoTwist | Joint::Spherical => (
                    motor(SphericalJointBuilder::new().local_anchor1(a).build().into(), &BALL_AXES),
                    FixedJointBuilder::new().local_anchor2(b).build().into(),
                ),
                Joint::Hinge => (
                    motor(RevoluteJointBuilder::new(Vector::X).local_anchor1(a).build().into(), &[JointAxis::AngX]),
                    FixedJointBuilder::new().local_anchor2(b).build().into(),
                ),
            };
            world
                .multibody_joints
                .insert(parent, cross, first, true)
                .ok_or(RapierError::JointRejected("a joint from a parent to its joint body"))?;
            any_joint = Some(
                world
                    .multibody_joints
                    .insert(cross, child, second, true)
                    .ok_or(RapierError::JointRejected("a joint from a joint body to its child"))?,
            );
        }
        let any_joint = any_joint.ok_or(RapierError::Missing("a joint (the tree has one body)"))?;
        let link_ids = handles
            .iter()
            .map(|h| {
                world.multibody_joints.rigid_body_link(*h).map(|l| l.id).ok_or(RapierError::Missing("a body's link"))
            })
            .collect::<Result<Vec<usize>, RapierError>>()?;
        let built = {
            let (mb, _) = world.multibody_joints.get(any_joint).ok_or(RapierError::Missing("the multibody"))?;
            let dof = |id: usize| mb.link(id).map(|l| l.assembly_id()).ok_or(RapierError::Missing("a link"));
            tree.links()
                .iter()
                .enumerate()
                .map(|(i, l)| {
                    let ids = [link_ids[n + i], link_ids[i + 1]];
                    Ok(Built { joint: l.joint, link_ids: ids, dofs: [dof(ids[0])?, dof(ids[1])?] })
                })
                .collect::<Result<Vec<Built>, RapierError>>()?
        };
        let mut scene = TreeScene { world, handles, link_ids, built, any_joint, tree: tree.clone(), masses, gains };
        scene.place(q0)?;
        Ok(scene)
    }

    fn multibody(&self) -> Result<&Multibody, RapierError> {
        self.world.multibody_joints.get(self.any_joint).map(|(mb, _)| mb).ok_or(RapierError::Missing("the multibody"))
    }

    fn multibody_mut(&mut self) -> Result<&mut Multibody, RapierError> {
        multibody_in(&mut self.world, self.any_joint)
    }

    /// Turns the joints from zero to `q` (a revolute by its angle, a ball by the rotation vector
    /// of `R(q)`), zeroes rapier's damping and writes the poses to the rigid bodies.
    fn place(&mut self, q: &[f64]) -> Result<(), RapierError> {
        let tree = self.tree.clone();
        let built = self.built.clone();
        let mb = self.multibody_mut()?;
        let mut disp = vec![0.0; mb.ndofs()];
        for (i, b) in built.iter().enumerate() {
            let qi = &q[tree.coordinates(i)];
            match b.joint {
                Joint::Universal => {
                    disp[b.dofs[0]] = qi[0];
                    disp[b.dofs[1]] = qi[1];
                }
                Joint::NoTwist | Joint::Spherical => {
                    let v = rot_from_matrix(&b.joint.rotation(qi)).scaled_axis();
                    disp[b.dofs[0]..b.dofs[0] + 3].copy_from_slice(v.as_slice());
                }
                Joint::Hinge => disp[b.dofs[0]] = qi[0],
            }
        }
        mb.apply_displacements(&disp);
        mb.damping_mut().fill(0.0);
        let world = &mut self.world;
        let (mb, _) = world.multibody_joints.get_mut(self.any_joint).ok_or(RapierError::Missing("the multibody"))?;
        mb.forward_kinematics(&world.bodies, true);
        mb.update_rigid_bodies(&mut world.bodies, true);
        Ok(())
    }

    /// The tree the scene was built from.
    pub fn tree(&self) -> &Tree {
        &self.tree
    }

    /// The time step, s.
    pub fn dt(&self) -> f64 {
        self.world.integration_parameters.dt
    }

    /// Advances one step.
    pub fn step(&mut self) {
        self.world.step();
    }

    /// Every body's pose and velocity, and the generalized velocities (module docs).
    pub fn snapshot(&self) -> Result<TreeSnapshot, RapierError> {
        let mb = self.multibody()?;
        let velocities = mb.generalized_velocity().as_slice().to_vec();
        let mut bodies = Vec::with_capacity(self.handles.len());
        for (k, id) in self.link_ids.iter().enumerate() {
            let pose = mb.link(*id).ok_or(RapierError::Missing("a link"))?.local_to_world();
            let rotation = rot_to_na(pose.rotation);
            let (mass, moments) = self.masses[k];
            let r = rotation.to_rotation_matrix().into_inner();
            bodies.push(TreeBody {
                mass,
                inertia: r * Matrix3::from_diagonal(&moments) * r.transpose(),
                position: to_na(pose.translation),
                rotation,
                linvel: Vector3::zeros(),
                angvel: Vector3::zeros(),
            });
        }
        let mut snap = TreeSnapshot { bodies, velocities };
        self.map_velocities(&mut snap);
        Ok(snap)
    }

    /// Maps `snap.velocities` to its bodies' velocities at its poses (module docs).
    pub fn map_velocities(&self, snap: &mut TreeSnapshot) {
        let (v, bodies) = (&snap.velocities, &mut snap.bodies);
        bodies[0].linvel = Vector3::new(v[0], v[1], v[2]);
        bodies[0].angvel = Vector3::new(v[3], v[4], v[5]);
        let n = self.tree.bodies().len();
        for (i, (l, b)) in self.tree.links().iter().zip(&self.built).enumerate() {
            let (p, j, c) = (l.parent, n + i, i + 1);
            let (w_j, w_c) = match b.joint {
                Joint::Universal => {
                    let w_j = bodies[p].angvel + v[b.dofs[0]] * (bodies[p].rotation * Vector3::x());
                    (w_j, w_j + v[b.dofs[1]] * (bodies[j].rotation * Vector3::y()))
                }
                Joint::NoTwist | Joint::Spherical => {
                    let at = b.dofs[0];
                    let w = bodies[p].angvel + bodies[p].rotation * Vector3::new(v[at], v[at + 1], v[at + 2]);
                    (w, w)
                }
                Joint::Hinge => {
                    let w = bodies[p].angvel + v[b.dofs[0]] * (bodies[p].rotation * Vector3::x());
                    (w, w)
                }
            };
            let point = bodies[j].position;
            let v_j = bodies[p].linvel + bodies[p].angvel.cross(&(point - bodies[p].position));
            (bodies[j].linvel, bodies[j].angvel) = (v_j, w_j);
            bodies[c].linvel = v_j + w_c.cross(&(bodies[c].position - point));
            bodies[c].angvel = w_c;
        }
    }

    /// The motor axes of link `i` in the world at `snap`'s poses ([`Joint::motor_axes`]): the
    /// parent's `x` and the cross's `y` (universal), the parent's `x` and `y` (no-twist), and the
    /// child's spine (spherical); and which bodies each motor drives (the child's subtree with
    /// the link's joint body, without it for the cross's `y`); a hinge's, the parent's `x`.
    pub fn motors_of(&self, i: usize, snap: &TreeSnapshot) -> Vec<(Vector3<f64>, Vec<bool>)> {
        let n = self.tree.bodies().len();
        let l = self.tree.links()[i];
        let inside = self.tree.subtree(i);
        let mut driven: Vec<bool> = inside.clone();
        driven.extend((0..self.tree.links().len()).map(|k| inside[k + 1]));
        let r = |k: usize| snap.bodies[k].rotation;
        match l.joint {
            Joint::Universal => {
                let mut without_cross = driven.clone();
                without_cross[n + i] = false;
                vec![(r(l.parent) * Vector3::x(), driven), (r(n + i) * Vector3::y(), without_cross)]
            }
            Joint::NoTwist => {
                vec![(r(l.parent) * Vector3::x(), driven.clone()), (r(l.parent) * Vector3::y(), driven)]
            }
            Joint::Spherical => vec![
                (r(l.parent) * Vector3::x(), driven.clone()),
                (r(l.parent) * Vector3::y(), driven.clone()),
                (r(i + 1) * Vector3::z(), driven),
            ],
            Joint::Hinge => vec![(r(l.parent) * Vector3::x(), driven)],
        }
    }

    /// Sets the generalized velocities.
    pub fn set_velocities(&mut self, v: &[f64]) -> Result<(), RapierError> {
        let mb = self.multibody_mut()?;
        if v.len() != mb.ndofs() {
            return Err(RapierError::Missing("the degrees of freedom of a floating root and the joints"));
        }
        mb.generalized_velocity_mut().copy_from_slice(v);
        Ok(())
    }

    /// Sets the joints' rates to the shape rates `qd` and gives the whole tree the rigid motion
    /// that makes its linear and angular momentum zero (`ω = −I_lock⁻¹ H` about the centre of
    /// mass, its velocity `−p/M`).
    pub fn start_at_zero_momentum(&mut self, q: &[f64], qd: &[f64]) -> Result<(), RapierError> {
        sized(&self.tree, q.len().min(qd.len()))?;
        let mut snap = self.snapshot()?;
        let v = &mut snap.velocities;
        v.fill(0.0);
        for (i, b) in self.built.iter().enumerate() {
            let range = self.tree.coordinates(i);
            match b.joint {
                Joint::Universal => {
                    v[b.dofs[0]] = qd[range.start];
                    v[b.dofs[1]] = qd[range.start + 1];
                }
                Joint::NoTwist | Joint::Spherical => {
                    let w = b.joint.relative_rate(&q[range.clone()], &qd[range]);
                    v[b.dofs[0]..b.dofs[0] + 3].copy_from_slice(w.as_slice());
                }
                Joint::Hinge => v[b.dofs[0]] = qd[range.start],
            }
        }
        self.map_velocities(&mut snap);
        let m = momenta(&snap.bodies);
        let total: f64 = snap.bodies.iter().map(|b| b.mass).sum();
        let omega = m
            .locked
            .cholesky()
            .map(|ch| ch.solve(&(-m.angular)))
            .ok_or(RapierError::Missing("a positive definite locked inertia"))?;
        let lin = -m.linear / total + omega.cross(&(snap.bodies[0].position - m.centre));
        let mut v = snap.velocities;
        v[..3].copy_from_slice(lin.as_slice());
        v[3..6].copy_from_slice(omega.as_slice());
        self.set_velocities(&v)
    }

    /// Bounds every motor's torque by `limit` N·m (one torque limit on every motor,
    /// [`crate::model::motor::MotorsBeyond::TorqueLimit`]) and returns each coordinate's bound:
    /// a universal joint's revolutes, a hinge's, and a no-twist joint's ball about the parent's `x` and `y`
    /// (its motors' axes; the motor about `z` holds the joint's constraint, the structure's, and
    /// stays unbounded). A spherical joint's motors (the parent's `x`, `y` and the child's spine)
    /// are not its ball's axes in rapier: refused.
    pub fn bound_motors(&mut self, limit: f64) -> Result<Vec<Option<f64>>, RapierError> {
        if !bounds_motors(&self.tree) {
            return Err(RapierError::TreeScope(UNBOUNDED_SPHERICAL.into()));
        }
        let mb = multibody_in(&mut self.world, self.any_joint)?;
        for b in &self.built {
            let (ids, axes): (&[usize], &[JointAxis]) = match b.joint {
                Joint::Universal => (&b.link_ids, &[JointAxis::AngX]),
                Joint::Hinge => (&b.link_ids[..1], &[JointAxis::AngX]),
                _ => (&b.link_ids[..1], &[JointAxis::AngX, JointAxis::AngY]),
            };
            for id in ids {
                let link = mb.link_mut(*id).ok_or(RapierError::Missing("a link"))?;
                for axis in axes {
                    link.joint.data.set_motor_max_force(*axis, limit);
                }
            }
        }
        Ok(vec![Some(limit); self.tree.dof()])
    }

    /// Aims every joint's motors at the shape `target` at the end of the next step (module docs):
    /// a revolute's spring at `q − h q̇` with velocity `q̇`; a ball's motors at the rate that
    /// carries its present relative rotation onto `R(q)` over the step.
    pub fn aim(&mut self, target: &ShapeState) -> Result<(), RapierError> {
        sized(&self.tree, target.q.len().min(target.qd.len()))?;
        let h = self.dt();
        let g = self.gains;
        let snap = self.snapshot()?;
        let (tree, built) = (&self.tree, &self.built);
        let mb = multibody_in(&mut self.world, self.any_joint)?;
        for (i, (l, b)) in tree.links().iter().zip(built).enumerate() {
            let range = tree.coordinates(i);
            let (q, qd) = (&target.q[range.clone()], &target.qd[range]);
            match b.joint {
                Joint::Universal | Joint::Hinge => {
                    for (k, id) in b.link_ids[..l.joint.dof()].iter().enumerate() {
                        let link = mb.link_mut(*id).ok_or(RapierError::Missing("a link"))?;
                        link.joint.data.set_motor(JointAxis::AngX, q[k] - h * qd[k], qd[k], g.stiffness, g.damping);
                    }
                }
                Joint::NoTwist | Joint::Spherical => {
                    let now = snap.bodies[l.parent].rotation.inverse() * snap.bodies[i + 1].rotation;
                    let goal = rot_from_matrix(&b.joint.rotation(q));
                    let mut w = (goal * now.inverse()).scaled_axis() / h;
                    if b.joint == Joint::NoTwist {
                        w.z = untwisting_rate(&now, &Vector3::new(w.x, w.y, 0.0), h)
                            .ok_or(RapierError::Missing("a twist of a no-twist joint (its bodies folded flat)"))?;
                    }
                    let link = mb.link_mut(b.link_ids[0]).ok_or(RapierError::Missing("a link"))?;
                    let coords = link.joint().coords();
                    for (k, axis) in BALL_AXES.into_iter().enumerate() {
                        link.joint.data.set_motor(axis, coords[3 + k], w[k], g.stiffness, g.damping);
                    }
                }
            }
        }
        Ok(())
    }
}

/// The momenta of a set of bodies about their centre of mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Momenta {
    /// The centre of mass `c`, m.
    pub centre: Vector3<f64>,
    /// The linear momentum `p`, kg·m/s.
    pub linear: Vector3<f64>,
    /// The angular momentum `H` about `c`, N·m·s.
    pub angular: Vector3<f64>,
    /// The locked inertia about `c`, kg·m².
    pub locked: Matrix3<f64>,
}

/// The [`Momenta`] of `bodies`: `H = Σ I ω + m (x − c) × (v − v_c)`.
pub fn momenta(bodies: &[TreeBody]) -> Momenta {
    let total: f64 = bodies.iter().map(|b| b.mass).sum();
    let centre = bodies.iter().map(|b| b.mass * b.position).sum::<Vector3<f64>>() / total;
    let linear = bodies.iter().map(|b| b.mass * b.linvel).sum::<Vector3<f64>>();
    let vc = linear / total;
    let mut angular = Vector3::zeros();
    let mut locked = Matrix3::zeros();
    for b in bodies {
        let r = b.position - centre;
        angular += b.inertia * b.angvel + b.mass * r.cross(&(b.linvel - vc));
        locked += b.inertia + b.mass * (Matrix3::identity() * r.norm_squared() - r * r.transpose());
    }
    Momenta { centre, linear, angular, locked }
}
