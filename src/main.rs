//! The `catflip` command line: parses arguments and calls the library.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};

use catflip::engines::resolved::Resolved;
use catflip::engines::Engine;
use catflip::problem::Problem;
use catflip::report::results_dir::check_target;

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
        /// First time step for --engine rapier, s (sets rapier.dt; the verification halves it
        /// until rapier's own error meets the tolerances).
        #[arg(long, allow_negative_numbers = true)]
        dt: Option<f64>,
        /// Evaluate this schedule CSV (t, q1, q2 and optionally q̇, q̈) instead of the problem's
        /// own schedule; the problem gives the cat and the engine settings.
        #[arg(long, value_name = "FILE.csv")]
        schedule: Option<PathBuf>,
    },
    /// Every profile side by side: the peak-torque table.
    Compare {
        #[command(flatten)]
        common: Common,
        /// Also verify every profile in rapier (its verdict against the exact engine), as `run`
        /// does; exits non-zero when rapier has no result for one.
        #[arg(long)]
        verify: bool,
    },
    /// How often the schedule lands the cat on its feet: a seeded Monte Carlo over the cat's
    /// sizes and the release spin ([robust]): the schedule run by the exact engine (ideal
    /// tracking) and/or tracked with motors in rapier (`robust.engine`).
    Robust {
        #[command(flatten)]
        common: Common,
        /// Check this schedule CSV (e.g. an exported optimum) instead of the problem's own.
        #[arg(long, value_name = "FILE.csv")]
        schedule: Option<PathBuf>,
        /// Also write robust.{md,csv,json}, the plots and filmstrips into <out>/<name>-robust/.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// The whole-manoeuvre optimum of each cat model (equal or unequal halves; universal, no-twist
    /// or spherical joint; with `[cat.tail]`, `[cat.legs]` the cat with them) on the problem's cat and fall,
    /// side by side: which body flips most cheaply.
    CompareModels {
        #[command(flatten)]
        common: Common,
        /// Also verify each optimum in rapier (its verdict against the exact engine).
        #[arg(long)]
        verify: bool,
        /// Also write models.{md,csv,json}, the bend plot (models_bend.{png,svg}) and a filmstrip
        /// per optimum into <out>/<name>-models/.
        #[arg(long)]
        out: Option<PathBuf>,
        /// No progress spinner on stderr (it is also hidden when stderr is not a terminal).
        #[arg(long)]
        quiet: bool,
    },
    /// Torque-optimal schedules: the profile QP and the exact-dynamics refinement; with --whole,
    /// the whole-manoeuvre path optimum that flips the cat exactly ([optimize.whole]).
    Optimize {
        #[command(flatten)]
        common: Common,
        /// Optimise both joint paths over the whole fall (twist π, swing 0 as constraints).
        #[arg(long)]
        whole: bool,
        /// With --whole: also verify the optimum in rapier (its verdict against the exact engine).
        #[arg(long, requires = "whole")]
        verify: bool,
        /// With --whole: also write the optimum's report, schedule file (CSV and sidecar),
        /// URDF/MJCF and filmstrip into <out>/<name>-whole/ (the universal or no-twist joint, no release spin).
        #[arg(long, requires = "whole", value_name = "DIR")]
        out: Option<PathBuf>,
        /// No progress spinner on stderr (it is also hidden when stderr is not a terminal).
        #[arg(long)]
        quiet: bool,
    },
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
        /// Write the schedule CSVs on a uniform grid at this rate, Hz (default: 400 steps per phase).
        #[arg(long, value_name = "HZ", allow_negative_numbers = true)]
        rate: Option<f64>,
        /// No progress spinner on stderr (it is also hidden when stderr is not a terminal).
        #[arg(long)]
        quiet: bool,
        /// Print how long each stage took (wall clock, s from the start; the stages overlap) to stderr.
        #[arg(long)]
        timings: bool,
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
    /// A grid of problems: tidy CSV, summary tables, heat maps; written to <out>/<name>/.
    Sweep {
        /// The sweep file (TOML).
        #[arg(required_unless_present = "merge")]
        sweep: Option<PathBuf>,
        /// Instead of running a sweep file, join these shard part folders into the folder one
        /// unsharded run would write.
        #[arg(long, num_args = 1.., conflicts_with_all = ["sweep", "shard"])]
        merge: Vec<PathBuf>,
        /// Where results go.
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// Run only the K-th of N slices of the cases; writes <out>/<name>.part-K-of-N/.
        #[arg(long, value_name = "K/N")]
        shard: Option<catflip::sweep::Shard>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Print what was written as JSON.
        #[arg(long)]
        json: bool,
    },
}

