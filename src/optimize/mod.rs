//! `catflip optimize`: torque-optimal schedules, checked by the exact engine.
//!
//! 1. The profile QP on the paper's model `I* |ω̇|` (Clarabel), with the problem's boundary
//!    conditions and limits; its closed form with rest-to-rest ends is bang-bang,
//!    `4 D I*/T²`.
//! 2. The exact-dynamics refinement of the twist phase ([`mod@crate::optimize::refine`]) started from the QP's
//!    optimum.
//! 3. The same refinement of the bend and the unbend, started from the paper's harmonic timing:
//!    the whole manoeuvre retimed along the problem's joint path.
//!
//! Each result is reported with its peak torque in the paper's model and in the exact dynamics
//! (per phase, per joint), and with the exact twist and swing for the problem's circulation and
//! for the calibrated one (the calibrated circulation depends on the joint path only, so one
//! calibration serves every profile).
//!
//! Every optimiser here (the profile QP, the refinement's step, the retiming, the whole
//! manoeuvre) calls Clarabel through one layer, [`conic`]: its settings, its statuses, the sparse
//! assembly and the solve. That layer imports none of them.

pub mod conic;
pub mod qp;
pub mod refine;
pub mod retime;
pub mod whole;

use crate::engines::calibrate::Calibration;
use crate::engines::circulation::ResolvedCirculation;
use crate::engines::exact::{flip, Flip};
use crate::engines::measured::Measured;
use crate::engines::resolved::Resolved;
use crate::schedule::profile::Profile;
use crate::schedule::variant::{Origin, Variant};
use crate::schedule::{Phase, Schedule};
use conic::ConicError;
use qp::{ProfileQp, ProfileQpSolution, QpError};
use refine::{rate_nodes, refine, with_phase_profile, Refinement};

