//! `catflip optimize --whole`: the whole-manoeuvre optimum ([`crate::measure::whole`]) and the
//! certified convex retimings of the problem's own path ([`crate::measure::retime`]), as
//! Markdown, table rows and files.
//!
//! Every number of the optimum is its measurement's ([`crate::engines::measured::Measured`]):
//! re-measured by the exact engine on the final trajectory, never taken from a linearisation.
//! The per-start table and the iteration log are the optimiser's own record.

use std::fmt::Write as _;

use crate::engines::measured::Measured;
use crate::measure::retime::RetimeRow;
use crate::measure::whole::WholeReport;
use crate::numeric::numfmt::{above_or_below, echo, fixed};
use crate::optimize::retime::RetimeSettings;
use crate::optimize::whole::{BSpline, Objective, WholeSolution, WholeStatus};
use crate::problem::PLAUSIBLE_HEIGHT_M;
use crate::report::check::verification_row;
use crate::report::compare::CompareRow;
use crate::schedule::variant::WHOLE;

impl WholeReport {
    /// The report as Markdown.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "## Whole-manoeuvre optimum (`{}`, objective {})\n", self.problem, self.objective.name());
        let _ = writeln!(s, "The cat: {}.\n", self.cat);
        let interior = self.best().is_some_and(WholeSolution::interior_point);
        let _ = writeln!(
            s,
            "Both joint trajectories over the whole fall (clamped cubic B-splines), optimised by successive convexification with Clarabel subproblems{}; the flip R(T) = Rz(π) is a constraint, and every number below is re-measured by the exact engine on the final trajectory.\n",
            if interior {
                " and the least peak by a primal-dual interior-point method with the torques' exact curvature (`optimize.whole.method`)"
            } else {
                ""
            }
        );
        if self.spins() {
            let l = self.angular_momentum_nms;
            let _ = writeln!(
                s,
                "Released with spin: total angular momentum L = [{}, {}, {}] N·m·s (world frame). The model, the flip and every torque below are those of the spinning motion (exact engine with spin, fourth-order Runge–Kutta); the ±π turning directions are not equivalent, so the starts turn both ways.\n",
                l[0], l[1], l[2]
            );
        }
        match (self.best(), self.measured.as_ref(), self.peak_torque_nm) {
            (Some(b), Some(m), Some(p)) => {
                let e = &m.exact;
                let _ = writeln!(
                    s,
                    "- Status: **{}** (start `{}`, {} iterations, {} Newton steps, {:.2} s).",
                    self.status, b.start, b.iterations, b.polish_steps, b.seconds
                );
                if b.status == WholeStatus::UpperBound {
                    let _ = writeln!(s, "  (Status {}.)", WholeStatus::UPPER_BOUND_MEANS);
                }
                let _ = writeln!(
                    s,
                    "- Flip: twist **{:+.9}°**, swing **{:.3e}°** (| |twist| − 180° | = {:.2e} rad; engine error estimate {:.1e} rad).",
                    e.twist_deg(),
                    e.swing_deg(),
                    (e.flip.twist.abs() - std::f64::consts::PI).abs(),
                    e.flip.error_estimate
                );
                let _ = writeln!(
                    s,
                    "- Peak motor torque **{} N·m** at t = {:.4} s; over the problem's phase windows bend [{}, {}], twist [{}, {}], unbend [{}, {}] N·m.",
                    fixed(p.max, 6),
                    e.peak_time(),
                    fixed(p.bend[0], 4),
                    fixed(p.bend[1], 4),
                    fixed(p.twist[0], 4),
                    fixed(p.twist[1], 4),
                    fixed(p.unbend[0], 4),
                    fixed(p.unbend[1], 4)
                );
                let _ = writeln!(
                    s,
                    "- Energy ∫τ·τ dt = {} N²·m²·s; largest bend {:.2}° (angle between the halves ≥ {:.2}°); the bend direction turns {:+.3} turns.",
                    fixed(b.energy, 6),
                    b.max_bend_deg,
                    180.0 - b.max_bend_deg,
                    b.bend_turns
                );
                if self.objective != Objective::Energy {
                    let c = &b.chatter;
                    let _ = writeln!(
                        s,
                        "- Torque switches: joint 1 {}×, joint 2 {}×; total variation {}, {} that of a clean bang-bang profile with the same switches; deepest dip of a saturated arc to {:.1} %, {:.1} % of the peak.",
                        c.switches[0],
                        c.switches[1],
                        above_or_below(c.excess_variation[0]),
                        above_or_below(c.excess_variation[1]),
                        100.0 * c.deepest_dip[0],
                        100.0 * c.deepest_dip[1]
                    );
                }
                let _ = writeln!(s, "{}", self.motor_lines(b, m));
            }
            _ => {
                let _ = writeln!(s, "- **{}**", self.status);
            }
        }
        let _ = writeln!(
            s,
            "\n| start | status | twist ° | swing ° | peak N·m | energy N²·m²·s | max bend ° | iterations | time s | why |"
        );
        let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|---|");
        for o in &self.outcome.solutions {
            let _ = writeln!(
                s,
                "| {} | {} | {:+.6} | {:.2e} | {:.6} | {:.6} | {:.2} | {} | {:.2} | {} |",
                o.start,
                o.status,
                o.twist.to_degrees(),
                o.swing.to_degrees(),
                o.peak_torque_nm,
                o.energy,
                o.max_bend_deg,
                o.iterations,
                o.seconds,
                o.reason
            );
        }
        for k in &self.outcome.skipped {
            let _ = writeln!(s, "| {} | not started | | | | | | | | {} |", k.start, k.reason);
        }
        if let Some(b) = self.best() {
            s.push_str(&iteration_table(b));
        }
        s
    }
}

