//! The least peak of every cat model on the paper's cat by both methods of the peak's stage
//! (`optimize.whole.method`): the trust-region loop and the interior-point method, each with
//! every default start, as `cargo bench --bench whole -- whole/models` solves them: wall time,
//! the best start's status and re-measured peak, and each start's iterations.
//!
//! `cargo run --release --example whole_methods [CAT ...]` (cats: universal, no-twist,
//! spherical, tail, legs; all by default; about a minute in all on 2 cores).

use std::path::Path;
use std::time::Instant;

use catflip::model::motor::Motors;
use catflip::model::{Cat, Joint};
use catflip::optimize::whole::{optimize_whole, Method, WholeCat, WholeSettings};
use catflip::problem::Problem;

fn main() -> anyhow::Result<()> {
    let asked: Vec<String> = std::env::args().skip(1).collect();
    let problem = |name: &str| Problem::load(&Path::new("problems").join(name), &[]);
    let (paper, tail, legs) = (problem("paper.toml")?, problem("tail.toml")?, problem("legs.toml")?);
    let on = |joint: Joint| Cat { joint, ..paper.cat.model() };
    let appended = |p: &Problem| -> anyhow::Result<WholeCat> {
        let appendages = p.cat.appendages()?;
        WholeCat::appended(p.cat.model(), appendages).ok_or_else(|| anyhow::anyhow!("{}: no appendages", p.name))
    };
    let cases = [
        ("universal", WholeCat::new(on(Joint::Universal))?, &paper),
        ("no-twist", WholeCat::new(on(Joint::NoTwist))?, &paper),
        ("spherical", WholeCat::spherical(on(Joint::Spherical)).ok_or_else(|| anyhow::anyhow!("spherical"))?, &paper),
        ("tail", appended(&tail)?, &tail),
        ("legs", appended(&legs)?, &legs),
    ];
    println!("| cat | method | wall s | best start | status | peak N·m | iterations per start |");
    println!("|---|---|---:|---|---|---:|---|");
    for (name, cat, p) in &cases {
        if !asked.is_empty() && !asked.iter().any(|a| a == name) {
            continue;
        }
        for method in [Method::TrustRegion, Method::InteriorPoint] {
            let settings = WholeSettings { method, ..p.optimize.whole.clone() };
            let clock = Instant::now();
            let outcome =
                optimize_whole(cat, p.drop.fall_time(), &p.manoeuvre, &settings, &Motors::ideal(), p.exact.tolerance)?;
            let wall = clock.elapsed().as_secs_f64();
            let iterations: Vec<String> =
                outcome.solutions.iter().map(|s| format!("{} {}", s.start, s.iterations)).collect();
            match outcome.best() {
                Some(b) => println!(
                    "| {name} | {} | {wall:.2} | {} | {} | {:.6} | {} |",
                    method.name(),
                    b.start,
                    b.status,
                    b.peak_torque_nm,
                    iterations.join(", ")
                ),
                None => {
                    println!("| {name} | {} | {wall:.2} | no flip | | | {} |", method.name(), iterations.join(", "))
                }
            }
        }
    }
    Ok(())
}
