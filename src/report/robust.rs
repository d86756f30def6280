//! The robustness check as a reader gets it: Markdown, one CSV row per trial and engine, and the
//! pictures, written together into `OUT/<problem>-robust/`:
//! - `robust.png`/`.svg`: the distribution of the landing error (and its twist and swing parts);
//! - `robust_histogram.png`/`.svg`: the landing error's histogram, every engine run on one axis;
//! - `robust_worst_filmstrip.png`: the worst tracked trial along its fall (rapier);
//! - `robust_touchdown_filmstrip.png`: the touch-down frames (rapier with `landing`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use nalgebra::Vector3;

use crate::engines::rapier::Snapshot;
use crate::model::orientation::swing_twist;
use crate::numeric::numfmt::signed_fixed;
use crate::problem::Problem;
use crate::report::plot::{
    line_plot, pose_filmstrip, Band, BodyPose, CatPose, LinePlot, PlotError, RefLine, Scale, Series,
};
use crate::report::results_dir::{Staging, WriteError};
use crate::robust::tracked::{FeedbackSummary, Film, TrackingSummary};
use crate::robust::{Engine, Percentiles, RobustReport, Robustness};
use crate::schedule::Trajectory;

/// Bins of the landing-error histogram.
pub const HISTOGRAM_BINS: usize = 30;

/// Whether errors from `least` to `most` (degrees, `least` positive or infinite when there is
/// none) span more than a decade: then the distribution and the histogram are drawn on a log
/// error axis.
fn spans_decades(least: f64, most: f64) -> bool {
    least.is_finite() && most > 10.0 * least
}

fn percentile_row(out: &mut String, name: &str, p: &Percentiles) {
    let _ = writeln!(out, "| {name} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} |", p.p50, p.p90, p.p95, p.p99, p.max);
}

const PERCENTILE_HEAD: &str = "| median | 90 % | 95 % | 99 % | max |\n";
const PERCENTILE_RULE: &str = "|---:|---:|---:|---:|---:|\n";

