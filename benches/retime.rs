//! Run time of the certified convex retiming of the paper's whole schedule (three pieces, each
//! on a grid of `N` intervals, along its progress-variable path): sampling the path, the SOCP
//! (Clarabel) and the reconstruction.
//!
//! `cargo bench --bench retime`; one size: `cargo bench --bench retime -- 'retime/kept/200'`.
//! Target (issue 13): the convex retiming of a whole schedule within 1 s.
//! Criterion prints the median's confidence interval per grid size; the worst run is in
//! `target/criterion/<group>/<size>/new/sample.json` (README, "Tests and benchmarks").

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;
use std::time::Duration;

use catflip::optimize::retime::{retime_schedule, RetimeSettings, Split};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode};

use common::paper;

fn whole_schedule(c: &mut Criterion) {
    let (p, s) = paper();
    for (name, split) in [("retime/kept", Split::Kept), ("retime/free", Split::Free)] {
        let mut group = c.benchmark_group(name);
        group
            .sample_size(10)
            .sampling_mode(SamplingMode::Flat)
            .warm_up_time(Duration::from_secs(1))
            .measurement_time(Duration::from_secs(3));
        for n in [50, 100, 200, 400, 800] {
            let settings = RetimeSettings { intervals: n, split, ..RetimeSettings::default() };
            group.bench_with_input(BenchmarkId::from_parameter(n), &settings, |b, settings| {
                b.iter(|| {
                    let r = retime_schedule(&p.cat.half(), black_box(&s), *settings).expect("valid problem");
                    assert!(r.solution.status.is_solved(), "{}", r.solution.status);
                    r.solution.peak
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, whole_schedule);
criterion_main!(benches);
