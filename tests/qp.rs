//! The profile QP and the refinement's linearised step against closed forms (module docs of
//! `catflip::optimize::qp` and `catflip::optimize::refine`'s step).
//!
//! Every reference value below is exact for the discrete problem unless a test says otherwise;
//! the tolerances are Clarabel's (gap and feasibility 1e-8 on an order-one problem).

#![deny(clippy::float_cmp)]

use approx::assert_relative_eq;
use catflip::optimize::conic::{ConicError, QpSettings, QpStatus};
use catflip::optimize::qp::{ProfileQp, ProfileQpSolution, QpError};
use catflip::optimize::refine::{solve_linearised_step, LinearisedStep, TorqueSample};
use catflip::problem::settings::{Boundary, OptimizeSettings};
use proptest::prelude::*;

/// A twist phase of the paper's size: 60 % of the fall from 10 m at g = 9.8 (√(20/9.8) = 10/7 s), the
/// paper's `I*` (§7), and a
/// circulation near its `π/C`.
const T: f64 = 6.0 / 7.0;
const D: f64 = 3.7;
const INERTIA: f64 = 0.3342;

fn qp(nodes: usize, boundary: Boundary) -> ProfileQp {
    ProfileQp {
        nodes,
        duration: T,
        circulation: D,
        inertia: INERTIA,
        boundary,
        rate_limit: None,
        jerk_limit: None,
        smoothness: 0.0,
    }
}

fn solved(problem: &ProfileQp) -> ProfileQpSolution {
    let sol = problem.solve().unwrap_or_else(|e| panic!("{problem:?}: {e}"));
    assert_eq!(sol.status, QpStatus::Solved, "{problem:?}: {:?}", sol.info);
    sol
}

/// The trapezoid integral of node rates over `[0, duration]`.
fn trapezoid(rates: &[f64], duration: f64) -> f64 {
    let h = duration / (rates.len() - 1) as f64;
    rates.windows(2).map(|w| 0.5 * h * (w[0] + w[1])).sum()
}

/// The bang-bang peak `4 D I*/T²` (DESIGN.md §5).
fn bang_bang() -> f64 {
    4.0 * D * INERTIA / (T * T)
}

#[test]
fn rest_to_rest_with_odd_nodes_is_the_bang_bang_triangle() {
    // N odd: the triangle v_k = 4 ĥ min(k, N−1−k) meets the integral exactly, c = 4.
    for n in [3, 5, 11, 101, 1001, 4001] {
        let sol = solved(&qp(n, Boundary::RestToRest));
        assert_relative_eq!(sol.peak_torque.expect("solved"), bang_bang(), max_relative = 1e-7);
        assert_relative_eq!(sol.objective.expect("solved"), bang_bang(), max_relative = 1e-7);
        let h = 1.0 / (n - 1) as f64;
        for (k, w) in sol.rates.iter().enumerate() {
            let triangle = D / T * 4.0 * h * (k.min(n - 1 - k) as f64);
            assert!((w - triangle).abs() < 1e-6 * D / T, "N = {n}, node {k}: {w} against {triangle}");
        }
        assert_relative_eq!(trapezoid(&sol.rates, T), D, max_relative = 1e-8);
    }
}

#[test]
fn rest_to_rest_with_even_nodes_shares_the_top_between_two_nodes() {
    // N even (n = N−1 odd intervals): the best rates are c ĥ² min(k, n−k) per unit c, whose
    // trapezoid sum is c (n² − 1)/(4n²); the integral one needs c = 4n²/(n² − 1).
    for n in [4, 6, 10, 100, 1000] {
        let sol = solved(&qp(n, Boundary::RestToRest));
        let intervals = (n - 1) as f64;
        let expected = bang_bang() * intervals.powi(2) / (intervals.powi(2) - 1.0);
        assert_relative_eq!(sol.peak_torque.expect("solved"), expected, max_relative = 1e-7);
        // The two middle nodes hold the same, highest rate.
        let (a, b) = (sol.rates[n / 2 - 1], sol.rates[n / 2]);
        assert!((a - b).abs() < 1e-7 * a, "N = {n}: middle rates {a} and {b} differ");
    }
}