impl RobustReport {
    /// The report in Markdown: the verdicts first, then the percentiles side by side, the
    /// tracking and landing figures, and the worst trials of each engine.
    pub fn to_markdown(&self) -> String {
        let mut out = String::new();
        let Some(first) = self.checks.first() else { return out };
        let s = &first.settings;
        let _ = writeln!(out, "# Robustness of `{}` on problem `{}`\n", first.schedule, first.problem);
        if !self.command.is_empty() {
            let _ = writeln!(out, "{}\n", crate::report::provenance::regenerate_line(&self.command));
        }
        for c in &self.checks {
            let _ = writeln!(out, "**{}: the schedule {}.**\n", c.engine.describe(), c.verdict);
            if let Some(l) = c.tracking.as_ref().and_then(|t| t.landing.as_ref()) {
                let _ = writeln!(out, "**Landing: the cat {}.**\n", l.verdict);
            }
        }
        let _ = writeln!(
            out,
            "Each of {} trials (seed {}) draws each half's mass ±{} %, length ±{} %, radius ±{} % (uniform, both halves alike) and a release spin with σ = {} N·m·s per world axis. Landing error: the angle between the front half's (A's) attitude at the end of the schedule and the half turn about its initial spine.\n",
            s.trials, s.seed, s.mass_pct, s.length_pct, s.radius_pct, s.spin_sigma_nms
        );
        for c in &self.checks {
            match c.engine {
                Engine::Exact => {
                    let _ = writeln!(out, "- *{}*: the joints follow the schedule exactly (no motors, no feedback); the exact engine integrates the attitude.", c.engine.describe());
                }
                Engine::Rapier => {
                    let _ = writeln!(
                        out,
                        "- *{}*: rapier (step {:.3e} s), the joints driven by the nominal cat's planned torques plus joint PD ({} Hz, ζ = {}, gains ±{} % per joint) through the actuators (`[actuator]`; none: unbounded); the controller is handed an attitude estimate {} s late with {}° of noise per axis (the PD ignores it).",
                        c.engine.describe(),
                        c.tracking.as_ref().map_or(s.dt_s, |t| t.dt_s),
                        s.servo_hz,
                        s.servo_damping,
                        s.gain_pct,
                        s.attitude_latency_s,
                        s.attitude_noise_deg
                    );
                }
                Engine::RapierFeedback => {
                    let _ = writeln!(
                        out,
                        "- *{}*: the same trials (same draws, same sensor noise), the plan corrected by time-varying LQR on the linearised reduced dynamics at {}{} (attitude scale {}°, joint correction scale {}°, joint acceleration ≤ {} rad/s²), fed by a Kalman filter that estimates the attitude error and the unknown spin from the late, noisy sensor (prior σ = {} N·m·s) and carries it over the latency.",
                        c.engine.describe(),
                        control_rate(s.feedback_hz, c.tracking.as_ref().and_then(|t| t.feedback.as_ref())),
                        replan_rate(c.tracking.as_ref().and_then(|t| t.feedback.as_ref())),
                        s.feedback_attitude_deg,
                        s.feedback_joint_deg,
                        s.feedback_accel,
                        s.feedback_spin_prior_nms
                    );
                }
            }
        }
        let _ = write!(out, "\n| figure (degrees) {}", PERCENTILE_HEAD);
        let _ = write!(out, "|---{}", PERCENTILE_RULE);
        let both = self.checks.len() > 1;
        for c in &self.checks {
            let tag = if both { format!(" ({})", c.engine.describe()) } else { String::new() };
            percentile_row(&mut out, &format!("landing error{tag}"), &c.landing_error_deg);
            percentile_row(&mut out, &format!("twist error, abs(\\|twist\\| − 180°){tag}"), &c.twist_error_deg);
            percentile_row(&mut out, &format!("swing{tag}"), &c.swing_deg);
        }
        for c in &self.checks {
            let n = &c.nominal;
            let _ = writeln!(
                out,
                "\nThe nominal cat (no draw), {}: {:.3}° from the target (twist error {}°, swing {:.3}°).",
                c.engine.describe(),
                n.landing_error_deg,
                signed_fixed(n.twist_error_deg, 3),
                n.swing_deg
            );
            if c.not_converged > 0 {
                let _ = writeln!(
                    out,
                    "\n**{} trial(s) did not meet exact.tolerance**: their landing errors are less accurate than stated.",
                    c.not_converged
                );
            }
        }
        for c in &self.checks {
            if let Some(t) = &c.tracking {
                tracking_section(&mut out, t, c);
            }
        }
        for c in &self.checks {
            worst_section(&mut out, c);
        }
        if !self.checks.iter().any(|c| c.engine == Engine::RapierFeedback) {
            let _ = writeln!(
                out,
                "\nNo trial here fed the attitude back: `--set robust.engine=rapier --set robust.controller=feedback` tracks the schedule with attitude feedback (README, \"Will it land on its feet, and how often?\")."
            );
        }
        out
    }

