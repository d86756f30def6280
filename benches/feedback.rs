//! Criterion benches of the attitude feedback ([`catflip::engines::rapier::feedback`]) on the
//! paper's schedule at the tracked check's step (100 µs) and regulator rate (1 kHz): the LQR
//! gains re-solved from the middle of the fall and from the release (the backward Riccati
//! sweep alone), the linearisation along the plan it starts from (and the exact engine's
//! integration of the plan inside it), the re-plan of the rest of the fall from a state off the
//! plan (roll-out, re-linearisation, sweep and line search: issue 21 §3's "warm re-plan ≤ 10
//! ms"), and one tracked trial with feedback (without and with re-plans) against one open loop.
//!
//! Run with `cargo bench --bench feedback` (`-- replan` for the re-plan alone).

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Duration;

use catflip::engines::rapier::feedback::State;
use catflip::engines::rapier::{
    lqr_gains, track, AttitudeSensor, FeedForwardPd, Feedback, FeedbackPlan, FeedbackSettings, Linearisation, PdGains,
    Plan, RapierOptions, Regulator, TrackOptions,
};
use catflip::engines::spin::SpinHistory;
use catflip::model::motor::Motors;
use catflip::schedule::Trajectory;
use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use nalgebra::Vector3;

use common::paper;

fn feedback(c: &mut Criterion) {
    let (p, s) = paper();
    let n = (s.total_duration() / 1e-4).ceil() as usize;
    let plan = Plan::new(&p.cat.half(), &s, &Vector3::zeros(), p.exact.tolerance, n);
    let settings = FeedbackSettings {
        rate_hz: 1000.0,
        replan_hz: 0.0,
        attitude: 1f64.to_radians(),
        joint: 10f64.to_radians(),
        accel: 20.0,
        spin_prior: 0.01,
        sensor_noise: 0.5f64.to_radians(),
    };
    let fb = FeedbackPlan::new(&p.cat.half(), &s, &Vector3::zeros(), p.exact.tolerance, &plan, settings);
    let nodes = fb.linearisation.nodes.len();
    let mut g = c.benchmark_group("feedback/gains");
    g.sample_size(20).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    for (name, from) in [("from mid-fall", nodes / 2), ("from release", 0)] {
        g.bench_with_input(BenchmarkId::from_parameter(name), &from, |b, from| {
            b.iter(|| lqr_gains(&fb.linearisation, &settings, *from))
        });
    }
    g.bench_function("exact history (part of the linearisation)", |b| {
        b.iter(|| SpinHistory::new(&p.cat.half(), &s, &Vector3::zeros(), p.exact.tolerance))
    });
    g.bench_function("linearisation", |b| {
        b.iter(|| Linearisation::new(&p.cat.half(), &s, &Vector3::zeros(), p.exact.tolerance, &plan, 1000.0))
    });
    g.finish();

    // A state off the plan of the size a 2σ release spin leaves (the check's worst trials):
    // attitude error (−2.5°, −0.5°, 0.3°), joint corrections (5.9°, 1.1°) and their rates
    // (−5°/s, 30°/s), the spin estimate (0.0002, 0, 0.0138) N·m·s. The same state from every
    // node: the work of a re-plan is its remaining nodes', whatever the state.
    let deg = 1f64.to_radians();
    let x = State::from_column_slice(&[
        -2.5 * deg,
        -0.5 * deg,
        0.3 * deg,
        5.9 * deg,
        1.1 * deg,
        -5.0 * deg,
        30.0 * deg,
        0.0002,
        0.0,
        0.0138,
    ]);
    let plan_regulator = Regulator::of(&fb);
    let mut g = c.benchmark_group("feedback/replan");
    g.sample_size(30).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(5));
    for (name, from) in [("from mid-fall", nodes / 2), ("from a quarter", nodes / 4), ("from release", 0)] {
        g.bench_with_input(BenchmarkId::from_parameter(name), &from, |b, from| {
            b.iter_batched_ref(
                || plan_regulator.clone(),
                |r| r.replan(&fb.linearisation, &settings, *from, &x),
                BatchSize::LargeInput,
            )
        });
    }
    g.finish();

    let options = TrackOptions {
        cross_mass_fraction: p.rapier.cross_mass_fraction,
        pgs_iterations: RapierOptions::default().pgs_iterations,
        motors: Motors::ideal(),
        spin: Vector3::new(0.004, -0.003, 0.008),
        sensor: AttitudeSensor { latency: 0.01, noise: 0.5f64.to_radians(), seed: 1 },
        landing: None,
        keep_poses_at: Vec::new(),
    };
    let servo = PdGains::servo(&p.cat.half(), 10.0, 1.0);
    let mut g = c.benchmark_group("feedback/trial");
    g.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(5));
    g.bench_function("open loop", |b| {
        b.iter(|| track(&p.cat.half(), &plan, &mut FeedForwardPd::new(&plan, servo), &options))
    });
    g.bench_function("feedback", |b| {
        b.iter(|| track(&p.cat.half(), &plan, &mut Feedback::new(&plan, &fb, servo, &p.cat.half()), &options))
    });
    let replanning = FeedbackPlan { settings: FeedbackSettings { replan_hz: 50.0, ..settings }, ..fb.clone() };
    g.bench_function("feedback, re-planned at 50 Hz", |b| {
        b.iter(|| track(&p.cat.half(), &plan, &mut Feedback::new(&plan, &replanning, servo, &p.cat.half()), &options))
    });
    g.finish();
}

criterion_group!(benches, feedback);
criterion_main!(benches);
