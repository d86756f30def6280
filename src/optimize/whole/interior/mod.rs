//! The least peak by a primal-dual interior-point method with the torques' exact curvature
//! (issue 22: the whole optimiser beyond two motors).
//!
//! ## Why
//! Successive linear programming ([`super::scvx`]) crawls at a least-peak optimum that is not a
//! vertex of its linearisation: beyond two motors every motor sits at the peak along arcs, the
//! model keeps predicting a decrease that the torques' curvature takes back, and the stage ran its
//! 200 iterations at trust radii near `10⁻³` rad (the spherical joint, the tailed and legged cats:
//! 8–25 s). A method whose steps carry the Lagrangian's curvature, indefinite as it is, ends the
//! crawl: an independent collocation with IPOPT reached the spherical joint's optimum in 51
//! iterations from the same start (`tests/reference/README.md`).
//!
//! ## Problem
//! On the control points `c` of the spline ([`super::spline`], the ends held as the settings say)
//! and the peak bound `t` (in units of the start's sampled peak `τ_u`):
//!
//! $$ \min_{c, t}\; t \quad\text{s.t.}\quad t ∓ τ_{kj}(c)/τ_u ≥ 0 \;\;\forall k, j,\qquad
//!    q_{max} ∓ c_v ≥ 0, \qquad e(c) = 0, $$
//!
//! the torques on the same samples as the trust-region loop's (`samples_per_span` per span), the
//! control points within their coordinate's limit where it has one (the legs' fold,
//! `joint_limit_deg`), and the flip `e = log(R_z(π)ᵀ R(T))` in the directions the controls
//! reach ([`super::reach`]). Each inequality `g_r ≥ 0` gets a slack `s_r > 0` and the barrier
//! `−μ Σ ln s_r`.
//!
//! ## Method
//! After IPOPT's algorithm, in the parts this problem needs (Wächter and Biegler 2006):
//! - Newton steps on the primal-dual equations of the barrier problem ([`newton`]) with the
//!   Lagrangian's Hessian `−Σ z_r ∇²g_r = Σ_kj (z⁺_kj − z⁻_kj) ∇²τ_kj / τ_u` (the rows
//!   `t ∓ τ_kj/τ_u` of each sample's torques, `L = t − λᵀe − zᵀ(g − s)`), the torques' curvature
//!   taken exactly sample by sample ([`curvature`]) where it was last made (made again once a
//!   control point has moved [`CURVATURE_KEPT`] from there) and weighed with the iteration's
//!   own multipliers, regularised until positive definite. The
//!   flip's curvature is left out: with it (by finite differences of the flip's Jacobian, a
//!   second a step) the spherical joint took as many iterations.
//! - Steps kept within the slacks' bounds by the fraction to the boundary `τ = max(0.99, 1 − μ)`
//!   and judged by a filter ([`filter`]), with up to four second-order corrections of the
//!   constraint residuals when the first trial is rejected; the multipliers kept within
//!   `[μ/(10¹⁰ s), 10¹⁰ μ/s]`.
//! - `μ` from `10⁻⁴` (`10⁻⁶` for a refinement, which starts at an optimum: [`WARM_BARRIER`]),
//!   divided by ten down to `ε/10` whenever the barrier problem's error is below `100 μ`
//!   ([`BARRIER_DECREASE`], [`BARRIER_SOLVED`]).
//! - The stage starts from the start (after the coarse energy solve, where
//!   `optimize.whole.coarse_control_points` asks for one), not from the energy's optimum on the
//!   fine spline as the trust region's does (`optimize.whole.homotopy` is the trust region's):
//!   the homotopy's 20 to 80 iterations cost more than they saved (without it, before the
//!   barrier was lowered by tenths: the spherical joint 3.9 s against 6.6, the tailed cat 7.3
//!   against 8.7, the legged cat 4.0 against 6.7, the same peaks or lower; scratch). The
//!   spherical joint also starts at the universal joint's optimum refined where its torques
//!   switch, lifted ([`super::lift`]; from the library starts alone it ended above the universal
//!   joint at 40 control points).
//!
//! It ends **converged** when the error of the original problem (the Lagrangian's gradient, the
//! flip, the rows' residuals and complementarity, in the scaled units) is within `optimality`;
//! at its budget with the status max-iterations; **stalled** when a line search or a
//! factorisation fails or the error is not a number. The Newton phase and the re-measurement of
//! the trust-region loop ([`super::optimize_start`]) follow as for every stage.
//!
//! It solves the least peak of a cat with ideal motors released without spin and without a
//! bend limit, when `optimize.whole.method = "interior-point"`, or `"auto"` (the default) on a
//! cat of more than two motors; the energy's stages (the coarse solve that starts each start)
//! and every other problem keep the trust-region loop. On the five cats of the bench it is 3 to
//! 11 times faster than the trust region (the spherical joint 1.57–1.59 s against 8.4, the tailed
//! cat 1.51–1.58 against 17.5–18.6, the legged cat 1.08–1.13 against 6.3–6.5; 2 cores,
//! 2026-12-07) and its peaks lie from 1.6 % below the trust region's (the spherical joint's, from
//! the refined universal optimum lifted, [`super::lift`]) to 0.004 % above (README, "More
//! motors"). On two motors `auto` keeps the trust region: there the interior point's refinement
//! of unequal halves cycles at its last barrier and stops at its budget, 0.3 % above the trust
//! region's optimum.
//!
//! ## References
//! - A. Wächter, L. T. Biegler, *On the implementation of an interior-point filter line-search
//!   algorithm for large-scale nonlinear programming*, Math. Program. 106 (2006) 25–57;
//! - J. Nocedal, S. J. Wright, *Numerical Optimization* (2nd ed., 2006), ch. 19.