    /// One CSV row per trial and engine, with a header.
    pub fn to_csv(&self) -> String {
        let mut out = String::from(
            "engine,trial,mass_kg,length_m,radius_m,lx_nms,ly_nms,lz_nms,gain1,gain2,landing_error_deg,twist_error_deg,swing_deg,converged,tracking_error1_deg,tracking_error2_deg,peak_torque1_nm,peak_torque2_nm,saturated1,saturated2,touchdown_s,first_part,impact_speed_ms,feet_down_a_deg,feet_down_b_deg,on_its_feet\n",
        );
        for c in &self.checks {
            let engine = c.engine.key();
            for t in &c.trials {
                let d = &t.draw;
                let l = d.angular_momentum_nms;
                // The servo gains are drawn for every trial but matter to rapier's only (as in
                // the worst trials' table): an exact-engine row leaves them empty.
                let gain = |k: usize| if c.engine == Engine::Exact { String::new() } else { d.gain[k].to_string() };
                let _ = write!(
                    out,
                    "{engine},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                    d.trial,
                    d.mass,
                    d.length,
                    d.radius,
                    l[0],
                    l[1],
                    l[2],
                    gain(0),
                    gain(1),
                    t.landing_error_deg,
                    t.twist_error_deg,
                    t.swing_deg,
                    t.converged
                );
                match &t.tracked {
                    Some(f) => {
                        let _ = write!(
                            out,
                            ",{},{},{},{},{},{}",
                            f.tracking_error_deg[0],
                            f.tracking_error_deg[1],
                            f.peak_torque_nm[0],
                            f.peak_torque_nm[1],
                            f.saturated[0],
                            f.saturated[1]
                        );
                        match &f.touchdown {
                            Some(td) => {
                                let part = serde_json::to_value(td.part).ok();
                                let part = part.as_ref().and_then(|p| p.as_str()).unwrap_or("");
                                let _ = writeln!(
                                    out,
                                    ",{},{part},{},{},{},{}",
                                    td.time, td.impact_speed, td.feet_down_deg[0], td.feet_down_deg[1], td.on_its_feet
                                );
                            }
                            None => out.push_str(",,,,,,\n"),
                        }
                    }
                    None => out.push_str(",,,,,,,,,,,,\n"),
                }
            }
        }
        out
    }

    /// The distribution of the landing error (and its twist and swing parts) of every engine:
    /// the fraction of trials at or below each error, with the tolerance marked.
    pub fn distribution_plot(&self) -> LinePlot {
        let cdf = |values: Vec<f64>| {
            let mut v = values;
            v.sort_by(f64::total_cmp);
            let n = v.len() as f64;
            let mut points = vec![(0.0, 0.0)];
            for (i, x) in v.iter().enumerate() {
                points.push((*x, i as f64 / n));
                points.push((*x, (i + 1) as f64 / n));
            }
            points
        };
        let mut series = Vec::new();
        let both = self.checks.len() > 1;
        for c in &self.checks {
            let tag = if both { format!(", {}", c.engine.describe()) } else { String::new() };
            series.push(Series::new(
                format!("landing error{tag}"),
                cdf(c.trials.iter().map(|t| t.landing_error_deg).collect()),
            ));
            series.push(Series::new(
                format!("| |twist| − 180° |{tag}"),
                cdf(c.trials.iter().map(|t| t.twist_error_deg.abs()).collect()),
            ));
            series.push(Series::new(format!("swing{tag}"), cdf(c.trials.iter().map(|t| t.swing_deg).collect())));
        }
        // Over more than a decade of errors (feedback's tenths of a degree beside open loop's tens)
        // a linear axis squeezes the small ones into a line at its left: then it is logarithmic.
        let positive = series.iter().flat_map(|s| s.points.iter().map(|p| p.0)).filter(|x| *x > 0.0);
        let (least, most) = positive.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
        let mut plot = LinePlot::new(
            "robust",
            format!("{}: {}", self.title(), self.engines_in_words()),
            "error (degrees)",
            "fraction of trials at or below",
            series,
        );
        if spans_decades(least, most) {
            plot.scale = Scale::LogX;
        }
        for c in &self.checks {
            let tag = if both { format!(" ({})", c.engine.describe()) } else { String::new() };
            plot.ref_lines.push(RefLine {
                y: c.within,
                label: format!("{:.1} % within {}°{tag}", 100.0 * c.within, c.settings.tolerance_deg),
            });
        }
        plot
    }

