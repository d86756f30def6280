//! The spherical joint's whole optimum, started from the universal joint's (issue 22).
//!
//! A spherical joint holds every motion of the universal joint (`Rx(q1) Ry(q2)` is a swing
//! followed by a twist, [`crate::model::joint::spherical_coordinates`]) and of the no-twist joint
//! (its twist held at zero), so its least peak is at most theirs. Planned from the library starts
//! alone (the no-twist joint's, the twist held at zero) it was not: on the paper's cat the peak
//! stage crept down by `10⁻⁵` of the peak per step at trust radii near `7·10⁻⁴` rad until the
//! progress test called it converged at 0.316462 N·m, above the universal joint's 0.316452.
//! With three coordinates the least-peak optimum is not a vertex of the linearised problem (all
//! three motors sit at the peak along arcs, and the relative twist is a nearly flat direction:
//! an independent collocation finds ten optima within 0.1 % that differ mainly in their twist,
//! `tests/reference/README.md`), and successive linear programming crawls there whatever its
//! start; the start decides where the crawl begins.
//!
//! So the spherical joint is also started at the universal joint's optimum. The universal joint
//! is solved from each of the settings' starts on the uniform knots, and its best optimum is
//! lifted twice: as it is, its path expressed in the spherical joint's coordinates along the way
//! and fitted on the same knots ([`lift`]), solved for the iteration budget of the settings; and
//! refined where its torques switch, as the universal joint's own answer is
//! ([`super::refine_solution`]), lifted on those knots and solved for a refined solve's budget
//! ([`refine::BUDGET`]), which keeps the answer at or below the universal joint's own. Both start
//! with the first trust radius of a refined solve ([`refine::TRUST_SHARE`]). They run beside the
//! library starts, and the best of all is refined where its own torques switch, as every cat's
//! optimum is. A lifted stage that stops at its budget still descending, lower than the universal
//! optimum it started from, is kept, as a refined stage is, and its reason says that its value is
//! an upper bound on the spherical joint's least peak. Each lifted solution's time, iterations
//! and log count the universal joint's solve too.
//!
//! Measured (2 cores, the spherical cat's `optimize_whole` alone, 2026-12-05): on the paper's cat the
//! library starts end at 0.318285 and 0.317192 N·m, the universal optimum lifted (0.318346 on the
//! uniform knots) at 0.314330 after its 200 iterations and 0.311937 refined (1.4 % below the
//! universal joint's 0.316452; an independent collocation finds 0.3054), the refined one lifted
//! at 0.316165 after its 25; 10.0 s. On unequal halves (`problems/unequal-halves.toml`) the
//! universal joint's optimum is 0.457 N·m and its lift ends at 0.288, while the library's
//! `cone-mirrored` start ends at 0.282670 as before: neither start alone finds both; 13.2 s.

use nalgebra::Vector3;
use rayon::prelude::*;

use super::settings::{Objective, WholeError, WholeSettings};
use super::solution::{valued, SkippedStart, WholeOutcome, WholeSolution, WholeStatus};
use super::spline::BSpline;
use super::starts::NamedStart;
use super::{
    build_starts, flipped, optimize_start, optimize_whole, outcome_of, refine, refine_solution, torque_limited,
    ScvxProblem, WholeCat,
};
use crate::model::joint::spherical_coordinates;
use crate::model::motor::{motors_beyond, Motors, MotorsBeyond};
use crate::model::{Cat, Joint};
use crate::optimize::conic::QpSettings;
use crate::problem::manoeuvre::Manoeuvre;

/// The universal joint's path `spline` (two coordinates) in the spherical joint's coordinates
/// (three: the swing's rotation vector and the relative twist), fitted by least squares on the
/// same knots with the first and last `fixed` control points held at zero (both joints are
/// straight there).
pub fn lift(spline: &BSpline, fixed: usize) -> BSpline {
    // The twist is unwrapped along the path: each instant's the value nearest the one before.
    let twist = std::cell::Cell::new(0.0);
    spline.fit_on_knots(fixed, 3, |t| {
        let q = spherical_coordinates(&Joint::Universal.rotation(&spline.angles(t)), twist.get());
        twist.set(q[2]);
        q.to_vec()
    })
}

