//! The summary's comparison of schedules: per case the exact peak torque of each schedule
//! (library, certified retiming with its lower bound, whole-manoeuvre optimum) and which is
//! lowest, and the count of rapier's verdicts per schedule.

use std::fmt::Write as _;

use super::cases::cell;
use super::heatmap::short;
use super::row::SweepSchedule;
use super::spec::Sweep;
use super::table::Record;
use crate::engines::Engine;

/// At most this many rows in one table, and grids per quantity.
pub const MAX_ROWS: usize = 60;

/// The schedules compared, in row order, with the peak a row shows for them.
fn schedules(sweep: &Sweep) -> Vec<SweepSchedule> {
    let c = &sweep.compute;
    let mut s = Vec::new();
    if c.peaks && c.paper_flip {
        s.push(SweepSchedule::Paper);
    }
    if c.peaks && c.calibrated {
        s.push(SweepSchedule::Calibrated);
    }
    if c.retiming {
        s.push(SweepSchedule::Retimed);
    }
    if c.whole {
        s.push(SweepSchedule::Whole);
    }
    s
}

/// "## Peak torque by schedule": one line per case (written only when an optimiser ran).
pub fn by_schedule(s: &mut String, sweep: &Sweep, records: &[Record]) {
    let c = &sweep.compute;
    if !(c.retiming || c.whole) {
        return;
    }
    let names = schedules(sweep);
    let _ = writeln!(
        s,
        "## Peak torque by schedule\n\nThe exact peak `max |τ|` (N·m) of each schedule per case; `retimed` is the calibrated schedule (`*`: the paper's, the calibration having failed) timed by the certified convex retiming, `bound` the certified lower bound of its discrete program (finer grids lower it); `whole` the whole-manoeuvre optimum; — where the row has no result (see its status in `sweep.csv`); `†` a schedule beyond the case's motors (`within_motors` false in `sweep.csv`), never the `lowest`, which is the lowest within them.\n"
    );
    let mut head = String::from("| case |");
    for a in &sweep.axes {
        let _ = write!(head, " `{}` |", a.field);
    }
    for n in &names {
        let _ = write!(head, " {n} |");
        if *n == SweepSchedule::Retimed {
            head.push_str(" bound |");
        }
    }
    let _ = writeln!(s, "{head} lowest |");
    let extra = names.len() + usize::from(c.retiming);
    let _ = writeln!(s, "|---:|{}{}---|", "---|".repeat(sweep.axes.len()), "---:|".repeat(extra));
    let exact: Vec<&Record> = records.iter().filter(|r| r.engine == Engine::Exact).collect();
    let mut cases: Vec<usize> = exact.iter().map(|r| r.case).collect();
    cases.dedup();
    for &k in cases.iter().take(MAX_ROWS) {
        let rows: Vec<&&Record> = exact.iter().filter(|r| r.case == k).collect();
        let Some(first) = rows.first() else { continue };
        let mut line = format!("| {k} |");
        for (a, &p) in sweep.axes.iter().zip(&first.picks) {
            let _ = write!(line, " {} |", cell(&a.values[p]));
        }
        let mut lowest: Option<(SweepSchedule, f64)> = None;
        let mut any = false;
        for n in &names {
            let r = rows.iter().find(|r| r.schedule == *n);
            let peak = r.and_then(|r| r.peak_max()).filter(|p| p.is_finite());
            let mark = if r.is_some_and(|r| r.labels.retimed_from == Some(SweepSchedule::Paper)) { "*" } else { "" };
            let beyond =
                r.and_then(|r| r.numbers).and_then(|x| x.motors).and_then(|m| m.worst).is_some_and(|w| !w.within());
            let dagger = if beyond && peak.is_some() { "†" } else { "" };
            let _ = write!(line, " {}{mark}{dagger} |", peak.map_or_else(|| "—".to_string(), short));
            if *n == SweepSchedule::Retimed {
                let bound = r.and_then(|r| r.numbers).and_then(|x| x.retiming).map(|x| x.lower_bound_nm);
                let _ = write!(line, " {} |", bound.map_or_else(|| "—".to_string(), short));
            }
            any |= peak.is_some();
            if let Some(p) = peak.filter(|_| !beyond) {
                if lowest.is_none_or(|(_, b)| p < b) {
                    lowest = Some((*n, p));
                }
            }
        }
        let none = if any { "— (none within the motors)" } else { "—" };
        let _ = writeln!(s, "{line} {} |", lowest.map_or(none, |(n, _)| n.name()));
    }
    if cases.len() > MAX_ROWS {
        let _ = writeln!(s, "\n({} more cases in `sweep.csv`.)", cases.len() - MAX_ROWS);
    }
    s.push('\n');
}

/// "## Rapier's verdicts": how many rows of each schedule rapier verified, did not verify, or
/// could not judge (written only when rapier ran).
pub fn verdicts(s: &mut String, sweep: &Sweep, records: &[Record]) {
    if !sweep.compute.rapier {
        return;
    }
    let _ = writeln!(
        s,
        "## Rapier's verdicts\n\nRows of each schedule by rapier's verdict against the exact engine (twist, swing, peak torque within the `[rapier]` tolerances; `rapier.step_budget` bounds the steps, no wall-clock budget); `no verdict` counts rapier rows that rapier could not judge at all (no exact result to verify, or rapier could not run; see their reasons); a verification without a usable run is `inconclusive` (its row is `failed`: it has no numbers).\n\n| schedule | verified | not verified | inconclusive | no verdict |\n|---|---:|---:|---:|---:|"
    );
    let mut order: Vec<SweepSchedule> = Vec::new();
    for r in records.iter().filter(|r| r.engine == Engine::Rapier) {
        if !order.contains(&r.schedule) {
            order.push(r.schedule);
        }
    }
    for name in order {
        let rows: Vec<&Record> = records.iter().filter(|r| r.engine == Engine::Rapier && r.schedule == name).collect();
        // A verification that made no usable run has a verdict (inconclusive) but no numbers: it
        // counts by its verdict, as in `catflip run`.
        let word = |w: &str| rows.iter().filter(|r| r.labels.rapier_verdict.starts_with(w)).count();
        let none = rows.iter().filter(|r| r.labels.rapier_verdict.is_empty()).count();
        let _ = writeln!(
            s,
            "| {name} | {} | {} | {} | {none} |",
            word("verified"),
            word("not verified"),
            word("inconclusive")
        );
    }
    s.push('\n');
}
