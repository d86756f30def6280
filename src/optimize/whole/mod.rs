//! Whole-manoeuvre path optimisation: both joint trajectories over the whole fall, chosen so that
//! the cat lands turned by exactly π with the least peak motor torque (or effort), by successive
//! convexification with exact derivatives (DESIGN.md §5; issue 13 §2).
//!
//! ## Problem
//! Variables: the control points of one clamped cubic B-spline per joint coordinate, `q1(t), q2(t)`
//! (three on the spherical joint, up to six with a tail and legs) on `[0, T]` ([`spline`]), the first and last two of each
//! held at zero so that the cat is straight and at
//! rest at both ends (three with `optimize.zero_end_acceleration`). With `R(T)` A's final
//! orientation from the zero-momentum dynamics ([`crate::engines::exact`]):
//!
//! $$ \min_c\; \max_{t,j} |τ_j(t)| \;\text{ or }\; \int_0^T τ·τ\,dt \quad\text{s.t.}\quad
//!    R(T) = R_z(π),\; |c| ≤ q_{max},\; \cos β(t) ≥ \cos β_{max}. $$
//!
//! Twist `±π` with zero swing is the same rotation `R_z(π)`: the constraint is three equations on
//! `e = log(R_z(π)ᵀ R(T))`, and which of `±π` (or `±3π`) the path realises is read off the twist
//! tracker of the final [`crate::engines::exact::flip`], which re-measures every result. The bend
//! `β` is the angle between the spine axes, `cos β = cos q1 cos q2` on the universal joint and
//! `cos |q|` on the no-twist joint ([`WholeCat::bend_cosine`]); `min_angle_deg` bounds the
//! angle between the halves, `π − β`, from below on every torque sample.
//!
//! ## Cat models (DESIGN.md §10)
//! The cat is a [`WholeCat`]: the paper's (equal halves on the universal joint) through
//! [`dynamics`] and the two-cylinder engine, unchanged to the last bit, or any other two-motor
//! model (unequal halves, the no-twist joint) through [`model_dynamics`] and the general core
//! [`crate::engines::models::TwoMotorCat`] for the re-measurement and the starts' calibration.
//! A release with spin is planned on every two-motor model through the same seam (the spinning
//! dynamics of [`model_dynamics`]). A cat on the spherical joint ([`WholeCat::Spherical`]) and a
//! cat with a tail or legs ([`WholeCat::Appended`], the tree's dynamics of [`tree_dynamics`]) are
//! planned on their three to six coordinates by the same loop (the legs' within their fold,
//! [`WholeCat::control_limits`]), re-measured by the general core on every
//! coordinate ([`torques`]), without spin and with ideal motors or one torque limit on every motor
//! ([`beyond_two_motors`], [`torque_limited`]). On Kane
//! and Scher's symmetric cat (equal halves, no-twist joint) the controls cannot reach the swing's
//! directions of the flip error: the subproblems and the Newton steps work on the reachable ones
//! ([`reach`]).
//!
//! ## Why cubic B-splines
//! The torques need `q̈`; a cubic's `q̈` is continuous and piecewise linear, so the torque is
//! continuous (no impulse anywhere) and the spline can still switch its torque over one knot
//! span, which a minimum-peak optimum (bang-bang-like, several joints saturating at once) needs.
//! Higher degrees buy smoothness the objective does not ask for and widen every basis function's
//! support (denser Jacobians). The default 120 control points (117 spans) make 232 free
//! variables; on these uniform knots the optimum's peak is 0.3183 N·m on the paper's cat, 0.77 %
//! above an independent collocation, converging as `h²` (0.3168 at 200 points, 0.3162 at 300),
//! limited where a torque switches across a span. One round of knot refinement there
//! ([`refine`], `switch_refinements`) brings it to 0.31645 N·m (+0.19 %) on 186 spans, and
//! takes away the spike and dips between saturated arcs ([`measure::Chatter`]). Each knot
//! span is one piece of the [`Trajectory`](crate::schedule::Trajectory), so the Magnus integrator
//! never steps across a jump of `q⃛`.
//!
//! ## Method
//! Successive convexification (SCvx, [`scvx`]): at each iterate the torques on a dense grid
//! (`samples_per_span` per span, ends included) and the final-orientation error are linearised
//! with exact derivatives ([`sensitivity`]: dual numbers through the engine's formulas, and the
//! forward sensitivity of the sixth-order Magnus integrator itself), the convex subproblem
//! ([`subproblem`]: a QP for the peak and for the energy, with an ℓ1-penalised virtual control on
//! the orientation and an ℓ∞ trust region) is solved by Clarabel, and the step is accepted by the
//! ratio of the exact merit decrease to the predicted one. The energy's model also carries a
//! damped-BFGS estimate of the orientation constraint's curvature, the peak's a scalar one of its
//! Lagrangian's ([`curvature`]), and an energy
//! step that did better than predicted is extended along its direction: without them a start
//! could crawl to the iteration limit along a curved, flat valley (a fat cat, r/l = 0.25: 200
//! iterations, now 35). A final phase of minimum-norm Newton
//! steps drives `|e|` to round-off. With `homotopy` the peak stage starts from the energy
//! optimum of the same start, which is smooth and reached in a few steps (the trust region's:
//! the interior-point method's peak stage starts from the start, after the coarse solve). For `peak` and
//! `min-time` the best start (converged, or an upper bound: [`WholeStatus::UpperBound`]) is then
//! refined where its torques switch and solved again from the same curve ([`refine_solution`]).
//! Several starts ([`starts`]); the best such flip is kept, and every start's outcome is
//! reported. With `method = "interior-point"`, and by default (`"auto"`) on a cat of more than
//! two motors, the least-peak stage (ideal motors, no spin, no bend limit) is a primal-dual
//! interior-point method with the torques' exact curvature instead (`interior`), on the same
//! spline and samples; the energy's stages stay the loop's.
//!
//! ## Motor limits (DESIGN.md §9)
//! With `[actuator]` limits ([`crate::model::motor`]) each torque sample gives linearised rows of
//! every limit ([`limits`]). The objective `min-time` minimises the largest stretch squared `k²`
//! over the path's shape (its duration is then the least fall time: the path slowed by `max k`,
//! measured densely, touches its limits exactly). At a fixed fall (`peak`, `energy`) a `min-time`
//! stage that stops as soon as the path fits (`k² ≤ 1`) comes first: if it cannot, no flip fits
//! this fall and the start ends infeasible with the least fall time found; else the objective is
//! minimised with the usage ratios `ρ ≤ 1` as elastic constraints, and the samples' bound is
//! tightened while the dense re-measurement ([`measure`]) finds a limit exceeded between them.
//! Starts are built within the joint limit and the bend limit ([`starts`]). A cat beyond two
//! motors takes one torque limit on every motor only, planned as the least peak and then scaled
//! in time ([`torque_limited`]).
//!
//! ## Release with spin (DESIGN.md §9)
//! With total angular momentum `L ≠ 0` ([`optimize_whole_spinning`]) A's body rate
//! `Ω = I_lock⁻¹(Rᵀ L − h)` depends on `R`: the loop's model is then [`spin`]'s (the exact
//! engine's Runge–Kutta step on the quaternion, differentiated span by span, the attitude at the
//! span starts kept as lifted unknowns of the subproblem so that the torque rows, which depend
//! on every earlier control point through `R(t_k)`, stay sparse). The target is still
//! `R(T) = R_z(π)`; the ±π directions are no longer mirror images, so the starts (one per
//! direction by default) are calibrated under the spin, the mirrored ones under the mirrored
//! spin ([`starts::start_schedule_spinning`]), and every result is re-measured by
//! [`crate::engines::exact::flip_spinning`] with the spinning torques
//! ([`measure::measure_spinning`]). The energy's curvature estimate ([`curvature`]) is left out
//! with spin (it needs dense gradients). Motor limits and `min-time` are refused with spin
//! ([`spin_supported`]). `L = 0` takes the zero-momentum code unchanged.
//!
//! ## References
//! - D. Malyuta et al., *Convex optimization for trajectory generation*, IEEE Control Systems
//!   Magazine 42 (2022) 40–113 (arXiv:2106.09125);
//! - C. de Boor, *A Practical Guide to Splines* (2001);
//! - R. Montgomery, *Gauge theory of the falling cat* (1993).

