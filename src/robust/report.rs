//! The robustness check as a reader gets it: Markdown, one CSV row per trial, and the
//! distribution of the landing error as a plot, written together into `OUT/<problem>-robust/`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{Percentiles, Robustness};
use crate::report::plot::{line_plot, LinePlot, PlotError, RefLine, Series};

use crate::report::results_dir::{ResultsDirError, Staging};

/// Why the check's files could not be written.
#[derive(Debug, thiserror::Error)]
pub enum RobustWriteError {
    /// The results folder.
    #[error(transparent)]
    Folder(#[from] ResultsDirError),
    /// A file.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file, as the user will find it.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// The plot.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

impl Robustness {
    /// The report in Markdown: the verdict first, then the percentiles and the worst trials.
    pub fn to_markdown(&self) -> String {
        let s = &self.settings;
        let mut out = String::new();
        let _ = writeln!(out, "# Robustness of `{}` on problem `{}`\n", self.schedule, self.problem);
        if !self.command.is_empty() {
            let _ = writeln!(out, "Regenerate with `{}`.\n", self.command);
        }
        let _ = writeln!(out, "**The open-loop schedule {}.**\n", self.verdict);
        let _ = writeln!(
            out,
            "Each of {} trials (seed {}) draws each half's mass ±{} %, length ±{} %, radius ±{} % (uniform, both halves alike) and a release spin with σ = {} N·m·s per world axis, then runs the schedule exactly as planned (ideal tracking, no feedback) through the exact engine. Landing error: the angle between A's final attitude and the half turn about its initial spine.\n",
            s.trials, s.seed, s.mass_pct, s.length_pct, s.radius_pct, s.spin_sigma_nms
        );
        let _ = writeln!(out, "| figure (degrees) | median | 90 % | 95 % | 99 % | max |");
        let _ = writeln!(out, "|---|---:|---:|---:|---:|---:|");
        let row = |out: &mut String, name: &str, p: &Percentiles| {
            let _ =
                writeln!(out, "| {name} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} |", p.p50, p.p90, p.p95, p.p99, p.max);
        };
        row(&mut out, "landing error", &self.landing_error_deg);
        row(&mut out, "twist error, abs(\\|twist\\| − 180°)", &self.twist_error_deg);
        row(&mut out, "swing", &self.swing_deg);
        let _ = writeln!(
            out,
            "\nThe nominal cat (no draw) lands {:.3}° from the target (twist error {:+.3}°, swing {:.3}°).",
            self.nominal.landing_error_deg, self.nominal.twist_error_deg, self.nominal.swing_deg
        );
        if self.not_converged > 0 {
            let _ = writeln!(
                out,
                "\n**{} trial(s) did not meet exact.tolerance**: their landing errors are less accurate than stated.",
                self.not_converged
            );
        }
        let _ = writeln!(out, "\n## The worst trials\n");
        let _ = writeln!(
            out,
            "| trial | mass kg | length m | radius m | L N·m·s | landing error ° | twist error ° | swing ° |"
        );
        let _ = writeln!(out, "|---:|---:|---:|---:|---|---:|---:|---:|");
        for t in &self.worst {
            let d = &t.draw;
            let l = d.angular_momentum_nms;
            let _ = writeln!(
                out,
                "| {} | {:.4} | {:.4} | {:.4} | [{:.4}, {:.4}, {:.4}] | {:.3} | {:+.3} | {:.3} |",
                d.trial,
                d.mass,
                d.length,
                d.radius,
                l[0],
                l[1],
                l[2],
                t.landing_error_deg,
                t.twist_error_deg,
                t.swing_deg
            );
        }
        let _ = writeln!(
            out,
            "\nNot modelled here: feedback, motor lag and saturation, sensor latency and noise, unequal halves."
        );
        out
    }

    /// One CSV row per trial, with a header.
    pub fn to_csv(&self) -> String {
        let mut out = String::from(
            "trial,mass_kg,length_m,radius_m,lx_nms,ly_nms,lz_nms,landing_error_deg,twist_error_deg,swing_deg,converged\n",
        );
        for t in &self.trials {
            let d = &t.draw;
            let l = d.angular_momentum_nms;
            let _ = writeln!(
                out,
                "{},{},{},{},{},{},{},{},{},{},{}",
                d.trial,
                d.mass,
                d.length,
                d.radius,
                l[0],
                l[1],
                l[2],
                t.landing_error_deg,
                t.twist_error_deg,
                t.swing_deg,
                t.converged
            );
        }
        out
    }

    /// The distribution of the landing error (and its twist and swing parts): the fraction of
    /// trials at or below each error, with the tolerance marked.
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
        let series = vec![
            Series::new("landing error", cdf(self.trials.iter().map(|t| t.landing_error_deg).collect())),
            Series::new("| |twist| − 180° |", cdf(self.trials.iter().map(|t| t.twist_error_deg.abs()).collect())),
            Series::new("swing", cdf(self.trials.iter().map(|t| t.swing_deg).collect())),
        ];
        let mut plot = LinePlot::new(
            "robust",
            format!(
                "{}, problem {}: {} trials, open loop",
                Path::new(&self.schedule)
                    .file_name()
                    .map_or(self.schedule.clone(), |n| n.to_string_lossy().into_owned()),
                self.problem,
                self.trials.len()
            ),
            "error (degrees)",
            "fraction of trials at or below",
            series,
        );
        plot.ref_lines.push(RefLine {
            y: self.within,
            label: format!("{:.1} % within {}°", 100.0 * self.within, self.settings.tolerance_deg),
        });
        plot
    }

    /// Writes `robust.md`, `robust.csv`, `robust.json` and the plot into `out/<problem>-robust/`,
    /// replacing an earlier check there only when every file is written; returns the folder.
    pub fn write(&self, out: &Path) -> Result<PathBuf, RobustWriteError> {
        let staging = Staging::begin(out, &format!("{}-robust", self.problem))?;
        let json = serde_json::to_string_pretty(self).unwrap_or_default();
        for (name, text) in [("robust.md", self.to_markdown()), ("robust.csv", self.to_csv()), ("robust.json", json)] {
            let path = staging.dir().join(name);
            std::fs::write(&path, text)
                .map_err(|source| RobustWriteError::Io { path: staging.shown(&path), source })?;
        }
        line_plot(staging.dir(), &self.distribution_plot())?;
        Ok(staging.commit()?)
    }
}
