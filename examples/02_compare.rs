//! Step 2: the same joint path timed by every library profile. Twist and swing are the path's
//! (a geometric phase: the timing does not change them); the peak torque is the timing's.
//!
//! `cargo run --release --example 02_compare [PROBLEM.toml]`. Next: `03_optimize`.

use std::path::Path;

use catflip::prelude::*;

fn main() -> anyhow::Result<()> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "problems/paper.toml".to_string());
    let resolved = Resolved::new(&Problem::load(Path::new(&path), &[])?)?;
    println!("| profile | twist ° | swing ° | peak torque N·m |\n|---|---:|---:|---:|");
    // Each library schedule measured once, on first use, and shared by every command.
    for (_, m) in resolved.library() {
        let e = &m.exact;
        println!("| {} | {:+.4} | {:.4} | {:.4} |", m.name, e.twist_deg(), e.swing_deg(), e.peak());
    }
    Ok(())
}
