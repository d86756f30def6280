//! `catflip optimize`: torque-optimal schedules, checked by the exact engine.
//!
//! 1. The profile QP on the paper's model `I* |ω̇|` (Clarabel), with the problem's boundary
//!    conditions and limits; its closed form with rest-to-rest ends is bang-bang,
//!    `4 D I*/T²`.
//! 2. The exact-dynamics refinement of the twist phase ([`crate::refine`]) started from the QP's
//!    optimum.
//! 3. The same refinement of the bend and the unbend, started from the paper's harmonic timing:
//!    the whole manoeuvre retimed along the problem's joint path.
//!
//! Each result is reported with its peak torque in the paper's model and in the exact dynamics
//! (per phase, per joint), and with the exact twist and swing for the problem's circulation and
//! for the calibrated one (the calibrated circulation depends on the joint path only, so one
//! calibration serves every profile).

pub mod whole;

use serde::Serialize;

use crate::calibrate::{calibrate, Calibration};
use crate::compare::{row, CompareRow};
use crate::exact::flip;
use crate::problem::Problem;
use crate::profile::Profile;
use crate::qp::{ProfileQp, ProfileQpSolution, QpError};
use crate::refine::{phase_distance, rate_nodes, refine, retimed, Refinement};
use crate::schedule::{Phase, Schedule};
use crate::simulate::{resolve_circulation, ResolvedCirculation, SimulateError};

/// Why optimisation could not run.
#[derive(Debug, thiserror::Error)]
pub enum OptimizeError {
    /// The schedule or circulation could not be resolved.
    #[error(transparent)]
    Simulate(#[from] SimulateError),
    /// A QP's data was refused.
    #[error(transparent)]
    Qp(#[from] QpError),
}

/// One optimised profile, evaluated.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Optimum {
    /// The evaluation on the problem's circulation (a peak-torque table row).
    pub evaluation: CompareRow,
    /// Twist with the calibrated circulation, degrees.
    pub calibrated_twist_deg: f64,
    /// Swing with the calibrated circulation, degrees.
    pub calibrated_swing_deg: f64,
    /// Node rates, rad/s.
    pub rates: Vec<f64>,
}

/// Name of the twist profile of the schedule with every phase retimed.
pub const WHOLE: &str = "exact-refined-all-phases";

/// The schedule with all three phases retimed against their exact peaks: the joint path (and so
/// the flip) is the problem's; only the timing of bend, twist and unbend changes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WholeRetiming {
    /// Its evaluation (the twist phase's node rates as `rates`).
    #[serde(flatten)]
    pub optimum: Optimum,
    /// The bend phase's refinement.
    pub bend: Refinement,
    /// The unbend phase's refinement.
    pub unbend: Refinement,
    /// The schedule itself.
    #[serde(skip)]
    pub schedule: Schedule,
}

/// Everything `catflip optimize` reports.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OptimizeReport {
    /// Problem name.
    pub problem: String,
    /// The circulation the profiles realise.
    pub circulation: ResolvedCirculation,
    /// The calibration of this joint path (π exactly).
    pub calibration: Calibration,
    /// The profile QP's solve: status, iterations, residuals, gap.
    pub qp: ProfileQpSolution,
    /// The QP's exact discrete optimum when it has a closed form (no limits, no smoothing), N·m.
    pub qp_closed_form_nm: Option<f64>,
    /// The QP optimum, evaluated (absent when the QP did not solve).
    pub qp_optimum: Option<Optimum>,
    /// The exact-dynamics refinement's history.
    pub refinement: Option<Refinement>,
    /// The refined profile, evaluated.
    pub refined_optimum: Option<Optimum>,
    /// Every phase retimed against its exact peak (twist, then bend and unbend).
    pub whole: Option<WholeRetiming>,
    /// The best library profile by exact twist-phase peak: name and peak, N·m.
    pub best_library: (String, f64),
}

/// Runs the profile QP and the exact refinement on a problem.
pub fn optimize(problem: &Problem) -> Result<OptimizeReport, OptimizeError> {
    let circulation = resolve_circulation(problem)?;
    let base = Schedule::new(problem, circulation.radians);
    let t2 = base.durations[1];
    let inertia = problem.cat.end_transverse();
    let qp_data = ProfileQp::new(&problem.optimize, t2, circulation.radians, inertia);
    let qp = qp_data.solve()?;
    let calibration = match circulation.calibration {
        Some(c) => c,
        None => calibrate(&problem.cat, &base, problem.exact.tolerance),
    };
    // A schedule on the problem's circulation, evaluated there and with the calibrated one.
    let evaluate = |s: &Schedule, origin: &str, rates: Vec<f64>| {
        let f = flip(&problem.cat, &s.with_circulation(calibration.circulation), problem.exact.tolerance);
        Optimum {
            evaluation: row(problem, s, origin),
            calibrated_twist_deg: f.twist.to_degrees(),
            calibrated_swing_deg: f.swing.to_degrees(),
            rates,
        }
    };
    let qp_optimum = qp.to_profile().map(|p| evaluate(&base.with_profile(p), "qp", qp.rates.clone()));
    let refinement = if qp.status.is_solved() { Some(refine(problem, &base, Phase::Twist, &qp.rates)?) } else { None };
    let refined_optimum = refinement
        .as_ref()
        .and_then(|r| r.to_profile().map(|p| evaluate(&base.with_profile(p), "refined", r.rates.clone())));
    // Beyond the twist: retime the bend and the unbend too (their paths stay, so does the flip).
    let mut whole = None;
    if let Some(twist) = refinement.as_ref().and_then(|r| Profile::from_rate_nodes(WHOLE, &r.rates)) {
        let mut s = base.with_profile(twist);
        let mut phases = Vec::new();
        for phase in [Phase::Bend, Phase::Unbend] {
            let start = rate_nodes(
                &Profile::harmonic(),
                phase_distance(&s, phase),
                s.durations[phase.index()],
                problem.optimize.nodes,
            );
            let r = refine(problem, &s, phase, &start)?;
            if let Some(p) = r.to_profile() {
                s = retimed(&s, phase, p);
            }
            phases.push(r);
        }
        let rates = refinement.as_ref().map_or_else(Vec::new, |r| r.rates.clone());
        whole = Some(WholeRetiming {
            optimum: evaluate(&s, "refined-all-phases", rates),
            bend: phases.remove(0),
            unbend: phases.remove(0),
            schedule: s,
        });
    }
    let best_library = crate::manoeuvre::ProfileKind::ALL
        .iter()
        .map(|&k| {
            let r = row(problem, &base.with_profile(Profile::library(k)), "library");
            (r.profile, r.exact_peak_nm.twist[0].max(r.exact_peak_nm.twist[1]))
        })
        .fold((String::new(), f64::INFINITY), |best, r| if r.1 < best.1 { r } else { best });
    Ok(OptimizeReport {
        problem: problem.name.clone(),
        circulation,
        calibration,
        qp_closed_form_nm: qp_data.closed_form_peak(),
        qp,
        qp_optimum,
        refinement,
        refined_optimum,
        whole,
        best_library,
    })
}

