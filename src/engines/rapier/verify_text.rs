//! How a [`Verification`] reads: prose for `simulate`, cells for the verification table and CSV,
//! and the run summary's line of verdicts. Gaps and estimates read as degrees (twist, swing) or
//! percent of the exact peak (peak torque), steps in seconds with four significant digits.

use super::verdict::{Convergence, Quantity, Status, StepSource, Verification};

impl Verification {
    /// The steps of the runs kept, s: `7.14e-4, 3.57e-4, 1.79e-4` (`—` when no run was kept).
    pub fn dt_sequence_text(&self) -> String {
        if self.dt_sequence.is_empty() {
            return "—".to_string();
        }
        self.dt_sequence.iter().map(|d| format!("{d:.3e}")).collect::<Vec<_>>().join(", ")
    }

    /// Rapier's own error estimates of twist, swing and peak torque: `0.029°, 0.011°, 0.01 %`
    /// (`—` where there is none).
    pub fn estimates_text(&self) -> String {
        let one = |c: &Convergence| c.estimate.map_or("—".to_string(), |e| c.quantity.format_gap(e));
        self.quantities.iter().map(one).collect::<Vec<_>>().join(", ")
    }

    /// The tolerances: `twist 0.500°, swing 0.500°, peak torque 2.00 %`.
    pub fn tolerances_text(&self) -> String {
        let one = |c: &Convergence| format!("{} {}", c.quantity, c.quantity.format_gap(c.tolerance));
        self.quantities.iter().map(one).collect::<Vec<_>>().join(", ")
    }

    /// The verification as indented lines of prose.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "  verdict          {} (tolerances: {})", self.verdict, self.tolerances_text());
        let first = match self.first_step {
            StepSource::Auto => format!("first step auto, set by the {}", self.time_scales.limited_by),
            StepSource::Fixed => "first step fixed by rapier.dt".to_string(),
        };
        let _ = writeln!(
            s,
            "  dt sequence      {} s ({first}; {} rapier steps of a budget of {}, {:.3} s)",
            self.dt_sequence_text(),
            self.steps_taken,
            self.step_budget,
            self.run_time_s
        );
        if let Some(d) = &self.motor_demand {
            let finest = self.runs.last().map(|r| &r.saturation);
            let rapier = match finest {
                Some(sat) if !sat.is_empty() => {
                    sat.iter().map(|m| m.describe()).collect::<Vec<_>>().join(", ") + " in the finest run"
                }
                // What a motor applied, not the torque reconstructed from the motion, whose raw
                // peaks (below) carry an error of order dt and may read above the bound.
                Some(_) => "rapier's motors stayed within their bounds (what they applied; the raw peaks below are reconstructed from the motion, first order in dt)".to_string(),
                None => "no rapier run".to_string(),
            };
            let _ = writeln!(s, "  motors           {} (exact engine); {rapier}", d.verdict());
        }
        let twists: Vec<String> =
            self.runs.iter().filter_map(|r| r.spine_twist_max_deg).map(|t| format!("{t:.1e}")).collect();
        if !twists.is_empty() {
            let _ = writeln!(
                s,
                "  joint twist      the halves twisted about the spine by at most {}° (ball joint, per run: its no-twist constraint as rapier held it)",
                twists.join(", ")
            );
        }
        for f in &self.failures {
            let _ = writeln!(s, "  failed run       dt = {:.3e} s: {}", f.dt, f.reason);
        }
        for c in &self.quantities {
            let unit = if c.quantity == Quantity::PeakTorque { " N·m" } else { "°" };
            let list = |v: &[f64]| {
                if v.is_empty() {
                    return "—".to_string();
                }
                v.iter().map(|x| format!("{x:.4}")).collect::<Vec<_>>().join(", ")
            };
            let opt = |x: Option<f64>| x.map_or("—".to_string(), |e| c.quantity.format_gap(e));
            // The peak's raw values are the largest motor's; its limits each motor's on its own.
            let limit = if c.quantity == Quantity::PeakTorque { "→ 0 motor by motor" } else { "→ 0" };
            let _ = writeln!(
                s,
                "  {:<16} raw {}{unit}; {limit}: {}{unit}; order {}; estimate {}; gap to exact {} (exact {:.4}{unit})",
                c.quantity.to_string(),
                list(&c.raw),
                list(&c.extrapolated),
                c.observed_order.map_or("—".to_string(), |p| format!("{p:.2}")),
                opt(c.estimate),
                opt(c.gap),
                c.reference
            );
        }
        s
    }
}

impl Verification {
    /// Header of [`Verification::csv`].
    pub const CSV_HEADER: &'static str = "verdict,dt_sequence_s,observed_order_twist,twist_estimate_deg,swing_estimate_deg,peak_torque_estimate_rel,rapier_time_s";

    /// The verification as CSV fields (the dt sequence separated by `;`).
    pub fn csv(&self) -> String {
        self.fields().join(",")
    }

    /// The fields of [`Verification::CSV_HEADER`], formatted (the dt sequence joined by `;`).
    pub fn fields(&self) -> [String; 7] {
        let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:.6e}"));
        let est = |q| opt(self.quantity(q).and_then(|c| c.estimate));
        let dts = self.dt_sequence.iter().map(|d| format!("{d:.6e}")).collect::<Vec<_>>().join(";");
        let order = opt(self.quantity(Quantity::Twist).and_then(|c| c.observed_order));
        [
            self.status.to_string(),
            dts,
            order,
            est(Quantity::Twist),
            est(Quantity::Swing),
            est(Quantity::PeakTorque),
            format!("{:.6}", self.run_time_s),
        ]
    }

    /// Four Markdown table cells: verdict, dt sequence, estimates, rapier time.
    pub fn table_cells(&self) -> String {
        format!("{} | {} | {} | {:.3}", self.verdict, self.dt_sequence_text(), self.estimates_text(), self.run_time_s)
    }

    /// `paper-cosine verified, cycloidal verified, …` with the count of each word first.
    pub fn verdicts_line<'a, N: std::fmt::Display>(
        rows: impl Iterator<Item = (N, Option<&'a Verification>)>,
    ) -> String {
        let rows: Vec<(N, Option<&Verification>)> = rows.collect();
        let count = |st: Status| rows.iter().filter(|(_, v)| v.is_some_and(|v| v.status == st)).count();
        let list = rows
            .iter()
            .map(|(n, v)| format!("{n} {}", v.map_or("unverified".to_string(), |v| v.status.to_string())))
            .collect::<Vec<_>>()
            .join(", ");
        format!(
            "{} verified, {} not verified, {} inconclusive ({list})",
            count(Status::Verified),
            count(Status::NotVerified),
            count(Status::Inconclusive)
        )
    }
}
