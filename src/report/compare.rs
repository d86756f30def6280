//! The peak-torque table: every profile side by side on one problem (DESIGN.md §3, §5).
//!
//! One row per profile: the peak torque in the paper's model `I* · max|ω̇|` (with the correct
//! `I* = m(3r² + 4l²)/12`), the exact peak torque per phase and joint (Newton–Euler on the
//! zero-momentum motion), the motor sizing (peak speed and mechanical power per joint, and with
//! `[actuator]` the worst usage of a motor limit), velocity jumps, twist, swing and circulation. The bend path and the
//! circulation are the problem's, shared by every row; since the reorientation depends only on
//! the joint path (not its timing), twist and swing agree across rows: a check, printed anyway.
//!
//! Every row is a measured schedule ([`Measured`]) as the table shows it ([`CompareRow`]): a
//! profile's, or a trajectory's without a circulation profile (the whole-manoeuvre optimum),
//! whose profile columns are absent (`—` in Markdown, empty in CSV).

use serde::Serialize;

use crate::engines::circulation::ResolvedCirculation;
use crate::engines::measured::Measured;
use crate::engines::motors::MotorDemand;
use crate::engines::peaks::PhasePeaks;
use crate::engines::resolved::Resolved;
use crate::model::Cylinder;
use crate::schedule::{Phase, Schedule};

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

/// The table of every library profile (their measurements made once, in [`Resolved::library`]);
/// `extra` adds more rows (e.g. the optimisers' schedules, already measured).
pub fn compare(r: &Resolved, extra: &[CompareRow]) -> CompareTable {
    let p = &r.problem;
    let rear = &r.model().cat().rear;
    let mut rows: Vec<CompareRow> =
        r.library().iter().map(|(_, m)| CompareRow::of_schedule(&p.name, rear, m)).collect();
    rows.extend_from_slice(extra);
    CompareTable {
        problem: p.name.clone(),
        circulation: r.circulation,
        model_inertia: rear.end_transverse(),
        model: r.model().cat().paper().is_none().then(|| r.model().cat().describe()),
        angular_momentum_nms: p.drop.angular_momentum,
        rows,
    }
}

/// One row of the peak-torque table, as its Markdown, CSV and JSON write it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareRow {
    /// Problem name.
    pub problem: String,
    /// Profile (or trajectory) name.
    pub profile: String,
    /// Where it comes from: `paper`, `library`, `qp`, `refined`, `refined-all-phases` or `whole`.
    pub origin: String,
    /// Whether the twist phase's rate is zero at both ends.
    pub rest_to_rest: Option<bool>,
    /// Peak-acceleration coefficient `max|A|` of the normalised profile.
    pub accel_coefficient: Option<f64>,
    /// Peak torque in the paper's model `I* · max|ω̇| = I* C_a |D| / T²`, N·m.
    pub model_peak_nm: Option<f64>,
    /// Exact peak torques per phase (for the whole optimum, over the problem's phase windows)
    /// and joint, N·m.
    pub exact_peak_nm: PhasePeaks,
    /// Number of velocity jumps (impulses).
    pub velocity_jumps: usize,
    /// Largest impulse of a jump, N·m·s (0 when none).
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

impl CompareRow {
    /// The row of a measured three-phase schedule on a cat whose rear half is `rear` (the
    /// paper's model's `I*`), named by its variant.
    pub fn of_schedule(problem: &str, rear: &Cylinder, m: &Measured<Schedule>) -> CompareRow {
        let (s, e) = (&m.trajectory, &m.exact);
        let coefficient = s.profile.peak_accel_coefficient();
        let t2 = s.durations[Phase::Twist.index()];
        let origin = m.name.variant().map_or("library", |v| v.origin.name());
        CompareRow {
            problem: problem.to_string(),
            profile: s.profile.name().to_string(),
            origin: origin.to_string(),
            rest_to_rest: Some(s.profile.is_rest_to_rest()),
            accel_coefficient: Some(coefficient),
            model_peak_nm: Some(rear.end_transverse() * coefficient * s.circulation.abs() / (t2 * t2)),
            exact_peak_nm: e.phase_peaks(),
            velocity_jumps: e.jumps.len(),
            max_impulse_nms: e.max_impulse(),
            twist_deg: e.twist_deg(),
            swing_deg: e.swing_deg(),
            circulation_rad: Some(s.circulation),
            motors: e.motors.clone(),
        }
    }

    /// Header of [`CompareRow::csv_fields`].
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
            s.push_str(&r.markdown());
        }
        s
    }

    /// The table as tidy CSV: one row per problem × profile × engine.
    pub fn to_csv(&self) -> String {
        self.to_csv_with(&[])
    }

    /// [`CompareTable::to_csv`] with `extra` lines (e.g. the whole-manoeuvre optimum's), sorted in
    /// with the rows.
    pub fn to_csv_with(&self, extra: &[CompareRow]) -> String {
        let mut lines: Vec<CompareRow> = self.rows.clone();
        lines.extend_from_slice(extra);
        lines.sort_by(|a, b| a.profile.cmp(&b.profile));
        crate::exchange::table::csv_table(&CompareRow::csv_header(), lines.iter().map(CompareRow::csv_fields))
    }
}