pub mod cat;
pub mod curvature;
pub mod dual;
pub mod dynamics;
mod interior;
pub mod lift;
pub mod limits;
pub mod measure;
pub mod model_dynamics;
pub mod reach;
pub mod refine;
mod run;
pub mod scope;
pub mod scvx;
pub mod sensitivity;
pub mod settings;
pub mod solution;
pub mod spin;
pub mod spline;
pub mod starts;
pub mod subproblem;
pub mod torque_limited;
pub mod torques;
pub mod tree_dynamics;

use std::f64::consts::PI;
use std::time::Instant;

use nalgebra::{UnitQuaternion, Vector3};
use rayon::prelude::*;

pub use crate::model::motor::{held_to_torque_limit, motors_beyond, MotorsBeyond};
pub use cat::{NamedBody, WholeCat};
pub use scope::{beyond_two_motors, spin_supported};
pub use scvx::ScvxProblem;
pub use settings::{Method, Objective, StartKind, WholeError, WholeSettings};
pub use solution::{IterationLog, SkippedStart, WholeOutcome, WholeSolution, WholeStatus};
pub use spline::BSpline;
pub use starts::{build_start, build_start_spinning, NamedStart};

use crate::engines::motors::{MotorDemand, RATIO_TOLERANCE};
use crate::model::motor::Motors;
use crate::optimize::conic::QpSettings;
use crate::problem::manoeuvre::Manoeuvre;
use run::{FinalStage, Run};

