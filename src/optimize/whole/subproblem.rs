//! The convex subproblem of one successive-convexification step, solved by Clarabel (the
//! energy's with a dense curvature estimate first by its KKT system, below).
//!
//! Variables `x = (δ, t, s)`: the step `δ` on the free control points (rad), the epigraph bound
//! `t` of the peak objective and the bounds `s ∈ ℝ³` on the linearised orientation error (the
//! virtual control `ν = e + Jδ`, penalised in ℓ1). With `τ̂ = τ/J_u`, `Ĝ = G/J_u` scaled by the
//! current objective `J_u`:
//!
//! $$ \text{peak: } \min\; t + ½ δᵀBδ/J_u + λ \textstyle\sum_i s_i \quad
//!    |τ̂_k + Ĝ_k δ| ≤ t \;\;\forall k \text{ and both joints}, $$
//! $$ \text{energy: } \min\; \textstyle\sum_k w_k |τ_k + G_k δ|^2 / J_u + ½ δᵀBδ/J_u + λ \sum_i s_i, $$
//! $$ \text{min-time: } \min\; t + λ \textstyle\sum_i s_i \quad
//!    (k^2_r + ∇k^2_r δ)/J_u ≤ t \;\;\forall \text{motor-limit rows } r \;([`super::limits`]), $$
//!
//! with `B` the curvature estimate ([`super::curvature`]; none before the first pair), all
//! subject to `|e_i + J_i δ| ≤ s_i` (or, for an iterate already on the constraint,
//! `e + Jδ = 0` exactly and no `s`: an exact penalty weighted far above the multiplier turns
//! Clarabel's residuals into noise of the model's size), the trust box `|δ_v| ≤ Δ s_v` (`s_v = 1` on
//! uniform knots, smaller where the knots are refined), the joint limits on the
//! control points `|c + δ| ≤ q_max` (each coordinate's) and the linearised bend limit
//! `cos β_k + g_kᵀ δ + σ ≥ cos β_max` on every sample, with one elastic variable `σ ≥ 0`
//! weighted by [`BEND_PENALTY`] (so that a start bent beyond the limit can come back to it), and at
//! a fixed fall with motor limits the rows `ρ_r + ∇ρ_r δ − σ_m ≤ b` with one elastic `σ_m ≥ 0`
//! weighted by [`LIMIT_PENALTY`]. The box makes every subproblem feasible
//! (`δ = 0` with `s = |e|` is a point when the current iterate meets the limits), so Clarabel's
//! status is a statement about numerics, not about the physics.
//!
//! The energy's model with its dense curvature estimate makes `P` dense, which Clarabel factors
//! at each of its interior-point iterations (on the legged cat of `problems/legs.toml`, 464
//! variables: 110 ms a solve, and 8 of 20 solved again with iterative refinement, 210 ms). With
//! the orientation imposed exactly and neither a bend nor a motor limit, its only inequalities are
//! the trust box and the joint limits, bounds on single variables, and the step is first sought
//! by its KKT system on an active set of those bounds (`Assembly::solve_by_active_set`, exact
//! when it answers); Clarabel solves it otherwise.

use nalgebra::{DMatrix, Vector3};

use super::curvature::Estimate;
use super::limits::{LimitRow, ROW_FLOOR};
use super::reach::Reach;
use super::sensitivity::{BendSample, TorqueSample};
use super::settings::Objective;
use super::spin::Lift;
use crate::optimize::conic::{active_sides, Assembly, ConicError, QpSettings, QpStatus};

/// Weight of the bend limit's elastic variable, relative to the current objective, per unit of
/// `cos β`. Far above the limit's multiplier (of order one in these units) yet not so far that the
/// constraint's curvature dominates every ratio test: with the orientation's `10⁴` the trust
/// radius stayed below `10⁻³` rad for 100 iterations on the paper's problem at a 40° limit.
pub const BEND_PENALTY: f64 = 100.0;