/// One spherical joint's planning: the cat, the fall (s), the manoeuvre its library starts are
/// built from, the settings, the motors and the flip tolerance (rad), as
/// [`super::optimize_whole`] takes them.
#[derive(Clone, Copy)]
pub(super) struct Plan<'a> {
    pub(super) cat: &'a WholeCat,
    pub(super) duration: f64,
    pub(super) manoeuvre: &'a Manoeuvre,
    pub(super) settings: &'a WholeSettings,
    pub(super) motors: &'a Motors,
    pub(super) tolerance: f64,
}

/// The whole optimum of `plan`'s cat on the spherical joint, from the library starts and from
/// the universal joint's optimum on the same halves (the module's docs), driven by its motors
/// (ideal, or one torque limit on every motor: then planned for the least peak with ideal motors
/// and held to the limit, [`torque_limited::within`], as every cat of more than two motors is).
pub(super) fn optimize_spherical(plan: &Plan<'_>) -> Result<WholeOutcome, WholeError> {
    let (cat, settings, motors, tolerance) = (plan.cat, plan.settings, plan.motors, plan.tolerance);
    if let MotorsBeyond::TorqueLimit(limit) = motors_beyond(motors) {
        let planning = WholeSettings { objective: Objective::Peak, ..settings.clone() };
        let ideal = Plan { settings: &planning, motors: &Motors::ideal(), ..*plan };
        let outcome = optimize_spherical(&ideal)?;
        return Ok(torque_limited::within(cat, outcome, settings.objective, motors, limit, tolerance));
    }
    // The library starts (the no-twist joint's, the twist held at zero) beside the universal
    // joint's optimum, lifted: the one goes further on some cats, the other on others.
    let (library, lifted) = rayon::join(|| library_solutions(plan), || lifted_solutions(plan));
    let (mut solutions, mut skipped) = library?;
    let (more, more_skipped) = lifted?;
    solutions.extend(more);
    skipped.extend(more_skipped);
    let mut outcome = outcome_of(&spherical(cat, settings, motors), solutions, tolerance)?;
    outcome.skipped = skipped;
    Ok(outcome)
}

/// The solutions of the spherical cat from the library starts named in the settings, and the
/// starts that could not be built.
fn library_solutions(plan: &Plan<'_>) -> Result<(Vec<WholeSolution>, Vec<SkippedStart>), WholeError> {
    let (starts, skipped) = build_starts(plan.cat, plan.duration, plan.manoeuvre, plan.settings, &Vector3::zeros());
    let problem = spherical(plan.cat, plan.settings, plan.motors);
    let solutions = starts
        .par_iter()
        .map(|start| optimize_start(&problem, start, plan.tolerance))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((solutions, skipped))
}

