//! The successive-convexification loop: linearise, solve the convex subproblem in a trust
//! region, accept by a merit function evaluated by the exact engine, update the radius.
//!
//! The merit function of an iterate `c` is `φ(c) = J(c)/J_u + λ |e(c)|₁` (plus the bend limit's and,
//! at a fixed fall, the motor limits' elastic penalties) with the objective `J` (sampled peak,
//! energy, or for `min-time` the largest stretch squared), its current value `J_u` as unit and the orientation error `e` from
//! the Magnus integration ([`super::sensitivity::final_orientation`]). The subproblem's optimum
//! `δ` predicts `φ(c) − L(δ)`; the trial `c + δ` is evaluated anew (torques by Newton–Euler, the
//! orientation by the integrator, never by the linear model) and with
//! `ρ = (φ(c) − φ(c + δ)) / (φ(c) − L(δ))` the step is accepted when `ρ ≥ 0.1`; the radius is
//! halved (to half the step taken) when `ρ < 0.1` and doubled when `ρ > 0.75` with the step on
//! the trust boundary (Malyuta et al. 2021, §4.3; Nocedal & Wright, Alg. 4.1).
//!
//! A stage ends **converged** when the predicted decrease is below `optimality` with `|e|₁`
//! below the loop's feasibility threshold (for a step the trust region cut short, below
//! `optimality` times the radius in radians, up to one: such a step predicts in proportion to
//! the radius, and a radius set small must not pass for an optimum); when it is below with the
//! error still above, the penalty `λ` grows tenfold, up to `10⁶` times its setting, and then the
//! stage ends **infeasible**. It ends **stalled** when the radius falls below `10⁻¹⁰` rad. A peak
//! stage also ends converged when its last five accepted steps, between iterates on the
//! constraint and within the limits, lowered the peak by less than `3·10⁻⁵` of itself with a mean
//! ratio below 0.75 (the reason says so): there the linear model
//! of a minimax optimum that is not a vertex keeps predicting a decrease that the torques'
//! curvature takes back, and the stage crawled for 50 iterations at radii near `10⁻⁴` rad for
//! `10⁻⁵` of the peak (Kane and Scher's cat; the paper's cat converges before the test applies).
//!
//! Each trial point is first returned to the constraint manifold `e = 0` by at most three
//! minimum-norm Newton steps `δ = −Jᵀ(JJᵀ)⁻¹e` (a second-order correction, Nocedal & Wright
//! §15.6): without it the curvature of `e` makes every long step look bad to an exact penalty
//! and the trust region collapses (measured on the paper's problem: the violation stalled near
//! 5e-4 rad for 150 iterations). The final phase drives `|e|` to round-off with minimum-norm Newton steps
//! `δ = −Jᵀ(JJᵀ)⁻¹e` (the objective moves by `O(|e|)`, far below its tolerance) and re-measures the
//! flip with [`crate::engines::exact::flip`]; if the engine's adaptive answer disagrees with the loop's
//! fixed-step integration by more than the tolerance, the loop's steps per span double and the
//! Newton phase repeats.
//!
//! ## References
//! - D. Malyuta et al., *Convex optimization for trajectory generation*, IEEE Control Systems
//!   Magazine 42 (2022) 40–113 (arXiv:2106.09125), §4 (SCvx);
//! - J. Nocedal, S. J. Wright, *Numerical Optimization* (2nd ed., 2006), ch. 4 and §15.5.

use nalgebra::{UnitQuaternion, Vector3};

use super::cat::WholeCat;
use super::curvature::{Curvature, Form, Point};
use super::limits::{largest, limit_rows, LimitRow, RowForm};
use super::reach::Reach;
use super::sensitivity::{
    bend_samples, final_orientation, gauss_grid, torque_samples, uniform_grid, BendSample, FinalOrientation, Layout,
    TorqueSample,
};
use super::settings::{Objective, WholeError, WholeSettings};
use super::solution::{IterationLog, WholeStatus};
use super::spin::{spin_pass, Lift};
use super::spline::BSpline;
use super::subproblem::{Subproblem, BEND_PENALTY, LIMIT_PENALTY};
use crate::model::motor::Motors;
use crate::optimize::conic::QpSettings;

