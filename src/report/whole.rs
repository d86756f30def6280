//! `catflip optimize --whole`: the whole-manoeuvre optimum ([`crate::optimize::whole`]) and the
//! certified convex retiming of the problem's own path ([`crate::optimize::retime`]), as a report.
//!
//! Every number here is re-measured by the exact engine on the final trajectory, never taken from
//! a linearisation: the optimum's twist and swing from [`crate::engines::exact::flip`], its peak
//! from [`crate::engines::torque::peak_torques`] (on a cat other than the paper's, the general
//! core's, [`crate::optimize::whole::WholeCat`]). The optimum has no phases of its own (it bends
//! and circulates at once), so its peaks are also given over the time windows of the problem's
//! phases, for the peak-torque table; `max` is the peak over the whole fall.

use std::fmt::Write as _;

use rayon::prelude::*;
use serde::Serialize;

use crate::engines::motors::LimitUse;
use crate::engines::peaks::PhasePeaks;
use crate::engines::rapier::{verify_with, RapierError, RapierOptions, Reference, Verification};
use crate::engines::resolved::Resolved;
use crate::optimize::retime::{retime_schedule, RetimeSettings, Split};
use crate::optimize::whole::{
    optimize_whole_spinning, BSpline, Objective, WholeCat, WholeError, WholeOutcome, WholeSolution,
};
use crate::report::check::{verification_row, ExactValues};
use crate::report::compare::CompareLine;
use crate::schedule::{Schedule, Trajectory};

/// Samples per second of fall used to split the optimum's peaks over the phase windows (the
/// whole-fall maximum is the refined peak of the optimiser's re-measurement).
const WINDOW_SAMPLES: usize = 20_000;

/// A limit whose usage ratio is within this of 1 counts as active.
pub const ACTIVE_RATIO: f64 = 1e-3;

/// The whole-manoeuvre optimum of a problem.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WholeReport {
    /// Problem name.
    pub problem: String,
    /// The cat optimised, in words ([`crate::model::Cat::describe`]).
    pub cat: String,
    /// What was minimised.
    pub objective: Objective,
    /// How the best start ended (`converged`), or why there is no optimum.
    pub status: String,
    /// Signed twist of the optimum, degrees (absent when no start flipped the cat).
    pub twist_deg: Option<f64>,
    /// Swing of the optimum, degrees.
    pub swing_deg: Option<f64>,
    /// Peak motor torques of the optimum, N·m: `max` over the whole fall, and over the time
    /// windows of the problem's phases.
    pub peak_torque_nm: Option<PhasePeaks>,
    /// `∫ τ·τ dt` of the optimum, N²·m²·s.
    pub energy: Option<f64>,
    /// Trust-region iterations of the best start.
    pub iterations: Option<usize>,
    /// The largest bend of the optimum (angle between the spine axes), degrees.
    pub max_bend_deg: Option<f64>,
    /// How far its bend direction turns over the fall, turns.
    pub bend_turns: Option<f64>,
    /// The optimum's fall time, s: the problem's, or with the objective `min-time` the least
    /// fall time within the motors.
    pub fall_time_s: Option<f64>,
    /// The drop height of that fall, `g T²/2`, m.
    pub drop_height_m: Option<f64>,
    /// Peak joint speeds of joints 1 and 2, rad/s.
    pub peak_speed_rad_s: Option<[f64; 2]>,
    /// Peak mechanical powers `|τ q̇|` of joints 1 and 2, W.
    pub peak_power_w: Option<[f64; 2]>,
    /// The motor limits the optimum reaches (usage within [`ACTIVE_RATIO`] of 1), where and when.
    pub active_limits: Vec<LimitUse>,
    /// The motors' verdict on the optimum, in words ("ideal motors" without `[actuator]`).
    pub motors: Option<String>,
    /// Every start's outcome, the best one included.
    pub outcome: WholeOutcome,
    /// The release's total angular momentum `drop.angular_momentum`, N·m·s, world frame (left
    /// out at zero): every number above is then that of the spinning motion.
    #[serde(skip_serializing_if = "is_zero3")]
    pub angular_momentum_nms: [f64; 3],
}