#[test]
fn start_at_rest_accelerates_over_the_whole_phase() {
    // v_k = 2 k ĥ: trapezoid sum exactly 1 for every N, so c = 2, and ω ends at 2D/T.
    for n in [4, 5, 50, 501, 2000] {
        let sol = solved(&qp(n, Boundary::StartAtRest));
        assert_relative_eq!(sol.peak_torque.expect("solved"), 2.0 * D * INERTIA / (T * T), max_relative = 1e-7);
        assert_relative_eq!(sol.rates[n - 1], 2.0 * D / T, max_relative = 1e-7);
        assert!(sol.rates[0].abs() < 1e-9 * D / T, "N = {n}: ω₀ = {}", sol.rates[0]);
    }
}

#[test]
fn a_rate_limit_below_the_mean_rate_is_infeasible() {
    // The trapezoid integral of rates bounded by R is below R·T: R ≤ D/T cannot reach D.
    for boundary in [Boundary::RestToRest, Boundary::StartAtRest] {
        for fraction in [0.5, 0.9, 1.0] {
            // Refused up front by the closed-form bound (ProfileQp::feasibility).
            let problem = ProfileQp { rate_limit: Some(fraction * D / T), ..qp(201, boundary) };
            match problem.solve() {
                Err(QpError::Infeasible { given, needed, .. }) => assert!(given < needed),
                other => panic!("{boundary:?}, R = {fraction} D/T: expected Infeasible, got {other:?}"),
            }
        }
    }
}

#[test]
fn a_rate_limit_of_three_halves_the_mean_gives_the_trapezoid_of_thirds() {
    // With R = 3D/(2T) and N−1 divisible by 3, the ramp of slope 4.5 D/T² reaches R exactly at
    // the thirds and the trapezoid sum is exactly 1: c = 9/2, DESIGN.md §3's trapezoid value.
    for n in [31, 301] {
        let limit = 1.5 * D / T;
        let sol = solved(&ProfileQp { rate_limit: Some(limit), ..qp(n, Boundary::RestToRest) });
        assert_relative_eq!(sol.peak_torque.expect("solved"), 4.5 * D * INERTIA / (T * T), max_relative = 1e-7);
        let top = sol.rates.iter().fold(0.0, |m: f64, w| m.max(w.abs()));
        assert!(top <= limit * (1.0 + 1e-8), "N = {n}: max ω = {top} above the limit {limit}");
    }
}

/// The largest `|Δ²ω|/h²` of the rates, counting the ends as from zero acceleration.
fn peak_jerk(rates: &[f64], duration: f64) -> f64 {
    let h = duration / (rates.len() - 1) as f64;
    let mut accel = vec![0.0];
    accel.extend(rates.windows(2).map(|w| (w[1] - w[0]) / h));
    accel.push(0.0);
    accel.windows(2).map(|a| (a[1] - a[0]).abs() / h).fold(0.0, f64::max)
}

