//! The motor limits in the whole-manoeuvre optimisation: one row per sample, joint and limit.
//!
//! Each row is a limit's stretch squared `k²` at one torque sample ([`crate::model::motor`]:
//! the square of the factor by which the path must be slowed there to stay within the limit)
//! with its gradient on the control points,
//!
//! $$ ∇k^2 = \frac{∂k^2}{∂τ_j} ∇τ_j + \frac{∂k^2}{∂q̇_j} ∇q̇_j, $$
//!
//! from the torque and rate gradients of [`super::sensitivity::TorqueSample`]. Two uses:
//! - at a fixed fall time (objectives `peak`, `energy`) the path is within the motors where every
//!   `k ≤ 1`, that is every usage ratio `ρ ≤ 1`: the rows are constraints `ρ + ∇ρ·δ ≤ b + σ` with
//!   an elastic `σ ≥ 0` ([`RowForm::Ratio`]; the ratio, not `k²`, because it is linear in `|τ|`
//!   and `|q̇|` for every limit but power, so the linearisation is exact in the torque and rate:
//!   with `k²` the speed limit's curvature held the trust region near 5e-4 rad for a hundred
//!   iterations on the paper's cat);
//! - for the least fall time (objective `min-time`) the path's least duration within the motors
//!   is its own times `max k`: the rows are the objective `min max k²` (proportional to the least
//!   drop height `g (T max k)²/2`), whose linearisation is a minimax LP like the peak torque's.
//!
//! With a torque limit alone `k² = |τ|/τ_max` and `min max k²` is the peak-torque optimum, so the
//! least fall time follows it by the exact `1/T²` scaling (DESIGN.md §9).
//!
//! ## Signs
//! `k²` depends on `|τ_j|` and `|q̇_j|`, and a step may carry either through zero. As the peak
//! torque's rows `±(τ + ∇τ·δ) ≤ t` do, each limit is linearised in the *linearised* torque and
//! rate: with `f = k²`, `f_a = ∂f/∂|τ| ≥ 0`, `f_w = ∂f/∂|q̇| ≥ 0`,
//!
//! $$ k^2(δ) ≈ f + f_a (|τ + ∇τ·δ| − |τ|) + f_w (|q̇ + ∇q̇·δ| − |q̇|)
//!    = \max_{σ_a, σ_w = ±1} \big[f − f_a|τ| − f_w|q̇| + f_a σ_a (τ + ∇τ·δ) + f_w σ_w (q̇ + ∇q̇·δ)\big], $$
//!
//! one linear row per sign pair (two when a partial is zero). With a torque limit alone these are
//! exactly the peak LP's rows divided by `τ_max`.
//!
//! Rows of the power limit far below the reference (`k²` under [`ROW_FLOOR`] of the bound, or of
//! the largest row) are left out of a subproblem: `∂k²/∂|τ| = ⅔ (|q̇|/P)^{2/3} |τ|^{−1/3}` is
//! unbounded as `τ → 0`, such rows cannot become active within one trust region in practice, and
//! the ratio test rejects a step that makes one active. Every other row is kept (the torque's and
//! speed's partials are constant or bounded, the envelope's `∂k²/∂|τ| ≤ 2/τ_s` and
//! `∂k²/∂|q̇| ≤ 2k/ω_0`), and screened exactly as the peak's are: a torque moves by
//! `O(Δ/h²)` within a trust radius `Δ` on knot spans `h` apart, so a row far below the largest
//! may still become it.

use super::sensitivity::TorqueSample;
use crate::model::motor::{Limit, Motors};

/// Power rows whose `k²` is below this fraction of the reference are left out of a
/// subproblem (module docs).
pub const ROW_FLOOR: f64 = 0.25;

/// One linear row of one limit at one sample and joint, for one sign pair (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct LimitRow {
    /// The limit's `k²` or `ρ` at the current iterate.
    pub value: f64,
    /// The row at `δ = 0` (at most `value`, equal for the signs of `τ` and `q̇`).
    pub constant: f64,
    /// The row's gradient, per rad.
    pub gradient: Vec<(usize, f64)>,
    /// Whether the row may be left out far below the reference ([`ROW_FLOOR`]).
    pub floored: bool,
}

/// Which measure of a limit's usage the rows linearise.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowForm {
    /// The stretch squared `k²` (the `min-time` objective).
    Stretch,
    /// The usage ratio `ρ` (constraints `ρ ≤ b` at a fixed fall: linear in `|τ|`, `|q̇|` but for
    /// the power limit, so the linearisation is exact in the torque and rate for the others).
    Ratio,
}

/// The rows of every sample, joint, limit and sign pair, in `form`.
pub fn limit_rows(samples: &[TorqueSample], motors: &Motors, form: RowForm) -> Vec<LimitRow> {
    let mut rows = Vec::new();
    if motors.is_ideal() {
        return rows;
    }
    for s in samples {
        for (j, motor) in motors.joints.iter().enumerate() {
            let (tau, rate) = (s.tau[j], s.rate[j]);
            let usage = match form {
                RowForm::Stretch => motor.stretch_squared(tau, rate),
                RowForm::Ratio => motor.usage(tau, rate),
            };
            for k in usage {
                let (fa, fw) = (k.d_torque, k.d_speed);
                let base = k.value - fa * tau.abs() - fw * rate.abs();
                let torque_signs: &[f64] = if fa > 0.0 { &[1.0, -1.0] } else { &[0.0] };
                let speed_signs: &[f64] = if fw > 0.0 { &[1.0, -1.0] } else { &[0.0] };
                for &sa in torque_signs {
                    for &sw in speed_signs {
                        let gradient = s.gradient[j]
                            .iter()
                            .zip(&s.rate_gradient[j])
                            .map(|(&(v, gt), &(_, gr))| (v, fa * sa * gt + fw * sw * gr))
                            .collect();
                        rows.push(LimitRow {
                            value: k.value,
                            constant: base + fa * sa * tau + fw * sw * rate,
                            gradient,
                            floored: form == RowForm::Stretch && k.limit == Limit::Power,
                        });
                    }
                }
            }
        }
    }
    rows
}

/// The largest `k²` of the rows (0 with none).
pub fn largest(rows: &[LimitRow]) -> f64 {
    rows.iter().map(|r| r.value).fold(0.0, f64::max)
}
