//! The cat the whole-manoeuvre optimiser plans for: one seam for the paper's cat, every other
//! two-motor model and the spherical joint (DESIGN.md §10).
//!
//! [`WholeCat::Paper`] is the paper's cat (two equal halves on the universal joint), which runs
//! through exactly the functions the optimiser was written with: [`super::dynamics`] for the
//! model and its derivatives, [`crate::engines::exact`] and [`crate::engines::torque`] for the
//! re-measurement and [`crate::engines::calibrate::calibrate_spinning`] for the starts, so its
//! results are bit-identical to the optimiser before the seam. [`WholeCat::Model`] is any other
//! two-motor [`Cat`] (unequal halves, the no-twist joint): [`super::model_dynamics`] for the model,
//! the general core [`TwoMotorCat`] for the flip, the torques and the calibration.
//! [`WholeCat::new`] chooses the branch by [`Cat::paper`]. [`WholeCat::Spherical`] is a cat on
//! the spherical joint, three coordinates and motors: [`super::model_dynamics`] for the model;
//! [`WholeCat::Appended`] a two-motor cat with appendages (a tail on a one- or two-motor joint,
//! legs on hinges; up to six coordinates): the general tree's [`super::tree_dynamics`]. Both are
//! re-measured by the general core on every coordinate ([`super::torques`]). A spherical cat
//! starts from a two-motor cat's starts ([`WholeCat::start_cat`]: the same halves on the no-twist
//! joint with the relative twist held at zero); a cat with appendages from its halves' starts
//! with its tail held straight behind it and its legs standing out, calibrated on its whole tree
//! ([`WholeCat::calibrate`]). Both are planned for a release without spin and ideal motors or
//! one torque limit on every motor ([`super::beyond_two_motors`], [`super::torque_limited`]).
//!
//! What depends on the joint is here too: the bend `β`, the angle between the spines, with
//! `cos β = e_z` for B's spine `e = R_AB ẑ`: `cos q1 cos q2` on the universal joint, `cos |q|` on
//! the no-twist joint and the spherical one (whose relative twist `q3` turns B about its own
//! spine), [`WholeCat::bend_cosine`]. The derivatives the loop needs come from dual numbers seeded
//! on every coordinate ([`WholeCat::rate_partials`], [`WholeCat::torque_partials`]).

use nalgebra::Vector3;

use super::dual::{Dual, Real, V3};
use super::dynamics;
use super::model_dynamics::{self, ExpSeries};
use super::settings::WholeError;
use super::spline::{BSpline, SplineShape};
use super::torques::ExactTorques;
use super::tree_dynamics;
use crate::engines::calibrate::{calibrate_held, calibrate_model, calibrate_spinning, Calibration};
use crate::engines::exact::{self, Flip};
use crate::engines::models::{self, TwoMotorCat};
use crate::engines::spin::SpinHistory;
use crate::engines::torque::TorqueSource;
use crate::model::cat::Appendages;
use crate::model::tree::Tree;
use crate::model::{Cat, Cylinder, Joint};
use crate::numeric::numfmt::echo;
use crate::schedule::{paper_circulation, Schedule, ScheduleError};

/// The optimiser's cat: the paper's, another two-motor model, or one of more motors (module docs).
#[derive(Clone, Debug, PartialEq)]
pub enum WholeCat {
    /// The paper's cat, one of its two equal halves (the two-cylinder engine).
    Paper(Cylinder),
    /// Any other two-motor model (the general core).
    Model(TwoMotorCat),
    /// A cat on the spherical joint: three coordinates and motors ([`WholeCat::spherical`]),
    /// re-measured by the general core on every coordinate ([`super::torques`]), for ideal motors
    /// or one torque limit on every motor ([`super::torque_limited`]) and without spin; the command
    /// line's one measurement takes two motors, so [`WholeCat::new`] refuses it.
    Spherical(SphericalCat),
    /// A two-motor cat with appendages ([`WholeCat::appended`]: a tail, legs), a tree of bodies
    /// planned by the loop through [`super::tree_dynamics`], for ideal motors or one torque limit
    /// on every motor and without spin.
    Appended(Appended),
}