/// Why optimisation could not run.
#[derive(Debug, thiserror::Error)]
pub enum OptimizeError {
    /// The problem asks for what this computation does not model.
    #[error(transparent)]
    Problem(#[from] crate::problem::ProblemError),
    /// The profile QP's data was refused, or it has no solution.
    #[error(transparent)]
    Qp(#[from] QpError),
    /// A refinement step's data was refused.
    #[error(transparent)]
    Conic(#[from] ConicError),
}

/// One optimised profile, measured.
#[derive(Clone, Debug)]
pub struct Optimum {
    /// The schedule on the problem's circulation, named by its variant, measured there.
    pub measured: Measured<Schedule>,
    /// Its flip with the calibrated circulation (absent when the calibration failed).
    pub calibrated: Option<Flip>,
    /// Node rates, rad/s.
    pub rates: Vec<f64>,
}

impl Optimum {
    /// Which schedule it is.
    pub fn variant(&self) -> Variant {
        // Every optimum is named by its variant (`optimize` below).
        self.measured.name.variant().unwrap_or_else(|| Variant::new(Origin::Qp))
    }

    /// The schedule itself, on the problem's circulation.
    pub fn schedule(&self) -> &Schedule {
        &self.measured.trajectory
    }
}

/// The schedule with all three phases retimed against their exact peaks: the joint path (and so
/// the flip) is the problem's; only the timing of bend, twist and unbend changes.
#[derive(Clone, Debug)]
pub struct AllPhasesRefinement {
    /// Its measurement (the twist phase's node rates as `rates`).
    pub optimum: Optimum,
    /// The bend phase's refinement.
    pub bend: Refinement,
    /// The unbend phase's refinement.
    pub unbend: Refinement,
}

/// Everything `catflip optimize` reports ([`crate::report::optimize`] renders it).
#[derive(Clone, Debug)]
pub struct OptimizeReport {
    /// Problem name.
    pub problem: String,
    /// The circulation the profiles realise.
    pub circulation: ResolvedCirculation,
    /// The calibration of this joint path (π exactly when its status is `converged`).
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
    pub all_phases: Option<AllPhasesRefinement>,
    /// The best library profile by exact twist-phase peak: name and peak, N·m.
    pub best_library: (String, f64),
}

/// Runs the profile QP and the exact refinement on a resolved problem.
pub fn optimize(r: &Resolved) -> Result<OptimizeReport, OptimizeError> {
    r.require_paper_cat("optimize (the profile QP and the refinements)")?;
    let problem = &r.problem;
    let base = &r.schedule;
    let t2 = base.durations[Phase::Twist.index()];
    let qp_data = ProfileQp::new(&problem.optimize, t2, r.circulation.radians, problem.cat.half().end_transverse());
    let qp = qp_data.solve()?.solved()?;
    let calibrated = r.calibrated();
    // A schedule on the problem's circulation, measured there, with its flip at the calibrated one.
    let evaluate = |s: Schedule, origin: Origin, rates: Vec<f64>| {
        let calibrated =
            calibrated.map(|c| flip(&problem.cat.half(), &s.with_circulation(c.radians), problem.exact.tolerance));
        Optimum { measured: r.measure(Variant::new(origin).into(), s), calibrated, rates }
    };
    let qp_optimum = qp.to_profile().map(|p| evaluate(base.with_profile(p), Origin::Qp, qp.rates.clone()));
    let refinement = if qp.status.is_solved() {
        Some(refine(&problem.cat.half(), &problem.exact, &problem.optimize, base, Phase::Twist, &qp.rates)?)
    } else {
        None
    };
    let refined_optimum = refinement
        .as_ref()
        .and_then(|f| f.to_profile().map(|p| evaluate(base.with_profile(p), Origin::Refined, f.rates.clone())));
    // Beyond the twist: retime the bend and the unbend too (their paths stay, so does the flip).
    let mut all_phases = None;
    let whole_twist = refinement
        .as_ref()
        .and_then(|f| Profile::from_rate_nodes(Origin::RefinedAllPhases.profile_name(), &f.rates).map(|p| (p, f)));
    if let Some((twist, twist_refinement)) = whole_twist {
        let s = base.with_profile(twist);
        // A phase's torques depend on its own timing only (the joint state at its start is the
        // path's), so the bend and the unbend are refined independently, in parallel.
        let refine_phase = |phase: Phase| {
            let start = rate_nodes(
                &Profile::harmonic(),
                s.progress_distance(phase),
                s.durations[phase.index()],
                problem.optimize.nodes,
            );
            refine(&problem.cat.half(), &problem.exact, &problem.optimize, &s, phase, &start)
        };
        let (bend, unbend) = rayon::join(|| refine_phase(Phase::Bend), || refine_phase(Phase::Unbend));
        let (bend, unbend) = (bend?, unbend?);
        let mut s = s;
        for (phase, f) in [(Phase::Bend, &bend), (Phase::Unbend, &unbend)] {
            if let Some(p) = f.to_profile() {
                s = with_phase_profile(&s, phase, p);
            }
        }
        let optimum = evaluate(s, Origin::RefinedAllPhases, twist_refinement.rates.clone());
        all_phases = Some(AllPhasesRefinement { optimum, bend, unbend });
    }
    let best_library = r.best_library().map_or((String::new(), f64::INFINITY), |(k, m)| {
        (k.name().to_string(), m.exact.phase_peaks().phase_max(Phase::Twist))
    });
    Ok(OptimizeReport {
        problem: problem.name.clone(),
        circulation: r.circulation,
        calibration: *r.calibration(),
        qp_closed_form_nm: qp_data.closed_form_peak(),
        qp,
        qp_optimum,
        refinement,
        refined_optimum,
        all_phases,
        best_library,
    })
}

impl OptimizeReport {
    /// The optimised schedules, evaluated: QP, refined, every phase refined (those that exist).
    pub fn optima(&self) -> impl Iterator<Item = &Optimum> {
        [self.qp_optimum.as_ref(), self.refined_optimum.as_ref(), self.all_phases.as_ref().map(|w| &w.optimum)]
            .into_iter()
            .flatten()
    }
}