/// `|e|₁` below which the loop counts an iterate as flipping (the Newton phase finishes the job).
const LOOP_FEASIBILITY: f64 = 1e-7;
/// `|e|₁` below which the subproblem imposes the linearised orientation constraint exactly, rad.
const HARD_CONSTRAINT: f64 = 1e-9;
/// Newton steps that return each trial point to the constraint (module docs).
const PROJECTION_STEPS: usize = 3;
/// An energy step whose merit fell by more than this multiple of the predicted decrease is
/// extended: doubled along `δ` while the merit keeps falling, within the trust radius. The model's
/// curvature (Gauss–Newton plus [`super::curvature`]) is positive definite; along a flat valley of
/// the true merit it overestimates, the actual decrease exceeds the predicted one, and without
/// the extension the steps stay short (measured on a fat cat, r/l = 0.25, energy: ratios of
/// 1.5–1.6 over a start's last dozen iterations; with a 1000 times smaller `B₀`, 2.00 for 160
/// iterations at the largest radius, still descending at the iteration limit).
const EXTEND_RATIO: f64 = 1.5;
/// The trust radius below which a stage has stalled, rad.
const MIN_RADIUS: f64 = 1e-10;
/// The share of the trust radius from which a step counts as cut short by it.
const BOUNDARY: f64 = 0.999;

/// One whole-manoeuvre problem: the cat, the settings and the target orientation.
#[derive(Clone, Debug)]
pub struct ScvxProblem<'a> {
    /// The cat (the paper's, another two-motor model, or one of more motors).
    pub cat: &'a WholeCat,
    /// The settings.
    pub settings: &'a WholeSettings,
    /// The joint motors (ideal: no limit rows).
    pub motors: &'a Motors,
    /// A's final orientation required; none leaves it free (a test problem with a known answer).
    pub target: Option<UnitQuaternion<f64>>,
    /// Clarabel's settings for every subproblem.
    pub qp: QpSettings,
    /// Total angular momentum at release, world frame, N·m·s (zero: the Magnus model of
    /// [`super::sensitivity`]; otherwise the lifted spinning model of [`super::spin`]).
    pub spin: Vector3<f64>,
}

/// An iterate and everything evaluated at it.
#[derive(Clone, Debug)]
pub(crate) struct Iterate {
    pub(crate) spline: BSpline,
    values: Vec<f64>,
    /// Each variable's share of the trust radius ([`Layout::trust_scales`]).
    trust_scales: Vec<f64>,
    orientation: Option<FinalOrientation>,
    samples: Vec<TorqueSample>,
    bend: Vec<BendSample>,
    pub(crate) objective: f64,
    peak: f64,
    pub(crate) violation: f64,
    /// `max_k max(0, cos β_max − cos β_k)`.
    bend_violation: f64,
    /// The motor-limit rows on the peak grid ([`super::limits`]: `k²` for `min-time`, `ρ`
    /// otherwise); empty with ideal motors.
    limits: Vec<LimitRow>,
    /// The largest `k²` or `ρ` of `limits`.
    pub(crate) limit_max: f64,
    /// With spin, the lifted attitude unknowns that the samples' gradients refer to.
    lift: Option<Lift>,
}

impl Iterate {
    /// How far the largest `ρ` exceeds `bound` (zero within, or without a bound).
    fn limit_violation(&self, bound: Option<f64>) -> f64 {
        bound.map_or(0.0, |b| (self.limit_max - b).max(0.0))
    }
}

/// How a stage ended: its last iterate's spline, status and why.
#[derive(Clone, Debug)]
pub(crate) struct StageEnd {
    pub(crate) spline: BSpline,
    pub(crate) status: WholeStatus,
    pub(crate) reason: String,
}