/// A cat on the spherical joint ([`WholeCat::spherical`] builds it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphericalCat(Cat);

/// A cat with appendages ([`WholeCat::appended`] builds it): the cat (its halves and joint, link
/// 0), its appendages and the tree of all the bodies ([`Cat::tree_with`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Appended {
    cat: Cat,
    appendages: Appendages,
    tree: Tree,
}

/// The most shape coordinates the optimiser plans: a cat's two, a tail's two and the legs' two.
pub const MAX_JOINTS: usize = 6;

/// One body of a cat's tree with its name and its cylinder ([`WholeCat::named_bodies`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NamedBody {
    /// `A`, `B`, `tail`, `front-legs`, `hind-legs`.
    pub name: &'static str,
    /// Its mass, length and radius.
    pub cylinder: Cylinder,
    /// Its cylinder's axis in its own frame (unit).
    pub axis: Vector3<f64>,
}

/// A quantity of the shape's motion and its partial derivatives: `d[0][j]`, `d[1][j]`, `d[2][j]`
/// with respect to coordinate `j`'s angle, rate and acceleration (the first
/// [`WholeCat::joints`] entries of each; the rest zero).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Partials {
    /// The value.
    pub value: f64,
    /// `[∂/∂q, ∂/∂q̇, ∂/∂q̈]`, one entry per coordinate.
    pub d: [[f64; MAX_JOINTS]; 3],
}

/// The first two of `N` values (the two-motor models' coordinates).
fn two<T: Copy, const N: usize>(x: [T; N]) -> [T; 2] {
    assert_eq!(N, 2, "the paper's dynamics take two coordinates, not {N}");
    [x[0], x[1]]
}

/// The `(value, partials)` of `f` at `x`, seeded as dual numbers: `D = K·N` inputs, `K` the
/// orders given (angle, rate, acceleration), `N` the coordinates.
fn seeded<const N: usize, const D: usize, const M: usize>(
    x: [&[f64]; 3],
    orders: usize,
    f: impl Fn([[Dual<D>; N]; 3]) -> [Dual<D>; M],
) -> [Partials; M] {
    assert_eq!(D, orders * N, "{D} dual directions for {orders} orders of {N} coordinates");
    let input: [[Dual<D>; N]; 3] = std::array::from_fn(|k| {
        std::array::from_fn(|j| if k < orders { Dual::input(x[k][j], k * N + j) } else { Dual::cst(0.0) })
    });
    f(input).map(|y| {
        let mut p = Partials { value: y.re, ..Partials::default() };
        for k in 0..orders {
            for j in 0..N {
                p.d[k][j] = y.eps[k * N + j];
            }
        }
        p
    })
}

impl From<Cylinder> for WholeCat {
    /// The paper's cat of two halves `half`.
    fn from(half: Cylinder) -> WholeCat {
        WholeCat::Paper(half)
    }
}

impl From<&Cylinder> for WholeCat {
    /// The paper's cat of two halves `half`.
    fn from(half: &Cylinder) -> WholeCat {
        WholeCat::Paper(*half)
    }
}

impl From<&WholeCat> for WholeCat {
    /// A copy, so that the optimiser's entry points take a cat by reference too.
    fn from(cat: &WholeCat) -> WholeCat {
        cat.clone()
    }
}

impl From<&TwoMotorCat> for WholeCat {
    /// The model's branch: the paper's cat when it is one ([`Cat::paper`]).
    fn from(model: &TwoMotorCat) -> WholeCat {
        match model.cat().paper() {
            Some(half) => WholeCat::Paper(*half),
            None => WholeCat::Model(model.clone()),
        }
    }
}