/// The solutions of the spherical cat from the universal joint's optimum on its halves, lifted
/// (the module's docs), and why the universal joint's other starts are not lifted.
fn lifted_solutions(plan: &Plan<'_>) -> Result<(Vec<WholeSolution>, Vec<SkippedStart>), WholeError> {
    let (cat, settings, motors, tolerance) = (plan.cat, plan.settings, plan.motors, plan.tolerance);
    let universal = WholeCat::new(Cat { joint: Joint::Universal, ..cat.cat() })?;
    let unrefined = WholeSettings { switch_refinements: 0, ..settings.clone() };
    let sub = optimize_whole(&universal, plan.duration, plan.manoeuvre, &unrefined, motors, tolerance)?;
    let (froms, mut skipped) = lifted_optima(&sub, settings.objective);
    // Each start: the universal solution it lifts, its name, its own settings (its layout and
    // budget) and whether it is the refined optimum.
    let own = |from: &WholeSolution, budget: usize| WholeSettings {
        control_points: from.spline.control_points(),
        coarse_control_points: None,
        homotopy: false,
        trust_radius_deg: settings.trust_radius_deg * refine::TRUST_SHARE,
        max_iterations: budget,
        ..settings.clone()
    };
    let named = |from: &WholeSolution| format!("universal {} from {}", what(from), from.start);
    let mut starts: Vec<(WholeSolution, String, WholeSettings, bool)> =
        froms.iter().map(|&f| (f.clone(), named(f), own(f, settings.max_iterations), false)).collect();
    if let Some(refined) = refined_best(&universal, &sub, settings, motors, tolerance)? {
        let name = format!("{}, refined", named(&refined));
        let budget = own(&refined, refine::BUDGET);
        starts.push((refined, name, budget, true));
    }
    let limit = settings.joint_limit_deg.map(f64::to_radians);
    let solutions = starts
        .par_iter()
        .map(|(from, name, own, refined)| {
            let mut spline = lift(&from.spline, own.fixed());
            // The joint limit holds on the control points, as every start's does.
            if let Some(limit) = limit {
                spline.coefficients.iter_mut().flatten().for_each(|c| *c = c.clamp(-limit, limit));
            }
            let start = NamedStart { name: name.clone(), spline };
            let solved = optimize_start(&spherical(cat, own, motors), &start, tolerance)?;
            Ok(after(from, solved, own, *refined, tolerance))
        })
        .collect::<Result<Vec<_>, WholeError>>()?;
    skipped.extend(sub.skipped.into_iter().map(|s| SkippedStart {
        start: format!("universal optimum from {}", s.start),
        reason: format!("its universal-joint start could not be built: {}", s.reason),
    }));
    Ok((solutions, skipped))
}

/// What a universal solution lifted is: an optimum when it converged, else a path.
fn what(from: &WholeSolution) -> &'static str {
    if from.status == WholeStatus::Converged {
        "optimum"
    } else {
        "path"
    }
}

/// The problem of the spherical `cat` with `settings`, without spin.
fn spherical<'a>(cat: &'a WholeCat, settings: &'a WholeSettings, motors: &'a Motors) -> ScvxProblem<'a> {
    ScvxProblem { cat, settings, motors, target: Some(flipped()), qp: QpSettings::default(), spin: Vector3::zeros() }
}

/// The universal joint's best solution of `sub` refined where its torques switch, as its own
/// optimisation would refine it ([`super::refine_solution`], `settings.switch_refinements`
/// rounds); none without a best, without rounds (or for the energy, whose torques do not
/// switch), or when no round was kept.
fn refined_best(
    universal: &WholeCat,
    sub: &WholeOutcome,
    settings: &WholeSettings,
    motors: &Motors,
    tolerance: f64,
) -> Result<Option<WholeSolution>, WholeError> {
    let Some(best) = sub.best().filter(|_| settings.switch_refinements > 0 && settings.objective != Objective::Energy)
    else {
        return Ok(None);
    };
    let problem = ScvxProblem { cat: universal, ..spherical(universal, settings, motors) };
    let refined = refine_solution(&problem, best, tolerance)?;
    let kept = refined.status == WholeStatus::Converged
        && refined.flips(tolerance)
        && refined.spline.control_points() != best.spline.control_points();
    Ok(kept.then_some(refined))
}

/// The universal joint's solutions of `sub` that the spherical joint starts from on the uniform
/// knots: its best (the lowest converged flip), or every start's solution when none converged;
/// and why each other start is not lifted.
fn lifted_optima(sub: &WholeOutcome, objective: Objective) -> (Vec<&WholeSolution>, Vec<SkippedStart>) {
    let Some(best) = sub.best() else { return (sub.solutions.iter().collect(), Vec::new()) };
    let skipped = sub
        .solutions
        .iter()
        .filter(|s| !std::ptr::eq(*s, best))
        .map(|s| SkippedStart {
            start: format!("universal optimum from {}", s.start),
            reason: format!(
                "its universal-joint solve ended {} at {}; the spherical joint starts from the lowest, {}'s {}",
                s.status,
                valued(objective, s.value(objective)),
                best.start,
                valued(objective, best.value(objective))
            ),
        })
        .collect();
    (vec![best], skipped)
}

