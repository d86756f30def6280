//! Calibration: the circulation for which the exact engine turns the cat by exactly π.
//!
//! The twist is a smooth function of the circulation `D`; the root of `twist(D) − ±π` (the sign
//! of the twist the paper's circulation produces) is bracketed from the paper's `π/C` outwards
//! and found by Brent's method. Each evaluation needs only the final orientation
//! ([`crate::engines::exact::flip`]): no torques, no history. The swing at the solution is reported, not
//! driven to zero (one circulation cannot fix two angles). Released with spin, the twist is the
//! spinning motion's ([`calibrate_spinning`]).

use std::f64::consts::PI;

use nalgebra::Vector3;
use serde::Serialize;

use crate::engines::exact::{flip_spinning, Flip};
use crate::engines::models::{flip_on, TwoMotorCat};
use crate::engines::shape::Held;
use crate::model::tree::Tree;
use crate::model::Cylinder;
use crate::numeric::roots::{brent, Brackets, RootStatus};
use crate::schedule::Schedule;

/// The outcome of a calibration.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Calibration {
    /// The circulation found, rad.
    pub circulation: f64,
    /// The twist there, rad (±π when converged).
    pub twist: f64,
    /// The swing there, rad.
    pub swing: f64,
    /// Exact-engine evaluations used.
    pub evaluations: usize,
    /// How the root search ended.
    pub status: RootStatus,
}

/// Finds the circulation near `schedule.circulation` that makes the twist ±π, to `tolerance` rad
/// in twist. The brackets are tried nearest first ([`Brackets`]): where the twist jumps (the
/// swing passing through π, where the twist is not defined), the sign change on that side is
/// not a root, and the other side's is tried.
pub fn calibrate(cat: &Cylinder, schedule: &Schedule, tolerance: f64) -> Calibration {
    calibrate_spinning(cat, schedule, &Vector3::zeros(), tolerance)
}

/// [`calibrate`] for a release with total angular momentum `spin` (N·m·s, world frame;
/// [`crate::engines::exact::flip_spinning`]).
pub fn calibrate_spinning(cat: &Cylinder, schedule: &Schedule, spin: &Vector3<f64>, tolerance: f64) -> Calibration {
    calibrate_by(|s, inner| flip_spinning(cat, s, spin, inner), schedule, tolerance)
}

/// [`calibrate_spinning`] for any two-motor model: the paper's cat by the two-cylinder engine
/// (the same numbers), any other through the general core ([`TwoMotorCat::flip_released`]).
pub fn calibrate_model(cat: &TwoMotorCat, schedule: &Schedule, spin: &Vector3<f64>, tolerance: f64) -> Calibration {
    if let Some(half) = cat.cat().paper() {
        return calibrate_spinning(half, schedule, spin, tolerance);
    }
    calibrate_by(|s, inner| cat.flip_released(s, spin, inner), schedule, tolerance)
}

/// [`calibrate_spinning`] for a cat of more bodies (`tree`: a cat with a tail or legs) driven by a
/// schedule of its two joint coordinates with the further ones held at zero ([`Held`]: the tail
/// straight behind the cat, the legs standing out), through the general core on the whole tree:
/// held still, the appendages are parts of their halves and move the flip.
pub fn calibrate_held(tree: &Tree, schedule: &Schedule, spin: &Vector3<f64>, tolerance: f64) -> Calibration {
    let held = tree.dof().saturating_sub(2);
    calibrate_by(|s, inner| flip_on(tree, &Held(s, held), spin, inner), schedule, tolerance)
}

/// The calibration with `flip(schedule, tolerance)` the engine's final orientation.
fn calibrate_by(flip: impl Fn(&Schedule, f64) -> Flip, schedule: &Schedule, tolerance: f64) -> Calibration {
    let inner = 0.1 * tolerance;
    let d0 = schedule.circulation;
    let flip = |s: &Schedule| flip(s, inner);
    let first = flip(schedule).twist;
    let target = if first < 0.0 { -PI } else { PI };
    let mut evaluations = 1;
    let mut f = |d: f64| flip(&schedule.with_circulation(d)).twist - target;
    let f0 = first - target;
    let step = 0.05 * d0.abs().max(0.1);
    let mut brackets = Brackets::new(d0, f0, step, 12);
    let mut failed: Option<Calibration> = None;
    while let Some((lo, hi)) = brackets.next(&mut f, &mut evaluations) {
        // The twist changes by O(1) per radian of circulation, so a circulation accurate to
        // `tolerance · 1e-2` rad leaves a twist error well below `tolerance` (checked below).
        let root = brent(&mut f, lo, hi, 1e-2 * tolerance, 100);
        evaluations += root.evaluations;
        let at = flip(&schedule.with_circulation(root.x));
        evaluations += 1;
        // A root is only a root if the engine met its tolerance there and the twist is ±π.
        let status =
            if root.status == RootStatus::Converged && !(at.converged && (at.twist - target).abs() <= tolerance) {
                RootStatus::NotAtRoot
            } else {
                root.status
            };
        let found = Calibration { circulation: root.x, twist: at.twist, swing: at.swing, evaluations, status };
        if status.is_converged() {
            return found;
        }
        failed.get_or_insert(found);
    }
    match failed {
        // The first bracket's outcome, with every evaluation counted.
        Some(first_failure) => Calibration { evaluations, ..first_failure },
        None => {
            Calibration { circulation: d0, twist: first, swing: f64::NAN, evaluations, status: RootStatus::NoBracket }
        }
    }
}
