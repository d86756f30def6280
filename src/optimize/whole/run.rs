//! One start's optimisation as it runs ([`Run`]): its stages (the trust-region loop's or the
//! interior point's), the Newton phase that holds the flip, the exact re-measurement, and the
//! result checked against the tolerances and limits ([`super::optimize_start`],
//! [`super::refine_solution`]).

use std::f64::consts::PI;
use std::time::Instant;

use super::scvx::ScvxProblem;
use super::settings::Objective;
use super::solution::{IterationLog, WholeSolution, WholeStatus};
use super::spline::BSpline;
use super::{flip_tolerance, interior, measure, WholeError, BEND_SLACK_DEG, LIMIT_MARGIN};

/// Most times the motor limits are tightened on the samples after the dense re-measurement
/// found them exceeded between samples.
const MAX_TIGHTENINGS: usize = 4;

/// How the final stage of one layout ended: its status, why, the spline, its measurement and the
/// times the motor limits were tightened on the samples.
pub(super) struct FinalStage {
    pub(super) status: WholeStatus,
    pub(super) reason: String,
    pub(super) spline: BSpline,
    pub(super) measurement: measure::Measurement,
    pub(super) tightenings: usize,
}

/// The state of one start's optimisation: the loop's Magnus steps per span, the log, the
/// Newton steps spent, and whether its stages start at an optimum (or an upper bound) of a
/// coarser layout (a refinement: the interior-point method then starts with a small barrier).
pub(super) struct Run {
    pub(super) steps: usize,
    pub(super) log: Vec<IterationLog>,
    pub(super) polish_steps: usize,
    pub(super) tolerance: f64,
    pub(super) warm: bool,
}

impl Run {
    /// The start's result from its final stage: `notes` added to the reason, the least fall time's
    /// path slowed to touch its limits, the limits checked on the dense re-measurement.
    pub(super) fn finish(
        self,
        p: &ScvxProblem<'_>,
        name: &str,
        end: FinalStage,
        notes: Vec<String>,
        constrained: bool,
        clock: Instant,
    ) -> WholeSolution {
        let FinalStage { mut status, mut reason, spline, measurement: m, tightenings } = end;
        if tightenings > 0 {
            reason = format!("{reason}; limits tightened {tightenings}× on the samples to hold between them");
        }
        for note in notes {
            reason = format!("{reason}; {note}");
        }
        // The least fall time: the path slowed by its largest stretch touches its limits exactly.
        let (spline, m) = match (p.settings.objective, m.motors.stretch) {
            (Objective::MinTime, Some(k)) if k.value > 0.0 => {
                let slowed = spline.stretched(k.value);
                let m = measure::measure_spinning(p.cat, &slowed, p.motors, self.flip_tolerance(), &p.spin);
                (slowed, m)
            }
            _ => (spline, m),
        };
        if constrained && !m.motors.within() && status.is_result() {
            status = WholeStatus::Infeasible;
            reason = format!("{reason}; the dense re-measurement {}", m.motors.verdict());
        }
        self.solution(p, name, status, reason, spline, m, clock)
    }

    /// The final stage of `objective` on the layout of `p` from `spline` (with the motor limits as
    /// constraints `ρ ≤ bound` when `constrained`, the bound tightened while the dense
    /// re-measurement finds them exceeded between the samples), until `budget` log entries.
    pub(super) fn final_stage(
        &mut self,
        p: &ScvxProblem<'_>,
        mut spline: BSpline,
        constrained: bool,
        bound: &mut f64,
        budget: usize,
    ) -> Result<FinalStage, WholeError> {
        let mut tightenings = 0;
        loop {
            let (status, reason, next, m) =
                self.solve(p, spline, p.settings.objective, constrained.then_some(*bound), None, budget)?;
            let excess = m.motors.worst().map_or(0.0, |w| w.ratio);
            if constrained && status == WholeStatus::Converged && excess > 1.0 && tightenings < MAX_TIGHTENINGS {
                // Exceeded between the samples: hold the samples below the limit by the excess.
                *bound /= excess * (1.0 + LIMIT_MARGIN);
                tightenings += 1;
                spline = next;
                continue;
            }
            return Ok(FinalStage { status, reason, spline: next, measurement: m, tightenings });
        }
    }