/// The iteration log of the best start `b` as a Markdown table, with its legend; the barrier
/// column only when an interior-point stage planned (`optimize.whole.method`).
fn iteration_table(b: &WholeSolution) -> String {
    let interior = b.interior_point();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\nIterations of the best start (`{}`; the stages: coarse and fine energy, then the objective). *peak* is the largest torque on the loop's samples at the iterate (`samples_per_span` per knot span, on the knots that stage solves: a refined stage's are finer), which can lie a little below the optimum's dense re-measurement above; *violation* `|e|₁` is the flip's error, rad; *trust radius* the largest step a subproblem may take, rad; *ratio* the actual merit decrease over the predicted one (a step is accepted at 0.1 or more); {}*Newton steps* are the final phase's, which drive `|e|` to round-off:\n",
        b.start,
        if interior {
            "*barrier μ* the barrier parameter of an interior-point iteration (in units of the stage's first peak), which has no trust radius, subproblem or ratio (its steps are judged by a filter); "
        } else {
            ""
        }
    );
    let barrier = if interior { " barrier μ |" } else { "" };
    let _ = writeln!(
        s,
        "| # | stage objective | peak N·m | violation | trust radius |{barrier} subproblem | ratio | accepted |"
    );
    let _ = writeln!(s, "|---:|---|---:|---:|---:|{}---|---:|---|", if interior { "---:|" } else { "" });
    let sci = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x:.2e}"));
    for (i, l) in b.log.iter().enumerate() {
        let barrier = if interior { format!(" {} |", sci(l.barrier)) } else { String::new() };
        let _ = writeln!(
            s,
            "| {} | {} | {:.6} | {:.2e} | {} |{barrier} {} | {} | {} |",
            i + 1,
            l.objective.name(),
            l.peak_nm,
            l.violation,
            sci(l.trust_radius),
            l.subproblem.map_or("—".to_string(), |q| q.to_string()),
            l.ratio.map_or("—".to_string(), |x| format!("{x:.3}")),
            if l.accepted { "yes" } else { "no" }
        );
    }
    s
}