mod banded;
mod curvature;
mod filter;
mod newton;
#[cfg(test)]
mod tests;

use nalgebra::{DMatrix, DVector, UnitQuaternion, Vector3};

use super::cat::Partials;
use super::reach::Reach;
use super::scvx::{ScvxProblem, StageEnd};
use super::sensitivity::{chained_samples, final_orientation, grid_partials, uniform_grid, GridPoint, Layout};
use super::settings::{Objective, WholeError};
use super::solution::{IterationLog, WholeStatus};
use super::spline::BSpline;
use curvature::SampleCurvature;
use filter::{Current, Filter, Verdict};
use newton::{Newton, Order, Rows};

/// The first barrier parameter, in the scaled units.
const FIRST_BARRIER: f64 = 1e-4;
/// The first barrier parameter of a stage that starts at an optimum (or an upper bound) of a
/// coarser layout, a refinement where the torques switch: a fresh `10⁻⁴` pushed the iterate off
/// it and back, and the tailed cat's refinement stopped at its 25 iterations; from `10⁻⁶` the
/// tailed cat's refined in 19 and the legged cat's in 13 (timed stage by stage in scratch).
const WARM_BARRIER: f64 = 1e-6;
/// `κ_μ`: each barrier problem solved, `μ` is divided by ten (IPOPT's superlinear
/// `min(μ/5, μ^{1.5})` jumped from `10⁻⁴` to `10⁻⁶` while the tailed cat's peak was still 40 %
/// above its optimum, and the iterate then wandered 70 iterations at steps cut short by the
/// fraction to the boundary: 110 iterations from its `paper` start against 53 by tenths;
/// scratch).
const BARRIER_DECREASE: f64 = 0.1;
/// The bound `t` starts this share above the start's sampled peak.
const FIRST_MARGIN: f64 = 1e-3;
/// The least first slack.
const LEAST_SLACK: f64 = 1e-8;
/// `κ_Σ`: how far the multipliers may stray from `μ/s`.
const DUAL_SPREAD: f64 = 1e10;
/// `κ_ε`: the barrier problem counts as solved at this multiple of `μ` (IPOPT's 10 left the
/// spherical joint's `cone-mirrored` start 125 iterations at one `μ`, wandering along the
/// relative twist; at 100 it converged in 28 to the same optimum, 0.312461 N·m against 0.312518).
const BARRIER_SOLVED: f64 = 100.0;
/// How far any control point may move, rad, before the samples' torque curvature is made again
/// ([`curvature::torque_curvatures`]); until then each iteration weighs the curvature it holds
/// with its own multipliers. An inexact Hessian changes the path, not the point the method
/// converges to (its error is measured with exact gradients). Made at every iteration, the
/// curvature was three fifths of an iteration's time (the tailed cat's `paper` start: 13 of 22
/// ms); kept within 0.03 rad it is made at a third of the iterations or fewer (both starts and
/// the refinement: the spherical joint 57 of 165, the tailed cat 39 of 102, the legged cat 20 of
/// 69; the universal joint 10 of 49), with the peaks of every cat unchanged to six digits and
/// the iterations within three but for the spherical joint's `paper` start (67 against 77). At
/// 0.1 rad the spherical joint's `paper` start ran out of iterations, and so it did when the
/// curvature was kept for four iterations whatever the motion (scratch, 2026-12-07).
const CURVATURE_KEPT: f64 = 0.03;
/// Second-order corrections tried after a rejected first trial.
const CORRECTIONS: usize = 4;
/// The shortest step of a line search.
const LEAST_STEP: f64 = 1e-10;