/// Loads the problem (its rapier step set to `dt` when given) and prints its warnings on stderr
/// (also with `--json`, whose output is stdout's).
fn load(common: &Common, dt: Option<f64>) -> anyhow::Result<Problem> {
    Ok(warned(Problem::load(&common.problem, &common.overrides)?.with_rapier_dt(dt)?))
}

/// `problem`, its warnings printed on stderr.
fn warned(problem: Problem) -> Problem {
    for w in problem.warnings() {
        eprintln!("warning: {w}");
    }
    problem
}

/// Resolves `problem` (its circulation, calibrated if asked) and prints what the resolution
/// warns of on stderr.
fn resolve(problem: &Problem) -> anyhow::Result<Resolved> {
    let r = Resolved::new(problem)?;
    for w in r.warnings() {
        eprintln!("warning: {w}");
    }
    Ok(r)
}

/// Writes `text` to stdout. A closed stdout (`catflip … | head -1`) is not an error: the output
/// is dropped quietly and the command goes on, as Unix tools do (Rust ignores SIGPIPE, so the
/// write fails with `BrokenPipe`, which `print!` would turn into a panic). Any other write error
/// is reported.
fn say(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other.context("cannot write to standard output"),
    }
}

fn print_json(value: &impl serde::Serialize) -> anyhow::Result<()> {
    say(&(serde_json::to_string_pretty(value).context("serialising the result")? + "\n"))
}

/// Prints `value` as JSON when asked, else its prose rendering.
fn emit<T: serde::Serialize>(json: bool, value: &T, prose: impl FnOnce() -> String) -> anyhow::Result<()> {
    if json {
        print_json(value)
    } else {
        say(&prose())
    }
}

/// The command line that regenerates a result, overrides quoted.
/// With `--out`, the whole optimum's results folder (`catflip::report::whole_files`), and where
/// it went on stderr; nothing without an optimum.
fn write_whole(
    out: Option<&Path>,
    r: &Resolved,
    report: &catflip::measure::whole::WholeReport,
    json: &impl serde::Serialize,
    markdown: &str,
    command: &str,
) -> anyhow::Result<()> {
    let Some(out) = out else { return Ok(()) };
    if let Some(dir) = catflip::report::whole_files::write_whole(out, &r.problem, report, json, markdown, command)? {
        eprintln!("wrote {}", dir.display());
    }
    Ok(())
}

fn regenerate(base: String, overrides: &[String]) -> String {
    overrides.iter().fold(base, |c, o| format!("{c} --set '{o}'"))
}

/// A spinner with the elapsed time on stderr while a long step runs; hidden when `quiet` or when
/// stderr is not a terminal (scripts, CI).
fn progress(quiet: bool, message: String) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if quiet || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new_spinner();
    if let Ok(style) = indicatif::ProgressStyle::with_template("{spinner} {msg} [{elapsed}]") {
        bar.set_style(style);
    }
    bar.set_message(message);
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    bar
}

