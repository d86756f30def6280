//! Work-precision curves of the optimisers and of the calibration.
//!
//! - `qp`: the profile QP (rest-to-rest, no limits, no smoothing) over `N = 10…5120` nodes
//!   (doubling, even), the paper's twist phase; error = relative gap of the solved peak torque
//!   to the discrete problem's closed-form optimum `4(N−1)²/(N(N−2)) · I*|D|/T²`
//!   ([`ProfileQp::closed_form_peak`]): the solver's accuracy; secondary = the closed form's
//!   own gap to the continuous optimum `4 I*|D|/T²`, `1/(N(N−2))`: the discretisation's.
//! - `calibration`: [`calibrate`] at twist tolerances 1e-2…1e-11 rad; error = `|D − D_ref|`
//!   (rad) against the calibration at 1e-12 rad; secondary = `|twist − π|`.
//! - `retime`: the certified convex retiming ([`retime_schedule`], phases' durations kept) of the
//!   problem's schedule over grid sizes `N = 25…1600` intervals per phase; error = relative gap
//!   of the retimed trajectory's *exact* peak torque (re-measured by the exact engine, 16 samples
//!   per interval, not timed) to the converged bound `P_∞`; secondary = the certified duality
//!   gap of each solve, `(primal − dual)/dual`. `P_∞` is the Richardson limit of Clarabel's
//!   certified bounds on two grids `N₂ = r N₁` (in the report the sweep's two finest, 800 and
//!   1600, solved once more for the reference): `P_∞ = (r b(N₂) − b(N₁))/(r − 1)`. The discrete
//!   program's optimum converges at first order in `1/N` (piecewise constant `s̈` cannot hold
//!   the torque at the bound across an interval; [`crate::optimize::retime`]). On the calibrated
//!   schedule the limits from (800, 1600) and from (1600, 3200) differ by 3e-5 (relative); on the
//!   paper's schedule `N = 3200` ends without a solution (Clarabel: insufficient progress) and
//!   `N = 800` ends "almost solved" (`cargo run --release --example retime_paper 800 1600 3200`),
//!   so the reference is good to about 1e-5, not to the duality gap. The finest bound alone
//!   still carries its `O(1/N)` term (5e-4 at 1600): as large as the gap it would be the
//!   reference for, so the curve would flatten onto its own reference and end in a zero.
//! - `whole`: the whole-manoeuvre optimiser ([`optimize_whole`], the problem's
//!   `[optimize.whole]` with every start) over control points per joint `20…160`; error =
//!   relative gap of the peak torque reached to that of a finer run (240 control points,
//!   computed once); secondary = the constraint violation, the angle between the landed
//!   orientation and `R_z(π)` from an exact re-measurement of the optimum's flip (rad, not
//!   timed). The finer run is a reference *inside* the method: the peak falls as the spline
//!   space grows (0.379, 0.335, 0.325, 0.320, 0.318, 0.317, 0.316 N·m at 20…240 points on the
//!   paper's problem), with no clean order to extrapolate by, so the gap to the finer run
//!   understates the gap to the continuous optimum by the finer run's own (≈ 0.2 %: it lies
//!   0.17 % above the outside reference, IPOPT's collocation optimum [`IPOPT_PEAK_NM`], which
//!   the report quotes beside it).
//!
//! A new optimiser gets its curve the same way: one function that computes the reference once
//! and returns [`Curve::sweep`] over its resolution setting with a closure that solves at one
//! setting and returns the gap (or the solver's status as `Err`).

use std::f64::consts::PI;

use crate::engines::calibrate::calibrate;
use crate::engines::exact::flip;
use crate::engines::torque::peak_torques;
use crate::measure::bench::curve::{Curve, CurveNote, Outcome};
use crate::model::Cylinder;
use crate::optimize::qp::ProfileQp;
use crate::optimize::retime::{retime_schedule, PhasePath, RetimeSettings, Retiming};
use crate::optimize::whole::{flipped, optimize_whole, WholeOutcome, WholeSettings};
use crate::problem::settings::Boundary;
use crate::problem::Problem;
use crate::schedule::{Phase, Schedule};

/// The whole manoeuvre's least peak torque on the paper's problem found by an independent IPOPT
/// collocation (issue 13; README), N·m: the outside reference of the `whole` curve.
pub const IPOPT_PEAK_NM: f64 = 0.3159;

/// Exact re-measurement of a retimed trajectory: torque samples per grid interval (its `s̈`
/// jumps at every node, so the samples follow the grid).
pub const RETIME_SAMPLES_PER_INTERVAL: usize = 16;

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

/// The retiming program at `intervals` per phase, the rest at its defaults (phases kept).
fn retime_settings(intervals: usize) -> RetimeSettings {
    RetimeSettings { intervals, ..RetimeSettings::default() }
}

/// Clarabel's certified lower bound of the retiming of `schedule` on `intervals` per phase, N·m.
fn retime_bound(cat: &Cylinder, schedule: &Schedule, intervals: usize) -> Result<f64, String> {
    let r = retime_schedule(cat, schedule, retime_settings(intervals)).map_err(|e| e.to_string())?;
    if !r.solution.status.is_solved() {
        return Err(format!("the retiming at N = {intervals} ended {}", r.solution.status));
    }
    Ok(r.solution.lower_bound)
}

