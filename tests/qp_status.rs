//! The profile QP reports a result that does not exist as a status or a typed error in words,
//! never as NaN (issue 9, "NaN or no end, exit 0").
#![deny(clippy::float_cmp)]

use catflip::optimize::conic::{QpSettings, QpStatus};
use catflip::optimize::qp::{ProfileQp, QpError};
use catflip::problem::settings::Boundary;
use catflip::problem::Problem;

/// The paper's twist phase: T = 0.6 √(2 · 10/9.8) s, D = π/C = 3.2249860792499017 rad (the
/// circulation `catflip simulate problems/paper.toml --json` reports), I* of the default cat.
fn paper_qp() -> ProfileQp {
    let p = Problem::default();
    let t2 = 0.6 * p.drop.fall_time();
    ProfileQp::new(&p.optimize, t2, 3.2249860792499017, p.cat.half().end_transverse())
}

fn message(qp: ProfileQp) -> String {
    match qp.solve() {
        Ok(sol) => panic!("expected an error, got {sol:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_jerk_limit_below_what_the_move_needs_is_infeasible_in_words() {
    // 32 D/T³ = 32 · 3.22498607925 / 0.857142857³ = 163.877 rad/s³ (Biagiotti & Melchiorri §3.4).
    assert_eq!(
        message(ProfileQp { jerk_limit: Some(85.0), ..paper_qp() }),
        "optimize.jerk_limit = 85: infeasible: the jerk limit 85 rad/s³ is below the 163.877 rad/s³ this move needs (32|D|/T³: bang-bang jerk over quarters of the phase)"
    );
    // Start-at-rest needs a quarter of it: 8 D/T³ = 40.9693 rad/s³.
    assert_eq!(
        message(ProfileQp { jerk_limit: Some(40.0), boundary: Boundary::StartAtRest, ..paper_qp() }),
        "optimize.jerk_limit = 40: infeasible: the jerk limit 40 rad/s³ is below the 40.9693 rad/s³ this move needs (8|D|/T³: bang-bang jerk over halves of the phase)"
    );
    // Just above the continuum bound the QP solves.
    let sol = ProfileQp { jerk_limit: Some(1.2 * 163.877), ..paper_qp() }.solve().expect("feasible");
    assert_eq!(sol.status, QpStatus::Solved);
}

#[test]
fn a_rate_limit_below_the_mean_rate_is_infeasible_in_words() {
    // |D|/(T(1 − 1/(N−1))) with N = 200: 3.78149 rad/s.
    assert_eq!(
        message(ProfileQp { rate_limit: Some(3.0), ..paper_qp() }),
        "optimize.rate_limit = 3: infeasible: the rate limit 3 rad/s is below the 3.78149 rad/s this move needs (rates bounded by R cover at most R·T(1 − 1/(N−1)) from rest to rest)"
    );
}

#[test]
fn a_limit_that_can_never_matter_is_refused_with_its_field() {
    assert_eq!(
        message(ProfileQp { rate_limit: Some(1e20), ..paper_qp() }),
        "optimize.rate_limit = 1e20 rad/s is numerically meaningless: more than 10000 times the 3.78149 rad/s this move needs; leave it out for no limit"
    );
    assert_eq!(
        message(ProfileQp { jerk_limit: Some(1e20), ..paper_qp() }),
        "optimize.jerk_limit = 1e20 rad/s³ is numerically meaningless: more than 10000 times the 163.877 rad/s³ this move needs; leave it out for no limit"
    );
    // At the factor itself the limit is kept and the QP solves with finite peaks.
    let sol = ProfileQp { rate_limit: Some(1e4 * 3.7814), ..paper_qp() }.solve().expect("accepted");
    assert!(sol.status.is_solved() && sol.peak_torque.is_some_and(f64::is_finite), "{sol:?}");
}

#[test]
fn a_solve_without_solution_has_no_peak_and_says_why_in_words() {
    let settings = QpSettings { max_iterations: 2, ..Default::default() };
    let sol = paper_qp().solve_with(&settings).expect("valid input");
    assert_eq!(sol.status, QpStatus::MaxIterations);
    assert_eq!(sol.peak_torque, None);
    assert_eq!(sol.objective, None);
    let e = sol.solved().expect_err("not solved");
    assert_eq!(e.to_string(), "the profile QP has no solution: stopped at the iteration limit before converging");
    assert!(matches!(e, QpError::NotSolved { status: QpStatus::MaxIterations }));
}

#[test]
fn statuses_read_as_words_not_variant_names() {
    assert_eq!(QpStatus::PrimalInfeasible.to_string(), "infeasible: no profile meets the constraints");
    assert_eq!(QpStatus::Solved.to_string(), "solved");
    assert_eq!(QpStatus::AlmostSolved.to_string(), "solved to reduced accuracy");
}

#[test]
fn optimize_refuses_an_infeasible_jerk_limit() {
    let mut p = Problem::default();
    p.optimize.jerk_limit = Some(85.0);
    let resolved = catflip::engines::resolved::Resolved::new(&p).expect("the paper's circulation");
    let e = catflip::optimize::optimize(&resolved).expect_err("no profile meets the limit");
    assert!(
        e.to_string()
            .starts_with("optimize.jerk_limit = 85: infeasible: the jerk limit 85 rad/s³ is below the 163.877 rad/s³"),
        "{e}"
    );
}
