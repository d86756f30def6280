//! An imported schedule through the exact engine, and through rapier verified against it: what
//! `catflip simulate PROBLEM --schedule FILE.csv [--engine rapier]` reports, with the problem's
//! cat and `exact` and `rapier` settings.
//!
//! The same quantities as [`crate::report::simulate::SimulationReport`] where they apply: signed twist
//! about A's initial `+z` and swing (degrees), peak motor torques per piece and joint and
//! overall (N·m), the rate jumps between pieces with their impulses, the largest angular
//! momentum relative to `I* · max|q̇|`, and the engine's error estimate. An imported schedule
//! has no profile or circulation; it has a file, a row count and an interpolation scheme. rapier's
//! report has its own twist, swing, per-piece peaks and momentum drift, and beside them the
//! [`crate::engines::rapier_check::RapierCheck`] of every rapier report (step, tracking error, `dt → 0`, errors against the
//! exact engine on the same imported schedule, verdict).
//!
//! Before the engine runs, [`crate::exchange::checks::check`] refuses what cannot be evaluated and
//! warns of what looks wrong (`warnings`); the peak torque is sampled by the schedule's own time
//! scale ([`crate::engines::torque::piece_samples`], `exact.torque_samples` per piece at least)
//! and at every row, from both sides; after it, a number that came out NaN or infinite refuses
//! the whole report ([`ImportError::NotComputable`]) rather than print it.

use std::time::Instant;

use serde::Serialize;

use crate::engines::evaluate::{momentum_check, momentum_on_model, released_flip, released_on_model, torque_source};
use crate::engines::exact::Flip;
use crate::engines::models::TwoMotorCat;
use crate::engines::rapier::{RapierError, RapierOptions};
use crate::engines::rapier_check::{rapier_check, EngineFigures, RapierOutcome};
use crate::engines::spin::SpinHistory;
use crate::engines::torque::{peak_torques_from, PeakTorques, TorqueSource};
use crate::engines::Engine;
use crate::exchange::checks::{check, peak_samples, sampling};
use crate::exchange::import::{ImportError, ImportedSchedule, Interpolation};
use crate::exchange::jumps::{rate_jumps_by, uncertain_rate_jumps, Jump};
use crate::problem::Problem;
use crate::schedule::Trajectory;

/// Peak motor torques of one piece (or of consecutive pieces with the same name), N·m.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PiecePeak {
    /// The piece's name.
    pub piece: String,
    /// `max |τ1|`, `max |τ2|` over the piece, N·m.
    pub tau_nm: [f64; 2],
}

/// Peak torques of an imported schedule.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ImportedPeaks {
    /// Per piece, in order; consecutive pieces with the same name are merged.
    pub pieces: Vec<PiecePeak>,
    /// The largest, N·m.
    pub max: f64,
}

/// A joint-rate jump between pieces, named as in `simulate --json`'s `velocity_jumps`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PieceJump {
    /// Time from the schedule's start, s.
    pub time: f64,
    /// The piece that ends there (0-based; the next one starts there).
    pub after_piece: usize,
    /// Joint rates just before, rad/s.
    pub rates_before: [f64; 2],
    /// Joint rates just after, rad/s.
    pub rates_after: [f64; 2],
    /// Generalised impulse `M(q) Δq̇` the joints must deliver, N·m·s.
    pub impulse: [f64; 2],
}

impl From<Jump> for PieceJump {
    fn from(j: Jump) -> Self {
        PieceJump {
            time: j.time_s,
            after_piece: j.after_piece,
            rates_before: j.rates_before_rad_s,
            rates_after: j.rates_after_rad_s,
            impulse: j.impulse_nms,
        }
    }
}

/// A piece boundary whose rate jump could not be judged: the spline's rates at the two sides
/// are too uncertain (a piece of fewer than seven rows).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UncheckedBoundary {
    /// Time from the schedule's start, s.
    pub time: f64,
    /// The two rows of the repeated time.
    pub lines: [u64; 2],
}

/// What the exact engine says an imported schedule does.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ImportReport {
    /// Problem whose cat was used.
    pub problem: String,
    /// The engine that ran it.
    pub engine: Engine,
    /// The schedule file.
    pub schedule_file: String,
    /// Data rows read.
    pub rows: usize,
    /// How rows were interpolated.
    pub interpolation: Interpolation,
    /// Duration, s.
    pub duration_s: f64,
    /// Peak motor torques, N·m.
    pub peak_torque_nm: ImportedPeaks,
    /// Joint-rate jumps between pieces (impulses); empty when the rates are continuous (or
    /// could not be checked: see `velocity_jumps_unchecked`).
    pub velocity_jumps: Vec<PieceJump>,
    /// Piece boundaries where whether the rates jump could not be checked.
    pub velocity_jumps_unchecked: Vec<UncheckedBoundary>,
    /// What looks wrong in the file (units, duration, ends, rates, sampling), in the user's words
    /// with the line or the column; empty when nothing does.
    pub warnings: Vec<String>,
    /// Twist, swing and what the engine says of its own accuracy.
    #[serde(flatten)]
    pub figures: EngineFigures,
}

