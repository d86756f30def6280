//! The problem resolved once: what every command starts from.
//!
//! [`Resolved`] holds the problem as loaded, its schedule with the resolved circulation
//! ([`crate::engines::circulation`]), the cat model the exact engine runs
//! ([`TwoMotorCat`]; the paper's cat through the two-cylinder engine), and, computed once on first
//! use, the calibration of its joint path and the exact evaluation of every library profile.

use std::sync::OnceLock;

use rayon::prelude::*;

use crate::engines::calibrate::{calibrate_model, Calibration};
use crate::engines::circulation::{resolve_circulation, CirculationError, ResolvedCirculation};
use crate::engines::evaluate::Evaluation;
use crate::engines::measured::{Measured, Rig};
use crate::engines::models::TwoMotorCat;
use crate::model::Cylinder;
use crate::problem::{Problem, ProfileKind};
use crate::schedule::profile::Profile;
use crate::schedule::variant::ScheduleName;
use crate::schedule::{Schedule, Trajectory};

/// The swing of the spine, degrees, above which a calibrated circulation is warned: it turns the
/// cat by π about its spine, but the spine ends nearer across its start than along it, so the cat
/// does not land on its feet (the paper's flip ends with the swing near zero; a circulation alone
/// cannot set both angles).
pub const LANDING_SWING_DEG: f64 = 45.0;

/// A problem resolved once: its schedule and circulation, its calibration and its library
/// profiles' evaluations, handed to every command.
#[derive(Clone, Debug)]
pub struct Resolved {
    /// The problem as loaded.
    pub problem: Problem,
    /// The problem's own schedule with [`Resolved::circulation`].
    pub schedule: Schedule,
    /// The resolved circulation.
    pub circulation: ResolvedCirculation,
    rig: Rig,
    half: Cylinder,
    calibration: OnceLock<Calibration>,
    own: OnceLock<Measured<Schedule>>,
    library: OnceLock<Vec<(ProfileKind, Measured<Schedule>)>>,
}

impl Resolved {
    /// Resolves `problem`'s circulation (one calibration when it asks for one) and builds its
    /// schedule.
    pub fn new(problem: &Problem) -> Result<Resolved, CirculationError> {
        let fall_time = problem.drop.fall_time();
        let spin = problem.drop.spin();
        let rig = Rig::new(problem)?;
        let circulation =
            resolve_circulation(&rig.model, &problem.manoeuvre, fall_time, &spin, problem.exact.tolerance).map_err(
                |e| match e {
                    CirculationError::PaperUndefined { .. } => CirculationError::PaperUndefined {
                        field: problem.cat.unequal_halves().map_or_else(|| "cat.front".into(), |(f, _)| f),
                    },
                    other => other,
                },
            )?;
        let schedule = Schedule::from_manoeuvre(&problem.manoeuvre, fall_time, circulation.radians);
        let calibration = OnceLock::new();
        if let Some(c) = circulation.calibration {
            let _ = calibration.set(c);
        }
        Ok(Resolved {
            problem: problem.clone(),
            schedule,
            circulation,
            rig,
            half: problem.cat.half(),
            calibration,
            own: OnceLock::new(),
            library: OnceLock::new(),
        })
    }

    /// What is not an error but should be said: a calibrated circulation that turns the cat by
    /// π with its spine swung by more than [`LANDING_SWING_DEG`].
    pub fn warnings(&self) -> Vec<String> {
        let Some(c) = self.circulation.calibration.filter(|c| c.swing.to_degrees().abs() > LANDING_SWING_DEG) else {
            return Vec::new();
        };
        vec![format!(
            "manoeuvre.circulation = \"calibrated\": {:.6} rad turns this cat by π, but its spine ends swung by {:.1}° (more than {LANDING_SWING_DEG}°), so it does not land on its feet (one circulation sets the twist, not the swing; `catflip optimize --whole` flips it with the swing held at 0)",
            c.circulation,
            c.swing.to_degrees()
        )]
    }

    /// The half of the paper's cat (`[cat]`'s shorthand). Only for a computation that models
    /// the paper's cat, after [`Resolved::require_paper_cat`]; any other reads [`Resolved::model`].
    pub fn cat(&self) -> &Cylinder {
        &self.half
    }

    /// The cat model the exact engine runs (the paper's cat through the two-cylinder engine).
    pub fn model(&self) -> &TwoMotorCat {
        &self.rig.model
    }

