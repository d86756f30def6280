//! What `catflip run` prints in the terminal: the answer first (does the optimum flip the cat,
//! at what torque, against the problem's own schedule, verified or not), then one short table;
//! the prose stays in `report.md`.

use std::fmt::Write;

use crate::engines::rapier::Verification;
use crate::measure::whole::WholeReport;
use crate::report::export::Shown;
use crate::schedule::variant::{Origin, ScheduleName, Variant, WHOLE};

/// The terminal text of a run of the problem whose own profile is `own` and whose best library
/// profile is `best` ([`crate::engines::resolved::Resolved::best_library`]), written to `shown`;
/// `not_run` holds one sentence per part that models the paper's cat only and was not run;
/// `audited` says whether the audit of the paper's numbers was.
pub(super) fn answer(
    own: Origin,
    best: Option<&ScheduleName>,
    verified: &[Shown],
    whole: &WholeReport,
    not_run: &[String],
    audited: bool,
    shown: &str,
) -> String {
    let mut s = String::new();
    let variant = |v: &Shown| v.measured.name.variant();
    let problem = verified.iter().find(|v| variant(v) == Some(Variant::new(own)));
    let verdict = |v: Option<&Verification>| v.map_or("no rapier verification".to_string(), |v| v.verdict.to_string());
    let whole_verification = whole.verification();
    match (whole.measured.as_ref().map(|m| &m.exact), problem) {
        (Some(b), Some(p)) => {
            let own_peak = p.exact.peak_torque_nm.max;
            let _ = writeln!(
                s,
                "The whole-manoeuvre optimum flips the cat (twist {:+.6}°, swing {:.1e}°) with a peak torque of {:.4} N·m, {:.0}× below the problem's own schedule ({:.4} N·m, twist {:+.3}°); rapier: {}.",
                b.twist_deg(),
                b.swing_deg(),
                b.peak(),
                own_peak / b.peak(),
                own_peak,
                p.exact.figures.twist_deg,
                verdict(whole_verification)
            );
        }
        (Some(b), None) => {
            let _ = writeln!(
                s,
                "The whole-manoeuvre optimum flips the cat (twist {:+.6}°, swing {:.1e}°) with a peak torque of {:.4} N·m; rapier: {}.",
                b.twist_deg(),
                b.swing_deg(),
                b.peak(),
                verdict(whole_verification)
            );
        }
        (None, _) => {
            let _ = writeln!(s, "No whole-manoeuvre optimum: {}.", whole.status);
        }
    }
    for line in not_run {
        let _ = writeln!(s, "{line}");
    }
    s.push_str("\n| schedule | twist ° | swing ° | peak N·m | rapier |\n|---|---:|---:|---:|---|\n");
    let optimised = |v: &Shown| variant(v).is_some_and(|x| x.origin.is_optimised());
    let best_library = best.and_then(|b| verified.iter().find(|v| &v.measured.name == b));
    let mut shown_rows: Vec<(String, &Shown)> = Vec::new();
    if let Some(p) = problem {
        shown_rows.push((format!("{} (the problem's)", p.name()), p));
    }
    if let Some(b) = best_library.filter(|b| problem.is_none_or(|p| p.name() != b.name())) {
        shown_rows.push((format!("{} (best library profile)", b.name()), b));
    }
    shown_rows.extend(verified.iter().filter(|v| optimised(v)).map(|v| (v.name(), v)));
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
    if let Some(b) = whole.measured.as_ref().map(|m| &m.exact) {
        let _ = writeln!(
            s,
            "| {WHOLE} | {:+.3} | {:.1e} | {:.4} | {} |",
            b.twist_deg(),
            b.swing_deg(),
            b.peak(),
            whole_verification.map_or("not run".to_string(), |x| x.verdict.status().to_string())
        );
    }
    let what = if audited { "The audit, every table" } else { "Every table" };
    let _ = writeln!(s, "\n{what}, plot and schedule file: {shown}/report.md");
    s
}
