//! Whole-manoeuvre path optimisation: both joint trajectories over the whole fall, chosen so that
//! the cat lands turned by exactly π with the least peak motor torque (or effort), by successive
//! convexification with exact derivatives (DESIGN.md §5; issue 13 §2).
//!
//! ## Problem
//! Variables: the control points of two clamped cubic B-splines `q1(t), q2(t)` on `[0, T]`
//! ([`spline`]), the first and last two of each held at zero so that the cat is straight and at
//! rest at both ends (three with `optimize.zero_end_acceleration`). With `R(T)` A's final
//! orientation from the zero-momentum dynamics ([`crate::exact`]):
//!
//! $$ \min_c\; \max_{t,j} |τ_j(t)| \;\text{ or }\; \int_0^T τ·τ\,dt \quad\text{s.t.}\quad
//!    R(T) = R_z(π),\; |c| ≤ q_{max},\; \cos β(t) ≥ \cos β_{max}. $$
//!
//! Twist `±π` with zero swing is the same rotation `R_z(π)`: the constraint is three equations on
//! `e = log(R_z(π)ᵀ R(T))`, and which of `±π` (or `±3π`) the path realises is read off the twist
//! tracker of the final [`crate::engines::exact::flip`], which re-measures every result. The bend
//! `β` is the angle between the spine axes, `cos β = cos q1 cos q2`; `min_angle_deg` bounds the
//! angle between the halves, `π − β`, from below on every torque sample.
//!
//! ## Why cubic B-splines
//! The torques need `q̈`; a cubic's `q̈` is continuous and piecewise linear, so the torque is
//! continuous (no impulse anywhere) and the spline can still switch its torque over one knot
//! span, which a minimum-peak optimum (bang-bang-like, several joints saturating at once) needs.
//! Higher degrees buy smoothness the objective does not ask for and widen every basis function's
//! support (denser Jacobians). Thirty control points (27 spans) make 52 free variables: the
//! optimum's peak changes by well under 1 % between 20 and 40 points (see the report). Each knot
//! span is one piece of the [`Trajectory`](crate::schedule::Trajectory), so the Magnus integrator
//! never steps across a jump of `q⃛`.
//!
//! ## Method
//! Successive convexification (SCvx, [`scvx`]): at each iterate the torques on a dense grid
//! (`samples_per_span` per span, ends included) and the final-orientation error are linearised
//! with exact derivatives ([`sensitivity`]: dual numbers through the engine's formulas, and the
//! forward sensitivity of the sixth-order Magnus integrator itself), the convex subproblem
//! ([`subproblem`]: an LP for the peak, a QP for the energy, with an ℓ1-penalised virtual control on
//! the orientation and an ℓ∞ trust region) is solved by Clarabel, and the step is accepted by the
//! ratio of the exact merit decrease to the predicted one. A final phase of minimum-norm Newton
//! steps drives `|e|` to round-off. With `homotopy` the peak stage starts from the energy
//! optimum of the same start, which is smooth and reached in a few steps. Several starts
//! ([`starts`]); the best converged flip is kept, and every start's outcome is reported.
//!
//! ## References
//! - D. Malyuta et al., *Convex optimization for trajectory generation*, IEEE Control Systems
//!   Magazine 42 (2022) 40–113 (arXiv:2106.09125);
//! - C. de Boor, *A Practical Guide to Splines* (2001);
//! - R. Montgomery, *Gauge theory of the falling cat* (1993).

pub mod dual;
pub mod dynamics;
pub mod measure;
pub mod scvx;
pub mod sensitivity;
pub mod settings;
pub mod solution;
pub mod spline;
pub mod starts;
pub mod subproblem;

use std::f64::consts::PI;
use std::time::Instant;

use nalgebra::{UnitQuaternion, Vector3};
use rayon::prelude::*;

pub use scvx::ScvxProblem;
pub use settings::{Objective, StartKind, WholeError, WholeSettings};
pub use solution::{IterationLog, SkippedStart, WholeOutcome, WholeSolution, WholeStatus};
pub use spline::BSpline;
pub use starts::{build_start, NamedStart};

use crate::model::Cylinder;
use crate::optimize::qp::QpSettings;
use crate::problem::manoeuvre::Manoeuvre;

/// Optimality of the stages that only prepare a start (coarse spline, energy homotopy).
const COARSE_OPTIMALITY: f64 = 1e-5;

/// How far the measured bend may exceed its limit between the samples it is imposed on, degrees.
pub const BEND_SLACK_DEG: f64 = 0.1;

/// The target orientation of a flip: a half turn about A's initial spine axis.
pub fn flipped() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), PI)
}

/// Optimises the whole manoeuvre of `cat` over a fall of `duration` s from the starts named in
/// `settings` (built from `manoeuvre`: its bend, phases and profile), flipping the cat to
/// `tolerance` rad in twist and swing.
pub fn optimize_whole(
    cat: &Cylinder,
    duration: f64,
    manoeuvre: &Manoeuvre,
    settings: &WholeSettings,
    tolerance: f64,
) -> Result<WholeOutcome, WholeError> {
    settings.validate()?;
    settings::positive_input("drop duration", duration)?;
    let built: Vec<_> =
        settings.starts.par_iter().map(|&kind| (kind, build_start(cat, duration, manoeuvre, kind, settings))).collect();
    let mut starts = Vec::new();
    let mut skipped = Vec::new();
    for (kind, start) in built {
        match start {
            Ok(s) => starts.push(s),
            Err(reason) => skipped.push(SkippedStart { start: kind.name().to_string(), reason }),
        }
    }
    let mut outcome = optimize_from(cat, &starts, settings, tolerance)?;
    outcome.skipped = skipped;
    Ok(outcome)
}