fn run() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Audit(common) => {
            let problem = load(&common, None)?;
            problem.require_no_spin("the audit of the paper's numbers")?;
            let r = resolve(&problem)?;
            let audit = catflip::measure::audit::audit_with_exact(&r)?;
            emit(common.json, &audit, || audit.to_markdown())?;
        }
        Command::Simulate { common, engine, dt, schedule } => {
            if let (Some(d), Engine::Exact) = (dt, engine) {
                anyhow::bail!(
                    "--dt {}: --dt is the time step of --engine rapier; the exact engine chooses its own steps (exact.tolerance)",
                    catflip::numeric::numfmt::echo(d)
                );
            }
            if let Some(file) = schedule {
                // The problem gives the cat and the settings; its manoeuvre is not used, so the
                // manoeuvre's warnings are not printed (the import's checks say what applies).
                let problem = Problem::load(&common.problem, &common.overrides)?.with_rapier_dt(dt)?;
                for w in problem.warnings_without_manoeuvre() {
                    eprintln!("warning: {w}");
                }
                let imported = catflip::exchange::read_schedule(&file)?;
                let report = catflip::report::import::simulate_import(&problem, imported, engine)?;
                if !common.json {
                    for w in &report.warnings {
                        eprintln!("warning: {w}");
                    }
                }
                emit(common.json, &report, || report.to_text())?;
            } else {
                let r = resolve(&load(&common, dt)?)?;
                let report = catflip::report::simulate::simulate(&r, engine)?;
                emit(common.json, &report, || report.to_text())?;
                // Printed in full, but a number that is not a result does not exit 0.
                if let Some(why) = report.unconverged() {
                    anyhow::bail!("{why}");
                }
            }
        }
        Command::Optimize { common, whole: false, quiet, .. } => {
            let problem = load(&common, None)?;
            problem.require_no_spin("optimize (the profile QP and the refinements)")?;
            let r = resolve(&problem)?;
            let spinner = progress(quiet || common.json, "optimize: profile QP and exact refinement".into());
            let report = catflip::optimize::optimize(&r)?;
            spinner.finish_and_clear();
            let report = report.to_json(&r.model().cat().rear);
            emit(common.json, &report, || report.to_markdown())?;
        }
        Command::Optimize { common, whole: true, verify, out, quiet } => {
            let problem = load(&common, None)?;
            if let Some(o) = &out {
                catflip::report::whole_files::files_refusal(&problem)?;
                check_target(o, &format!("{}-whole", problem.name))?;
            }
            let r = resolve(&problem)?;
            let spinner = progress(quiet || common.json, "optimize --whole: successive convexification".into());
            let mut report = catflip::measure::whole::whole(&r)?;
            spinner.finish_and_clear();
            let found = report.best().is_some();
            let status = report.status.clone();
            let verify_arg = if verify { " --verify" } else { "" };
            let out_arg = out.as_ref().map_or(String::new(), |o| format!(" --out {}", o.display()));
            let command = regenerate(
                format!("cargo run --release -- optimize {} --whole{verify_arg}{out_arg}", common.problem.display()),
                &common.overrides,
            );
            let out = out.as_deref();
            if verify && found {
                let spinner = progress(quiet || common.json, "optimize --whole --verify: rapier".into());
                report.verify(&r)?;
                let check = catflip::report::whole_check::WholeCheck::new(report);
                spinner.finish_and_clear();
                write_whole(out, &r, &check.report, &check, &check.to_markdown(), &command)?;
                emit(common.json, &check, || check.to_markdown())?;
                if check.rapier.as_ref().is_some_and(|v| !v.has_result()) {
                    anyhow::bail!(
                        "optimize --whole --verify: rapier has no result for the optimum (inconclusive: no usable run; the verification says why)"
                    );
                }
            } else {
                write_whole(out, &r, &report, &report, &report.to_markdown(), &command)?;
                emit(common.json, &report, || report.to_markdown())?;
            }
            if !found {
                anyhow::bail!("{status}");
            }
        }
        Command::Run { problems, overrides, out, rate, quiet, timings } => {
            let export = catflip::exchange::ExportOptions { rate_hz: rate, ..Default::default() };
            export.validate(0.0)?;
            let rate_arg = rate.map_or(String::new(), |r| format!(" --rate {r}"));
            // Load every problem first, so a bad one stops the run before anything is written.
            // Each error names its file: `run` takes several.
            // The error with its causes (a folder's "afile is a file, not a folder"), after the file.
            let named = |p: &std::path::PathBuf, e: anyhow::Error| e.context(p.display().to_string());
            let loaded = problems
                .iter()
                .map(|p| {
                    Problem::load(p, &overrides).map(|x| (p, x)).map_err(|e| match e {
                        // These name the file already.
                        catflip::problem::ProblemError::Io { .. } | catflip::problem::ProblemError::Parse { .. } => {
                            anyhow::Error::from(e)
                        }
                        other => named(p, other.into()),
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            // Every problem's cat and schedule resolved too (a tail or legs, a circulation its
            // halves do not define are refused there), before anything is computed or written.
            let mut resolved = Vec::with_capacity(loaded.len());
            for (path, problem) in &loaded {
                catflip::report::run::runnable(problem).map_err(|e| named(path, e.into()))?;
                // The rate against this fall.
                export.validate(problem.drop.fall_time()).map_err(|e| named(path, e.into()))?;
                resolved.push(Resolved::new(problem).map_err(|e| named(path, e.into()))?);
                check_target(&out, &problem.name).map_err(|e| named(path, e.into()))?;
            }
            // Reserved names (`bench`) and two problems of one name would overwrite results.
            catflip::report::results_dir::check_names(loaded.iter().map(|(_, p)| p.name.as_str()))?;
            // Folders written, and schedules rapier could not verify, for the errors below.
            let mut written: Vec<String> = Vec::new();
            let mut without_result: Vec<String> = Vec::new();
            for ((path, problem), r) in loaded.into_iter().zip(resolved) {
                let coarse = export.coarse(&problem);
                for w in problem.warnings().into_iter().chain(coarse) {
                    eprintln!("warning: {}: {w}", path.display());
                }
                for w in r.warnings() {
                    eprintln!("warning: {}: {w}", path.display());
                }
                let command =
                    regenerate(format!("cargo run --release -- run {}{rate_arg}", path.display()), &overrides);
                let spinner =
                    progress(quiet, format!("run {}: audit, optimisers, rapier verification, plots", problem.name));
                let outcome = catflip::report::run::run_with(&r, &command, &out, &export).map_err(|e| {
                    let before = if written.is_empty() {
                        String::new()
                    } else {
                        format!(" (written before it, complete: {})", written.join(", "))
                    };
                    anyhow::Error::new(e).context(format!("{}{before}", path.display()))
                })?;
                spinner.finish_and_clear();
                written.push(outcome.dir.display().to_string());
                if outcome.without_result > 0 {
                    let n = outcome.without_result;
                    without_result.push(format!("{} ({n} schedule{})", problem.name, if n == 1 { "" } else { "s" }));
                }
                say(&format!("{}: {} files in {}\n", problem.name, outcome.files.len(), outcome.dir.display()))?;
                say(&outcome.summary)?;
                if timings {
                    eprint!("{}", catflip::report::run::timings_table(&outcome.stages, outcome.total_s));
                }
            }
            if !without_result.is_empty() {
                anyhow::bail!(
                    "run: rapier has no result (inconclusive: no usable run) in {}; each verification says why in verification.md",
                    without_result.join(" and ")
                );
            }
        }
        Command::Bench { problem, overrides, out, json } => {
            let p = warned(Problem::load(&problem, &overrides)?);
            p.require_no_spin("bench")?;
            let command =
                regenerate(format!("cargo run --release -- bench --problem {}", problem.display()), &overrides);
            let (outcome, report) = catflip::report::run::run_bench(&resolve(&p)?, &command, &out)?;
            if json {
                print_json(&report)?;
            } else {
                say(&format!("{} files in {}\n", outcome.files.len(), outcome.dir.display()))?;
                say(&outcome.summary)?;
            }
        }
        Command::Sweep { sweep, merge, out, shard, quiet, json } => {
            let whole = shard.is_none();
            let outcome = match sweep {
                Some(path) => {
                    let command = format!("cargo run --release -- sweep {}", path.display());
                    let options = catflip::sweep::SweepOptions { out, shard, quiet, command };
                    catflip::sweep::run_file(&path, &options)?
                }
                None => {
                    let dirs: Vec<String> = merge.iter().map(|d| d.display().to_string()).collect();
                    let command = format!("cargo run --release -- sweep --merge {}", dirs.join(" "));
                    catflip::sweep::merge(&merge, &out, &command)?
                }
            };
            emit(json, &outcome, || outcome.to_text())?;
            if outcome.warned_cases > 0 {
                let listed = if whole {
                    format!("{}, \"Warnings\", lists them", outcome.dir.join("sweep.md").display())
                } else {
                    format!("the warnings column of {} holds them", outcome.dir.join("cases.csv").display())
                };
                eprintln!(
                    "warning: sweep {}: {} of its {} cases carry warnings (the problem file's with the case's values, and flips that end swung past 45°): {listed}",
                    outcome.name, outcome.warned_cases, outcome.cases
                );
            }
            // A sweep (or a merge) without one computed row has no result; a shard's other
            // parts may have them, so the merge decides.
            if whole && outcome.rows > 0 && !outcome.has_result() {
                anyhow::bail!(
                    "sweep {}: no case gave a result ({}): the reason column of {} says why for each",
                    outcome.name,
                    outcome.counts(),
                    outcome.dir.join("sweep.csv").display()
                );
            }
        }
        Command::Robust { common, schedule, out } => {
            let problem = load(&common, None)?;
            if let Some(o) = &out {
                check_target(o, &format!("{}-robust", problem.name))?;
            }
            let schedule_arg = schedule.as_ref().map_or(String::new(), |f| format!(" --schedule {}", f.display()));
            let out_arg = out.as_ref().map_or(String::new(), |o| format!(" --out {}", o.display()));
            let command = regenerate(
                format!("cargo run --release -- robust {}{schedule_arg}{out_arg}", common.problem.display()),
                &common.overrides,
            );
            let (report, dir) = match &schedule {
                Some(file) => {
                    // The import's own checks (units, ends, sampling, numbers that cannot be
                    // computed) apply to the file before any trial runs.
                    let read = catflip::exchange::read_schedule(file)?;
                    catflip::robust::fits_the_fall(&problem, &read)
                        .map_err(|why| anyhow::anyhow!("{}: {why}", file.display()))?;
                    let checked = catflip::measure::import::measure_import(&problem, read)?;
                    for w in &checked.warnings {
                        eprintln!("warning: {w}");
                    }
                    let imported = &checked.measured.trajectory;
                    let mut report = catflip::robust::check(&problem, imported, &file.display().to_string())?;
                    report.command = command;
                    let dir = out.as_ref().map(|o| report.write(o, &problem, imported)).transpose()?;
                    (report, dir)
                }
                None => {
                    let r = resolve(&problem)?;
                    let mut report = catflip::robust::check(&problem, &r.schedule, "the problem's schedule")?;
                    report.command = command;
                    let dir = out.as_ref().map(|o| report.write(o, &problem, &r.schedule)).transpose()?;
                    (report, dir)
                }
            };
            if let Some(dir) = dir {
                eprintln!("wrote {}", dir.display());
            }
            emit(common.json, &report, || report.to_markdown())?;
        }
        Command::CompareModels { common, verify, out, quiet } => {
            let problem = load(&common, None)?;
            if let Some(o) = &out {
                check_target(o, &format!("{}-models", problem.name))?;
            }
            let verify_arg = if verify { " --verify" } else { "" };
            let out_arg = out.as_ref().map_or(String::new(), |o| format!(" --out {}", o.display()));
            let command = regenerate(
                format!("cargo run --release -- compare-models {}{verify_arg}{out_arg}", common.problem.display()),
                &common.overrides,
            );
            let spinner = progress(quiet || common.json, "compare-models: the whole optimum of each cat model".into());
            let comparison = catflip::compare_models::compare_models(&problem, verify, &command)?;
            spinner.finish_and_clear();
            // Without any optimum there is nothing to compare: the table says why, nothing is
            // written, and the exit is non-zero.
            if comparison.cheapest.is_some() {
                if let Some(dir) = out.as_ref().map(|o| comparison.write(o)).transpose()? {
                    eprintln!("wrote {}", dir.display());
                }
            }
            emit(common.json, &comparison, || comparison.to_markdown())?;
            if comparison.cheapest.is_none() {
                anyhow::bail!("compare-models: no cat model has an optimum that flips the cat (each row says why)");
            }
        }
        Command::Compare { common, verify } => {
            let r = resolve(&load(&common, None)?)?;
            let table = catflip::report::compare::compare(&r, &[]);
            if verify {
                let spinner = progress(common.json, "compare --verify: rapier".into());
                let verified =
                    catflip::measure::run::verify_library(&r, &catflip::measure::timings::Stopwatch::start())?;
                spinner.finish_and_clear();
                let (markdown, json) = catflip::report::export::with_verification(&r, &table, &verified)?;
                emit(common.json, &json, || markdown)?;
                let missing = verified.iter().filter(|m| m.finest().is_none()).count();
                if missing > 0 {
                    anyhow::bail!(
                        "compare --verify: rapier has no result for {missing} of the {} profiles (inconclusive: no usable run; each row says why)",
                        verified.len()
                    );
                }
            } else {
                emit(common.json, &table, || table.to_markdown())?;
            }
        }
    }
    Ok(())
}

/// Keeps freed memory in the process (glibc's allocator). The solvers allocate and free the same
/// large buffers thousands of times per run (each conic solve builds its KKT factorisation). By
/// default glibc serves a block of 128 KiB or more by a fresh `mmap` and returns it to the system
/// when freed, so every solve pays its page faults again. With a 32 MiB threshold (the largest
/// every glibc accepts: half its heap size) the heap keeps and reuses the blocks, and a high trim
/// threshold keeps the heap's freed top: `catflip run problems/paper.toml` makes about 15 000
/// page faults instead of 81 000 (with the animation's frames drawn in batches), and its system
/// time falls from ~0.2 s to ~0.05 s (`perf stat -e page-faults`). Results do not change: only
/// where the memory comes from.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_freed_memory() {
    // SAFETY: `mallopt` only sets the allocator's tuning parameters; it is called first thing in
    // `main`, before any other thread exists. The trim threshold is set only when the mmap
    // threshold was accepted (return 1): setting it alone would freeze glibc's dynamic mmap
    // threshold at its 128 KiB default.
    unsafe {
        if libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20) == 1 {
            libc::mallopt(libc::M_TRIM_THRESHOLD, 1 << 30);
        }
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_freed_memory() {}

fn main() -> ExitCode {
    keep_freed_memory();
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