/// The exact engine's report on an imported schedule, with the checks' warnings; refused when the
/// file cannot be evaluated with this problem or a number cannot be computed.
pub fn evaluate(problem: &Problem, schedule: &ImportedSchedule) -> Result<ImportReport, ImportError> {
    // The paper's cat through the two-cylinder engine, any other two-motor model through the
    // general core.
    let model = TwoMotorCat::new(problem.cat.model())?;
    let mut warnings = check(problem, &model, schedule)?;
    let uncertainty = |k: usize| schedule.boundary_rate_uncertainty(k);
    let start = Instant::now();
    let (f, peaks, history) = measured(problem, &model, schedule);
    let jumps = match model.cat().paper() {
        Some(cat) => uncertain_rate_jumps(cat, schedule, uncertainty),
        None => rate_jumps_by(|q, dq| model.motor_impulse(q, dq), schedule, uncertainty),
    };
    let (spin, samples) = (problem.drop.spin(), problem.exact.torque_samples);
    let momentum = match model.cat().paper() {
        Some(cat) => momentum_check(cat, schedule, history.as_ref(), samples),
        None => momentum_on_model(&model, schedule, &spin, history.as_ref(), samples),
    };
    let run_time_s = start.elapsed().as_secs_f64();
    let pieces = merged(schedule, peaks.per_piece.iter().map(|p| [p[0].value, p[1].value]));
    let not_computable =
        |quantity: &str| ImportError::NotComputable { path: schedule.path.clone(), quantity: quantity.into() };
    let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
    if !finite(&[f.twist, f.swing]) {
        return Err(not_computable("the twist and swing"));
    }
    if !f.error_estimate.is_finite() {
        return Err(not_computable("the twist's error estimate"));
    }
    if !pieces.iter().all(|p| finite(&p.tau_nm)) || !peaks.max.is_finite() {
        return Err(not_computable("the peak torque"));
    }
    if !jumps.iter().all(|j| finite(&j.impulse_nms) && finite(&j.rates_before_rad_s) && finite(&j.rates_after_rad_s)) {
        return Err(not_computable("the rate jumps' impulses"));
    }
    if !momentum.is_finite() {
        return Err(not_computable("the angular momentum"));
    }
    let unchecked = (0..schedule.pieces.len().saturating_sub(1))
        .filter(|&k| !schedule.boundary_rate_uncertainty(k).is_finite())
        .map(|k| UncheckedBoundary {
            time: schedule.piece_durations()[..=k].iter().sum(),
            lines: [schedule.pieces[k].lines.1, schedule.pieces[k + 1].lines.0],
        })
        .collect::<Vec<_>>();
    if !unchecked.is_empty() {
        let lines: Vec<String> = unchecked.iter().map(|u| format!("{}–{}", u.lines[0], u.lines[1])).collect();
        warnings.push(format!(
            "lines {}: whether the rates jump there could not be checked: a piece of fewer than 7 rows is too short for the spline's rates at its ends; give q̇ (columns qd1, qd2) or more rows",
            lines.join(", ")
        ));
    }
    let per_piece: Vec<[f64; 2]> = peaks.per_piece.iter().map(|p| [p[0].value, p[1].value]).collect();
    warnings.extend(sampling(schedule, &per_piece, |coarse| measured(problem, &model, coarse).1));
    Ok(ImportReport {
        problem: problem.name.clone(),
        engine: Engine::Exact,
        schedule_file: schedule.path.clone(),
        rows: schedule.rows,
        interpolation: schedule.interpolation,
        duration_s: schedule.total_duration(),
        peak_torque_nm: ImportedPeaks { pieces, max: peaks.max },
        velocity_jumps: jumps.into_iter().map(PieceJump::from).collect(),
        velocity_jumps_unchecked: unchecked,
        warnings,
        figures: EngineFigures::exact(&f, momentum, peaks.action_reaction_gap, run_time_s),
    })
}

/// An imported trajectory measured on `model` as the problem asks (released with its spin, to its
/// tolerance): the flip, the torque peaks and the orientation history of a spinning release
/// ([`released_flip`] for the paper's cat, [`released_on_model`] for any other).
fn measured(
    problem: &Problem,
    model: &TwoMotorCat,
    traj: &ImportedSchedule,
) -> (Flip, PeakTorques, Option<SpinHistory>) {
    let (spin, tolerance) = (problem.drop.spin(), problem.exact.tolerance);
    let at = peak_samples(traj, problem.exact.torque_samples);
    match model.cat().paper() {
        Some(cat) => {
            let (f, history) = released_flip(cat, traj, &spin, tolerance);
            let peaks = peak_torques_from(&torque_source(cat, history.as_ref()), traj, &at);
            (f, peaks, history)
        }
        None => {
            let (f, history) = released_on_model(model, traj, &spin, tolerance);
            let peaks = peak_torques_from(&TorqueSource::model_released(model, history.as_ref()), traj, &at);
            (f, peaks, history)
        }
    }
}

