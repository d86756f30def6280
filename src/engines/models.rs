//! The exact engine and the joint torques for any cat model (DESIGN.md §10): unequal halves, the
//! universal, no-twist or spherical joint.
//!
//! The model's two-body [`Tree`] ([`Cat::tree`]) is reduced by [`crate::engines::reduction`]
//! (`Ω = I_lock⁻¹(λ − h)`, its rate, and Newton–Euler for the joint's couple), and A's orientation
//! is integrated by the exact engine's own adaptive sixth-order Magnus (or, with spin,
//! fourth-order Runge–Kutta) integration ([`crate::engines::exact::adaptive_on`]) on the
//! model's [`RateField`]: one integrator for every model. On the paper's cat (equal halves,
//! universal joint) this reproduces [`crate::engines::exact::flip`] and
//! [`crate::engines::torque::joint_torques`] to round-off (tests/models.rs).
//!
//! A trajectory must give the joint's number of coordinates ([`crate::model::Joint::dof`]): a
//! library schedule (`q1, q2`) drives the universal and no-twist joints, and
//! [`crate::engines::shape::Held`] a spherical one with its relative twist held at zero.

use nalgebra::{Matrix2, Vector3};

use crate::engines::exact::{
    adaptive_on, integrate_on, Flip, OrientationSample, RateField, Stepper, MIN_HISTORY_PIECE_STEPS,
};
use crate::engines::reduction::{self, polarised_mass_matrix, LinkTorques};
use crate::engines::shape::ShapeTrajectory;
use crate::engines::spin::SpinHistory;
use crate::model::shape::ShapeState;
use crate::model::tree::Tree;
use crate::model::{Cat, Cylinder, Joint};
use crate::schedule::{JointState, Trajectory};

/// Why a model cannot run a trajectory.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum ModelError {
    /// The trajectory gives another number of shape coordinates than the joint has.
    #[error("cat.joint = \"{joint}\" has {expected} joint coordinates, but the trajectory gives {got}")]
    ShapeMismatch {
        /// The joint.
        joint: Joint,
        /// Its number of coordinates.
        expected: usize,
        /// The trajectory's.
        got: usize,
    },
    /// A command that measures two bodies met a problem with `[cat.tail]` or `[cat.legs]` (the field).
    #[error("{field}: {reason}", field = .0, reason = crate::problem::cat::appendage_refused(.0))]
    Appendage(&'static str),
}

/// Whether `shape` has the cat's number of coordinates.
fn check(cat: &Cat, shape: &ShapeState) -> Result<(), ModelError> {
    let expected = cat.dof();
    if shape.len() == expected && shape.qd.len() == expected && shape.qdd.len() == expected {
        Ok(())
    } else {
        Err(ModelError::ShapeMismatch { joint: cat.joint, expected, got: shape.len() })
    }
}

/// Whether every piece of `traj` starts with the cat's number of coordinates.
fn check_trajectory(cat: &Cat, traj: &impl ShapeTrajectory) -> Result<(), ModelError> {
    (0..traj.piece_durations().len()).try_for_each(|piece| check(cat, &traj.piece_shape(piece, 0.0)))
}

/// A model on a shape trajectory, as the integrator sees it.
pub struct ModelField<'a, T: ShapeTrajectory> {
    tree: &'a Tree,
    traj: &'a T,
}

impl<T: ShapeTrajectory> RateField for ModelField<'_, T> {
    fn piece_durations(&self) -> Vec<f64> {
        self.traj.piece_durations()
    }
    fn acceleration_jumps(&self, piece: usize) -> Vec<f64> {
        self.traj.acceleration_jumps(piece)
    }
    fn body_rate(&self, piece: usize, s: f64) -> Vector3<f64> {
        reduction::body_rate(self.tree, &self.traj.piece_shape(piece, s), &Vector3::zeros())
    }
    fn body_rate_spinning(&self, piece: usize, s: f64, lambda: &Vector3<f64>) -> Vector3<f64> {
        reduction::body_rate(self.tree, &self.traj.piece_shape(piece, s), lambda)
    }
}

/// `cat`'s tree, checked against `traj`'s number of coordinates.
fn checked_tree(cat: &Cat, traj: &impl ShapeTrajectory) -> Result<Tree, ModelError> {
    check_trajectory(cat, traj)?;
    Ok(cat.tree())
}