fn is_zero3(l: &[f64; 3]) -> bool {
    l.iter().all(|x| *x == 0.0)
}

impl WholeReport {
    /// The optimum, when a start converged to a flip.
    pub fn best(&self) -> Option<&WholeSolution> {
        self.outcome.best()
    }

    /// The optimum's trajectory, when there is one.
    pub fn spline(&self) -> Option<&BSpline> {
        self.best().map(|b| &b.spline)
    }
}

/// Runs the whole-manoeuvre optimisation on a resolved problem (`[optimize.whole]`), on its cat
/// model ([`WholeCat`]: the paper's cat through the two-cylinder engine).
pub fn whole(r: &Resolved) -> Result<WholeReport, WholeError> {
    let p = &r.problem;
    let settings = &p.optimize.whole;
    let cat = WholeCat::from(r.model());
    let outcome = optimize_whole_spinning(
        &cat,
        p.drop.fall_time(),
        &p.manoeuvre,
        settings,
        &p.actuator.motors(),
        p.exact.tolerance,
        &p.drop.spin(),
    )?;
    let best = outcome.best();
    let status = match best {
        Some(b) => b.status.to_string(),
        None => outcome.no_optimum(settings, p.exact.tolerance),
    };
    let peaks = best.map(|b| window_peaks(r, &cat, &b.spline, b.peak_torque_nm));
    let fall = best.map(|b| b.fall_time_s);
    Ok(WholeReport {
        problem: p.name.clone(),
        cat: cat.describe(),
        objective: settings.objective,
        status,
        twist_deg: best.map(|b| b.twist.to_degrees()),
        swing_deg: best.map(|b| b.swing.to_degrees()),
        peak_torque_nm: peaks,
        energy: best.map(|b| b.energy),
        iterations: best.map(|b| b.iterations),
        max_bend_deg: best.map(|b| b.max_bend_deg),
        bend_turns: best.map(|b| b.bend_turns),
        fall_time_s: fall,
        drop_height_m: fall.map(|t| 0.5 * p.drop.gravity * t * t),
        peak_speed_rad_s: best.map(|b| b.motors.peak_speed_rad_s.map(|x| x.value)),
        peak_power_w: best.map(|b| b.motors.peak_power_w.map(|x| x.value)),
        active_limits: best
            .map(|b| b.motors.limits.iter().copied().filter(|l| l.ratio >= 1.0 - ACTIVE_RATIO).collect())
            .unwrap_or_default(),
        motors: best.map(|b| b.motors.verdict()),
        outcome,
        angular_momentum_nms: p.drop.angular_momentum,
    })
}

/// The optimum's peaks over the time windows of the problem's phases (as fractions of its own
/// duration, which `min-time` makes shorter than the problem's fall); `max` is `peak`, the
/// refined whole-fall peak (at least every window's sampled peak).
fn window_peaks(r: &Resolved, cat: &WholeCat, spline: &BSpline, peak: f64) -> PhasePeaks {
    let total = spline.total_duration();
    let to_schedule = r.schedule.duration() / total;
    let n = ((WINDOW_SAMPLES as f64 * total).ceil() as usize).max(64);
    let mut w = [[0.0f64; 2]; 3];
    for (t, tau) in sampled_torques(r, cat, spline, n) {
        let window = &mut w[r.schedule.locate(t * to_schedule).0.index()];
        for (m, x) in window.iter_mut().zip(tau) {
            *m = m.max(x.abs());
        }
    }
    let sampled = w.iter().flatten().copied().fold(0.0, f64::max);
    PhasePeaks { bend: w[0], twist: w[1], unbend: w[2], max: peak.max(sampled) }
}

/// The motor torques `(t, [τ₁, τ₂])` of `spline` on `cat` at `n + 1` instants evenly spaced over
/// it, ends included, released as the problem says (with spin, at the orientations of the
/// spinning motion).
fn sampled_torques(r: &Resolved, cat: &WholeCat, spline: &BSpline, n: usize) -> Vec<(f64, [f64; 2])> {
    let total = spline.total_duration();
    let spin = r.problem.drop.spin();
    let history = r.problem.drop.spins().then(|| cat.spin_history(spline, &spin, r.problem.exact.tolerance).1);
    let source = cat.torque_source(history.as_ref());
    (0..=n)
        .map(|k| {
            let t = total * k as f64 / n as f64;
            let (piece, s) = spline.locate_piece(t);
            (t, source.at(spline, piece, s, &spline.piece_state(piece, s)).tau)
        })
        .collect()
}