/// The longest Magnus step of the stage's flip, as a share of the fall: two steps on each of the
/// default 117 spans.
const STAGE_STEP: f64 = 1.0 / 234.0;

/// The Magnus steps on the widest span of `spline` the stage integrates the flip with (the
/// narrower spans get proportionally fewer, [`BSpline::by_width`]), for the loop's `steps`: the
/// fewest that keep each step within [`STAGE_STEP`] of the fall, at least two and at most the
/// loop's. Against 64 steps a span, at two on the default 117 spans the flip's error `e` lies
/// within `10⁻¹¹` rad and its Jacobian within `7·10⁻⁸` of its largest entry, on both starts'
/// optima of all five cats of `whole_methods` (the refined layouts' included), and the peaks and
/// iterations are those of four steps; there the five cats together took an eighth less
/// processor time than at four. On 37 spans (40 control points) two steps were `6·10⁻¹⁰` rad
/// off, and the paper's cat's least peak moved by `7·10⁻⁶` of itself; there it takes seven
/// (scratch, 2026-12-07). The Newton phase after the stage ([`super::optimize_start`])
/// integrates with the loop's own steps, doubled until the adaptive engine agrees, and holds
/// the flip there.
fn stage_steps(spline: &BSpline, steps: usize) -> usize {
    let needed = spline.widest_span() / (STAGE_STEP * spline.duration());
    // A hair below, so that a span of exactly two steps' length takes two.
    ((needed - 1e-9).ceil() as usize).clamp(2, steps.max(2))
}

/// One evaluated point: the unknowns, the inequality rows and the flip's equality rows.
#[derive(Clone)]
struct Point {
    /// `(c, t)`.
    x: Vec<f64>,
    /// The inequality rows at `x`.
    rows: Rows,
    /// The flip's error `e`.
    error: Vector3<f64>,
    /// `∂e/∂c`.
    jacobian: DMatrix<f64>,
    /// The directions of `e` the equality rows measure ([`Reach`]): the point's own once it is
    /// the iterate, the iterate's while it is a trial (so that its residuals are comparable).
    reach: Reach,
    /// The equality rows over the control points in those directions, and their residuals.
    equality: Vec<Vec<f64>>,
    equality_residual: Vec<f64>,
    /// The largest sampled `|τ|`, N·m.
    peak: f64,
    /// Each sample's torques with their partials in `(q, q̇, q̈)`, for the curvature.
    partials: Vec<Vec<Partials>>,
}

impl Point {
    /// The point with its equality rows in the directions `reach`.
    fn measured_in(mut self, reach: Reach) -> Point {
        let rows = reach.constraint_rows(&self.jacobian, &self.error);
        (self.equality, self.equality_residual) = rows.into_iter().map(|(a, b)| (a, -b)).unzip();
        self.reach = reach;
        self
    }

    /// The point with its equality rows in its own reachable directions.
    fn measured_in_own(self) -> Point {
        let reach = Reach::of(&self.jacobian);
        self.measured_in(reach)
    }
}

/// The multipliers of the equality rows in the directions `reach` for the multiplier `nu` of `e`
/// itself: `nu` where every direction is reached, its components along the reached ones else.
fn row_multipliers(reach: &Reach, nu: &Vector3<f64>) -> DVector<f64> {
    match reach {
        Reach::Full => DVector::from_column_slice(nu.as_slice()),
        Reach::Directions(dirs) => DVector::from_iterator(dirs.len(), dirs.iter().map(|(u, _)| u.dot(nu))),
    }
}