    /// The landing error's histogram, [`HISTOGRAM_BINS`] bins from 0 to the largest error of any
    /// engine (at least 1.2 times the tolerance, so that the tolerance is on the scale even when
    /// every trial lands within it, or all alike), equal in the error, or in its logarithm from
    /// the decade of the least error when the errors span more than a decade; each engine's
    /// counts as a step outline; the tolerance starts a band.
    pub fn histogram_plot(&self) -> LinePlot {
        let tolerance = self.checks.first().map_or(0.0, |c| c.settings.tolerance_deg);
        let top =
            self.checks.iter().map(|c| c.landing_error_deg.max).fold(0.0, f64::max).max(1.2 * tolerance).max(1e-9);
        // Over more than a decade of errors (feedback's tenths of a degree beside open loop's tens)
        // equal bins put one engine's trials in the first bin and flatten the others: then the
        // bins are equal in log error, from the decade of the least error, on a log axis.
        let least = self
            .checks
            .iter()
            .flat_map(|c| c.trials.iter().map(|t| t.landing_error_deg))
            .filter(|e| *e > 0.0)
            .fold(f64::INFINITY, f64::min);
        let log = spans_decades(least, top);
        let bottom = if log { 10f64.powf(least.log10().floor()) } else { 0.0 };
        let edge = |i: usize| {
            let u = i as f64 / HISTOGRAM_BINS as f64;
            if log {
                bottom * (top / bottom).powf(u)
            } else {
                top * u
            }
        };
        let bin_of = |e: f64| {
            let u = if log { (e.max(bottom) / bottom).ln() / (top / bottom).ln() } else { e / top };
            ((u * HISTOGRAM_BINS as f64).floor().max(0.0) as usize).min(HISTOGRAM_BINS - 1)
        };
        let series = self
            .checks
            .iter()
            .map(|c| {
                let mut counts = [0usize; HISTOGRAM_BINS];
                for t in &c.trials {
                    counts[bin_of(t.landing_error_deg)] += 1;
                }
                let mut points = vec![(bottom, 0.0)];
                for (i, n) in counts.iter().enumerate() {
                    points.push((edge(i), *n as f64));
                    points.push((edge(i + 1), *n as f64));
                }
                points.push((top, 0.0));
                Series::new(c.engine.describe(), points)
            })
            .collect();
        let per_bin = if log {
            format!("trials per bin ({HISTOGRAM_BINS} bins, equal in log error)")
        } else {
            format!("trials per {}° bin", crate::numeric::numfmt::sig(top / HISTOGRAM_BINS as f64, 3))
        };
        let mut plot = LinePlot::new(
            "robust_histogram",
            format!("{}: landing error, {} trials", self.title(), self.checks.first().map_or(0, |c| c.trials.len())),
            "landing error (degrees)",
            per_bin,
            series,
        );
        if log {
            plot.scale = Scale::LogX;
        }
        if let Some(c) = self.checks.first() {
            let tol = c.settings.tolerance_deg;
            if tol < top {
                plot.bands.push(Band { from: tol, to: top, label: format!("beyond {tol}°") });
            }
        }
        plot
    }

    fn title(&self) -> String {
        let Some(c) = self.checks.first() else { return String::new() };
        let name = Path::new(&c.schedule).file_name().map_or(c.schedule.clone(), |n| n.to_string_lossy().into_owned());
        format!("{name}, problem {}", c.problem)
    }

    fn engines_in_words(&self) -> String {
        let names: Vec<&str> = self.checks.iter().map(|c| c.engine.describe()).collect();
        format!("{} trials, {}", self.checks.first().map_or(0, |c| c.trials.len()), names.join(" vs "))
    }

    /// Writes `robust.md`, `robust.csv`, `robust.json` and the plots into `out/<problem>-robust/`,
    /// replacing an earlier check there only when every file is written; returns the folder.
    /// The filmstrips need the problem (the cat's sizes) and the schedule (its phases).
    pub fn write(&self, out: &Path, problem: &Problem, schedule: &impl Trajectory) -> Result<PathBuf, WriteError> {
        let staging = Staging::begin(out, &format!("{}-robust", problem.name))?;
        let json = serde_json::to_string_pretty(self)
            .map_err(|source| WriteError::Json { what: "the robustness check", source })?;
        for (name, text) in [("robust.md", self.to_markdown()), ("robust.csv", self.to_csv()), ("robust.json", json)] {
            let path = staging.dir().join(name);
            std::fs::write(&path, text).map_err(|source| WriteError::Io { path: staging.shown(&path), source })?;
        }
        line_plot(staging.dir(), &self.distribution_plot())?;
        line_plot(staging.dir(), &self.histogram_plot())?;
        for c in &self.checks {
            if let Some(film) = &c.film {
                write_film(staging.dir(), problem, schedule, film, c.engine)?;
            }
        }
        Ok(staging.commit()?)
    }
}