/// A's angular velocity (A's frame) at zero angular momentum.
pub fn body_rate(cat: &Cat, shape: &ShapeState) -> Result<Vector3<f64>, ModelError> {
    check(cat, shape)?;
    Ok(reduction::body_rate(&cat.tree(), shape, &Vector3::zeros()))
}

/// The total angular momentum about the centre of mass (A's frame) of the motion at `shape` with
/// A turning at `omega` ([`reduction::momentum`]).
pub fn momentum(cat: &Cat, shape: &ShapeState, omega: &Vector3<f64>) -> Result<Vector3<f64>, ModelError> {
    check(cat, shape)?;
    Ok(reduction::momentum(&cat.tree(), shape, omega))
}

/// What the joint transmits to the rear half at zero angular momentum.
pub fn joint_torques(cat: &Cat, shape: &ShapeState) -> Result<LinkTorques, ModelError> {
    joint_torques_spinning(cat, shape, &Vector3::zeros())
}

/// [`joint_torques`] with the total angular momentum `λ = Rᵀ L` in A's frame.
pub fn joint_torques_spinning(cat: &Cat, shape: &ShapeState, lambda: &Vector3<f64>) -> Result<LinkTorques, ModelError> {
    check(cat, shape)?;
    let mut all = reduction::joint_torques(&cat.tree(), shape, lambda);
    // A cat's tree has exactly one link.
    Ok(all.swap_remove(0))
}

/// The final twist and swing of a trajectory at zero angular momentum, to `tolerance` rad
/// ([`crate::engines::exact::flip`]'s adaptive integration).
pub fn flip(cat: &Cat, traj: &impl ShapeTrajectory, tolerance: f64) -> Result<Flip, ModelError> {
    let tree = checked_tree(cat, traj)?;
    Ok(adaptive_on(&ModelField { tree: &tree, traj }, Stepper::Magnus, tolerance, None))
}

/// [`flip`] for a release with total angular momentum `spin` (N·m·s, world frame).
pub fn flip_spinning(
    cat: &Cat,
    traj: &impl ShapeTrajectory,
    spin: &Vector3<f64>,
    tolerance: f64,
) -> Result<Flip, ModelError> {
    Ok(flip_on(&checked_tree(cat, traj)?, traj, spin, tolerance))
}

/// [`flip_spinning`] on any `tree` of bodies (a cat with a tail), `traj` giving its
/// [`Tree::dof`] coordinates (not checked: the caller's own tree and trajectory).
pub fn flip_on(tree: &Tree, traj: &impl ShapeTrajectory, spin: &Vector3<f64>, tolerance: f64) -> Flip {
    adaptive_on(&ModelField { tree, traj }, Stepper::for_spin(spin), tolerance, None)
}

/// The orientation history with `steps` steps per piece ([`crate::engines::exact::history`]).
pub fn history(
    cat: &Cat,
    traj: &impl ShapeTrajectory,
    stepper: Stepper,
    steps: usize,
) -> Result<Vec<OrientationSample>, ModelError> {
    let tree = checked_tree(cat, traj)?;
    let mut out = Vec::with_capacity(3 * steps + 1);
    integrate_on(&ModelField { tree: &tree, traj }, stepper, steps, |s| out.push(*s));
    Ok(out)
}

/// A cat whose joint has two coordinates and two motors (the universal and no-twist joints): the
/// models the library schedules drive, `q = (q1, q2)`, and whose torques fit the two-motor tables.
/// Its functions cannot meet a trajectory of another size, so they do not fail.
#[derive(Clone, Debug, PartialEq)]
pub struct TwoMotorCat {
    cat: Cat,
    tree: Tree,
}

impl TwoMotorCat {
    /// `cat`, refused ([`ModelError::ShapeMismatch`]) when its joint has not two coordinates.
    pub fn new(cat: Cat) -> Result<TwoMotorCat, ModelError> {
        if cat.dof() != 2 {
            return Err(ModelError::ShapeMismatch { joint: cat.joint, expected: cat.dof(), got: 2 });
        }
        Ok(TwoMotorCat { cat, tree: cat.tree() })
    }

