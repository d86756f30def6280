//! The `catflip` command line: parses arguments and calls the library.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};

use catflip::engines::circulation::Resolved;
use catflip::engines::Engine;
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

#[derive(Subcommand)]
enum Command {
    /// The paper's numbers: published, literal recomputation, corrected.
    Audit(Common),
    /// One schedule through an engine.
    Simulate {
        #[command(flatten)]
        common: Common,
        /// Engine to run: `exact` (the momentum-map engine, ground truth) or `rapier`
        /// (rapier3d-f64 multibody simulation).
        #[arg(long, default_value = "exact")]
        engine: Engine,
        /// Time step for --engine rapier, s (overrides rapier.dt).
        #[arg(long)]
        dt: Option<f64>,
    },
    /// Every profile side by side: the peak-torque table.
    Compare(Common),
    /// Torque-optimal schedules: the profile QP and the exact-dynamics refinement.
    Optimize(Common),
    /// Everything above for each problem, written to <out>/<name>/.
    Run {
        /// Problem files (TOML).
        #[arg(required = true)]
        problems: Vec<PathBuf>,
        /// Override a problem field in every problem (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        overrides: Vec<String>,
        /// Where results go.
        #[arg(long, default_value = "results")]
        out: PathBuf,
    },
    /// Run time against error for every engine, and stress tests; written to <out>/bench/.
    Bench {
        /// The problem to measure on.
        #[arg(long, default_value = "problems/paper.toml")]
        problem: PathBuf,
        /// Override a field of that problem (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        overrides: Vec<String>,
        /// Where results go.
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
    },
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

/// Prints `value` as JSON when asked, else its prose rendering.
fn emit<T: serde::Serialize>(json: bool, value: &T, prose: impl FnOnce() -> String) -> anyhow::Result<()> {
    if json {
        print_json(value)
    } else {
        print!("{}", prose());
        Ok(())
    }
}

/// The command line that regenerates a result, overrides quoted.
fn regenerate(base: String, overrides: &[String]) -> String {
    overrides.iter().fold(base, |c, o| format!("{c} --set '{o}'"))
}

fn run() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Audit(common) => {
            let r = Resolved::new(&load(&common, &[])?)?;
            let audit = catflip::report::audit::audit_with_exact(&r)?;
            emit(common.json, &audit, || audit.to_markdown())?;
        }
        Command::Simulate { common, engine, dt } => {
            let extra: Vec<String> = dt.map(|d| format!("rapier.dt={d:e}")).into_iter().collect();
            let r = Resolved::new(&load(&common, &extra)?)?;
            let report = catflip::report::simulate::simulate(&r, engine)?;
            emit(common.json, &report, || report.to_text())?;
        }
        Command::Optimize(common) => {
            let r = Resolved::new(&load(&common, &[])?)?;
            let report = catflip::optimize::optimize(&r)?;
            emit(common.json, &report, || report.to_markdown())?;
        }
        Command::Run { problems, overrides, out } => {
            // Load every problem first, so a bad one stops the run before anything is written.
            let loaded =
                problems.iter().map(|p| Problem::load(p, &overrides).map(|x| (p, x))).collect::<Result<Vec<_>, _>>()?;
            for (path, problem) in loaded {
                for w in problem.warnings() {
                    eprintln!("warning: {}: {w}", path.display());
                }
                let command = regenerate(format!("cargo run --release -- run {}", path.display()), &overrides);
                let outcome = catflip::report::run::run(&Resolved::new(&problem)?, &command, &out)?;
                println!("{}: {} files in {}", problem.name, outcome.files.len(), outcome.dir.display());
                print!("{}", outcome.summary);
            }
        }
        Command::Bench { problem, overrides, out, json } => {
            let p = Problem::load(&problem, &overrides)?;
            let command =
                regenerate(format!("cargo run --release -- bench --problem {}", problem.display()), &overrides);
            let dts = [
                1.0 / 60.0,
                1.0 / 125.0,
                1.0 / 250.0,
                1.0 / 500.0,
                1.0 / 1000.0,
                1.0 / 2000.0,
                1.0 / 4000.0,
                1.0 / 8000.0,
                1.0 / 16000.0,
                1.0 / 32000.0,
            ];
            let outcome = catflip::report::run::run_bench(&Resolved::new(&p)?, &command, &out, &dts)?;
            if json {
                let text = std::fs::read_to_string(outcome.dir.join("bench.json")).context("reading bench.json")?;
                print!("{text}");
            } else {
                println!("{} files in {}", outcome.files.len(), outcome.dir.display());
                print!("{}", outcome.summary);
            }
        }
        Command::Compare(common) => {
            let r = Resolved::new(&load(&common, &[])?)?;
            let table = catflip::report::compare::compare(&r, &[]);
            emit(common.json, &table, || table.to_markdown())?;
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
