//! The tables and the summary of `catflip run`: verification CSV and Markdown, the report's summary lines.

use std::fmt::Write as _;

use super::Verified;
use crate::engines::circulation::Resolved;
use crate::engines::peaks::PhasePeaks;
use crate::optimize::OptimizeReport;
use crate::problem::Problem;
use crate::report::compare::CompareTable;
use crate::report::simulate::SimulationReport;
use crate::schedule::variant::Origin;
use crate::schedule::Phase;

pub(super) fn verification_csv(rows: &[Verified]) -> String {
    let mut header = vec!["problem", "schedule", "engine", "circulation_rad", "twist_deg", "swing_deg"];
    header.extend(PhasePeaks::CSV_HEADER.split(','));
    header.extend(["momentum_max", "dt_s", "tracking1_rad", "tracking2_rad", "run_time_s"]);
    header.extend(crate::engines::rapier::Verification::CSV_HEADER.split(','));
    let mut all: Vec<(String, &SimulationReport)> =
        rows.iter().flat_map(|v| [(v.variant.to_string(), &v.exact), (v.variant.to_string(), &v.rapier)]).collect();
    all.sort_by(|a, b| (&a.0, a.1.engine).cmp(&(&b.0, b.1.engine)));
    let records = all.into_iter().map(|(name, r)| {
        let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:.6e}"));
        let tr = r.tracking_error_rad;
        let mut f = vec![
            r.problem.clone(),
            name,
            r.engine.to_string(),
            format!("{:.12}", r.circulation_rad),
            format!("{:.9}", r.twist_deg),
            format!("{:.9}", r.swing_deg),
        ];
        f.extend(r.peak_torque_nm.fields());
        f.extend([
            format!("{:.3e}", r.momentum_max),
            opt(r.dt),
            opt(tr.map(|t| t[0])),
            opt(tr.map(|t| t[1])),
            format!("{:.6}", r.run_time_s),
        ]);
        f.extend(r.verification.as_ref().map_or_else(|| vec![String::new(); 7], |v| v.fields().to_vec()));
        f
    });
    crate::exchange::table::csv_table(&header, records)
}

pub(super) fn verification_markdown(problem: &Problem, rows: &[Verified]) -> String {
    let mut s = format!(
        "## Verification in rapier3d-f64 (`{}`, first dt {})\n\nEvery schedule of the peak-torque table, through the exact engine and rapier. Twist and swing in degrees; torques in N·m; momentum relative to I*·max|q̇|.\n\n",
        problem.name, problem.rapier.dt
    );
    s.push_str("rapier's multibody integrator is first order and leaks angular momentum at a rate proportional to dt, which moves the twist; *rapier → 0* is the Richardson extrapolation from the last two steps of the dt sequence, and *estimates* are rapier's own errors of the extrapolated twist, swing and peak torque (the change between the last two extrapolations). The rapier columns are from the finest step.\n\n");
    if let Some(v) = rows.iter().find_map(|v| v.rapier.verification.as_ref()) {
        let _ =
            writeln!(s, "Tolerances: {}; budget {} rapier steps per schedule.\n", v.tolerances_text(), v.step_budget);
    }
    s.push_str("| schedule | exact twist | rapier twist | rapier → 0 twist | exact swing | rapier swing | rapier → 0 swing | exact peak | rapier peak | peak diff | rapier momentum drift | tracking error rad | verdict | dt sequence s | estimates | rapier time s |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---|---:|\n");
    for v in rows {
        let (e, r) = (&v.exact, &v.rapier);
        let tr = r.tracking_error_rad.unwrap_or([f64::NAN; 2]);
        let (xt, xs) = r.extrapolated.map_or((f64::NAN, f64::NAN), |x| (x.twist_deg, x.swing_deg));
        let _ = writeln!(
            s,
            "| {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.3} | {:.3} | {:+.2}% | {:.2e} | {:.1e}, {:.1e} | {} |",
            v.variant,
            e.twist_deg,
            r.twist_deg,
            xt,
            e.swing_deg,
            r.swing_deg,
            xs,
            e.peak_torque_nm.max,
            r.peak_torque_nm.max,
            100.0 * (r.peak_torque_nm.max / e.peak_torque_nm.max - 1.0),
            r.momentum_max,
            tr[0],
            tr[1],
            r.verification.as_ref().map_or("— | — | — | —".to_string(), |x| x.table_cells())
        );
    }
    s
}

pub(super) fn summary(
    r: &Resolved,
    table: &CompareTable,
    opt: &OptimizeReport,
    verified: &[Verified],
    optimum: &str,
) -> String {
    let problem = &r.problem;
    let mut s = String::new();
    let _ = writeln!(s, "## Summary\n");
    let own = Origin::Library(problem.manoeuvre.profile);
    if let Some(p) = table.rows.iter().find(|row| row.origin == own && row.profile == own.profile_name()) {
        let verdict = if (p.twist_deg.abs() - 180.0).abs() < 1e-6 { "a half turn" } else { "not a half turn" };
        let _ = writeln!(
            s,
            "- The problem's schedule ({} profile, {} path, circulation {:.6} rad, {}) turns the cat by **{:.6}°** with a swing of {:.6}° (exact engine): {verdict}.",
            p.profile, problem.manoeuvre.bend_path, p.circulation_rad, table.circulation.source, p.twist_deg, p.swing_deg
        );
        let e = &p.exact_peak_nm;
        let _ = writeln!(
            s,
            "- Its exact peak torque is **{:.4} N·m** (bend {:.4}, twist {:.4}, unbend {:.4}); the paper's model I*·max|ω̇| gives {:.4} N·m for the twist.",
            e.max,
            e.phase_max(Phase::Bend),
            e.phase_max(Phase::Twist),
            e.phase_max(Phase::Unbend),
            p.model_peak_nm
        );
        if p.velocity_jumps > 0 {
            let _ = writeln!(
                s,
                "- It has {} velocity jump(s): an impulse of up to {:.4} N·m·s, not a torque.",
                p.velocity_jumps, p.max_impulse_nms
            );
        }
    }
    let c = &opt.calibration;
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
    if let Some(w) = &opt.whole {
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
    let worst = verified.iter().map(|v| (v.exact.twist_deg - v.rapier.twist_deg).abs()).fold(0.0, f64::max);
    let worst_x =
        verified.iter().filter_map(|v| v.rapier.extrapolated).map(|x| x.twist_error_deg.abs()).fold(0.0, f64::max);
    let worst_peak = verified.iter().filter_map(|v| v.rapier.peak_torque_rel_error).map(f64::abs).fold(0.0, f64::max);
    let _ = writeln!(
        s,
        "- rapier3d-f64 verification of {} schedules (first dt {}): peak torques within {:.2}% of the exact engine; twist within {:.3}° raw (rapier's first-order momentum leak) and {:.3}° extrapolated to dt → 0.",
        verified.len(),
        problem.rapier.dt,
        100.0 * worst_peak,
        worst,
        worst_x
    );
    let _ = writeln!(
        s,
        "- Verdicts: {}.",
        crate::engines::rapier::Verification::verdicts_line(
            verified.iter().map(|v| (v.variant.to_string(), v.rapier.verification.as_ref()))
        )
    );
    s.push_str(optimum);
    let _ = writeln!(
        s,
        "\nSee `audit.md`, `compare.md`, `optimize.md`, `whole.md`, `retime.md` and `verification.md` for the tables."
    );
    s
}
