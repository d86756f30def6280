//! `catflip simulate`: one schedule through an engine, as a report (DESIGN.md §8).
//!
//! Twist is signed, right-handed about A's initial spine axis `+z` (towards the head); a
//! successful flip has `|twist| = 180°` and `swing = 0`. Torques are the motor torques on B
//! about joint 1's and joint 2's axes. `momentum_max` is the largest total angular momentum
//! about the centre of mass seen along the motion, relative to a half's typical momentum
//! `I* · max|q̇|` (`I*` the end-transverse inertia). The exact numbers are one
//! [`Evaluation`]; rapier's run is reported beside them, with its errors against them.

use serde::Serialize;

use crate::engines::calibrate::Calibration;
use crate::engines::circulation::{CirculationSource, Resolved, ResolvedCirculation};
use crate::engines::evaluate::Evaluation;
use crate::engines::peaks::PhasePeaks;
use crate::engines::rapier::{JumpTorque, Quantity, RapierError, Reference};
use crate::engines::torque::VelocityJump;
use crate::engines::Engine;
use crate::problem::BendPath;
use crate::schedule::{Schedule, Trajectory};

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
    /// Signed twist about A's initial `+z`, degrees.
    pub twist_deg: f64,
    /// Swing of the spine axis, degrees.
    pub swing_deg: f64,
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
    /// Largest angular momentum along the motion relative to `I* · max|q̇|`.
    pub momentum_max: f64,
    /// Time step, s (rapier only).
    pub dt: Option<f64>,
    /// Largest joint tracking error per joint, rad (rapier only).
    pub tracking_error_rad: Option<[f64; 2]>,
    /// Integrator steps per phase (exact) or in all (rapier).
    pub steps: usize,
    /// Estimated error of twist and swing, rad (exact only).
    pub error_estimate_rad: Option<f64>,
    /// Whether the exact integration met `exact.tolerance` (exact only); when false the angles
    /// are not to be trusted to that tolerance.
    pub converged: Option<bool>,
    /// Largest gap between the joint torques from B's and A's sides, N·m (exact only).
    pub action_reaction_gap_nm: Option<f64>,
    /// The motors' torque spikes at rate jumps, as rapier measured them (rapier only).
    pub rapier_jumps: Option<Vec<JumpTorque>>,
    /// First-order Richardson extrapolation to `dt → 0` from runs at `dt` and `dt/2`: twist and
    /// swing in degrees, peak torque in N·m (rapier only; its integrator is first order).
    pub extrapolated: Option<Extrapolation>,
    /// Exact engine's twist minus this engine's, degrees (rapier only).
    pub twist_error_deg: Option<f64>,
    /// Relative error of the peak torque against the exact engine's (rapier only).
    pub peak_torque_rel_error: Option<f64>,
    /// Wall-clock time of the engine run, s.
    pub run_time_s: f64,
    /// How rapier's verification ended (rapier only); its numbers are not to be used without it.
    pub verdict: Option<crate::engines::rapier::Status>,
    /// The verification behind the verdict: dt sequence, raw and extrapolated values, observed
    /// orders, error estimates, tolerances (rapier only).
    pub verification: Option<crate::engines::rapier::Verification>,
}

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

/// `catflip simulate`: the problem's schedule through `engine`.
pub fn simulate(r: &Resolved, engine: Engine) -> Result<SimulationReport, RapierError> {
    let exact = exact_report(r, &r.schedule, r.circulation, None);
    match engine {
        Engine::Exact => Ok(exact),
        Engine::Rapier => rapier_report(r, &r.schedule, &exact),
    }
}

/// The exact engine's report on `schedule` with circulation `circ`, from its evaluation when
/// one was made already (else it is made now).
pub fn exact_report(
    r: &Resolved,
    schedule: &Schedule,
    circ: ResolvedCirculation,
    evaluation: Option<&Evaluation>,
) -> SimulationReport {
    let made;
    let e = match evaluation {
        Some(e) => e,
        None => {
            made = Evaluation::new(r.cat(), schedule, &r.problem.exact);
            &made
        }
    };
    SimulationReport {
        problem: r.problem.name.clone(),
        engine: Engine::Exact,
        profile: schedule.profile.name().to_string(),
        bend_path: schedule.path,
        twist_deg: e.twist_deg(),
        swing_deg: e.swing_deg(),
        circulation_rad: circ.radians,
        circulation_source: circ.source,
        calibration: circ.calibration,
        peak_torque_nm: e.peaks,
        velocity_jumps: e.jumps.clone(),
        momentum_max: e.momentum_max,
        dt: None,
        tracking_error_rad: None,
        steps: e.flip.steps_per_phase,
        error_estimate_rad: Some(e.flip.error_estimate),
        converged: Some(e.flip.converged),
        action_reaction_gap_nm: Some(e.action_reaction_gap),
        rapier_jumps: None,
        extrapolated: None,
        twist_error_deg: None,
        peak_torque_rel_error: None,
        run_time_s: e.run_time_s,
        verdict: None,
        verification: None,
    }
}

