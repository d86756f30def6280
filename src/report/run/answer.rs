//! What `catflip run` prints in the terminal: the answer first (does the optimum flip the cat,
//! at what torque, against the problem's own schedule, verified or not), then one short table;
//! the prose stays in `report.md`.

use std::fmt::Write;

use super::Verified;
use crate::engines::rapier::Verification;
use crate::report::whole::{WholeReport, WHOLE};
use crate::schedule::variant::Origin;

/// The terminal text of a run of the problem whose own profile is `own`, written to `shown`.
pub(super) fn answer(
    own: Origin,
    verified: &[Verified],
    whole: &WholeReport,
    whole_verification: Option<&Verification>,
    shown: &str,
) -> String {
    let mut s = String::new();
    let problem = verified.iter().find(|v| v.variant.origin == own && !v.variant.is_calibrated());
    let verdict = |v: Option<&Verification>| v.map_or("no rapier verification".to_string(), |v| v.verdict.to_string());
    match (whole.best(), problem) {
        (Some(b), Some(p)) => {
            let own_peak = p.exact.peak_torque_nm.max;
            let _ = writeln!(
                s,
                "The whole-manoeuvre optimum flips the cat (twist {:+.6}°, swing {:.1e}°) with a peak torque of {:.4} N·m, {:.0}× below the problem's own schedule ({:.4} N·m, twist {:+.3}°); rapier: {}.",
                b.twist.to_degrees(),
                b.swing.to_degrees(),
                b.peak_torque_nm,
                own_peak / b.peak_torque_nm,
                own_peak,
                p.exact.figures.twist_deg,
                verdict(whole_verification)
            );
        }
        (Some(b), None) => {
            let _ = writeln!(
                s,
                "The whole-manoeuvre optimum flips the cat (twist {:+.6}°, swing {:.1e}°) with a peak torque of {:.4} N·m; rapier: {}.",
                b.twist.to_degrees(),
                b.swing.to_degrees(),
                b.peak_torque_nm,
                verdict(whole_verification)
            );
        }
        (None, _) => {
            let _ = writeln!(s, "No whole-manoeuvre optimum: {}.", whole.status);
        }
    }
    s.push_str("\n| schedule | twist ° | swing ° | peak N·m | rapier |\n|---|---:|---:|---:|---|\n");
    let best_library = verified
        .iter()
        .filter(|v| !v.variant.origin.is_optimised() && !v.variant.is_calibrated())
        .min_by(|a, b| a.exact.peak_torque_nm.max.total_cmp(&b.exact.peak_torque_nm.max));
    let mut shown_rows: Vec<(String, &Verified)> = Vec::new();
    if let Some(p) = problem {
        shown_rows.push((format!("{} (the problem's)", p.variant), p));
    }
    if let Some(b) = best_library.filter(|b| problem.is_none_or(|p| p.variant != b.variant)) {
        shown_rows.push((format!("{} (best library profile)", b.variant), b));
    }
    shown_rows.extend(verified.iter().filter(|v| v.variant.origin.is_optimised()).map(|v| (v.variant.to_string(), v)));
    for (name, v) in shown_rows {
        let f = &v.exact.figures;
        let _ = writeln!(
            s,
            "| {name} | {:+.3} | {:.3} | {:.4} | {} |",
            f.twist_deg,
            f.swing_deg,
            v.exact.peak_torque_nm.max,
            v.verification().map_or("no result".to_string(), |x| x.verdict.status().to_string())
        );
    }
    if let Some(b) = whole.best() {
        let _ = writeln!(
            s,
            "| {WHOLE} | {:+.3} | {:.1e} | {:.4} | {} |",
            b.twist.to_degrees(),
            b.swing.to_degrees(),
            b.peak_torque_nm,
            whole_verification.map_or("not run".to_string(), |x| x.verdict.status().to_string())
        );
    }
    let _ = writeln!(s, "\nThe audit, every table, plot and schedule file: {shown}/report.md");
    s
}
