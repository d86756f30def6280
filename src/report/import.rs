//! `catflip simulate PROBLEM --schedule FILE.csv`: an imported schedule's measurement
//! ([`crate::measure::import`]) as a report, the exact engine's or rapier's.
//!
//! The same quantities as [`crate::report::simulate::SimulationReport`] where they apply: the
//! release spin, signed twist about A's initial `+z` and swing (degrees), peak motor torques per
//! piece and joint and overall (N·m), what they ask of the motors (peak speed and power, each
//! `[actuator]` limit's usage, the verdict), the rate jumps between pieces with their impulses,
//! the largest angular momentum (relative as `simulate`'s is), and the engine's error estimate.
//! An imported schedule has no profile or circulation; it has a file, a row count and an
//! interpolation scheme. rapier's report has its own twist, swing, per-piece peaks and momentum
//! drift, and beside them the
//! [`crate::engines::rapier_check::RapierCheck`] of every rapier report (step, tracking error,
//! `dt → 0`, errors against the exact engine on the same imported schedule, verdict).

use serde::Serialize;

use crate::engines::jumps::VelocityJump;
use crate::engines::rapier::RapierError;
use crate::engines::rapier_check::{EngineFigures, RapierOutcome};
use crate::engines::Engine;
use crate::exchange::import::{ImportError, ImportedSchedule, Interpolation};
use crate::measure::import::{measure_import, MeasuredImport, UncheckedBoundary};
use crate::problem::Problem;
use crate::report::simulate::{momentum_line, spin_line, MotorReport};
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
    /// The release spin: total angular momentum about the centre of mass, world frame, N·m·s
    /// (`drop.angular_momentum`; zero for a release without spin).
    pub angular_momentum_nms: [f64; 3],
    /// Peak motor torques, N·m.
    pub peak_torque_nm: ImportedPeaks,
    /// Joint-rate jumps between pieces (impulses); empty when the rates are continuous (or
    /// could not be checked: see `velocity_jumps_unchecked`).
    pub velocity_jumps: Vec<VelocityJump>,
    /// Piece boundaries where whether the rates jump could not be checked.
    pub velocity_jumps_unchecked: Vec<UncheckedBoundary>,
    /// What the schedule asks of its motors, by the exact engine: peak speed and power per joint,
    /// each `[actuator]` limit's worst usage, and the verdict in words.
    pub motors: MotorReport,
    /// What looks wrong in the file (units, duration, ends, rates, sampling), in the user's words
    /// with the line or the column; empty when nothing does.
    pub warnings: Vec<String>,
    /// Twist, swing and what the engine says of its own accuracy.
    #[serde(flatten)]
    pub figures: EngineFigures,
}

/// Why an imported schedule has no report: the file cannot be evaluated with the problem, or
/// rapier cannot run it (or made no usable run).
#[derive(Debug, thiserror::Error)]
pub enum ImportReportError {
    /// The file cannot be evaluated with this problem.
    #[error(transparent)]
    Import(#[from] ImportError),
    /// rapier cannot run it, or made no usable run.
    #[error(transparent)]
    Rapier(#[from] RapierError),
}

/// `catflip simulate PROBLEM --schedule FILE.csv [--engine rapier]`: `schedule` measured on the
/// problem's cat ([`measure_import`]), verified in rapier when `engine` is rapier, as `engine`'s
/// report.
pub fn simulate_import(
    problem: &Problem,
    schedule: ImportedSchedule,
    engine: Engine,
) -> Result<ImportReport, ImportReportError> {
    let mut measured = measure_import(problem, schedule)?;
    if engine == Engine::Rapier {
        measured.verify()?;
    }
    Ok(ImportReport::of(&problem.name, &measured, engine)?)
}

/// The exact engine's report of `schedule` on `problem`'s cat ([`simulate_import`] with the
/// exact engine).
pub fn evaluate(problem: &Problem, schedule: &ImportedSchedule) -> Result<ImportReport, ImportError> {
    Ok(ImportReport::exact(&problem.name, &measure_import(problem, schedule.clone())?))
}

impl ImportReport {
    /// The exact engine's report of the measured file `m` (problem `problem`).
    pub fn exact(problem: &str, m: &MeasuredImport) -> ImportReport {
        let (schedule, e) = (&m.measured.trajectory, &m.measured.exact);
        let per_piece = e.peaks.per_piece.iter().map(|p| [p[0].value, p[1].value]);
        ImportReport {
            problem: problem.to_string(),
            engine: Engine::Exact,
            schedule_file: schedule.path.clone(),
            rows: schedule.rows,
            interpolation: schedule.interpolation,
            duration_s: schedule.total_duration(),
            angular_momentum_nms: m.rig.spin.into(),
            peak_torque_nm: ImportedPeaks { pieces: merged(schedule, per_piece), max: e.peaks.max },
            velocity_jumps: e.jumps.clone(),
            velocity_jumps_unchecked: m.unchecked.clone(),
            motors: MotorReport::new(&e.motors),
            warnings: m.warnings.clone(),
            figures: EngineFigures::exact(e),
        }
    }

    /// The report of `engine` on the measured file `m` of problem `problem` (verified when
    /// `engine` is rapier: [`MeasuredImport::verify`]); rapier without a usable run is an error
    /// ([`RapierError::NoResult`]).
    pub fn of(problem: &str, m: &MeasuredImport, engine: Engine) -> Result<ImportReport, RapierError> {
        let exact = ImportReport::exact(problem, m);
        match engine {
            Engine::Exact => Ok(exact),
            Engine::Rapier => ImportReport::rapier(m, &exact)?.into_report(),
        }
    }

    /// rapier's report of the verified file `m` beside `exact`, the exact engine's report of it;
    /// [`RapierOutcome::NoResult`] when the verification made no usable run,
    /// [`RapierError::NoResult`] when `m` was not verified.
    pub fn rapier(m: &MeasuredImport, exact: &ImportReport) -> Result<RapierOutcome<ImportReport>, RapierError> {
        let outcome = m.measured.rapier.clone().ok_or_else(|| RapierError::NoResult("not verified".into()))?;
        let schedule = &m.measured.trajectory;
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
        s.push_str(&spin_line(&self.angular_momentum_nms));
        let _ = writeln!(s, "  twist            {:+.9}° (target ±180°)", self.figures.twist_deg);
        let _ = writeln!(s, "  swing            {:.9}° (target 0°)", self.figures.swing_deg);
        let per: Vec<String> = self
            .peak_torque_nm
            .pieces
            .iter()
            .map(|p| format!("{} [{:.4}, {:.4}]", p.piece, p.tau_nm[0], p.tau_nm[1]))
            .collect();
        let _ = writeln!(
            s,
            "  peak torque N·m  {}  max {:.4}{}",
            per.join("  "),
            self.peak_torque_nm.max,
            self.figures.peaks_note()
        );
        s.push_str(&self.motors.to_text());
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
            s.push_str(&crate::report::check::jump_line(j));
        }
        s.push_str(&momentum_line(self.figures.momentum_max, &self.angular_momentum_nms, self.engine));
        s.push_str(&self.figures.closing_text("piece"));
        s
    }
}
