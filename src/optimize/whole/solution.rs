//! What the whole-manoeuvre optimisation returns: per start, how it ended and why, the spline,
//! its flip and torques re-measured by the exact engine, and the per-iteration log.

use std::fmt;

use serde::Serialize;

use super::settings::{Objective, WholeSettings};
use super::spline::BSpline;
use crate::engines::motors::MotorDemand;
use crate::optimize::conic::QpStatus;

/// How one start's optimisation ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum WholeStatus {
    /// A stationary point of the merit function that flips the cat within the tolerance (for the
    /// peak, also a stage whose progress fell below `3e-5` of the peak over five accepted steps,
    /// which its reason says: [`super::scvx`]).
    Converged,
    /// A refined stage ([`super::refine_solution`]) or the spherical joint's stage from the
    /// universal joint's optimum ([`super::lift`]) that stopped at its iteration budget, still
    /// descending, below what it started from (a converged optimum, or an upper bound below one),
    /// on a flip within the limits: a flip that exists and the best found, but not proved
    /// stationary; its value is an upper bound on the optimum it was descending to.
    UpperBound,
    /// The trust region collapsed (or the subproblems kept failing) before stationarity.
    Stalled,
    /// Stationary with the orientation error still above the tolerance at the largest penalty:
    /// no nearby trajectory flips the cat.
    Infeasible,
    /// The iteration limit came first.
    MaxIterations,
}

impl fmt::Display for WholeStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            WholeStatus::Converged => "converged",
            WholeStatus::UpperBound => "upper-bound",
            WholeStatus::Stalled => "stalled",
            WholeStatus::Infeasible => "infeasible",
            WholeStatus::MaxIterations => "max-iterations",
        })
    }
}

impl WholeStatus {
    /// Whether a start that ended so may be the outcome's best: it converged, or it is an upper
    /// bound (still to be checked for a flip within the limits).
    pub fn is_result(self) -> bool {
        matches!(self, WholeStatus::Converged | WholeStatus::UpperBound)
    }

    /// What the status `upper-bound` means, in a sentence for the reports that show it.
    pub const UPPER_BOUND_MEANS: &'static str = "`upper-bound`: the stage that gave the number stopped at its iteration budget, still descending, below what it started from (a converged optimum, or an upper bound below one): a flip that exists and the best found, its value an upper bound on the optimum it was descending to, not proved one";
}

/// One iteration: of the trust-region loop or of the interior-point method.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct IterationLog {
    /// Iteration number, from one, counted over all stages.
    pub iteration: usize,
    /// The stage's objective (the homotopy's energy stage, then the peak).
    pub objective: Objective,
    /// The objective at the current iterate (sampled), N·m or N²·m²·s.
    pub value: f64,
    /// The largest sampled `|τ|` at the current iterate, N·m.
    pub peak_nm: f64,
    /// `|e|₁` of the final orientation at the current iterate, rad.
    pub violation: f64,
    /// Trust radius of the subproblem, rad (none for an interior-point iteration).
    pub trust_radius: Option<f64>,
    /// The barrier parameter `μ` of an interior-point iteration, in units of the start's peak
    /// (none for a trust-region iteration).
    pub barrier: Option<f64>,
    /// The subproblem's status (none for an interior-point iteration, which has no subproblem).
    pub subproblem: Option<QpStatus>,
    /// Actual over predicted decrease of the merit function (none when nothing was tried).
    pub ratio: Option<f64>,
    /// Whether the step was accepted.
    pub accepted: bool,
}

