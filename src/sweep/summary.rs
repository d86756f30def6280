//! The sweep's Markdown report: the provenance header, what was swept, the rows not computed and
//! why, the peak torque of each schedule per case and rapier's verdicts ([`super::schedules`]),
//! the best value of each choice axis (profile, bend path, …) per combination of the others
//! by lowest peak torque, each quantity over the axes, and the figures.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::cases::cell;
use super::grid::{grids, primary_schedule, Grid};
use super::heatmap::short;
use super::plots::{min_time, quantities, PlotInfo};
use super::row::SweepSchedule;
use super::schedules::MAX_ROWS;
use super::spec::Sweep;
use super::table::Record;
use super::Status;
use crate::engines::Engine;

/// At most this many grids per quantity.
pub const MAX_GRIDS: usize = 6;

/// The whole report.
pub fn markdown(sweep: &Sweep, records: &[Record], command: &str, plots: &[PlotInfo]) -> String {
    let mut s = crate::report::provenance::header(&format!("catflip sweep `{}`", sweep.name), command, &sweep.text);
    s.push_str(&body(sweep, records, plots));
    s
}

/// The report without its provenance header (what a merge of shards reproduces byte for byte).
pub fn body(sweep: &Sweep, records: &[Record], plots: &[PlotInfo]) -> String {
    let mut s = String::new();
    overview(&mut s, sweep, records);
    not_computed(&mut s, records);
    warnings(&mut s, records);
    super::schedules::by_schedule(&mut s, sweep, records);
    super::schedules::verdicts(&mut s, sweep, records);
    drop_heights(&mut s, sweep, records);
    for axis in 0..sweep.axes.len() {
        best_choice(&mut s, sweep, records, axis);
    }
    for q in quantities(sweep) {
        let gs = grids(sweep, records, q.schedule, q.value);
        let _ = writeln!(s, "## {}\n", q.label);
        for (k, g) in gs.iter().enumerate().take(MAX_GRIDS) {
            // A quantity that does not depend on the group axes (π/C and the calibrated
            // circulation do not depend on the profile: the flip depends on the path, not its
            // timing) would repeat the same table; say so instead (equal as shown, to four digits).
            match gs[..k].iter().find(|e| shown(e) == shown(g)) {
                Some(e) => {
                    let _ = writeln!(s, "{}: the same as for {}.\n", g.group, e.group);
                }
                None => grid_table(&mut s, sweep, g),
            }
        }
        if gs.len() > MAX_GRIDS {
            let _ = writeln!(s, "({} more groups in `sweep.csv`.)\n", gs.len() - MAX_GRIDS);
        }
    }
    if !plots.is_empty() {
        let _ = writeln!(s, "## Figures\n");
        for p in plots {
            let _ = writeln!(s, "![{}](plots/{}) ([SVG](plots/{}))\n", p.caption, p.file, p.svg);
        }
    }
    s
}

fn overview(s: &mut String, sweep: &Sweep, records: &[Record]) {
    let mut cases: Vec<usize> = records.iter().map(|r| r.case).collect();
    cases.dedup();
    let _ = writeln!(
        s,
        "## Cases\n\n{} cases ({:?} of {} axes), {} rows (one per case × schedule × engine) in `sweep.csv`. Each case is the base problem `{}` with the axis values set as `--set field=value`.\n",
        cases.len(),
        sweep.combine,
        sweep.axes.len(),
        records.len(),
        sweep.base_origin
    );
    let _ = writeln!(s, "| axis | values |\n|---|---|");
    for a in &sweep.axes {
        let v: Vec<String> = a.values.iter().map(cell).collect();
        let shown = if v.len() > 12 {
            format!("{} values: {} … {}", v.len(), v[..3].join(", "), v[v.len() - 2..].join(", "))
        } else {
            v.join(", ")
        };
        let _ = writeln!(s, "| `{}` | {shown} |", a.field);
    }
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for r in records {
        *counts.entry(r.status.name()).or_insert(0) += 1;
    }
    let _ = writeln!(s, "\n| status | rows |\n|---|---:|");
    for (k, n) in counts {
        let _ = writeln!(s, "| {k} | {n} |");
    }
    let _ = writeln!(
        s,
        "\nAccuracy: twist and swing to each case's `exact.tolerance` (rad, Richardson estimate in `error_estimate_rad`); calibrated circulations to 1 % of it; peak torques sampled at `exact.torque_samples` per phase and refined by golden-section search.\n"
    );
}