/// Optimality of the stages that only prepare a start (coarse spline, energy homotopy).
const COARSE_OPTIMALITY: f64 = 1e-5;

/// How far the measured bend may exceed its limit between the samples it is imposed on, degrees.
pub const BEND_SLACK_DEG: f64 = 0.1;

/// Relative margin below each motor limit that the samples are held to at a fixed fall: above the
/// stage's feasibility threshold, so that a converged stage is within its limits.
const LIMIT_MARGIN: f64 = 1e-6;

/// The target orientation of a flip: a half turn about A's initial spine axis.
pub fn flipped() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), PI)
}

/// Optimises the whole manoeuvre of `cat`, driven by `motors`, over a fall of `duration` s from
/// the starts named in `settings` (built from `manoeuvre`: its bend, phases and profile),
/// flipping the cat to `tolerance` rad in twist and swing. With the objective `min-time` the
/// result's duration is the least fall time within the motors (`duration` only scales the
/// starts).
pub fn optimize_whole(
    cat: impl Into<WholeCat>,
    duration: f64,
    manoeuvre: &Manoeuvre,
    settings: &WholeSettings,
    motors: &Motors,
    tolerance: f64,
) -> Result<WholeOutcome, WholeError> {
    optimize_whole_spinning(cat, duration, manoeuvre, settings, motors, tolerance, &Vector3::zeros())
}

/// [`optimize_whole`] for a cat released with total angular momentum `spin` (N·m·s, world frame;
/// DESIGN.md §9): the target is still `R(T) = R_z(π)`, the model is [`spin`]'s, the starts are
/// calibrated under the spin ([`build_start_spinning`]) and every result is re-measured by
/// [`crate::engines::exact::flip_spinning`] with the torques of that motion. Zero `spin` is
/// [`optimize_whole`]. Motor limits (and so `min-time`) are refused with spin ([`spin_supported`]).
#[allow(clippy::too_many_arguments)]
pub fn optimize_whole_spinning(
    cat: impl Into<WholeCat>,
    duration: f64,
    manoeuvre: &Manoeuvre,
    settings: &WholeSettings,
    motors: &Motors,
    tolerance: f64,
    spin: &Vector3<f64>,
) -> Result<WholeOutcome, WholeError> {
    settings.validate()?;
    settings::positive_input("drop duration", duration)?;
    settings::needs_limits(settings.objective, motors)?;
    spin_supported(settings, motors, spin)?;
    settings::positive_input("tolerance", tolerance)?;
    let cat = &cat.into();
    beyond_two_motors(cat, settings.objective, motors, spin)?;
    if matches!(cat, WholeCat::Spherical(_)) {
        return lift::optimize_spherical(&lift::Plan { cat, duration, manoeuvre, settings, motors, tolerance });
    }
    let (starts, skipped) = build_starts(cat, duration, manoeuvre, settings, spin);
    let mut outcome = optimize_from_spinning(cat, &starts, settings, motors, tolerance, spin)?;
    outcome.skipped = skipped;
    Ok(outcome)
}

