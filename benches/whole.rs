//! Run time of the whole-manoeuvre optimisation on the paper's problem (issue 13: ≤ 2 s), grouped
//! by control points per joint: with every default start, and with the paper's start alone for
//! the peak and the energy objectives; and the least fall time within motor limits (issue 20:
//! ≤ 2 s) with every default start, for the three motors of issue 20's targets; and the peak
//! optimum without and with the knot refinement where the torques switch (issue 20 §6: ≤ 1 s);
//! and the least peak of each cat model on the paper's cat (issue 22: ≤ 2 s per model): the
//! paper's halves on the universal, no-twist and spherical joints, and Kane and Scher's cat with
//! the tail of `problems/tail.toml` and the legs of `problems/legs.toml`, every default start (as
//! `compare-models` runs each row, without its verification), by each method of the peak's stage
//! (`optimize.whole.method`: the ids are `<method>/<cat>`; the default, `auto`, is the interior point
//! beyond two motors and the trust region on two).
//!
//! `cargo bench --bench whole`; one size: `cargo bench --bench whole -- 'whole/peak/120'`; the
//! models: `cargo bench --bench whole -- whole/models` (several minutes: ten solves of each, by each method).
//! Criterion prints the median's confidence interval per size; the worst run is in
//! `target/criterion/<group>/<size>/new/sample.json` (README, "Tests and benchmarks").

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use catflip::model::motor::{Motor, Motors};
use catflip::model::{Cat, Joint};
use catflip::optimize::whole::{optimize_whole, Method, Objective, StartKind, WholeCat, WholeSettings};
use catflip::problem::Problem;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode};

/// Solves once and insists on a converged flip, so that a bench never times a failure.
fn solve(problem: &Problem, settings: &WholeSettings) -> f64 {
    solve_with(problem, settings, &problem.actuator.motors())
}

/// [`solve`] with `motors`; returns the peak torque and the fall time's sum (both are results).
fn solve_with(problem: &Problem, settings: &WholeSettings, motors: &Motors) -> f64 {
    let outcome =
        optimize_whole(problem.cat.half(), problem.drop.fall_time(), &problem.manoeuvre, settings, motors, 1e-8)
            .expect("valid settings");
    let best = outcome.best().expect("a converged flip");
    best.peak_torque_nm + best.fall_time_s
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

/// Issue 20 §6: the paper's peak optimum on the uniform knots alone (0) and refined once where
/// the torques switch (1, the default), every default start.
fn refinements(c: &mut Criterion) {
    let problem = Problem::default();
    let mut group = c.benchmark_group("whole/peak-switch-refinements");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(8));
    for n in [0, 1] {
        let s = WholeSettings { switch_refinements: n, ..WholeSettings::default() };
        group.bench_with_input(BenchmarkId::from_parameter(n), &s, |b, s| b.iter(|| solve(black_box(&problem), s)));
    }
    group.finish();
}

fn min_time(c: &mut Criterion) {
    let problem = Problem::default();
    let settings = WholeSettings { objective: Objective::MinTime, ..WholeSettings::default() };
    let motor = |m: Motor| Motors { joints: [m; 2] };
    let cases = [
        ("torque", motor(Motor { torque: Some(0.5), ..Motor::default() })),
        ("torque-speed", motor(Motor { torque: Some(0.5), speed: Some(6.0), ..Motor::default() })),
        ("envelope", motor(Motor { envelope: Some((0.6, 12.0)), ..Motor::default() })),
    ];
    let mut group = c.benchmark_group("whole/min-time");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(10));
    for (name, motors) in &cases {
        group.bench_with_input(BenchmarkId::from_parameter(name), motors, |b, m| {
            b.iter(|| solve_with(black_box(&problem), &settings, m))
        });
    }
    group.finish();
}

/// Issue 22: the least peak of every cat model on the paper's cat, each with every default start
/// (the spherical joint's also from the universal joint's optimum lifted, by the trust region), by the trust-region
/// loop and by the interior-point method (`optimize.whole.method`); the result must be a
/// flip ([`WholeOutcome::best`](catflip::optimize::whole::WholeOutcome::best)).
fn models(c: &mut Criterion) {
    let problem = |name: &str| Problem::load(&Path::new("problems").join(name), &[]).expect("a committed problem");
    let paper = problem("paper.toml");
    let on = |joint: Joint| Cat { joint, ..paper.cat.model() };
    let appended = |p: &Problem| {
        WholeCat::appended(p.cat.model(), p.cat.appendages().expect("a validated problem"))
            .expect("a cat with appendages")
    };
    let (tail, legs) = (problem("tail.toml"), problem("legs.toml"));
    let cases = [
        ("universal", WholeCat::new(on(Joint::Universal)).expect("two motors"), &paper),
        ("no-twist", WholeCat::new(on(Joint::NoTwist)).expect("two motors"), &paper),
        ("spherical", WholeCat::spherical(on(Joint::Spherical)).expect("three motors"), &paper),
        ("no-twist-tail", appended(&tail), &tail),
        ("no-twist-legs", appended(&legs), &legs),
    ];
    let mut group = c.benchmark_group("whole/models");
    group.sampling_mode(SamplingMode::Flat).sample_size(10).warm_up_time(Duration::from_secs(1));
    for method in [Method::TrustRegion, Method::InteriorPoint] {
        for (name, cat, p) in &cases {
            let id = format!("{}/{name}", method.name());
            let settings = WholeSettings { method, ..p.optimize.whole.clone() };
            group.bench_with_input(BenchmarkId::from_parameter(id), cat, |b, cat| {
                b.iter(|| {
                    let outcome = optimize_whole(
                        black_box(cat),
                        p.drop.fall_time(),
                        &p.manoeuvre,
                        &settings,
                        &Motors::ideal(),
                        p.exact.tolerance,
                    )
                    .expect("valid settings");
                    outcome.best().expect("a flip").peak_torque_nm
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, paper, refinements, min_time, models);
criterion_main!(benches);
