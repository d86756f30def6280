//! `catflip optimize`: the profile QP, the exact-dynamics refinement and the whole manoeuvre
//! retimed, as Markdown and as JSON ([`OptimizeJson`]; each optimum as a row of the peak-torque
//! table). A failed calibration reads as failed, never as a number.

use serde::Serialize;

use crate::engines::calibrate::Calibration;
use crate::engines::circulation::ResolvedCirculation;
use crate::model::Cylinder;
use crate::numeric::numfmt::above_or_below;
use crate::optimize::qp::ProfileQpSolution;
use crate::optimize::refine::Refinement;
use crate::optimize::{OptimizeReport, Optimum};
use crate::report::compare::CompareRow;

/// `optimize.json` and `catflip optimize --json`: the report with each optimum as a row of the
/// peak-torque table.
#[derive(Clone, Debug, Serialize)]
pub struct OptimizeJson<'a> {
    /// Problem name.
    pub problem: &'a str,
    /// The circulation the profiles realise.
    pub circulation: ResolvedCirculation,
    /// The calibration of this joint path (π exactly when its status is `converged`).
    pub calibration: Calibration,
    /// The profile QP's solve: status, iterations, residuals, gap.
    pub qp: &'a ProfileQpSolution,
    /// The QP's exact discrete optimum when it has a closed form (no limits, no smoothing), N·m.
    pub qp_closed_form_nm: Option<f64>,
    /// The QP optimum (absent when the QP did not solve).
    pub qp_optimum: Option<OptimumJson>,
    /// The exact-dynamics refinement's history.
    pub refinement: Option<&'a Refinement>,
    /// The refined profile.
    pub refined_optimum: Option<OptimumJson>,
    /// Every phase retimed against its exact peak (twist, then bend and unbend).
    pub all_phases: Option<AllPhasesJson<'a>>,
    /// The best library profile by exact twist-phase peak: name and peak, N·m.
    pub best_library: &'a (String, f64),
}

/// One optimum in [`OptimizeJson`].
#[derive(Clone, Debug, Serialize)]
pub struct OptimumJson {
    /// Its row of the peak-torque table on the problem's circulation.
    pub evaluation: CompareRow,
    /// Twist with the calibrated circulation, degrees (absent when the calibration failed).
    pub calibrated_twist_deg: Option<f64>,
    /// Swing with the calibrated circulation, degrees (absent when the calibration failed).
    pub calibrated_swing_deg: Option<f64>,
    /// Node rates, rad/s.
    pub rates: Vec<f64>,
}

/// Every phase retimed, in [`OptimizeJson`].
#[derive(Clone, Debug, Serialize)]
pub struct AllPhasesJson<'a> {
    /// The optimum (the twist phase's node rates as `rates`).
    #[serde(flatten)]
    pub optimum: OptimumJson,
    /// The bend phase's refinement.
    pub bend: &'a Refinement,
    /// The unbend phase's refinement.
    pub unbend: &'a Refinement,
}

impl OptimumJson {
    fn new(problem: &str, rear: &Cylinder, o: &Optimum) -> OptimumJson {
        OptimumJson {
            evaluation: CompareRow::of_schedule(problem, rear, &o.measured),
            calibrated_twist_deg: o.calibrated.map(|f| f.twist.to_degrees()),
            calibrated_swing_deg: o.calibrated.map(|f| f.swing.to_degrees()),
            rates: o.rates.clone(),
        }
    }
}

impl OptimizeReport {
    /// The report as `optimize.json` writes it, on a cat whose rear half is `rear` (the paper's
    /// model's `I*`).
    pub fn to_json(&self, rear: &Cylinder) -> OptimizeJson<'_> {
        let row = |o: &Optimum| OptimumJson::new(&self.problem, rear, o);
        OptimizeJson {
            problem: &self.problem,
            circulation: self.circulation,
            calibration: self.calibration,
            qp: &self.qp,
            qp_closed_form_nm: self.qp_closed_form_nm,
            qp_optimum: self.qp_optimum.as_ref().map(row),
            refinement: self.refinement.as_ref(),
            refined_optimum: self.refined_optimum.as_ref().map(row),
            all_phases: self.all_phases.as_ref().map(|w| AllPhasesJson {
                optimum: row(&w.optimum),
                bend: &w.bend,
                unbend: &w.unbend,
            }),
            best_library: &self.best_library,
        }
    }
}

/// `x` to `digits` decimals, or `calibration failed` when there is none.
fn failed_or(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "calibration failed".to_string(), |v| format!("{v:.digits$}"))
}