/// The starts named in `settings` for `cat` ([`build_start_spinning`]), and those that could not
/// be built with the reason why.
fn build_starts(
    cat: &WholeCat,
    duration: f64,
    manoeuvre: &Manoeuvre,
    settings: &WholeSettings,
    spin: &Vector3<f64>,
) -> (Vec<NamedStart>, Vec<SkippedStart>) {
    let built: Vec<_> = settings
        .starts
        .par_iter()
        .map(|&kind| (kind, build_start_spinning(cat, duration, manoeuvre, kind, settings, spin)))
        .collect();
    let mut starts = Vec::new();
    let mut skipped = Vec::new();
    for (kind, start) in built {
        match start {
            Ok(s) => starts.push(s),
            Err(reason) => skipped.push(SkippedStart { start: kind.name().to_string(), reason }),
        }
    }
    (starts, skipped)
}

/// Optimises from given starts (each a spline of `settings.control_points` cubic control points
/// with the ends fixed as `settings` says), driven by `motors`.
pub fn optimize_from(
    cat: impl Into<WholeCat>,
    starts: &[NamedStart],
    settings: &WholeSettings,
    motors: &Motors,
    tolerance: f64,
) -> Result<WholeOutcome, WholeError> {
    optimize_from_spinning(cat, starts, settings, motors, tolerance, &Vector3::zeros())
}

/// The tolerance of a result's flip re-measurement for a result tolerance `tolerance`, rad: a
/// hundred times finer, and at most 1e-10.
pub(crate) fn flip_tolerance(tolerance: f64) -> f64 {
    (1e-2 * tolerance).min(1e-10)
}

/// [`optimize_from`] for a release with total angular momentum `spin` ([`optimize_whole_spinning`]).
pub fn optimize_from_spinning(
    cat: impl Into<WholeCat>,
    starts: &[NamedStart],
    settings: &WholeSettings,
    motors: &Motors,
    tolerance: f64,
    spin: &Vector3<f64>,
) -> Result<WholeOutcome, WholeError> {
    settings.validate()?;
    settings::positive_input("tolerance", tolerance)?;
    settings::needs_limits(settings.objective, motors)?;
    spin_supported(settings, motors, spin)?;
    let cat = &cat.into();
    beyond_two_motors(cat, settings.objective, motors, spin)?;
    if let Some(held) = held_to_one_limit(cat, settings, motors, tolerance, |planning, ideal| {
        optimize_from_spinning(cat, starts, planning, ideal, tolerance, spin)
    }) {
        return held;
    }
    let problem =
        ScvxProblem { cat, settings, motors, target: Some(flipped()), qp: QpSettings::default(), spin: *spin };
    // The starts are independent: solved in parallel, reported in the order given.
    let solutions =
        starts.par_iter().map(|start| optimize_start(&problem, start, tolerance)).collect::<Result<Vec<_>, _>>()?;
    outcome_of(&problem, solutions, tolerance)
}

/// Beyond two motors within one torque limit on every motor: the outcome of `plan` for the least
/// peak with ideal motors (its settings and motors), held to the limit
/// ([`torque_limited::within`]); none for other motors or two motors.
fn held_to_one_limit(
    cat: &WholeCat,
    settings: &WholeSettings,
    motors: &Motors,
    tolerance: f64,
    plan: impl FnOnce(&WholeSettings, &Motors) -> Result<WholeOutcome, WholeError>,
) -> Option<Result<WholeOutcome, WholeError>> {
    let limit = held_to_torque_limit(cat.joints(), motors)?;
    let planning = WholeSettings { objective: Objective::Peak, ..settings.clone() };
    let outcome = plan(&planning, &Motors::ideal());
    Some(outcome.map(|o| torque_limited::within(cat, o, settings.objective, motors, limit, tolerance)))
}

/// Whether the best of a solve with `settings` is refined where its torques switch: rounds
/// asked, and not for the energy, whose torques do not switch.
fn refines(settings: &WholeSettings) -> bool {
    settings.objective != Objective::Energy && settings.switch_refinements > 0
}

/// `best` refined where its torques switch ([`refine_solution`]) when the refinement ends on a
/// result (converged, or an upper bound) that flips the cat; none otherwise (the best then stays
/// as it was).
fn kept_refinement(
    problem: &ScvxProblem<'_>,
    best: &WholeSolution,
    tolerance: f64,
) -> Result<Option<WholeSolution>, WholeError> {
    let refined = refine_solution(problem, best, tolerance)?;
    Ok((refined.status.is_result() && refined.flips(tolerance)).then_some(refined))
}

