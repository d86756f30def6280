//! A schedule made elsewhere, measured: `catflip simulate PROBLEM --schedule FILE.csv`.
//!
//! Before the engine runs, [`crate::exchange::checks::check`] refuses what cannot be evaluated
//! with this problem and warns of what looks wrong (units, duration, ends, rates against angles).
//! The trajectory is then measured as every schedule is ([`crate::engines::measured::Rig::measure`]:
//! flip, peaks per piece on the trajectory's own time scale and at every row from both sides,
//! rate jumps beyond the interpolation's own uncertainty, momentum, motor demand); a number
//! that came out NaN or infinite refuses the whole measurement ([`ImportError::NotComputable`])
//! rather than print it. The rows' spacing is judged by measuring a coarser copy the same way
//! ([`crate::exchange::checks::sampling`]).

use serde::Serialize;

use crate::engines::measured::{Measured, Rig};
use crate::engines::rapier::RapierError;
use crate::exchange::checks::{check, sampling};
use crate::exchange::import::{ImportError, ImportedSchedule};
use crate::problem::Problem;
use crate::schedule::variant::ScheduleName;
use crate::schedule::Trajectory;

/// A piece boundary whose rate jump could not be judged: the spline's rates at the two sides
/// are too uncertain (a piece of fewer than seven rows).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UncheckedBoundary {
    /// Time from the schedule's start, s.
    pub time: f64,
    /// The two rows of the repeated time.
    pub lines: [u64; 2],
}

/// An imported schedule measured, with what looks wrong in it.
#[derive(Clone, Debug)]
pub struct MeasuredImport {
    /// The schedule, named by its file, with its exact measurement (and, once verified,
    /// rapier's).
    pub measured: Measured<ImportedSchedule>,
    /// The rig it was measured on (the problem's cat, release, motors and settings).
    pub rig: Rig,
    /// Piece boundaries where whether the rates jump could not be checked.
    pub unchecked: Vec<UncheckedBoundary>,
    /// What looks wrong in the file (units, duration, ends, rates, sampling), in the user's words
    /// with the line or the column; empty when nothing does.
    pub warnings: Vec<String>,
}

impl MeasuredImport {
    /// Verifies the schedule in rapier on its rig ([`Measured::verify`]).
    pub fn verify(&mut self) -> Result<(), RapierError> {
        self.measured.verify(&self.rig)
    }
}

/// Measures `schedule` on `problem`'s cat, release and motors (module docs); refused when the
/// file cannot be evaluated with this problem or a number cannot be computed.
pub fn measure_import(problem: &Problem, schedule: ImportedSchedule) -> Result<MeasuredImport, ImportError> {
    let rig = Rig::new(problem)?;
    let mut warnings = check(problem, &rig.model, &schedule)?;
    let measured = rig.measure(ScheduleName::File(schedule.path.clone()), schedule);
    let (schedule, e) = (&measured.trajectory, &measured.exact);
    let not_computable =
        |quantity: &str| ImportError::NotComputable { path: schedule.path.clone(), quantity: quantity.into() };
    let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
    if !finite(&[e.flip.twist, e.flip.swing]) {
        return Err(not_computable("the twist and swing"));
    }
    if !e.flip.error_estimate.is_finite() {
        return Err(not_computable("the twist's error estimate"));
    }
    if !e.peaks.per_piece.iter().all(|p| finite(&[p[0].value, p[1].value])) || !e.peaks.max.is_finite() {
        return Err(not_computable("the peak torque"));
    }
    if !e.jumps.iter().all(|j| finite(&j.impulse) && finite(&j.rates_before) && finite(&j.rates_after)) {
        return Err(not_computable("the rate jumps' impulses"));
    }
    if !e.momentum_max.is_finite() {
        return Err(not_computable("the angular momentum"));
    }
    let unchecked = (0..schedule.pieces.len().saturating_sub(1))
        .filter(|&k| !schedule.boundary_rate_uncertainty(k).is_finite())
        .map(|k| UncheckedBoundary {
            time: schedule.piece_durations()[..=k].iter().sum(),
            lines: [schedule.pieces[k].lines.1, schedule.pieces[k + 1].lines.0],
        })
        .collect::<Vec<_>>();
    if !unchecked.is_empty() {
        let lines: Vec<String> = unchecked.iter().map(|u| format!("{}–{}", u.lines[0], u.lines[1])).collect();
        warnings.push(format!(
            "lines {}: whether the rates jump there could not be checked: a piece of fewer than 7 rows is too short for the spline's rates at its ends; give q̇ (columns qd1, qd2) or more rows",
            lines.join(", ")
        ));
    }
    let per_piece: Vec<[f64; 2]> = e.peaks.per_piece.iter().map(|p| [p[0].value, p[1].value]).collect();
    warnings.extend(sampling(schedule, &per_piece, |coarse| rig.evaluate(coarse).peaks));
    Ok(MeasuredImport { measured, rig, unchecked, warnings })
}
