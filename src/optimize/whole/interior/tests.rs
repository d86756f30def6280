//! The interior-point method's tests: its curvature against differences of the exact
//! gradients, and its least peak against the trust-region loop's on the paper's cat.

use super::super::cat::WholeCat;
use super::super::sensitivity::{grid_partials, torque_samples, uniform_grid, Layout};
use super::super::settings::{Method, Objective, WholeSettings};
use super::super::solution::WholeStatus;
use super::super::{build_start, optimize_whole, StartKind};
use super::curvature::{torque_curvatures, weighted_torque_hessian};
use crate::model::motor::Motors;
use crate::model::{Cat, Cylinder, Joint};
use crate::numeric::random::SplitMix64;
use crate::problem::Manoeuvre;

/// The paper's half.
const HALF: Cylinder = Cylinder { mass: 1.0, length: 1.0, radius: 0.1 };

/// The paper's fall from 10 m, s.
fn fall() -> f64 {
    (2.0 * 10.0 / 9.8f64).sqrt()
}

/// `Σ_k Σ_j w_kj ∇τ_kj` at `spline` on the layout's variables.
fn weighted_gradient(
    cat: &WholeCat,
    spline: &super::BSpline,
    layout: &Layout,
    grid: &[super::GridPoint],
    w: &[Vec<f64>],
) -> Vec<f64> {
    let mut g = vec![0.0; layout.variables()];
    for (sample, wk) in torque_samples(cat, spline, layout, grid).iter().zip(w) {
        for (gradient, wkj) in sample.gradient.iter().zip(wk) {
            for &(v, d) in gradient {
                g[v] += wkj * d;
            }
        }
    }
    g
}

/// The curvature of [`weighted_torque_hessian`] applied to a direction equals the central
/// difference of the exact (dual-number) gradients along it, on the spherical joint, on a cat
/// with a tail and on a cat with legs (three, four and four coordinates), at a bent path with
/// random weights: the differences along the angles and the rates' quadratic form together.
#[test]
fn the_torque_curvature_matches_differences_of_the_exact_gradients() {
    // problems/tail.toml's tail: a tenth of the cat's mass, as long as a half.
    let rod = Cylinder { mass: 0.2, length: 1.0, radius: 0.02 };
    let tail = crate::model::cat::Appendages { tail: Some((rod, Joint::Universal)), legs: None };
    // problems/legs.toml's legs: each pair a tenth of the cat's mass, 0.45 m.
    let leg = Cylinder { mass: 0.2, length: 0.45, radius: 0.03 };
    let legs = crate::model::cat::Appendages { tail: None, legs: Some([leg; 2]) };
    let cats = [
        WholeCat::spherical(Cat::equal(HALF, Joint::Spherical)).expect("a spherical cat"),
        WholeCat::appended(Cat::equal(HALF, Joint::NoTwist), tail).expect("a cat with a tail"),
        WholeCat::appended(Cat::equal(HALF, Joint::NoTwist), legs).expect("a cat with legs"),
    ];
    let settings = WholeSettings { control_points: 14, ..WholeSettings::default() };
    for cat in &cats {
        let joints = cat.joints();
        let start = build_start(cat, fall(), &Manoeuvre::default(), StartKind::ConeMirrored, &settings)
            .unwrap_or_else(|e| panic!("{e}"));
        let layout = Layout { control_points: settings.control_points, fixed: settings.fixed(), joints };
        let mut rng = SplitMix64::new(7);
        // Every coordinate moved off the start (the tail's and the twist's are zero there).
        let shake: Vec<f64> = (0..layout.variables()).map(|_| rng.uniform(-0.3, 0.3)).collect();
        let spline = layout.moved(&start.spline.with_joints(joints), &shake);
        let grid = uniform_grid(&spline, 3);
        let w: Vec<Vec<f64>> = grid.iter().map(|_| (0..joints).map(|_| rng.uniform(-1.0, 1.0)).collect()).collect();
        let direction: Vec<f64> = (0..layout.variables()).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let mut product = vec![0.0; layout.variables()];
        let own = grid_partials(cat, &spline, layout.joints, &grid);
        let curvatures = torque_curvatures(cat, &spline, joints, &grid, &own);
        for (v, u, a) in weighted_torque_hessian(&spline, &layout, &grid, &curvatures, &w) {
            product[v] += a * direction[u];
        }
        let h = 1e-5;
        let along = |sign: f64| {
            let step: Vec<f64> = direction.iter().map(|d| sign * h * d).collect();
            weighted_gradient(cat, &layout.moved(&spline, &step), &layout, &grid, &w)
        };
        let (plus, minus) = (along(1.0), along(-1.0));
        let scale = product.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let worst = (0..layout.variables())
            .map(|v| ((plus[v] - minus[v]) / (2.0 * h) - product[v]).abs())
            .fold(0.0f64, f64::max);
        assert!(scale > 1.0, "{}: a curvature to compare ({scale:.3e})", cat.describe());
        assert!(
            worst <= 1e-5 * scale,
            "{}: the curvature times a direction differs from the gradients' difference by {worst:.3e} (scale {scale:.3e})",
            cat.describe()
        );
    }
}

