//! Run time of the whole-manoeuvre optimisation on the paper's problem (issue 13: ≤ 2 s), grouped
//! by control points per joint: with every default start, and with the paper's start alone for
//! the peak and the energy objectives.
//!
//! `cargo bench --bench whole`; one size: `cargo bench --bench whole -- 'whole/peak/120'`.
//! Criterion prints the median's confidence interval per size; the worst run is in
//! `target/criterion/<group>/<size>/new/sample.json` (README, "Tests and benchmarks").

use std::hint::black_box;
use std::time::Duration;

use catflip::optimize::whole::{optimize_whole, Objective, StartKind, WholeSettings};
use catflip::problem::Problem;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode};

/// Solves once and insists on a converged flip, so that a bench never times a failure.
fn solve(problem: &Problem, settings: &WholeSettings) -> f64 {
    let outcome = optimize_whole(
        &problem.cat,
        problem.drop.fall_time(),
        &problem.manoeuvre,
        settings,
        &problem.actuator.motors(),
        1e-8,
    )
    .expect("valid settings");
    outcome.best().expect("a converged flip").peak_torque_nm
}

/// `settings` with `n` control points per joint (a coarse start no larger than the spline).
fn at(settings: &WholeSettings, n: usize) -> WholeSettings {
    WholeSettings {
        control_points: n,
        coarse_control_points: settings.coarse_control_points.map(|c| c.min(n)),
        ..settings.clone()
    }
}

fn paper(c: &mut Criterion) {
    let problem = Problem::default();
    let every = WholeSettings::default();
    let one = WholeSettings { starts: vec![StartKind::Paper], ..WholeSettings::default() };
    let energy = WholeSettings { objective: Objective::Energy, ..one.clone() };
    for (name, settings, sizes) in [
        ("whole/peak", &every, &[20, 60, 120][..]),
        ("whole/peak-one-start", &one, &[120]),
        ("whole/energy-one-start", &energy, &[120]),
    ] {
        let mut group = c.benchmark_group(name);
        group
            .sampling_mode(SamplingMode::Flat)
            .sample_size(10)
            .warm_up_time(Duration::from_secs(1))
            .measurement_time(Duration::from_secs(8));
        for &n in sizes {
            let s = at(settings, n);
            group.bench_with_input(BenchmarkId::from_parameter(n), &s, |b, s| b.iter(|| solve(black_box(&problem), s)));
        }
        group.finish();
    }
}

criterion_group!(benches, paper);
criterion_main!(benches);
