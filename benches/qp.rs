//! Run time of the profile QP (Clarabel) against its size, and of one linearised step.
//!
//! `cargo bench --bench qp`; one size: `cargo bench --bench qp -- 'profile_qp/large/100000'`.
//! Targets (the optimiser's issue): N = 2000 within 10 ms, N = 10⁵ within 2 s.
//! Criterion prints the median's confidence interval per size; the worst run is in
//! `target/criterion/<group>/<size>/new/sample.json` (README, "Tests and benchmarks").

use std::hint::black_box;
use std::time::Duration;

use catflip::optimize::conic::{QpSettings, QpStatus};
use catflip::optimize::qp::ProfileQp;
use catflip::optimize::refine::{solve_linearised_step, LinearisedStep, TorqueSample};
use catflip::problem::settings::Boundary;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode};

/// The paper's twist phase (60 % of the fall from 10 m), its `I*`, a circulation near `π/C`.
fn problem(nodes: usize) -> ProfileQp {
    ProfileQp {
        nodes,
        duration: 6.0 / 7.0,
        circulation: 3.7,
        inertia: 0.3342,
        boundary: Boundary::RestToRest,
        rate_limit: None,
        jerk_limit: None,
        smoothness: 0.0,
    }
}

/// Solves once and insists on a solution, so that a bench never times a failure.
fn solve(qp: &ProfileQp) -> f64 {
    let sol = qp.solve().expect("valid problem");
    assert_eq!(sol.status, QpStatus::Solved, "{qp:?}");
    sol.peak_torque.expect("solved")
}

fn rest_to_rest(c: &mut Criterion) {
    let mut small = c.benchmark_group("profile_qp/small");
    small.sample_size(30).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    for nodes in [200, 2000, 5000] {
        let qp = problem(nodes);
        small.bench_with_input(BenchmarkId::from_parameter(nodes), &qp, |b, qp| b.iter(|| solve(black_box(qp))));
    }
    small.finish();

    let mut large = c.benchmark_group("profile_qp/large");
    large
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(15));
    for nodes in [20_000, 100_000] {
        let qp = problem(nodes);
        large.bench_with_input(BenchmarkId::from_parameter(nodes), &qp, |b, qp| b.iter(|| solve(black_box(qp))));
    }
    large.finish();
}

fn with_limits(c: &mut Criterion) {
    // Every row type at once: rate, jerk (with zero end acceleration) and smoothness.
    let (t, d) = (6.0 / 7.0, 3.7);
    let qp = ProfileQp {
        rate_limit: Some(1.6 * d / t),
        jerk_limit: Some(80.0 * d / (t * t * t)),
        smoothness: 1e-6,
        ..problem(2000)
    };
    let mut group = c.benchmark_group("profile_qp/limits");
    group.sample_size(30).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    group.bench_with_input(BenchmarkId::from_parameter(2000), &qp, |b, qp| b.iter(|| solve(black_box(qp))));
    group.finish();
}

fn linearised_step(c: &mut Criterion) {
    // Samples as the exact refinement makes them: two per interval end, each depending on the
    // node's rate, its interval's acceleration, and (through φ) every earlier node: O(N²) nonzeros.
    let nodes = 200;
    let (t, d) = (6.0 / 7.0, 3.7);
    let h = t / (nodes - 1) as f64;
    let rates: Vec<f64> = (0..nodes)
        .map(|k| d / t * (1.0 - (2.0 * std::f64::consts::PI * k as f64 / (nodes - 1) as f64).cos()))
        .collect();
    let mut samples = Vec::new();
    for i in 0..nodes - 1 {
        for k in [i, i + 1] {
            for joint in 0..2 {
                let weight = 0.1 * (joint + 1) as f64;
                let mut gradient: Vec<(usize, f64)> = (0..=k).map(|m| (m, weight * h)).collect();
                gradient.extend([(i + 1, 0.33 / h), (i, -0.33 / h), (k, weight)]);
                let value = 0.33 * (rates[i + 1] - rates[i]) / h + weight * rates[k];
                samples.push(TorqueSample { value, gradient });
            }
        }
    }
    let step = LinearisedStep {
        rates: &rates,
        samples: &samples,
        trust_radius: 0.25 * d / t,
        duration: t,
        circulation: d,
        boundary: Boundary::RestToRest,
        rate_limit: None,
        jerk_limit: None,
    };
    let settings = QpSettings::default();
    let mut group = c.benchmark_group("linearised_step");
    group.sample_size(20).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(2));
    group.bench_function(BenchmarkId::from_parameter(nodes), |b| {
        b.iter(|| {
            let sol = solve_linearised_step(black_box(&step), &settings).expect("valid step");
            assert_eq!(sol.status, QpStatus::Solved);
            sol.predicted_peak
        })
    });
    group.finish();
}

criterion_group!(benches, rest_to_rest, with_limits, linearised_step);
criterion_main!(benches);