#[test]
fn a_jerk_limit_raises_the_peak_and_is_met() {
    // Continuum S-curve (module docs): c = Ĵ/4 − √(Ĵ²/16 − 2Ĵ); Ĵ = 64 gives 16 − √128.
    let scaled = 64.0;
    let jerk = scaled * D / T.powi(3);
    let s_curve = (16.0 - 128f64.sqrt()) * D * INERTIA / (T * T);
    let mut previous = f64::INFINITY;
    for n in [101, 401, 1601, 6401] {
        let sol = solved(&ProfileQp { jerk_limit: Some(jerk), ..qp(n, Boundary::RestToRest) });
        assert!(
            sol.peak_torque.expect("solved") > bang_bang() * 1.1,
            "N = {n}: the peak {} did not rise",
            sol.peak_torque.expect("solved")
        );
        // Met to Clarabel's feasibility tolerance, absolute on the rows (change of acceleration
        // per step, normalised): about 1e-8 of the order-ten norms, 1e-7 D/T² per step.
        let measured = peak_jerk(&sol.rates, T);
        let slack = 1e-7 * D / T.powi(2) / (T / (n - 1) as f64);
        assert!(measured <= jerk + slack, "N = {n}: jerk {measured} above the limit {jerk}");
        // The discrete optimum tends to the continuum S-curve at first order in h: its piecewise
        // constant acceleration runs half a step ahead of the continuous ramp (measured: about
        // −2.5/N, i.e. −2.5 % at N = 101).
        let error = ((sol.peak_torque.expect("solved") - s_curve) / s_curve).abs();
        assert!(error < 3.0 / n as f64, "N = {n}: {error:e} from the S-curve");
        assert!(error < 0.5 * previous, "N = {n}: not converging ({error:e} against {previous:e})");
        previous = error;
    }
}

#[test]
fn a_jerk_limit_below_the_s_curve_minimum_is_infeasible() {
    // The continuum S-curve needs Ĵ ≥ 32 (pure triangular acceleration); Ĵ = 24 is short of it.
    let jerk = 24.0 * D / T.powi(3);
    let sol = ProfileQp { jerk_limit: Some(jerk), ..qp(201, Boundary::RestToRest) }.solve();
    assert!(matches!(sol, Err(QpError::Infeasible { .. })), "{sol:?}");
}

#[test]
fn a_tiny_smoothness_weight_keeps_the_peak_near_bang_bang() {
    // Rounding the switch over a width δ raises the peak by O(δ²) and costs λ∫jerk² = O(λ/δ):
    // the balance is δ ~ λ^{1/3}, a peak rise of order λ^{2/3}.
    let rise = |weight: f64| {
        let sol = solved(&ProfileQp { smoothness: weight, ..qp(401, Boundary::RestToRest) });
        sol.peak_torque.expect("solved") / bang_bang() - 1.0
    };
    for (weight, tolerance) in [(1e-10, 1e-7), (1e-8, 1e-4), (1e-6, 1e-3)] {
        let r = rise(weight);
        assert!((-1e-8..tolerance).contains(&r), "λ = {weight}: peak {r:e} above bang-bang");
    }
    // 100 times the weight: 100^{2/3} ≈ 21.5 times the rise (measured 21.3 at N = 401).
    let ratio = rise(1e-4) / rise(1e-6);
    assert!((12.0..35.0).contains(&ratio), "rise ratio {ratio} is not of order 100^(2/3)");
    // A large weight must smooth visibly: the interior jerk (the term penalises interior second
    // differences only) falls well below that of the bang-bang switch, 8 D/(T² h).
    let interior = |rates: &[f64]| {
        let h = T / (rates.len() - 1) as f64;
        rates.windows(3).map(|w| (w[2] - 2.0 * w[1] + w[0]).abs() / (h * h)).fold(0.0, f64::max)
    };
    let sharp = solved(&qp(401, Boundary::RestToRest));
    let smooth = solved(&ProfileQp { smoothness: 1e-3, ..qp(401, Boundary::RestToRest) });
    assert_relative_eq!(interior(&sharp.rates), 8.0 * D / T.powi(3) * 400.0, max_relative = 1e-5);
    assert!(interior(&smooth.rates) < 0.1 * interior(&sharp.rates));
}

#[test]
fn a_negative_circulation_mirrors_the_rates() {
    let up = solved(&qp(51, Boundary::RestToRest));
    let down = solved(&ProfileQp { circulation: -D, ..qp(51, Boundary::RestToRest) });
    assert_relative_eq!(down.peak_torque.expect("solved"), up.peak_torque.expect("solved"), max_relative = 1e-8);
    for (a, b) in up.rates.iter().zip(&down.rates) {
        assert!((a + b).abs() < 1e-8 * D / T, "{a} against {b}");
    }
}

