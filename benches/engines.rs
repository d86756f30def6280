//! Criterion benches of the exact engine on the paper's schedule, grouped by size: the adaptive
//! flip by tolerance, the fixed-step sixth-order Magnus integration by steps per phase, and the
//! peak-torque search by samples per phase. (The calibration is in `benches/calibration.rs`.)
//!
//! `cargo bench --bench engines`; one size: `cargo bench --bench engines -- 'exact/adaptive/1e-9'`.
//! Criterion prints the median's confidence interval per size; the worst run is in
//! `target/criterion/<group>/<size>/new/sample.json` (README, "Tests and benchmarks").

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Duration;

use catflip::engines::exact::{flip, integrate};
use catflip::engines::torque::peak_torques;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

use common::paper;

fn exact(c: &mut Criterion) {
    let (p, s) = paper();
    let mut g = c.benchmark_group("exact/adaptive");
    g.sample_size(30).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(2));
    for tol in [1e-6, 1e-9, 1e-12] {
        g.bench_with_input(BenchmarkId::from_parameter(format!("{tol:e}")), &tol, |b, &tol| {
            b.iter(|| flip(&p.cat.half(), &s, tol))
        });
    }
    g.finish();
    let mut g = c.benchmark_group("exact/magnus6");
    g.sample_size(30).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(2));
    for steps in [16usize, 128, 1024] {
        g.bench_with_input(BenchmarkId::from_parameter(steps), &steps, |b, &n| {
            b.iter(|| integrate(&p.cat.half(), &s, n, |_| {}))
        });
    }
    g.finish();
    let mut g = c.benchmark_group("peak_torques");
    g.sample_size(30).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(2));
    for samples in [100usize, 400, 1600] {
        g.bench_with_input(BenchmarkId::from_parameter(samples), &samples, |b, &n| {
            b.iter(|| peak_torques(&p.cat.half(), &s, n))
        });
    }
    g.finish();
}

criterion_group!(benches, exact);
criterion_main!(benches);
