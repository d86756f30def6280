//! The circulation a problem's schedule runs with, resolved once, and the problem resolved
//! around it.
//!
//! A problem file asks for the paper's circulation `π/C`, a given angle, or the calibrated one
//! (the root of `twist(D) = ±π` on the exact engine, [`crate::engines::calibrate`]). A
//! calibration that does not converge is an error here ([`CirculationError::Calibration`]):
//! nothing downstream may label its circulation "calibrated".
//!
//! [`crate::engines::resolved::Resolved`], what every command starts from, holds the circulation
//! resolved here.

use std::fmt;

use nalgebra::Vector3;
use serde::Serialize;

use crate::engines::calibrate::{calibrate_model, Calibration};
use crate::engines::models::{ModelError, TwoMotorCat};
use crate::numeric::roots::RootStatus;
use crate::problem::{Circulation, Manoeuvre};
use crate::schedule::{paper_circulation, Schedule, ScheduleError};

/// Why a problem's circulation could not be resolved.
#[derive(Debug, thiserror::Error)]
pub enum CirculationError {
    /// The schedule cannot be built.
    #[error(transparent)]
    Schedule(#[from] ScheduleError),
    /// Calibration found no circulation that turns the cat by π.
    #[error("manoeuvre.circulation = \"calibrated\": no circulation near {near:.6} rad (the paper's π/C, of the mean half when the halves differ) turns this cat by π (the search ended: {status})")]
    Calibration {
        /// Where the search started, rad.
        near: f64,
        /// How it ended.
        status: RootStatus,
    },
    /// The calibration starts from the paper's `π/C`, which this cat and bend do not have.
    #[error("manoeuvre.circulation = \"calibrated\": the calibration starts from the paper's π/C (of the mean half when the halves differ), and here there is none: {}; bend more (lower manoeuvre.theta_deg) or give the circulation in radians", cause.detail())]
    NoStart {
        /// Why there is no `π/C`.
        cause: ScheduleError,
    },
    /// The paper's `C` is defined for equal halves only.
    #[error("manoeuvre.circulation = \"paper\": the paper's C (and π/C) is defined for two equal halves only, and {field} makes them differ; give the circulation in radians or set it to \"calibrated\"")]
    PaperUndefined {
        /// The problem field that makes the halves differ.
        field: String,
    },
    /// The cat cannot run the problem's schedule.
    #[error(transparent)]
    Model(#[from] ModelError),
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
/// The paper's `π/C` needs equal halves; the calibration of unequal halves starts from the `π/C`
/// of their mean half ([`crate::model::Cat::mean_half`]).
pub fn resolve_circulation(
    cat: &TwoMotorCat,
    m: &Manoeuvre,
    fall_time: f64,
    spin: &Vector3<f64>,
    tolerance: f64,
) -> Result<ResolvedCirculation, CirculationError> {
    let model = cat.cat();
    let paper = || paper_circulation(&model.mean_half(), m.theta());
    if m.circulation == Circulation::Paper && !model.has_equal_halves() {
        return Err(CirculationError::PaperUndefined { field: "cat.front or cat.rear".into() });
    }
    Ok(match m.circulation {
        Circulation::Paper => {
            ResolvedCirculation { radians: paper()?, source: CirculationSource::Paper, calibration: None }
        }
        Circulation::Angle(a) => {
            ResolvedCirculation { radians: a, source: CirculationSource::Given, calibration: None }
        }
        Circulation::Calibrated => {
            let near = paper().map_err(|cause| CirculationError::NoStart { cause })?;
            let cal = calibrate_model(cat, &Schedule::from_manoeuvre(m, fall_time, near), spin, tolerance);
            ResolvedCirculation::from_calibration(&cal)
                .ok_or(CirculationError::Calibration { near, status: cal.status })?
        }
    })
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
}