/// The multiplier of `e` itself for the rows' multipliers `lambda` in the directions `reach`
/// (the inverse of [`row_multipliers`] on the reached directions).
fn error_multiplier(reach: &Reach, lambda: &DVector<f64>) -> Vector3<f64> {
    match reach {
        Reach::Full => Vector3::new(lambda[0], lambda[1], lambda[2]),
        Reach::Directions(dirs) => dirs.iter().zip(lambda.iter()).map(|((u, _), l)| u * *l).sum(),
    }
}

/// The problem in the method's unknowns: the spline they move, the grid, the scales.
struct Barrier<'a> {
    /// The cat, the settings and the target.
    problem: &'a ScvxProblem<'a>,
    /// The free control points.
    layout: Layout,
    /// The spline the unknowns move (its held control points stay).
    base: BSpline,
    /// The torque samples, `samples_per_span` per span.
    grid: Vec<GridPoint>,
    /// Magnus steps per span of the flip's integration.
    steps: usize,
    /// The final orientation required.
    target: UnitQuaternion<f64>,
    /// `τ_u`, N·m.
    unit: f64,
    /// Each control point's limit, rad.
    limits: Vec<Option<f64>>,
}

impl Barrier<'_> {
    fn variables(&self) -> usize {
        self.layout.variables()
    }

    /// The spline at the control points `x[..n]`.
    fn spline(&self, x: &[f64]) -> BSpline {
        let now = self.layout.values(&self.base);
        let step: Vec<f64> = now.iter().zip(x).map(|(c, v)| v - c).collect();
        self.layout.moved(&self.base, &step)
    }

    /// Evaluates torques, limits and flip at `x`, the flip's rows in the directions `reach`.
    fn evaluate(&self, x: &[f64], reach: &Reach) -> Point {
        let n = self.variables();
        let spline = self.spline(x);
        let partials = grid_partials(self.problem.cat, &spline, self.layout.joints, &self.grid);
        let samples = chained_samples(&spline, &self.layout, &self.grid, &partials);
        let flip = final_orientation(self.problem.cat, &spline, &self.layout, self.steps, &self.target);
        let mut rows = Rows::default();
        rows.start.push(0);
        let mut peak = 0.0f64;
        for sample in &samples {
            for (tau, gradient) in sample.tau.iter().zip(&sample.gradient) {
                peak = peak.max(tau.abs());
                for sign in [1.0, -1.0] {
                    rows.values.push(x[n] - sign * tau / self.unit);
                    rows.t.push(1.0);
                    rows.entries.extend(gradient.iter().map(|&(v, d)| (v, -sign * d / self.unit)));
                    rows.start.push(rows.entries.len());
                }
            }
        }
        for (v, limit) in self.limits.iter().enumerate() {
            if let Some(l) = limit {
                for sign in [1.0, -1.0] {
                    rows.values.push(l - sign * x[v]);
                    rows.t.push(0.0);
                    rows.entries.push((v, -sign));
                    rows.start.push(rows.entries.len());
                }
            }
        }
        let point = Point {
            x: x.to_vec(),
            rows,
            error: flip.error,
            jacobian: flip.jacobian,
            reach: Reach::Full,
            equality: Vec::new(),
            equality_residual: Vec::new(),
            peak,
            partials,
        };
        point.measured_in(reach.clone())
    }

    /// Each sample's torque curvature at `point` ([`curvature::torque_curvatures`]).
    fn torque_curvatures(&self, point: &Point) -> Vec<SampleCurvature> {
        let spline = self.spline(&point.x);
        curvature::torque_curvatures(self.problem.cat, &spline, self.layout.joints, &self.grid, &point.partials)
    }

    /// The Lagrangian's curvature `−Σ z_r ∇²g_r` on the control points for the multipliers `z`
    /// (the torque rows' `Σ (z⁺ − z⁻) ∇²τ / τ_u`; the limit rows are linear) from the samples'
    /// `curvatures`, as entries ([`curvature::weighted_torque_hessian`]).
    fn curvature(&self, curvatures: &[SampleCurvature], z: &[f64]) -> Vec<(usize, usize, f64)> {
        let joints = self.layout.joints;
        let weights: Vec<Vec<f64>> = (0..self.grid.len())
            .map(|k| (0..joints).map(|j| (z[2 * (k * joints + j)] - z[2 * (k * joints + j) + 1]) / self.unit).collect())
            .collect();
        curvature::weighted_torque_hessian(&self.base, &self.layout, &self.grid, curvatures, &weights)
    }

    /// The order of the Newton matrix's unknowns.
    fn order(&self) -> Order {
        Order { joints: self.layout.joints, free: self.layout.free() }
    }
}

