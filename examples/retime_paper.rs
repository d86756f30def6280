//! The certified retiming of the paper's schedule (problems/paper.toml), with the paper's and the
//! calibrated circulation, both duration splits, against the grid size.
//!
//! `cargo run --release --example retime_paper [N...]`

use std::path::Path;
use std::time::Instant;

use catflip::engines::calibrate::calibrate;
use catflip::engines::exact::flip;
use catflip::optimize::retime::{retime_schedule, RetimeSettings, Split};
use catflip::problem::Problem;
use catflip::schedule::{paper_circulation, Schedule};

fn main() -> anyhow::Result<()> {
    let problem = Problem::load(Path::new("problems/paper.toml"), &[])?;
    let cat = &problem.cat.half();
    let tol = problem.exact.tolerance;
    let paper = paper_circulation(cat, problem.manoeuvre.theta())?;
    let base = Schedule::new(&problem, paper);
    let calibrated = calibrate(cat, &base, tol).circulation;
    let sizes: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let sizes = if sizes.is_empty() { vec![25, 50, 100, 200, 400, 800] } else { sizes };
    println!("| circulation | split | N/piece | status | iters | SOCP peak | certified bound | gap | slowed timing's discrete peak | exact peak | exact − bound | durations s | twist change ° | swing change ° | solve ms | total ms |");
    println!("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|");
    for (name, circ) in [("paper", paper), ("calibrated", calibrated)] {
        let path = Schedule::new(&problem, circ);
        let original = flip(cat, &path, tol);
        for split in [Split::Kept, Split::Free] {
            for &n in &sizes {
                let settings = RetimeSettings { intervals: n, split, ..RetimeSettings::default() };
                let start = Instant::now();
                let r = retime_schedule(cat, &path, settings)?;
                let elapsed = start.elapsed().as_secs_f64();
                let s = &r.solution;
                let m = r.remeasure(cat, 16 * n, tol);
                let (exact, over, dt, ds) = m.as_ref().map_or((f64::NAN, f64::NAN, f64::NAN, f64::NAN), |m| {
                    (
                        m.peaks.max,
                        m.gap_to_bound,
                        (m.flip.twist - original.twist).to_degrees(),
                        (m.flip.swing - original.swing).to_degrees(),
                    )
                });
                let d: Vec<String> = s.durations().iter().map(|d| format!("{d:.4}")).collect();
                println!(
                    "| {name} | {split:?} | {n} | {} | {} | {:.7} | {:.7} | {:.1e} | {:.7} | {:.5} | {:.5} | {} | {:.1e} | {:.1e} | {:.1} | {:.1} |",
                    s.status,
                    s.iterations,
                    s.peak,
                    s.lower_bound,
                    s.gap,
                    s.discrete_peak,
                    exact,
                    over,
                    d.join(", "),
                    dt,
                    ds,
                    1e3 * s.solve_time_s,
                    1e3 * elapsed
                );
            }
        }
    }
    Ok(())
}
