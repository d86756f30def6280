//! rapier's check of a trajectory against the exact engine, the figures every report shows: the
//! finest run's step, tracking error and jump spikes, the Richardson extrapolation to `dt → 0`,
//! the errors against the exact engine and the verdict ([`crate::engines::rapier::verify`],
//! DESIGN.md §6). Computed here, below every stage that shows it: [`crate::report`] renders it
//! (`RapierCheck::to_text`, the verification table), [`crate::exchange`] measures an imported
//! schedule with it.
//!
//! A verification may end without a single usable run (rapier diverged at every step it tried, or
//! the step budget did not allow the first run): then rapier has no number for the trajectory,
//! and [`RapierOutcome::NoResult`] carries the verification alone, whose verdict is
//! `inconclusive` and says why. Nothing here fills a missing number with NaN or zero.
//!
//! Twist and swing are in degrees (twist signed about A's initial `+z`), torques in N·m, the
//! peak torque's error relative to the exact engine's peak.

use serde::Serialize;

use crate::engines::evaluate::Evaluation;
use crate::engines::models::TwoMotorCat;
use crate::engines::rapier::{
    JumpTorque, Quantity, RapierError, RapierOptions, RapierRun, Reference, Status, Verification,
};
use crate::problem::settings::RapierSettings;
use crate::schedule::Trajectory;

/// rapier's results extrapolated to `dt → 0`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Extrapolation {
    /// The two steps, s.
    pub dt: [f64; 2],
    /// Twist, degrees.
    pub twist_deg: f64,
    /// Swing, degrees.
    pub swing_deg: f64,
    /// Peak torque, N·m.
    pub peak_torque_nm: f64,
    /// Exact engine's twist minus the extrapolated one, degrees.
    pub twist_error_deg: f64,
}

/// rapier's own numbers beside a report's twist, swing and peaks: all `Some` in a rapier report,
/// all `None` in the exact engine's.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RapierCheck {
    /// Time step of the finest run, s.
    pub dt: Option<f64>,
    /// The finest run's own twist, degrees: raw, before the extrapolation to `dt → 0` that the
    /// report's `twist_deg` gives.
    pub twist_deg_raw: Option<f64>,
    /// The finest run's own swing, degrees (raw).
    pub swing_deg_raw: Option<f64>,
    /// Largest joint tracking error per joint, rad.
    pub tracking_error_rad: Option<[f64; 2]>,
    /// The motors' torque spikes at rate jumps, as rapier measured them.
    pub rapier_jumps: Option<Vec<JumpTorque>>,
    /// First-order Richardson extrapolation to `dt → 0` from the last two runs (absent with
    /// fewer than two).
    pub extrapolated: Option<Extrapolation>,
    /// Exact engine's twist minus rapier's raw one (`twist_deg_raw`), degrees.
    pub twist_error_deg: Option<f64>,
    /// Relative error of the peak torque against the exact engine's (absent when the exact peak
    /// is zero: the schedule does not move).
    pub peak_torque_rel_error: Option<f64>,
    /// How rapier's verification ended; rapier's numbers are not to be used without it.
    pub verdict: Option<Status>,
    /// The verification behind the verdict: dt sequence, raw and extrapolated values, observed
    /// orders, error estimates, tolerances.
    pub verification: Option<Verification>,
}

/// What an engine says of a trajectory besides its peaks, as both the built-in schedules' report
/// ([`crate::report::simulate::SimulationReport`]) and an imported schedule's
/// ([`crate::report::import::ImportReport`]) show it: the exact engine fills the integration's fields,
/// rapier its check.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EngineFigures {
    /// Signed twist about A's initial `+z`, degrees; rapier's is its estimate at `dt → 0` (the
    /// extrapolation the verdict judges) when it has one, its finest run's otherwise (the raw
    /// value is `twist_deg_raw`).
    pub twist_deg: f64,
    /// Swing of the spine axis, degrees; rapier's as its twist.
    pub swing_deg: f64,
    /// Largest angular momentum along the motion relative to `I* · max|q̇|`.
    pub momentum_max: f64,
    /// Most Magnus steps of a piece (exact), or rapier's steps in its finest run.
    pub steps: usize,
    /// Estimated error of twist and swing, rad (exact only).
    pub error_estimate_rad: Option<f64>,
    /// Whether the exact integration met `exact.tolerance` (exact only); when false the angles
    /// are not to be trusted to that tolerance.
    pub converged: Option<bool>,
    /// Largest gap between the joint torques from B's and A's sides, N·m (exact only).
    pub action_reaction_gap_nm: Option<f64>,
    /// Wall-clock time of the engine run (rapier: all runs of the verification), s.
    pub run_time_s: f64,
    /// rapier's own numbers and its verdict against the exact engine (rapier only; every field
    /// is `null` in the exact engine's report).
    #[serde(flatten)]
    pub check: RapierCheck,
}

impl EngineFigures {
    /// The exact engine's figures of its evaluation `e`: its flip, the momentum residual, the two
    /// sides' torque gap and the run time.
    pub fn exact(e: &Evaluation) -> Self {
        let flip = &e.flip;
        Self {
            twist_deg: flip.twist.to_degrees(),
            swing_deg: flip.swing.to_degrees(),
            momentum_max: e.momentum_max,
            steps: flip.steps_per_phase,
            error_estimate_rad: Some(flip.error_estimate),
            converged: Some(flip.converged),
            action_reaction_gap_nm: Some(e.peaks.action_reaction_gap),
            run_time_s: e.run_time_s,
            check: RapierCheck::default(),
        }
    }

