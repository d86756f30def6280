//! The spherical joint's whole optimum (issue 22), through the library: the problem's halves on
//! Kane and Scher's no-twist joint (two motors; the joint itself keeps the halves from twisting)
//! and on the spherical joint (three motors: the bend's two and the relative twist, which now a
//! motor must hold or use), each optimised over the problem's fall and re-measured here by the
//! general core's adaptive engine, independently of the optimiser.
//!
//! `cargo run --release --example spherical_whole [PROBLEM.toml]` (default problems/kane-scher.toml).
//!
//! The spherical optimum is not yet measured by the one rig every command reports from, nor
//! verified in rapier, nor exported: `catflip` refuses `cat.joint = "spherical"` until it is.

use std::f64::consts::PI;
use std::path::Path;

use catflip::engines::models;
use catflip::model::motor::Motors;
use catflip::model::{Cat, Joint};
use catflip::optimize::whole::spline::SplineShape;
use catflip::optimize::whole::{optimize_whole, WholeCat};
use catflip::problem::Problem;

fn main() -> anyhow::Result<()> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "problems/kane-scher.toml".to_string());
    let problem = Problem::load(Path::new(&path), &[])?;
    let halves = problem.cat.model();
    let settings = &problem.optimize.whole;
    let fall = problem.drop.fall_time();
    println!(
        "{}: {} over a fall of {fall:.6} s, objective {}",
        problem.name,
        halves.describe(),
        settings.objective.name()
    );
    for joint in [Joint::NoTwist, Joint::Spherical] {
        let model = Cat { joint, ..halves };
        let cat = match joint {
            Joint::Spherical => WholeCat::spherical(model).expect("a spherical cat"),
            _ => WholeCat::new(model)?,
        };
        let outcome =
            optimize_whole(&cat, fall, &problem.manoeuvre, settings, &Motors::ideal(), problem.exact.tolerance)?;
        let Some(best) = outcome.best() else {
            println!("{joint}: {}", outcome.no_optimum(settings, problem.exact.tolerance));
            continue;
        };
        // Re-measured here: the general core on every coordinate of the spline.
        let flip = models::flip(&model, &SplineShape(&best.spline), 1e-12)?;
        let duration = best.spline.duration();
        let twist = (0..=2000)
            .filter_map(|k| best.spline.angles(duration * k as f64 / 2000.0).get(2).copied())
            .fold(0.0, |m: f64, x| m.max(x.abs()));
        println!(
            "{joint:>9}: {} ({}, {:.2} s); flip {:+.9}° (| |twist| − 180° | = {:.1e}°), swing {:.1e}°; peak {:.6} N·m, energy {:.6} N²·m²·s, largest bend {:.2}°, relative twist up to {:.2}°; peak speed per motor {:?} rad/s",
            best.status,
            best.start,
            best.seconds,
            flip.twist.to_degrees(),
            (flip.twist.abs() - PI).abs().to_degrees(),
            flip.swing.to_degrees(),
            best.peak_torque_nm,
            best.energy,
            best.max_bend_deg,
            twist.to_degrees(),
            best.motors.peak_speed_rad_s.iter().map(|p| (p.value * 1e4).round() / 1e4).collect::<Vec<_>>(),
        );
    }
    Ok(())
}