    /// The paper's cat: two equal halves `half` on the universal joint.
    pub fn paper(half: Cylinder) -> TwoMotorCat {
        let cat = Cat::from(half);
        TwoMotorCat { cat, tree: cat.tree() }
    }

    /// The model.
    pub fn cat(&self) -> &Cat {
        &self.cat
    }

    /// The model on `traj`, as the integrator and a [`SpinHistory`] see it.
    pub fn field<'a, T: Trajectory>(&'a self, traj: &'a T) -> ModelField<'a, T> {
        ModelField { tree: &self.tree, traj }
    }

    /// A's angular velocity (A's frame) at zero angular momentum through `st`.
    pub fn body_rate(&self, st: &JointState) -> Vector3<f64> {
        self.body_rate_spinning(st, &Vector3::zeros())
    }

    /// A's angular velocity `Ω = I_lock⁻¹ (λ − h)` through `st` with the total angular momentum
    /// `λ` in A's frame.
    pub fn body_rate_spinning(&self, st: &JointState, lambda: &Vector3<f64>) -> Vector3<f64> {
        reduction::body_rate(&self.tree, &ShapeState::from(st), lambda)
    }

    /// A's angular velocity and acceleration `(Ω, Ω̇)` (A's frame) at zero angular momentum
    /// through `st`.
    pub fn body_motion(&self, st: &JointState) -> (Vector3<f64>, Vector3<f64>) {
        let d = reduction::dynamics(&self.tree, &ShapeState::from(st), &Vector3::zeros());
        (d.omega, d.omega_dot)
    }

    /// The total angular momentum about the centre of mass (A's frame) of the motion through
    /// `st` with A turning at `omega`.
    pub fn momentum(&self, st: &JointState, omega: &Vector3<f64>) -> Vector3<f64> {
        reduction::momentum(&self.tree, &ShapeState::from(st), omega)
    }

    /// What the joint transmits to the rear half at zero angular momentum through `st`: the motor
    /// torques on the joint's motor axes ([`Joint::motor_axes`]), the same from A's side, the
    /// couple and the force.
    pub fn joint_torques(&self, st: &JointState) -> LinkTorques {
        self.joint_torques_spinning(st, &Vector3::zeros())
    }

    /// [`TwoMotorCat::joint_torques`] with the total angular momentum `λ = Rᵀ L` in A's frame.
    pub fn joint_torques_spinning(&self, st: &JointState, lambda: &Vector3<f64>) -> LinkTorques {
        let mut all = reduction::joint_torques(&self.tree, &ShapeState::from(st), lambda);
        // A cat's tree has exactly one link.
        all.swap_remove(0)
    }

    /// The impulse the motors deliver when the joint rates jump by `dq` at `q` (zero angular
    /// momentum): the joint's couple at `q̇ = 0` with `q̈ = dq` projected on the motor axes. Over
    /// an instant only the couple's terms linear in the velocity change count, and at `q̇ = 0` its
    /// acceleration terms are exactly those (the base's `ΔΩ = −I_lock⁻¹ Δh` as `Ω̇ = −I_lock⁻¹ ḣ`).
    pub fn motor_impulse(&self, q: [f64; 2], dq: [f64; 2]) -> [f64; 2] {
        let t = self.jump_impulse_couple(q, dq);
        [t.tau[0], t.tau[1]]
    }

    /// The joint's whole impulse on B when the rates jump by `dq` at `q` (zero angular
    /// momentum), as [`TwoMotorCat::joint_torques`] gives a couple: its projections on the motor
    /// axes ([`TwoMotorCat::motor_impulse`]), the impulsive couple about the joint point in A's
    /// frame, N·m·s, and the impulsive force, N·s.
    pub fn jump_impulse_couple(&self, q: [f64; 2], dq: [f64; 2]) -> LinkTorques {
        self.joint_torques(&JointState { q, qd: [0.0; 2], qdd: dq })
    }

