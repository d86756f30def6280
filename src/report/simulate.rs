//! `catflip simulate`: one schedule through an engine, as a report (DESIGN.md §8).
//!
//! Twist is signed, right-handed about A's initial spine axis `+z` (towards the head); a
//! successful flip has `|twist| = 180°` and `swing = 0`. Torques are the motor torques on B
//! about joint 1's and joint 2's axes. `momentum_max` is the largest total angular momentum
//! about the centre of mass seen along the motion, relative to a half's typical momentum
//! `I* · max|q̇|` (`I*` the end-transverse inertia); released with spin `L`
//! (`angular_momentum_nms`), the exact engine's is the largest `|R H − L|`, relative to
//! `max(I* · max|q̇|, |L|)`, and rapier's the drift of `H` from its start. The exact numbers are one
//! measured schedule's ([`Measured`], [`crate::measure::simulate`]); rapier's run is reported
//! beside them, with its errors against them.

use serde::Serialize;

use crate::engines::calibrate::Calibration;
use crate::engines::circulation::CirculationSource;
use crate::engines::jumps::VelocityJump;
use crate::engines::measured::Measured;
use crate::engines::motors::{LimitUse, MotorDemand};
use crate::engines::peaks::PhasePeaks;
use crate::engines::rapier::RapierError;
use crate::engines::resolved::Resolved;
use crate::engines::Engine;
use crate::problem::BendPath;
use crate::schedule::Schedule;

pub use crate::engines::rapier_check::{EngineFigures, Extrapolation, Finest, RapierCheck, RapierOutcome};

/// What one engine says a schedule does.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SimulationReport {
    /// Problem name.
    pub problem: String,
    /// The engine that ran it.
    pub engine: Engine,
    /// The twist-phase profile.
    pub profile: String,
    /// The bend path.
    pub bend_path: BendPath,
    /// The cat when it is not the paper's (its joint and halves, in words).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// The release spin: total angular momentum about the centre of mass, world frame, N·m·s
    /// (`drop.angular_momentum`; zero for a release without spin).
    pub angular_momentum_nms: [f64; 3],
    /// The circulation `∫ω ds`, rad.
    pub circulation_rad: f64,
    /// Where the circulation came from.
    pub circulation_source: CirculationSource,
    /// The calibration, if one was run.
    pub calibration: Option<Calibration>,
    /// Peak motor torques per phase and joint, N·m.
    pub peak_torque_nm: PhasePeaks,
    /// Joint-rate jumps (impulses); empty when the schedule is smooth.
    pub velocity_jumps: Vec<VelocityJump>,
    /// What the schedule asks of its motors, by the exact engine: peak speed and power per joint,
    /// each `[actuator]` limit's worst usage, and the verdict in words.
    pub motors: MotorReport,
    /// Twist, swing and what the engine says of its own accuracy.
    #[serde(flatten)]
    pub figures: EngineFigures,
}

/// `catflip simulate`: the problem's schedule measured ([`crate::measure::simulate::simulate`]) and
/// reported by `engine`.
pub fn simulate(r: &Resolved, engine: Engine) -> Result<SimulationReport, RapierError> {
    let measured = crate::measure::simulate::simulate(r, engine)?;
    SimulationReport::of(r, &measured, engine)
}

impl SimulationReport {
    /// The exact engine's report of `m`, one of `r`'s schedules: on the problem's circulation, or
    /// on the calibrated one when its variant says so.
    pub fn exact(r: &Resolved, m: &Measured<Schedule>) -> SimulationReport {
        let (schedule, e) = (&m.trajectory, &m.exact);
        let calibrated = m.name.variant().is_some_and(|v| v.is_calibrated());
        let circ = if calibrated { r.calibrated().unwrap_or(r.circulation) } else { r.circulation };
        SimulationReport {
            problem: r.problem.name.clone(),
            engine: Engine::Exact,
            profile: schedule.profile.name().to_string(),
            bend_path: schedule.path,
            model: r.model().cat().paper().is_none().then(|| r.model().cat().describe()),
            angular_momentum_nms: r.problem.drop.angular_momentum,
            circulation_rad: schedule.circulation,
            circulation_source: circ.source,
            calibration: circ.calibration,
            peak_torque_nm: e.phase_peaks(),
            velocity_jumps: e.jumps.clone(),
            motors: MotorReport::new(&e.motors),
            figures: EngineFigures::exact(e),
        }
    }

    /// rapier's report of `m` beside `exact`, the exact engine's report of it; its outcome
    /// without a usable run ([`RapierOutcome::NoResult`]); an error when `m` was not verified.
    pub fn rapier(
        m: &Measured<Schedule>,
        exact: &SimulationReport,
    ) -> Result<RapierOutcome<SimulationReport>, RapierError> {
        let outcome = m.rapier.clone().ok_or_else(|| RapierError::NoResult("not verified in rapier".into()))?;
        match outcome {
            RapierOutcome::NoResult(v) => Ok(RapierOutcome::NoResult(v)),
            RapierOutcome::Report(finest) => {
                // A schedule has its three phases in rapier's run too.
                let peaks = finest.run.peak_torque.phase_peaks().ok_or_else(|| {
                    RapierError::NoResult(format!(
                        "rapier's run has {} pieces, not the schedule's three phases",
                        finest.run.peak_torque.per_piece.len()
                    ))
                })?;
                Ok(RapierOutcome::Report(SimulationReport {
                    engine: Engine::Rapier,
                    peak_torque_nm: peaks,
                    figures: EngineFigures::rapier(finest),
                    ..exact.clone()
                }))
            }
        }
    }

