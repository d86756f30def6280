//! What the whole-manoeuvre optimisation returns: per start, how it ended and why, the spline,
//! its flip and torques re-measured by the exact engine, and the per-iteration log.

use std::fmt;

use serde::Serialize;

use super::settings::Objective;
use super::spline::BSpline;
use crate::engines::motors::MotorDemand;
use crate::optimize::conic::QpStatus;

/// How one start's optimisation ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum WholeStatus {
    /// A stationary point of the merit function that flips the cat within the tolerance.
    Converged,
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
            WholeStatus::Stalled => "stalled",
            WholeStatus::Infeasible => "infeasible",
            WholeStatus::MaxIterations => "max-iterations",
        })
    }
}

/// One trust-region iteration.
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
    /// Trust radius of the subproblem, rad.
    pub trust_radius: f64,
    /// The subproblem's status.
    pub subproblem: QpStatus,
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
    /// Whether it flips the cat within `tolerance` (twist and swing).
    pub fn flips(&self, tolerance: f64) -> bool {
        self.twist_error <= tolerance && self.swing <= tolerance
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
    /// Index in `solutions` of the lowest objective among those that converged and flip the
    /// cat; none when no start did.
    pub best: Option<usize>,
    /// Starts that could not be built.
    pub skipped: Vec<SkippedStart>,
}

impl WholeOutcome {
    /// The best solution, if any start converged to a flip.
    pub fn best(&self) -> Option<&WholeSolution> {
        self.best.map(|i| &self.solutions[i])
    }
}
