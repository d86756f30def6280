//! `[robust]`: the draws of the robustness check ([`crate::robust`]), how many and how wide.

use serde::{Deserialize, Serialize};

use super::error::{bad, ProblemError};
use crate::numeric::numfmt::echo;
use crate::problem::limits::{count_in_range, CountRange};

/// Trials of one robustness check.
pub const TRIALS: CountRange = CountRange { min: 1, max: 100_000 };
/// Largest spread of a size, percent: a half must keep a positive mass, length and radius.
pub const MAX_SPREAD_PCT: f64 = 90.0;

/// Settings of the robustness check: each trial draws a cat around the problem's (each size
/// scaled by a factor uniform in `[1 − p/100, 1 + p/100]`, both halves alike) and a release spin
/// (each world component normal with standard deviation `spin_sigma_nms`), and runs the schedule
/// open loop on it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RobustSettings {
    /// Number of trials.
    pub trials: usize,
    /// Seed of the draws; trial `k` draws from its own stream, so any trial can be rerun alone.
    pub seed: u64,
    /// Spread of each half's mass, percent.
    pub mass_pct: f64,
    /// Spread of each half's length, percent.
    pub length_pct: f64,
    /// Spread of each half's radius, percent.
    pub radius_pct: f64,
    /// Standard deviation of each component of the release spin `L`, N·m·s (added to
    /// `drop.angular_momentum`).
    pub spin_sigma_nms: f64,
    /// A trial lands when A's final attitude is within this angle of the target, degrees.
    pub tolerance_deg: f64,
}

impl Default for RobustSettings {
    fn default() -> Self {
        Self {
            trials: 200,
            seed: 1,
            mass_pct: 10.0,
            length_pct: 0.0,
            radius_pct: 0.0,
            spin_sigma_nms: 0.005,
            tolerance_deg: 5.0,
        }
    }
}

impl RobustSettings {
    pub(crate) fn validate(&self) -> Result<(), ProblemError> {
        count_in_range("robust.trials", self.trials, TRIALS)?;
        for (field, v) in [
            ("robust.mass_pct", self.mass_pct),
            ("robust.length_pct", self.length_pct),
            ("robust.radius_pct", self.radius_pct),
        ] {
            if !(0.0..=MAX_SPREAD_PCT).contains(&v) {
                return Err(bad(field, echo(v), &format!("must lie in [0, {MAX_SPREAD_PCT}] percent")));
            }
        }
        if !(self.spin_sigma_nms.is_finite() && self.spin_sigma_nms >= 0.0) {
            return Err(bad("robust.spin_sigma_nms", echo(self.spin_sigma_nms), "must be a finite number ≥ 0 (N·m·s)"));
        }
        if !(self.tolerance_deg > 0.0 && self.tolerance_deg <= 180.0) {
            return Err(bad("robust.tolerance_deg", echo(self.tolerance_deg), "must lie in (0, 180] degrees"));
        }
        Ok(())
    }
}