/// What a least drop height outside [`PLAUSIBLE_HEIGHT_M`] says about the motors: far too weak
/// above it, and below it so strong (or given in another unit: N·cm as N·m, rpm as rad/s) that
/// the cat flips in less than any drop. Empty within.
fn height_note(h: f64) -> String {
    let (low, high) = PLAUSIBLE_HEIGHT_M;
    if h > high {
        format!(" (beyond the {} m of any drop: the motors are far too weak for this cat)", echo(high))
    } else if h < low {
        format!(
            " (below the {} m of any drop: the motors flip the cat in less; are the [actuator] limits in their units, N·m and rad/s?)",
            echo(low)
        )
    } else {
        String::new()
    }
}

impl WholeReport {
    /// The fall and motor lines of the Markdown report.
    fn motor_lines(&self, b: &WholeSolution, measured: &Measured<BSpline>) -> String {
        let m = &measured.exact.motors;
        let fall = match (self.objective, self.drop_height_m) {
            (Objective::MinTime, Some(h)) => format!(
                "- Least fall time within the motors **{:.6} s**: drop height **{:.4} m**{}; active limits: {}.",
                b.fall_time_s,
                h,
                height_note(h),
                if self.active_limits.is_empty() {
                    "none".to_string()
                } else {
                    self.active_limits.iter().map(|l| l.describe()).collect::<Vec<_>>().join(", ")
                }
            ),
            _ => format!("- Fall time {:.6} s.", b.fall_time_s),
        };
        format!(
            "{fall}\n- Motor sizing: peak speed [{:.4}, {:.4}] rad/s, peak power [{:.4}, {:.4}] W (joints 1, 2); {}.",
            m.peak_speed_rad_s[0].value,
            m.peak_speed_rad_s[1].value,
            m.peak_power_w[0].value,
            m.peak_power_w[1].value,
            m.verdict()
        )
    }
}

/// The retiming rows as a Markdown table.
pub fn retime_markdown(rows: &[RetimeRow]) -> String {
    let mut s = String::from("## Certified retiming along the problem's joint path (SOCP, Clarabel)\n\n");
    let _ = write!(s, "The path stays, so does the flip; only the timing changes. *bound* is Clarabel's dual objective, a certified lower bound on the optimum of the discrete program ({} intervals per phase, piecewise-constant path acceleration), up to the solver's residuals: it holds to about 1e-6 (relative), not to the *gap* column, and a retimed trajectory's exact peak can lie that little below it; *exact* is the exact engine's peak of the retimed trajectory. The bound is not one on the continuous retiming of the path: finer grids lower the optimum at first order in 1/N (`catflip bench --problem PROBLEM`, curve `retime`, measures how far this path's exact peak at N = {} lies above the continuous optimum extrapolated from finer grids). The path is parametrised by the phases' progress variables (joint 1's angle, the bend direction, the fraction straightened), on which the joints never stop inside a phase, so the program is well posed.\n\n", RetimeSettings::default().intervals, RetimeSettings::default().intervals);
    s.push_str("| schedule | split | status | peak N·m | bound N·m | gap | exact N·m | twist ° | swing ° | solve s |\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    let f = |x: Option<f64>, d: usize| x.map_or("—".to_string(), |v| format!("{v:.d$}"));
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3} |",
            r.schedule,
            r.split,
            r.status,
            f(r.peak_nm, 4),
            f(r.lower_bound_nm, 4),
            r.gap_nm.map_or("—".to_string(), |g| format!("{g:.1e}")),
            f(r.exact_peak_nm, 4),
            f(r.twist_deg, 6),
            f(r.swing_deg, 6),
            r.solve_time_s
        );
    }
    s
}