/// `∇f − Eᵀλ − Aᵀz` over `(c, t)` at `point`.
fn lagrangian_gradient(point: &Point, lambda: &DVector<f64>, z: &[f64]) -> DVector<f64> {
    let n = point.x.len() - 1;
    let mut g = DVector::zeros(n + 1);
    g[n] = 1.0;
    for (row, l) in point.equality.iter().zip(lambda.iter()) {
        for (v, a) in row.iter().enumerate() {
            g[v] -= a * l;
        }
    }
    let minus: Vec<f64> = z.iter().map(|x| -x).collect();
    point.rows.add_transposed(&minus, &mut g);
    g
}

/// `|e|₁ + Σ|g − s|`.
fn violation(point: &Point, slacks: &[f64]) -> f64 {
    point.equality_residual.iter().map(|c| c.abs()).sum::<f64>()
        + point.rows.values.iter().zip(slacks).map(|(g, s)| (g - s).abs()).sum::<f64>()
}

/// `t − μ Σ ln s`.
fn barrier_objective(point: &Point, slacks: &[f64], mu: f64) -> f64 {
    point.x[point.x.len() - 1] - mu * slacks.iter().map(|s| s.ln()).sum::<f64>()
}

/// Whether this stage is the interior-point method's: the least peak with ideal motors, no
/// spin, no bend limit and a target, as `optimize.whole.method` chooses.
pub(crate) fn applies(
    problem: &ScvxProblem<'_>,
    objective: Objective,
    bound: Option<f64>,
    enough: Option<f64>,
) -> bool {
    let s = problem.settings;
    objective == Objective::Peak
        && bound.is_none()
        && enough.is_none()
        && problem.motors.is_ideal()
        && !problem.spins()
        && problem.target.is_some()
        && s.min_angle_deg.is_none()
        && s.method.interior_point(problem.cat.joints())
}