    /// The report of `engine` on the measured schedule `m` (verified when `engine` is rapier);
    /// rapier without a usable run is an error ([`RapierError::NoResult`]).
    pub fn of(r: &Resolved, m: &Measured<Schedule>, engine: Engine) -> Result<SimulationReport, RapierError> {
        let exact = SimulationReport::exact(r, m);
        match engine {
            Engine::Exact => Ok(exact),
            Engine::Rapier => SimulationReport::rapier(m, &exact)?.into_report(),
        }
    }
}

impl SimulationReport {
    /// Why the engine's numbers are not a result, when they are not: rapier's verification
    /// ended inconclusive (its runs did not converge as `dt → 0`), or the exact integration missed
    /// its tolerance.
    pub fn unconverged(&self) -> Option<String> {
        use crate::engines::rapier::Status;
        if self.figures.check.verdict == Some(Status::Inconclusive) {
            return Some(
                "rapier's verification is inconclusive (its runs did not converge as dt → 0): the twist, swing and torques below are its unconverged estimates, not a result (see the verdict)".into(),
            );
        }
        (self.figures.converged == Some(false)).then(|| {
            "the exact integration missed exact.tolerance: the angles below are not to be trusted to it".into()
        })
    }

    /// A short human-readable summary.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let p = &self.peak_torque_nm;
        let _ = writeln!(
            s,
            "{} engine — problem {}, profile {}, path {}",
            self.engine, self.problem, self.profile, self.bend_path
        );
        if let Some(line) = self.unconverged() {
            let _ = writeln!(s, "  NO RESULT        {line}");
        }
        if let Some(m) = &self.model {
            let _ = writeln!(s, "  cat              {m}");
        }
        s.push_str(&spin_line(&self.angular_momentum_nms));
        let _ = writeln!(s, "  circulation      {:.9} rad ({})", self.circulation_rad, self.circulation_source);
        let _ = writeln!(s, "  twist            {:+.9}° (target ±180°)", self.figures.twist_deg);
        let _ = writeln!(s, "  swing            {:.9}° (target 0°)", self.figures.swing_deg);
        let (b, t, u, note) = (p.bend, p.twist, p.unbend, self.figures.peaks_note());
        let _ = writeln!(
            s,
            "  peak torque N·m  bend [{:.4}, {:.4}]  twist [{:.4}, {:.4}]  unbend [{:.4}, {:.4}]  max {:.4}{note}",
            b[0], b[1], t[0], t[1], u[0], u[1], p.max
        );
        s.push_str(&self.motors.to_text());
        if self.velocity_jumps.is_empty() {
            let _ = writeln!(s, "  velocity jumps   none");
        }
        for j in &self.velocity_jumps {
            s.push_str(&crate::report::check::jump_line(j));
        }
        s.push_str(&momentum_line(self.figures.momentum_max, &self.angular_momentum_nms, self.engine));
        s.push_str(&self.figures.closing_text("phase"));
        s
    }
}

/// The motor figures of a simulation report (JSON `motors`): the exact engine's, whatever engine
/// ran the schedule.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MotorReport {
    /// Peak `|q̇|` of joints 1 and 2, rad/s.
    pub peak_speed_rad_s: [f64; 2],
    /// Peak `|τ q̇|` of joints 1 and 2, W.
    pub peak_power_w: [f64; 2],
    /// Each `[actuator]` limit's worst usage ratio (at most 1 within), joint and time.
    pub limits: Vec<LimitUse>,
    /// Whether every limit holds (true with ideal motors).
    pub within: bool,
    /// The verdict in words.
    pub verdict: String,
}

/// The release-spin line of a report's text; empty for a release without spin.
pub(crate) fn spin_line(l: &[f64; 3]) -> String {
    if l.iter().all(|c| *c == 0.0) {
        return String::new();
    }
    format!("  release spin     L = [{}, {}, {}] N·m·s (world frame)\n", l[0], l[1], l[2])
}

/// The momentum line of a report's text: `momentum_max` and what it is relative to, which
/// depends on the release spin `l` and on the engine (module docs).
pub(crate) fn momentum_line(momentum_max: f64, l: &[f64; 3], engine: Engine) -> String {
    let spins = l.iter().any(|c| *c != 0.0);
    let scale = match (spins, engine) {
        (true, Engine::Exact) => "|R H − L|, relative to max(I*·max|q̇|, |L|)",
        (true, Engine::Rapier) => "drift of H from its start, relative to I*·max|q̇|",
        (false, _) => "relative to I*·max|q̇|",
    };
    format!("  momentum max     {momentum_max:.3e} ({scale})\n")
}

impl MotorReport {
    /// The report's motor lines: peak speed and power per joint, and the verdict.
    pub fn to_text(&self) -> String {
        format!(
            "  peak speed       [{:.4}, {:.4}] rad/s   peak power [{:.4}, {:.4}] W\n  motors           {}\n",
            self.peak_speed_rad_s[0],
            self.peak_speed_rad_s[1],
            self.peak_power_w[0],
            self.peak_power_w[1],
            self.verdict
        )
    }

    /// From the exact engine's measurement.
    pub fn new(m: &MotorDemand) -> Self {
        MotorReport {
            peak_speed_rad_s: std::array::from_fn(|j| m.peak_speed_rad_s[j].value),
            peak_power_w: std::array::from_fn(|j| m.peak_power_w[j].value),
            limits: m.limits.clone(),
            within: m.within(),
            verdict: m.verdict(),
        }
    }
}
