//! Work-precision curves of the optimisers and of the calibration.
//!
//! - `qp`: the profile QP (rest-to-rest, no limits, no smoothing) over `N = 10…5120` nodes
//!   (doubling, even), the paper's twist phase; error = relative gap of the solved peak torque
//!   to the discrete problem's closed-form optimum `4(N−1)²/(N(N−2)) · I*|D|/T²`
//!   ([`ProfileQp::closed_form_peak`]): the solver's accuracy; secondary = the closed form's
//!   own gap to the continuous optimum `4 I*|D|/T²`, `1/(N(N−2))`: the discretisation's.
//! - `calibration`: [`calibrate`] at twist tolerances 1e-2…1e-11 rad; error = `|D − D_ref|`
//!   (rad) against the calibration at 1e-12 rad; secondary = `|twist − π|`.
//!
//! A new optimiser gets its curve the same way: one function that computes the reference once
//! and returns [`Curve::sweep`] over its resolution setting with a closure that solves at one
//! setting and returns the gap (or the solver's status as `Err`).

use std::f64::consts::PI;

use crate::engines::calibrate::calibrate;
use crate::model::Cylinder;
use crate::optimize::qp::ProfileQp;
use crate::problem::settings::Boundary;
use crate::report::bench::curve::{Curve, Outcome};
use crate::schedule::{Phase, Schedule};

/// The profile QP of the paper's torque model on the twist phase of `schedule` with `nodes`
/// nodes: rest-to-rest, no limits, no smoothing, so that it has a closed form.
pub fn twist_qp(cat: &Cylinder, schedule: &Schedule, nodes: usize) -> ProfileQp {
    ProfileQp {
        nodes,
        duration: schedule.durations[Phase::Twist.index()],
        circulation: schedule.circulation,
        inertia: cat.end_transverse(),
        boundary: Boundary::RestToRest,
        rate_limit: None,
        jerk_limit: None,
        smoothness: 0.0,
    }
}

/// The profile QP's curve on the twist phase of `schedule`, over node counts `nodes`.
pub fn qp_curve(cat: &Cylinder, schedule: &Schedule, nodes: &[usize]) -> Curve {
    let settings: Vec<f64> = nodes.iter().map(|&n| n as f64).collect();
    Curve::sweep("qp", "nodes N", "peak torque gap to the closed form (rel.)", &settings, |n| {
        let qp = twist_qp(cat, schedule, n as usize);
        let exact = qp.closed_form_peak().ok_or("no closed form for this QP")?;
        let solution = qp.solve().map_err(|e| e.to_string())?;
        let Some(peak) = solution.peak_torque.filter(|_| solution.status.is_solved()) else {
            return Err(format!("Clarabel ended {}", solution.status));
        };
        let continuous = 4.0 * qp.torque_scale();
        Ok(Outcome { error: (peak - exact).abs() / exact, secondary: Some((exact - continuous) / continuous) })
    })
    .with_secondary("closed form's gap to 4 I*|D|/T² (rel.)")
}

/// The calibration's curve on `schedule` over twist tolerances `tolerances` (rad).
pub fn calibration_curve(cat: &Cylinder, schedule: &Schedule, tolerances: &[f64]) -> Curve {
    let reference = calibrate(cat, schedule, 1e-12);
    Curve::sweep("calibration", "twist tolerance (rad)", "circulation error |D − D_ref| (rad)", tolerances, |tol| {
        if !reference.status.is_converged() {
            return Err(format!("the 1e-12 rad reference calibration ended {}", reference.status.name()));
        }
        let c = calibrate(cat, schedule, tol);
        if !c.status.is_converged() {
            return Err(format!("calibration ended {}", c.status.name()));
        }
        Ok(Outcome {
            error: (c.circulation - reference.circulation).abs(),
            secondary: Some((c.twist.abs() - PI).abs()),
        })
    })
    .with_secondary("twist error |twist| − π (rad)")
}