#[test]
fn the_profile_of_the_solution_has_unit_circulation_and_the_node_rates() {
    let n = 41;
    let sol = solved(&qp(n, Boundary::RestToRest));
    let profile = sol.to_profile().expect("a solved QP has a profile");
    assert_relative_eq!(profile.at(1.0).position, 1.0, max_relative = 1e-12);
    assert!(profile.is_rest_to_rest() || sol.rates[0].abs() > 1e-12);
    for (k, w) in sol.rates.iter().enumerate() {
        let rate = profile.at(k as f64 / (n - 1) as f64).rate * D / T;
        assert!((rate - w).abs() < 1e-9 * D / T, "node {k}: profile {rate} against QP {w}");
    }
    assert_relative_eq!(profile.peak_accel_coefficient(), 4.0, max_relative = 1e-7);
}

#[test]
fn the_settings_carry_over_and_the_status_serialises_in_kebab_case() {
    let settings = OptimizeSettings { nodes: 77, rate_limit: Some(9.0), smoothness: 0.5, ..Default::default() };
    let problem = ProfileQp::new(&settings, T, D, INERTIA);
    assert_eq!((problem.nodes, problem.boundary, problem.rate_limit), (77, settings.boundary, Some(9.0)));
    assert_eq!(problem.jerk_limit, None);
    assert_relative_eq!(problem.smoothness, 0.5);
    let json = serde_json::to_value(QpStatus::PrimalInfeasible).expect("serialisable");
    assert_eq!(json, "primal-infeasible");
    let sol = solved(&qp(11, Boundary::RestToRest));
    let json = serde_json::to_value(&sol).expect("serialisable");
    for key in ["status", "rates", "peak_torque", "objective", "iterations", "solve_time_s", "duality_gap"] {
        assert!(json.get(key).is_some(), "{key} missing from {json}");
    }
}

#[test]
fn bad_input_names_the_field() {
    let cases: [(ProfileQp, &str); 6] = [
        (qp(2, Boundary::RestToRest), "nodes"),
        (ProfileQp { duration: f64::NAN, ..qp(11, Boundary::RestToRest) }, "duration"),
        (ProfileQp { circulation: 0.0, ..qp(11, Boundary::RestToRest) }, "circulation"),
        (ProfileQp { inertia: -1.0, ..qp(11, Boundary::RestToRest) }, "inertia"),
        (ProfileQp { rate_limit: Some(0.0), ..qp(11, Boundary::RestToRest) }, "rate_limit"),
        (ProfileQp { smoothness: f64::INFINITY, ..qp(11, Boundary::RestToRest) }, "smoothness"),
    ];
    for (problem, name) in cases {
        match problem.solve() {
            Err(QpError::Conic(ConicError::BadInput { field, .. })) => assert_eq!(field, name),
            other => panic!("{name}: expected BadInput, got {other:?}"),
        }
    }
    let bad_settings = QpSettings { tolerance: 0.0, ..Default::default() };
    assert!(matches!(
        qp(11, Boundary::RestToRest).solve_with(&bad_settings),
        Err(QpError::Conic(ConicError::BadInput { field: "tolerance", .. }))
    ));
}

#[test]
fn the_iteration_limit_is_reported_not_hidden() {
    let settings = QpSettings { max_iterations: 2, ..Default::default() };
    let sol = qp(101, Boundary::RestToRest).solve_with(&settings).expect("valid input");
    assert_eq!(sol.status, QpStatus::MaxIterations);
    assert_eq!(sol.rates.len(), 101);
    assert!(sol.to_profile().is_none());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// The peak scales as `I* |D| / T²` whatever the units (odd N: exactly 4 of them).
    #[test]
    fn the_bang_bang_peak_scales_with_inertia_circulation_and_time(
        duration in 0.05f64..20.0, circulation in -50.0f64..50.0, inertia in 1e-4f64..1e3, half in 1usize..150,
    ) {
        prop_assume!(circulation.abs() > 1e-3);
        let problem = ProfileQp { duration, circulation, inertia, ..qp(2 * half + 1, Boundary::RestToRest) };
        let sol = problem.solve().expect("valid input");
        prop_assert_eq!(sol.status, QpStatus::Solved);
        let expected = 4.0 * inertia * circulation.abs() / (duration * duration);
        prop_assert!((sol.peak_torque.expect("solved") / expected - 1.0).abs() < 1e-7, "{} against {}", sol.peak_torque.expect("solved"), expected);
    }
}