/// The least-peak stage from `spline` (module docs) until the log holds `budget` entries;
/// `warm` when `spline` is an optimum (or an upper bound) of a coarser layout ([`WARM_BARRIER`]).
pub(crate) fn stage(
    problem: &ScvxProblem<'_>,
    spline: BSpline,
    warm: bool,
    optimality: f64,
    budget: usize,
    steps: usize,
    log: &mut Vec<IterationLog>,
) -> Result<StageEnd, WholeError> {
    let s = problem.settings;
    let layout = Layout { control_points: s.control_points, fixed: s.fixed(), joints: problem.cat.joints() };
    let grid = uniform_grid(&spline, s.samples_per_span);
    let first = grid_partials(problem.cat, &spline, layout.joints, &grid);
    let unit = first.iter().flatten().map(|t| t.value.abs()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let coordinates = problem.cat.control_limits(s.joint_limit_deg);
    let limits = (0..layout.variables()).map(|v| coordinates[v / layout.free()]).collect();
    let target = problem.target.unwrap_or_else(UnitQuaternion::identity);
    let steps = stage_steps(&spline, steps);
    let barrier = Barrier { problem, layout, base: spline, grid, steps, target, unit, limits };
    let mut x = layout.values(&barrier.base);
    x.push(1.0 + FIRST_MARGIN);
    let point = barrier.evaluate(&x, &Reach::Full).measured_in_own();
    let first = if warm { WARM_BARRIER } else { FIRST_BARRIER };
    let (status, reason, point) = solve(&barrier, point, first, optimality, budget, log);
    Ok(StageEnd { spline: barrier.spline(&point.x), status, reason })
}

/// The method's iterations from `p` with the first barrier parameter `mu` (module docs): how
/// they ended, why, and the last point.
fn solve(
    b: &Barrier<'_>,
    mut p: Point,
    mut mu: f64,
    tolerance: f64,
    budget: usize,
    log: &mut Vec<IterationLog>,
) -> (WholeStatus, String, Point) {
    let m = p.rows.len();
    let mut slacks: Vec<f64> = p.rows.values.iter().map(|g| g.max(LEAST_SLACK)).collect();
    let mut z: Vec<f64> = slacks.iter().map(|s| mu / s).collect();
    // The flip's multiplier, carried as that of `e` itself: the rows' directions may change
    // from one iterate to the next (a symmetric cat's, [`Reach`]).
    let mut nu = Vector3::zeros();
    let mut filter = Filter::new(violation(&p, &slacks));
    let mut regularisation = 0.0;
    // The samples' curvature and the control points it was made at ([`CURVATURE_KEPT`]).
    let mut held: Option<(Vec<f64>, Vec<SampleCurvature>)> = None;
    loop {
        let lambda = row_multipliers(&p.reach, &nu);
        let residual: Vec<f64> = (0..m).map(|r| p.rows.values[r] - slacks[r]).collect();
        let dual = lagrangian_gradient(&p, &lambda, &z).amax();
        let primal = p.equality_residual.iter().chain(&residual).fold(0.0f64, |a, c| a.max(c.abs()));
        let complementarity = |target: f64| (0..m).map(|r| (slacks[r] * z[r] - target).abs()).fold(0.0, f64::max);
        let error = dual.max(primal).max(complementarity(0.0));
        if !error.is_finite() {
            return (WholeStatus::Stalled, format!("interior point: the optimality error is {error}"), p);
        }
        let mut entry = IterationLog {
            iteration: log.len() + 1,
            objective: Objective::Peak,
            value: p.peak,
            peak_nm: p.peak,
            violation: p.error.abs().sum(),
            trust_radius: None,
            barrier: Some(mu),
            subproblem: None,
            ratio: None,
            accepted: false,
        };
        if error <= tolerance {
            return (
                WholeStatus::Converged,
                format!("interior point: optimality error {error:.1e}, within the tolerance {tolerance:.0e}"),
                p,
            );
        }
        if log.len() >= budget {
            return (WholeStatus::MaxIterations, format!("{budget} iterations used"), p);
        }
        let least = 0.1 * tolerance;
        if mu > least && dual.max(primal).max(complementarity(mu)) <= BARRIER_SOLVED * mu {
            // The barrier problem is solved: the next, smaller μ (at least ε/10, where it stays).
            mu = (BARRIER_DECREASE * mu).max(least);
            filter.clear();
            continue;
        }
        let n = b.variables();
        let moved = |at: &[f64]| at.iter().zip(&p.x[..n]).any(|(a, x)| (a - x).abs() > CURVATURE_KEPT);
        if held.as_ref().is_none_or(|(at, _)| moved(at)) {
            held = Some((p.x[..n].to_vec(), b.torque_curvatures(&p)));
        }
        let curvature = b.curvature(&held.as_ref().expect("made above").1, &z);
        let degree = b.base.degree;
        let Some(newton) =
            Newton::factor(b.order(), degree, &curvature, &p.rows, &slacks, &z, &p.equality, regularisation)
        else {
            log.push(entry);
            return (WholeStatus::Stalled, "interior point: the Newton system could not be factored".into(), p);
        };
        regularisation = newton.regularisation;
        let d = newton.direction(&p.rows, &slacks, &z, mu, &residual, &p.equality_residual, &lambda);
        let dz: Vec<f64> = (0..m).map(|r| mu / slacks[r] - z[r] - z[r] / slacks[r] * d.s[r]).collect();
        let tau = (1.0 - mu).max(0.99);
        let boundary = |from: &[f64], step: &[f64]| {
            from.iter().zip(step).filter(|(_, s)| **s < 0.0).fold(1.0f64, |a, (x, s)| a.min(-tau * x / s))
        };
        let alpha_max = boundary(&slacks, &d.s);
        let alpha_z = boundary(&z, &dz);
        let slope = d.x[n] - mu * (0..m).map(|r| d.s[r] / slacks[r]).sum::<f64>();
        let current = Current { theta: violation(&p, &slacks), phi: barrier_objective(&p, &slacks, mu), slope };
        let Some((alpha, next, next_slacks, verdict)) = line_search(
            b,
            &p,
            &slacks,
            &d,
            &newton,
            Search { mu, tau, alpha_max, current, lambda: &lambda, z: &z },
            &filter,
        ) else {
            log.push(entry);
            return (
                WholeStatus::Stalled,
                format!("interior point: the line search found no acceptable step (μ = {mu:.1e})"),
                p,
            );
        };
        if verdict == Verdict::Filter {
            filter.add(current);
        }
        entry.accepted = true;
        log.push(entry);
        nu = error_multiplier(&p.reach, &(lambda + &d.lambda * alpha));
        p = next.measured_in_own();
        slacks = next_slacks;
        for r in 0..m {
            z[r] = (z[r] + alpha_z * dz[r]).clamp(mu / (DUAL_SPREAD * slacks[r]), DUAL_SPREAD * mu / slacks[r]);
        }
    }
}

/// What a line search needs besides the point and the direction.
struct Search<'a> {
    /// The barrier parameter.
    mu: f64,
    /// The fraction to the boundary.
    tau: f64,
    /// The longest step within it.
    alpha_max: f64,
    /// The current point's violation, barrier objective and slope.
    current: Current,
    /// The equality rows' multipliers.
    lambda: &'a DVector<f64>,
    /// The rows' multipliers.
    z: &'a [f64],
}