/// The certified retiming's curve on `schedule` over grid sizes `intervals` (per phase), against
/// the Richardson limit of the bounds on the two grids `reference` (module docs); with the
/// report's note on the reference.
pub fn retime_curve(
    cat: &Cylinder,
    schedule: &Schedule,
    intervals: &[usize],
    reference: [usize; 2],
) -> (Curve, CurveNote) {
    let [n1, n2] = reference;
    let limit = retime_bound(cat, schedule, n1).and_then(|b1| {
        let b2 = retime_bound(cat, schedule, n2)?;
        let r = n2 as f64 / n1 as f64;
        Ok(((r * b2 - b1) / (r - 1.0), b1, b2))
    });
    let settings: Vec<f64> = intervals.iter().map(|&n| n as f64).collect();
    let curve = Curve::sweep_with(
        "retime",
        "grid intervals per phase N",
        "exact peak's gap to the converged bound (rel.)",
        &settings,
        |n| retime_schedule(cat, schedule, retime_settings(n as usize)).map_err(|e| e.to_string()),
        |n, r: &Retiming<PhasePath>| {
            let (limit, ..) = limit.clone()?;
            let Some(traj) = r.trajectory.as_ref() else {
                return Err(format!("Clarabel ended {}", r.solution.status));
            };
            let exact = peak_torques(cat, traj, RETIME_SAMPLES_PER_INTERVAL * n as usize).max;
            let sol = &r.solution;
            Ok(Outcome { error: (exact - limit).abs() / limit, secondary: Some(sol.gap / sol.lower_bound) })
        },
    )
    .with_secondary("certified duality gap (rel.)");
    let note = match limit {
        Ok((limit, b1, b2)) => format!(
            "Error: how far the exact engine's peak torque of the retimed trajectory (phases' durations kept) lies from the converged bound `P_∞ = {limit:.6}` N·m, the first-order Richardson limit of Clarabel's certified bounds {b1:.6} N·m (N = {n1}) and {b2:.6} N·m (N = {n2}); the program converges at first order in `1/N`, so the observed order should approach 1. Secondary: each solve's certified duality gap, `(primal − dual)/dual`. Time: sampling the path, the SOCP and the reconstruction (the re-measurement is not timed)."
        ),
        Err(why) => format!("No converged bound: {why}."),
    };
    (curve, CurveNote { curve: "retime".into(), note })
}

/// `settings` with `control_points` per joint (a coarse start no larger than the spline).
fn whole_settings(settings: &WholeSettings, control_points: usize) -> WholeSettings {
    WholeSettings {
        control_points,
        coarse_control_points: settings.coarse_control_points.map(|c| c.min(control_points)),
        ..settings.clone()
    }
}

/// Runs the whole-manoeuvre optimiser of `problem` at `control_points`.
fn whole_at(problem: &Problem, control_points: usize) -> Result<WholeOutcome, String> {
    let settings = whole_settings(&problem.optimize.whole, control_points);
    optimize_whole(
        problem.cat.half(),
        problem.drop.fall_time(),
        &problem.manoeuvre,
        &settings,
        &problem.actuator.motors(),
        problem.exact.tolerance,
    )
    .map_err(|e| e.to_string())
}

/// The best start's peak torque on `problem`, N·m, or why there is none.
fn whole_peak(outcome: &WholeOutcome, problem: &Problem) -> Result<f64, String> {
    outcome
        .best()
        .map(|b| b.peak_torque_nm)
        .ok_or_else(|| outcome.no_optimum(&problem.optimize.whole, problem.exact.tolerance))
}

/// The whole-manoeuvre optimiser's curve on `problem` over control points per joint
/// `control_points`, against the peak of a run at `reference_points` (module docs); with the
/// report's note on the references.
pub fn whole_curve(problem: &Problem, control_points: &[usize], reference_points: usize) -> (Curve, CurveNote) {
    let reference = whole_at(problem, reference_points).and_then(|o| whole_peak(&o, problem));
    let settings: Vec<f64> = control_points.iter().map(|&n| n as f64).collect();
    let curve = Curve::sweep_with(
        "whole",
        "control points per joint",
        "peak torque's gap to the finer run (rel.)",
        &settings,
        |n| whole_at(problem, n as usize),
        |_, outcome: &WholeOutcome| {
            let reference = reference.clone().map_err(|why| format!("no reference: {why}"))?;
            let peak = whole_peak(outcome, problem)?;
            let best = outcome.best().ok_or("no best start")?;
            let landed = flip(&problem.cat.half(), &best.spline, problem.exact.tolerance);
            let violation = (flipped().inverse() * landed.orientation).angle();
            Ok(Outcome { error: (peak - reference).abs() / reference, secondary: Some(violation) })
        },
    )
    .with_secondary("constraint violation ‖e‖ (rad)");
    let note = match reference {
        Ok(peak) => format!(
            "Error: the relative gap of the peak motor torque reached to {peak:.5} N·m, the optimum on a finer spline ({reference_points} control points per joint, every start of `[optimize.whole]`); that reference is {:+.2} % from {IPOPT_PEAK_NM} N·m, the least peak an independent IPOPT collocation found on the paper's problem (outside reference; meaningful for `problems/paper.toml` only). Secondary: the constraint violation, the angle between the landed orientation and the half turn `R_z(π)`, re-measured by the exact engine to `exact.tolerance`. Time: every start, as `catflip optimize --whole` runs them.",
            100.0 * (peak / IPOPT_PEAK_NM - 1.0)
        ),
        Err(why) => format!("No reference peak at {reference_points} control points: {why}."),
    };
    (curve, CurveNote { curve: "whole".into(), note })
}
