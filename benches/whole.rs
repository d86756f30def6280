//! Run time of the whole-manoeuvre optimisation on the paper's problem (issue 13: ≤ 2 s).
//!
//! `cargo bench --bench whole`; one start only: `cargo bench --bench whole -- 'whole/paper/one-start'`.

use std::hint::black_box;
use std::time::Duration;

use catflip::optimize::whole::{optimize_whole, Objective, StartKind, WholeSettings};
use catflip::problem::Problem;
use criterion::{criterion_group, criterion_main, Criterion, SamplingMode};

/// Solves once and insists on a converged flip, so that a bench never times a failure.
fn solve(problem: &Problem, settings: &WholeSettings) -> f64 {
    let outcome = optimize_whole(&problem.cat, problem.drop.fall_time(), &problem.manoeuvre, settings, 1e-8)
        .expect("valid settings");
    outcome.best().expect("a converged flip").peak_torque_nm
}

fn paper(c: &mut Criterion) {
    let problem = Problem::default();
    let mut group = c.benchmark_group("whole/paper");
    group.sampling_mode(SamplingMode::Flat).sample_size(10).measurement_time(Duration::from_secs(10));
    let every = WholeSettings::default();
    group.bench_function("peak/default-starts", |b| b.iter(|| solve(black_box(&problem), &every)));
    let one = WholeSettings { starts: vec![StartKind::Paper], ..WholeSettings::default() };
    group.bench_function("peak/one-start", |b| b.iter(|| solve(black_box(&problem), &one)));
    let energy = WholeSettings { objective: Objective::Energy, ..one.clone() };
    group.bench_function("energy/one-start", |b| b.iter(|| solve(black_box(&problem), &energy)));
    group.finish();
}

criterion_group!(benches, paper);
criterion_main!(benches);
