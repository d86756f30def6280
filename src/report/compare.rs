//! The peak-torque table: every profile side by side on one problem (DESIGN.md §3, §5).
//!
//! One row per profile: the peak torque in the paper's model `I* · max|ω̇|` (with the correct
//! `I* = m(3r² + 4l²)/12`), the exact peak torque per phase and joint (Newton–Euler on the
//! zero-momentum motion), velocity jumps, twist, swing and circulation. The bend path and the
//! circulation are the problem's, shared by every row; since the reorientation depends only on
//! the joint path (not its timing), twist and swing agree across rows: a check, printed anyway.

use serde::Serialize;

use crate::engines::circulation::{Resolved, ResolvedCirculation};
pub use crate::engines::evaluate::CompareRow;
use crate::engines::peaks::PhasePeaks;
use crate::schedule::variant::Origin;

/// The table with its shared settings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareTable {
    /// Problem name.
    pub problem: String,
    /// The circulation every row uses.
    pub circulation: ResolvedCirculation,
    /// `I*` used by the paper's model, kg·m².
    pub model_inertia: f64,
    /// The rows, the paper's cosine first.
    pub rows: Vec<CompareRow>,
}

/// The table of every library profile (their evaluations made once, in [`Resolved::library`]);
/// `extra` adds more rows (e.g. the optimisers' profiles, already evaluated).
pub fn compare(r: &Resolved, extra: &[CompareRow]) -> CompareTable {
    let p = &r.problem;
    let mut rows: Vec<CompareRow> =
        r.library().iter().map(|(k, s, e)| CompareRow::new(&p.name, &p.cat, s, Origin::Library(*k), e)).collect();
    rows.extend_from_slice(extra);
    CompareTable { problem: p.name.clone(), circulation: r.circulation, model_inertia: p.cat.end_transverse(), rows }
}

impl CompareTable {
    /// The table as Markdown.
    pub fn to_markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Peak torques of problem `{}` (circulation {:.6} rad, {}; paper's model with I* = {:.6} kg·m²). Exact peaks are |τ| per joint (τ1, τ2) in N·m.\n",
            self.problem, self.circulation.radians, self.circulation.source, self.model_inertia
        );
        let _ = writeln!(s, "| profile | origin | C_a | model peak | bend τ1, τ2 | twist τ1, τ2 | unbend τ1, τ2 | exact max | jumps (max impulse N·m·s) | twist ° | swing ° |");
        let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
        for r in &self.rows {
            let p = &r.exact_peak_nm;
            let _ = writeln!(
                s,
                "| {} | {} | {:.4} | {:.4} | {:.3}, {:.3} | {:.3}, {:.3} | {:.3}, {:.3} | **{:.3}** | {} ({:.4}) | {:.6} | {:.6} |",
                r.profile, r.origin, r.accel_coefficient, r.model_peak_nm, p.bend[0], p.bend[1], p.twist[0], p.twist[1],
                p.unbend[0], p.unbend[1], p.max, r.velocity_jumps, r.max_impulse_nms, r.twist_deg, r.swing_deg
            );
        }
        s
    }

    /// The table as tidy CSV: one row per problem × profile × engine.
    pub fn to_csv(&self) -> String {
        let mut header =
            vec!["problem", "profile", "origin", "engine", "rest_to_rest", "accel_coefficient", "model_peak_nm"];
        header.extend(PhasePeaks::CSV_HEADER.split(','));
        header.extend(["velocity_jumps", "max_impulse_nms", "twist_deg", "swing_deg", "circulation_rad"]);
        let mut rows: Vec<&CompareRow> = self.rows.iter().collect();
        rows.sort_by(|a, b| a.profile.cmp(&b.profile));
        let records = rows.into_iter().map(|r| {
            let mut f = vec![
                r.problem.clone(),
                r.profile.clone(),
                r.origin.to_string(),
                "exact".to_string(),
                r.rest_to_rest.to_string(),
                format!("{:.9}", r.accel_coefficient),
                format!("{:.9}", r.model_peak_nm),
            ];
            f.extend(r.exact_peak_nm.fields());
            f.extend([
                r.velocity_jumps.to_string(),
                format!("{:.9}", r.max_impulse_nms),
                format!("{:.9}", r.twist_deg),
                format!("{:.9}", r.swing_deg),
                format!("{:.12}", r.circulation_rad),
            ]);
            f
        });
        crate::exchange::table::csv_table(&header, records)
    }
}
