//! The peak-torque table: every profile side by side on one problem (DESIGN.md §3, §5).
//!
//! One row per profile: the peak torque in the paper's model `I* · max|ω̇|` (with the correct
//! `I* = m(3r² + 4l²)/12`), the exact peak torque per phase and joint (Newton–Euler on the
//! zero-momentum motion), the motor sizing (peak speed and mechanical power per joint, and with
//! `[actuator]` the worst usage of a motor limit), velocity jumps, twist, swing and circulation. The bend path and the
//! circulation are the problem's, shared by every row; since the reorientation depends only on
//! the joint path (not its timing), twist and swing agree across rows: a check, printed anyway.

use serde::Serialize;

use crate::engines::circulation::ResolvedCirculation;
pub use crate::engines::evaluate::CompareRow;
use crate::engines::motors::MotorDemand;
use crate::engines::peaks::PhasePeaks;
use crate::engines::resolved::Resolved;
use crate::schedule::variant::Origin;

/// The table with its shared settings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareTable {
    /// Problem name.
    pub problem: String,
    /// The circulation every row uses.
    pub circulation: ResolvedCirculation,
    /// `I*` used by the paper's model, kg·m²: the rear half's (the half the motors turn; both halves' on the paper's cat).
    pub model_inertia: f64,
    /// The cat when it is not the paper's (its joint and halves, in words; the paper's `I*` is
    /// then the rear half's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// The release spin every row is measured with, world frame, N·m·s (zero: none).
    pub angular_momentum_nms: [f64; 3],
    /// The rows, the paper's cosine first.
    pub rows: Vec<CompareRow>,
}

/// The table of every library profile (their evaluations made once, in [`Resolved::library`]);
/// `extra` adds more rows (e.g. the optimisers' profiles, already evaluated).
pub fn compare(r: &Resolved, extra: &[CompareRow]) -> CompareTable {
    let p = &r.problem;
    let mut rows: Vec<CompareRow> = r
        .library()
        .iter()
        .map(|(k, s, e)| CompareRow::new(&p.name, &r.model().cat().rear, s, Origin::Library(*k), e))
        .collect();
    rows.extend_from_slice(extra);
    CompareTable {
        problem: p.name.clone(),
        circulation: r.circulation,
        model_inertia: r.model().cat().rear.end_transverse(),
        model: r.model().cat().paper().is_none().then(|| r.model().cat().describe()),
        angular_momentum_nms: p.drop.angular_momentum,
        rows,
    }
}

/// One line of the peak-torque table as both its Markdown and its CSV write it: a profile's row,
/// or a trajectory's that has no circulation profile (the whole-manoeuvre optimum), whose
/// profile columns (rest to rest, `C_a`, the paper's model peak, the circulation) are `None`:
/// `—` in Markdown, empty in CSV.
#[derive(Clone, Debug, PartialEq)]
pub struct CompareLine {
    /// Problem name.
    pub problem: String,
    /// Profile (or trajectory) name.
    pub profile: String,
    /// Where it comes from.
    pub origin: String,
    /// Whether the twist phase's rate is zero at both ends.
    pub rest_to_rest: Option<bool>,
    /// Peak-acceleration coefficient of the normalised profile.
    pub accel_coefficient: Option<f64>,
    /// Peak torque in the paper's model `I* · max|ω̇|`, N·m.
    pub model_peak_nm: Option<f64>,
    /// Exact peak torques per phase and joint, N·m.
    pub exact_peak_nm: PhasePeaks,
    /// Number of velocity jumps.
    pub velocity_jumps: usize,
    /// Largest generalised impulse of a jump, N·m·s (0 when none).
    pub max_impulse_nms: f64,
    /// Signed twist, degrees.
    pub twist_deg: f64,
    /// Swing, degrees.
    pub swing_deg: f64,
    /// Circulation, rad.
    pub circulation_rad: Option<f64>,
    /// Peak speed and power per joint, and each motor limit's usage.
    pub motors: MotorDemand,
}

impl From<&CompareRow> for CompareLine {
    fn from(r: &CompareRow) -> Self {
        CompareLine {
            problem: r.problem.clone(),
            profile: r.profile.clone(),
            origin: r.origin.to_string(),
            rest_to_rest: Some(r.rest_to_rest),
            accel_coefficient: Some(r.accel_coefficient),
            model_peak_nm: Some(r.model_peak_nm),
            exact_peak_nm: r.exact_peak_nm,
            velocity_jumps: r.velocity_jumps,
            max_impulse_nms: r.max_impulse_nms,
            twist_deg: r.twist_deg,
            swing_deg: r.swing_deg,
            circulation_rad: Some(r.circulation_rad),
            motors: r.motors.clone(),
        }
    }
}

