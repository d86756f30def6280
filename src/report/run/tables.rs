//! The tables and the summary of `catflip run`: verification CSV and Markdown, the report's summary lines.

use std::fmt::Write as _;

use crate::engines::rapier::Verification;
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
        let _ = writeln!(
            s,
            "- The calibrated circulation {:.9} rad makes the twist exactly 180° ({:.9}°; {}); the swing, {:.6}°, is what remains: one circulation cannot also zero it.",
            c.circulation,
            c.twist.to_degrees(),
            c.status,
            c.swing.to_degrees()
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

/// The summary's line on rapier: how close its results came to the exact engine's, and how many
/// schedules it has no result for.
fn rapier_line(problem: &Problem, verified: &[Shown]) -> String {
    let reports: Vec<&SimulationReport> = verified.iter().filter_map(|v| v.rapier.report()).collect();
    let missing = verified.len() - reports.len();
    let mut s = format!("- rapier3d-f64 verification of {} schedules (first dt {})", verified.len(), problem.rapier.dt);
    if !reports.is_empty() {
        let worst = reports.iter().filter_map(|r| r.figures.check.twist_error_deg).map(f64::abs).fold(0.0, f64::max);
        let worst_x = reports
            .iter()
            .filter_map(|r| r.figures.check.extrapolated)
            .map(|x| x.twist_error_deg.abs())
            .fold(0.0, f64::max);
        let worst_peak =
            reports.iter().filter_map(|r| r.figures.check.peak_torque_rel_error).map(f64::abs).fold(0.0, f64::max);
        let of = if missing > 0 { format!(" (of the {} with a result)", reports.len()) } else { String::new() };
        let _ = write!(
            s,
            ": peak torques{of} within {:.2}% of the exact engine; twist within {:.3}° raw (rapier's first-order momentum leak) and {:.3}° extrapolated to dt → 0",
            100.0 * worst_peak,
            worst,
            worst_x
        );
    }
    if missing > 0 {
        let sep = if reports.is_empty() { ":" } else { ";" };
        let _ = write!(
            s,
            "{sep} rapier has no result for {missing} of them (inconclusive: no usable run; see `verification.md`)"
        );
    }
    s.push('.');
    s
}