impl WholeReport {
    /// The report as Markdown.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "## Whole-manoeuvre optimum (`{}`, objective {})\n", self.problem, self.objective.name());
        let _ = writeln!(s, "The cat: {}.\n", self.cat);
        let _ = writeln!(
            s,
            "Both joint trajectories over the whole fall (clamped cubic B-splines), optimised by successive convexification with Clarabel subproblems; the flip R(T) = Rz(π) is a constraint, and every number below is re-measured by the exact engine on the final trajectory.\n"
        );
        if !is_zero3(&self.angular_momentum_nms) {
            let l = self.angular_momentum_nms;
            let _ = writeln!(
                s,
                "Released with spin: total angular momentum L = [{}, {}, {}] N·m·s (world frame). The model, the flip and every torque below are those of the spinning motion (exact engine with spin, fourth-order Runge–Kutta); the ±π turning directions are not equivalent, so the starts turn both ways.\n",
                l[0], l[1], l[2]
            );
        }
        match self.best() {
            Some(b) => {
                let p = self.peak_torque_nm.unwrap_or(PhasePeaks {
                    bend: [0.0; 2],
                    twist: [0.0; 2],
                    unbend: [0.0; 2],
                    max: b.peak_torque_nm,
                });
                let _ = writeln!(
                    s,
                    "- Status: **{}** (start `{}`, {} iterations, {} Newton steps, {:.2} s).",
                    self.status, b.start, b.iterations, b.polish_steps, b.seconds
                );
                let _ = writeln!(
                    s,
                    "- Flip: twist **{:+.9}°**, swing **{:.3e}°** (| |twist| − 180° | = {:.2e} rad; engine error estimate {:.1e} rad).",
                    b.twist.to_degrees(),
                    b.swing.to_degrees(),
                    b.twist_error,
                    b.flip_error_estimate
                );
                let _ = writeln!(
                    s,
                    "- Peak motor torque **{:.6} N·m** at t = {:.4} s; over the problem's phase windows bend [{:.4}, {:.4}], twist [{:.4}, {:.4}], unbend [{:.4}, {:.4}] N·m.",
                    p.max, b.peak_time, p.bend[0], p.bend[1], p.twist[0], p.twist[1], p.unbend[0], p.unbend[1]
                );
                let _ = writeln!(
                    s,
                    "- Energy ∫τ·τ dt = {:.6} N²·m²·s; largest bend {:.2}° (angle between the halves ≥ {:.2}°); the bend direction turns {:+.3} turns.",
                    b.energy,
                    b.max_bend_deg,
                    180.0 - b.max_bend_deg,
                    b.bend_turns
                );
                if self.objective != Objective::Energy {
                    let c = &b.chatter;
                    let _ = writeln!(
                        s,
                        "- Torque switches: joint 1 {}×, joint 2 {}×; total variation {:.1} %, {:.1} % above that of a clean bang-bang profile with the same switches; deepest dip of a saturated arc to {:.1} %, {:.1} % of the peak.",
                        c.switches[0],
                        c.switches[1],
                        100.0 * c.excess_variation[0],
                        100.0 * c.excess_variation[1],
                        100.0 * c.deepest_dip[0],
                        100.0 * c.deepest_dip[1]
                    );
                }
                let _ = writeln!(s, "{}", self.motor_lines(b));
            }
            None => {
                let _ = writeln!(s, "- **{}**", self.status);
            }
        }
        let _ = writeln!(
            s,
            "\n| start | status | twist ° | swing ° | peak N·m | energy | max bend ° | iterations | time s | why |"
        );
        let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|---|");
        for o in &self.outcome.solutions {
            let _ = writeln!(
                s,
                "| {} | {} | {:+.6} | {:.2e} | {:.6} | {:.6} | {:.2} | {} | {:.2} | {} |",
                o.start,
                o.status,
                o.twist.to_degrees(),
                o.swing.to_degrees(),
                o.peak_torque_nm,
                o.energy,
                o.max_bend_deg,
                o.iterations,
                o.seconds,
                o.reason
            );
        }
        for k in &self.outcome.skipped {
            let _ = writeln!(s, "| {} | not started | | | | | | | | {} |", k.start, k.reason);
        }
        if let Some(b) = self.best() {
            let _ = writeln!(
                s,
                "\nIterations of the best start (`{}`; the stages: coarse and fine energy, then the objective):\n",
                b.start
            );
            let _ = writeln!(
                s,
                "| # | stage objective | peak N·m | violation | trust radius | subproblem | ratio | accepted |"
            );
            let _ = writeln!(s, "|---:|---|---:|---:|---:|---|---:|---|");
            for (i, l) in b.log.iter().enumerate() {
                let _ = writeln!(
                    s,
                    "| {} | {} | {:.6} | {:.2e} | {:.2e} | {} | {} | {} |",
                    i + 1,
                    l.objective.name(),
                    l.peak_nm,
                    l.violation,
                    l.trust_radius,
                    l.subproblem,
                    l.ratio.map_or("—".to_string(), |x| format!("{x:.3}")),
                    if l.accepted { "yes" } else { "no" }
                );
            }
        }
        s
    }
}