impl ScvxProblem<'_> {
    fn layout(&self) -> Layout {
        Layout { control_points: self.settings.control_points, fixed: self.settings.fixed(), joints: self.cat.joints() }
    }

    /// Evaluates torques (and their gradients), bend and orientation at `spline`.
    pub(crate) fn evaluate(&self, spline: BSpline, objective: Objective, steps: usize) -> Iterate {
        self.evaluate_known(spline, None, objective, steps)
    }

    /// [`Self::evaluate`] with the final orientation at `spline` already known (`known`, from
    /// [`final_orientation`] at these `steps` and the target; a projection computes it last):
    /// without spin it is taken as it is, not integrated again (the same numbers bit for bit).
    fn evaluate_known(
        &self,
        spline: BSpline,
        known: Option<FinalOrientation>,
        objective: Objective,
        steps: usize,
    ) -> Iterate {
        let layout = self.layout();
        let uniform = uniform_grid(&spline, self.settings.samples_per_span);
        let grid = match objective {
            Objective::Peak | Objective::MinTime => uniform.clone(),
            Objective::Energy => gauss_grid(&spline, 2),
        };
        let (samples, spun, lift) = if self.spins() {
            let target = self.target.unwrap_or_else(UnitQuaternion::identity);
            let pass = spin_pass(self.cat, &spline, &layout, steps, &target, &self.spin, &grid);
            (pass.samples, self.target.map(|_| pass.orientation), Some(pass.lift))
        } else {
            (torque_samples(self.cat, &spline, &layout, &grid), None, None)
        };
        let limits = match objective {
            _ if self.motors.is_ideal() => Vec::new(),
            Objective::MinTime => limit_rows(&samples, self.motors, RowForm::Stretch),
            Objective::Peak => limit_rows(&samples, self.motors, RowForm::Ratio),
            Objective::Energy => {
                limit_rows(&torque_samples(self.cat, &spline, &layout, &uniform), self.motors, RowForm::Ratio)
            }
        };
        let limit_max = largest(&limits);
        let bend = if self.settings.min_angle_deg.is_some() {
            bend_samples(self.cat, &spline, &layout, &uniform)
        } else {
            Vec::new()
        };
        let orientation = match spun {
            Some(o) => Some(o),
            None => known.or_else(|| self.target.map(|t| final_orientation(self.cat, &spline, &layout, steps, &t))),
        };
        let peak = samples.iter().flat_map(|s| s.tau.iter().map(|t| t.abs())).fold(0.0, f64::max);
        let value = match objective {
            Objective::Peak => peak,
            Objective::Energy => samples.iter().map(|s| s.weight * s.tau.iter().map(|t| t.powi(2)).sum::<f64>()).sum(),
            Objective::MinTime => limit_max,
        };
        let violation = orientation.as_ref().map_or(0.0, |o| o.error.abs().sum());
        let floor = self.settings.min_angle_deg.map(|a| (std::f64::consts::PI - a.to_radians()).cos());
        let bend_violation = floor.map_or(0.0, |f| bend.iter().map(|b| f - b.cos_bend).fold(0.0, f64::max));
        Iterate {
            values: layout.values(&spline),
            trust_scales: layout.trust_scales(&spline),
            spline,
            orientation,
            samples,
            bend,
            objective: value,
            peak,
            violation,
            bend_violation,
            limits,
            limit_max,
            lift,
        }
    }

    /// Whether the cat is released with spin.
    pub(crate) fn spins(&self) -> bool {
        self.spin.norm_squared() > 0.0
    }

    /// The final orientation and its Jacobian by the model of the release ([`final_orientation`]
    /// at zero momentum, [`spin_pass`] with spin).
    fn orientation(
        &self,
        spline: &BSpline,
        layout: &Layout,
        steps: usize,
        target: &UnitQuaternion<f64>,
    ) -> FinalOrientation {
        if self.spins() {
            spin_pass(self.cat, spline, layout, steps, target, &self.spin, &[]).orientation
        } else {
            final_orientation(self.cat, spline, layout, steps, target)
        }
    }

    /// Runs one stage (module docs) from `it` until it ends or the log holds `budget` entries;
    /// with `bound`, every motor-limit ratio is held to `ρ ≤ bound` ([`super::limits`]); with
    /// `enough`, it also ends (converged) at the first iterate on the orientation constraint whose
    /// objective is at most `enough` (a feasibility phase).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn stage(
        &self,
        mut it: Iterate,
        objective: Objective,
        bound: Option<f64>,
        enough: Option<f64>,
        optimality: f64,
        budget: usize,
        steps: usize,
        log: &mut Vec<IterationLog>,
    ) -> Result<StageEnd, WholeError> {
        let layout = self.layout();
        let s = self.settings;
        let mut radius = s.trust_radius_deg.to_radians();
        let max_radius = 4.0 * radius;
        let mut penalty = s.penalty;
        // A floor for the unit so that an objective driven to zero stays a number.
        let floor = 1e-12 * it.objective.max(1e-300);
        let bend_floor = s.min_angle_deg.map(|a| (std::f64::consts::PI - a.to_radians()).cos());
        let joint_limits = self.variable_limits(&layout);
        let end = |iterate: Iterate, status, reason: String| Ok(StageEnd { spline: iterate.spline, status, reason });
        // The curvature the energy's and the peak's models leave out, learnt from the accepted
        // steps ([`super::curvature`]).
        let mut curvature = Curvature::new(match objective {
            Objective::Peak => Form::Scalar,
            _ => Form::Bfgs,
        });
        // The objective at each accepted iterate of the stage and the ratio of the step that
        // reached it (the peak's progress test).
        let mut accepted: Vec<(f64, f64)> = Vec::new();
        loop {
            if enough.is_some_and(|e| it.objective <= e) && it.violation <= LOOP_FEASIBILITY {
                let reason = format!("objective {:.6} within {:.6}", it.objective, enough.unwrap_or(0.0));
                return end(it, WholeStatus::Converged, reason);
            }
            if log.len() >= budget {
                return end(it, WholeStatus::MaxIterations, format!("{budget} iterations used"));
            }
            let scale = it.objective.max(floor);
            let sub = Subproblem {
                objective,
                samples: &it.samples,
                scale,
                orientation: it.orientation.as_ref().map(|o| (&o.error, &o.jacobian)),
                hard: it.violation <= HARD_CONSTRAINT,
                penalty,
                trust_radius: radius,
                trust_scales: &it.trust_scales,
                values: &it.values,
                joint_limits: &joint_limits,
                bend: bend_floor.map(|f| (it.bend.as_slice(), f)),
                limits: &it.limits,
                limit_bound: bound,
                curvature: curvature.estimate(),
                lift: it.lift.as_ref(),
            };
            let step = sub.solve(&self.qp)?;
            let merit = |x: &Iterate| {
                x.objective / scale
                    + penalty * x.violation
                    + BEND_PENALTY * x.bend_violation
                    + LIMIT_PENALTY * x.limit_violation(bound)
            };
            let now = merit(&it);
            let mut entry = IterationLog {
                iteration: log.len() + 1,
                objective,
                value: it.objective,
                peak_nm: it.peak,
                violation: it.violation,
                trust_radius: Some(radius),
                barrier: None,
                subproblem: Some(step.status),
                ratio: None,
                accepted: false,
            };
            if !step.status.is_solved() {
                log.push(entry);
                radius *= 0.25;
                if radius < MIN_RADIUS {
                    return end(it, WholeStatus::Stalled, format!("subproblems kept failing ({:?})", step.status));
                }
                continue;
            }
            let predicted = now - step.model;
            if predicted < -optimality {
                // The model cannot rise above its value at δ = 0: Clarabel's answer is off.
                log.push(entry);
                radius *= 0.25;
                if radius < MIN_RADIUS {
                    return end(
                        it,
                        WholeStatus::Stalled,
                        format!("subproblem optimum above the model at δ = 0 by {:.1e}", -predicted),
                    );
                }
                continue;
            }
            let length = step.step.iter().zip(&it.trust_scales).fold(0.0f64, |m, (d, s)| m.max(d.abs() / s));
            // A step the trust region cuts short predicts a decrease in proportion to the radius:
            // there the test is on the decrease per radian of radius (up to one), so that a radius
            // set small does not pass for an optimum (a review's trust_radius_deg = 1e-6 ended
            // "converged" at 130 times the optimum); an interior step is the model's own optimum.
            let stationary = if length >= BOUNDARY * radius { optimality * radius.min(1.0) } else { optimality };
            if predicted <= stationary {
                log.push(entry);
                let limit_violation = it.limit_violation(bound);
                if it.violation <= LOOP_FEASIBILITY
                    && it.bend_violation <= LOOP_FEASIBILITY
                    && limit_violation <= LOOP_FEASIBILITY
                {
                    return end(
                        it,
                        WholeStatus::Converged,
                        if stationary < optimality {
                            format!("predicted decrease {predicted:.1e} on the trust boundary, within the optimality tolerance {optimality:.0e} per radian of the radius ({stationary:.1e})")
                        } else {
                            format!(
                                "predicted decrease {predicted:.1e}, within the optimality tolerance {optimality:.0e}"
                            )
                        },
                    );
                }
                if penalty < 1e6 * s.penalty {
                    penalty *= 10.0;
                    // A new merit: the progress test starts again.
                    accepted.clear();
                    continue;
                }
                let reason = if limit_violation > LOOP_FEASIBILITY {
                    format!(
                        "no flip within the motors in this fall: a motor limit is still used at {:.2} % (|e|₁ = {:.3e} rad); objective \"min-time\" finds the least fall time",
                        100.0 * it.limit_max,
                        it.violation
                    )
                } else {
                    format!(
                        "stationary with |e|₁ = {:.3e} rad and the bend limit exceeded by {:.3e} (cosine) at penalty {penalty:.1e}",
                        it.violation, it.bend_violation
                    )
                };
                return end(it, WholeStatus::Infeasible, reason);
            }
            let mut trial = self.trial(layout.moved(&it.spline, &step.step), objective, steps);
            let ratio = (now - merit(&trial)) / predicted;
            if objective == Objective::Energy && ratio > EXTEND_RATIO {
                let mut factor = 2.0;
                while factor * length <= radius {
                    let longer: Vec<f64> = step.step.iter().map(|d| d * factor).collect();
                    let candidate = self.trial(layout.moved(&it.spline, &longer), objective, steps);
                    if merit(&candidate) >= merit(&trial) {
                        break;
                    }
                    trial = candidate;
                    factor *= 2.0;
                }
            }
            entry.ratio = Some(ratio);
            entry.accepted = ratio >= 0.1;
            log.push(entry);
            if ratio < 0.1 {
                radius = 0.5 * length.min(radius);
            } else if ratio > 0.75 && length > 0.5 * radius {
                radius = (2.0 * radius).min(max_radius);
            }
            if ratio >= 0.1 {
                // The curvature estimate needs dense gradients; with spin they are lifted.
                if it.lift.is_none() {
                    if let (Some(from), Some(to)) = (it.orientation.as_ref(), trial.orientation.as_ref()) {
                        let from = Point { values: &it.values, samples: &it.samples, jacobian: &from.jacobian };
                        let to = Point { values: &trial.values, samples: &trial.samples, jacobian: &to.jacobian };
                        match (objective, step.multipliers) {
                            (Objective::Energy, _) => curvature.update(from, to),
                            (Objective::Peak, Some(lambda)) => {
                                curvature.update_with(from, to, &lambda, &step.torque_multipliers)
                            }
                            _ => {}
                        }
                    }
                }
                it = trial;
                // The progress test looks at feasible iterates only: an infeasible one starts it again.
                let feasible = it.violation <= LOOP_FEASIBILITY
                    && it.bend_violation <= LOOP_FEASIBILITY
                    && it.limit_violation(bound) <= LOOP_FEASIBILITY;
                if feasible {
                    accepted.push((it.objective, ratio));
                    if let Some(reason) = crawling(objective, &accepted) {
                        return end(it, WholeStatus::Converged, reason);
                    }
                } else {
                    accepted.clear();
                }
            }
            if radius < MIN_RADIUS {
                let reason = format!("trust radius below {MIN_RADIUS:.0e} rad (last ratio {ratio:.2e})");
                return end(it, WholeStatus::Stalled, reason);
            }
        }
    }

    /// Each variable's limit on its control point, rad ([`WholeCat::control_limits`]: variable
    /// `v` is coordinate `v / free`'s).
    fn variable_limits(&self, layout: &Layout) -> Vec<Option<f64>> {
        let coordinates = self.cat.control_limits(self.settings.joint_limit_deg);
        (0..layout.variables()).map(|v| coordinates[v / layout.free()]).collect()
    }

    /// Every control point within its coordinate's limit ([`WholeCat::control_limits`]).
    pub(crate) fn clamp_to_limits(&self, spline: &mut BSpline) {
        for (curve, limit) in spline.coefficients.iter_mut().zip(self.cat.control_limits(self.settings.joint_limit_deg))
        {
            if let Some(limit) = limit {
                for c in curve.iter_mut() {
                    *c = c.clamp(-limit, limit);
                }
            }
        }
    }

    /// Minimum-norm Newton steps on the orientation error until `max |e_i| ≤ 1e-13` rad (at most
    /// `most`, each kept only if it lowers `|e|`); returns the spline and the steps kept. A control
    /// point on its limit (within 1e-12 rad) is held there and the steps move the others, each
    /// clamped to its limit: every step kept is within the limits, so no clamp undoes part of
    /// the correction afterwards (as one did on a cat with a tail and legs, its legs folded to
    /// their limit for much of the fall: the flip missed by 1.7e-10 rad).
    pub(crate) fn polish(&self, spline: BSpline, steps: usize, most: usize) -> (BSpline, usize) {
        let (spline, kept, _) = self.polish_keeping(spline, steps, most);
        (spline, kept)
    }

    /// A trial point `moved` returned to the constraint ([`PROJECTION_STEPS`] Newton steps, module
    /// docs) and evaluated there, with the orientation the last projection step computed.
    fn trial(&self, moved: BSpline, objective: Objective, steps: usize) -> Iterate {
        let (spline, _, orientation) = self.polish_keeping(moved, steps, PROJECTION_STEPS);
        let known = orientation.filter(|_| !self.spins());
        self.evaluate_known(spline, known, objective, steps)
    }

    /// [`Self::polish`], also returning the orientation at the spline it returns (none without a
    /// target).
    fn polish_keeping(&self, spline: BSpline, steps: usize, most: usize) -> (BSpline, usize, Option<FinalOrientation>) {
        let Some(target) = self.target else { return (spline, 0, None) };
        let layout = self.layout();
        let limits = self.variable_limits(&layout);
        let mut best = (self.orientation(&spline, &layout, steps, &target), spline);
        for k in 0..most {
            let (o, spline) = &best;
            if o.error.amax() <= 1e-13 {
                return (best.1, k, Some(best.0));
            }
            // The Jacobian without the columns of the control points held on their limits.
            let mut j = o.jacobian.clone();
            for (v, (limit, c)) in limits.iter().zip(layout.values(spline)).enumerate() {
                if limit.is_some_and(|l| c.abs() >= l - 1e-12) {
                    j.column_mut(v).fill(0.0);
                }
            }
            let j = &j;
            let Some(y) = Reach::of(j).newton_multipliers(j, &o.error) else { return (best.1, k, Some(best.0)) };
            let step: Vec<f64> =
                (0..layout.variables()).map(|v| -(0..3).map(|a| j[(a, v)] * y[a]).sum::<f64>()).collect();
            let mut next = layout.moved(spline, &step);
            self.clamp_to_limits(&mut next);
            let at = self.orientation(&next, &layout, steps, &target);
            if at.error.norm() >= o.error.norm() {
                return (best.1, k, Some(best.0));
            }
            best = (at, next);
        }
        (best.1, most, Some(best.0))
    }
}