    /// What every trajectory of this problem is measured on: its cat, release, motors and the
    /// engines' settings.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// Measures `trajectory`, named `name`, on the problem's rig ([`Rig::measure`]).
    pub fn measure<T: Trajectory>(&self, name: ScheduleName, trajectory: T) -> Measured<T> {
        self.rig.measure(name, trajectory)
    }

    /// Refuses a cat other than the paper's for `what` ([`Problem::require_paper_cat`]).
    pub fn require_paper_cat(&self, what: &str) -> Result<(), crate::problem::ProblemError> {
        self.problem.require_paper_cat(what)
    }

    /// The exact evaluation of `traj` on the problem's cat, release and motors (what
    /// [`Resolved::measure`] holds).
    pub fn evaluate(&self, traj: &impl Trajectory) -> Evaluation {
        self.rig.evaluate(traj)
    }

    /// The calibration of the problem's joint path, started from its circulation: the one
    /// [`Resolved::new`] made for a calibrated problem, else made now (once). Its status may say
    /// it failed; [`Resolved::calibrated`] is the circulation only when it converged.
    pub fn calibration(&self) -> &Calibration {
        self.calibration.get_or_init(|| {
            let spin = self.problem.drop.spin();
            calibrate_model(&self.rig.model, &self.schedule, &spin, self.problem.exact.tolerance)
        })
    }

    /// The calibrated circulation, when the calibration converged.
    pub fn calibrated(&self) -> Option<ResolvedCirculation> {
        ResolvedCirculation::from_calibration(self.calibration())
    }

    /// The calibrated circulation when the problem's own schedule does not already turn the cat
    /// by π (to the exact engine's tolerance, the calibration's): what a schedule's
    /// `…-calibrated` variant changes. None when the calibration failed, or when the schedule's
    /// circulation already is the calibrated one (`manoeuvre.circulation = "calibrated"`, or
    /// Kane and Scher's cat on π/C), whose variants would repeat the schedules themselves.
    pub fn recalibration(&self) -> Option<ResolvedCirculation> {
        let off = (self.own().exact.flip.twist.abs() - std::f64::consts::PI).abs();
        self.calibrated().filter(|_| off > self.problem.exact.tolerance)
    }

    /// The problem's schedule with the library profile `kind` in the twist phase.
    pub fn with_library(&self, kind: ProfileKind) -> Schedule {
        self.schedule.with_profile(Profile::library(kind))
    }

    /// Every library profile's schedule on the problem's path and circulation, measured by the
    /// exact engine (once; the problem's own profile is [`Resolved::own`]), the paper's cosine
    /// first.
    pub fn library(&self) -> &[(ProfileKind, Measured<Schedule>)] {
        self.library.get_or_init(|| {
            let own = self.problem.manoeuvre.profile;
            ProfileKind::ALL
                .par_iter()
                .map(|&k| match k == own {
                    true => (k, self.own().clone()),
                    false => (k, self.measure(ScheduleName::library(k), self.with_library(k))),
                })
                .collect()
        })
    }

    /// The best library profile: the least exact twist-phase peak torque, the first of equals in
    /// library order. The library profiles share the bend and the unbend and differ in the twist
    /// phase only, so it also has the least peak over the whole manoeuvre (where the bend or the
    /// unbend dominates, every profile ties there and the twist phase decides).
    pub fn best_library(&self) -> Option<(ProfileKind, &Measured<Schedule>)> {
        let twist = |m: &Measured<Schedule>| m.exact.phase_peaks().phase_max(crate::schedule::Phase::Twist);
        self.library().iter().min_by(|a, b| twist(&a.1).total_cmp(&twist(&b.1))).map(|(k, m)| (*k, m))
    }

    /// The measurement of the problem's own schedule, named by its library profile (made once,
    /// alone: a command that needs only it does not measure the whole library).
    pub fn own(&self) -> &Measured<Schedule> {
        self.own.get_or_init(|| {
            let kind = self.problem.manoeuvre.profile;
            self.measure(ScheduleName::library(kind), self.schedule.clone())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engines::circulation::CirculationSource;
    use crate::problem::Circulation;

    #[test]
    fn a_calibrated_problem_is_resolved_with_one_converged_calibration() {
        let mut p = Problem::default();
        p.manoeuvre.circulation = Circulation::Calibrated;
        let r = Resolved::new(&p).expect("the default cat calibrates");
        assert_eq!(r.circulation.source, CirculationSource::Calibrated);
        // The calibration asked for later is the one made while resolving, not a second one.
        assert_eq!(Some(*r.calibration()), r.circulation.calibration);
        assert_eq!(r.schedule.circulation.to_bits(), r.circulation.radians.to_bits());
    }
}
