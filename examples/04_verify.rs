//! Step 4: check the exact engine with an independent one. rapier3d-f64 simulates the two
//! cylinders (equal or unequal halves) and the universal joint as a multibody driven by motors, at a sequence of time steps, and
//! judges twist, swing and peak torque against the exact engine's (DESIGN.md §6).
//!
//! `cargo run --release --example 04_verify [PROBLEM.toml]`. Next: `05_import`.

use std::path::Path;

use catflip::prelude::*;

fn main() -> anyhow::Result<()> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "problems/paper.toml".to_string());
    let problem = Problem::load(Path::new(&path), &[])?;
    let resolved = Resolved::new(&problem)?;
    // The exact engine's numbers on the problem's cat (equal or unequal halves), then rapier's
    // check of them: the step halved until rapier's own error estimate meets `[rapier]`.
    let mut measured = resolved.measure(ScheduleName::Problem, resolved.schedule.clone());
    measured.verify(resolved.rig())?;
    if let Some(v) = measured.verification() {
        let steps: Vec<String> = v.dt_sequence.iter().map(|dt| format!("{dt:.2e}")).collect();
        println!("rapier at dt = {} s: {}", steps.join(", "), v.verdict);
    }
    Ok(())
}
