//! Step 1 of the ladder: load a problem, resolve it once (its schedule and circulation) and
//! measure the schedule with the exact engine (zero angular momentum, DESIGN.md §2): the twist,
//! the swing and the peak joint torque. Every command measures every schedule this way, into one
//! noun, [`Measured`].
//!
//! `cargo run --release --example 01_simulate [PROBLEM.toml]` (default problems/paper.toml).
//! Next: `02_compare`.

use std::path::Path;

use catflip::prelude::*;

fn main() -> anyhow::Result<()> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "problems/paper.toml".to_string());
    let problem = Problem::load(Path::new(&path), &[])?;
    let resolved = Resolved::new(&problem)?;
    // Any cat model the problem file describes (`[cat] joint`, `[cat.front]`, `[cat.rear]`).
    let measured = resolved.measure(ScheduleName::Problem, resolved.schedule.clone());
    let e = &measured.exact;
    println!("{}: circulation {:.6} rad ({})", problem.name, resolved.circulation.radians, resolved.circulation.source);
    println!(
        "exact engine: twist {:+.4}°, swing {:.4}°, peak torque {:.4} N·m (integration converged: {})",
        e.twist_deg(),
        e.swing_deg(),
        e.peaks.max,
        e.flip.converged
    );
    // The paper's circulation π/C turns the default cat by about 174°, not 180° (DESIGN.md §3);
    // `circulation = "calibrated"` in the problem file asks for the one that turns it by 180°.
    Ok(())
}
