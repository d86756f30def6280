//! The spherical joint's whole optimum, started from the universal joint's (issue 22).
//!
//! A spherical joint holds every motion of the universal joint (`Rx(q1) Ry(q2)` is a swing
//! followed by a twist, [`crate::model::joint::spherical_coordinates`]) and of the no-twist joint
//! (its twist held at zero), so without a joint limit its least peak is at most theirs (the
//! limit bounds different coordinates on each joint: a lifted start is clamped to the spherical
//! joint's). Planned from the library starts alone (the no-twist joint's, the twist held at zero)
//! it was not: on the paper's cat the peak stage crept down by `10⁻⁵` of the peak per step at trust
//! radii near `7·10⁻⁴` rad until the progress test stopped it, and refined it ended at 0.316825
//! N·m, above the universal joint's 0.316452. With three coordinates the least-peak optimum is not
//! a vertex of the linearised problem (all three motors sit at the peak along arcs, and the
//! relative twist is a nearly flat direction: an independent collocation finds ten optima within
//! 0.1 % that differ mainly in their twist, `tests/reference/README.md`), and successive linear
//! programming crawls there whatever its start; the start decides where the crawl begins.
//!
//! So the spherical joint is also started at the universal joint's optimum. The universal joint
//! is solved from each of the settings' starts on the uniform knots, and its best optimum is
//! lifted twice: as it is, its path expressed in the spherical joint's coordinates along the way
//! and fitted on the same knots ([`lift`]), solved for the iteration budget of the settings; and
//! refined where its torques switch, as the universal joint's own answer is
//! ([`super::refine_solution`]), lifted on those knots and solved as a refined solve is (its
//! budget [`refine::BUDGET`] and optimality). Both start with the first trust radius of a refined
//! solve ([`refine::TRUST_SHARE`]). They run beside the library starts, and the best of all is
//! refined where its own torques switch, as every cat's optimum is. A lifted stage that stops at
//! its budget below the universal optimum it started from, on a flip within the limits, is kept
//! with the status `upper-bound` ([`WholeStatus::UpperBound`]), as a refined stage is, and its
//! reason says that its value is an upper bound on the spherical joint's least peak. Each lifted
//! solution's time, iterations and log count its universal solve (the start it lifts) too.
//!
//! Where the least peak is the interior-point method's (ideal motors; `optimize.whole.method`
//! `auto` beyond two motors), the universal joint is solved by that method too, and only its
//! refined optimum is lifted (on its budget [`refine::INTERIOR_BUDGET`]; the unrefined one is a
//! skipped start that says why). From the library starts alone the spherical joint ended above
//! the universal joint at 40 control points (0.321760 against 0.320226 N·m); with the refined
//! lift it ends at 0.308073 there, and at 0.306843 on the default 120 (against 0.308286 from the
//! library starts, 0.5 % above an independent collocation's 0.3054), 1.55 s in all on 2 cores;
//! lifting the unrefined optimum too reached 0.312505 from it and took 2.0 s
//! (`cargo run --release --example spherical_starts`, 2026-12-07).
//!
//! Measured by the trust region (`cargo run --release --example spherical_starts` with
//! `optimize.whole.method = "trust-region"`, which prints every start; 2 cores, 2026-12-06): on
//! the paper's cat the library starts end at 0.318285 and 0.317192 N·m, the universal optimum
//! lifted (0.318346 on the uniform knots) 1.262 % below it after its 200
//! iterations and at 0.311945 refined (1.4 % below the universal joint's 0.316452; an
//! independent collocation finds 0.3054), the refined one lifted at 0.316165 after its 25;
//! 8.4 s in all. On 40 control points (`--set optimize.whole.control_points=40`) the refined
//! lift is the best (0.318143 against the universal joint's 0.320227; the unrefined one's stage
//! was stopped early by the progress test at 0.325765). On unequal halves
//! (`problems/unequal-halves.toml`) the universal joint's `cone-mirrored` optimum (0.459490 N·m)
//! lifted ends at 0.284772, the library's starts at their 200 iterations at 0.285436 and 0.284828
//! (on 2026-12-05 `cone-mirrored` converged at 0.282670, before the energy's exact step moved its
//! path): which start is best moves with the path; 24.3 s.