impl WholeCat {
    /// `cat`'s branch ([`Cat::paper`] chooses), refused when its joint has not two motors
    /// (naming `cat.joint`).
    pub fn new(cat: Cat) -> Result<WholeCat, WholeError> {
        let model = TwoMotorCat::new(cat).map_err(|e| WholeError::BadFieldValue {
            field: "cat.joint",
            value: format!("\"{}\"", cat.joint),
            reason: format!(
                "WholeCat::new takes the two-motor cats ({e}): use \"universal\" or \"no-twist\", or WholeCat::spherical"
            ),
        })?;
        Ok(WholeCat::from(&model))
    }

    /// A cat on the spherical joint for the successive-convexification loop alone
    /// ([`WholeCat::Spherical`]); `None` for another joint.
    pub fn spherical(cat: Cat) -> Option<WholeCat> {
        (cat.joint == Joint::Spherical).then_some(WholeCat::Spherical(SphericalCat(cat)))
    }

    /// `cat` with a tail: a rod `tail` hung from the rear half's end (`(0, 0, −l_B/2)` in B's
    /// frame) by its own front end on `joint`, straight behind the cat at `q = 0`
    /// ([`WholeCat::appended`]).
    pub fn tailed(cat: Cat, tail: Cylinder, joint: Joint) -> Option<WholeCat> {
        WholeCat::appended(cat, Appendages { tail: Some((tail, joint)), legs: None })
    }

    /// `cat` with `appendages` ([`Cat::tree_with`]). `None` unless the cat's joint has two motors
    /// (the universal or no-twist joint), the tail's is one of those or a hinge, and there is an
    /// appendage.
    pub fn appended(cat: Cat, appendages: Appendages) -> Option<WholeCat> {
        let tail_ok =
            appendages.tail.is_none_or(|(_, j)| matches!(j, Joint::Universal | Joint::NoTwist | Joint::Hinge));
        if cat.dof() != 2 || !tail_ok || appendages.is_empty() {
            return None;
        }
        Some(WholeCat::Appended(Appended { cat, appendages, tree: cat.tree_with(&appendages) }))
    }

    /// The appendages (none but on [`WholeCat::Appended`]).
    pub fn appendages(&self) -> Appendages {
        match self {
            WholeCat::Appended(a) => a.appendages,
            _ => Appendages::default(),
        }
    }

