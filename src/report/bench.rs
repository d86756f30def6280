//! `catflip bench` ([`crate::measure::bench`]) as tables: the time-to-reach table, one Markdown
//! table per curve, the stress tables, a tidy CSV (one row per point) and the log–log plots (one
//! per error kind).

use std::fmt::Write;
use std::path::{Path, PathBuf};

use crate::measure::bench::curve::Curve;
use crate::measure::bench::random::Verdict;
use crate::measure::bench::BenchReport;
use crate::report::plot::{line_plot, LinePlot, PlotError, Scale, Series};

/// The targets of the time-to-reach table, rad.
pub const TARGETS: [f64; 3] = [1e-3, 1e-6, 1e-9];

/// Measured from outside the project (by an independent script in one sitting, the paper's problem, 2 cores):
/// `(method, time to 1e-3, 1e-6, 1e-9 rad in s; None = not reached or not reported)`.
pub const OUTSIDE: [(&str, [Option<f64>; 3]); 4] = [
    ("exact engine (outside measurement)", [None, None, Some(0.63e-3)]),
    ("MuJoCo RK4, prescribed motion, Python loop", [None, Some(0.544), None]),
    ("scipy DOP853", [None, None, Some(0.741)]),
    ("rapier extrapolated (outside measurement)", [Some(0.177), None, None]),
];

/// Where accuracy degrades and why, as measured on the random sample and the named cases.
const DEGRADATION: &str = "Where accuracy degrades, and why:\n\n\
- **Near-singular joint configurations** are refused, not integrated: the cone path within 5° of 90° meets gimbal lock of the Rx·Ry joint (B's spine along joint 1's axis).\n\
- **Nearly straight cats** (θ → 180°): `C → 0`, so the paper's circulation `π/C` grows past the 1000 rad a schedule may circulate and is refused (give a circulation).\n\
- **High circulations** need more torque samples: the sampling follows the radians the bend direction turns (64 per radian), and the steps per phase of the flip grow with the circulation (8192 at 60 rad).\n\
- **Short, fast, sharp schedules** (fall times ~0.1 s, s-curve or trapezoid profiles): the stated peak accuracy (the change when every other sample is dropped) rises to ~1e-3 and the case is marked degraded; it is pessimistic (the halved grid is the one that misses; on case 36 of the sample drawn with `--seed 2026`, not necessarily this run's, the default grid agrees with 4e5 samples to 1e-15).\n\
- **Locked-inertia conditioning**: thin cylinders (r/l = 1e-3) make the axial inertia tiny; the momentum map stays exact (residuals ~1e-14 relative) because the locked inertia is solved by Cholesky, not inverted.\n\n";

fn time(t: Option<f64>) -> String {
    t.map_or("not reached".into(), |t| format!("{:.3} ms", 1e3 * t))
}

fn opt(x: Option<f64>) -> String {
    x.map_or("—".into(), |x| format!("{x:.2e}"))
}

impl BenchReport {
    /// The time-to-reach table (Markdown): this run's engine curves, then the outside figures.
    pub fn reach_table(&self) -> String {
        let mut s = String::from("| engine | to 1e-3 rad | to 1e-6 rad | to 1e-9 rad |\n|---|---:|---:|---:|\n");
        for c in self.curves.iter().filter(|c| c.error_is_angle) {
            let t = TARGETS.map(|x| time(c.time_to_reach(x)));
            let _ = writeln!(s, "| `{}` (this run) | {} | {} | {} |", c.name, t[0], t[1], t[2]);
        }
        for (name, t) in OUTSIDE {
            let t = t.map(|x| x.map_or("—".into(), |v| format!("{:.3} ms", 1e3 * v)));
            let _ = writeln!(s, "| {name} | {} | {} | {} |", t[0], t[1], t[2]);
        }
        s
    }

    /// The whole report body in Markdown (after the provenance header).
    pub fn to_markdown(&self) -> String {
        let mut s = format!(
            "Machine: {}. Times are the best of up to 7 runs (median beside it).\n\n## Time to reach an accuracy\n\n",
            self.machine
        );
        s.push_str(&self.reach_table());
        s.push_str("\nRows marked *outside* were measured outside this project (an independent measurement in one sitting on the paper's problem, 2 cores), not by this run. `—`: not reported; *not reached*: no point of this run's sweep got there. In the tables below the rows run from coarse to fine, and *observed order* is `ln(e₁/e₂) / |ln(x₁/x₂)|` between a row and the one above: positive where the error fell, negative where it grew.\n\n");
        let _ = writeln!(
            s,
            "One default evaluation of the problem's schedule (flip to `exact.tolerance`, peak torques, jumps): best {:.3} ms, median {:.3} ms.\n",
            1e3 * self.evaluation.best_s,
            1e3 * self.evaluation.median_s
        );
        s.push_str("![work-precision of the engines](plots/bench_engines.png)\n![work-precision of the optimisers](plots/bench_optimizers.png)\n\n");
        for c in &self.curves {
            curve_markdown(&mut s, c);
            for n in self.notes.iter().filter(|n| n.curve == c.name) {
                let _ = writeln!(s, "{}\n", n.note);
            }
        }
        self.stress_markdown(&mut s);
        s
    }