/// The rapier engine's report on `schedule`, verified against the exact engine's report `exact`
/// on the same schedule: the time step is refined until rapier's own error estimate meets the
/// tolerances of `[rapier]` ([`crate::engines::rapier::verify`]); the raw numbers are from the
/// finest step, `extrapolated` from the last extrapolation, and `verdict` says whether they agree.
pub fn rapier_report(
    r: &Resolved,
    schedule: &impl Trajectory,
    exact: &SimulationReport,
) -> Result<SimulationReport, RapierError> {
    let reference = Reference {
        twist: exact.twist_deg.to_radians(),
        swing: exact.swing_deg.to_radians(),
        peak_torque: exact.peak_torque_nm.max,
    };
    let v = crate::engines::rapier::verify(r.cat(), schedule, &r.problem.rapier, &reference)?;
    let Some(run) = v.finest.clone() else { return Err(RapierError::NoResult(v.verdict.to_string())) };
    let [twist, swing, peak] = [Quantity::Twist, Quantity::Swing, Quantity::PeakTorque].map(|q| v.quantity(q));
    let extrapolated = match (twist.and_then(|c| c.value), swing.and_then(|c| c.value), peak.and_then(|c| c.value)) {
        (Some(t), Some(s), Some(p)) if v.dt_sequence.len() >= 2 => Some(Extrapolation {
            dt: [v.dt_sequence[v.dt_sequence.len() - 2], run.dt],
            twist_deg: t,
            swing_deg: s,
            peak_torque_nm: p,
            twist_error_deg: exact.twist_deg - t,
        }),
        _ => None,
    };
    let peaks = run.peak_torque.phase_peaks().unwrap_or(PhasePeaks {
        bend: [0.0; 2],
        twist: [0.0; 2],
        unbend: [0.0; 2],
        max: run.peak_torque.max,
    });
    Ok(SimulationReport {
        engine: Engine::Rapier,
        twist_deg: run.twist.to_degrees(),
        swing_deg: run.swing.to_degrees(),
        twist_error_deg: Some(exact.twist_deg - run.twist.to_degrees()),
        peak_torque_rel_error: Some((peaks.max - exact.peak_torque_nm.max) / exact.peak_torque_nm.max),
        peak_torque_nm: peaks,
        momentum_max: run.momentum.max_rel,
        dt: Some(run.dt),
        tracking_error_rad: Some(run.tracking_error),
        steps: run.steps,
        error_estimate_rad: None,
        converged: None,
        action_reaction_gap_nm: None,
        rapier_jumps: Some(run.jumps),
        extrapolated,
        run_time_s: v.run_time_s,
        verdict: Some(v.status),
        verification: Some(v),
        ..exact.clone()
    })
}

impl SimulationReport {
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
        let _ = writeln!(s, "  circulation      {:.9} rad ({})", self.circulation_rad, self.circulation_source);
        let _ = writeln!(s, "  twist            {:+.9}° (target ±180°)", self.twist_deg);
        let _ = writeln!(s, "  swing            {:.9}° (target 0°)", self.swing_deg);
        let _ = writeln!(
            s,
            "  peak torque N·m  bend [{:.4}, {:.4}]  twist [{:.4}, {:.4}]  unbend [{:.4}, {:.4}]  max {:.4}",
            p.bend[0], p.bend[1], p.twist[0], p.twist[1], p.unbend[0], p.unbend[1], p.max
        );
        if self.velocity_jumps.is_empty() {
            let _ = writeln!(s, "  velocity jumps   none");
        }
        for j in &self.velocity_jumps {
            let _ = writeln!(
                s,
                "  velocity jump    at t = {:.6} s: q̇ [{:.4}, {:.4}] → [{:.4}, {:.4}] rad/s, impulse [{:.5}, {:.5}] N·m·s",
                j.time, j.rates_before[0], j.rates_before[1], j.rates_after[0], j.rates_after[1], j.impulse[0], j.impulse[1]
            );
        }
        let _ = writeln!(s, "  momentum max     {:.3e} (relative to I*·max|q̇|)", self.momentum_max);
        if let Some(dt) = self.dt {
            let _ = writeln!(s, "  dt               {dt:e} s");
        }
        if let Some(e) = self.tracking_error_rad {
            let _ = writeln!(s, "  tracking error   [{:.3e}, {:.3e}] rad", e[0], e[1]);
        }
        if let (Some(e), Some(p)) = (self.twist_error_deg, self.peak_torque_rel_error) {
            let _ = writeln!(s, "  vs exact engine  twist {e:+.4e}°, peak torque {:+.3}%", 100.0 * p);
        }
        if let Some(x) = self.extrapolated {
            let _ = writeln!(
                s,
                "  dt → 0 (from {:.2e} s and {:.2e} s): twist {:+.6}°, swing {:.6}°, peak torque {:.4} N·m; vs exact engine twist {:+.4e}°",
                x.dt[0], x.dt[1], x.twist_deg, x.swing_deg, x.peak_torque_nm, x.twist_error_deg
            );
        }
        if let Some(v) = &self.verification {
            let _ = write!(s, "{}", v.to_text());
        }
        if let Some(e) = self.error_estimate_rad {
            let _ = writeln!(s, "  error estimate   {e:.1e} rad ({} steps per phase)", self.steps);
        }
        if self.converged == Some(false) {
            let _ =
                writeln!(s, "  NOT CONVERGED    the integration did not meet exact.tolerance within its step budget");
        }
        let _ = writeln!(s, "  run time         {:.3} ms", 1e3 * self.run_time_s);
        s
    }
}