impl CompareLine {
    /// Header of [`CompareLine::csv_fields`].
    pub fn csv_header() -> Vec<&'static str> {
        let mut header =
            vec!["problem", "profile", "origin", "engine", "rest_to_rest", "accel_coefficient", "model_peak_nm"];
        header.extend(PhasePeaks::CSV_HEADER.split(','));
        header.extend(["velocity_jumps", "max_impulse_nms", "twist_deg", "swing_deg", "circulation_rad"]);
        header.extend(MotorDemand::CSV_HEADER);
        header
    }

    /// The line as CSV fields (empty where a column does not apply).
    pub fn csv_fields(&self) -> Vec<String> {
        let opt = |x: Option<f64>, d: usize| x.map_or(String::new(), |v| format!("{v:.d$}"));
        let mut f = vec![
            self.problem.clone(),
            self.profile.clone(),
            self.origin.clone(),
            "exact".to_string(),
            self.rest_to_rest.map_or(String::new(), |b| b.to_string()),
            opt(self.accel_coefficient, 9),
            opt(self.model_peak_nm, 9),
        ];
        f.extend(self.exact_peak_nm.fields());
        f.extend([
            self.velocity_jumps.to_string(),
            format!("{:.9}", self.max_impulse_nms),
            format!("{:.9}", self.twist_deg),
            format!("{:.9}", self.swing_deg),
            opt(self.circulation_rad, 12),
        ]);
        f.extend(self.motors.csv_fields());
        f
    }

    /// The line as a row of [`CompareTable::to_markdown`]'s table (`—` where a column does not
    /// apply).
    pub fn markdown(&self) -> String {
        let opt = |x: Option<f64>| x.map_or("—".to_string(), |v| format!("{v:.4}"));
        let p = &self.exact_peak_nm;
        format!(
            "| {} | {} | {} | {} | {:.3}, {:.3} | {:.3}, {:.3} | {:.3}, {:.3} | **{:.3}** | {:.3}, {:.3} | {:.3}, {:.3} | {} | {} ({:.4}) | {:.6} | {:.6} |\n",
            self.profile,
            self.origin,
            opt(self.accel_coefficient),
            opt(self.model_peak_nm),
            p.bend[0],
            p.bend[1],
            p.twist[0],
            p.twist[1],
            p.unbend[0],
            p.unbend[1],
            p.max,
            self.motors.peak_speed_rad_s[0].value,
            self.motors.peak_speed_rad_s[1].value,
            self.motors.peak_power_w[0].value,
            self.motors.peak_power_w[1].value,
            self.motors.usage_cell(),
            self.velocity_jumps,
            self.max_impulse_nms,
            self.twist_deg,
            self.swing_deg
        )
    }
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
        if let Some(m) = &self.model {
            let _ = writeln!(s, "The cat: {m}; the paper's model uses the rear half's I*.\n");
        }
        if self.angular_momentum_nms.iter().any(|l| l.abs() > 0.0) {
            let l = self.angular_momentum_nms;
            let _ = writeln!(
                s,
                "Released with spin L = [{}, {}, {}] N·m·s (world frame): the exact columns are the spinning motion's; the paper's model knows no spin.\n",
                l[0], l[1], l[2]
            );
        }
        let _ = writeln!(s, "| profile | origin | C_a | model peak | bend τ1, τ2 | twist τ1, τ2 | unbend τ1, τ2 | exact max | peak speed rad/s | peak power W | motors: worst usage | jumps (max impulse N·m·s) | twist ° | swing ° |");
        let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|");
        for r in &self.rows {
            s.push_str(&CompareLine::from(r).markdown());
        }
        s
    }

    /// The table as tidy CSV: one row per problem × profile × engine.
    pub fn to_csv(&self) -> String {
        self.to_csv_with(&[])
    }

    /// [`CompareTable::to_csv`] with `extra` lines (e.g. the whole-manoeuvre optimum's), sorted in
    /// with the rows.
    pub fn to_csv_with(&self, extra: &[CompareLine]) -> String {
        let mut lines: Vec<CompareLine> = self.rows.iter().map(CompareLine::from).collect();
        lines.extend_from_slice(extra);
        lines.sort_by(|a, b| a.profile.cmp(&b.profile));
        crate::exchange::table::csv_table(&CompareLine::csv_header(), lines.iter().map(CompareLine::csv_fields))
    }
}