/// Accepted steps over which the peak's progress is judged.
const PROGRESS_STEPS: usize = 5;
/// The peak's least relative progress over [`PROGRESS_STEPS`] accepted steps.
const PROGRESS: f64 = 3e-5;
/// The mean ratio of those steps below which the model is taking back its predictions (the
/// ratio above which the radius may grow).
const MODEL_FAILS: f64 = 0.75;

/// Why the peak's stage should end although its model still predicts a decrease: over its last
/// [`PROGRESS_STEPS`] accepted steps between feasible iterates (`accepted`, their peaks and the
/// ratios of the steps, at one penalty) the peak fell, but by less than [`PROGRESS`] of itself
/// (a peak that rose, as when a tightened motor bound is being met, is not a stall), with a mean
/// ratio below [`MODEL_FAILS`] (steps the model predicts well are no crawl, only short: a review's
/// trust radius of 1e-6° ended "converged" at 130 times the optimum). Near a
/// minimax optimum that is not a vertex the linear model keeps predicting a decrease that the
/// torques' curvature takes back (ratios of 0.1–0.3 at radii near 1e-4 rad): measured on Kane and
/// Scher's cat, 50 more iterations would lower the peak by 1e-5 of itself. None for the other
/// objectives, or while the peak still moves.
fn crawling(objective: Objective, accepted: &[(f64, f64)]) -> Option<String> {
    if objective != Objective::Peak || accepted.len() <= PROGRESS_STEPS {
        return None;
    }
    let last = &accepted[accepted.len() - 1 - PROGRESS_STEPS..];
    let (then, now) = (last[0].0, last[PROGRESS_STEPS].0);
    let progress = (then - now) / now.abs().max(f64::MIN_POSITIVE);
    let ratio = last[1..].iter().map(|a| a.1).sum::<f64>() / PROGRESS_STEPS as f64;
    ((0.0..PROGRESS).contains(&progress) && ratio < MODEL_FAILS).then(|| {
        format!(
            "the peak fell by {progress:.1e} of itself over the last {PROGRESS_STEPS} accepted steps (below {PROGRESS:.0e}): the linear model's predicted decrease is taken back by the torques' curvature"
        )
    })
}

#[cfg(test)]
mod tests;