use nalgebra::Vector3;
use rayon::prelude::*;

use super::settings::{Method, Objective, WholeError, WholeSettings};
use super::solution::{valued, SkippedStart, WholeOutcome, WholeSolution, WholeStatus};
use super::spline::BSpline;
use super::starts::NamedStart;
use super::{
    build_starts, flipped, held_to_one_limit, interior, kept_refinement, optimize_start, optimize_whole, outcome_of,
    refine, refines, ScvxProblem, WholeCat, BEND_SLACK_DEG,
};
use crate::model::joint::spherical_coordinates;
use crate::model::motor::Motors;
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
/// and held to the limit, [`super::torque_limited::within`], as every cat of more than two motors is).
pub(super) fn optimize_spherical(plan: &Plan<'_>) -> Result<WholeOutcome, WholeError> {
    let (cat, settings, motors, tolerance) = (plan.cat, plan.settings, plan.motors, plan.tolerance);
    if let Some(held) = held_to_one_limit(cat, settings, motors, tolerance, |planning, ideal| {
        optimize_spherical(&Plan { settings: planning, motors: ideal, ..*plan })
    }) {
        return held;
    }
    // The library starts (the no-twist joint's, the twist held at zero) beside the universal
    // joint's optimum, lifted: the one goes further on some cats, the other on others.
    let problem = problem_of(cat, settings, motors);
    let (library, lifted) = rayon::join(|| library_solutions(plan), || lifted_solutions(plan));
    let (mut solutions, mut skipped) = library?;
    let (more, more_skipped) = lifted?;
    solutions.extend(more);
    skipped.extend(more_skipped);
    let mut outcome = outcome_of(&problem, solutions, tolerance)?;
    outcome.skipped = skipped;
    Ok(outcome)
}

/// The solutions of the spherical cat from the library starts named in the settings, and the
/// starts that could not be built.
fn library_solutions(plan: &Plan<'_>) -> Result<(Vec<WholeSolution>, Vec<SkippedStart>), WholeError> {
    let (starts, skipped) = build_starts(plan.cat, plan.duration, plan.manoeuvre, plan.settings, &Vector3::zeros());
    let problem = problem_of(plan.cat, plan.settings, plan.motors);
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
    // The universal joint is solved by the spherical joint's method (`auto` chooses by motors).
    let interior_point = interior::applies(&problem_of(cat, settings, motors), settings.objective, None, None);
    let method = if interior_point { Method::InteriorPoint } else { Method::TrustRegion };
    let on_two = WholeSettings { method, ..settings.clone() };
    let unrefined = WholeSettings { switch_refinements: 0, ..on_two.clone() };
    let sub = match optimize_whole(&universal, plan.duration, plan.manoeuvre, &unrefined, motors, tolerance) {
        Ok(sub) => sub,
        // The library starts do not need it: a start that could not be tried, said so.
        Err(e) => {
            let reason = format!("the universal joint's solve on these halves failed: {e}");
            return Ok((Vec::new(), vec![SkippedStart { start: "universal optimum".into(), reason }]));
        }
    };
    let (mut froms, mut skipped) = lifted_optima(&sub, settings.objective);
    let refined = refined_best(&universal, &sub, &on_two, motors, tolerance)?;
    // The interior point lifts the refined optimum alone where there is one: on the paper's cat
    // it ends lower from there than from the unrefined one, whose solve cost 0.4 s more in all
    // (module docs).
    if interior_point && refined.is_some() {
        let reason =
            "not lifted: the interior-point method lifts the universal optimum refined where its torques switch";
        skipped.extend(froms.drain(..).map(|f| SkippedStart { start: lifted_name(f), reason: reason.to_string() }));
    }
    // Each start: the universal solution it lifts, its name, its own settings (the layout of
    // its knots, the budget and optimality of its solve) and whether it is the refined optimum.
    let layout = |from: &WholeSolution| WholeSettings {
        control_points: from.spline.control_points(),
        coarse_control_points: None,
        homotopy: false,
        trust_radius_deg: settings.trust_radius_deg * refine::TRUST_SHARE,
        ..settings.clone()
    };
    let mut starts: Vec<(WholeSolution, String, WholeSettings, bool)> =
        froms.iter().map(|&f| (f.clone(), lifted_name(f), layout(f), false)).collect();
    if let Some(refined) = refined {
        let name = format!("{}, refined", lifted_name(&refined));
        let own = WholeSettings {
            max_iterations: refine::budget(interior_point),
            optimality: settings.optimality.max(refine::OPTIMALITY),
            ..layout(&refined)
        };
        starts.push((refined, name, own, true));
    }
    let solutions = starts
        .par_iter()
        .map(|(from, name, own, refined)| {
            let problem = problem_of(cat, own, motors);
            let mut spline = lift(&from.spline, own.fixed());
            // The limits hold on the control points, as every start's do.
            problem.clamp_to_limits(&mut spline);
            let start = NamedStart { name: name.clone(), spline };
            Ok(after(from, optimize_start(&problem, &start, tolerance)?, own, *refined, tolerance))
        })
        .collect::<Result<Vec<_>, WholeError>>()?;
    skipped.extend(sub.skipped.into_iter().map(|s| SkippedStart {
        start: format!("universal optimum from {}", s.start),
        reason: format!("its universal-joint start could not be built: {}", s.reason),
    }));
    Ok((solutions, skipped))
}

