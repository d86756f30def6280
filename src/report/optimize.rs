//! The prose of `catflip optimize`: the profile QP, the exact-dynamics refinement and the whole
//! manoeuvre retimed, as Markdown. A failed calibration reads as failed, never as a number.

use crate::optimize::OptimizeReport;

/// `x` to `digits` decimals, or `calibration failed` when there is none.
fn failed_or(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "calibration failed".to_string(), |v| format!("{v:.digits$}"))
}

impl OptimizeReport {
    /// A readable Markdown summary.
    pub fn to_markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let q = &self.qp;
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
        if let Some(r) = &self.refinement {
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
                "| {} | {:.6} | {:.6}, {:.6} | {:.6} | {:.6} | {:.6} | {} | {} |",
                e.profile,
                e.model_peak_nm,
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
