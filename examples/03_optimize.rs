//! Step 3: lower the peak torque. The certified retiming keeps the schedule's path and retimes
//! it (a second-order cone program; its dual gives a lower bound no timing of that path beats),
//! the whole-manoeuvre optimiser changes the path too (successive convexification on a B-spline).
//!
//! `cargo run --release --example 03_optimize [PROBLEM.toml]`. Next: `04_verify`.

use std::path::Path;

use catflip::prelude::*;

fn main() -> anyhow::Result<()> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "problems/paper.toml".to_string());
    let problem = Problem::load(Path::new(&path), &[])?;
    let resolved = Resolved::new(&problem)?;
    let own = resolved.own();
    println!("the problem's schedule: peak torque {:.4} N·m", own.exact.peak());

    let retimed = retime_schedule(&problem.cat.half(), &resolved.schedule, RetimeSettings::default())?;
    let s = &retimed.solution;
    println!("retimed along its path: {}, peak {:.4} N·m, certified bound {:.4} N·m", s.status, s.peak, s.lower_bound);

    let whole = optimize_whole(
        problem.cat.half(),
        problem.drop.fall_time(),
        &problem.manoeuvre,
        &problem.optimize.whole,
        &problem.actuator.motors(),
        problem.exact.tolerance,
    )?;
    match whole.best() {
        Some(b) => {
            // The optimum measured as every schedule is.
            let optimum = resolved.measure(ScheduleName::WholeOptimum, b.spline.clone());
            println!(
                "whole manoeuvre ({} start): peak {:.4} N·m, twist {:+.4}°, {:.0}× below the problem's schedule",
                b.start,
                optimum.exact.peak(),
                optimum.exact.twist_deg(),
                own.exact.peak() / optimum.exact.peak()
            )
        }
        None => println!("whole manoeuvre: no start converged to a flip"),
    }
    Ok(())
}