/// The outcome of the starts' `solutions` of `problem`: the best flip among the results
/// ([`solution::best_of`]), refined where its torques switch ([`refine_solution`]; not for the
/// energy, whose torques do not switch).
fn outcome_of(
    problem: &ScvxProblem<'_>,
    mut solutions: Vec<WholeSolution>,
    tolerance: f64,
) -> Result<WholeOutcome, WholeError> {
    let settings = problem.settings;
    let best = solution::best_of(&solutions, settings.objective, tolerance);
    if let Some(b) = best.filter(|_| refines(settings)) {
        if let Some(refined) = kept_refinement(problem, &solutions[b], tolerance)? {
            solutions[b] = refined;
        }
    }
    Ok(WholeOutcome { solutions, best, skipped: Vec::new() })
}

/// Optimises from one start: the stages, the Newton phase, and the exact re-measurement.
///
/// With motor limits at a fixed fall (objectives `peak` and `energy`), a `min-time` stage comes
/// first: its least fall time says whether any flip within the motors exists in this fall, and
/// its path, slowed to the fall, is a start within the limits for the constrained final stage.
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
    if start.spline.joints() != problem.cat.joints() {
        return Err(WholeError::BadFieldValue {
            field: "start",
            value: start.name.clone(),
            reason: format!(
                "has {} joint coordinates; the cat ({}) has {}",
                start.spline.joints(),
                problem.cat.describe(),
                problem.cat.joints()
            ),
        });
    }
    let mut run = Run { steps: s.steps_per_span, log: Vec::new(), polish_steps: 0, tolerance, warm: false };
    let (duration, fixed) = (start.spline.duration(), s.fixed());
    let mut spline = start.spline.clone();
    let quarter = (s.max_iterations / 4).max(1);
    if let Some(n) = s.coarse_control_points.filter(|&n| n < s.control_points) {
        let coarse_settings = WholeSettings { control_points: n, ..s.clone() };
        let coarse = ScvxProblem { settings: &coarse_settings, ..problem.clone() };
        let steps = run.steps;
        let fitted = coarse.polish(spline.refit(n, fixed), steps, 8).0;
        let it = coarse.evaluate(fitted, Objective::Energy, steps);
        let solved =
            coarse.stage(it, Objective::Energy, None, None, COARSE_OPTIMALITY, quarter, steps, &mut run.log)?.spline;
        spline = solved.refit(s.control_points, fixed);
    }
    spline = problem.polish(spline, run.steps, 8).0;
    // The interior-point method's peak stage starts from here, without the homotopy (its
    // module's docs).
    let interior_peak = interior::applies(problem, s.objective, None, None);
    if s.homotopy && s.objective != Objective::Energy && !interior_peak {
        let it = problem.evaluate(spline, Objective::Energy, run.steps);
        let budget = run.log.len() + quarter;
        spline = problem
            .stage(it, Objective::Energy, None, None, COARSE_OPTIMALITY, budget, run.steps, &mut run.log)?
            .spline;
    }
    let constrained = !problem.motors.is_ideal() && s.objective != Objective::MinTime;
    // At a fixed fall the motors' limits are constraints `ρ ≤ bound` of the final stage,
    // tightened when the dense re-measurement finds them exceeded between the samples.
    let mut bound = 1.0 - LIMIT_MARGIN;
    if constrained {
        // Feasibility first: shorten the least fall time until the path fits this one.
        let (status, reason, shape, m) =
            run.solve(problem, spline, Objective::MinTime, None, Some(bound), s.max_iterations)?;
        let least = stretch(&m.motors);
        if least > 1.0 + RATIO_TOLERANCE {
            let reason = if status == WholeStatus::Converged {
                format!(
                    "no flip within the motors in a fall of {duration:.6} s: the least fall time found is {:.6} s ({least:.4}× this fall; objective \"min-time\" gives the least drop height)",
                    duration * least
                )
            } else {
                format!(
                    "no flip within the motors found in a fall of {duration:.6} s (the least-fall-time stage ended {status} at {least:.4}× this fall: {reason})"
                )
            };
            return Ok(run.solution(problem, &start.name, WholeStatus::Infeasible, reason, shape, m, clock));
        }
        spline = shape;
    }
    let end = run.final_stage(problem, spline, constrained, &mut bound, s.max_iterations)?;
    Ok(run.finish(problem, &start.name, end, Vec::new(), constrained, clock))
}