/// rapier's report on an imported schedule, verified against `exact`, the exact engine's report on
/// the same schedule ([`evaluate`]); [`RapierOutcome::NoResult`] when the verification made no
/// usable run.
pub fn evaluate_rapier(
    problem: &Problem,
    schedule: &ImportedSchedule,
    exact: &ImportReport,
) -> Result<RapierOutcome<ImportReport>, RapierError> {
    let reference = exact.figures.reference(exact.peak_torque_nm.max);
    let outcome = rapier_check(
        &TwoMotorCat::new(problem.cat.model())?,
        schedule,
        &problem.rapier,
        &reference,
        &RapierOptions::for_problem(problem),
    )?;
    Ok(outcome.map(|finest| ImportReport {
        engine: Engine::Rapier,
        peak_torque_nm: ImportedPeaks {
            pieces: merged(schedule, finest.run.peak_torque.per_piece.iter().copied()),
            max: finest.run.peak_torque.max,
        },
        figures: EngineFigures::rapier(finest),
        ..exact.clone()
    }))
}

/// Per-piece peaks `[max |τ1|, max |τ2|]` named by the schedule's pieces; consecutive pieces of
/// one name (a phase cut where its acceleration jumps) are one phase.
fn merged(schedule: &ImportedSchedule, per_piece: impl Iterator<Item = [f64; 2]>) -> Vec<PiecePeak> {
    let mut pieces: Vec<PiecePeak> = Vec::new();
    for (p, tau) in schedule.pieces.iter().zip(per_piece) {
        match pieces.last_mut() {
            Some(last) if last.piece == p.name => {
                last.tau_nm = [last.tau_nm[0].max(tau[0]), last.tau_nm[1].max(tau[1])]
            }
            _ => pieces.push(PiecePeak { piece: p.name.clone(), tau_nm: tau }),
        }
    }
    pieces
}

impl ImportReport {
    /// A short human-readable summary.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{} engine — problem {}, schedule {} ({} rows, {}, {} phase(s), {:.6} s)",
            self.engine,
            self.problem,
            self.schedule_file,
            self.rows,
            self.interpolation,
            self.peak_torque_nm.pieces.len(),
            self.duration_s
        );
        let _ = writeln!(s, "  twist            {:+.9}° (target ±180°)", self.figures.twist_deg);
        let _ = writeln!(s, "  swing            {:.9}° (target 0°)", self.figures.swing_deg);
        let per: Vec<String> = self
            .peak_torque_nm
            .pieces
            .iter()
            .map(|p| format!("{} [{:.4}, {:.4}]", p.piece, p.tau_nm[0], p.tau_nm[1]))
            .collect();
        let _ = writeln!(s, "  peak torque N·m  {}  max {:.4}", per.join("  "), self.peak_torque_nm.max);
        if !self.velocity_jumps_unchecked.is_empty() {
            let at: Vec<String> = self
                .velocity_jumps_unchecked
                .iter()
                .map(|u| format!("t = {:.6} s (lines {}–{})", u.time, u.lines[0], u.lines[1]))
                .collect();
            let _ = writeln!(s, "  velocity jumps   could not check at {}", at.join(", "));
        } else if self.velocity_jumps.is_empty() {
            let _ = writeln!(s, "  velocity jumps   none");
        }
        for j in &self.velocity_jumps {
            let _ = writeln!(
                s,
                "  velocity jump    at t = {:.6} s: q̇ [{:.4}, {:.4}] → [{:.4}, {:.4}] rad/s, impulse [{:.5}, {:.5}] N·m·s",
                j.time,
                j.rates_before[0],
                j.rates_before[1],
                j.rates_after[0],
                j.rates_after[1],
                j.impulse[0],
                j.impulse[1]
            );
        }
        let _ = writeln!(s, "  momentum max     {:.3e} (relative to I*·max|q̇|)", self.figures.momentum_max);
        s.push_str(&self.figures.check.to_text());
        if let Some(e) = self.figures.error_estimate_rad {
            let _ = writeln!(s, "  error estimate   {e:.1e} rad ({} steps per piece)", self.figures.steps);
        }
        if self.figures.converged == Some(false) {
            let _ =
                writeln!(s, "  NOT CONVERGED    the integration did not meet exact.tolerance within its step budget");
        }
        let _ = writeln!(s, "  run time         {:.3} ms", 1e3 * self.figures.run_time_s);
        s
    }
}