/// The optimum's row of the peak-torque table (its Markdown row and its CSV record), its peaks
/// over the problem's phase windows. The paper's model, the rest-to-rest flag and the circulation
/// do not apply to a trajectory without a circulation profile.
pub fn compare_row(report: &WholeReport) -> Option<CompareRow> {
    let (m, p) = (report.measured.as_ref()?, report.peak_torque_nm?);
    let e = &m.exact;
    Some(CompareRow {
        problem: report.problem.clone(),
        profile: m.name.to_string(),
        origin: "whole".to_string(),
        rest_to_rest: None,
        accel_coefficient: None,
        model_peak_nm: None,
        exact_peak_nm: p,
        velocity_jumps: e.jumps.len(),
        max_impulse_nms: e.max_impulse(),
        twist_deg: e.twist_deg(),
        swing_deg: e.swing_deg(),
        circulation_rad: None,
        motors: e.motors.clone(),
    })
}

/// The optimum's row of the verification table (Markdown, the table's columns), once verified.
pub fn verification_row_markdown(report: &WholeReport) -> Option<String> {
    let m = report.measured.as_ref()?;
    Some(verification_row(&m.name.to_string(), &m.reference(), m.verification()?))
}

/// The summary lines of the optimum, its verification and the certified retiming, for the
/// run's report.
pub fn summary_lines(report: &WholeReport, retimed: &[RetimeRow]) -> String {
    let mut s = String::new();
    match (report.best(), report.measured.as_ref()) {
        (Some(b), Some(m)) => {
            let e = &m.exact;
            let _ = writeln!(
                s,
                "- **Whole-manoeuvre optimum** (`{WHOLE}`, both joint paths optimised over the whole fall): twist **{:+.9}°**, swing {:.1e}°, peak torque **{:.4} N·m**, energy {:.4} N²·m²·s; it bends at most {:.1}° and its bend direction turns {:+.2} turns ({}, {} iterations). See `whole.md`.",
                e.twist_deg(),
                e.swing_deg(),
                e.peak(),
                b.energy,
                b.max_bend_deg,
                b.bend_turns,
                b.status,
                b.iterations
            );
            if let (Objective::MinTime, Some(h)) = (report.objective, report.drop_height_m) {
                let _ = writeln!(
                    s,
                    "- **Least fall time within the motors: {:.4} s, a drop of {h:.4} m**{}; the limits it reaches: {}.",
                    b.fall_time_s,
                    height_note(h),
                    report.active_limits.iter().map(|l| l.describe()).collect::<Vec<_>>().join(", ")
                );
            }
            let _ = writeln!(
                s,
                "- The optimum's motors reach {:.4} rad/s and {:.4} W: {}.",
                e.motors.max_speed(),
                e.motors.max_power(),
                e.motors.verdict()
            );
        }
        _ => {
            let _ = writeln!(s, "- Whole-manoeuvre optimum: **{}**.", report.status);
        }
    }
    if let Some(v) = report.verification() {
        let _ = writeln!(s, "- rapier verification of `{WHOLE}`: **{}**.", v.verdict);
    }
    for row in retimed {
        if let (Some(bound), Some(exact), Some(twist), Some(swing)) =
            (row.lower_bound_nm, row.exact_peak_nm, row.twist_deg, row.swing_deg)
        {
            let _ = writeln!(
                s,
                "- Certified retiming of `{}` ({}): exact peak {:.4} N·m, certified lower bound {:.4} N·m of its discrete program (finer grids lower it, see `retime.md`); twist {:+.6}°, swing {:.6}° (unchanged: the path is kept). See `retime.md`.",
                row.schedule,
                row.split,
                exact,
                bound,
                twist,
                swing
            );
        } else {
            let _ = writeln!(s, "- Certified retiming of `{}` ({}): {}.", row.schedule, row.split, row.status);
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A least drop height outside the drops any cat meets is said (a review's 500 N·m motors,
    /// N·cm typed as N·m, flipped the paper's cat within 6.4 mm without a word).
    #[test]
    fn a_least_drop_height_outside_any_drop_is_said() {
        assert!(height_note(0.0064).contains("below the 0.05 m of any drop"), "{}", height_note(0.0064));
        assert!(height_note(0.0064).contains("N·m and rad/s"));
        assert!(height_note(800.0).contains("beyond the 500 m of any drop"));
        assert_eq!(height_note(2.05), "", "a plausible height needs no note");
    }
}
