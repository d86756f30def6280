//! Criterion benches of the rapier verification: one run of the paper's schedule (the whole
//! measurement: twist, momentum, torques) at 1 kHz and 2 kHz, and, to separate rapier's own cost
//! from ours, the bare stepping of the scene over the same schedule at 1 kHz.
//!
//! Run with `cargo bench --bench rapier`; grouped by step rate. Criterion prints the median's
//! confidence interval per size; the worst run is in
//! `target/criterion/<group>/<size>/new/sample.json` (README, "Tests and benchmarks").

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Duration;

use catflip::engines::models::TwoMotorCat;
use catflip::engines::rapier::{simulate, CatScene, MotorGains, RapierOptions};
use catflip::model::Cat;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

use common::paper;

fn rapier(c: &mut Criterion) {
    let (p, s) = paper();
    let mut g = c.benchmark_group("rapier/simulate");
    g.sample_size(20).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(4));
    for rate in [500.0, 1000.0, 2000.0] {
        let settings = p.rapier.with_dt(1.0 / rate);
        g.bench_with_input(BenchmarkId::from_parameter(format!("{rate} Hz")), &settings, |b, st| {
            b.iter(|| simulate(&TwoMotorCat::paper(p.cat.half()), &s, st))
        });
    }
    g.finish();
    // The scene alone: targets from the schedule and one rapier step per millisecond.
    let n = (s.duration() / 1e-3).ceil() as usize;
    let dt = s.duration() / n as f64;
    let opts = RapierOptions::default();
    let gains = MotorGains::new(opts.bandwidth_per_step / dt, opts.damping_ratio);
    let mut g = c.benchmark_group("rapier/steps_only");
    g.sample_size(20).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    g.bench_function(BenchmarkId::from_parameter("1000 Hz"), |b| {
        b.iter(|| {
            let mut scene = CatScene::new(
                &Cat::from(p.cat.half()),
                p.rapier.cross_mass_fraction,
                dt,
                opts.pgs_iterations,
                Some(gains),
                [0.0; 2],
            )?;
            for k in 1..=n {
                let st = s.state(k as f64 * dt);
                scene.set_targets([st.q[0] - dt * st.qd[0], st.q[1] - dt * st.qd[1]], st.qd)?;
                scene.step();
            }
            scene.snapshot()
        })
    });
    g.finish();
}

criterion_group!(benches, rapier);
criterion_main!(benches);
