//! One schedule through an engine: the numbers `catflip simulate` reports (DESIGN.md §8).
//!
//! Twist is signed, right-handed about A's initial spine axis `+z` (towards the head); a
//! successful flip has `|twist| = 180°` and `swing = 0`. Torques are the motor torques on B
//! about joint 1's and joint 2's axes. `momentum_max` is the largest total angular momentum
//! about the centre of mass seen along the motion, relative to a half's typical momentum
//! `I* · max|q̇|` (`I*` the end-transverse inertia).

use std::time::Instant;

use serde::Serialize;

use crate::calibrate::{calibrate, Calibration};
use crate::exact::{body_rate, flip, momentum};
use crate::manoeuvre::Circulation;
use crate::problem::Problem;
use crate::roots::RootStatus;
use crate::schedule::{paper_circulation, Phase, Schedule, ScheduleError};
use crate::torque::{peak_torques, velocity_jumps, PeakTorques, VelocityJump};

/// Why a simulation could not run.
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    /// The schedule cannot be built.
    #[error(transparent)]
    Schedule(#[from] ScheduleError),
    /// Calibration found no circulation that turns the cat by π.
    #[error("manoeuvre.circulation = \"calibrated\": no circulation near the paper's {near:.6} rad turns this cat by π (the search ended: {status:?})")]
    Calibration {
        /// Where the search started, rad.
        near: f64,
        /// How it ended.
        status: RootStatus,
    },
    /// The rapier engine failed.
    #[error(transparent)]
    Rapier(#[from] crate::rapier::RapierError),
}

/// Where a circulation came from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CirculationSource {
    /// The paper's `π/C`.
    Paper,
    /// Calibrated on the exact engine.
    Calibrated,
    /// Given in the problem file.
    Given,
}

/// A circulation and where it came from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ResolvedCirculation {
    /// `∫ω ds`, rad.
    pub radians: f64,
    /// Its source.
    pub source: CirculationSource,
    /// The calibration, when one was run.
    pub calibration: Option<Calibration>,
}

/// Resolves the problem's circulation setting to radians (running the calibration if asked).
pub fn resolve_circulation(problem: &Problem) -> Result<ResolvedCirculation, SimulateError> {
    let paper = || paper_circulation(&problem.cat, problem.manoeuvre.theta());
    Ok(match problem.manoeuvre.circulation {
        Circulation::Paper => {
            ResolvedCirculation { radians: paper()?, source: CirculationSource::Paper, calibration: None }
        }
        Circulation::Angle(a) => {
            ResolvedCirculation { radians: a, source: CirculationSource::Given, calibration: None }
        }
        Circulation::Calibrated => {
            let near = paper()?;
            let cal = calibrate(&problem.cat, &Schedule::new(problem, near), problem.exact.tolerance);
            if cal.status != RootStatus::Converged {
                return Err(SimulateError::Calibration { near, status: cal.status });
            }
            ResolvedCirculation {
                radians: cal.circulation,
                source: CirculationSource::Calibrated,
                calibration: Some(cal),
            }
        }
    })
}

/// Peak torque per phase and joint, N·m.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PhasePeaks {
    /// Bend phase, joints 1 and 2.
    pub bend: [f64; 2],
    /// Twist phase, joints 1 and 2.
    pub twist: [f64; 2],
    /// Unbend phase, joints 1 and 2.
    pub unbend: [f64; 2],
    /// The largest.
    pub max: f64,
}

impl PhasePeaks {
    /// The CSV header of [`PhasePeaks::csv`].
    pub const CSV_HEADER: &'static str =
        "bend_tau1_nm,bend_tau2_nm,twist_tau1_nm,twist_tau2_nm,unbend_tau1_nm,unbend_tau2_nm,max_nm";

    /// The seven values as CSV fields, N·m.
    pub fn csv(&self) -> String {
        self.fields().join(",")
    }

    /// The seven values, formatted, in the order of [`PhasePeaks::CSV_HEADER`], N·m.
    pub fn fields(&self) -> [String; 7] {
        let v = [self.bend[0], self.bend[1], self.twist[0], self.twist[1], self.unbend[0], self.unbend[1], self.max];
        v.map(|x| format!("{x:.9}"))
    }

    /// From per-phase peaks of a three-phase schedule.
    pub fn from_peaks(p: &PeakTorques) -> PhasePeaks {
        let get = |ph: Phase| p.per_piece.get(ph.index()).map_or([f64::NAN; 2], |x| [x[0].value, x[1].value]);
        PhasePeaks { bend: get(Phase::Bend), twist: get(Phase::Twist), unbend: get(Phase::Unbend), max: p.max }
    }
}

/// What one engine says a schedule does.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SimulationReport {
    /// Problem name.
    pub problem: String,
    /// `exact` or `rapier`.
    pub engine: String,
    /// The twist-phase profile.
    pub profile: String,
    /// The bend path.
    pub bend_path: crate::manoeuvre::BendPath,
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
    pub rapier_jumps: Option<Vec<crate::rapier::JumpTorque>>,
    /// First-order Richardson extrapolation to `dt → 0` from runs at `dt` and `dt/2`: twist and
    /// swing in degrees, peak torque in N·m (rapier only; its integrator is first order).
    pub extrapolated: Option<Extrapolation>,
    /// Exact engine's twist minus this engine's, degrees (rapier only).
    pub twist_error_deg: Option<f64>,
    /// Relative error of the peak torque against the exact engine's (rapier only).
    pub peak_torque_rel_error: Option<f64>,
    /// Wall-clock time of the engine run, s.
    pub run_time_s: f64,
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