    /// Each coordinate's limit on its control points, rad: `joint_limit_deg`
    /// (`optimize.whole.joint_limit_deg`, on every coordinate) and the coordinate's own (the
    /// legs' fold, [`Appendages::limits`]), the smaller where both hold.
    pub fn control_limits(&self, joint_limit_deg: Option<f64>) -> Vec<Option<f64>> {
        let every = joint_limit_deg.map(f64::to_radians);
        std::iter::repeat_n(None, self.joint().dof())
            .chain(self.appendages().limits())
            .map(|own| match (own, every) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            })
            .collect()
    }

    /// The two-motor cat this one's starts are built and calibrated on: a spherical joint's
    /// halves on the no-twist joint (its twist held at zero, which is exactly that joint,
    /// DESIGN.md §10); `None` for every other cat, whose starts are calibrated on the cat itself
    /// (a cat with appendages on its whole tree, the appendages held still:
    /// [`WholeCat::calibrate`]).
    pub fn start_cat(&self) -> Option<WholeCat> {
        match self {
            WholeCat::Spherical(SphericalCat(cat)) => {
                let bent =
                    TwoMotorCat::new(Cat { joint: Joint::NoTwist, ..*cat }).expect("the no-twist joint has two motors");
                Some(WholeCat::Model(bent))
            }
            _ => None,
        }
    }

    /// The model as a [`Cat`].
    pub fn cat(&self) -> Cat {
        match self {
            WholeCat::Paper(half) => Cat::from(*half),
            WholeCat::Model(m) => *m.cat(),
            WholeCat::Spherical(SphericalCat(cat)) => *cat,
            WholeCat::Appended(a) => a.cat,
        }
    }

    /// Each body of the model's tree ([`WholeCat::tree`]) in its order, named, with the axis of
    /// its cylinder in its own frame: the front half `A`, the rear half `B`, with a tail the
    /// `tail` (each along `z`), with legs the `front-legs` and `hind-legs` (along `y`).
    pub fn named_bodies(&self) -> Vec<NamedBody> {
        let cat = self.cat();
        let along_z = |name, cylinder| NamedBody { name, cylinder, axis: Vector3::z() };
        let mut out = vec![along_z("A", cat.front), along_z("B", cat.rear)];
        let appendages = self.appendages();
        if let Some((tail, _)) = appendages.tail {
            out.push(along_z("tail", tail));
        }
        if let Some(legs) = appendages.legs {
            for (name, cylinder) in ["front-legs", "hind-legs"].into_iter().zip(legs) {
                out.push(NamedBody { name, cylinder, axis: Vector3::y() });
            }
        }
        out
    }

    /// Number of shape coordinates (and motors): 2, 3 on the spherical joint, and the
    /// appendages' beyond the cat's.
    pub fn joints(&self) -> usize {
        match self {
            WholeCat::Appended(a) => a.tree.dof(),
            _ => self.joint().dof(),
        }
    }

    /// The model in words ([`Cat::describe`], and the appendages', [`Appendages::describe`], with
    /// the whole cat's mass: heavier than the cat without them).
    pub fn describe(&self) -> String {
        match self {
            WholeCat::Appended(a) => {
                format!("{}{}; {} kg in all", a.cat.describe(), a.appendages.describe(), echo(a.tree.mass()))
            }
            _ => self.cat().describe(),
        }
    }

    /// The joint.
    pub fn joint(&self) -> Joint {
        match self {
            WholeCat::Paper(_) => Joint::Universal,
            WholeCat::Model(m) => m.cat().joint,
            WholeCat::Spherical(_) => Joint::Spherical,
            WholeCat::Appended(a) => a.cat.joint,
        }
    }

    /// A's angular velocity (A's frame) through `(q, q̇)` at zero momentum; `N` is
    /// [`WholeCat::joints`].
    pub fn body_rate<T: Real, const N: usize>(&self, q: [T; N], qd: [T; N]) -> V3<T> {
        match self {
            WholeCat::Paper(c) => dynamics::body_rate(c, two(q), two(qd)),
            WholeCat::Model(m) => model_dynamics::body_rate(m.cat(), q, qd),
            WholeCat::Spherical(SphericalCat(cat)) => model_dynamics::body_rate(cat, q, qd),
            WholeCat::Appended(a) => tree_dynamics::body_rate(&a.tree, &q, &qd, [T::cst(0.0); 3]),
        }
    }

    /// A's angular velocity with the total momentum `λ = Rᵀ L` in A's frame (the two-motor
    /// models: a release with spin is not planned beyond two motors, [`super::beyond_two_motors`]).
    pub fn body_rate_spinning<T: Real>(&self, q: [T; 2], qd: [T; 2], lambda: V3<T>) -> V3<T> {
        match self {
            WholeCat::Paper(c) => dynamics::body_rate_spinning(c, q, qd, lambda),
            WholeCat::Model(m) => model_dynamics::body_rate_spinning(m.cat(), q, qd, lambda),
            _ => unreachable!("a release with spin is planned for two motors only (beyond_two_motors refuses it)"),
        }
    }

    /// The motor torques `(τ1, …, τ_N)`, N·m, through `(q, q̇, q̈)` at zero momentum; `N` is
    /// [`WholeCat::joints`].
    pub fn motor_torques<T: Real, const N: usize>(&self, q: [T; N], qd: [T; N], qdd: [T; N]) -> [T; N] {
        match self {
            WholeCat::Paper(c) => {
                let t = dynamics::motor_torques(c, two(q), two(qd), two(qdd));
                std::array::from_fn(|j| t[j])
            }
            WholeCat::Model(m) => model_dynamics::motor_torques(m.cat(), q, qd, qdd),
            WholeCat::Spherical(SphericalCat(cat)) => model_dynamics::motor_torques(cat, q, qd, qdd),
            WholeCat::Appended(a) => {
                let tau = tree_dynamics::motor_torques(&a.tree, &q, &qd, &qdd, [T::cst(0.0); 3]);
                std::array::from_fn(|j| tau[j])
            }
        }
    }

    /// A's angular velocity at `(q, q̇)` (zero momentum) and its partials in the shape, from dual
    /// numbers: one [`Partials`] per component (no `q̈` partials).
    pub fn rate_partials(&self, q: &[f64], qd: &[f64]) -> [Partials; 3] {
        let x = [q, qd, &[][..]];
        match q.len() {
            2 => seeded::<2, 4, 3>(x, 2, |[q, qd, _]| self.body_rate(q, qd)),
            3 => seeded::<3, 6, 3>(x, 2, |[q, qd, _]| self.body_rate(q, qd)),
            4 => seeded::<4, 8, 3>(x, 2, |[q, qd, _]| self.body_rate(q, qd)),
            5 => seeded::<5, 10, 3>(x, 2, |[q, qd, _]| self.body_rate(q, qd)),
            6 => seeded::<6, 12, 3>(x, 2, |[q, qd, _]| self.body_rate(q, qd)),
            n => panic!("a shape of {n} coordinates"),
        }
    }

    /// The motor torques at `(q, q̇, q̈)` (zero momentum) and their partials in the shape, from
    /// dual numbers: one [`Partials`] per motor, [`WholeCat::joints`] of them.
    pub fn torque_partials(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> Vec<Partials> {
        let x = [q, qd, qdd];
        match q.len() {
            2 => seeded::<2, 6, 2>(x, 3, |[q, qd, qdd]| self.motor_torques(q, qd, qdd)).to_vec(),
            3 => seeded::<3, 9, 3>(x, 3, |[q, qd, qdd]| self.motor_torques(q, qd, qdd)).to_vec(),
            4 => seeded::<4, 12, 4>(x, 3, |[q, qd, qdd]| self.motor_torques(q, qd, qdd)).to_vec(),
            5 => seeded::<5, 15, 5>(x, 3, |[q, qd, qdd]| self.motor_torques(q, qd, qdd)).to_vec(),
            6 => seeded::<6, 18, 6>(x, 3, |[q, qd, qdd]| self.motor_torques(q, qd, qdd)).to_vec(),
            n => panic!("a shape of {n} coordinates"),
        }
    }

    /// The motor torques at `(q, q̇, q̈)` (zero momentum), N·m, without partials: one per motor,
    /// [`WholeCat::joints`] of them.
    pub fn torques(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> Vec<f64> {
        fn at<const N: usize>(cat: &WholeCat, q: &[f64], qd: &[f64], qdd: &[f64]) -> Vec<f64> {
            let take = |x: &[f64]| -> [f64; N] { std::array::from_fn(|j| x[j]) };
            cat.motor_torques(take(q), take(qd), take(qdd)).to_vec()
        }
        match q.len() {
            2 => at::<2>(self, q, qd, qdd),
            3 => at::<3>(self, q, qd, qdd),
            4 => at::<4>(self, q, qd, qdd),
            5 => at::<5>(self, q, qd, qdd),
            6 => at::<6>(self, q, qd, qdd),
            n => panic!("a shape of {n} coordinates"),
        }
    }

    /// The motor torques with the total momentum `λ = Rᵀ L` in A's frame.
    pub fn motor_torques_spinning<T: Real>(&self, q: [T; 2], qd: [T; 2], qdd: [T; 2], lambda: V3<T>) -> [T; 2] {
        match self {
            WholeCat::Paper(c) => dynamics::motor_torques_spinning(c, q, qd, qdd, lambda),
            WholeCat::Model(m) => model_dynamics::motor_torques_spinning(m.cat(), q, qd, qdd, lambda),
            _ => unreachable!("a release with spin is planned for two motors only (beyond_two_motors refuses it)"),
        }
    }

    /// The joint whose bend is this cat's: the spherical joint bends as the no-twist joint (its
    /// relative twist turns B about its own axis, which moves neither spine).
    fn bend_joint(&self) -> Joint {
        match self.joint() {
            Joint::Spherical => Joint::NoTwist,
            joint => joint,
        }
    }

    /// B's spine `e = R_AB ẑ` in A's frame at `q` (its first two coordinates).
    pub fn spine(&self, q: &[f64]) -> [f64; 3] {
        model_dynamics::spine(self.bend_joint(), [q[0], q[1]])
    }

    /// The cosine of the bend, `cos β = e_z`, and its gradient in `q` (zero in a spherical joint's
    /// twist and in a tail's coordinates): `cos q1 cos q2` on the universal joint, `cos |q|`
    /// (gradient `−(sin θ/θ) q`) on the no-twist and spherical joints.
    pub fn bend_cosine(&self, q: &[f64]) -> (f64, [f64; MAX_JOINTS]) {
        match self.bend_joint() {
            Joint::Universal => {
                let (s1, c1) = q[0].sin_cos();
                let (s2, c2) = q[1].sin_cos();
                let mut g = [0.0; MAX_JOINTS];
                g[..2].copy_from_slice(&[-s1 * c2, -c1 * s2]);
                (c1 * c2, g)
            }
            Joint::NoTwist | Joint::Spherical => {
                let s = q[0] * q[0] + q[1] * q[1];
                let k = ExpSeries::at(s);
                let mut g = [0.0; MAX_JOINTS];
                g[..2].copy_from_slice(&[-k.sinc * q[0], -k.sinc * q[1]]);
                (1.0 - k.a * s, g)
            }
            Joint::Hinge => unreachable!("the halves are never on a hinge (WholeCat's constructors refuse it)"),
        }
    }

    /// The flip of `spline` at zero momentum, to `tolerance` rad.
    pub fn flip(&self, spline: &BSpline, tolerance: f64) -> Flip {
        self.flip_spinning(spline, &Vector3::zeros(), tolerance)
    }

    /// The flip of `spline` released with total angular momentum `spin` (N·m·s, world frame).
    pub fn flip_spinning(&self, spline: &BSpline, spin: &Vector3<f64>, tolerance: f64) -> Flip {
        match self {
            WholeCat::Paper(c) => exact::flip_spinning(c, spline, spin, tolerance),
            WholeCat::Model(m) => m.flip_released(spline, spin, tolerance),
            WholeCat::Spherical(_) | WholeCat::Appended(_) => {
                assert_eq!(spline.joints(), self.joints(), "a spline of the cat's coordinates");
                models::flip_on(&self.tree(), &SplineShape(spline), spin, tolerance)
            }
        }
    }

    /// The model's tree of bodies.
    pub fn tree(&self) -> Tree {
        match self {
            WholeCat::Appended(a) => a.tree.clone(),
            _ => self.cat().tree(),
        }
    }

    /// The two-motor model, for what is two-motor still (a spin history, a torque source, a
    /// calibration): never asked of a cat of more motors (a spherical cat's starts are a two-motor
    /// cat's, an appended cat calibrates on its tree, [`WholeCat::calibrate`]).
    fn two_motor(&self, what: &str) -> &TwoMotorCat {
        match self {
            WholeCat::Model(m) => m,
            _ => panic!("{what} of a cat of {} motors: not built (two motors only)", self.joints()),
        }
    }

    /// The flip released with `spin` and the orientations its torques need.
    pub fn spin_history(&self, spline: &BSpline, spin: &Vector3<f64>, tolerance: f64) -> (Flip, SpinHistory) {
        match self {
            WholeCat::Paper(c) => SpinHistory::new(c, spline, spin, tolerance),
            _ => self.two_motor("the spin history").flip_spinning(spline, spin, tolerance),
        }
    }

    /// Where the exact torques come from: zero momentum, or the motion of `history`.
    pub fn torque_source<'a>(&'a self, history: Option<&'a SpinHistory>) -> TorqueSource<'a> {
        match (self, history) {
            (WholeCat::Paper(c), None) => TorqueSource::zero_momentum(c),
            (WholeCat::Paper(c), Some(h)) => TorqueSource::spinning(c, h),
            (_, None) => TorqueSource::model(self.two_motor("the torque source")),
            (_, Some(h)) => TorqueSource::model_spinning(self.two_motor("the torque source"), h),
        }
    }

    /// Where a spline's exact torques come from ([`ExactTorques`]): the two-motor models'
    /// [`WholeCat::torque_source`], the general core on a cat of more motors (without spin).
    pub fn exact_torques<'a>(&'a self, history: Option<&'a SpinHistory>) -> ExactTorques<'a> {
        match self {
            WholeCat::Spherical(_) | WholeCat::Appended(_) => ExactTorques::General(self.tree()),
            _ => ExactTorques::TwoMotor(self.torque_source(history)),
        }
    }

    /// The circulation that turns `schedule` by ±π released with `spin`, to `tolerance` rad.
    pub fn calibrate(&self, schedule: &Schedule, spin: &Vector3<f64>, tolerance: f64) -> Calibration {
        match self {
            WholeCat::Paper(c) => calibrate_spinning(c, schedule, spin, tolerance),
            WholeCat::Appended(a) => calibrate_held(&a.tree, schedule, spin, tolerance),
            _ => calibrate_model(self.two_motor("the calibration"), schedule, spin, tolerance),
        }
    }

    /// The paper's `π/C` at the angle `theta` between the halves (of the mean half,
    /// [`Cat::mean_half`], when the halves differ: a start for the calibration only).
    pub fn paper_circulation(&self, theta: f64) -> Result<f64, ScheduleError> {
        match self {
            WholeCat::Paper(c) => paper_circulation(c, theta),
            _ => paper_circulation(&self.cat().mean_half(), theta),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::shape::ShapeState;

    const HALF: Cylinder = Cylinder { mass: 1.0, length: 1.0, radius: 0.1 };

    #[test]
    fn the_paper_cat_takes_the_paper_branch_and_others_the_model() {
        assert_eq!(WholeCat::new(Cat::from(HALF)).ok(), Some(WholeCat::Paper(HALF)));
        let kane = WholeCat::new(Cat::equal(HALF, Joint::NoTwist)).unwrap_or_else(|e| panic!("{e}"));
        assert!(matches!(kane, WholeCat::Model(_)), "{kane:?}");
        let e = WholeCat::new(Cat::equal(HALF, Joint::Spherical)).map(|_| ()).unwrap_err();
        assert!(e.to_string().starts_with("cat.joint = \"spherical\""), "{e}");
    }

    /// The partials through the seeded dual numbers, on cats of three to six coordinates (a
    /// hinged tail; legs; legs and a hinged tail; legs and a universal tail), against central
    /// differences (step 1e-6: truncation ~1e-12, round-off ~1e-10; 1e-7 absolute, as the dual
    /// tests of the dynamics), and their values against the general core's.
    #[test]
    fn the_partials_of_every_size_match_central_differences() {
        let cat = Cat::equal(HALF, Joint::NoTwist);
        let (tail, leg) =
            (Cylinder { mass: 0.2, length: 1.0, radius: 0.02 }, Cylinder { mass: 0.2, length: 0.45, radius: 0.03 });
        let cats = [
            Appendages { tail: Some((tail, Joint::Hinge)), legs: None },
            Appendages { tail: None, legs: Some([leg; 2]) },
            Appendages { tail: Some((tail, Joint::Hinge)), legs: Some([leg; 2]) },
            Appendages { tail: Some((tail, Joint::Universal)), legs: Some([leg; 2]) },
        ];
        for appendages in cats {
            let whole = WholeCat::appended(cat, appendages).expect("a cat with appendages");
            let n = whole.joints();
            let f = |a: f64, b: f64| -> Vec<f64> { (0..n).map(|j| a * ((j as f64 + 1.0) * b + 0.3).sin()).collect() };
            let x = [f(1.1, 0.7), f(2.1, 1.3), f(3.4, 0.4)];
            let rates = whole.rate_partials(&x[0], &x[1]);
            let torques = whole.torque_partials(&x[0], &x[1], &x[2]);
            assert_eq!((torques.len(), n), (appendages.dof() + 2, n));
            let tree = whole.tree();
            let shape = |x: &[Vec<f64>; 3]| ShapeState { q: x[0].clone(), qd: x[1].clone(), qdd: x[2].clone() };
            let rate = |x: &[Vec<f64>; 3]| crate::engines::reduction::body_rate(&tree, &shape(x), &Vector3::zeros());
            let tau = |x: &[Vec<f64>; 3]| -> Vec<f64> {
                crate::engines::reduction::joint_torques(&tree, &shape(x), &Vector3::zeros())
                    .into_iter()
                    .flat_map(|l| l.tau)
                    .collect()
            };
            let (w, t) = (rate(&x), tau(&x));
            for i in 0..3 {
                assert!((rates[i].value - w[i]).abs() <= 1e-12 * w.norm().max(1.0), "{n}: Ω {i}");
            }
            for (p, want) in torques.iter().zip(&t) {
                assert!((p.value - want).abs() <= 1e-12, "{n}: τ {} against {want}", p.value);
            }
            let step = 1e-6;
            for order in 0..3 {
                for j in 0..n {
                    let shifted = |sign: f64| {
                        let mut y = x.clone();
                        y[order][j] += sign * step;
                        y
                    };
                    let (plus, minus) = (shifted(1.0), shifted(-1.0));
                    let dw = (rate(&plus) - rate(&minus)) / (2.0 * step);
                    if order < 2 {
                        for i in 0..3 {
                            assert!((rates[i].d[order][j] - dw[i]).abs() <= 1e-7, "{n}: ∂Ω{i}/∂x{order},{j}");
                        }
                    }
                    let (tp, tm) = (tau(&plus), tau(&minus));
                    for (k, p) in torques.iter().enumerate() {
                        let fd = (tp[k] - tm[k]) / (2.0 * step);
                        assert!(
                            (p.d[order][j] - fd).abs() <= 1e-7,
                            "{n}: ∂τ{k}/∂x{order},{j}: {} against {fd}",
                            p.d[order][j]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_bend_is_the_angle_between_the_spines_with_its_gradient() {
        let spherical = WholeCat::spherical(Cat::equal(HALF, Joint::Spherical)).expect("a spherical cat");
        let cats = [Joint::Universal, Joint::NoTwist]
            .map(|joint| WholeCat::new(Cat::equal(HALF, joint)).unwrap_or_else(|e| panic!("{e}")));
        for cat in cats.iter().chain([&spherical]) {
            let joint = cat.joint();
            for bend in [[0.0, 0.0], [1e-3, -2e-3], [0.4, -0.9], [1.7, 0.6]] {
                // The spherical joint's relative twist turns B about its own spine: no bend.
                let q: Vec<f64> = bend.iter().copied().chain([0.7]).take(cat.joints()).collect();
                let (c, g) = cat.bend_cosine(&q);
                let e = joint.rotation(&q) * nalgebra::Vector3::z();
                assert!((cat.spine(&q)[2] - e.z).abs() < 1e-15, "{joint}: the spine at {q:?}");
                assert!((c - e.z).abs() < 1e-15, "{joint}: {c} at {q:?}");
                if joint != Joint::Universal {
                    assert!((c - q[0].hypot(q[1]).cos()).abs() < 1e-15, "the {joint} bend is |(q1, q2)|");
                }
                for k in 0..q.len() {
                    let step = 1e-6;
                    let shifted = |sign: f64| {
                        let mut p = q.clone();
                        p[k] += sign * step;
                        cat.bend_cosine(&p).0
                    };
                    let fd = (shifted(1.0) - shifted(-1.0)) / (2.0 * step);
                    assert!((g[k] - fd).abs() < 1e-9, "{joint}: ∂/∂q{k} {} against {fd}", g[k]);
                }
            }
        }
    }
}