impl WholeReport {
    /// The fall and motor lines of the Markdown report.
    fn motor_lines(&self, b: &WholeSolution) -> String {
        let m = &b.motors;
        let fall = match (self.objective, self.drop_height_m) {
            (Objective::MinTime, Some(h)) => format!(
                "- Least fall time within the motors **{:.6} s**: drop height **{:.4} m**; active limits: {}.",
                b.fall_time_s,
                h,
                if self.active_limits.is_empty() {
                    "none".to_string()
                } else {
                    self.active_limits.iter().map(|l| l.describe()).collect::<Vec<_>>().join(", ")
                }
            ),
            _ => format!("- Fall time {:.6} s.", b.fall_time_s),
        };
        format!(
            "{fall}\n- Motor sizing: peak speed [{:.4}, {:.4}] rad/s, peak power [{:.4}, {:.4}] W (joints 1, 2); {}.",
            m.peak_speed_rad_s[0].value,
            m.peak_speed_rad_s[1].value,
            m.peak_power_w[0].value,
            m.peak_power_w[1].value,
            m.verdict()
        )
    }
}

/// The certified convex retiming of one schedule along its fixed joint path.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RetimeRow {
    /// Which schedule was retimed (the problem's circulation, or the calibrated one).
    pub schedule: String,
    /// Whether the phase durations were kept or the split was free.
    pub split: String,
    /// The solver's status.
    pub status: String,
    /// The program's primal peak, N·m (absent when not solved).
    pub peak_nm: Option<f64>,
    /// Clarabel's dual objective: a certified lower bound on the discrete program's optimum, N·m.
    pub lower_bound_nm: Option<f64>,
    /// Duality gap, N·m.
    pub gap_nm: Option<f64>,
    /// The exact engine's peak of the retimed trajectory, N·m.
    pub exact_peak_nm: Option<f64>,
    /// Its twist, degrees (the path's: timing does not change it).
    pub twist_deg: Option<f64>,
    /// Its swing, degrees.
    pub swing_deg: Option<f64>,
    /// Solve time, s.
    pub solve_time_s: f64,
}

