//! Criterion benches of the exact engine: one evaluation of the paper's schedule (final
//! orientation only, at several tolerances), its peak torques, and a calibration.

use catflip::engines::calibrate::calibrate;
use catflip::engines::exact::flip;
use catflip::engines::torque::peak_torques;
use catflip::problem::Problem;
use catflip::schedule::{paper_circulation, Schedule};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn paper() -> (Problem, Schedule) {
    let p = Problem::default();
    let d = paper_circulation(&p.cat, p.manoeuvre.theta()).unwrap_or(std::f64::consts::PI);
    let s = Schedule::new(&p, d);
    (p, s)
}

fn exact(c: &mut Criterion) {
    let (p, s) = paper();
    let mut g = c.benchmark_group("exact_flip");
    for tol in [1e-6, 1e-9, 1e-10, 1e-12] {
        g.bench_with_input(BenchmarkId::from_parameter(format!("{tol:e}")), &tol, |b, &tol| {
            b.iter(|| flip(&p.cat, &s, tol))
        });
    }
    g.finish();
    c.bench_function("peak_torques_400_per_phase", |b| b.iter(|| peak_torques(&p.cat, &s, 400)));
    let mut g = c.benchmark_group("calibrate");
    g.sample_size(20);
    g.bench_function("paper_1e-10", |b| b.iter(|| calibrate(&p.cat, &s, 1e-10)));
    g.finish();
}

criterion_group!(benches, exact);
criterion_main!(benches);