fn not_computed(s: &mut String, records: &[Record]) {
    let mut reasons: Vec<(Status, &str, SweepSchedule, usize, usize)> = Vec::new();
    for r in records.iter().filter(|r| r.status != Status::Ok) {
        let key = (r.status, r.reason.as_str(), r.schedule);
        match reasons.iter_mut().find(|x| (x.0, x.1, x.2) == key) {
            Some(x) => x.4 += 1,
            None => reasons.push((r.status, r.reason.as_str(), r.schedule, r.case, 1)),
        }
    }
    if reasons.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "## Rows not computed\n\n| status | schedule | reason | rows | first case |\n|---|---|---|---:|---:|"
    );
    for (status, reason, schedule, first, n) in reasons.iter().take(MAX_ROWS) {
        let _ = writeln!(s, "| {} | {schedule} | {} | {n} | {first} |", status.name(), reason.replace('|', "\\|"));
    }
    if reasons.len() > MAX_ROWS {
        let _ = writeln!(s, "\n({} more reasons in `sweep.csv`.)", reasons.len() - MAX_ROWS);
    }
    s.push('\n');
}

/// "## Warnings": each case's warnings (the problem file's, as `--set` gives them the case's
/// values: a drop height that reads like kilometres, a bend outside the paper's stability range),
/// one line per distinct text with its cases; the CSV's `warnings` column holds them too.
fn warnings(s: &mut String, records: &[Record]) {
    // (text, first case, cases), in case order, and each text's place in it.
    let mut seen: Vec<(&str, usize, usize)> = Vec::new();
    let mut at: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    let mut last = None;
    for r in records.iter().filter(|r| !r.warnings.is_empty()) {
        if last == Some(r.case) {
            continue;
        }
        last = Some(r.case);
        match at.get(r.warnings.as_str()) {
            Some(&k) => seen[k].2 += 1,
            None => {
                at.insert(r.warnings.as_str(), seen.len());
                seen.push((r.warnings.as_str(), r.case, 1));
            }
        }
    }
    if seen.is_empty() {
        return;
    }
    let _ = writeln!(s, "## Warnings\n\n| warnings | cases | first case |\n|---|---:|---:|");
    for (text, first, n) in seen.iter().take(MAX_ROWS) {
        let _ = writeln!(s, "| {} | {n} | {first} |", text.replace('|', "\\|"));
    }
    if seen.len() > MAX_ROWS {
        let _ = writeln!(s, "\n({} more in `sweep.csv`.)", seen.len() - MAX_ROWS);
    }
    s.push('\n');
}

/// One combination of the other axes, with the best and worst value of the ranked axis.
struct Ranked {
    /// Value indices of the other axes.
    key: Vec<usize>,
    /// Lowest peak: (value index, N·m).
    best: Option<(usize, f64)>,
    /// Highest peak.
    worst: Option<(usize, f64)>,
    /// Values with a result.
    ranked: usize,
}

/// For a choice axis (non-numeric, ≥ 2 values): per combination of the other axes, the value
/// with the lowest peak torque on the primary schedule, and the highest for contrast.
fn best_choice(s: &mut String, sweep: &Sweep, records: &[Record], axis: usize) {
    let a = &sweep.axes[axis];
    if a.numeric || a.values.len() < 2 || !sweep.compute.peaks || sweep.combine == super::spec::Combine::Zip {
        return;
    }
    let schedule = primary_schedule(sweep);
    let others: Vec<usize> = (0..sweep.axes.len()).filter(|&i| i != axis).collect();
    let mut groups: Vec<Ranked> = Vec::new();
    for r in records.iter().filter(|r| r.schedule == schedule && r.engine == Engine::Exact) {
        let key: Vec<usize> = others.iter().map(|&i| r.picks[i]).collect();
        let g = match groups.iter().position(|g| g.key == key) {
            Some(g) => g,
            None => {
                groups.push(Ranked { key, best: None, worst: None, ranked: 0 });
                groups.len() - 1
            }
        };
        if let Some(p) = r.peak_max() {
            let entry = &mut groups[g];
            entry.ranked += 1;
            if entry.best.is_none_or(|(_, b)| p < b) {
                entry.best = Some((r.picks[axis], p));
            }
            if entry.worst.is_none_or(|(_, w)| p > w) {
                entry.worst = Some((r.picks[axis], p));
            }
        }
    }
    let _ = writeln!(
        s,
        "## Best `{}` by peak torque ({schedule} circulation)\n\nLowest and highest peak `max |τ|` over the {} values of `{}`, per combination of the other axes (N·m; `ranked` = values with a result).\n",
        a.field,
        a.values.len(),
        a.field
    );
    let mut head = String::from("|");
    for &i in &others {
        let _ = write!(head, " `{}` |", sweep.axes[i].field);
    }
    let _ = writeln!(s, "{head} best | peak | worst | peak | ranked |");
    let _ = writeln!(s, "|{}---|---:|---|---:|---:|", "---|".repeat(others.len()));
    for g in groups.iter().take(MAX_ROWS) {
        let mut line = String::from("|");
        for (&i, &k) in others.iter().zip(&g.key) {
            let _ = write!(line, " {} |", cell(&sweep.axes[i].values[k]));
        }
        let show = |x: &Option<(usize, f64)>, strong: &str| {
            x.map_or_else(
                || "— | —".to_string(),
                |(k, p)| format!("{strong}{}{strong} | {}", cell(&a.values[k]), short(p)),
            )
        };
        let _ = writeln!(s, "{line} {} | {} | {} |", show(&g.best, "**"), show(&g.worst, ""), g.ranked);
    }
    if groups.len() > MAX_ROWS {
        let _ = writeln!(s, "\n({} more rows in `sweep.csv`.)", groups.len() - MAX_ROWS);
    }
    s.push('\n');
}

