//! Criterion benches grouped by size: the calibration by twist tolerance and by circulation
//! (more turns, more steps), and the peak-torque search by circulation (the sampling grows with
//! the radians the bend direction turns, `engines::torque::piece_samples`).
//!
//! Run with `cargo bench --bench calibration`; criterion reports the median with its
//! confidence interval per size; the worst run is in
//! `target/criterion/<group>/<size>/new/sample.json` (README, "Tests and benchmarks").

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Duration;

use catflip::engines::calibrate::calibrate;
use catflip::engines::torque::{peak_torques_on, piece_samples};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

use common::paper;

fn calibration(c: &mut Criterion) {
    let (p, s) = paper();
    let mut g = c.benchmark_group("calibrate_by_tolerance");
    g.sample_size(20).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(2));
    for tol in [1e-4, 1e-7, 1e-10] {
        g.bench_with_input(BenchmarkId::from_parameter(format!("{tol:e}")), &tol, |b, &tol| {
            b.iter(|| calibrate(&p.cat.half(), &s, tol))
        });
    }
    g.finish();
    let mut g = c.benchmark_group("calibrate_by_circulation");
    g.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    for turns in [1.0, 4.0, 10.0] {
        let start = s.with_circulation(turns * s.circulation);
        g.bench_with_input(BenchmarkId::from_parameter(format!("{:.1} rad", start.circulation)), &start, |b, st| {
            b.iter(|| calibrate(&p.cat.half(), st, 1e-10))
        });
    }
    g.finish();
    let mut g = c.benchmark_group("peak_torques_by_circulation");
    g.sample_size(20).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(2));
    for d in [s.circulation, 28.0, 100.0] {
        let sch = s.with_circulation(d);
        let n = piece_samples(&sch, p.exact.torque_samples);
        g.bench_with_input(BenchmarkId::from_parameter(format!("{d:.1} rad")), &(sch, n), |b, (sch, n)| {
            b.iter(|| peak_torques_on(&p.cat.half(), sch, n))
        });
    }
    g.finish();
}

criterion_group!(benches, calibration);
criterion_main!(benches);
