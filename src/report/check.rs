//! rapier's check of a trajectory against the exact engine, as every report shows it: the check
//! as prose ([`RapierCheck::to_text`]) and the verification table ([`verification_row`]). The
//! check itself is computed by [`crate::engines::rapier_check`] (DESIGN.md §6).
//!
//! Twist and swing are in degrees (twist signed about A's initial `+z`), torques in N·m, the
//! peak torque's error relative to the exact engine's peak.

use std::fmt::Write as _;

use crate::engines::jumps::VelocityJump;
use crate::engines::rapier::{Quantity, Reference, Verdict, Verification};
use crate::engines::rapier_check::{EngineFigures, RapierCheck};

impl RapierCheck {
    /// The check as indented lines of prose (nothing for the exact engine's report).
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        if let Some(dt) = self.dt {
            let _ = writeln!(s, "  dt               {dt:e} s");
        }
        if let (Some(t), Some(w)) = (self.twist_deg_raw, self.swing_deg_raw) {
            let _ = writeln!(s, "  raw (finest dt)  twist {t:+.9}°, swing {w:.9}°");
        }
        if let Some(e) = self.tracking_error_rad {
            let _ = writeln!(s, "  tracking error   [{:.3e}, {:.3e}] rad", e[0], e[1]);
        }
        if let Some(e) = self.twist_error_deg {
            let peak = self
                .peak_torque_rel_error
                .map_or("— (the exact peak is zero)".to_string(), |p| format!("{:+.3}%", 100.0 * p));
            let _ = writeln!(s, "  raw vs exact     twist {e:+.4e}°, peak torque {peak}");
        }
        if let Some(x) = self.extrapolated {
            let _ = writeln!(
                s,
                "  dt → 0 (from {:.2e} s and {:.2e} s): twist {:+.6}°, swing {:.6}°, peak torque {:.4} N·m; vs exact engine twist {:+.4e}°",
                x.dt[0], x.dt[1], x.twist_deg, x.swing_deg, x.peak_torque_nm, x.twist_error_deg
            );
        }
        if let Some(v) = &self.verification {
            let _ = write!(s, "{}", v.to_text());
        }
        s
    }
}

impl EngineFigures {
    /// What a report's peak-torque line adds to say whose peaks they are: nothing for the exact
    /// engine; for rapier, that they are its finest run's, raw (the estimate at `dt → 0`, which
    /// the verdict judges, is in the check's lines below them), and, when a motor saturated, that
    /// they are not converged in the step (no extrapolation is made then), with the raw peak of
    /// each run (on Kane and Scher's cat at a 10 N·m limit: 66.9931, 46.6468, 30.3401 N·m).
    pub fn peaks_note(&self) -> String {
        let Some(v) = self.check.verification.as_ref().filter(|_| self.check.dt.is_some()) else {
            return String::new();
        };
        if !matches!(v.verdict, Verdict::Saturated { .. }) {
            return "  (rapier's finest run, raw; dt → 0 below)".into();
        }
        let raw = v.quantity(Quantity::PeakTorque).map_or(String::new(), |c| {
            let list: Vec<String> = c.raw.iter().map(|x| format!("{x:.4}")).collect();
            format!(": {} N·m over its steps", list.join(", "))
        });
        format!("  (rapier's finest run, raw; a motor saturated, and rapier's peaks do not converge as dt → 0{raw})")
    }

    /// The prose lines every engine report ends with: rapier's check, the integration's error
    /// estimate (with its steps per `piece`, e.g. `phase`), whether it converged, the run time.
    pub fn closing_text(&self, piece: &str) -> String {
        let mut s = self.check.to_text();
        if let Some(e) = self.error_estimate_rad {
            let _ = writeln!(s, "  error estimate   {e:.1e} rad ({} steps per {piece})", self.steps);
        }
        if self.converged == Some(false) {
            let _ =
                writeln!(s, "  NOT CONVERGED    the integration did not meet exact.tolerance within its step budget");
        }
        let _ = writeln!(s, "  run time         {:.3} ms", 1e3 * self.run_time_s);
        s
    }
}

/// A rate jump as a line of a report's prose.
pub fn jump_line(j: &VelocityJump) -> String {
    format!(
        "  velocity jump    at t = {:.6} s: q̇ [{:.4}, {:.4}] → [{:.4}, {:.4}] rad/s, impulse [{:.5}, {:.5}] N·m·s\n",
        j.time, j.rates_before[0], j.rates_before[1], j.rates_after[0], j.rates_after[1], j.impulse[0], j.impulse[1]
    )
}

/// Header of the verification table that [`verification_row`] fills.
pub const VERIFICATION_TABLE_HEADER: &str = "| schedule | exact twist | rapier twist | rapier → 0 twist | exact swing | rapier swing | rapier → 0 swing | exact peak | rapier peak | rapier → 0 peak | → 0 peak diff | rapier momentum drift | tracking error rad | verdict | dt sequence s | estimates | rapier time s |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---|---:|\n";

/// The number of cells of a [`VERIFICATION_TABLE_HEADER`] row after the schedule's name.
pub const VERIFICATION_TABLE_CELLS: usize = 16;

/// One row of the verification table: the exact engine's values (twist and swing shown in
/// degrees) and rapier's verification of the same trajectory. rapier's raw columns are the finest
/// run's, `→ 0` the last extrapolation, which the verdict judges (so the peak's difference is the
/// extrapolated peak's: the finest run's is of order `dt`, +5.8 % on the paper's whole optimum);
/// a number rapier does not have (no run, fewer than two runs, an extrapolation left out because a
/// motor saturated, a zero exact peak) reads `—`.
pub fn verification_row(name: &str, exact: &Reference, v: &Verification) -> String {
    let run = v.finest.as_ref();
    let dash = || "—".to_string();
    let value = |q: Quantity| v.quantity(q).and_then(|c| c.value).map_or_else(dash, |x| format!("{x:.4}"));
    let raw = |x: Option<f64>, d: usize| x.map_or_else(dash, |x| format!("{x:.d$}"));
    let tr = v
        .tracking_error_rad
        .as_ref()
        .map_or_else(dash, |t| t.iter().map(|x| format!("{x:.1e}")).collect::<Vec<_>>().join(", "));
    let peak = v.quantity(Quantity::PeakTorque).and_then(|c| c.value);
    let diff = peak
        .filter(|_| exact.peak_torque > 0.0)
        .map_or_else(dash, |x| format!("{:+.2}%", 100.0 * (x / exact.peak_torque - 1.0)));
    format!(
        "| {name} | {:.4} | {} | {} | {:.4} | {} | {} | {:.3} | {} | {} | {diff} | {} | {tr} | {} |\n",
        exact.twist.to_degrees(),
        raw(run.map(|x| x.twist.to_degrees()), 4),
        value(Quantity::Twist),
        exact.swing.to_degrees(),
        raw(run.map(|x| x.swing.to_degrees()), 4),
        value(Quantity::Swing),
        exact.peak_torque,
        raw(run.map(|x| x.peak_torque.max), 3),
        raw(peak, 3),
        v.momentum_drift.map_or_else(dash, |x| format!("{x:.2e}")),
        v.table_cells()
    )
}