/// The name of the spherical joint's start lifted from the universal solution `from`.
fn lifted_name(from: &WholeSolution) -> String {
    format!("universal {} from {}", what(from), from.start)
}

/// What a universal solution lifted is: an optimum when it ended on a result (converged, or a
/// refined stage's upper bound), else a path.
fn what(from: &WholeSolution) -> &'static str {
    if from.status.is_result() {
        "optimum"
    } else {
        "path"
    }
}

/// The problem of `cat` with `settings`, flipped, without spin.
fn problem_of<'a>(cat: &'a WholeCat, settings: &'a WholeSettings, motors: &'a Motors) -> ScvxProblem<'a> {
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
    let Some(best) = sub.best().filter(|_| refines(settings)) else { return Ok(None) };
    let refined = kept_refinement(&problem_of(universal, settings, motors), best, tolerance)?;
    Ok(refined.filter(|r| r.spline.control_points() != best.spline.control_points()))
}

/// The universal joint's solutions of `sub` that the spherical joint starts from on the uniform
/// knots: its best (the lowest flip among the results, [`super::solution::best_of`]), or every
/// start's solution when none converged; and why each other start is not lifted.
fn lifted_optima(sub: &WholeOutcome, objective: Objective) -> (Vec<&WholeSolution>, Vec<SkippedStart>) {
    let Some(best) = sub.best() else { return (sub.solutions.iter().collect(), Vec::new()) };
    let skipped = sub
        .solutions
        .iter()
        .filter(|s| !std::ptr::eq(*s, best))
        .map(|s| SkippedStart {
            start: lifted_name(s),
            reason: format!(
                "not lifted: its universal-joint solve ended {} at {}, and the spherical joint starts from the lowest, {}'s {}",
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
/// budget): the time, iterations and log of that solve and its own, and where it started in its
/// reason. A stage that stopped at its iteration budget on a flip within the motors and the bend
/// limit, below the converged universal optimum it started from (on the same knots), is kept as
/// an upper bound ([`WholeStatus::UpperBound`]), as a refined stage is
/// ([`super::refine_solution`]), and its reason says so: a flip below that optimum, its value
/// an upper bound on the spherical joint's least.
fn after(
    from: &WholeSolution,
    mut s: WholeSolution,
    settings: &WholeSettings,
    refined: bool,
    tolerance: f64,
) -> WholeSolution {
    let objective = settings.objective;
    let mut reason = s.reason.clone();
    let improved = from.status.is_result() && s.value(objective) < from.value(objective);
    let most_bend = settings.min_angle_deg.map_or(f64::INFINITY, |a| 180.0 - a + BEND_SLACK_DEG);
    let within = s.flips(tolerance) && s.motors.within() && s.max_bend_deg <= most_bend;
    if s.status == WholeStatus::MaxIterations && improved && within {
        s.status = WholeStatus::UpperBound;
        reason = format!(
            "{reason}, {:.3} % below it: a flip below the universal joint's optimum on these knots, not proved the spherical joint's least (an upper bound on it{})",
            100.0 * (1.0 - s.value(objective) / from.value(objective)),
            if refined { "" } else { "; optimize.whole.max_iterations goes further" }
        );
    }
    // Which of the universal joint's answers: the one on the uniform knots is not its row's
    // (that one is refined where its torques switch, as every optimum is).
    let knots =
        if refined { "refined where its torques switch" } else { "on the uniform knots, before its refinement" };
    s.reason = format!(
        "from the universal joint's {} {knots} ({}, {}), lifted onto the spherical joint: {reason}",
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
    use super::super::solution::tests::solution;
    use super::*;

    /// A lifted stage at its budget is kept as an upper bound only below the converged optimum it
    /// started from, on a flip within the bend limit, and says it is an upper bound; either way
    /// it counts the universal solve's iterations and time and names where it started.
    #[test]
    fn a_lifted_stage_at_its_budget_is_kept_only_below_its_start_and_within_the_limits() {
        let settings = WholeSettings { min_angle_deg: Some(120.0), ..WholeSettings::default() };
        let from = solution(WholeStatus::Converged, 0.32, 50.0, 40);
        let kept = after(&from, solution(WholeStatus::MaxIterations, 0.31, 55.0, 200), &settings, false, 1e-8);
        assert_eq!(kept.status, WholeStatus::UpperBound, "{}", kept.reason);
        assert!(kept.reason.contains("upper bound") && kept.reason.contains("3.125 % below it"), "{}", kept.reason);
        assert_eq!((kept.iterations, kept.seconds), (240, 2.0));
        // Beyond the bend limit (60° here), above its start, or from a start that did not converge.
        let bent = after(&from, solution(WholeStatus::MaxIterations, 0.31, 61.0, 200), &settings, false, 1e-8);
        let higher = after(&from, solution(WholeStatus::MaxIterations, 0.33, 55.0, 200), &settings, false, 1e-8);
        let unproved = solution(WholeStatus::MaxIterations, 0.32, 50.0, 200);
        let after_unproved =
            after(&unproved, solution(WholeStatus::MaxIterations, 0.31, 55.0, 200), &settings, false, 1e-8);
        for s in [bent, higher, after_unproved] {
            assert_eq!(s.status, WholeStatus::MaxIterations, "{}", s.reason);
            assert!(
                s.reason.starts_with("from the universal joint's") && !s.reason.contains("upper bound"),
                "{}",
                s.reason
            );
        }
    }

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
        let (on40, on80) = (path.refit(40, 2), path.refit(80, 2));
        let (coarse, fine) = (lift(&on40, 2), lift(&on80, 2));
        let (e40, e80) = (largest_gap(&on40, &coarse), largest_gap(&on80, &fine));
        assert!(e40 < 1e-3, "40 control points: {e40} rad");
        assert!(e80 < e40 / 8.0, "80 control points: {e80} rad against {e40}");
        // On refined knots (two narrow spans) as on uniform ones.
        let narrow = on40.with_knot(0.301).with_knot(0.302);
        let gap = largest_gap(&narrow, &lift(&narrow, 2));
        assert!(gap < 1e-3, "refined knots: {gap} rad");
        let twists: Vec<f64> = (0..=2000).map(|k| fine.angles(k as f64 / 2000.0)[2]).collect();
        let most = twists.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let jump = twists.windows(2).map(|w| (w[1] - w[0]).abs()).fold(0.0, f64::max);
        assert!(most > 0.5 && jump < 0.01, "twist up to {most} rad, steps up to {jump} rad");
        assert!(fine.angles(0.0).iter().chain(&fine.angles(1.0)).all(|q| q.abs() < 1e-15));
    }
}
