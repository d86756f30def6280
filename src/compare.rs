//! The peak-torque table: every profile side by side on one problem (DESIGN.md §3, §5).
//!
//! One row per profile: the peak torque in the paper's model `I* · max|ω̇|` (with the correct
//! `I* = m(3r² + 4l²)/12`), the exact peak torque per phase and joint (Newton–Euler on the
//! zero-momentum motion), velocity jumps, twist, swing and circulation. The bend path and the
//! circulation are the problem's, shared by every row; since the reorientation depends only on
//! the joint path (not its timing), twist and swing agree across rows: a check, printed anyway.

use serde::Serialize;

use crate::exact::flip;
use crate::manoeuvre::ProfileKind;
use crate::problem::Problem;
use crate::profile::Profile;
use crate::schedule::Schedule;
use crate::simulate::{resolve_circulation, PhasePeaks, ResolvedCirculation, SimulateError, JUMP_TOLERANCE};
use crate::torque::{peak_torques, velocity_jumps};

/// One row of the peak-torque table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareRow {
    /// Problem name.
    pub problem: String,
    /// Profile name.
    pub profile: String,
    /// Where the profile comes from: `paper`, `library`, `qp` or `refined`.
    pub origin: String,
    /// Whether the rate is zero at both ends of the twist phase.
    pub rest_to_rest: bool,
    /// Peak-acceleration coefficient `max|A|` of the normalised profile.
    pub accel_coefficient: f64,
    /// Peak torque in the paper's model `I* · max|ω̇|`, N·m.
    pub model_peak_nm: f64,
    /// Exact peak torques per phase and joint, N·m.
    pub exact_peak_nm: PhasePeaks,
    /// Number of velocity jumps (impulses).
    pub velocity_jumps: usize,
    /// Largest generalised impulse of a jump, N·m·s (0 when none).
    pub max_impulse_nms: f64,
    /// Signed twist, degrees.
    pub twist_deg: f64,
    /// Swing, degrees.
    pub swing_deg: f64,
    /// Circulation, rad.
    pub circulation_rad: f64,
}

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

/// One row for a given profile.
pub fn row(problem: &Problem, schedule: &Schedule, origin: &str) -> CompareRow {
    let cat = &problem.cat;
    let coefficient = schedule.profile.peak_accel_coefficient();
    let t2 = schedule.durations[1];
    let f = flip(cat, schedule, problem.exact.tolerance);
    let peaks = peak_torques(cat, schedule, problem.exact.torque_samples);
    let jumps = velocity_jumps(cat, schedule, JUMP_TOLERANCE);
    CompareRow {
        problem: problem.name.clone(),
        profile: schedule.profile.name().to_string(),
        origin: origin.to_string(),
        rest_to_rest: schedule.profile.is_rest_to_rest(),
        accel_coefficient: coefficient,
        model_peak_nm: cat.end_transverse() * coefficient * schedule.circulation.abs() / (t2 * t2),
        exact_peak_nm: PhasePeaks::from_peaks(&peaks),
        velocity_jumps: jumps.len(),
        max_impulse_nms: jumps.iter().flat_map(|j| j.impulse).map(f64::abs).fold(0.0, f64::max),
        twist_deg: f.twist.to_degrees(),
        swing_deg: f.swing.to_degrees(),
        circulation_rad: schedule.circulation,
    }
}

/// The table of every library profile; `extra` adds more rows (e.g. optimised profiles).
pub fn compare(problem: &Problem, extra: &[(Profile, &str)]) -> Result<CompareTable, SimulateError> {
    let circulation = resolve_circulation(problem)?;
    let base = Schedule::new(problem, circulation.radians);
    let mut rows: Vec<CompareRow> = ProfileKind::ALL
        .iter()
        .map(|&k| {
            let origin = if k == ProfileKind::PaperCosine { "paper" } else { "library" };
            row(problem, &base.with_profile(Profile::library(k)), origin)
        })
        .collect();
    rows.extend(extra.iter().map(|(p, origin)| row(problem, &base.with_profile(p.clone()), origin)));
    Ok(CompareTable { problem: problem.name.clone(), circulation, model_inertia: problem.cat.end_transverse(), rows })
}

impl CompareTable {
    /// The table as Markdown.
    pub fn to_markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Peak torques of problem `{}` (circulation {:.6} rad, {:?}; paper's model with I* = {:.6} kg·m²). Exact peaks are |τ| per joint (τ1, τ2) in N·m.\n",
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
                r.origin.clone(),
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
