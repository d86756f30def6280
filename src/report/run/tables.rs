//! The tables and the summary of `catflip run`: verification CSV and Markdown, the report's summary lines.

use std::fmt::Write as _;

use crate::engines::rapier::{Quantity, Verdict, Verification};
use crate::engines::resolved::Resolved;
use crate::problem::Problem;
use crate::report::export::{Shown, Views};
use crate::report::optimize::OptimizeJson;
use crate::report::simulate::SimulationReport;
use crate::schedule::variant::Origin;
use crate::schedule::Phase;

/// The report's summary of the run's `views`; `not_run` holds one sentence per part that models
/// the paper's cat only and was not run ([`crate::measure::run::PaperOnly`]), `optimum` the whole
/// optimum's lines.
pub(super) fn summary(r: &Resolved, views: &Views, not_run: &[String], optimum: &str) -> String {
    let (table, verified) = (views.table, views.verified);
    let problem = &r.problem;
    let mut s = String::new();
    let _ = writeln!(s, "## Summary\n");
    let own = Origin::Library(problem.manoeuvre.profile);
    if let Some(p) = table.rows.iter().find(|row| row.origin == own.name() && row.profile == own.profile_name()) {
        let verdict = if (p.twist_deg.abs() - 180.0).abs() < 1e-6 { "a half turn" } else { "not a half turn" };
        let _ = writeln!(
            s,
            "- The problem's schedule ({} profile, {} path, circulation {:.6} rad, {}) turns the cat by **{:.6}°** with a swing of {:.6}° (exact engine): {verdict}.",
            p.profile, problem.manoeuvre.bend_path, table.circulation.radians, table.circulation.source, p.twist_deg, p.swing_deg
        );
        let e = &p.exact_peak_nm;
        let model = p
            .model_peak_nm
            .map_or(String::new(), |m| format!("; the paper's model I*·max|ω̇| gives {m:.4} N·m for the twist"));
        let _ = writeln!(
            s,
            "- Its exact peak torque is **{:.4} N·m** (bend {:.4}, twist {:.4}, unbend {:.4}){model}.",
            e.max,
            e.phase_max(Phase::Bend),
            e.phase_max(Phase::Twist),
            e.phase_max(Phase::Unbend),
        );
        if p.velocity_jumps > 0 {
            let _ = writeln!(
                s,
                "- It has {} velocity jump(s): an impulse of up to {:.4} N·m·s, not a torque.",
                p.velocity_jumps, p.max_impulse_nms
            );
        }
        let m = &p.motors;
        let _ = writeln!(
            s,
            "- Its motors must reach {:.4} rad/s and {:.4} W (peak joint speed and mechanical power); with the problem's motors: {}.",
            m.max_speed(),
            m.max_power(),
            m.verdict()
        );
    }
    let c = r.calibration();
    if c.status.is_converged() {
        // A swing that rounds to zero at the shown digits (Kane and Scher's symmetric cat has
        // none) needs no second control.
        let swing = c.swing.to_degrees();
        let remains = if swing < 5e-7 {
            format!("no swing remains ({swing:.1e}°): this cat's flip needs no more than the circulation")
        } else {
            format!("the swing, {swing:.6}°, is what remains: one circulation cannot also zero it")
        };
        let _ = writeln!(
            s,
            "- The calibrated circulation {:.9} rad makes the twist exactly 180° ({:.9}°; {}); {remains}.",
            c.circulation,
            c.twist.to_degrees(),
            c.status
        );
    } else {
        let _ = writeln!(
            s,
            "- The calibration FAILED ({}, {} evaluations): no circulation near {:.9} rad was found that turns this cat by exactly 180°, so no calibrated schedule is reported.",
            c.status, c.evaluations, r.circulation.radians
        );
    }
    if let Some(opt) = views.optimize {
        profile_qp_lines(&mut s, opt);
    }
    for line in not_run {
        let _ = writeln!(s, "- {line}");
    }
    let _ = writeln!(s, "{}", rapier_line(problem, verified));
    let _ = writeln!(
        s,
        "- Verdicts: {}.",
        Verification::verdicts_line(verified.iter().map(|v| (v.name(), v.verification())))
    );
    s.push_str(optimum);
    let tables: Vec<String> = [
        ("audit.md", views.audit.is_some()),
        ("compare.md", true),
        ("optimize.md", views.optimize.is_some()),
        ("whole.md", true),
        ("retime.md", true),
        ("verification.md", true),
    ]
    .into_iter()
    .filter(|(_, written)| *written)
    .map(|(f, _)| format!("`{f}`"))
    .collect();
    let (last, rest) = tables.split_last().map_or(("", &[][..]), |(l, r)| (l.as_str(), r));
    let _ = writeln!(s, "\nSee {} and {last} for the tables.", rest.join(", "));
    s
}