/// The result of one start, re-measured by the exact engine.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WholeSolution {
    /// Which start.
    pub start: String,
    /// How it ended.
    pub status: WholeStatus,
    /// Why, in words.
    pub reason: String,
    /// Final twist from [`crate::engines::exact::flip`], rad (signed, continued).
    pub twist: f64,
    /// Final swing from [`crate::engines::exact::flip`], rad.
    pub swing: f64,
    /// `| |twist| − π |`, rad.
    pub twist_error: f64,
    /// The exact engine's error estimate of the flip, rad.
    pub flip_error_estimate: f64,
    /// Peak `|τ|` over both joints and the whole fall ([`crate::engines::torque::peak_torques`]), N·m.
    pub peak_torque_nm: f64,
    /// When it occurs, s.
    pub peak_time: f64,
    /// `∫ τ·τ dt` (five-point Gauss–Legendre per sub-interval), N²·m²·s.
    pub energy: f64,
    /// The largest bend (angle between the spine axes), degrees.
    pub max_bend_deg: f64,
    /// How far the bend direction turns about A's axis over the fall, turns (signed).
    pub bend_turns: f64,
    /// The trajectory's duration, s: the problem's fall time, or with the objective `min-time`
    /// the least fall time within the motors.
    pub fall_time_s: f64,
    /// What it asks of the motors (peak speed and power per joint, each limit's usage).
    pub motors: MotorDemand,
    /// How cleanly the torques switch between saturated arcs.
    pub chatter: super::measure::Chatter,
    /// Trust-region iterations used.
    pub iterations: usize,
    /// Final Newton steps on the orientation constraint.
    pub polish_steps: usize,
    /// Wall-clock time of this start, s.
    pub seconds: f64,
    /// The per-iteration log.
    pub log: Vec<IterationLog>,
    /// The trajectory.
    pub spline: BSpline,
}

impl WholeSolution {
    /// Whether an interior-point stage planned it (`optimize.whole.method`): its log holds a
    /// barrier parameter.
    pub fn interior_point(&self) -> bool {
        self.log.iter().any(|l| l.barrier.is_some())
    }

    /// Whether it flips the cat within `tolerance` (twist and swing).
    pub fn flips(&self, tolerance: f64) -> bool {
        self.twist_error <= tolerance && self.swing <= tolerance
    }

    /// Its value of `objective`: the peak torque (N·m), the energy (N²·m²·s) or the fall time (s).
    pub fn value(&self, objective: Objective) -> f64 {
        match objective {
            Objective::Peak => self.peak_torque_nm,
            Objective::Energy => self.energy,
            Objective::MinTime => self.fall_time_s,
        }
    }
}

/// Relative difference below which two starts' objectives are the same optimum: the mirrored
/// starts of a symmetric cat end on mirror images whose peaks differ by round-off (2e-10 of
/// themselves on the paper's cat), which must not decide which one is kept.
const TIE: f64 = 1e-9;

/// Index of the lowest `objective` among `solutions` that ended on a result
/// ([`WholeStatus::is_result`]: converged, or an upper bound) and flip the cat within `tolerance`
/// (none when none did); of values within `1e-9` of the lowest (relative), the first start's.
pub fn best_of(solutions: &[WholeSolution], objective: Objective, tolerance: f64) -> Option<usize> {
    let value = |i: usize| solutions[i].value(objective);
    let results: Vec<usize> = (0..solutions.len())
        .filter(|&i| solutions[i].status.is_result() && solutions[i].flips(tolerance) && value(i).is_finite())
        .collect();
    let lowest = results.iter().map(|&i| value(i)).min_by(f64::total_cmp)?;
    results.into_iter().find(|&i| value(i) <= lowest + TIE * lowest.abs())
}

/// `objective`'s value with its name and unit, as a sentence fragment: "peak 0.464684 N·m".
pub(crate) fn valued(objective: Objective, value: f64) -> String {
    match objective {
        Objective::Peak => format!("peak {value:.6} N·m"),
        Objective::Energy => format!("energy {value:.6} N²·m²·s"),
        Objective::MinTime => format!("fall time {value:.6} s"),
    }
}

/// A start that could not be built.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SkippedStart {
    /// Which start.
    pub start: String,
    /// Why.
    pub reason: String,
}

/// Every start's result and the best feasible one.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WholeOutcome {
    /// One per start that could be built, in order.
    pub solutions: Vec<WholeSolution>,
    /// Index in `solutions` of the lowest objective among those that ended on a result
    /// (converged, or an upper bound: [`WholeStatus::is_result`]) and flip the cat; none when
    /// no start did.
    pub best: Option<usize>,
    /// Starts that were not solved, and why: they could not be built, or (the spherical joint,
    /// [`super::lift`]) the universal joint's solution from them was not lifted (another start's
    /// was lower) or its solve failed.
    pub skipped: Vec<SkippedStart>,
}

impl WholeOutcome {
    /// The best solution, if any start ended on a result that flips the cat ([`best_of`]).
    pub fn best(&self) -> Option<&WholeSolution> {
        self.best.map(|i| &self.solutions[i])
    }