    /// The tolerance of the final flip's re-measurement, rad ([`flip_tolerance`]).
    pub(super) fn flip_tolerance(&self) -> f64 {
        flip_tolerance(self.tolerance)
    }

    /// One stage of `objective` (with `bound` on the limit rows, ending early at `enough`,
    /// [`ScvxProblem::stage`]) until `budget` log entries, then the Newton phase (doubling the
    /// loop's steps until the adaptive engine agrees) and the exact re-measurement.
    pub(super) fn solve(
        &mut self,
        p: &ScvxProblem<'_>,
        spline: BSpline,
        objective: Objective,
        bound: Option<f64>,
        enough: Option<f64>,
        budget: usize,
    ) -> Result<(WholeStatus, String, BSpline, measure::Measurement), WholeError> {
        let optimality = p.settings.optimality;
        let end = if interior::applies(p, objective, bound, enough) {
            interior::stage(p, spline, self.warm, optimality, budget, self.steps, &mut self.log)?
        } else {
            let it = p.evaluate(spline, objective, self.steps);
            p.stage(it, objective, bound, enough, optimality, budget, self.steps, &mut self.log)?
        };
        // The loop's projections move every control point, those on a limit too (by ~1e-11 rad on
        // refined knots): back within the limits, as in the subproblems, before the Newton phase
        // (which holds them there, ScvxProblem::polish).
        let mut last = end.spline;
        p.clamp_to_limits(&mut last);
        let (mut spline, k) = p.polish(last, self.steps, 8);
        self.polish_steps += k;
        let flip_tolerance = self.flip_tolerance();
        if p.target.is_some() {
            loop {
                let f = p.cat.flip_spinning(&spline, &p.spin, flip_tolerance);
                let good = ((f.twist.abs() - PI).abs() <= 0.1 * self.tolerance && f.swing <= 0.1 * self.tolerance)
                    || self.steps >= 1024;
                if good {
                    break;
                }
                self.steps *= 2;
                let (next, k) = p.polish(spline, self.steps, 8);
                spline = next;
                self.polish_steps += k;
            }
        }
        let m = measure::measure_spinning(p.cat, &spline, p.motors, flip_tolerance, &p.spin);
        Ok((end.status, end.reason, spline, m))
    }

    /// The start's result: the flip and bend checked against the tolerances and limits.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn solution(
        self,
        p: &ScvxProblem<'_>,
        name: &str,
        mut status: WholeStatus,
        mut reason: String,
        spline: BSpline,
        m: measure::Measurement,
        clock: Instant,
    ) -> WholeSolution {
        let flips = m.twist_error <= self.tolerance && m.flip.swing <= self.tolerance;
        if p.target.is_some() && !flips {
            if status.is_result() {
                status = WholeStatus::Infeasible;
            }
            reason = format!(
                "{reason}; the exact engine measures |twist| − π = {:.3e} rad, swing {:.3e} rad",
                m.twist_error, m.flip.swing
            );
        }
        if let Some(limit) = p.settings.min_angle_deg {
            let excess = m.max_bend.to_degrees() - (180.0 - limit);
            if excess > BEND_SLACK_DEG {
                if status.is_result() {
                    status = WholeStatus::Infeasible;
                }
                reason = format!("{reason}; the bend exceeds its limit by {excess:.3}° between samples");
            }
        }
        WholeSolution {
            start: name.to_string(),
            status,
            reason,
            twist: m.flip.twist,
            swing: m.flip.swing,
            twist_error: m.twist_error,
            flip_error_estimate: m.flip.error_estimate,
            peak_torque_nm: m.peak,
            peak_time: m.peak_time,
            energy: m.energy,
            max_bend_deg: m.max_bend.to_degrees(),
            bend_turns: m.bend_turns,
            fall_time_s: spline.duration(),
            motors: m.motors,
            chatter: m.chatter,
            iterations: self.log.len(),
            polish_steps: self.polish_steps,
            seconds: clock.elapsed().as_secs_f64(),
            log: self.log,
            spline,
        }
    }
}