/// The summary's lines on the profile QP and its refinements.
fn profile_qp_lines(s: &mut String, opt: &OptimizeJson) {
    let closed = opt.qp_closed_form_nm.map_or("none with limits".to_string(), |c| format!("{c:.6}"));
    let _ = writeln!(
        s,
        "- Profile QP: {}, model peak {} N·m (closed form {closed}).",
        opt.qp.status,
        opt.qp.peak_torque.map_or("none".to_string(), |p| format!("{p:.6}"))
    );
    if let Some(o) = &opt.refined_optimum {
        let t = o.evaluation.exact_peak_nm.twist;
        let _ = writeln!(
            s,
            "- Exact-dynamics refinement: exact twist-phase peak {:.4} N·m against {:.4} N·m for the best library profile ({}); the whole manoeuvre's peak is then {:.4} N·m (bend and unbend are not retimed).",
            t[0].max(t[1]),
            opt.best_library.1,
            opt.best_library.0,
            o.evaluation.exact_peak_nm.max
        );
    }
    if let Some(w) = &opt.all_phases {
        let e = &w.optimum.evaluation.exact_peak_nm;
        let _ = writeln!(
            s,
            "- Retiming the bend and the unbend too (same joint path, same flip): the whole manoeuvre's exact peak falls to **{:.4} N·m** (bend {:.4}, twist {:.4}, unbend {:.4}).",
            e.max,
            e.phase_max(Phase::Bend),
            e.phase_max(Phase::Twist),
            e.phase_max(Phase::Unbend)
        );
    }
}

/// The summary's line on rapier: how close its results extrapolated to `dt → 0` (what the verdicts
/// judge) came to the exact engine's and for how many schedules, how far its finest runs' raw
/// twist moved (its momentum leak, or motors that saturated), and how many schedules it has no
/// result for. A schedule without an extrapolation (a saturated motor, too few runs) adds no
/// number to the first part: a missing number is said, never shown as zero.
fn rapier_line(problem: &Problem, verified: &[Shown]) -> String {
    let reports: Vec<&SimulationReport> = verified.iter().filter_map(|v| v.rapier.report()).collect();
    let missing = verified.len() - reports.len();
    let s = format!("- rapier3d-f64 verification of {} schedules (first dt {})", verified.len(), problem.rapier.dt);
    let gap = |v: &Shown, q: Quantity| v.verification().and_then(|x| x.quantity(q)).and_then(|c| c.gap);
    let judged: Vec<(f64, f64)> =
        verified.iter().filter_map(|v| Some((gap(v, Quantity::Twist)?, gap(v, Quantity::PeakTorque)?))).collect();
    let saturated = verified
        .iter()
        .filter(|v| v.verification().is_some_and(|x| matches!(x.verdict, Verdict::Saturated { .. })))
        .count();
    let mut parts: Vec<String> = Vec::new();
    if !reports.is_empty() {
        parts.push(if judged.is_empty() {
            "no schedule has a result extrapolated to dt → 0 (see `verification.md`)".to_string()
        } else {
            let of = if judged.len() < verified.len() {
                format!(" (the {} of them with one)", judged.len())
            } else {
                String::new()
            };
            format!(
                "extrapolated to dt → 0, as the verdicts judge, twist within {} and peak torques within {} of the exact engine{of}",
                Quantity::Twist.format_gap(judged.iter().map(|j| j.0).fold(0.0, f64::max)),
                Quantity::PeakTorque.format_gap(judged.iter().map(|j| j.1).fold(0.0, f64::max))
            )
        });
        let raw = reports.iter().filter_map(|r| r.figures.check.twist_error_deg).map(f64::abs).fold(0.0, f64::max);
        let why = if saturated > 0 {
            format!("a motor saturated in {saturated} of them, and rapier's first-order momentum leak")
        } else {
            "rapier's first-order momentum leak".to_string()
        };
        parts.push(format!("the finest runs' raw twist differs from the exact engine's by up to {raw:.3}° ({why})"));
    }
    if missing > 0 {
        parts.push(format!(
            "rapier has no result for {missing} of them (inconclusive: no usable run; see `verification.md`)"
        ));
    }
    if parts.is_empty() {
        format!("{s}.")
    } else {
        format!("{s}: {}.", parts.join("; "))
    }
}