/// Optimises from given starts (each a spline of `settings.control_points` cubic control points
/// with the ends fixed as `settings` says).
pub fn optimize_from(
    cat: &Cylinder,
    starts: &[NamedStart],
    settings: &WholeSettings,
    tolerance: f64,
) -> Result<WholeOutcome, WholeError> {
    settings.validate()?;
    settings::positive_input("tolerance", tolerance)?;
    let problem = ScvxProblem { cat, settings, target: Some(flipped()), qp: QpSettings::default() };
    // The starts are independent: solved in parallel, reported in the order given.
    let solutions =
        starts.par_iter().map(|start| optimize_start(&problem, start, tolerance)).collect::<Result<Vec<_>, _>>()?;
    let value = |s: &WholeSolution| match settings.objective {
        Objective::Peak => s.peak_torque_nm,
        Objective::Energy => s.energy,
    };
    let best = (0..solutions.len())
        .filter(|&i| solutions[i].status == WholeStatus::Converged && solutions[i].flips(tolerance))
        .min_by(|&a, &b| value(&solutions[a]).total_cmp(&value(&solutions[b])));
    Ok(WholeOutcome { solutions, best, skipped: Vec::new() })
}

/// Optimises from one start: the stages, the Newton phase, and the exact re-measurement.
pub fn optimize_start(
    problem: &ScvxProblem<'_>,
    start: &NamedStart,
    tolerance: f64,
) -> Result<WholeSolution, WholeError> {
    let clock = Instant::now();
    let s = problem.settings;
    let layout_ok = start.spline.control_points() == s.control_points && start.spline.degree == WholeSettings::DEGREE;
    if !layout_ok {
        return Err(WholeError::BadFieldValue {
            field: "start",
            value: start.name.clone(),
            reason: format!("needs {} cubic control points per joint", s.control_points),
        });
    }
    let mut steps = s.steps_per_span;
    let mut log = Vec::new();
    let (duration, degree, fixed) = (start.spline.duration(), WholeSettings::DEGREE, s.fixed());
    let mut spline = start.spline.clone();
    let quarter = (s.max_iterations / 4).max(1);
    if let Some(n) = s.coarse_control_points.filter(|&n| n < s.control_points) {
        let coarse_settings = WholeSettings { control_points: n, ..s.clone() };
        let coarse = ScvxProblem { settings: &coarse_settings, ..problem.clone() };
        let fitted = coarse.polish(BSpline::fit(duration, n, degree, fixed, |t| spline.state(t).q), steps, 8).0;
        let it = coarse.evaluate(fitted, Objective::Energy, steps);
        let solved = coarse.stage(it, Objective::Energy, COARSE_OPTIMALITY, quarter, steps, &mut log)?.iterate.spline;
        spline = BSpline::fit(duration, s.control_points, degree, fixed, |t| solved.state(t).q);
    }
    spline = problem.polish(spline, steps, 8).0;
    if s.homotopy && s.objective == Objective::Peak {
        let it = problem.evaluate(spline, Objective::Energy, steps);
        let budget = log.len() + quarter;
        spline = problem.stage(it, Objective::Energy, COARSE_OPTIMALITY, budget, steps, &mut log)?.iterate.spline;
    }
    let it = problem.evaluate(spline, s.objective, steps);
    let end = problem.stage(it, s.objective, s.optimality, s.max_iterations, steps, &mut log)?;
    let (mut status, mut reason) = (end.status, end.reason);
    let flip_tolerance = (1e-2 * tolerance).min(1e-10);
    let (mut spline, mut polish_steps) = problem.polish(end.iterate.spline, steps, 8);
    if problem.target.is_some() {
        loop {
            let f = crate::engines::exact::flip(problem.cat, &spline, flip_tolerance);
            let good = ((f.twist.abs() - PI).abs() <= 0.1 * tolerance && f.swing <= 0.1 * tolerance) || steps >= 1024;
            if good {
                break;
            }
            steps *= 2;
            let (next, k) = problem.polish(spline, steps, 8);
            spline = next;
            polish_steps += k;
        }
    }
    let m = measure::measure(problem.cat, &spline, flip_tolerance);
    let flips = m.twist_error <= tolerance && m.flip.swing <= tolerance;
    if problem.target.is_some() && !flips {
        if status == WholeStatus::Converged {
            status = WholeStatus::Infeasible;
        }
        reason = format!(
            "{reason}; the exact engine measures |twist| − π = {:.3e} rad, swing {:.3e} rad",
            m.twist_error, m.flip.swing
        );
    }
    if let Some(limit) = s.min_angle_deg {
        let excess = m.max_bend.to_degrees() - (180.0 - limit);
        if excess > BEND_SLACK_DEG {
            if status == WholeStatus::Converged {
                status = WholeStatus::Infeasible;
            }
            reason = format!("{reason}; the bend exceeds its limit by {excess:.3}° between samples");
        }
    }
    Ok(WholeSolution {
        start: start.name.clone(),
        status,
        reason,
        twist: m.flip.twist,
        swing: m.flip.swing,
        twist_error: m.twist_error,
        flip_error_estimate: m.flip.error_estimate,
        peak_torque_nm: m.peak,
        peak_time: m.peak_time,
        energy: m.energy,
        max_bend_deg: m.max_bend.to_degrees(),
        bend_turns: m.bend_turns,
        iterations: log.len(),
        polish_steps,
        seconds: clock.elapsed().as_secs_f64(),
        log,
        spline,
    })
}