/// Retimes `schedule` (named `name`) with both splits.
pub fn retime_rows(r: &Resolved, name: &str, schedule: &Schedule) -> Vec<RetimeRow> {
    let p = &r.problem;
    [Split::Kept, Split::Free]
        .into_par_iter()
        .map(|split| {
            let settings = RetimeSettings { split, ..RetimeSettings::default() };
            let label = match split {
                Split::Kept => "phases kept",
                Split::Free => "split free",
            };
            let row = |status: String| RetimeRow {
                schedule: name.to_string(),
                split: label.to_string(),
                status,
                peak_nm: None,
                lower_bound_nm: None,
                gap_nm: None,
                exact_peak_nm: None,
                twist_deg: None,
                swing_deg: None,
                solve_time_s: 0.0,
            };
            match retime_schedule(&p.cat.half(), schedule, settings) {
                Err(e) => row(format!("refused: {e}")),
                Ok(t) => {
                    let sol = &t.solution;
                    let solved = sol.status.is_solved();
                    let again = if solved {
                        t.remeasure(&p.cat.half(), 4 * settings.intervals, p.exact.tolerance)
                    } else {
                        None
                    };
                    RetimeRow {
                        status: sol.status.to_string(),
                        peak_nm: solved.then_some(sol.peak),
                        lower_bound_nm: solved.then_some(sol.lower_bound),
                        gap_nm: solved.then_some(sol.gap),
                        exact_peak_nm: again.as_ref().map(|m| m.peaks.max),
                        twist_deg: again.as_ref().map(|m| m.flip.twist.to_degrees()),
                        swing_deg: again.as_ref().map(|m| m.flip.swing.to_degrees()),
                        solve_time_s: sol.solve_time_s,
                        ..row(String::new())
                    }
                }
            }
        })
        .collect()
}

/// The retiming rows as a Markdown table.
pub fn retime_markdown(rows: &[RetimeRow]) -> String {
    let mut s = String::from("## Certified retiming along the problem's joint path (SOCP, Clarabel)\n\n");
    let _ = write!(s, "The path stays, so does the flip; only the timing changes. *bound* is Clarabel's dual objective, a certified lower bound on the optimum of the discrete program ({} intervals per phase, piecewise-constant path acceleration), up to the solver's residuals: it holds to about 1e-6 (relative), not to the *gap* column, and a retimed trajectory's exact peak can lie that little below it; *exact* is the exact engine's peak of the retimed trajectory. The bound is not one on the continuous retiming of the path: finer grids lower the optimum at first order in 1/N (`catflip bench --problem PROBLEM`, curve `retime`, measures how far this path's exact peak at N = {} lies above the continuous optimum extrapolated from finer grids). The path is parametrised by the phases' progress variables (joint 1's angle, the bend direction, the fraction straightened), on which the joints never stop inside a phase, so the program is well posed.\n\n", RetimeSettings::default().intervals, RetimeSettings::default().intervals);
    s.push_str("| schedule | split | status | peak N·m | bound N·m | gap | exact N·m | twist ° | swing ° | solve s |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    let f = |x: Option<f64>, d: usize| x.map_or("—".to_string(), |v| format!("{v:.d$}"));
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3} |",
            r.schedule,
            r.split,
            r.status,
            f(r.peak_nm, 4),
            f(r.lower_bound_nm, 4),
            r.gap_nm.map_or("—".to_string(), |g| format!("{g:.1e}")),
            f(r.exact_peak_nm, 4),
            f(r.twist_deg, 6),
            f(r.swing_deg, 6),
            r.solve_time_s
        );
    }
    s
}

/// The whole-manoeuvre optimum through rapier, against the exact engine's numbers of the
/// optimum (none when there is no optimum).
pub fn verify_whole(r: &Resolved, report: &WholeReport) -> Result<Option<Verification>, RapierError> {
    let Some(b) = report.best() else { return Ok(None) };
    let reference = Reference { twist: b.twist, swing: b.swing, peak_torque: b.peak_torque_nm };
    let opts = RapierOptions::for_problem(&r.problem);
    verify_with(r.model(), &b.spline, &r.problem.rapier, &reference, &opts).map(Some)
}

/// The optimum's line of the peak-torque table (its Markdown row and its CSV record). The
/// paper's model, the rest-to-rest flag and the circulation do not apply to a trajectory without
/// a circulation profile, and a cubic spline's joint rates are continuous, so it has no velocity
/// jumps.
pub fn compare_line(report: &WholeReport) -> Option<CompareLine> {
    let (b, p) = (report.best()?, report.peak_torque_nm?);
    Some(CompareLine {
        problem: report.problem.clone(),
        profile: WHOLE.to_string(),
        origin: "whole".to_string(),
        rest_to_rest: None,
        accel_coefficient: None,
        model_peak_nm: None,
        exact_peak_nm: p,
        velocity_jumps: 0,
        max_impulse_nms: 0.0,
        twist_deg: b.twist.to_degrees(),
        swing_deg: b.swing.to_degrees(),
        circulation_rad: None,
        motors: b.motors.clone(),
    })
}

