//! Every start of the spherical joint's whole optimum on the problem's halves (issue 22): the
//! library starts (the no-twist joint's, the relative twist held at zero) and the universal
//! joint's optimum lifted onto the spherical joint's coordinates, as found and refined
//! (`optimize::whole::lift`: by the default method, the interior point on three motors, the
//! refined universal optimum alone, the unrefined one a skipped start that says why; by the trust
//! region, `--set optimize.whole.method='"trust-region"'`, both), each with how it ended, and the
//! starts not tried with why.
//! `compare-models` reports the best of them only.
//!
//! `cargo run --release --example spherical_starts [PROBLEM.toml] [--set KEY=VALUE ...]`
//! (default problems/paper.toml; e.g. `--set optimize.whole.control_points=40`).

use std::time::Instant;

mod common;

use catflip::model::motor::Motors;
use catflip::model::{Cat, Joint};
use catflip::optimize::whole::{optimize_whole, WholeCat};

fn main() -> anyhow::Result<()> {
    let (_, problem) = common::problem_from_args("problems/paper.toml")?;
    let cat = WholeCat::spherical(Cat { joint: Joint::Spherical, ..problem.cat.model() }).expect("a spherical cat");
    let settings = &problem.optimize.whole;
    let clock = Instant::now();
    let outcome = optimize_whole(
        &cat,
        problem.drop.fall_time(),
        &problem.manoeuvre,
        settings,
        &Motors::ideal(),
        problem.exact.tolerance,
    )?;
    println!("{}: {} ({:.2} s in all)", problem.name, cat.describe(), clock.elapsed().as_secs_f64());
    for (i, s) in outcome.solutions.iter().enumerate() {
        let best = if outcome.best == Some(i) { " (the best)" } else { "" };
        println!(
            "- {}{best}: {}, {} iterations, {:.2} s, peak {:.6} N·m: {}",
            s.start, s.status, s.iterations, s.seconds, s.peak_torque_nm, s.reason
        );
    }
    for k in &outcome.skipped {
        println!("- {} not tried: {}", k.start, k.reason);
    }
    Ok(())
}
