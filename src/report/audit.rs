//! The paper audit ([`crate::measure::audit`]) as a Markdown report.

use std::fmt::Write;

use crate::measure::audit::{Audit, Entry};

/// A value with six significant digits, or a dash.
fn cell(x: Option<f64>) -> String {
    match x {
        None => "—".to_string(),
        Some(0.0) => "0".to_string(),
        Some(v) => {
            let digits = (5 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
            format!("{v:.digits$}")
        }
    }
}

/// The published value as printed.
fn printed(e: &Entry) -> String {
    match (e.published, e.published_decimals) {
        (Some(v), Some(d)) => format!("{v:.*}", d as usize),
        (p, _) => cell(p),
    }
}

fn escape(s: &str) -> String {
    s.replace('|', "\\|")
}

impl Audit {
    /// A readable Markdown report: one table row per entry, then warnings and notes.
    pub fn to_markdown(&self) -> String {
        render(self)
    }
}

fn render(a: &Audit) -> String {
    let mut out = String::new();
    let with_exact = a.entries.iter().any(|e| e.exact.is_some());
    let _ = writeln!(out, "# Paper audit: {}\n", a.problem);
    let _ = writeln!(
        out,
        "{}\n",
        if a.worked_example {
            "This problem is the paper's §7 worked example: its printed numbers are shown."
        } else {
            "This problem is not the paper's §7 worked example: only the paper's general statements are shown as published."
        }
    );
    let _ = writeln!(
        out,
        "*published*: printed in the paper; *literal*: the paper's formula and inputs, slips included, for this problem; *corrected*: the right value{}. ✓ marks a literal value that reproduces the printed one to its printed digits (rounded or truncated).\n",
        if with_exact { "; *exact*: the exact engine" } else { "" }
    );
    let _ = write!(out, "| key | § | quantity | unit | published | literal | corrected |");
    if with_exact {
        let _ = write!(out, " exact |");
    }
    let _ = writeln!(out, " explanation |");
    let _ = writeln!(out, "|---|---|---|---|---:|---:|---:|{}---|", if with_exact { "---:|" } else { "" });
    for e in &a.entries {
        let mark = match e.literal_reproduces_published {
            Some(true) => " ✓",
            Some(false) => " ✗",
            None => "",
        };
        let _ = write!(
            out,
            "| `{}` | {} | {} | {} | {} | {}{} | {} |",
            e.key,
            e.section,
            escape(&e.quantity),
            e.unit,
            printed(e),
            cell(e.literal),
            mark,
            cell(e.corrected)
        );
        if with_exact {
            let _ = write!(out, " {} |", cell(e.exact));
        }
        let mut why = escape(&e.explanation);
        if !e.readings.is_empty() {
            let list: Vec<String> =
                e.readings.iter().map(|r| format!("{} = {}", escape(&r.label), cell(r.value))).collect();
            let _ = write!(why, ". Readings: {}", list.join("; "));
        }
        let _ = writeln!(out, " {why} |");
    }
    if let Some(search) = &a.omega_readings {
        out.push_str(&search.to_markdown());
    }
    if !a.warnings.is_empty() {
        let _ = writeln!(out, "\n## Warnings (§3)\n");
        for w in &a.warnings {
            let _ = writeln!(out, "- {w}");
        }
    }
    let _ = writeln!(out, "\n## Other slips\n");
    for n in &a.notes {
        let _ = writeln!(out, "- {}: {}", n.section, n.text);
    }
    out
}
