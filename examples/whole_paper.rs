//! The whole-manoeuvre optimum of a problem file: `cargo run --release --example whole_paper --
//! problems/paper.toml [peak|energy] [control_points] [key=value ...]` (the last as `--set`
//! overrides, e.g. `cat.radius=0.05`). Diagnostics: `WHOLE_STARTS=paper,cone`, `WHOLE_LOG=1`,
//! `WHOLE_MIN_ANGLE=140`, `WHOLE_SAMPLES=6`.

use catflip::optimize::whole::{optimize_whole, Objective, WholeSettings};
use catflip::problem::Problem;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).map_or("problems/paper.toml", String::as_str);
    let overrides: Vec<String> = args.iter().skip(4).cloned().collect();
    let problem = Problem::load(std::path::Path::new(path), &overrides)?;
    let mut settings = WholeSettings::default();
    if let Some(o) = args.get(2) {
        settings.objective = if o == "energy" { Objective::Energy } else { Objective::Peak };
    }
    if let Some(n) = args.get(3) {
        settings.control_points = n.parse()?;
    }
    if let Ok(a) = std::env::var("WHOLE_MIN_ANGLE") {
        settings.min_angle_deg = Some(a.parse()?);
    }
    if let Ok(n) = std::env::var("WHOLE_SAMPLES") {
        settings.samples_per_span = n.parse()?;
    }
    if let Ok(list) = std::env::var("WHOLE_STARTS") {
        settings.starts =
            list.split(',').map(|n| serde_json::from_str(&format!("\"{n}\""))).collect::<Result<_, _>>()?;
    }
    let clock = std::time::Instant::now();
    let outcome = optimize_whole(
        problem.cat.half(),
        problem.drop.fall_time(),
        &problem.manoeuvre,
        &settings,
        &problem.actuator.motors(),
        1e-8,
    )?;
    let total = clock.elapsed().as_secs_f64();
    for s in &outcome.solutions {
        println!(
            "{:16} {:15} it {:4} peak {:.6} N·m energy {:.6} twist {:+.12} (|twist|−π {:.1e}) swing {:.2e} bend {:.2}° turns {:+.3} {:.2} s | {}",
            s.start,
            s.status.to_string(),
            s.iterations,
            s.peak_torque_nm,
            s.energy,
            s.twist,
            s.twist_error,
            s.swing,
            s.max_bend_deg,
            s.bend_turns,
            s.seconds,
            s.reason
        );
    }
    for s in &outcome.skipped {
        println!("{:16} skipped: {}", s.start, s.reason);
    }
    if std::env::var("WHOLE_LOG").is_ok() {
        for s in &outcome.solutions {
            for l in &s.log {
                println!(
                    "{} {:3} {:?} val {:.6} peak {:.6} viol {:.2e} r {:?} mu {:?} {:?} rho {:?} {}",
                    s.start,
                    l.iteration,
                    l.objective,
                    l.value,
                    l.peak_nm,
                    l.violation,
                    l.trust_radius,
                    l.barrier,
                    l.subproblem,
                    l.ratio,
                    l.accepted
                );
            }
        }
    }
    println!("best: {:?}, total {total:.2} s", outcome.best().map(|b| (&b.start, b.peak_torque_nm, b.energy)));
    Ok(())
}
