//! The circulation a problem's schedule runs with, resolved once, and the problem resolved
//! around it.
//!
//! A problem file asks for the paper's circulation `π/C`, a given angle, or the calibrated one
//! (the root of `twist(D) = ±π` on the exact engine, [`crate::engines::calibrate`]). A
//! calibration that does not converge is an error here ([`CirculationError::Calibration`]):
//! nothing downstream may label its circulation "calibrated".
//!
//! [`Resolved`] is what every command starts from: the problem, its schedule with the resolved
//! circulation, and (computed once, on first use) the calibration of its joint path and the
//! exact evaluation of every library profile on it.

use std::sync::OnceLock;

use rayon::prelude::*;
use std::fmt;

use nalgebra::Vector3;
use serde::Serialize;

use crate::engines::calibrate::{calibrate_spinning, Calibration};
use crate::engines::evaluate::Evaluation;
use crate::model::Cylinder;
use crate::numeric::roots::RootStatus;
use crate::problem::{Circulation, Manoeuvre, Problem, ProfileKind};
use crate::schedule::profile::Profile;
use crate::schedule::{paper_circulation, Schedule, ScheduleError};

/// Why a problem's circulation could not be resolved.
#[derive(Debug, thiserror::Error)]
pub enum CirculationError {
    /// The schedule cannot be built.
    #[error(transparent)]
    Schedule(#[from] ScheduleError),
    /// Calibration found no circulation that turns the cat by π.
    #[error("manoeuvre.circulation = \"calibrated\": no circulation near the paper's {near:.6} rad turns this cat by π (the search ended: {status})")]
    Calibration {
        /// Where the search started, rad.
        near: f64,
        /// How it ended.
        status: RootStatus,
    },
}

/// Where a circulation came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CirculationSource {
    /// The paper's `π/C`.
    Paper,
    /// Calibrated on the exact engine (a converged calibration).
    Calibrated,
    /// Given in the problem file.
    Given,
}

impl fmt::Display for CirculationSource {
    /// The kebab-case name, as in problem files: `paper`, `calibrated`, `given`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CirculationSource::Paper => "paper",
            CirculationSource::Calibrated => "calibrated",
            CirculationSource::Given => "given",
        })
    }
}

/// A circulation and where it came from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ResolvedCirculation {
    /// `∫ω ds`, rad.
    pub radians: f64,
    /// Its source.
    pub source: CirculationSource,
    /// The calibration, when one was run.
    pub calibration: Option<Calibration>,
}

impl ResolvedCirculation {
    /// The circulation of a converged calibration; `None` when it did not converge.
    pub fn from_calibration(calibration: &Calibration) -> Option<ResolvedCirculation> {
        calibration.status.is_converged().then_some(ResolvedCirculation {
            radians: calibration.circulation,
            source: CirculationSource::Calibrated,
            calibration: Some(*calibration),
        })
    }
}

/// Resolves manoeuvre `m`'s circulation for `cat` over a fall of `fall_time` s (running the
/// calibration to `tolerance` rad of twist if asked, for a release with angular momentum `spin`).
pub fn resolve_circulation(
    cat: &Cylinder,
    m: &Manoeuvre,
    fall_time: f64,
    spin: &Vector3<f64>,
    tolerance: f64,
) -> Result<ResolvedCirculation, CirculationError> {
    let paper = || paper_circulation(cat, m.theta());
    Ok(match m.circulation {
        Circulation::Paper => {
            ResolvedCirculation { radians: paper()?, source: CirculationSource::Paper, calibration: None }
        }
        Circulation::Angle(a) => {
            ResolvedCirculation { radians: a, source: CirculationSource::Given, calibration: None }
        }
        Circulation::Calibrated => {
            let near = paper()?;
            let cal = calibrate_spinning(cat, &Schedule::from_manoeuvre(m, fall_time, near), spin, tolerance);
            ResolvedCirculation::from_calibration(&cal)
                .ok_or(CirculationError::Calibration { near, status: cal.status })?
        }
    })
}

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
    calibration: OnceLock<Calibration>,
    library: OnceLock<Vec<(ProfileKind, Schedule, Evaluation)>>,
}

impl Resolved {
    /// Resolves `problem`'s circulation (one calibration when it asks for one) and builds its
    /// schedule.
    pub fn new(problem: &Problem) -> Result<Resolved, CirculationError> {
        let fall_time = problem.drop.fall_time();
        let spin = problem.drop.spin();
        let circulation =
            resolve_circulation(&problem.cat, &problem.manoeuvre, fall_time, &spin, problem.exact.tolerance)?;
        let schedule = Schedule::from_manoeuvre(&problem.manoeuvre, fall_time, circulation.radians);
        let calibration = OnceLock::new();
        if let Some(c) = circulation.calibration {
            let _ = calibration.set(c);
        }
        Ok(Resolved { problem: problem.clone(), schedule, circulation, calibration, library: OnceLock::new() })
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

    /// The cat.
    pub fn cat(&self) -> &Cylinder {
        &self.problem.cat
    }

    /// The calibration of the problem's joint path, started from its circulation: the one
    /// [`Resolved::new`] made for a calibrated problem, else made now (once). Its status may say
    /// it failed; [`Resolved::calibrated`] is the circulation only when it converged.
    pub fn calibration(&self) -> &Calibration {
        self.calibration.get_or_init(|| {
            calibrate_spinning(self.cat(), &self.schedule, &self.problem.drop.spin(), self.problem.exact.tolerance)
        })
    }

    /// The calibrated circulation, when the calibration converged.
    pub fn calibrated(&self) -> Option<ResolvedCirculation> {
        ResolvedCirculation::from_calibration(self.calibration())
    }

    /// The problem's schedule with the library profile `kind` in the twist phase.
    pub fn with_library(&self, kind: ProfileKind) -> Schedule {
        self.schedule.with_profile(Profile::library(kind))
    }

    /// Every library profile's schedule on the problem's path and circulation, evaluated by the
    /// exact engine (once), the paper's cosine first.
    pub fn library(&self) -> &[(ProfileKind, Schedule, Evaluation)] {
        self.library.get_or_init(|| {
            ProfileKind::ALL
                .par_iter()
                .map(|&k| {
                    let s = self.with_library(k);
                    let e = Evaluation::new(
                        self.cat(),
                        &s,
                        &self.problem.drop.spin(),
                        &self.problem.actuator.motors(),
                        &self.problem.exact,
                    );
                    (k, s, e)
                })
                .collect()
        })
    }

    /// The exact evaluation of the problem's own schedule (the library entry of its profile;
    /// `None` only if the library lacked that profile).
    pub fn own(&self) -> Option<&Evaluation> {
        let kind = self.problem.manoeuvre.profile;
        self.library().iter().find(|(k, _, _)| *k == kind).map(|(_, _, e)| e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_calibration_gives_no_calibrated_circulation() {
        let failed = Calibration {
            circulation: 3.0,
            twist: 1.0,
            swing: f64::NAN,
            evaluations: 13,
            status: RootStatus::NoBracket,
        };
        assert!(ResolvedCirculation::from_calibration(&failed).is_none());
        let converged = Calibration { status: RootStatus::Converged, ..failed };
        let c = ResolvedCirculation::from_calibration(&converged);
        assert_eq!(c.map(|c| c.source), Some(CirculationSource::Calibrated));
        assert_eq!(CirculationSource::Calibrated.to_string(), "calibrated");
    }

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
