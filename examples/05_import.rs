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
    let measured = resolved.own();
    let file = write_schedule(&problem, measured, &ExportOptions::default())?;
    let csv = std::env::temp_dir().join(format!("catflip-05_import-{}.csv", std::process::id()));
    std::fs::write(&csv, &file.csv)?;
    let imported = read_schedule(&csv)?;
    let rows = imported.rows;
    // Checked (units, ends, sampling) and measured as every schedule is.
    let read_back = catflip::measure::import::measure_import(&problem, imported)?;
    std::fs::remove_file(&csv)?;
    let (file_e, e) = (&read_back.measured.exact, &measured.exact);
    println!("{rows} rows read back from {}", csv.display());
    println!("twist {:+.6}° from the file, {:+.6}° from the schedule", file_e.twist_deg(), e.twist_deg());
    println!("peak torque {:.4} N·m from the file, {:.4} N·m from the schedule", file_e.peak(), e.peak());
    Ok(())
}
