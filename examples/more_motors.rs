//! Whole optima of cats with more than two motors (issue 22), through the library: the problem's
//! cat (two motors), its halves on the spherical joint (three: the bend's two and the relative
//! twist, which now a motor must hold or use), the cat with a tail (four: a rod a tenth of the
//! cat's mass, as long as a half, on a universal joint at the rear half's end) and the cat with
//! legs (four: on each half a pair's rod, a tenth of the cat's mass, on a hinge), each optimised
//! over the problem's fall; each flip is re-measured here at 1e-12 rad by the general core's
//! adaptive engine on the cat's tree of bodies, and verified in rapier's tree scene
//! (`engines::rapier::tree_run::verify_tree`: the problem's `[rapier]` tolerances, the step
//! refinement and the verdict of every verification).
//!
//! `cargo run --release --example more_motors [PROBLEM.toml]` (default problems/kane-scher.toml).
//!
//! On the command line these cats are `catflip compare-models`' rows (`[cat.tail]`, `[cat.legs]`
//! in the problem file), which with `--out` also writes each optimum's model and schedule files
//! for MuJoCo and pyBullet; the one rig the other commands report from takes two motors, and they
//! refuse the spherical joint, `[cat.tail]` and `[cat.legs]` by name.

use std::f64::consts::PI;
use std::path::Path;

use nalgebra::Vector3;

use catflip::engines::models;
use catflip::engines::rapier::tree_run::verify_tree;
use catflip::engines::rapier::{Quantity, RapierOptions, Reference};
use catflip::model::cat::Appendages;
use catflip::model::motor::Motors;
use catflip::model::{Cat, Cylinder, Joint};
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
    let tail =
        Cylinder { mass: 0.1 * (halves.front.mass + halves.rear.mass), length: halves.rear.length, radius: 0.02 };
    // Each pair of legs a tenth of the cat's mass, as long as the drawn legs (problems/legs.toml).
    let legs = Cylinder {
        mass: 0.1 * (halves.front.mass + halves.rear.mass),
        length: 0.45 * halves.front.length,
        radius: 0.03 * halves.front.length,
    };
    let cats = [
        WholeCat::new(halves)?,
        WholeCat::spherical(Cat { joint: Joint::Spherical, ..halves }).expect("a spherical cat"),
        WholeCat::tailed(halves, tail, Joint::Universal).expect("a two-motor cat and tail"),
        WholeCat::appended(halves, Appendages { tail: None, legs: Some([legs; 2]) })
            .expect("a two-motor cat with legs"),
    ];
    for cat in cats {
        let tree = cat.tree();
        let outcome =
            optimize_whole(&cat, fall, &problem.manoeuvre, settings, &Motors::ideal(), problem.exact.tolerance)?;
        let Some(best) = outcome.best() else {
            println!("{}: {}", cat.describe(), outcome.no_optimum(settings, problem.exact.tolerance));
            continue;
        };
        // Re-measured here: the general core on every coordinate of the spline.
        let flip = models::flip_on(&tree, &SplineShape(&best.spline), &Vector3::zeros(), 1e-12);
        let duration = best.spline.duration();
        // Beyond the cat's bend: the spherical joint's relative twist |q3|, how far the tail
        // bends from straight behind the rear half, acos(cos q3 cos q4) on its universal joint, or
        // how far the legs swing from standing out, max |q3|, |q4|.
        let legged = cat.appendages().legs.is_some();
        let beyond = |q: &[f64]| match q.len() {
            3 => q[2].abs(),
            4 if legged => q[2].abs().max(q[3].abs()),
            4 => (Joint::Universal.rotation(&q[2..]) * Vector3::z()).z.clamp(-1.0, 1.0).acos(),
            _ => 0.0,
        };
        let third = (0..=2000).map(|k| beyond(&best.spline.angles(duration * k as f64 / 2000.0))).fold(0.0, f64::max);
        println!(
            "{}\n  {} ({}, {} iterations, {:.2} s); flip {:+.9}° (| |twist| − 180° | = {:.1e}°), swing {:.1e}°; peak {:.6} N·m, energy {:.6} N²·m²·s, largest bend {:.2}°, relative twist, tail bend or legs' swing up to {:.2}°; peak speed per motor {:?} rad/s",
            cat.describe(),
            best.status,
            best.start,
            best.iterations,
            best.seconds,
            flip.twist.to_degrees(),
            (flip.twist.abs() - PI).abs().to_degrees(),
            flip.swing.to_degrees(),
            best.peak_torque_nm,
            best.energy,
            best.max_bend_deg,
            third.to_degrees(),
            best.motors.peak_speed_rad_s.iter().map(|p| (p.value * 1e4).round() / 1e4).collect::<Vec<_>>(),
        );
        let reference = Reference { twist: flip.twist, swing: flip.swing, peak_torque: best.peak_torque_nm };
        let rapier =
            verify_tree(&tree, &SplineShape(&best.spline), &problem.rapier, &reference, &RapierOptions::default())?;
        println!("  rapier (the tree scene): {}", rapier.verdict);
        let quantity = |q: Quantity| rapier.quantity(q).and_then(|c| c.value.zip(c.gap));
        if let (Some((twist, twist_gap)), Some((swing, _)), Some((peak, peak_gap)), Some(last)) =
            (quantity(Quantity::Twist), quantity(Quantity::Swing), quantity(Quantity::PeakTorque), rapier.runs.last())
        {
            println!(
                "    {} runs down to dt {:.3e} s, extrapolated: twist {twist:+.4}° ({twist_gap:.4}° from the exact), swing {swing:.4}°, peak {peak:.6} N·m ({:.2} % from the exact); finest run: tracking ≤ {:.1e} rad, momentum drift {:.1e}",
                rapier.runs.len(),
                last.dt,
                100.0 * peak_gap,
                last.tracking_error_rad.iter().copied().fold(0.0, f64::max),
                last.momentum_drift,
            );
        }
    }
    Ok(())
}