// ---- the linearised step ----

/// Torques of the model, exactly linear in the rates: τ_k = I* (ω_{k+1} − ω_k)/h.
fn model_samples(rates: &[f64], duration: f64) -> Vec<TorqueSample> {
    let g = INERTIA * (rates.len() - 1) as f64 / duration;
    rates
        .windows(2)
        .enumerate()
        .map(|(k, w)| TorqueSample { value: g * (w[1] - w[0]), gradient: vec![(k, -g), (k + 1, g)] })
        .collect()
}

fn step_problem<'a>(rates: &'a [f64], samples: &'a [TorqueSample], trust_radius: f64) -> LinearisedStep<'a> {
    LinearisedStep {
        rates,
        samples,
        trust_radius,
        duration: T,
        circulation: D,
        boundary: Boundary::RestToRest,
        rate_limit: None,
        jerk_limit: None,
    }
}

/// Cycloidal rates scaled by `scale`: rest to rest, circulation `scale · D`.
fn cycloidal(n: usize, scale: f64) -> Vec<f64> {
    (0..n).map(|k| scale * D / T * (1.0 - (2.0 * std::f64::consts::PI * k as f64 / (n - 1) as f64).cos())).collect()
}

#[test]
fn one_step_on_linear_torques_lands_on_the_bang_bang_optimum() {
    // The torques are exactly the model's, so the linearisation is exact: with a trust radius
    // wider than any move, one step solves the profile QP from any start.
    for (n, start) in [(51, cycloidal(51, 1.0)), (101, cycloidal(101, 0.3)), (75, vec![0.7; 75])] {
        let samples = model_samples(&start, T);
        let sol = solve_linearised_step(&step_problem(&start, &samples, 100.0 * D / T), &QpSettings::default())
            .expect("valid input");
        assert_eq!(sol.status, QpStatus::Solved, "N = {n}");
        let rates: Vec<f64> = start.iter().zip(&sol.step).map(|(w, d)| w + d).collect();
        let intervals = (n - 1) as f64;
        let expected =
            if n % 2 == 1 { bang_bang() } else { bang_bang() * intervals.powi(2) / (intervals.powi(2) - 1.0) };
        assert_relative_eq!(sol.predicted_peak, expected, max_relative = 1e-7);
        let peak = model_samples(&rates, T).iter().fold(0.0, |m: f64, s| m.max(s.value.abs()));
        assert_relative_eq!(peak, expected, max_relative = 1e-7);
        assert_relative_eq!(trapezoid(&rates, T), D, max_relative = 1e-8);
        assert!(rates[0].abs() < 1e-8 && rates[n - 1].abs() < 1e-8, "N = {n}: ends {} {}", rates[0], rates[n - 1]);
    }
}

#[test]
fn a_small_trust_radius_bounds_the_step_and_still_lowers_the_peak() {
    let start = cycloidal(61, 1.0);
    let samples = model_samples(&start, T);
    let current = samples.iter().fold(0.0, |m: f64, s| m.max(s.value.abs()));
    let radius = 0.02 * D / T;
    let sol =
        solve_linearised_step(&step_problem(&start, &samples, radius), &QpSettings::default()).expect("valid input");
    assert_eq!(sol.status, QpStatus::Solved);
    let largest = sol.step.iter().fold(0.0, |m: f64, d| m.max(d.abs()));
    assert!(largest <= radius * (1.0 + 1e-8), "step {largest} beyond the radius {radius}");
    assert!(sol.predicted_peak < current, "{} not below {current}", sol.predicted_peak);
    assert!(sol.predicted_peak > bang_bang(), "a short step cannot reach the optimum");
}