impl OptimizeJson<'_> {
    /// A readable Markdown summary.
    pub fn to_markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let q = self.qp;
        let _ = writeln!(s, "## Torque-optimal twist profiles: `{}`\n", self.problem);
        let c = &self.calibration;
        let calibrated = if c.status.is_converged() {
            format!(
                "calibrated circulation (exact flip of π) {:.9} rad ({}, {} evaluations)",
                c.circulation, c.status, c.evaluations
            )
        } else {
            format!(
                "calibration FAILED ({}, {} evaluations): no circulation found that flips by π",
                c.status, c.evaluations
            )
        };
        let _ = writeln!(
            s,
            "Circulation {:.9} rad ({}); {calibrated}.\n",
            self.circulation.radians, self.circulation.source
        );
        let _ = writeln!(
            s,
            "**Profile QP** (paper's model I*·|ω̇|, {} nodes): status {}, {} iterations, {:.3} ms, primal residual {:.1e}, dual residual {:.1e}, duality gap {:.1e}; model peak {} N·m (closed form of the discrete problem: {}).\n",
            q.rates.len(),
            q.status,
            q.info.iterations,
            1e3 * q.info.solve_time_s,
            q.info.primal_residual,
            q.info.dual_residual,
            q.info.duality_gap,
            q.peak_torque.map_or("none".to_string(), |p| format!("{p:.6}")),
            self.qp_closed_form_nm.map_or("none with limits or smoothing".to_string(), |c| format!("{c:.6} N·m"))
        );
        if let Some(r) = self.refinement {
            let accepted = r.iterations.iter().filter(|i| i.accepted).count();
            let _ = writeln!(
                s,
                "**Exact-dynamics refinement**: {} after {} iterations ({} accepted); exact twist-phase peak (dense evaluation) {:.6} → {:.6} N·m.\n",
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
                "| {} | {} | {:.6}, {:.6} | {:.6} | {:.6} | {:.6} | {} | {} |",
                e.profile,
                e.model_peak_nm.map_or("—".to_string(), |m| format!("{m:.6}")),
                e.exact_peak_nm.twist[0],
                e.exact_peak_nm.twist[1],
                e.exact_peak_nm.max,
                e.twist_deg,
                e.swing_deg,
                failed_or(o.calibrated_twist_deg, 9),
                failed_or(o.calibrated_swing_deg, 6)
            );
        }
        if let Some(w) = &self.all_phases {
            let e = &w.optimum.evaluation.exact_peak_nm;
            let _ = writeln!(
                s,
                "\n**All phases retimed** (bend and unbend too, paths unchanged): bend {:.4} → {:.4}, unbend {:.4} → {:.4} N·m ({}, {}); whole-manoeuvre exact peak **{:.4} N·m** (bend [{:.4}, {:.4}], twist [{:.4}, {:.4}], unbend [{:.4}, {:.4}]); twist {:.6}°, calibrated {}°.",
                w.bend.start_peak, w.bend.final_peak, w.unbend.start_peak, w.unbend.final_peak, w.bend.status, w.unbend.status,
                e.max, e.bend[0], e.bend[1], e.twist[0], e.twist[1], e.unbend[0], e.unbend[1],
                w.optimum.evaluation.twist_deg, failed_or(w.optimum.calibrated_twist_deg, 9)
            );
        }
        // Against the problem's motors, when it gives limits (the optima are torque-optimal, not
        // made to fit them: said, as `compare` says it, rather than left to the JSON).
        let optima: Vec<&CompareRow> = [&self.qp_optimum, &self.refined_optimum]
            .into_iter()
            .flatten()
            .chain(self.all_phases.as_ref().map(|w| &w.optimum))
            .map(|o| &o.evaluation)
            .collect();
        if optima.iter().any(|e| e.motors.worst().is_some()) {
            let _ = writeln!(s, "\n**Against the motors** (`[actuator]`):");
            for e in optima {
                let _ = writeln!(s, "- {}: {}", e.profile, e.motors.verdict());
            }
        }
        let (name, peak) = self.best_library;
        let _ = writeln!(s, "\nBest library profile by exact twist-phase peak: {name} ({peak:.6} N·m).");
        if let Some(o) = &self.refined_optimum {
            let t = &o.evaluation.exact_peak_nm.twist;
            let refined = t[0].max(t[1]);
            let _ = writeln!(
                s,
                "The refined profile's exact twist-phase peak is {:.6} N·m: {} the best library profile's.",
                refined,
                above_or_below(refined / peak - 1.0)
            );
        }
        s
    }
}