/// The `best` of the starts (converged, or an upper bound) refined where its torques switch
/// ([`refine`]), for at most `switch_refinements` rounds, each solved again from the curve it
/// refines; `best` itself (with the reason why in its own) when no round is kept. Only the best
/// start is refined: the starts that converge land in the same optimum on the paper's cat, and
/// the refined solve costs about as much again as the whole solve before it.
pub fn refine_solution(
    problem: &ScvxProblem<'_>,
    best: &WholeSolution,
    tolerance: f64,
) -> Result<WholeSolution, WholeError> {
    let clock = Instant::now();
    let s = problem.settings;
    let constrained = !problem.motors.is_ideal() && s.objective != Objective::MinTime;
    let mut bound = 1.0 - LIMIT_MARGIN;
    let mut run =
        Run { steps: s.steps_per_span, log: best.log.clone(), polish_steps: best.polish_steps, tolerance, warm: true };
    let mut end: Option<FinalStage> = None;
    let mut notes = Vec::new();
    for _ in 0..s.switch_refinements {
        // What this round refines: the last round kept, else `best` (its peak and stretch as its
        // own re-measurement found them).
        let (from, from_status, from_peak, from_stretch) = match &end {
            Some(e) => (&e.spline, e.status, e.measurement.peak, stretch(&e.measurement.motors)),
            None => (&best.spline, best.status, best.peak_torque_nm, stretch(&best.motors)),
        };
        let spans = if problem.spins() {
            let (_, history) = problem.cat.spin_history(from, &problem.spin, run.flip_tolerance());
            refine::switching_spans_from(&problem.cat.exact_torques(Some(&history)), from)
        } else {
            refine::switching_spans(problem.cat, from)
        };
        let finer = refine::refined(from, &spans);
        if spans.is_empty() || finer.control_points() > WholeSettings::MAX_CONTROL_POINTS {
            break;
        }
        let settings = WholeSettings {
            control_points: finer.control_points(),
            trust_radius_deg: s.trust_radius_deg * refine::TRUST_SHARE,
            optimality: s.optimality.max(refine::OPTIMALITY),
            ..s.clone()
        };
        let fine = ScvxProblem { settings: &settings, ..problem.clone() };
        let stage_budget = refine::budget(interior::applies(&fine, s.objective, None, None));
        let budget = run.log.len() + stage_budget;
        let next = run.final_stage(&fine, finer, constrained, &mut bound, budget)?;
        let lower = match s.objective {
            Objective::MinTime => stretch(&next.measurement.motors) < from_stretch,
            _ => next.measurement.peak < from_peak,
        };
        let m = &next.measurement;
        let flips = m.twist_error <= tolerance && m.flip.swing <= tolerance;
        let within = !constrained || m.motors.within();
        // A refined stage that ends at its budget still crawling down from what it refines is
        // kept when it is lower and flips within the limits (an upper bound, below).
        let usable = matches!(next.status, WholeStatus::Converged | WholeStatus::MaxIterations);
        if !(usable && lower && flips && within) {
            notes.push(format!("a refinement ({} spans) ended {} and was not kept", next.spline.spans(), next.status));
            break;
        }
        notes.push(if next.status == WholeStatus::MaxIterations {
            format!(
                "refined to {} spans where the torques switch (that stage stopped at its {} iterations, lower than the {} it refines)",
                next.spline.spans(),
                stage_budget,
                if from_status == WholeStatus::UpperBound { "upper bound" } else { "optimum" }
            )
        } else if from_status == WholeStatus::UpperBound {
            // The upper bound it refines is now a converged optimum: the reader is told so.
            format!("refined to {} spans where the torques switch, where it converged", next.spline.spans())
        } else {
            format!("refined to {} spans where the torques switch", next.spline.spans())
        });
        // A stage stopped at its budget is an upper bound below what it refines; one that
        // stopped on its own test converged, whatever the curve it started from.
        let status =
            if next.status == WholeStatus::MaxIterations { WholeStatus::UpperBound } else { WholeStatus::Converged };
        end = Some(FinalStage { status, reason: best.reason.clone(), ..next });
    }
    let Some(end) = end else {
        let mut same = best.clone();
        for note in notes {
            same.reason = format!("{}; {note}", same.reason);
        }
        return Ok(same);
    };
    let mut refined = run.finish(problem, &best.start, end, notes, constrained, clock);
    refined.seconds += best.seconds;
    Ok(refined)
}

/// The largest stretch of a motor demand (0 with ideal motors).
fn stretch(demand: &MotorDemand) -> f64 {
    demand.stretch.map_or(0.0, |k| k.value)
}
