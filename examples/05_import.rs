//! Step 5: a schedule as a file. The problem's schedule is written as a CSV (time, angles, rates,
//! accelerations, one row per sample), read back as any other program's schedule would be, and
//! measured again by the exact engine: the file keeps the flip.
//!
//! `cargo run --release --example 05_import [PROBLEM.toml]` (writes to the system's temp folder).

use std::path::Path;

use catflip::prelude::*;

fn main() -> anyhow::Result<()> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "problems/paper.toml".to_string());
    let problem = Problem::load(Path::new(&path), &[])?;
    let resolved = Resolved::new(&problem)?;
    let file = write_schedule(&problem, &resolved.schedule, "problem", &ExportOptions::default())?;
    let csv = std::env::temp_dir().join(format!("catflip-05_import-{}.csv", std::process::id()));
    std::fs::write(&csv, &file.csv)?;
    let imported = read_schedule(&csv)?;
    let report = catflip::exchange::evaluate(&problem, &imported)?;
    std::fs::remove_file(&csv)?;
    let e = Evaluation::new(
        &problem.cat.half(),
        &resolved.schedule,
        &problem.drop.spin(),
        &problem.actuator.motors(),
        &problem.exact,
    );
    println!("{} rows read back from {}", report.rows, csv.display());
    println!("twist {:+.6}° from the file, {:+.6}° from the schedule", report.figures.twist_deg, e.twist_deg());
    println!(
        "peak torque {:.4} N·m from the file, {:.4} N·m from the schedule",
        report.peak_torque_nm.max, e.peaks.max
    );
    Ok(())
}
