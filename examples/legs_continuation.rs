//! The whole optimum of a problem's cat with legs of two sizes (`[cat.legs.front]`,
//! `[cat.legs.rear]`) reached by continuation (issue 22): first the same cat with both pairs of
//! legs their mean pair, from the library starts, then the problem's cat from that optimum (refit
//! on the settings' uniform knots). On `problems/real-cat.toml` the library starts end in a
//! costlier basin (0.618 N·m, `compare-models`) and the continuation ends well below it, 0.519
//! N·m, with the halves folded onto each other (README, "A real cat"); with the starts bent by 80° (`--set manoeuvre.theta_deg=100`) the
//! mean pair finds no optimum, and the example says so and fails. Which start finds which basin
//! is the optimiser's exploration, not a property of the cat.
//!
//! `cargo run --release --example legs_continuation -- [PROBLEM.toml] [--set KEY=VALUE ...]`
//! (default problems/real-cat.toml).

use std::time::Instant;

mod common;

use catflip::model::cat::Appendages;
use catflip::model::motor::Motors;
use catflip::optimize::whole::{optimize_from, optimize_whole, NamedStart, WholeCat};

fn main() -> anyhow::Result<()> {
    let (path, problem) = common::problem_from_args("problems/real-cat.toml")?;
    let (settings, fall, tolerance) = (&problem.optimize.whole, problem.drop.fall_time(), problem.exact.tolerance);
    let appendages = problem.cat.appendages()?;
    let [front, rear] = appendages.legs.ok_or_else(|| anyhow::anyhow!("{path} has no [cat.legs]"))?;
    let mean = front.mean(&rear);
    let cat =
        |legs| WholeCat::appended(problem.cat.model(), Appendages { legs: Some(legs), ..appendages }).expect("legs");
    let clock = Instant::now();
    let mean_cat = cat([mean; 2]);
    let first = optimize_whole(&mean_cat, fall, &problem.manoeuvre, settings, &Motors::ideal(), tolerance)?;
    let Some(best) = first.best() else {
        anyhow::bail!("no optimum with the mean pair of legs: {}", first.no_optimum(settings, tolerance));
    };
    println!("{}", mean_cat.describe());
    println!(
        "- from `{}`: {}, peak {:.6} N·m, largest bend {:.2}°: {}",
        best.start, best.status, best.peak_torque_nm, best.max_bend_deg, best.reason
    );
    // Back onto the uniform knots every start has (the optimum's may be refined).
    let spline = best.spline.refit(settings.control_points, settings.fixed());
    let own = cat([front, rear]);
    let start = NamedStart { name: "the mean pair's optimum".to_string(), spline };
    let second = optimize_from(&own, &[start], settings, &Motors::ideal(), tolerance)?;
    println!("{}", own.describe());
    for s in &second.solutions {
        println!(
            "- from {}: {}, {} iterations, peak {:.6} N·m, largest bend {:.2}°: {}",
            s.start, s.status, s.iterations, s.peak_torque_nm, s.max_bend_deg, s.reason
        );
    }
    println!("{:.1} s in all", clock.elapsed().as_secs_f64());
    Ok(())
}