/// Runs the exact engine on a problem's schedule.
pub fn simulate_exact(problem: &Problem) -> Result<SimulationReport, SimulateError> {
    let circ = resolve_circulation(problem)?;
    let schedule = Schedule::new(problem, circ.radians);
    Ok(exact_report(problem, &schedule, circ))
}

/// The exact engine's report on a given schedule.
pub fn exact_report(problem: &Problem, schedule: &Schedule, circ: ResolvedCirculation) -> SimulationReport {
    let cat = &problem.cat;
    let start = Instant::now();
    let f = flip(cat, schedule, problem.exact.tolerance);
    let peaks = peak_torques(cat, schedule, problem.exact.torque_samples);
    let jumps = velocity_jumps(cat, schedule, JUMP_TOLERANCE);
    let run_time_s = start.elapsed().as_secs_f64();
    SimulationReport {
        problem: problem.name.clone(),
        engine: "exact".into(),
        profile: schedule.profile.name().to_string(),
        bend_path: schedule.path,
        twist_deg: f.twist.to_degrees(),
        swing_deg: f.swing.to_degrees(),
        circulation_rad: circ.radians,
        circulation_source: circ.source,
        calibration: circ.calibration,
        peak_torque_nm: PhasePeaks::from_peaks(&peaks),
        velocity_jumps: jumps,
        momentum_max: momentum_max(problem, schedule),
        dt: None,
        tracking_error_rad: None,
        steps: f.steps_per_phase,
        error_estimate_rad: Some(f.error_estimate),
        converged: Some(f.converged),
        action_reaction_gap_nm: Some(peaks.action_reaction_gap),
        rapier_jumps: None,
        extrapolated: None,
        twist_error_deg: None,
        peak_torque_rel_error: None,
        run_time_s,
    }
}

/// Runs the rapier verification on a problem's schedule, beside the exact engine.
pub fn simulate_rapier(problem: &Problem) -> Result<SimulationReport, SimulateError> {
    let circ = resolve_circulation(problem)?;
    let schedule = Schedule::new(problem, circ.radians);
    rapier_report(problem, &schedule, circ)
}

/// The rapier engine's report on a given schedule, compared with the exact engine's.
pub fn rapier_report(
    problem: &Problem,
    schedule: &Schedule,
    circ: ResolvedCirculation,
) -> Result<SimulationReport, SimulateError> {
    let exact = exact_report(problem, schedule, circ);
    let start = Instant::now();
    let run = crate::rapier::simulate(&problem.cat, schedule, &problem.rapier)?;
    let run_time_s = start.elapsed().as_secs_f64();
    let half = crate::settings::RapierSettings { dt: 0.5 * run.dt, ..problem.rapier };
    let fine = crate::rapier::simulate(&problem.cat, schedule, &half)?;
    let extrapolated = crate::rapier::extrapolate(&run, &fine).map(|x| Extrapolation {
        dt: x.dt,
        twist_deg: x.twist.to_degrees(),
        swing_deg: x.swing.to_degrees(),
        peak_torque_nm: x.peak_torque,
        twist_error_deg: exact.twist_deg - x.twist.to_degrees(),
    });
    let p = &run.peak_torque;
    let peaks = PhasePeaks { bend: p.bend, twist: p.twist, unbend: p.unbend, max: p.max };
    Ok(SimulationReport {
        engine: "rapier".into(),
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
        run_time_s,
        ..exact
    })
}

/// Joint-rate jumps smaller than this, relative to the rates on either side, are round-off.
pub const JUMP_TOLERANCE: f64 = 1e-9;

/// Largest `|H|` of the zero-momentum motion on a fine grid, relative to `I* · max|q̇|`.
pub fn momentum_max(problem: &Problem, schedule: &impl crate::schedule::Trajectory) -> f64 {
    let cat = &problem.cat;
    let n = problem.exact.torque_samples;
    let (mut h_max, mut qd_max) = (0.0f64, 0.0f64);
    for (piece, dur) in schedule.piece_durations().into_iter().enumerate() {
        for k in 0..=n {
            let st = schedule.piece_state(piece, dur * k as f64 / n as f64);
            let w = body_rate(cat, st.q, st.qd);
            h_max = h_max.max(momentum(cat, &st, &w).norm());
            qd_max = qd_max.max(st.qd[0].hypot(st.qd[1]));
        }
    }
    let reference = cat.end_transverse() * qd_max;
    if reference > 0.0 {
        h_max / reference
    } else {
        h_max
    }
}

impl SimulationReport {
    /// A short human-readable summary.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let p = &self.peak_torque_nm;
        let _ = writeln!(
            s,
            "{} engine — problem {}, profile {}, path {:?}",
            self.engine, self.problem, self.profile, self.bend_path
        );
        let _ = writeln!(s, "  circulation      {:.9} rad ({:?})", self.circulation_rad, self.circulation_source);
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