/// On the paper's cat (40 control points, no refinement) the interior-point method's least
/// peak flips the cat exactly and is the trust-region loop's from the same starts, to 10⁻⁶ of
/// it (measured 0.33539302 against 0.33539308 N·m, 1.6·10⁻⁷ apart: the same local optimum of
/// the same discrete problem, by the same dense re-measurement).
#[test]
fn the_interior_point_least_peak_flips_the_paper_cat_near_the_trust_regions() {
    let cat = WholeCat::new(Cat::equal(HALF, Joint::Universal)).expect("the paper's cat");
    let base = WholeSettings { control_points: 40, switch_refinements: 0, ..WholeSettings::default() };
    let solve = |method| {
        let settings = WholeSettings { method, ..base.clone() };
        optimize_whole(&cat, fall(), &Manoeuvre::default(), &settings, &Motors::ideal(), 1e-8)
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let (interior, trust) = (solve(Method::InteriorPoint), solve(Method::TrustRegion));
    let best = |o: &super::super::WholeOutcome| o.best.map(|b| o.solutions[b].clone()).expect("a best start");
    let (ip, tr) = (best(&interior), best(&trust));
    assert_eq!(ip.status, WholeStatus::Converged, "{}", ip.reason);
    assert!(ip.reason.contains("interior point"), "the stage was the interior point's: {}", ip.reason);
    assert!(ip.log.iter().any(|l| l.objective == Objective::Peak && l.barrier.is_some()));
    assert!(tr.log.iter().all(|l| l.barrier.is_none()), "the trust region's log has no barrier");
    assert!(ip.twist_error <= 1e-8 && ip.swing <= 1e-8, "flips: {:.1e}, {:.1e}", ip.twist_error, ip.swing);
    let gap = (ip.peak_torque_nm - tr.peak_torque_nm) / tr.peak_torque_nm;
    assert!(gap.abs() < 1e-6, "interior point {} N·m, trust region {} N·m", ip.peak_torque_nm, tr.peak_torque_nm);
    // The same effort objective stays the trust region's: the method changes the peak's stage only.
    let energy = WholeSettings { method: Method::InteriorPoint, objective: Objective::Energy, ..base.clone() };
    let o = optimize_whole(&cat, fall(), &Manoeuvre::default(), &energy, &Motors::ideal(), 1e-8)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(o.solutions.iter().all(|s| s.log.iter().all(|l| l.barrier.is_none())));
}

/// Where the interior-point method plans the least peak, its stage starts from the start itself
/// (no energy homotopy: with no coarse solve the log holds no energy iteration), the spherical
/// joint is planned from the library starts and from the universal joint's optimum refined and
/// lifted (not the unrefined one), and ends below the universal joint's least peak, and a
/// refinement (the paper's cat's) starts at the smaller barrier of a stage that starts at an
/// optimum.
#[test]
fn the_interior_point_plans_from_the_starts_and_refines_warm() {
    let settings = WholeSettings {
        method: Method::InteriorPoint,
        control_points: 40,
        coarse_control_points: None,
        homotopy: true,
        ..WholeSettings::default()
    };
    let solve = |cat: &WholeCat| {
        optimize_whole(cat, fall(), &Manoeuvre::default(), &settings, &Motors::ideal(), 1e-8)
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let spherical = solve(&WholeCat::spherical(Cat::equal(HALF, Joint::Spherical)).expect("a spherical cat"));
    let names: Vec<&str> = spherical.solutions.iter().map(|s| s.start.as_str()).collect();
    assert_eq!(names[..2], ["paper", "cone-mirrored"], "the library starts first: {names:?}");
    assert!(
        names.len() == 3 && names[2].starts_with("universal optimum from ") && names[2].ends_with(", refined"),
        "the refined universal optimum lifted, alone: {names:?}"
    );
    let unrefined = spherical.skipped.iter().any(|s| s.reason.contains("lifts the universal optimum refined"));
    assert!(unrefined, "the unrefined optimum not lifted, said so: {:?}", spherical.skipped);
    let paper = solve(&WholeCat::new(Cat::equal(HALF, Joint::Universal)).expect("the paper's cat"));
    let least = |o: &super::super::WholeOutcome| o.best().expect("a best start").peak_torque_nm;
    assert!(least(&spherical) < least(&paper), "spherical {}, universal {}", least(&spherical), least(&paper));
    for s in spherical.solutions.iter().chain(&paper.solutions) {
        let interior = !s.log.is_empty() && s.log.iter().all(|l| l.objective == Objective::Peak && l.barrier.is_some());
        assert!(interior, "{}: every iteration the interior point's peak stage: {:?}", s.start, s.log);
    }
    let best = &paper.solutions[paper.best.expect("a best start")];
    assert!(best.flips(1e-8), "{}", best.reason);
    assert!(best.reason.contains("refined to"), "a refinement kept: {}", best.reason);
    // Each stage's first barrier: where μ rises, a new stage began.
    let barriers: Vec<f64> = best.log.iter().filter_map(|l| l.barrier).collect();
    let firsts: Vec<f64> =
        (0..barriers.len()).filter(|&i| i == 0 || barriers[i] > barriers[i - 1]).map(|i| barriers[i]).collect();
    assert_eq!(firsts, [super::FIRST_BARRIER, super::WARM_BARRIER], "{barriers:?}");
}

/// The default method, `auto`, plans the least peak by the interior point beyond two motors (a
/// barrier in every peak iteration's log, the lifted universal solve's too) and by the trust
/// region on two (no barrier anywhere): the choice README's "More motors" measures.
#[test]
fn the_default_method_is_the_interior_point_beyond_two_motors_only() {
    let settings = WholeSettings { control_points: 30, ..WholeSettings::default() };
    assert_eq!(settings.method, Method::Auto);
    let solve = |cat: &WholeCat| {
        optimize_whole(cat, fall(), &Manoeuvre::default(), &settings, &Motors::ideal(), 1e-8)
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let peak_barriers = |o: &super::super::WholeOutcome| -> Vec<bool> {
        let logs = o.solutions.iter().flat_map(|s| &s.log);
        logs.filter(|l| l.objective == Objective::Peak).map(|l| l.barrier.is_some()).collect()
    };
    let two = peak_barriers(&solve(&WholeCat::new(Cat::equal(HALF, Joint::Universal)).expect("two motors")));
    assert!(!two.is_empty() && two.iter().all(|b| !b), "two motors: the trust region's log");
    let three = WholeCat::spherical(Cat::equal(HALF, Joint::Spherical)).expect("three motors");
    let three = peak_barriers(&solve(&three));
    assert!(!three.is_empty() && three.iter().all(|&b| b), "three motors: the interior point's log");
}