    /// The lowest objective among the starts that did not converge but whose last iterate is
    /// feasible: it flips the cat within `tolerance`, within the motors' limits and within the
    /// bend limit of `settings` (each re-measured by the exact engine, as every start's is). A
    /// schedule that exists, its value an upper bound on the optimum, though not proved a local
    /// optimum. None when some start ended on a result ([`WholeOutcome::best`]).
    pub fn unconverged_flip(&self, settings: &WholeSettings, tolerance: f64) -> Option<&WholeSolution> {
        if self.best.is_some() {
            return None;
        }
        let most_bend = settings.min_angle_deg.map_or(f64::INFINITY, |a| 180.0 - a);
        let objective = settings.objective;
        self.solutions
            .iter()
            .filter(|s| !s.status.is_result() && s.flips(tolerance))
            .filter(|s| s.motors.within() && s.max_bend_deg <= most_bend)
            .min_by(|a, b| a.value(objective).total_cmp(&b.value(objective)))
    }

    /// Why there is no optimum, in one sentence: how each start ended (and which could not be
    /// built), and the best feasible schedule a start ended on without converging, when one did
    /// ([`WholeOutcome::unconverged_flip`]).
    pub fn no_optimum(&self, settings: &WholeSettings, tolerance: f64) -> String {
        let objective = settings.objective;
        let mut why: Vec<String> = self.solutions.iter().map(|s| format!("{}: {}", s.start, s.reason)).collect();
        why.extend(self.skipped.iter().map(|s| format!("{} not tried: {}", s.start, s.reason)));
        let mut line = if self.solutions.is_empty() {
            format!("no optimum: no start could be built ({})", why.join("; "))
        } else {
            format!(
                "no optimum: none of the {} start(s) converged to a flip ({})",
                self.solutions.len(),
                why.join("; ")
            )
        };
        if let Some(s) = self.unconverged_flip(settings, tolerance) {
            line.push_str(&format!(
                "; the best flip found, not proved optimal: {} ended ({}) on a flip within {tolerance:.0e} rad and the limits at {}",
                s.start,
                s.status,
                valued(objective, s.value(objective))
            ));
        }
        line
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A solution that flips the cat exactly, at `peak` N·m and a largest bend of `bend_deg`,
    /// after `iterations` iterations that ended `status`.
    pub(crate) fn solution(status: WholeStatus, peak: f64, bend_deg: f64, iterations: usize) -> WholeSolution {
        let motors = MotorDemand { peak_speed_rad_s: vec![], peak_power_w: vec![], limits: vec![], stretch: None };
        WholeSolution {
            start: "s".into(),
            status,
            reason: format!("{iterations} iterations used"),
            twist: std::f64::consts::PI,
            swing: 0.0,
            twist_error: 0.0,
            flip_error_estimate: 0.0,
            peak_torque_nm: peak,
            peak_time: 0.5,
            energy: 1.0,
            max_bend_deg: bend_deg,
            bend_turns: 1.0,
            fall_time_s: 1.0,
            motors,
            chatter: Default::default(),
            iterations,
            polish_steps: 0,
            seconds: 1.0,
            log: Vec::new(),
            spline: BSpline::zero(1.0, 8, 3).with_joints(3),
        }
    }

    /// The lowest objective wins; of two within round-off of each other (mirror images of one
    /// optimum), the first start's, whichever is lower by round-off; a start that did not end on
    /// a result is never the best.
    #[test]
    fn the_best_is_the_lowest_and_round_off_does_not_decide_it() {
        let lowest = |peaks: &[f64]| {
            let solutions: Vec<_> = peaks.iter().map(|&p| solution(WholeStatus::Converged, p, 50.0, 40)).collect();
            best_of(&solutions, Objective::Peak, 1e-8)
        };
        assert_eq!(lowest(&[0.32, 0.31]), Some(1));
        assert_eq!(lowest(&[0.318345918223, 0.318345918222]), Some(0), "a tie at 3e-12 of the peak");
        assert_eq!(lowest(&[0.318345918223, 0.318345917]), Some(1), "3.8e-9 apart: not a tie");
        let stalled = solution(WholeStatus::Stalled, 0.30, 50.0, 40);
        assert_eq!(
            best_of(&[stalled, solution(WholeStatus::Converged, 0.31, 50.0, 40)], Objective::Peak, 1e-8),
            Some(1)
        );
    }
}