/// Backtracks from the longest step within the slacks' bounds until the filter accepts,
/// trying second-order corrections after a rejected first trial; the step, the point and slacks
/// it reached and the verdict, none when the step falls below [`LEAST_STEP`].
fn line_search(
    b: &Barrier<'_>,
    p: &Point,
    slacks: &[f64],
    d: &newton::Direction,
    newton: &Newton,
    search: Search<'_>,
    filter: &Filter,
) -> Option<(f64, Point, Vec<f64>, Verdict)> {
    let m = slacks.len();
    let Search { mu, tau, alpha_max, current, lambda, z } = search;
    let judge =
        |q: &Point, s: &[f64], alpha: f64| filter.judge(current, violation(q, s), barrier_objective(q, s, mu), alpha);
    let mut alpha = alpha_max;
    let mut first = true;
    while alpha >= LEAST_STEP {
        let x: Vec<f64> = p.x.iter().zip(d.x.iter()).map(|(x, dx)| x + alpha * dx).collect();
        let s: Vec<f64> = (0..m).map(|r| slacks[r] + alpha * d.s[r]).collect();
        let trial = b.evaluate(&x, &p.reach);
        let verdict = judge(&trial, &s, alpha);
        if verdict != Verdict::Reject {
            return Some((alpha, trial, s, verdict));
        }
        if first && violation(&trial, &s) >= current.theta {
            // Second-order corrections (Wächter and Biegler 2006, §2.4): the residuals of each
            // trial added to the step's.
            let mut row_sum: Vec<f64> = (0..m).map(|r| alpha * (p.rows.values[r] - slacks[r])).collect();
            let mut equality_sum: Vec<f64> = p.equality_residual.iter().map(|c| alpha * c).collect();
            let (mut last, mut last_s) = (trial, s);
            let mut last_theta = violation(&last, &last_s);
            for _ in 0..CORRECTIONS {
                for r in 0..m {
                    row_sum[r] += last.rows.values[r] - last_s[r];
                }
                for (sum, c) in equality_sum.iter_mut().zip(&last.equality_residual) {
                    *sum += c;
                }
                let c = newton.direction(&p.rows, slacks, z, mu, &row_sum, &equality_sum, lambda);
                if (0..m).any(|r| slacks[r] + c.s[r] < (1.0 - tau) * slacks[r]) {
                    break;
                }
                let x: Vec<f64> = p.x.iter().zip(c.x.iter()).map(|(x, dx)| x + dx).collect();
                let s: Vec<f64> = (0..m).map(|r| slacks[r] + c.s[r]).collect();
                let corrected = b.evaluate(&x, &p.reach);
                let verdict = judge(&corrected, &s, alpha);
                if verdict != Verdict::Reject {
                    return Some((alpha, corrected, s, verdict));
                }
                let theta = violation(&corrected, &s);
                if theta > 0.99 * last_theta {
                    break;
                }
                (last, last_s, last_theta) = (corrected, s, theta);
            }
        }
        first = false;
        alpha *= 0.5;
    }
    None
}
