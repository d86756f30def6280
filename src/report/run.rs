//! `catflip run`: everything for one problem, written to `results/<name>/`.
//!
//! The audit, the exact engine on the problem's schedule, the peak-torque table (every library
//! profile, the QP optimum and the exact-dynamics refinement), the rapier verification of every
//! schedule in that table, the schedules as CSV, the plots and the animation, and a Markdown
//! report with a provenance header. Files are written into a scratch folder beside the target
//! and moved into place only when everything succeeded: a failed run leaves no half-written
//! results (and keeps the previous ones).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::engines::circulation::{CirculationError, Resolved, ResolvedCirculation};
use crate::engines::evaluate::Evaluation;
use crate::engines::peaks::PhasePeaks;
use crate::engines::rapier::RapierError;
use crate::optimize::{optimize, OptimizeError, OptimizeReport};
use crate::problem::{Problem, ProfileKind};
use crate::report::audit::AuditError;
use crate::report::bench::BenchError;
use crate::report::compare::{compare, CompareTable};
use crate::report::results_dir::Staging;
use crate::report::simulate::{exact_report, rapier_report, SimulationReport};
use crate::report::whole::WHOLE;
use crate::schedule::variant::{Origin, Variant, VariantCirculation};
use crate::schedule::{Phase, Schedule, Trajectory};

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// A file or folder could not be written.
    #[error("cannot write {path}")]
    Io {
        /// The path.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The problem's circulation could not be resolved.
    #[error(transparent)]
    Circulation(#[from] CirculationError),
    /// The rapier engine failed.
    #[error(transparent)]
    Rapier(#[from] RapierError),
    /// An optimiser failed.
    #[error(transparent)]
    Optimize(#[from] OptimizeError),
    /// The audit refused a value.
    #[error(transparent)]
    Audit(#[from] AuditError),
    /// The benchmark failed.
    #[error(transparent)]
    Bench(#[from] BenchError),
    /// A plot failed.
    #[error(transparent)]
    Plot(#[from] crate::report::plot::PlotError),
    /// A result could not be serialised.
    #[error("cannot serialise {0}")]
    Json(&'static str),
    /// The problem could not be written as TOML for the report's header.
    #[error("cannot write the problem as TOML for the report header")]
    Toml(#[from] toml::ser::Error),
    /// The results folder could not be staged or swapped in.
    #[error(transparent)]
    ResultsDir(#[from] crate::report::results_dir::ResultsDirError),
    /// The whole-manoeuvre optimisation could not run.
    #[error(transparent)]
    Whole(#[from] crate::optimize::whole::WholeError),
    /// A schedule file could not be written.
    #[error(transparent)]
    Exchange(#[from] crate::exchange::ExchangeError),
}

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunOutcome {
    /// The results folder.
    pub dir: PathBuf,
    /// Files written, relative to it.
    pub files: Vec<String>,
    /// The report's summary lines.
    pub summary: String,
}

struct Writer {
    /// Where files are written (the scratch folder).
    dir: PathBuf,
    /// The folder the user asked for, named in errors.
    shown: PathBuf,
    files: Vec<String>,
}

impl Writer {
    fn put(&mut self, name: &str, contents: &str) -> Result<(), RunError> {
        let path = self.dir.join(name);
        let shown = self.shown.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|source| io(shown.parent().unwrap_or(&shown), source))?;
        }
        std::fs::write(&path, contents).map_err(|source| io(&shown, source))?;
        self.files.push(name.to_string());
        Ok(())
    }

    fn json(&mut self, name: &str, value: &impl serde::Serialize) -> Result<(), RunError> {
        let text = serde_json::to_string_pretty(value).map_err(|_| RunError::Json("a JSON result"))?;
        self.put(name, &(text + "\n"))
    }

    fn record(&mut self, written: Vec<PathBuf>) {
        self.files.extend(written.iter().map(|p| p.strip_prefix(&self.dir).unwrap_or(p).display().to_string()));
    }
}

fn io(path: &Path, source: std::io::Error) -> RunError {
    RunError::Io { path: path.display().to_string(), source }
}

/// A verified schedule: the exact engine's and rapier's reports side by side.
struct Verified {
    variant: Variant,
    schedule: Schedule,
    exact: SimulationReport,
    rapier: SimulationReport,
}

/// Runs everything for the resolved problem and writes `out_root/<name>/`. `command` is the
/// command line that regenerates it, for the report's header.
pub fn run(r: &Resolved, command: &str, out_root: &Path) -> Result<RunOutcome, RunError> {
    run_with(r, command, out_root, &crate::exchange::ExportOptions::default())
}

/// [`run`] with the schedule files sampled as `export` says (e.g. a uniform `--rate`).
pub fn run_with(
    r: &Resolved,
    command: &str,
    out_root: &Path,
    export: &crate::exchange::ExportOptions,
) -> Result<RunOutcome, RunError> {
    atomically(out_root, &r.problem.name, |w| produce(r, command, export, w))
}

/// Runs `catflip bench` on the resolved problem and writes `out_root/bench/`.
pub fn run_bench(r: &Resolved, command: &str, out_root: &Path, dts: &[f64]) -> Result<RunOutcome, RunError> {
    atomically(out_root, "bench", |w| {
        let report = crate::report::bench::bench(r, dts)?;
        w.put("bench.csv", &report.to_csv())?;
        w.json("bench.json", &report)?;
        let plots = w.dir.join("plots");
        std::fs::create_dir_all(&plots).map_err(|e| io(&w.shown.join("plots"), e))?;
        w.record(report.plots(&plots)?);
        let settings = toml::to_string(&r.problem)?;
        let mut md = crate::report::provenance::header("catflip benchmark: run time against error", command, &settings);
        md.push_str(&report.to_markdown());
        w.put("bench.md", &md)?;
        Ok(report.reach_table())
    })
}

/// Writes into a scratch folder beside `final_dir` and moves it into place only on success.
fn atomically(
    out_root: &Path,
    name: &str,
    body: impl FnOnce(&mut Writer) -> Result<String, RunError>,
) -> Result<RunOutcome, RunError> {
    let staging = Staging::begin(out_root, name)?;
    let mut w = Writer { dir: staging.dir().to_path_buf(), shown: staging.target().to_path_buf(), files: Vec::new() };
    // On an error the staging folder is dropped, and with it the scratch folder: the previous
    // results stay as they were.
    let summary = body(&mut w)?;
    let dir = staging.commit()?;
    Ok(RunOutcome { dir, files: w.files, summary })
}

/// The library profiles shown in the plots beside the optimised ones.
const SHOWN: [ProfileKind; 4] =
    [ProfileKind::PaperCosine, ProfileKind::Cycloidal, ProfileKind::BangBang, ProfileKind::Trapezoid];

fn produce(
    r: &Resolved,
    command: &str,
    export: &crate::exchange::ExportOptions,
    w: &mut Writer,
) -> Result<String, RunError> {
    let problem = &r.problem;
    let settings = toml::to_string(problem)?;
    // 1. The audit.
    let audit = crate::report::audit::audit_with_exact(r)?;
    w.put("audit.md", &audit.to_markdown())?;
    w.json("audit.json", &audit)?;
    // 2. Optimisation and the peak-torque table (every schedule evaluated once).
    let opt = optimize(r)?;
    w.put("optimize.md", &opt.to_markdown())?;
    w.json("optimize.json", &opt)?;
    let whole = crate::report::whole::whole(r)?;
    w.put("whole.md", &whole.to_markdown())?;
    w.json("whole.json", &whole)?;
    let mut retimed = crate::report::whole::retime_rows(r, "problem", &r.schedule);
    if let Some(cal) = r.calibrated() {
        let name = Variant::new(Origin::Library(problem.manoeuvre.profile)).calibrated().to_string();
        retimed.extend(crate::report::whole::retime_rows(r, &name, &r.schedule.with_circulation(cal.radians)));
    }
    w.put("retime.md", &crate::report::whole::retime_markdown(&retimed))?;
    w.json("retime.json", &retimed)?;
    let extra: Vec<_> = opt.optima().map(|o| o.evaluation.clone()).collect();
    let table = compare(r, &extra);
    let mut compare_md = table.to_markdown();
    compare_md.extend(crate::report::whole::compare_row_markdown(&whole));
    w.put("compare.md", &compare_md)?;
    w.put("compare.csv", &table.to_csv())?;
    // 3. Every schedule of the table through both engines, and the recommended one: the most
    // refined schedule with the calibrated circulation (when the calibration converged).
    let mut runs: Vec<(Variant, Schedule, ResolvedCirculation, Option<&Evaluation>)> = r
        .library()
        .iter()
        .map(|(k, s, e)| (Variant::new(Origin::Library(*k)), s.clone(), r.circulation, Some(e)))
        .collect();
    runs.extend(opt.optima().map(|o| (o.variant, o.schedule.clone(), r.circulation, Some(&o.exact))));
    let most_refined =
        opt.optima().last().filter(|o| matches!(o.variant.origin, Origin::Refined | Origin::RefinedAllPhases));
    if let (Some(o), Some(cal)) = (most_refined, r.calibrated()) {
        runs.push((o.variant.calibrated(), o.schedule.with_circulation(cal.radians), cal, None));
    }
    let verified = runs
        .into_iter()
        .map(|(variant, schedule, circ, evaluation)| {
            let exact = exact_report(r, &schedule, circ, evaluation);
            let rapier = rapier_report(r, &schedule, &exact)?;
            Ok(Verified { variant, schedule, exact, rapier })
        })
        .collect::<Result<Vec<_>, RunError>>()?;
    let whole_verification = crate::report::whole::verify_whole(r, &whole)?;
    w.put("verification.csv", &verification_csv(&verified))?;
    let mut verification_md = verification_markdown(problem, &verified);
    if let Some(v) = &whole_verification {
        verification_md.extend(crate::report::whole::verification_row_markdown(&whole, v));
        w.json("verification_whole.json", v)?;
    }
    w.put("verification.md", &verification_md)?;
    w.json("simulate_exact.json", &verified.iter().map(|v| &v.exact).collect::<Vec<_>>())?;
    w.json("simulate_rapier.json", &verified.iter().map(|v| &v.rapier).collect::<Vec<_>>())?;
    // 4. Schedules for robots and other simulators (CSV + JSON sidecar), and the model files.
    let mut exported = vec![("problem".to_string(), r.schedule.clone())];
    exported.extend(
        verified
            .iter()
            .filter(|v| v.variant.origin.is_optimised())
            .map(|v| (v.variant.to_string(), v.schedule.clone())),
    );
    for (name, contents) in crate::exchange::results_files(problem, &exported, export)? {
        w.put(&name, &contents)?;
    }
    if let Some(spline) = whole.spline() {
        let pieces: Vec<String> = (0..spline.piece_durations().len()).map(|i| format!("span-{i}")).collect();
        let description = "the whole-manoeuvre optimum: both joints as clamped cubic B-splines over the whole fall";
        let file = crate::exchange::write_trajectory(problem, spline, &pieces, WHOLE, description, export)?;
        w.put(&format!("schedules/{WHOLE}.csv"), &file.csv)?;
        w.put(&format!("schedules/{WHOLE}.json"), &file.sidecar_json()?)?;
    }
    // 5. Plots and the animation.
    let plots = w.dir.join("plots");
    std::fs::create_dir_all(&plots).map_err(|e| io(&w.shown.join("plots"), e))?;
    let shown: Vec<(String, Schedule)> = verified
        .iter()
        .filter(|v| v.variant.circulation == VariantCirculation::Problem)
        .filter(|v| match v.variant.origin {
            Origin::Library(k) => SHOWN.contains(&k),
            _ => true,
        })
        .map(|v| (v.variant.to_string(), v.schedule.clone()))
        .collect();
    w.record(crate::report::plot::profiles_plot(&plots, problem, &shown)?);
    let mut curves: Vec<(String, &dyn Trajectory)> =
        shown.iter().map(|(n, s)| (n.clone(), s as &dyn Trajectory)).collect();
    if let Some(spline) = whole.spline() {
        curves.push((WHOLE.to_string(), spline));
    }
    w.record(crate::report::plot::torques_plot(&plots, problem, &curves)?);
    if let Some(spline) = whole.spline() {
        w.record(crate::report::plot::trajectory_torques_plot(
            &plots,
            problem,
            "torques_whole_optimum",
            WHOLE,
            spline,
        )?);
        w.record(crate::report::plot::flip_plot(&plots.join(WHOLE), problem, WHOLE, spline, 256)?);
    }
    let own = Variant::new(Origin::Library(problem.manoeuvre.profile)).to_string();
    w.record(crate::report::plot::flip_plot(&plots, problem, &own, &r.schedule, 256)?);
    // The animation shows the schedule to replay: the whole-manoeuvre optimum when there is
    // one (it flips the cat exactly), else the most refined calibrated one, else the problem's.
    let gif = plots.join("flip.gif");
    if let Some(spline) = whole.spline() {
        w.record(crate::report::plot::flip_animation(&gif, problem, WHOLE, spline, 72)?);
    } else {
        let (anim_name, anim_schedule) = verified
            .iter()
            .find(|v| v.variant.is_calibrated())
            .map_or((own, &r.schedule), |v| (v.variant.to_string(), &v.schedule));
        w.record(crate::report::plot::flip_animation(&gif, problem, &anim_name, anim_schedule, 72)?);
    }
    // 6. The report.
    let optimum = crate::report::whole::summary_lines(&whole, whole_verification.as_ref(), &retimed);
    let summary = summary(r, &table, &opt, &verified, &optimum);
    let mut report =
        crate::report::provenance::header(&format!("catflip results: {}", problem.name), command, &settings);
    report.push_str(&summary);
    report.push_str("\n## Files\n\n");
    for f in &w.files {
        let _ = writeln!(report, "- [`{f}`]({f})");
    }
    w.put("report.md", &report)?;
    Ok(summary)
}

fn verification_csv(rows: &[Verified]) -> String {
    let mut header = vec!["problem", "schedule", "engine", "circulation_rad", "twist_deg", "swing_deg"];
    header.extend(PhasePeaks::CSV_HEADER.split(','));
    header.extend(["momentum_max", "dt_s", "tracking1_rad", "tracking2_rad", "run_time_s"]);
    header.extend(crate::engines::rapier::Verification::CSV_HEADER.split(','));
    let mut all: Vec<(String, &SimulationReport)> =
        rows.iter().flat_map(|v| [(v.variant.to_string(), &v.exact), (v.variant.to_string(), &v.rapier)]).collect();
    all.sort_by(|a, b| (&a.0, a.1.engine).cmp(&(&b.0, b.1.engine)));
    let records = all.into_iter().map(|(name, r)| {
        let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:.6e}"));
        let tr = r.tracking_error_rad;
        let mut f = vec![
            r.problem.clone(),
            name,
            r.engine.to_string(),
            format!("{:.12}", r.circulation_rad),
            format!("{:.9}", r.twist_deg),
            format!("{:.9}", r.swing_deg),
        ];
        f.extend(r.peak_torque_nm.fields());
        f.extend([
            format!("{:.3e}", r.momentum_max),
            opt(r.dt),
            opt(tr.map(|t| t[0])),
            opt(tr.map(|t| t[1])),
            format!("{:.6}", r.run_time_s),
        ]);
        f.extend(r.verification.as_ref().map_or_else(|| vec![String::new(); 7], |v| v.fields().to_vec()));
        f
    });
    crate::exchange::table::csv_table(&header, records)
}

fn verification_markdown(problem: &Problem, rows: &[Verified]) -> String {
    let mut s = format!(
        "## Verification in rapier3d-f64 (`{}`, first dt {})\n\nEvery schedule of the peak-torque table, through the exact engine and rapier. Twist and swing in degrees; torques in N·m; momentum relative to I*·max|q̇|.\n\n",
        problem.name, problem.rapier.dt
    );
    s.push_str("rapier's multibody integrator is first order and leaks angular momentum at a rate proportional to dt, which moves the twist; *rapier → 0* is the Richardson extrapolation from the last two steps of the dt sequence, and *estimates* are rapier's own errors of the extrapolated twist, swing and peak torque (the change between the last two extrapolations). The rapier columns are from the finest step.\n\n");
    if let Some(v) = rows.iter().find_map(|v| v.rapier.verification.as_ref()) {
        let _ =
            writeln!(s, "Tolerances: {}; budget {} rapier steps per schedule.\n", v.tolerances_text(), v.step_budget);
    }
    s.push_str("| schedule | exact twist | rapier twist | rapier → 0 twist | exact swing | rapier swing | rapier → 0 swing | exact peak | rapier peak | peak diff | rapier momentum drift | tracking error rad | verdict | dt sequence s | estimates | rapier time s |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---|---:|\n");
    for v in rows {
        let (e, r) = (&v.exact, &v.rapier);
        let tr = r.tracking_error_rad.unwrap_or([f64::NAN; 2]);
        let (xt, xs) = r.extrapolated.map_or((f64::NAN, f64::NAN), |x| (x.twist_deg, x.swing_deg));
        let _ = writeln!(
            s,
            "| {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.3} | {:.3} | {:+.2}% | {:.2e} | {:.1e}, {:.1e} | {} |",
            v.variant,
            e.twist_deg,
            r.twist_deg,
            xt,
            e.swing_deg,
            r.swing_deg,
            xs,
            e.peak_torque_nm.max,
            r.peak_torque_nm.max,
            100.0 * (r.peak_torque_nm.max / e.peak_torque_nm.max - 1.0),
            r.momentum_max,
            tr[0],
            tr[1],
            r.verification.as_ref().map_or("— | — | — | —".to_string(), |x| x.table_cells())
        );
    }
    s
}

fn summary(r: &Resolved, table: &CompareTable, opt: &OptimizeReport, verified: &[Verified], optimum: &str) -> String {
    let problem = &r.problem;
    let mut s = String::new();
    let _ = writeln!(s, "## Summary\n");
    let own = Origin::Library(problem.manoeuvre.profile);
    if let Some(p) = table.rows.iter().find(|row| row.origin == own && row.profile == own.profile_name()) {
        let verdict = if (p.twist_deg.abs() - 180.0).abs() < 1e-6 { "a half turn" } else { "not a half turn" };
        let _ = writeln!(
            s,
            "- The problem's schedule ({} profile, {} path, circulation {:.6} rad, {}) turns the cat by **{:.6}°** with a swing of {:.6}° (exact engine): {verdict}.",
            p.profile, problem.manoeuvre.bend_path, p.circulation_rad, table.circulation.source, p.twist_deg, p.swing_deg
        );
        let e = &p.exact_peak_nm;
        let _ = writeln!(
            s,
            "- Its exact peak torque is **{:.4} N·m** (bend {:.4}, twist {:.4}, unbend {:.4}); the paper's model I*·max|ω̇| gives {:.4} N·m for the twist.",
            e.max,
            e.phase_max(Phase::Bend),
            e.phase_max(Phase::Twist),
            e.phase_max(Phase::Unbend),
            p.model_peak_nm
        );
        if p.velocity_jumps > 0 {
            let _ = writeln!(
                s,
                "- It has {} velocity jump(s): an impulse of up to {:.4} N·m·s, not a torque.",
                p.velocity_jumps, p.max_impulse_nms
            );
        }
    }
    let c = &opt.calibration;
    if c.status.is_converged() {
        let _ = writeln!(
            s,
            "- The calibrated circulation {:.9} rad makes the twist exactly 180° ({:.9}°; {}); the swing, {:.6}°, is what remains: one circulation cannot also zero it.",
            c.circulation,
            c.twist.to_degrees(),
            c.status,
            c.swing.to_degrees()
        );
    } else {
        let _ = writeln!(
            s,
            "- The calibration FAILED ({}, {} evaluations): no circulation near {:.9} rad was found that turns this cat by exactly 180°, so no calibrated schedule is reported.",
            c.status, c.evaluations, r.circulation.radians
        );
    }
    let closed = opt.qp_closed_form_nm.map_or("none with limits".to_string(), |c| format!("{c:.6}"));
    let _ = writeln!(
        s,
        "- Profile QP: {}, model peak {} N·m (closed form {closed}).",
        opt.qp.status,
        opt.qp.peak_torque.map_or("none".to_string(), |p| format!("{p:.6}"))
    );
    if let Some(o) = &opt.refined_optimum {
        let t = o.evaluation.exact_peak_nm.twist;
        let _ = writeln!(
            s,
            "- Exact-dynamics refinement: exact twist-phase peak {:.4} N·m against {:.4} N·m for the best library profile ({}); the whole manoeuvre's peak is then {:.4} N·m (bend and unbend are not retimed).",
            t[0].max(t[1]),
            opt.best_library.1,
            opt.best_library.0,
            o.evaluation.exact_peak_nm.max
        );
    }
    if let Some(w) = &opt.whole {
        let e = &w.optimum.evaluation.exact_peak_nm;
        let _ = writeln!(
            s,
            "- Retiming the bend and the unbend too (same joint path, same flip): the whole manoeuvre's exact peak falls to **{:.4} N·m** (bend {:.4}, twist {:.4}, unbend {:.4}).",
            e.max,
            e.phase_max(Phase::Bend),
            e.phase_max(Phase::Twist),
            e.phase_max(Phase::Unbend)
        );
    }
    let worst = verified.iter().map(|v| (v.exact.twist_deg - v.rapier.twist_deg).abs()).fold(0.0, f64::max);
    let worst_x =
        verified.iter().filter_map(|v| v.rapier.extrapolated).map(|x| x.twist_error_deg.abs()).fold(0.0, f64::max);
    let worst_peak = verified.iter().filter_map(|v| v.rapier.peak_torque_rel_error).map(f64::abs).fold(0.0, f64::max);
    let _ = writeln!(
        s,
        "- rapier3d-f64 verification of {} schedules (first dt {}): peak torques within {:.2}% of the exact engine; twist within {:.3}° raw (rapier's first-order momentum leak) and {:.3}° extrapolated to dt → 0.",
        verified.len(),
        problem.rapier.dt,
        100.0 * worst_peak,
        worst,
        worst_x
    );
    let _ = writeln!(
        s,
        "- Verdicts: {}.",
        crate::engines::rapier::Verification::verdicts_line(
            verified.iter().map(|v| (v.variant.to_string(), v.rapier.verification.as_ref()))
        )
    );
    s.push_str(optimum);
    let _ = writeln!(
        s,
        "\nSee `audit.md`, `compare.md`, `optimize.md`, `whole.md`, `retime.md` and `verification.md` for the tables."
    );
    s
}