/// Weight of the motor limits' elastic variable, relative to the current objective, per unit of
/// `k²` ([`super::limits`]); chosen as [`BEND_PENALTY`] is: the limits' multipliers are of order
/// one in these units (a torque limit active at the peak has multiplier `τ_max/J_u ≈ 1`).
pub const LIMIT_PENALTY: f64 = 100.0;

/// The data of one subproblem.
#[derive(Clone, Copy, Debug)]
pub struct Subproblem<'a> {
    /// What is minimised.
    pub objective: Objective,
    /// Torques and gradients on the grid.
    pub samples: &'a [TorqueSample],
    /// The objective's unit `J_u` (current objective), N·m or N²·m²·s.
    pub scale: f64,
    /// The orientation error and its Jacobian; none when the final orientation is free.
    pub orientation: Option<(&'a Vector3<f64>, &'a DMatrix<f64>)>,
    /// Whether the linearised orientation constraint is imposed exactly, `e + Jδ = 0`, rather
    /// than penalised (for iterates already on the constraint, module docs).
    pub hard: bool,
    /// `λ`, per radian.
    pub penalty: f64,
    /// `Δ`, rad.
    pub trust_radius: f64,
    /// Each variable's share of the trust radius, in `(0, 1]`: its box is `|δ_v| ≤ Δ s_v`
    /// ([`super::sensitivity::Layout::trust_scales`]).
    pub trust_scales: &'a [f64],
    /// Current free control points, rad.
    pub values: &'a [f64],
    /// Each variable's limit `|c + δ| ≤ q_max`, rad (its coordinate's,
    /// [`super::WholeCat::control_limits`]); none where absent.
    pub joint_limits: &'a [Option<f64>],
    /// Bend samples and `cos β_max`; none without a bend limit.
    pub bend: Option<(&'a [BendSample], f64)>,
    /// The motor-limit rows ([`super::limits`]): `k²`, the objective of `min-time`, or `ρ`,
    /// constraints `ρ ≤ limit_bound` otherwise (none without a bound).
    pub limits: &'a [LimitRow],
    /// The bound on every `ρ` row at a fixed fall time; none leaves the rows out (or, for
    /// `min-time`, makes them the objective).
    pub limit_bound: Option<f64>,
    /// For the energy and the peak: the estimate `B` of the curvature that the model leaves out
    /// ([`super::curvature`]: the orientation constraint's for the energy, the Lagrangian's
    /// for the peak), in the objective's units per rad²; the model gains `½ δᵀBδ / J_u`.
    pub curvature: Option<&'a Estimate>,
    /// With spin, the lifted attitude unknowns ([`super::spin`]): gradient entries from
    /// `values.len()` on are theirs, tied to `δ` by the transitions' equality rows.
    pub lift: Option<&'a Lift>,
}

/// The subproblem's answer.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// How Clarabel ended.
    pub status: QpStatus,
    /// `δ`, rad.
    pub step: Vec<f64>,
    /// The convex model of the merit function at `δ` (normalised objective, with `½δᵀBδ/J_u`,
    /// + `λ Σ|e + Jδ|` and the elastic penalties).
    pub model: f64,
    /// The multipliers `λ` of the hard orientation constraint `e + Jδ = 0` at the step, in the
    /// objective's own units per radian (N·m or N²·m²·s): `ℒ = J + λᵀe`. None when the constraint
    /// is penalised rather than imposed, or absent.
    pub multipliers: Option<Vector3<f64>>,
    /// The peak's multipliers of its torque rows `±τ_kj ≤ t`, as `(sample, joint, ±z)`: the
    /// Lagrangian's gradient is `Σ ±z ∇τ_kj + Jᵀλ` (empty for the other objectives).
    pub torque_multipliers: Vec<(usize, usize, f64)>,
}

