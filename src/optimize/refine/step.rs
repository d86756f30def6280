//! The linearised step of the exact-dynamics refinement: one trust-region LP of the sequential
//! linear programming on the node rates (module docs of the refinement).
//!
//! Given node rates `ω`, torque samples `τ_j` with sparse gradients `g_j = ∂τ_j/∂ω` and a trust
//! radius `Δ`, [`solve_linearised_step`] solves
//!
//! $$ \min_{δ, t}\; t \quad\text{s.t.}\quad |τ_j + g_j^{\mathsf T} δ| \le t,\; |δ_k| \le Δ, $$
//!
//! with the integral, boundary, rate and jerk constraints of the profile QP
//! ([`crate::optimize::qp`]) imposed on `ω + δ`. Torques that depend on the angle `φ = ∫ω` have
//! gradients with a long run of equal trapezoid weights on every earlier node, `O(N²)` nonzeros
//! in all; such runs are rewritten exactly on the prefix sums `S_k = \hat h \sum_{m ≤ k} δ_m` (one
//! equality each), which keeps the data `O(N)`.
//!
//! The outer loop ([`super::refine`]) evaluates the exact torques `τ_j` at sample instants and
//! their gradients with respect to the node rates, calls [`solve_linearised_step`], and accepts or
//! rejects `ω + δ` by a merit function, growing or shrinking the trust radius.
//!
//! Internally `δ = (D/T) \hat δ` (the normalisation of the profile QP) and `t = s_τ \hat t` with
//! `s_τ = \max_j |τ_j|` (one when all vanish), so that the LP Clarabel sees is of order one;
//! runs of equal gradient coefficients go onto prefix sums of `\hat δ` (see [`SampleRow`]).
//! Rows that cannot bind within the trust box are screened out first
//! ([`crate::optimize::conic`]'s `active_sides`; exact).
//!
//! ## References
//! - J. Nocedal and S. J. Wright, *Numerical Optimization*, 2nd ed. (2006), ch. 4 and 18
//!   (trust regions, sequential quadratic programming).

use serde::Serialize;

use crate::optimize::conic::{
    active_sides, bad, positive, positive_opt, Assembly, ConicError, QpSettings, QpStatus, SolveInfo,
};
use crate::optimize::qp::NodeConstraints;
use crate::problem::settings::Boundary;
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

