//! The certified convex retiming of a schedule along its fixed joint path
//! ([`crate::optimize::retime`]), both ways: the phases' durations kept, and the split free.
//! It runs on every two-motor cat (the problem's model, [`Resolved::model`]: its torques along the
//! path, [`crate::engines::torque::ZeroMomentumTorques`]). Each solved retiming's trajectory is
//! measured as every schedule is ([`crate::engines::measured::Rig::measure`]).

use rayon::prelude::*;
use serde::Serialize;

use crate::engines::resolved::Resolved;
use crate::optimize::retime::{retime_schedule, RetimeSettings, Split};
use crate::schedule::variant::ScheduleName;
use crate::schedule::Schedule;

/// The certified convex retiming of one schedule along its fixed joint path.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RetimeRow {
    /// Which schedule was retimed (the problem's circulation, or the calibrated one).
    pub schedule: String,
    /// Whether the phase durations were kept or the split was free.
    pub split: String,
    /// The solver's status.
    pub status: String,
    /// The program's primal peak, N·m (absent when not solved).
    pub peak_nm: Option<f64>,
    /// Clarabel's dual objective: a certified lower bound on the discrete program's optimum, N·m.
    pub lower_bound_nm: Option<f64>,
    /// Duality gap, N·m.
    pub gap_nm: Option<f64>,
    /// The exact engine's peak of the retimed trajectory, N·m.
    pub exact_peak_nm: Option<f64>,
    /// Its twist, degrees (the path's: timing does not change it).
    pub twist_deg: Option<f64>,
    /// Its swing, degrees.
    pub swing_deg: Option<f64>,
    /// Solve time, s.
    pub solve_time_s: f64,
}

/// Retimes `schedule` (named `name`) with both splits.
pub fn retime_rows(r: &Resolved, name: &ScheduleName, schedule: &Schedule) -> Vec<RetimeRow> {
    [Split::Kept, Split::Free]
        .into_par_iter()
        .map(|split| {
            let settings = RetimeSettings { split, ..RetimeSettings::default() };
            let label = match split {
                Split::Kept => "phases kept",
                Split::Free => "split free",
            };
            let row = |status: String| RetimeRow {
                schedule: name.to_string(),
                split: label.to_string(),
                status,
                peak_nm: None,
                lower_bound_nm: None,
                gap_nm: None,
                exact_peak_nm: None,
                twist_deg: None,
                swing_deg: None,
                solve_time_s: 0.0,
            };
            match retime_schedule(r.model(), schedule, settings) {
                Err(e) => row(format!("refused: {e}")),
                Ok(t) => {
                    let sol = &t.solution;
                    let solved = sol.status.is_solved();
                    // The timed trajectory measured as every schedule is.
                    let again = t
                        .trajectory
                        .clone()
                        .filter(|_| solved)
                        .map(|traj| r.measure(ScheduleName::Retimed(Box::new(name.clone())), traj).exact);
                    RetimeRow {
                        status: sol.status.to_string(),
                        peak_nm: solved.then_some(sol.peak),
                        lower_bound_nm: solved.then_some(sol.lower_bound),
                        gap_nm: solved.then_some(sol.gap),
                        exact_peak_nm: again.as_ref().map(|m| m.peak()),
                        twist_deg: again.as_ref().map(|m| m.flip.twist.to_degrees()),
                        swing_deg: again.as_ref().map(|m| m.flip.swing.to_degrees()),
                        solve_time_s: sol.solve_time_s,
                        ..row(String::new())
                    }
                }
            }
        })
        .collect()
}