impl Subproblem<'_> {
    /// The model `L(δ)` of the merit function (module docs), evaluated directly.
    pub fn model(&self, step: &[f64]) -> f64 {
        let extended = self.lift.map(|l| l.extend(step));
        let full = extended.as_deref().unwrap_or(step);
        let lin_full = |t: f64, g: &[(usize, f64)]| t + g.iter().map(|&(v, c)| c * full[v]).sum::<f64>();
        let lin = |t: f64, g: &[(usize, f64)]| t + g.iter().map(|&(v, c)| c * step[v]).sum::<f64>();
        let objective = match self.objective {
            Objective::Peak => {
                self.samples
                    .iter()
                    .flat_map(|s| s.tau.iter().zip(&s.gradient).map(|(&t, g)| lin_full(t, g).abs()))
                    .fold(0.0, f64::max)
                    / self.scale
            }
            Objective::Energy => {
                self.samples
                    .iter()
                    .map(|s| {
                        s.weight * s.tau.iter().zip(&s.gradient).map(|(&t, g)| lin_full(t, g).powi(2)).sum::<f64>()
                    })
                    .sum::<f64>()
                    / self.scale
            }
            Objective::MinTime => {
                self.limit_rows().map(|r| lin_full(r.constant, &r.gradient)).fold(0.0, f64::max) / self.scale
            }
        };
        let limits = self
            .constraint_bound()
            .map_or(0.0, |b| self.limit_rows().map(|r| lin_full(r.constant, &r.gradient) - b).fold(0.0, f64::max));
        let bend = self.bend.map_or(0.0, |(samples, floor)| {
            samples.iter().map(|b| floor - lin(b.cos_bend, &b.gradient)).fold(0.0, f64::max)
        });
        let violation = self.orientation.filter(|_| !self.hard).map_or(0.0, |(e, jac)| {
            (0..3).map(|i| (e[i] + (0..step.len()).map(|v| jac[(i, v)] * step[v]).sum::<f64>()).abs()).sum()
        });
        let curvature = self
            .curvature_estimate()
            .map_or(0.0, |b| 0.5 * b.quadratic_form(&nalgebra::DVector::from_column_slice(step)) / self.scale);
        objective + curvature + self.penalty * violation + BEND_PENALTY * bend + LIMIT_PENALTY * limits
    }

    /// The curvature estimate, which the energy's and the peak's models take (not `min-time`'s,
    /// whose rows are the motors' stretch).
    fn curvature_estimate(&self) -> Option<&Estimate> {
        self.curvature.filter(|_| matches!(self.objective, Objective::Energy | Objective::Peak))
    }

    /// The most a row with `gradient` can move within the trust box.
    /// A lifted unknown has no box of its own: a row with one can reach anything (and is kept).
    fn reach(&self, gradient: &[(usize, f64)]) -> f64 {
        let n = self.trust_scales.len();
        if gradient.iter().any(|&(v, _)| v >= n) {
            return f64::INFINITY;
        }
        self.trust_radius * gradient.iter().map(|&(v, c)| c.abs() * self.trust_scales[v]).sum::<f64>()
    }

    /// The bound of the motor-limit constraints, when they are constraints.
    fn constraint_bound(&self) -> Option<f64> {
        self.limit_bound.filter(|_| self.objective != Objective::MinTime)
    }

    /// The limit rows a subproblem keeps: those at or above [`ROW_FLOOR`] of the reference (the
    /// bound, or the largest row for `min-time`).
    fn limit_rows(&self) -> impl Iterator<Item = &LimitRow> + '_ {
        let reference = match self.constraint_bound() {
            Some(b) => b,
            None if self.objective == Objective::MinTime => super::limits::largest(self.limits),
            None => f64::INFINITY,
        };
        self.limits.iter().filter(move |r| !r.floored || r.value >= ROW_FLOOR * reference)
    }

    /// Assembles and solves the subproblem.
    pub fn solve(&self, settings: &QpSettings) -> Result<Step, ConicError> {
        let n = self.values.len();
        let bound = n;
        let slack = n + usize::from(matches!(self.objective, Objective::Peak | Objective::MinTime));
        let soft = self.orientation.filter(|_| !self.hard);
        let elastic = slack + if soft.is_some() { 3 } else { 0 };
        let limit_elastic = elastic + usize::from(self.bend.is_some());
        let lifted = limit_elastic + usize::from(self.constraint_bound().is_some());
        let total = lifted + self.lift.map_or(0, Lift::unknowns);
        // Lifted unknowns (gradient entries from n on) sit after every other variable.
        let at = |v: usize| if v < n { v } else { lifted + v - n };
        let mapped = |g: &[(usize, f64)]| -> Vec<(usize, f64)> { g.iter().map(|&(v, c)| (at(v), c)).collect() };
        let mut asm = Assembly::new(total);
        if let Some(lift) = self.lift {
            for row in lift.rows() {
                asm.equal(mapped(&row), 0.0);
            }
        }
        let unit = 1.0 / self.scale;
        // The peak's torque rows: (inequality index, sample, joint, side).
        let mut torque_rows: Vec<(usize, usize, usize, f64)> = Vec::new();
        match self.objective {
            Objective::Peak => {
                asm.linear_cost(bound, 1.0);
                // Only the sides that can be active (exact; the trust box bounds every step).
                // (sample, joint) of each row.
                let rows: Vec<(usize, usize)> =
                    self.samples.iter().enumerate().flat_map(|(k, s)| (0..s.tau.len()).map(move |j| (k, j))).collect();
                let spans: Vec<(f64, f64)> = rows
                    .iter()
                    .map(|&(k, j)| (self.samples[k].tau[j], self.reach(&self.samples[k].gradient[j])))
                    .collect();
                for (&(k, j), sides) in rows.iter().zip(active_sides(&spans)) {
                    let (g, tau) = (&self.samples[k].gradient[j], self.samples[k].tau[j]);
                    for (sign, _) in [1.0, -1.0].into_iter().zip(sides).filter(|(_, kept)| *kept) {
                        let row = asm.side_at_most(g.iter().map(|&(v, c)| (at(v), c * unit)), tau * unit, sign, bound);
                        torque_rows.push((row, k, j, sign));
                    }
                }
            }
            Objective::Energy => {
                let mut linear = vec![0.0; if self.lift.is_some() { total } else { n }];
                for s in self.samples {
                    for j in 0..s.tau.len() {
                        let w = s.weight * unit;
                        let g = mapped(&s.gradient[j]);
                        asm.square_cost(&g, w);
                        for &(v, g) in &g {
                            linear[v] += 2.0 * w * s.tau[j] * g;
                        }
                    }
                }
                for (v, &c) in linear.iter().enumerate() {
                    asm.linear_cost(v, c);
                }
            }
            Objective::MinTime => {
                asm.linear_cost(bound, 1.0);
                // k² + gᵀδ ≤ t, screened as the peak's rows are: t is at least L = max(k² − r).
                let rows: Vec<&LimitRow> = self.limit_rows().collect();
                let spans: Vec<f64> = rows.iter().map(|r| self.reach(&r.gradient)).collect();
                let floor = rows.iter().zip(&spans).map(|(r, s)| r.constant - s).fold(f64::NEG_INFINITY, f64::max);
                for (r, span) in rows.iter().zip(&spans) {
                    if r.constant + span >= floor {
                        let g = r.gradient.iter().map(|&(v, c)| (at(v), c * unit));
                        asm.sides_at_most(g, r.constant * unit, [true, false], bound);
                    }
                }
            }
        }
        if let Some(b) = self.curvature_estimate() {
            b.add_to(&mut asm, unit);
        }
        if let Some(b) = self.constraint_bound() {
            // k² + gᵀδ − σ ≤ b with σ ≥ 0; a row that cannot reach b within the trust box is left out.
            asm.linear_cost(limit_elastic, LIMIT_PENALTY);
            asm.at_most([(limit_elastic, -1.0)], 0.0);
            for r in self.limit_rows() {
                let span = self.reach(&r.gradient);
                if r.constant + span >= b {
                    asm.at_most(
                        r.gradient.iter().map(|&(v, c)| (at(v), c)).chain([(limit_elastic, -1.0)]),
                        b - r.constant,
                    );
                }
            }
        }
        let sparse =
            |row: Vec<f64>| -> Vec<(usize, f64)> { row.into_iter().enumerate().filter(|e| e.1 != 0.0).collect() };
        // The hard orientation rows: where they start among the equalities, and the directions.
        let mut hard_rows: Option<(usize, Reach)> = None;
        if let Some((e, jac)) = self.orientation {
            if self.hard {
                // Only the directions the controls reach ([`super::reach`]): J's own rows on a
                // cat whose J has full rank.
                let reach = Reach::of(jac);
                let first = asm.equalities();
                for (row, rhs) in reach.constraint_rows(jac, e) {
                    asm.equal(sparse(row), rhs);
                }
                hard_rows = Some((first, reach));
            } else {
                for i in 0..3 {
                    asm.linear_cost(slack + i, self.penalty);
                    asm.abs_at_most(sparse((0..n).map(|v| jac[(i, v)]).collect()).into_iter(), e[i], slack + i);
                }
            }
        }
        for (v, &c) in self.values.iter().enumerate() {
            let radius = self.trust_radius * self.trust_scales[v];
            let (mut lower, mut upper) = (-radius, radius);
            if let Some(limit) = self.joint_limits[v] {
                lower = lower.max(-limit - c);
                upper = upper.min(limit - c).max(lower);
            }
            asm.between(&[(v, 1.0)], lower, upper);
        }
        if let Some((bend, floor)) = self.bend {
            asm.linear_cost(elastic, BEND_PENALTY);
            asm.at_most([(elastic, -1.0)], 0.0);
            for b in bend {
                // cos β + gᵀδ + σ ≥ floor  ⇔  −gᵀδ − σ ≤ cos β − floor
                asm.at_most(b.gradient.iter().map(|&(v, g)| (v, -g)).chain([(elastic, -1.0)]), b.cos_bend - floor);
            }
        }
        let m_eq = asm.equalities();
        // The energy's dense model (module docs): its inequalities are bounds alone when the
        // orientation is imposed exactly (no slack `s`) and no bend or motor limit adds an
        // elastic variable (none of them in `P`).
        let dense =
            self.objective == Objective::Energy && matches!(self.curvature_estimate(), Some(Estimate::Dense(_)));
        let bounds_only = self.orientation.is_none_or(|_| self.hard)
            && self.bend.is_none()
            && self.constraint_bound().is_none()
            && self.lift.is_none();
        let direct = if dense && bounds_only { asm.solve_by_active_set() } else { None };
        let solved = match direct {
            Some(solved) => solved,
            None => asm.solve(settings)?,
        };
        let step = solved.x[..n].to_vec();
        let model = self.model(&step);
        // Clarabel's multipliers belong to the normalised objective (J/J_u): back to J's units.
        let multipliers = hard_rows.map(|(first, reach)| {
            let z = |k: usize| self.scale * solved.duals.get(first + k).copied().unwrap_or(0.0);
            match reach {
                Reach::Full => Vector3::new(z(0), z(1), z(2)),
                Reach::Directions(dirs) => dirs.iter().enumerate().map(|(k, (u, _))| u * z(k)).sum(),
            }
        });
        let torque_multipliers = torque_rows
            .iter()
            .map(|&(row, sample, joint, sign)| {
                (sample, joint, sign * solved.duals.get(m_eq + row).copied().unwrap_or(0.0))
            })
            .filter(|t| t.2 != 0.0)
            .collect();
        Ok(Step { status: solved.status, step, model, multipliers, torque_multipliers })
    }
}