fn tracking_section(out: &mut String, t: &TrackingSummary, c: &Robustness) {
    let feedback = c.engine == Engine::RapierFeedback;
    let _ = writeln!(out, "\n## Tracking with {} (rapier)\n", if feedback { "attitude feedback" } else { "motors" });
    let _ = writeln!(
        out,
        "{} steps of {:.3e} s; servo gains k_p = {:.4} N·m/rad, k_d = {:.4} N·m·s/rad (before the trials' factors). {} of {} trials saturated an actuator at least once; the largest torque applied was {:.4} N·m.\n",
        t.steps,
        t.dt_s,
        t.gains.kp[0],
        t.gains.kd[0],
        t.saturated_trials,
        c.trials.len(),
        t.peak_torque_nm
    );
    if let Some(f) = &t.feedback {
        let replans = match f.replan_dt_s {
            Some(every) => format!(" It re-plans the rest of the fall every {every:.3e} s from its estimate (one iteration of iterative LQR about the motion it then expects, the joint accelerations' bound respected)."),
            None => " Its gains are solved once, along the plan.".to_string(),
        };
        let _ = writeln!(
            out,
            "The regulator steps every {:.3e} s; its largest gain entry along the plan is {:.4e} (bounded to the end of the fall).{replans} The tracking error below is from the plan, the correction included.\n",
            f.control_dt_s, f.largest_gain
        );
    }
    let _ = write!(out, "| figure {}", PERCENTILE_HEAD);
    let _ = write!(out, "|---{}", PERCENTILE_RULE);
    percentile_row(out, "tracking error (larger joint), degrees", &t.tracking_error_deg);
    if let Some(f) = &t.feedback {
        percentile_row(out, "feedback's joint correction (larger joint), degrees", &f.correction_deg);
    }
    if let Some(l) = &t.landing {
        for (name, p) in [
            ("touch-down time, s", &l.time_s),
            ("impact speed, m/s", &l.impact_speed),
            ("feet-down angle (larger half), degrees", &l.feet_down_deg),
        ] {
            if let Some(p) = p {
                percentile_row(out, name, p);
            }
        }
        let parts: Vec<String> = l.first_part.iter().map(|(p, n)| format!("{} {n}", p.describe())).collect();
        let _ = writeln!(out, "\nFirst to touch the ground: {}.", parts.join(", "));
        if l.no_touchdown > 0 {
            let _ = writeln!(out, "\n**{} trial(s) had not touched down by the end of the run.**", l.no_touchdown);
        }
        if let Some(td) = c.nominal.tracked.and_then(|f| f.touchdown) {
            let _ = writeln!(
                out,
                "\nThe nominal cat touches down at {:.4} s with {} ({:.3} m/s), its feet {:.2}° (A) and {:.2}° (B) from straight down: {}.",
                td.time,
                td.part.describe(),
                td.impact_speed,
                td.feet_down_deg[0],
                td.feet_down_deg[1],
                if td.on_its_feet { "on its feet" } else { "not on its feet" }
            );
        }
    }
}

fn worst_section(out: &mut String, c: &Robustness) {
    // The servo's gain factors matter to rapier's trials only.
    let gains = c.engine != Engine::Exact;
    let _ = writeln!(out, "\n## The worst trials, {}\n", c.engine.describe());
    let _ = writeln!(
        out,
        "| trial | mass kg | length m | radius m | L N·m·s |{} landing error ° | twist error ° (signed: − short of 180°) | swing ° |",
        if gains { " servo gains |" } else { "" }
    );
    let _ = writeln!(out, "|---:|---:|---:|---:|---|{}---:|---:|---:|", if gains { "---|" } else { "" });
    for t in &c.worst {
        let d = &t.draw;
        let l = d.angular_momentum_nms;
        let g = if gains { format!(" [{:.3}, {:.3}] |", d.gain[0], d.gain[1]) } else { String::new() };
        let twist = signed_fixed(t.twist_error_deg, 3);
        let _ = writeln!(
            out,
            "| {} | {:.4} | {:.4} | {:.4} | [{:.4}, {:.4}, {:.4}] |{g} {:.3} | {twist} | {:.3} |",
            d.trial, d.mass, d.length, d.radius, l[0], l[1], l[2], t.landing_error_deg, t.swing_deg
        );
    }
    if c.unequal_halves {
        let _ = writeln!(
            out,
            "\nThe halves differ: mass, length and radius are the `[cat]` shorthand's as drawn; each half's own is scaled by the same factor."
        );
    }
}

