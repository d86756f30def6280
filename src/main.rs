//! The `catflip` command line: parses arguments and calls the library.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::{Args, Parser, Subcommand, ValueEnum};

use catflip::problem::Problem;

#[derive(Parser)]
#[command(name = "catflip", version, about = "Plan and check how a falling cat turns itself over")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Args, Clone)]
struct Common {
    /// Problem file (TOML).
    problem: PathBuf,
    /// Override a problem field, e.g. --set manoeuvre.profile=cycloidal (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    overrides: Vec<String>,
    /// Print one JSON object on stdout instead of prose.
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum Engine {
    /// The momentum-map engine (ground truth).
    Exact,
    /// rapier3d-f64 multibody simulation.
    Rapier,
}

#[derive(Subcommand)]
enum Command {
    /// The paper's numbers: published, literal recomputation, corrected.
    Audit(Common),
    /// One schedule through an engine.
    Simulate {
        #[command(flatten)]
        common: Common,
        /// Engine to run.
        #[arg(long, value_enum, default_value = "exact")]
        engine: Engine,
        /// Time step for --engine rapier, s (overrides rapier.dt).
        #[arg(long)]
        dt: Option<f64>,
    },
    /// Every profile side by side: the peak-torque table.
    Compare(Common),
    /// Torque-optimal schedules: the profile QP and the exact-dynamics refinement.
    Optimize(Common),
}

fn load(common: &Common, extra: &[String]) -> anyhow::Result<Problem> {
    let mut overrides = common.overrides.clone();
    overrides.extend_from_slice(extra);
    let problem = Problem::load(&common.problem, &overrides)?;
    if !common.json {
        for w in problem.warnings() {
            eprintln!("warning: {w}");
        }
    }
    Ok(problem)
}

fn print_json(value: &impl serde::Serialize) -> anyhow::Result<()> {
    println!("{}", serde_json::to_string_pretty(value).context("serialising the result")?);
    Ok(())
}

fn run() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Audit(common) => {
            let problem = load(&common, &[])?;
            let audit = catflip::audit::audit_with_exact(&problem)?;
            if common.json {
                print_json(&audit)?;
            } else {
                print!("{}", audit.to_markdown());
            }
        }
        Command::Simulate { common, engine, dt } => {
            let extra: Vec<String> = dt.map(|d| format!("rapier.dt={d:e}")).into_iter().collect();
            let problem = load(&common, &extra)?;
            let report = match engine {
                Engine::Exact => catflip::simulate::simulate_exact(&problem)?,
                Engine::Rapier => catflip::simulate::simulate_rapier(&problem)?,
            };
            if common.json {
                print_json(&report)?;
            } else {
                print!("{}", report.to_text());
            }
        }
        Command::Optimize(common) => {
            let problem = load(&common, &[])?;
            let report = catflip::optimize::optimize(&problem)?;
            if common.json {
                print_json(&report)?;
            } else {
                print!("{}", report.to_markdown());
            }
        }
        Command::Compare(common) => {
            let problem = load(&common, &[])?;
            let table = catflip::compare::compare(&problem, &[])?;
            if common.json {
                print_json(&table)?;
            } else {
                print!("{}", table.to_markdown());
            }
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprint!("error: {e}");
            for cause in e.chain().skip(1) {
                eprint!(": {cause}");
            }
            eprintln!();
            ExitCode::FAILURE
        }
    }
}