#[test]
fn a_trust_radius_too_small_to_reach_the_constraints_is_infeasible() {
    // The start has circulation 0.5 D; with |δ| ≤ 0.01 D/T the trapezoid integral moves by at
    // most 0.01 D, short of the 0.5 D missing.
    let start = cycloidal(41, 0.5);
    let samples = model_samples(&start, T);
    let sol = solve_linearised_step(&step_problem(&start, &samples, 0.01 * D / T), &QpSettings::default())
        .expect("valid input");
    assert_eq!(sol.status, QpStatus::PrimalInfeasible);
}

#[test]
fn the_step_meets_rate_and_jerk_limits_on_the_new_rates() {
    // Also a cross-check of the rest-to-rest profile QP, which solves on reversal-symmetric
    // profiles only, against the step QP, which does not: with exact linear torques and a wide
    // trust region they share the optimum, for odd and even N, with and without smoothing.
    for (n, smoothness) in [(91, 0.0), (90, 0.0), (90, 1e-6)] {
        let start = cycloidal(n, 1.0);
        let samples = model_samples(&start, T);
        let (rate, jerk) = (1.6 * D / T, 80.0 * D / T.powi(3));
        let problem = LinearisedStep {
            rate_limit: Some(rate),
            jerk_limit: Some(jerk),
            ..step_problem(&start, &samples, 10.0 * D / T)
        };
        let sol = solve_linearised_step(&problem, &QpSettings::default()).expect("valid input");
        assert_eq!(sol.status, QpStatus::Solved);
        let rates: Vec<f64> = start.iter().zip(&sol.step).map(|(w, d)| w + d).collect();
        let top = rates.iter().fold(0.0, |m: f64, w| m.max(w.abs()));
        assert!(top <= rate * (1.0 + 1e-8), "N = {n}: max ω {top} above {rate}");
        let slack = 1e-7 * D / T.powi(2) / (T / (n - 1) as f64); // as in a_jerk_limit_raises_the_peak_and_is_met
        assert!(peak_jerk(&rates, T) <= jerk + slack, "N = {n}: jerk {} above {jerk}", peak_jerk(&rates, T));
        if smoothness > 0.0 {
            // The step QP has no smoothness term: compare the smoothed profile QP with itself,
            // folded, through its own constraints and a peak no lower than the step's optimum.
            let smooth = solved(&ProfileQp {
                rate_limit: Some(rate),
                jerk_limit: Some(jerk),
                smoothness,
                ..qp(n, Boundary::RestToRest)
            });
            assert!(smooth.peak_torque.expect("solved") >= sol.predicted_peak * (1.0 - 1e-7));
            assert!(peak_jerk(&smooth.rates, T) <= jerk + slack);
            assert_relative_eq!(trapezoid(&smooth.rates, T), D, max_relative = 1e-8);
        } else {
            let direct =
                solved(&ProfileQp { rate_limit: Some(rate), jerk_limit: Some(jerk), ..qp(n, Boundary::RestToRest) });
            assert_relative_eq!(sol.predicted_peak, direct.peak_torque.expect("solved"), max_relative = 1e-6);
        }
    }
}

#[test]
fn a_gradient_naming_a_missing_node_is_rejected() {
    let start = cycloidal(11, 1.0);
    let samples = vec![TorqueSample { value: 1.0, gradient: vec![(11, 1.0)] }];
    let err = solve_linearised_step(&step_problem(&start, &samples, 1.0), &QpSettings::default());
    assert!(matches!(err, Err(ConicError::BadInput { field: "samples", .. })), "{err:?}");
    let err = solve_linearised_step(&step_problem(&start, &[], 1.0), &QpSettings::default());
    assert!(matches!(err, Err(ConicError::BadInput { field: "samples", .. })), "{err:?}");
    let err = solve_linearised_step(&step_problem(&start[..2], &samples, 1.0), &QpSettings::default());
    assert!(matches!(err, Err(ConicError::BadInput { field: "rates", .. })), "{err:?}");
}