    /// rapier's figures: its finest run and the check; twist and swing extrapolated to `dt → 0`
    /// when there is an extrapolation (the raw values are in the check).
    pub fn rapier(finest: Finest) -> Self {
        let Finest { run, check, run_time_s } = finest;
        let raw = (run.twist.to_degrees(), run.swing.to_degrees());
        let (twist_deg, swing_deg) = check.extrapolated.map_or(raw, |x| (x.twist_deg, x.swing_deg));
        Self {
            twist_deg,
            swing_deg,
            momentum_max: run.momentum.max_rel,
            steps: run.steps,
            error_estimate_rad: None,
            converged: None,
            action_reaction_gap_nm: None,
            run_time_s,
            check,
        }
    }

    /// The reference a rapier verification compares with: these figures (the exact engine's)
    /// and the peak torque `peak_torque_nm`.
    pub fn reference(&self, peak_torque_nm: f64) -> Reference {
        Reference {
            twist: self.twist_deg.to_radians(),
            swing: self.swing_deg.to_radians(),
            peak_torque: peak_torque_nm,
        }
    }
}

/// The finest run of a verification that made one, and the check built from it.
#[derive(Clone, Debug)]
pub struct Finest {
    /// The finest run in full (twist, swing, peaks per piece, momentum, steps).
    pub run: RapierRun,
    /// The check (every field `Some`, `extrapolated` when two runs were kept).
    pub check: RapierCheck,
    /// Time spent in rapier, all runs of the verification, s.
    pub run_time_s: f64,
}

/// What rapier made of a trajectory.
#[derive(Clone, Debug)]
pub enum RapierOutcome<T> {
    /// rapier's numbers, from the finest run, with the verification behind them.
    Report(T),
    /// The verification made no usable run: rapier has no number for this trajectory, only the
    /// verification, whose verdict (`inconclusive`) says why.
    NoResult(Box<Verification>),
}

impl<T> RapierOutcome<T> {
    /// The outcome with its report mapped by `f`.
    pub fn map<U>(self, f: impl FnOnce(T) -> U) -> RapierOutcome<U> {
        match self {
            RapierOutcome::Report(t) => RapierOutcome::Report(f(t)),
            RapierOutcome::NoResult(v) => RapierOutcome::NoResult(v),
        }
    }

    /// The report, if rapier made one.
    pub fn report(&self) -> Option<&T> {
        match self {
            RapierOutcome::Report(t) => Some(t),
            RapierOutcome::NoResult(_) => None,
        }
    }

    /// The report, or [`RapierError::NoResult`] with the verdict, for a command that has nothing
    /// else to show.
    pub fn into_report(self) -> Result<T, RapierError> {
        match self {
            RapierOutcome::Report(t) => Ok(t),
            RapierOutcome::NoResult(v) => Err(RapierError::NoResult(v.verdict.to_string())),
        }
    }
}

/// Verifies `traj` in rapier with `opts` (motors, release spin), against the exact engine's `reference` and
/// builds the check from the finest run; [`RapierOutcome::NoResult`] when there is none. `Err`
/// only when the settings or the trajectory are invalid (see [`crate::engines::rapier::verify`]).
pub fn rapier_check(
    cat: &TwoMotorCat,
    traj: &impl Trajectory,
    settings: &RapierSettings,
    reference: &Reference,
    opts: &RapierOptions,
) -> Result<RapierOutcome<Finest>, RapierError> {
    let v = crate::engines::rapier::verify_with(cat, traj, settings, reference, opts)?;
    let Some(run) = v.finest.clone() else { return Ok(RapierOutcome::NoResult(Box::new(v))) };
    let exact_twist = reference.twist.to_degrees();
    let value = |q| v.quantity(q).and_then(|c| c.value);
    let extrapolated = match (value(Quantity::Twist), value(Quantity::Swing), value(Quantity::PeakTorque)) {
        (Some(t), Some(s), Some(p)) if v.dt_sequence.len() >= 2 => Some(Extrapolation {
            dt: [v.dt_sequence[v.dt_sequence.len() - 2], run.dt],
            twist_deg: t,
            swing_deg: s,
            peak_torque_nm: p,
            twist_error_deg: exact_twist - t,
        }),
        _ => None,
    };
    let (peak, run_time_s) = (reference.peak_torque, v.run_time_s);
    let check = RapierCheck {
        dt: Some(run.dt),
        twist_deg_raw: Some(run.twist.to_degrees()),
        swing_deg_raw: Some(run.swing.to_degrees()),
        tracking_error_rad: Some(run.tracking_error),
        rapier_jumps: Some(run.jumps.clone()),
        extrapolated,
        twist_error_deg: Some(exact_twist - run.twist.to_degrees()),
        peak_torque_rel_error: (peak > 0.0).then(|| (run.peak_torque.max - peak) / peak),
        verdict: Some(v.status),
        verification: Some(v),
    };
    Ok(RapierOutcome::Report(Finest { run, check, run_time_s }))
}