/// The optimum's row of the verification table (Markdown, the table's columns).
pub fn verification_row_markdown(report: &WholeReport, v: &Verification) -> Option<String> {
    let b = report.best()?;
    let exact = ExactValues {
        twist_deg: b.twist.to_degrees(),
        swing_deg: b.swing.to_degrees(),
        peak_torque_nm: b.peak_torque_nm,
    };
    Some(verification_row(WHOLE, exact, v))
}

/// The name of the whole-manoeuvre optimum in files and tables.
pub const WHOLE: &str = "whole-optimum";

/// The optimum as the schedule file `WHOLE.csv` (+ sidecar) that `catflip run` writes, when there
/// is an optimum: one piece name for every span, so the rows spread over the whole fall (the
/// spans' joins, where only the jerk jumps, still get their boundary rows).
pub fn optimum_file(
    problem: &crate::problem::Problem,
    report: &WholeReport,
    export: &crate::exchange::ExportOptions,
) -> Result<Option<crate::exchange::ScheduleFile>, crate::exchange::ExchangeError> {
    let Some(spline) = report.spline() else { return Ok(None) };
    let pieces = vec!["whole".to_string(); spline.piece_durations().len()];
    let description = "the whole-manoeuvre optimum: both joints as clamped cubic B-splines over the whole fall";
    crate::exchange::write_trajectory(problem, spline, &pieces, WHOLE, description, export).map(Some)
}

/// The summary lines of the optimum, its verification and the certified retiming, for the
/// run's report.
pub fn summary_lines(report: &WholeReport, v: Option<&Verification>, retimed: &[RetimeRow]) -> String {
    let mut s = String::new();
    match report.best() {
        Some(b) => {
            let _ = writeln!(
                s,
                "- **Whole-manoeuvre optimum** (`{WHOLE}`, both joint paths optimised over the whole fall): twist **{:+.9}°**, swing {:.1e}°, peak torque **{:.4} N·m**, energy {:.4} N²·m²·s; it bends at most {:.1}° and its bend direction turns {:+.2} turns ({}, {} iterations). See `whole.md`.",
                b.twist.to_degrees(),
                b.swing.to_degrees(),
                b.peak_torque_nm,
                b.energy,
                b.max_bend_deg,
                b.bend_turns,
                b.status,
                b.iterations
            );
            if let (Objective::MinTime, Some(h)) = (report.objective, report.drop_height_m) {
                let _ = writeln!(
                    s,
                    "- **Least fall time within the motors: {:.4} s, a drop of {h:.4} m**; the limits it reaches: {}.",
                    b.fall_time_s,
                    report.active_limits.iter().map(|l| l.describe()).collect::<Vec<_>>().join(", ")
                );
            }
            let _ = writeln!(
                s,
                "- The optimum's motors reach {:.4} rad/s and {:.4} W: {}.",
                b.motors.max_speed(),
                b.motors.max_power(),
                b.motors.verdict()
            );
        }
        None => {
            let _ = writeln!(s, "- Whole-manoeuvre optimum: **{}**.", report.status);
        }
    }
    if let Some(v) = v {
        let _ = writeln!(s, "- rapier verification of `{WHOLE}`: **{}**.", v.verdict);
    }
    for row in retimed {
        if let (Some(bound), Some(exact), Some(twist), Some(swing)) =
            (row.lower_bound_nm, row.exact_peak_nm, row.twist_deg, row.swing_deg)
        {
            let _ = writeln!(
                s,
                "- Certified retiming of `{}` ({}): exact peak {:.4} N·m, certified lower bound {:.4} N·m of its discrete program (finer grids lower it, see `retime.md`); twist {:+.6}°, swing {:.6}° (unchanged: the path is kept). See `retime.md`.",
                row.schedule,
                row.split,
                exact,
                bound,
                twist,
                swing
            );
        } else {
            let _ = writeln!(s, "- Certified retiming of `{}` ({}): {}.", row.schedule, row.split, row.status);
        }
    }
    s
}