/// The answer of one linearised step, whatever the status (a status short of solved is not an
/// error; module docs of [`crate::optimize::conic`]).
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
    pub fn validate(&self) -> Result<(), ConicError> {
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
pub fn solve_linearised_step(problem: &LinearisedStep<'_>, settings: &QpSettings) -> Result<StepSolution, ConicError> {
    solve_rows(problem, settings, screened)
}

/// [`solve_linearised_step`] on the rows `rows` picks (the screened ones, or in tests all).
fn solve_rows<'s>(
    problem: &LinearisedStep<'s>,
    settings: &QpSettings,
    rows: impl Fn(&'s [TorqueSample], f64) -> Vec<(&'s TorqueSample, [bool; 2])>,
) -> Result<StepSolution, ConicError> {
    problem.validate()?;
    let n = problem.rates.len();
    let t = problem.duration;
    let rate_unit = problem.circulation.abs() / t;
    let torque_unit = problem.samples.iter().map(|s| s.value.abs()).fold(0.0, f64::max);
    let torque_unit = if torque_unit > 0.0 { torque_unit } else { 1.0 };

    // The normalisation of the profile QP: v = ωT/D, integral one (signed D).
    let to_v = t / problem.circulation;
    let offset: Vec<f64> = problem.rates.iter().map(|w| w * to_v).collect();
    // x is a step in v, so δ = x · D/T: the gradient column scale carries the sign of D.
    let column = problem.circulation / t / torque_unit;
    let h = 1.0 / (n - 1) as f64;
    let kept = rows(problem.samples, problem.trust_radius);
    let rows: Vec<SampleRow> = kept.iter().map(|(s, _)| SampleRow::new(&s.gradient, column, h)).collect();
    let prefix = rows.iter().any(|r| !r.on_prefix.is_empty());

    let bound = n; // the column of the epigraph bound t̂, then the accelerations, prefix sums
    let node_rows = NodeConstraints {
        nodes: n,
        boundary: problem.boundary,
        rate_limit: problem.rate_limit.map(|r| r / rate_unit),
        jerk_limit: problem.jerk_limit.map(|j| j * t * t / rate_unit),
        trust: Some(problem.trust_radius / rate_unit),
        offset: Some(&offset),
        accel: bound + 1,
    };
    let first_sum = bound + 1 + node_rows.accel_count();
    let mut asm = Assembly::new(first_sum + if prefix { n } else { 0 });
    asm.linear_cost(bound, 1.0);
    node_rows.add_to(&mut asm);
    if prefix {
        // S_k = ĥ Σ_{m ≤ k} x_m
        let s = |k: usize| first_sum + k;
        asm.equal([(s(0), 1.0), (0, -h)], 0.0);
        for k in 1..n {
            asm.equal([(s(k), 1.0), (s(k - 1), -1.0), (k, -h)], 0.0);
        }
    }
    for (row, (sample, sides)) in rows.iter().zip(&kept) {
        let entries = row.on_step.iter().copied().chain(row.on_prefix.iter().map(|&(k, g)| (first_sum + k, g)));
        asm.sides_at_most(entries, sample.value / torque_unit, *sides, bound);
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

/// The samples that can bound the step's peak, each with the sides of `|τ + gᵀδ| ≤ t` that
/// can be active ([`active_sides`]).
fn screened(samples: &[TorqueSample], radius: f64) -> Vec<(&TorqueSample, [bool; 2])> {
    let spans: Vec<(f64, f64)> =
        samples.iter().map(|s| (s.value, radius * s.gradient.iter().map(|(_, g)| g.abs()).sum::<f64>())).collect();
    samples.iter().zip(active_sides(&spans)).filter(|(_, sides)| sides[0] || sides[1]).collect()
}

/// Runs of equal coefficients shorter than this stay as they are.
const MIN_RUN: usize = 4;

/// One sample's gradient row on the normalised step `x`, with every run of at least [`MIN_RUN`]
/// equal coefficients on consecutive nodes rewritten on the prefix sums `S_k = ĥ Σ_{m≤k} x_m`:
/// `c Σ_{m=a}^{b} x_m = (c/ĥ)(S_b − S_{a−1})`. Exact, and it turns the dense rows of torques
/// that depend on the angle `φ = ∫ω` (trapezoid weights up to the sample) into a few nonzeros.
struct SampleRow {
    on_step: Vec<(usize, f64)>,
    on_prefix: Vec<(usize, f64)>,
}

impl SampleRow {
    fn new(gradient: &[(usize, f64)], scale: f64, h: f64) -> Self {
        let mut sorted: Vec<(usize, f64)> = gradient.iter().map(|&(k, g)| (k, g * scale)).collect();
        sorted.sort_unstable_by_key(|&(k, _)| k);
        let mut merged: Vec<(usize, f64)> = Vec::with_capacity(sorted.len());
        for (k, g) in sorted {
            match merged.last_mut() {
                Some(last) if last.0 == k => last.1 += g,
                _ => merged.push((k, g)),
            }
        }
        let (mut on_step, mut on_prefix) = (Vec::new(), Vec::new());
        let mut start = 0;
        while start < merged.len() {
            let (a, c) = merged[start];
            let mut end = start + 1;
            while end < merged.len() && merged[end].0 == a + (end - start) && merged[end].1.to_bits() == c.to_bits() {
                end += 1;
            }
            if end - start >= MIN_RUN {
                on_prefix.push((merged[end - 1].0, c / h));
                if a > 0 {
                    on_prefix.push((a - 1, -c / h));
                }
            } else {
                on_step.extend_from_slice(&merged[start..end]);
            }
            start = end;
        }
        Self { on_step, on_prefix }
    }
}

#[cfg(test)]
mod tests {
    use super::{screened, LinearisedStep, QpSettings, SampleRow, TorqueSample};
    use crate::problem::settings::Boundary;

    #[test]
    fn screening_leaves_the_step_as_it_is() {
        // Seeded samples of both signs and sizes, dense and local gradients, at a wide and a
        // narrow trust radius: the screened LP (some samples and sides left out) gives the
        // full LP's step and peak.
        let n = 21;
        let mut seed = 12345u64;
        let mut uniform = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let samples: Vec<TorqueSample> = (0..120)
            .map(|j| {
                let k = j % (n - 1);
                let mut gradient: Vec<(usize, f64)> = (0..=k).map(|m| (m, 0.2 * uniform())).collect();
                gradient.push((k + 1, 3.0 * uniform()));
                TorqueSample { value: 10.0 * uniform() * (1.0 + (j % 7) as f64), gradient }
            })
            .collect();
        // ω = 2t: at rest at the start, and its (trapezoid) integral over the unit time is one.
        let rates: Vec<f64> = (0..n).map(|k| 2.0 * k as f64 / (n - 1) as f64).collect();
        // Both signs of the same samples: each side of the screen gets to be the one that binds.
        let negated: Vec<TorqueSample> = samples
            .iter()
            .map(|s| TorqueSample { value: -s.value, gradient: s.gradient.iter().map(|&(k, g)| (k, -g)).collect() })
            .collect();
        for (samples, radius) in [(&samples, 0.5), (&samples, 0.01), (&negated, 0.5), (&negated, 0.01)] {
            let problem = LinearisedStep {
                rates: &rates,
                samples,
                trust_radius: radius,
                duration: 1.0,
                circulation: 1.0,
                boundary: Boundary::StartAtRest,
                rate_limit: None,
                jerk_limit: None,
            };
            let kept = screened(samples, radius);
            let sides: usize = kept.iter().map(|(_, s)| s.iter().filter(|x| **x).count()).sum();
            assert!(sides < 2 * samples.len(), "radius {radius}: nothing was screened, the test proves nothing");
            let settings = QpSettings::default();
            let a = super::solve_linearised_step(&problem, &settings).unwrap();
            let b =
                super::solve_rows(&problem, &settings, |s, _| s.iter().map(|x| (x, [true, true])).collect()).unwrap();
            assert!(a.status.is_solved() && b.status.is_solved());
            let scale = b.predicted_peak.abs().max(1.0);
            assert!(
                (a.predicted_peak - b.predicted_peak).abs() <= 1e-6 * scale,
                "radius {radius}: {} vs {}",
                a.predicted_peak,
                b.predicted_peak
            );
        }
    }

    #[test]
    fn runs_of_equal_coefficients_move_to_prefix_sums_and_the_rest_stays() {
        // Trapezoid weights up to node 9 (0.5, 1, …, 1, 0.5) plus a rate term at node 9 and an
        // acceleration pair on nodes 4 and 5, in shuffled order with a repeated index.
        let mut gradient: Vec<(usize, f64)> = (1..9).map(|m| (m, 2.0)).collect();
        gradient.extend([(9, 1.0), (0, 1.0), (5, 3.0), (4, -3.0), (9, 0.25)]);
        gradient.reverse();
        let row = SampleRow::new(&gradient, 1.0, 0.5);
        // 2 on nodes 1..=3 and 6..=8 (runs of three: below MIN_RUN, kept); 1 on node 0; 1.25 on 9.
        let on_step: Vec<(usize, f64)> =
            vec![(0, 1.0), (1, 2.0), (2, 2.0), (3, 2.0), (4, -1.0), (5, 5.0), (6, 2.0), (7, 2.0), (8, 2.0), (9, 1.25)];
        assert_eq!(row.on_step, on_step);
        assert!(row.on_prefix.is_empty());

        let long: Vec<(usize, f64)> = (3..40).map(|m| (m, 2.0)).chain([(41, 7.0)]).collect();
        let row = SampleRow::new(&long, 0.5, 0.25);
        // 1.0 on nodes 3..=39 = (1.0/0.25)(S_39 − S_2); node 41 alone.
        assert_eq!(row.on_prefix, vec![(39, 4.0), (2, -4.0)]);
        assert_eq!(row.on_step, vec![(41, 3.5)]);
    }
}