    fn stress_markdown(&self, s: &mut String) {
        s.push_str("## Stress: named edge cases of the exact engine\n\n| case | converged | error estimate rad | steps/phase | twist ° | momentum (rel.) | action–reaction (rel.) | peak torque N·m | refused with |\n|---|---|---:|---:|---:|---:|---:|---:|---|\n");
        for c in &self.stress {
            let f = |x: Option<f64>, fmt: fn(f64) -> String| x.map_or("—".to_string(), fmt);
            let converged = if c.refused.is_some() { "—".to_string() } else { c.converged.to_string() };
            let _ = writeln!(
                s,
                "| {} | {converged} | {} | {} | {} | {} | {} | {} | {} |",
                c.case,
                f(c.error_estimate_rad, |x| format!("{x:.1e}")),
                c.steps_per_phase.map_or("—".to_string(), |n| n.to_string()),
                f(c.twist_deg, |x| format!("{x:.4}")),
                f(c.momentum_max, |x| format!("{x:.1e}")),
                f(c.action_reaction_rel, |x| format!("{x:.1e}")),
                f(c.peak_torque_nm, |x| format!("{x:.4e}")),
                c.refused.as_deref().unwrap_or("")
            );
        }
        let t = self.random;
        let _ = writeln!(
            s,
            "\n## Stress: random problems spanning decades\n\nSeed {}, {} cases (`measure::bench::random`): {} passed, {} refused with a reason, {} degraded, {} failed.\n",
            crate::measure::bench::RANDOM_SEED,
            t.cases,
            t.passed,
            t.refused,
            t.degraded,
            t.failed
        );
        let _ = writeln!(
            s,
            "Worst over the accepted cases: momentum residual {:.1e}, action–reaction gap {:.1e} (both relative), twist change at 10× the mass {:.1e} rad, torque off ×10 by {:.1e}, QP gap to its closed form {:.1e}.\n",
            t.worst_momentum, t.worst_action_reaction, t.worst_mass_twist, t.worst_mass_torque, t.worst_qp_gap
        );
        s.push_str(DEGRADATION);
        if !self.random_notable.is_empty() {
            s.push_str("| case | verdict | overrides |\n|---:|---|---|\n");
            for r in &self.random_notable {
                let (v, why) = match &r.verdict {
                    Verdict::Passed => ("passed", ""),
                    Verdict::Refused(w) => ("refused", w.as_str()),
                    Verdict::Degraded(w) => ("degraded", w.as_str()),
                    Verdict::Failed(w) => ("FAILED", w.as_str()),
                };
                let _ = writeln!(s, "| {} | {v}: {why} | `{}` |", r.case.index, r.case.overrides[1..].join(" "));
            }
        }
    }

    /// Tidy CSV: one row per point of every curve.
    pub fn to_csv(&self) -> String {
        let mut s = String::from(
            "curve,setting_name,setting,repeats,best_s,median_s,error_name,error,secondary_name,secondary,failed\n",
        );
        for c in &self.curves {
            for p in &c.points {
                let (rep, best, med) = p.timing.map_or((String::new(), String::new(), String::new()), |t| {
                    (t.repeats.to_string(), format!("{:e}", t.best_s), format!("{:e}", t.median_s))
                });
                let _ = writeln!(
                    s,
                    "{},\"{}\",{:e},{rep},{best},{med},\"{}\",{},\"{}\",{},\"{}\"",
                    c.name,
                    c.setting,
                    p.setting,
                    c.error,
                    p.outcome.map_or(String::new(), |o| format!("{:e}", o.error)),
                    c.secondary.as_deref().unwrap_or(""),
                    p.outcome.and_then(|o| o.secondary).map_or(String::new(), |x| format!("{x:e}")),
                    p.failed.as_deref().unwrap_or("").replace('"', "'")
                );
            }
        }
        s
    }

    /// The log–log plots (best time against error): `bench_engines` (the angle curves) and
    /// `bench_optimizers` (the others), PNG and SVG, in `dir`.
    pub fn plots(&self, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
        let mut files = Vec::new();
        for (stem, title, x_label, angle) in [
            ("bench_engines", "Work-precision of the engines", "error (rad)", true),
            (
                "bench_optimizers",
                "Work-precision of the optimisers and the calibration",
                "error (curve's unit, see the tables)",
                false,
            ),
        ] {
            let series: Vec<Series> = self
                .curves
                .iter()
                .filter(|c| c.error_is_angle == angle)
                .map(|c| {
                    // In the sweep's order, so that the line follows the setting.
                    let pts: Vec<(f64, f64)> =
                        c.points.iter().filter_map(|p| Some((p.outcome?.error, p.timing?.best_s))).collect();
                    Series::new(c.name.clone(), pts)
                })
                .collect();
            let mut plot = LinePlot::new(stem, title, x_label, "best run time (s)", series);
            plot.scale = Scale::LogLog;
            plot.markers = true;
            files.extend(line_plot(dir, &plot)?);
        }
        Ok(files)
    }
}

fn curve_markdown(s: &mut String, c: &Curve) {
    let _ = writeln!(
        s,
        "## `{}`\n\n| {} | best time | median time | runs | {} | {} | observed order |\n|---:|---:|---:|---:|---:|---:|---:|",
        c.name,
        c.setting,
        c.error,
        c.secondary.as_deref().unwrap_or("—")
    );
    for (p, order) in c.points.iter().zip(c.observed_orders()) {
        match (p.timing, p.outcome) {
            (Some(t), Some(o)) => {
                let _ = writeln!(
                    s,
                    "| {:.3e} | {:.3e} s | {:.3e} s | {} | {:.2e} | {} | {} |",
                    p.setting,
                    t.best_s,
                    t.median_s,
                    t.repeats,
                    o.error,
                    opt(o.secondary),
                    order.map_or("—".into(), |x| format!("{x:.2}"))
                );
            }
            _ => {
                let _ = writeln!(
                    s,
                    "| {:.3e} | — | — | — | {} | — | — |",
                    p.setting,
                    p.failed.as_deref().unwrap_or("no result")
                );
            }
        }
    }
    s.push('\n');
}