/// "## Least drop height": with the `min-time` objective, one line per case: the least drop
/// height and fall within the motors, the limit that binds, and the peak speeds and powers the
/// motors must deliver; or the status and reason when no flip was found.
fn drop_heights(s: &mut String, sweep: &Sweep, records: &[Record]) {
    if !(sweep.compute.whole && min_time(sweep)) {
        return;
    }
    let _ = writeln!(
        s,
        "## Least drop height\n\nPer case, the whole-manoeuvre optimum of least fall time `T` within the motors (`[actuator]`): the drop height `g T²/2` from which the cat can right itself, the limit it uses most (`ratio` ≤ 1: within), and the peak joint speeds and mechanical powers it asks of the motors (joint 1, joint 2). A case without a flip shows its status and reason, never a number.\n"
    );
    let mut head = String::from("| case |");
    for a in &sweep.axes {
        let _ = write!(head, " `{}` |", a.field);
    }
    let _ = writeln!(
        s,
        "{head} drop height (m) | fall (s) | binding limit | ratio | peak speed (rad/s) | peak power (W) |"
    );
    let _ = writeln!(s, "|---:|{}---:|---:|---|---:|---:|---:|", "---|".repeat(sweep.axes.len()));
    let rows: Vec<&Record> =
        records.iter().filter(|r| r.schedule == SweepSchedule::Whole && r.engine == Engine::Exact).collect();
    for r in rows.iter().take(MAX_ROWS) {
        let mut line = format!("| {} |", r.case);
        for (a, &p) in sweep.axes.iter().zip(&r.picks) {
            let _ = write!(line, " {} |", cell(&a.values[p]));
        }
        let pair = |x: [f64; 2]| format!("{}, {}", short(x[0]), short(x[1]));
        match (r.numbers.and_then(|n| n.whole), r.numbers.and_then(|n| n.motors)) {
            (Some(w), Some(m)) => {
                let (limit, ratio) =
                    m.worst.map_or_else(|| ("—".to_string(), "—".to_string()), |w| (w.name(), short(w.ratio)));
                let _ = writeln!(
                    s,
                    "{line} **{}** | {} | {limit} | {ratio} | {} | {} |",
                    short(w.drop_height_m),
                    short(w.fall_time_s),
                    pair(m.peak_speed_rad_s),
                    pair(m.peak_power_w)
                );
            }
            _ => {
                let why = format!("{}: {}", r.status.name(), r.reason.replace('|', "\\|"));
                let _ = writeln!(s, "{line} — | — | {why} | — | — | — |");
            }
        }
    }
    if rows.len() > MAX_ROWS {
        let _ = writeln!(s, "\n({} more rows in `sweep.csv`.)", rows.len() - MAX_ROWS);
    }
    s.push('\n');
}

/// A grid's cells as the tables show them.
fn shown(g: &Grid) -> Vec<Vec<String>> {
    g.cells.iter().map(|row| row.iter().map(|v| v.map_or_else(|| "—".to_string(), short)).collect()).collect()
}

fn grid_table(s: &mut String, sweep: &Sweep, g: &Grid) {
    let lay = super::grid::layout(sweep);
    if !g.group.is_empty() {
        let _ = writeln!(s, "{}:\n", g.group);
    }
    let corner = match (lay.rows, lay.cols) {
        (Some(r), Some(c)) => format!("`{}` ↓ `{}` →", sweep.axes[r].field, sweep.axes[c].field),
        (Some(r), None) => format!("`{}`", sweep.axes[r].field),
        _ => String::new(),
    };
    let cols: Vec<String> = if lay.cols.is_some() { g.col_labels.clone() } else { vec!["value".into()] };
    let _ = writeln!(s, "| {corner} | {} |", cols.join(" | "));
    let _ = writeln!(s, "|---|{}", "---:|".repeat(cols.len()));
    for (label, row) in g.row_labels.iter().zip(shown(g)).take(MAX_ROWS) {
        let _ = writeln!(s, "| {label} | {} |", row.join(" | "));
    }
    if g.row_labels.len() > MAX_ROWS {
        let _ = writeln!(s, "\n({} more rows in `sweep.csv`.)", g.row_labels.len() - MAX_ROWS);
    }
    s.push('\n');
}