/// Samples shaped like the exact refinement's: each depends on its node's rate, its interval's
/// acceleration, and on the angle φ_k = ∫ω through trapezoid weights on every earlier node.
/// `jitter` > 0 multiplies the m-th weight by 1 + m·jitter, which breaks the runs of equal
/// coefficients without changing the problem beyond round-off.
fn angle_samples(rates: &[f64], jitter: f64) -> Vec<TorqueSample> {
    let n = rates.len();
    let h = T / (n - 1) as f64;
    let mut out = Vec::new();
    for i in 0..n - 1 {
        for k in [i, i + 1] {
            let weight = |m: usize| if m == 0 || m == k { 0.5 * h } else { h } * (1.0 + m as f64 * jitter);
            let mut gradient: Vec<(usize, f64)> = (0..=k).map(|m| (m, 0.8 * weight(m))).collect();
            gradient.extend([(i + 1, INERTIA / h), (i, -INERTIA / h), (k, 0.05)]);
            let phi: f64 = (0..=k).map(|m| weight(m) * rates[m]).sum();
            let value = INERTIA * (rates[i + 1] - rates[i]) / h + 0.8 * phi + 0.05 * rates[k] - 1.0;
            out.push(TorqueSample { value, gradient });
        }
    }
    out
}

#[test]
fn dense_angle_gradients_give_the_same_step_as_their_prefix_sum_form() {
    // Runs of equal coefficients are rewritten on prefix sums of the step (exact); the jittered
    // copy has no runs and goes in as given. Both must reach the same predicted peak.
    let start = cycloidal(80, 1.0);
    let (runs, plain) = (angle_samples(&start, 0.0), angle_samples(&start, 1e-15));
    let peaks: Vec<f64> = [&runs, &plain]
        .iter()
        .map(|samples| {
            let sol = solve_linearised_step(&step_problem(&start, samples, 0.3 * D / T), &QpSettings::default())
                .expect("valid input");
            assert_eq!(sol.status, QpStatus::Solved);
            sol.predicted_peak
        })
        .collect();
    assert_relative_eq!(peaks[0], peaks[1], max_relative = 1e-7);
    let current = runs.iter().fold(0.0, |m: f64, s| m.max(s.value.abs()));
    assert!(peaks[0] < current, "no improvement: {} against {current}", peaks[0]);
}

#[test]
fn closed_form_peak_matches_the_solver() {
    // The closed forms of the qp module docs against Clarabel's optimum, odd and even N, both
    // boundaries; none is claimed once a limit is set.
    use catflip::optimize::qp::ProfileQp;
    use catflip::problem::settings::{Boundary, OptimizeSettings};
    for (nodes, boundary) in [(51, Boundary::RestToRest), (50, Boundary::RestToRest), (40, Boundary::StartAtRest)] {
        let s = OptimizeSettings { nodes, boundary, ..OptimizeSettings::default() };
        let qp = ProfileQp::new(&s, 0.8, 3.2, 0.33);
        let sol = qp.solve().expect("valid");
        let closed = qp.closed_form_peak().expect("no limits");
        assert!(
            (sol.peak_torque.expect("solved") / closed - 1.0).abs() < 1e-7,
            "N = {nodes}: {} vs {closed}",
            sol.peak_torque.expect("solved")
        );
    }
    let limited = OptimizeSettings { rate_limit: Some(10.0), ..OptimizeSettings::default() };
    assert!(ProfileQp::new(&limited, 0.8, 3.2, 0.33).closed_form_peak().is_none());
}
