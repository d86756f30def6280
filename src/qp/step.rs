//! The linearised step of the exact-dynamics refinement: one trust-region QP of a sequential
//! QP on the node rates (module docs, "The linearised step").
//!
//! The outer loop (not here) evaluates the exact torques `τ_j` at sample instants and their
//! gradients with respect to the node rates, calls [`solve_linearised_step`], and accepts or
//! rejects `ω + δ` by a merit function, growing or shrinking the trust radius.
//!
//! Internally `δ = (|D|/T) \hat δ` and `t = s_τ \hat t` with `s_τ = \max_j |τ_j|` (one when all
//! vanish), so that the QP Clarabel sees is of order one.

use serde::Serialize;

use super::assembly::{Assembly, NodeConstraints};
use super::solution::{QpStatus, SolveInfo};
use super::{bad, positive, positive_opt, QpError, QpSettings};
use crate::settings::Boundary;

/// One torque sample: its current value and its gradient with respect to the node rates.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TorqueSample {
    /// `τ_j` at the current rates, N·m.
    pub value: f64,
    /// Nonzeros of `∂τ_j/∂ω_k` as `(k, value)`, N·m per rad/s; repeated `k` are summed.
    pub gradient: Vec<(usize, f64)>,
}

/// The data of one linearised step.
#[derive(Clone, Copy, Debug)]
pub struct LinearisedStep<'a> {
    /// Current node rates `ω_k`, rad/s, equally spaced on the twist phase, ends included.
    pub rates: &'a [f64],
    /// Torque samples with their gradients.
    pub samples: &'a [TorqueSample],
    /// Trust radius `Δ`: the step obeys `|δ_k| ≤ Δ`, rad/s.
    pub trust_radius: f64,
    /// Duration `T` of the twist phase, s.
    pub duration: f64,
    /// Circulation `D = ∫(ω + δ) ds` required of the new rates (trapezoid rule), rad, non-zero.
    pub circulation: f64,
    /// Boundary conditions imposed on `ω + δ`.
    pub boundary: Boundary,
    /// Bound on `|ω + δ|`, rad/s; none when absent.
    pub rate_limit: Option<f64>,
    /// Bound on the second difference of `ω + δ` per unit time squared, rad/s³, with zero
    /// acceleration at both ends (as in the profile QP); none when absent.
    pub jerk_limit: Option<f64>,
}

/// The answer of one linearised step, whatever the status (module docs of `solution`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StepSolution {
    /// How the solve ended.
    pub status: QpStatus,
    /// The step `δ_k` to add to the node rates, rad/s.
    pub step: Vec<f64>,
    /// The linear model's peak `max_j |τ_j + g_jᵀδ|` at this step, N·m.
    pub predicted_peak: f64,
    /// Clarabel's diagnostics; the duality gap is in N·m.
    #[serde(flatten)]
    pub info: SolveInfo,
}

impl LinearisedStep<'_> {
    /// Checks every input; names the first one that is wrong.
    pub fn validate(&self) -> Result<(), QpError> {
        let n = self.rates.len();
        if n < 3 {
            return Err(bad("rates", format!("{n} nodes"), "need at least 3 nodes"));
        }
        if let Some(k) = self.rates.iter().position(|w| !w.is_finite()) {
            return Err(bad("rates", self.rates[k], &format!("node {k} is not finite")));
        }
        if self.samples.is_empty() {
            return Err(bad("samples", "none", "need at least one torque sample"));
        }
        for (j, s) in self.samples.iter().enumerate() {
            if !s.value.is_finite() {
                return Err(bad("samples", s.value, &format!("sample {j}'s value is not finite")));
            }
            for &(k, g) in &s.gradient {
                if k >= n {
                    return Err(bad("samples", k, &format!("sample {j} names node {k} of {n}")));
                }
                if !g.is_finite() {
                    return Err(bad("samples", g, &format!("sample {j}'s gradient is not finite")));
                }
            }
        }
        positive("trust_radius", self.trust_radius)?;
        positive("duration", self.duration)?;
        if !self.circulation.is_finite() || self.circulation == 0.0 {
            return Err(bad("circulation", self.circulation, "must be finite and non-zero"));
        }
        positive_opt("rate_limit", self.rate_limit)?;
        positive_opt("jerk_limit", self.jerk_limit)
    }
}

/// Solves one linearised step (module docs): the step `δ` within the trust box that minimises
/// the linear model's peak torque, with the integral, boundary and limits imposed on `ω + δ`.
/// A solve that ends without a solution is not an error: its status says how it ended.
pub fn solve_linearised_step(
    problem: &LinearisedStep<'_>,
    settings: &QpSettings,
) -> Result<StepSolution, QpError> {
    problem.validate()?;
    let n = problem.rates.len();
    let t = problem.duration;
    let rate_unit = problem.circulation.abs() / t;
    let torque_unit = problem.samples.iter().map(|s| s.value.abs()).fold(0.0, f64::max);
    let torque_unit = if torque_unit > 0.0 { torque_unit } else { 1.0 };

    // The normalisation of the profile QP: v = ωT/D, integral one (signed D).
    let to_v = t / problem.circulation;
    let offset: Vec<f64> = problem.rates.iter().map(|w| w * to_v).collect();
    let bound = n; // the column of the epigraph bound t̂
    let mut asm = Assembly::new(n + 1);
    asm.linear_cost(bound, 1.0);
    NodeConstraints {
        nodes: n,
        boundary: problem.boundary,
        rate_limit: problem.rate_limit.map(|r| r / rate_unit),
        jerk_limit: problem.jerk_limit.map(|j| j * t * t / rate_unit),
        trust: Some(problem.trust_radius / rate_unit),
        offset: Some(&offset),
    }
    .add_to(&mut asm);
    // x is a step in v, so δ = x · D/T: the gradient column scale carries the sign of D.
    let column = problem.circulation / t / torque_unit;
    for s in problem.samples {
        let entries = s.gradient.iter().map(|&(k, g)| (k, g * column));
        asm.abs_at_most(entries, s.value / torque_unit, bound);
    }

    let solved = asm.solve(settings)?;
    let step: Vec<f64> = solved.x[..n].iter().map(|x| x * problem.circulation / t).collect();
    let predicted_peak = problem
        .samples
        .iter()
        .map(|s| (s.value + s.gradient.iter().map(|&(k, g)| g * step[k]).sum::<f64>()).abs())
        .fold(0.0, f64::max);
    let mut info = solved.info;
    info.duality_gap *= torque_unit;
    Ok(StepSolution { status: solved.status, step, predicted_peak, info })
}