impl OptimizeReport {
    /// A readable Markdown summary.
    pub fn to_markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let q = &self.qp;
        let _ = writeln!(s, "## Torque-optimal twist profiles: `{}`\n", self.problem);
        let _ = writeln!(
            s,
            "Circulation {:.9} rad ({:?}); calibrated circulation (exact flip of π) {:.9} rad ({:?}, {} evaluations).\n",
            self.circulation.radians,
            self.circulation.source,
            self.calibration.circulation,
            self.calibration.status,
            self.calibration.evaluations
        );
        let _ = writeln!(
            s,
            "**Profile QP** (paper's model I*·|ω̇|, {} nodes): status {:?}, {} iterations, {:.3} ms, primal residual {:.1e}, dual residual {:.1e}, duality gap {:.1e}; model peak {:.6} N·m (closed form of the discrete problem: {}).\n",
            q.rates.len(),
            q.status,
            q.info.iterations,
            1e3 * q.info.solve_time_s,
            q.info.primal_residual,
            q.info.dual_residual,
            q.info.duality_gap,
            q.peak_torque,
            self.qp_closed_form_nm.map_or("none with limits or smoothing".to_string(), |c| format!("{c:.6} N·m"))
        );
        if let Some(r) = &self.refinement {
            let accepted = r.iterations.iter().filter(|i| i.accepted).count();
            let _ = writeln!(
                s,
                "**Exact-dynamics refinement**: {:?} after {} iterations ({} accepted); exact twist-phase peak (dense evaluation) {:.6} → {:.6} N·m.\n",
                r.status,
                r.iterations.len(),
                accepted,
                r.start_peak,
                r.final_peak
            );
        }
        let _ = writeln!(s, "| profile | model peak N·m | exact twist-phase peak τ1, τ2 N·m | exact max (all phases) N·m | twist ° (problem's circulation) | swing ° | twist ° (calibrated) | swing ° (calibrated) |");
        let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|---:|---:|");
        for o in [&self.qp_optimum, &self.refined_optimum].into_iter().flatten() {
            let e = &o.evaluation;
            let _ = writeln!(
                s,
                "| {} | {:.6} | {:.6}, {:.6} | {:.6} | {:.6} | {:.6} | {:.9} | {:.6} |",
                e.profile,
                e.model_peak_nm,
                e.exact_peak_nm.twist[0],
                e.exact_peak_nm.twist[1],
                e.exact_peak_nm.max,
                e.twist_deg,
                e.swing_deg,
                o.calibrated_twist_deg,
                o.calibrated_swing_deg
            );
        }
        if let Some(w) = &self.whole {
            let e = &w.optimum.evaluation.exact_peak_nm;
            let _ = writeln!(
                s,
                "\n**All phases retimed** (bend and unbend too, paths unchanged): bend {:.4} → {:.4}, unbend {:.4} → {:.4} N·m ({:?}, {:?}); whole-manoeuvre exact peak **{:.4} N·m** (bend [{:.4}, {:.4}], twist [{:.4}, {:.4}], unbend [{:.4}, {:.4}]); twist {:.6}°, calibrated {:.9}°.",
                w.bend.start_peak, w.bend.final_peak, w.unbend.start_peak, w.unbend.final_peak, w.bend.status, w.unbend.status,
                e.max, e.bend[0], e.bend[1], e.twist[0], e.twist[1], e.unbend[0], e.unbend[1],
                w.optimum.evaluation.twist_deg, w.optimum.calibrated_twist_deg
            );
        }
        let (name, peak) = &self.best_library;
        let _ = writeln!(s, "\nBest library profile by exact twist-phase peak: {name} ({peak:.6} N·m).");
        if let Some(o) = &self.refined_optimum {
            let t = &o.evaluation.exact_peak_nm.twist;
            let refined = t[0].max(t[1]);
            let _ = writeln!(
                s,
                "The refined profile's exact twist-phase peak is {:.6} N·m: {:.1}% below the best library profile's.",
                refined,
                100.0 * (1.0 - refined / peak)
            );
        }
        s
    }
}