    /// The kinetic energy about the centre of mass of the zero-momentum motion `(q, q̇)`, J:
    /// `½ Σ_k (ω_k · I_k ω_k + m_k |ṙ_k + Ω × r_k|²)`, `ω_k = Ω + w_k` ([`Tree::motion`]).
    pub fn kinetic_energy(&self, q: [f64; 2], qd: [f64; 2]) -> f64 {
        let shape = ShapeState { q: q.to_vec(), qd: qd.to_vec(), qdd: vec![0.0; 2] };
        let motion = self.tree.motion(&shape);
        let omega = reduction::body_rate(&self.tree, &shape, &Vector3::zeros());
        self.tree
            .bodies()
            .iter()
            .zip(&motion.bodies)
            .map(|(b, k)| {
                let w = omega + k.rate;
                let v = k.velocity + omega.cross(&k.position);
                0.5 * (w.dot(&(k.inertia * w)) + b.mass * v.norm_squared())
            })
            .sum()
    }

    /// The reduced (zero-momentum) mass matrix `M(q)` with `E = ½ q̇ᵀ M q̇`, by polarisation of
    /// [`TwoMotorCat::kinetic_energy`].
    pub fn reduced_mass_matrix(&self, q: [f64; 2]) -> Matrix2<f64> {
        polarised_mass_matrix(|qd| self.kinetic_energy(q, qd))
    }

    /// The final twist and swing of `traj` at zero angular momentum, to `tolerance` rad
    /// ([`flip`]).
    pub fn flip(&self, traj: &impl Trajectory, tolerance: f64) -> Flip {
        self.flip_released(traj, &Vector3::zeros(), tolerance)
    }

    /// [`TwoMotorCat::flip`] for a release with total angular momentum `spin` (N·m·s, world
    /// frame; zero: the Magnus engine), without the orientation history.
    pub fn flip_released(&self, traj: &impl Trajectory, spin: &Vector3<f64>, tolerance: f64) -> Flip {
        adaptive_on(&self.field(traj), Stepper::for_spin(spin), tolerance, None)
    }

    /// The flip of `traj` released with total angular momentum `spin` (N·m·s, world frame), with
    /// the orientations its torques need ([`SpinHistory::new_on`]).
    pub fn flip_spinning(&self, traj: &impl Trajectory, spin: &Vector3<f64>, tolerance: f64) -> (Flip, SpinHistory) {
        SpinHistory::new_on(&self.field(traj), spin, tolerance)
    }

    /// The orientation history a picture of the fall of `traj` is drawn from, released with
    /// total angular momentum `spin` and about `steps` steps: the paper's cat without spin
    /// through the two-cylinder engine ([`crate::engines::exact::fall_history`]), any other
    /// through the general core ([`TwoMotorCat::fall_history`]).
    pub fn picture_history(&self, traj: &impl Trajectory, spin: &Vector3<f64>, steps: usize) -> Vec<OrientationSample> {
        match self.cat.paper() {
            Some(half) if spin.norm_squared() == 0.0 => crate::engines::exact::fall_history(half, traj, steps),
            _ => self.fall_history(traj, spin, steps),
        }
    }

    /// A's orientation history along `traj` released with total angular momentum `spin`, with
    /// about `steps` fixed steps over the whole trajectory, shared equally between its pieces (at
    /// least [`MIN_HISTORY_PIECE_STEPS`] each), as [`crate::engines::exact::fall_history`] on the
    /// paper's cat: the samples a picture of the fall is interpolated from.
    pub fn fall_history(&self, traj: &impl Trajectory, spin: &Vector3<f64>, steps: usize) -> Vec<OrientationSample> {
        fall_history_on(&self.tree, traj, spin, steps)
    }
}

/// A's orientation history along `traj` on any `tree` of bodies, as [`TwoMotorCat::fall_history`]
/// takes it on a two-motor cat: about `steps` fixed steps over the whole trajectory, shared
/// equally between its pieces (at least [`MIN_HISTORY_PIECE_STEPS`] each).
pub fn fall_history_on(
    tree: &Tree,
    traj: &impl ShapeTrajectory,
    spin: &Vector3<f64>,
    steps: usize,
) -> Vec<OrientationSample> {
    let pieces = traj.piece_durations().len().max(1);
    let per_piece = steps.div_ceil(pieces).max(MIN_HISTORY_PIECE_STEPS);
    let mut out = Vec::with_capacity(pieces * per_piece + 1);
    integrate_on(&ModelField { tree, traj }, Stepper::for_spin(spin), per_piece, |s| out.push(*s));
    out
}
