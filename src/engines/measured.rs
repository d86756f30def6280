//! The measured schedule: the one noun every command reports.
//!
//! A [`Measured`] is a named trajectory ([`ScheduleName`]), the trajectory itself, the exact
//! engine's [`Evaluation`] of it on the problem's cat, release and motors, and, once asked for,
//! rapier's verification of it against those exact numbers ([`RapierOutcome`], DESIGN.md §6). It
//! is made by one function, [`Rig::measure`] (a [`crate::engines::resolved::Resolved`] problem
//! holds its rig), and verified by one, [`Measured::verify`]: `simulate` (with or without
//! `--schedule`), `compare`, `optimize`, `run`, sweeps and `compare-models` measure every
//! schedule this way, and differ only in what they print.
//!
//! A [`Rig`] is what a trajectory is measured on: the problem's cat model, its release spin, its
//! motors, and the exact engine's and rapier's settings.

use nalgebra::Vector3;

use crate::engines::evaluate::Evaluation;
use crate::engines::models::{ModelError, TwoMotorCat};
use crate::engines::rapier::{RapierError, RapierOptions, Reference, Verification};
use crate::engines::rapier_check::{rapier_check, Finest, RapierOutcome};
use crate::model::motor::Motors;
use crate::problem::settings::{ExactSettings, RapierSettings};
use crate::problem::Problem;
use crate::schedule::variant::ScheduleName;
use crate::schedule::Trajectory;

/// What a trajectory is measured on: the cat model, the release, the motors and the engines'
/// settings, as the problem gives them.
#[derive(Clone, Debug, PartialEq)]
pub struct Rig {
    /// The cat model (the paper's cat through the two-cylinder engine).
    pub model: TwoMotorCat,
    /// The release's total angular momentum, world frame, N·m·s (zero: none).
    pub spin: Vector3<f64>,
    /// The joint motors (`[actuator]`; ideal without).
    pub motors: Motors,
    /// The exact engine's settings (`[exact]`).
    pub exact: ExactSettings,
    /// rapier's verification settings (`[rapier]`).
    pub rapier: RapierSettings,
}

impl Rig {
    /// The problem's rig; refused when its cat has not two motors, or has a tail
    /// or legs ([`ModelError::Appendage`]).
    pub fn new(problem: &Problem) -> Result<Rig, ModelError> {
        if let Some((field, _)) = problem.cat.appendage() {
            return Err(ModelError::Appendage(field));
        }
        Ok(Rig {
            model: TwoMotorCat::new(problem.cat.model())?,
            spin: problem.drop.spin(),
            motors: problem.actuator.motors(),
            exact: problem.exact,
            rapier: problem.rapier,
        })
    }

    /// The exact evaluation of `traj` on this rig ([`Evaluation::new`]).
    pub fn evaluate(&self, traj: &impl Trajectory) -> Evaluation {
        Evaluation::new(&self.model, traj, &self.spin, &self.motors, &self.exact)
    }

    /// Measures `trajectory`, named `name`, by the exact engine on this rig, not yet verified.
    pub fn measure<T: Trajectory>(&self, name: ScheduleName, trajectory: T) -> Measured<T> {
        let exact = self.evaluate(&trajectory);
        Measured { name, trajectory, exact, rapier: None }
    }

    /// rapier's options on this rig: its motors and release spin.
    pub fn rapier_options(&self) -> RapierOptions {
        RapierOptions { motors: self.motors, spin: self.spin, ..RapierOptions::default() }
    }
}

/// A named trajectory with its exact measurement and, when verified, rapier's check of it.
#[derive(Clone, Debug)]
pub struct Measured<T> {
    /// Its name in files and tables.
    pub name: ScheduleName,
    /// The trajectory.
    pub trajectory: T,
    /// The exact engine's numbers ([`Evaluation`]).
    pub exact: Evaluation,
    /// rapier's check against them, once verified ([`Measured::verify`]): its numbers from the
    /// finest run with the verification behind them, or the verification alone when rapier made
    /// no usable run.
    pub rapier: Option<RapierOutcome<Finest>>,
}

impl<T: Trajectory> Measured<T> {
    /// What rapier is checked against: the exact twist, swing and peak torque.
    pub fn reference(&self) -> Reference {
        Reference { twist: self.exact.flip.twist, swing: self.exact.flip.swing, peak_torque: self.exact.peak() }
    }

    /// Verifies the trajectory in rapier on `rig` (its cat, release, motors and `[rapier]`
    /// settings), refining the step until rapier's own error estimate meets the settings'
    /// tolerances ([`crate::engines::rapier::verify_with`]), against [`Measured::reference`].
    /// `Err` only when the settings or the trajectory are invalid; a verification without a
    /// usable run is an outcome ([`RapierOutcome::NoResult`]).
    pub fn verify(&mut self, rig: &Rig) -> Result<(), RapierError> {
        let outcome =
            rapier_check(&rig.model, &self.trajectory, &rig.rapier, &self.reference(), &rig.rapier_options())?;
        self.rapier = Some(outcome);
        Ok(())
    }

    /// [`Measured::verify`], by value.
    pub fn verified(mut self, rig: &Rig) -> Result<Measured<T>, RapierError> {
        self.verify(rig)?;
        Ok(self)
    }
}

impl<T> Measured<T> {
    /// rapier's verification, with or without a usable run (none before [`Measured::verify`]).
    pub fn verification(&self) -> Option<&Verification> {
        match self.rapier.as_ref()? {
            RapierOutcome::Report(f) => f.check.verification.as_ref(),
            RapierOutcome::NoResult(v) => Some(v),
        }
    }

    /// rapier's finest run and its check, when the verification made one.
    pub fn finest(&self) -> Option<&Finest> {
        self.rapier.as_ref().and_then(RapierOutcome::report)
    }

    /// The same measurement under another name.
    pub fn named(self, name: ScheduleName) -> Measured<T> {
        Measured { name, ..self }
    }

    /// The same measurement of another representation of the trajectory (e.g. a schedule kept by
    /// reference).
    pub fn map<U>(self, f: impl FnOnce(T) -> U) -> Measured<U> {
        Measured { name: self.name, trajectory: f(self.trajectory), exact: self.exact, rapier: self.rapier }
    }
}
