//! The Markdown files of a run: the reports people read, one per table.

use std::fmt::Write as _;

use super::{ExportError, Shown};
use super::{Exporter, Files, Views};
use crate::problem::Problem;
use crate::report::check::{verification_row, VERIFICATION_TABLE_CELLS, VERIFICATION_TABLE_HEADER};

/// The Markdown exporter.
pub struct Markdown;

impl Exporter for Markdown {
    fn files(&self, v: &Views) -> Result<Files, ExportError> {
        let mut compare = v.table.to_markdown();
        compare.extend(v.whole_row.map(|row| row.markdown()));
        let mut verification = verification_markdown(v.problem, v.verified);
        verification.extend(crate::report::whole::verification_row_markdown(v.whole));
        let mut files: Files = v.audit.map(|a| ("audit.md".to_string(), a.to_markdown())).into_iter().collect();
        files.extend(v.optimize.map(|o| ("optimize.md".to_string(), o.to_markdown())));
        files.extend([
            ("whole.md".to_string(), v.whole.to_markdown()),
            ("retime.md".to_string(), crate::report::whole::retime_markdown(v.retimed)),
            ("compare.md".to_string(), compare),
            ("verification.md".to_string(), verification),
        ]);
        files.extend(v.robust.map(|r| ("robust.md".to_string(), r.to_markdown())));
        Ok(files)
    }
}

/// `verification.md`: every schedule of the table through the exact engine and rapier (also
/// `catflip compare --verify`'s table, [`super::with_verification`]).
pub fn verification_markdown(problem: &Problem, rows: &[Shown]) -> String {
    let mut s = format!(
        "## Verification in rapier3d-f64 (`{}`, first dt {})\n\nEvery schedule of the peak-torque table, through the exact engine and rapier. Twist and swing in degrees; torques in N·m; momentum relative to I*·max|q̇|.\n\n",
        problem.name, problem.rapier.dt
    );
    s.push_str("rapier's multibody integrator is first order and leaks angular momentum at a rate proportional to dt, which moves the twist; *rapier → 0* is the Richardson extrapolation from the last two steps of the dt sequence, and *estimates* are rapier's own errors of the extrapolated twist, swing and peak torque (the change between the last two extrapolations). The rapier columns are from the finest step, the *rapier → 0* ones are what the verdict judges (the peak's difference is the extrapolated peak's); — where rapier has no such number (no run, fewer than two, or no extrapolation: a saturated motor is not smooth in the step).\n\n");
    if let Some(v) = rows.iter().find_map(Shown::verification) {
        let _ =
            writeln!(s, "Tolerances: {}; budget {} rapier steps per schedule.\n", v.tolerances_text(), v.step_budget);
    }
    s.push_str(VERIFICATION_TABLE_HEADER);
    for v in rows {
        match v.verification() {
            Some(x) => s.push_str(&verification_row(&v.name(), &v.measured.reference(), x)),
            None => {
                let _ = writeln!(s, "| {} | {} |", v.name(), ["—"; VERIFICATION_TABLE_CELLS].join(" | "));
            }
        }
    }
    s
}