/// A rapier snapshot as the pictures' pose: centres about the halves' midpoint (the halves
/// have equal masses; the cross's is left out as the exact engine's poses do).
fn pose_of(t: f64, snap: &Snapshot) -> CatPose {
    let mid: Vector3<f64> = 0.5 * (snap.positions[0] + snap.positions[2]);
    let st = swing_twist(&snap.rotations[0]);
    let body = |i: usize| BodyPose {
        centre: snap.positions[i] - mid,
        rotation: snap.rotations[i].to_rotation_matrix().into_inner(),
    };
    CatPose { time: t, phase: None, twist: st.twist, swing: st.swing, a: body(0), b: body(2), tail: None, legs: None }
}

/// The filmstrips of one tracked check: `robust_worst_filmstrip.png` and
/// `robust_touchdown_filmstrip.png` for the open loop, `robust_feedback_…` for the feedback.
fn write_film(
    dir: &Path,
    problem: &Problem,
    schedule: &impl Trajectory,
    film: &Film,
    engine: Engine,
) -> Result<(), PlotError> {
    let (prefix, engine_name, how) = match engine {
        Engine::RapierFeedback => ("robust_feedback", "rapier, feedback", "attitude feedback"),
        _ => ("robust", "rapier", "tracked with motors"),
    };
    let name = format!("{engine_name}, worst trial {}", film.worst_trial);
    if !film.worst.is_empty() {
        let poses: Vec<CatPose> = film.worst.iter().map(|(t, s)| pose_of(*t, s)).collect();
        let caption = format!("{how}, {} instants", poses.len());
        let path = dir.join(format!("{prefix}_worst_filmstrip.png"));
        pose_filmstrip(&path, problem, &name, schedule, &poses, &caption)?;
    }
    if !film.touchdowns.is_empty() {
        let poses: Vec<CatPose> = film.touchdowns.iter().map(|(_, t, s)| pose_of(*t, s)).collect();
        let labels: Vec<&str> = film.touchdowns.iter().map(|(l, _, _)| l.as_str()).collect();
        let caption = format!("touch-down of {}, {how}", labels.join(" and "));
        let path = dir.join(format!("{prefix}_touchdown_filmstrip.png"));
        pose_filmstrip(&path, problem, engine_name, schedule, &poses, &caption)?;
    }
    Ok(())
}

/// The re-plans as they ran: their interval, or nothing when the gains were solved once.
fn replan_rate(feedback: Option<&FeedbackSummary>) -> String {
    match feedback.and_then(|f| f.replan_dt_s) {
        Some(every) => format!(
            ", re-planned every {every:.3} s from its estimate (the rest of the fall re-linearised about the motion it then expects, the gains re-solved within the acceleration bound)"
        ),
        None => String::new(),
    }
}

/// The regulator's rate as it ran: the setting, or the whole number of run steps it was rounded
/// to when that differs from the setting by more than 0.1 %.
fn control_rate(setting_hz: f64, feedback: Option<&FeedbackSummary>) -> String {
    match feedback.map(|f| 1.0 / f.control_dt_s) {
        Some(ran) if (ran - setting_hz).abs() > 1e-3 * setting_hz => {
            format!("{ran:.1} Hz (`feedback_hz` = {setting_hz} rounded to a whole number of the run's steps)")
        }
        _ => format!("{setting_hz} Hz"),
    }
}