/// The spherical joint's solution `s` counted from the universal joint's solve `from` it started
/// at (`refined`: the universal optimum refined where its torques switch, on a refined solve's
/// budget): the time, iterations and log of both, and where it started in its reason. A stage that
/// stopped at its iteration budget still descending from a converged universal optimum, on a
/// flip and lower than that optimum, is kept as converged, as a refined stage is
/// ([`super::refine_solution`]), and its reason says so: a flip below the universal joint's
/// optimum, its value an upper bound on the spherical joint's.
fn after(
    from: &WholeSolution,
    mut s: WholeSolution,
    settings: &WholeSettings,
    refined: bool,
    tolerance: f64,
) -> WholeSolution {
    let objective = settings.objective;
    let mut reason = s.reason.clone();
    let improved = from.status == WholeStatus::Converged && s.value(objective) < from.value(objective);
    if s.status == WholeStatus::MaxIterations && improved && s.flips(tolerance) && s.motors.within() {
        s.status = WholeStatus::Converged;
        reason = format!(
            "stopped at its {} iterations {:.3} % below it and still descending: a flip below the universal joint's optimum, not proved the spherical joint's{}",
            settings.max_iterations,
            100.0 * (1.0 - s.value(objective) / from.value(objective)),
            if refined { "" } else { " (raise optimize.whole.max_iterations to go on)" }
        );
    }
    s.reason = format!(
        "from the universal joint's {} ({}, {}), lifted onto the spherical joint: {reason}",
        what(from),
        from.status,
        valued(objective, from.value(objective))
    );
    let offset = from.log.len();
    let mut log = from.log.clone();
    log.extend(s.log.drain(..).map(|mut l| {
        l.iteration += offset;
        l
    }));
    s.log = log;
    s.iterations += from.iterations;
    s.polish_steps += from.polish_steps;
    s.seconds += from.seconds;
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest angle between the universal joint's rotation along `path` and the spherical
    /// joint's along its lift, rad, at 2001 instants.
    fn largest_gap(path: &BSpline, lifted: &BSpline) -> f64 {
        (0..=2000)
            .map(|k| path.duration() * k as f64 / 2000.0)
            .map(|t| {
                let u = Joint::Universal.rotation(&path.angles(t));
                let v = Joint::Spherical.rotation(&lifted.angles(t));
                nalgebra::Rotation3::from_matrix_unchecked(u.transpose() * v).angle()
            })
            .fold(0.0, f64::max)
    }

    /// The lift is the universal joint's motion on the spherical joint, to the fit's error, which
    /// falls as a cubic fit's does (`h⁴`: about 16 times per halving of the knot spacing); the
    /// relative twist it carries is continuous, and the ends stay straight.
    #[test]
    fn a_lifted_path_is_the_universal_joints_motion_to_the_fits_error() {
        // The bend's direction circles once while the bend swings out to 100° and back: the
        // universal joint twists the halves by up to 0.78 rad on the way.
        let path = BSpline::fit(1.0, 60, 3, 2, 2, |t| {
            let s = (std::f64::consts::PI * t).sin().powi(2);
            vec![1.75 * s * (6.0 * t).cos(), 1.75 * s * (6.0 * t).sin()]
        });
        let coarse = lift(&path.refit(40, 2), 2);
        let fine = lift(&path.refit(80, 2), 2);
        let (e40, e80) = (largest_gap(&path, &coarse), largest_gap(&path, &fine));
        assert!(e40 < 1e-3, "40 control points: {e40} rad");
        assert!(e80 < e40 / 8.0, "80 control points: {e80} rad against {e40}");
        let twists: Vec<f64> = (0..=2000).map(|k| fine.angles(k as f64 / 2000.0)[2]).collect();
        let most = twists.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let jump = twists.windows(2).map(|w| (w[1] - w[0]).abs()).fold(0.0, f64::max);
        assert!(most > 0.5 && jump < 0.01, "twist up to {most} rad, steps up to {jump} rad");
        assert!(fine.angles(0.0).iter().chain(&fine.angles(1.0)).all(|q| q.abs() < 1e-15));
    }
}
