//! The Rust side of the Python package's call-overhead measurement (python/bench/simulate_10k.py):
//! `N` times the work of `catflip.simulate(problem, series=False)` — the exact engine's
//! `simulate` report on the resolved problem — and the same with its serialisation to JSON text
//! (which the Python call also does), timed per call. Timing only: it asserts nothing.
//!
//! `cargo run --release --example simulate_10k -- [PROBLEM [N]]` (defaults problems/paper.toml,
//! 10000); prints one JSON line.

use std::path::PathBuf;
use std::time::Instant;

use catflip::engines::resolved::Resolved;
use catflip::engines::Engine;
use catflip::problem::Problem;
use catflip::report::simulate::simulate;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().unwrap_or_else(|| "problems/paper.toml".into()));
    let n: usize = args.next().map_or(Ok(10_000), |a| a.parse())?;
    let r = Resolved::new(&Problem::load(&path, &[])?)?;
    let start = Instant::now();
    for _ in 0..n {
        std::hint::black_box(simulate(&r, Engine::Exact)?);
    }
    let bare = start.elapsed().as_secs_f64();
    let start = Instant::now();
    for _ in 0..n {
        std::hint::black_box(serde_json::to_string(&simulate(&r, Engine::Exact)?)?);
    }
    let with_json = start.elapsed().as_secs_f64();
    println!(
        "{{\"problem\": {:?}, \"calls\": {n}, \"rust_s\": {bare}, \"rust_per_call_s\": {}, \"rust_json_s\": {with_json}, \"rust_json_per_call_s\": {}}}",
        path.display().to_string(),
        bare / n as f64,
        with_json / n as f64
    );
    Ok(())
}
