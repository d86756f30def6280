//! rapier's convergence in the time step on the paper problem (problems/paper.toml): raw and
//! Richardson-extrapolated errors of the twist, of the swing's rotation vector (what the bench and
//! the verification compare) and of the swing angle (what is not smooth in dt), against the exact
//! engine at 1e-12 rad. See `src/report/bench/engines.rs` for the findings.
//!
//! `cargo run --release --example rapier_convergence -- [PROFILE [ALPHA [PGS [CROSS [DTS]]]]]`
//!
//! PROFILE a library profile (default `cycloidal`); ALPHA the motor bandwidth per step; PGS the
//! Gauss–Seidel sweeps; CROSS the cross's mass fraction; DTS comma-separated steps in s, or `nK`
//! for `K` steps over the fall (default: the bench's 1/60 … 1/32000 s).

use std::path::Path;

use anyhow::Context;
use catflip::engines::exact::flip;
use catflip::engines::models::TwoMotorCat;
use catflip::engines::rapier::{simulate_with, RapierOptions};
use catflip::engines::resolved::Resolved;
use catflip::measure::bench::engines::FinalAngles;
use catflip::problem::{Problem, ProfileKind};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize| args.get(i).map(String::as_str);
    let profile = arg(0).unwrap_or("cycloidal");
    let kind = *ProfileKind::ALL.iter().find(|k| k.name() == profile).context("unknown profile")?;
    let defaults = RapierOptions::default();
    let opts = RapierOptions {
        bandwidth_per_step: arg(1).map_or(Ok(defaults.bandwidth_per_step), str::parse)?,
        pgs_iterations: arg(2).map_or(Ok(defaults.pgs_iterations), str::parse)?,
        ..defaults
    };
    let p = Problem::load(Path::new("problems/paper.toml"), &[])?;
    let mut settings = p.rapier;
    settings.cross_mass_fraction = arg(3).map_or(Ok(settings.cross_mass_fraction), str::parse)?;
    let fall = p.drop.fall_time();
    let dts: Vec<f64> = match arg(4) {
        Some(list) => list
            .split(',')
            .map(|x| match x.strip_prefix('n') {
                Some(n) => n.parse::<f64>().map(|n| fall / n),
                None => x.parse(),
            })
            .collect::<Result<_, _>>()?,
        None => [60.0, 125.0, 250.0, 500.0, 1e3, 2e3, 4e3, 8e3, 16e3, 32e3].iter().map(|r| 1.0 / r).collect(),
    };
    let schedule = Resolved::new(&p)?.with_library(kind);
    let exact = flip(&p.cat.half(), &schedule, 1e-12);
    let reference = FinalAngles::new(&exact.orientation, exact.twist);
    println!(
        "{profile}: exact twist {:.9} rad, swing {:.4e} rad, swing vector ({:.4e}, {:.4e})",
        exact.twist, exact.swing, reference.swing.x, reference.swing.y
    );
    println!("| dt (s) | steps | Δtwist | |Δs| | Δswing angle | drift | extrapolated with the row above: max(|Δtwist|, |Δs|) | the same, Δswing angle |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut prev: Option<(f64, FinalAngles, f64)> = None;
    for dt in dts {
        let run = simulate_with(&TwoMotorCat::paper(p.cat.half()), &schedule, &settings.with_dt(dt), &opts)?;
        let now = FinalAngles::of_run(&run);
        let (ex, ex_angle) = match prev {
            Some((dt0, before, swing0)) => {
                let r = dt0 / run.dt;
                let x = FinalAngles::extrapolate(&before, &now, r);
                let angle = run.swing + (run.swing - swing0) / (r - 1.0);
                (format!("{:.3e}", x.error(&reference)), format!("{:+.3e}", angle - exact.swing))
            }
            None => ("—".into(), "—".into()),
        };
        println!(
            "| {:.4e} | {} | {:+.6e} | {:.3e} | {:+.3e} | {:.3e} | {ex} | {ex_angle} |",
            run.dt,
            run.steps,
            run.twist - exact.twist,
            (now.swing - reference.swing).norm(),
            run.swing - exact.swing,
            run.momentum.max_rel
        );
        prev = Some((run.dt, now, run.swing));
    }
    Ok(())
}
