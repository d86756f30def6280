//! The comparison as a report: the answer first (the cheapest model), then one row per model;
//! with `--out` also `models.csv`, `models.json`, the optima's bends and one filmstrip per
//! optimum, written into `<out>/<name>-models/` (the presentation only: [`super::run`] computes
//! every number; the plots and the results folder are [`crate::report`]'s, as a sweep's are).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{ModelComparison, ModelRow};
use crate::model::Joint;
use crate::optimize::whole::spline::SplineShape;
use crate::optimize::whole::{motors_beyond, MotorsBeyond, Objective, WholeStatus};
use crate::report::plot::{flip_filmstrip, line_plot, tree_filmstrip, LinePlot, Series};
use crate::report::results_dir::{Staging, WriteError};

/// An absent number: an empty CSV cell, a dash in a table.
fn cell(x: Option<f64>) -> String {
    x.map_or_else(String::new, |v| v.to_string())
}

fn shown(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "—".into(), |v| format!("{v:.digits$}"))
}

/// A model's place in the plots' palette, the same in every comparison: the halves' joint and
/// whether it has a tail or legs choose the colour, and the problem's own unequal halves are drawn
/// dashed beside the mean half's solid line.
fn palette_slot(joint: Joint, tail: bool, legs: bool, unequal: bool) -> usize {
    let joint = match joint {
        Joint::Universal => 0,
        Joint::NoTwist => 1,
        _ => 2,
    };
    let appendages = usize::from(tail) + 2 * usize::from(legs);
    // The joints take 0–2; a tail, legs or both on the universal or no-twist joint (the halves'
    // joints that take appendages) 3–8. Ten colours a pass (`style::PALETTE`); the second pass is
    // dashed.
    let colour = if appendages == 0 { joint } else { 1 + 2 * appendages + joint.min(1) };
    colour + if unequal { 10 } else { 0 }
}

/// [`palette_slot`] of a row.
fn row_slot(r: &ModelRow) -> usize {
    palette_slot(r.joint, r.problem.cat.tail.is_some(), r.problem.cat.legs.is_some(), r.has_unequal_halves())
}

impl ModelComparison {
    /// The comparison as Markdown: the cheapest model, the table, what each column means.
    pub fn to_markdown(&self) -> String {
        let mut s = format!("# {}\n\n", self.title());
        if !self.command.is_empty() {
            let _ = writeln!(s, "{}\n", crate::report::provenance::regenerate_line(&self.command));
        }
        s + &self.body()
    }

    fn title(&self) -> String {
        format!("Cat models compared on problem `{}`", self.problem)
    }

    /// The report after its title: the answer, the table, the notes.
    fn body(&self) -> String {
        let mut s = String::new();
        let what = match self.objective {
            Objective::Peak => "peak motor torque",
            Objective::Energy => "energy ∫τ·τ dt",
            Objective::MinTime => "fall time within the motors",
        };
        match self.cheapest_row() {
            Some(best) => {
                let _ = writeln!(s, "**The cheapest flip by {what}: {}**, {}.\n", best.label, self.lead(best));
            }
            None => {
                let _ = writeln!(s, "**No model has an optimum that flips the cat**: each row says why.\n");
            }
        }
        let spin = self.angular_momentum_nms;
        let release = if spin.iter().all(|x| *x == 0.0) {
            "released without spin".to_string()
        } else {
            format!("released with total angular momentum [{}, {}, {}] N·m·s (world frame)", spin[0], spin[1], spin[2])
        };
        let min_time = self.objective == Objective::MinTime;
        let fall = if min_time {
            "each model's least fall time within the motors (`[actuator]`; the drop height it needs beside it)"
                .to_string()
        } else {
            format!("the same fall of {:.4} s", self.fall_time_s)
        };
        let _ = writeln!(
            s,
            "Each model's whole-manoeuvre optimum (objective {}, `[optimize.whole]` of the problem) on {fall}, {release}; every number is re-measured by that model's exact engine. The library schedule is the problem's own (`[manoeuvre]`) on that model (on the problem's fall of {:.4} s).\n",
            self.objective.name(),
            self.fall_time_s
        );
        let rapier = if self.verified_in_rapier { " rapier |" } else { "" };
        let (fall_head, fall_rule) = if min_time { (" fall s | drop m |", "---:|---:|") } else { ("", "") };
        let _ = writeln!(
            s,
            "| model | status |{fall_head} peak N·m | energy N²·m²·s | max bend ° | bend turns | twist ° | swing ° | library schedule: twist °, peak N·m |{rapier} time s |"
        );
        let _ = writeln!(
            s,
            "|---|---|{fall_rule}---:|---:|---:|---:|---:|---:|---:|{}---:|",
            if rapier.is_empty() { "" } else { "---|" }
        );
        for r in &self.rows {
            let o = r.optimum.as_ref();
            let schedule = r
                .schedule
                .as_ref()
                .map_or_else(|| "—".to_string(), |f| format!("{:+.4}, {:.4}", f.twist_deg, f.peak_torque_nm));
            let verdict = if self.verified_in_rapier {
                format!(" {} |", r.rapier.as_ref().map_or_else(|| "not run".to_string(), |v| v.status.to_string()))
            } else {
                String::new()
            };
            let fall = if min_time {
                format!(" {} | {} |", shown(o.map(|o| o.fall_time_s), 6), shown(o.map(|o| o.drop_height_m), 4))
            } else {
                String::new()
            };
            let _ = writeln!(
                s,
                "| {} | {} |{fall} {} | {} | {} | {} | {} | {} | {schedule} |{verdict} {:.2} |",
                r.label,
                if o.is_some() { r.status.clone() } else { format!("**{}**", r.status.replace('-', " ")) },
                shown(o.map(|o| o.peak_torque_nm), 6),
                shown(o.map(|o| o.energy), 6),
                shown(o.map(|o| o.max_bend_deg), 2),
                shown(o.map(|o| o.bend_turns), 3),
                o.map_or_else(|| "—".into(), |o| format!("{:+.6}", o.twist_deg)),
                o.map_or_else(|| "—".into(), |o| format!("{:.1e}", o.swing_deg)),
                r.seconds
            );
        }
        let _ = writeln!(
            s,
            "\n(`max bend`: the largest angle between the halves' spine axes, 0 when straight; `bend turns`: how far the direction of the bend turns about A's spine over the fall, in turns, signed right-handed about A's +z (while the bend exceeds 1°); `twist` and `swing`: A's final orientation, a flip is ±180° and 0.)"
        );
        if self.rows.iter().any(|r| r.optimum.is_some()) {
            let _ = writeln!(s, "\nHow each optimum ended:\n");
        }
        if self.rows.iter().any(ModelRow::is_upper_bound) {
            let _ = writeln!(s, "(Status {}.)\n", WholeStatus::UPPER_BOUND_MEANS);
        }
        for r in &self.rows {
            if let Some(o) = &r.optimum {
                let _ = writeln!(
                    s,
                    "- {}: from the start `{}`, {} iterations: {}",
                    r.label, o.start, o.iterations, o.reason
                );
            }
        }
        let missing: Vec<&ModelRow> = self.rows.iter().filter(|r| r.optimum.is_none()).collect();
        if !missing.is_empty() {
            let _ = writeln!(s, "\nWhy a model has no optimum:\n");
            for r in missing {
                let _ = writeln!(s, "- {}: {}", r.label, r.reason.as_deref().unwrap_or(&r.status));
            }
        }
        let _ = writeln!(
            s,
            "\nThe models run in parallel (their times overlap); the comparison took {:.1} s in all.",
            self.seconds
        );
        if self.rows.iter().any(|r| r.motors > 2) {
            let _ = writeln!(
                s,
                "\nBeyond two motors (the spherical joint's third, a tail's one or two more, the legs' hinges) the optimiser plans every motor, the general core re-measures the flip on the tree of bodies and rapier's tree scene verifies it; their library schedule is the problem's with the further coordinates held at zero (the spherical joint's relative twist, the tail straight behind the cat, the legs standing out; a calibrated circulation calibrated on the model itself, the appendages held still), its peak over every motor sampled at 4001 instants per phase. Their filmstrips place every body by the general core on the tree of bodies; with `--out` each one's model and schedule files are in `<model>/` (`model.xml`, `model.urdf`, `whole-optimum.csv` and `.json`, replayed in MuJoCo by `python/examples/05_mujoco_replay_tree.py`)."
            );
            let limited = self.rows.iter().find(|r| r.motors > 2).map(|r| motors_beyond(&r.problem.actuator.motors()));
            if let (Some(MotorsBeyond::TorqueLimit(limit)), false) = (limited, self.objective == Objective::Energy) {
                let _ = writeln!(
                    s,
                    "\nBeyond two motors the torque limit ({limit} N·m) holds on every motor: each optimum is the least-peak path, at the problem's fall when its peak is within the limit, or (objective `min-time`) with its duration scaled by √(peak/τ_max) to fly at the limit, which leaves a zero-momentum flip unchanged and is exact for a torque limit alone (DESIGN.md §9). Rapier's tree scene bounds the universal and no-twist joints' motors by the limit, as the two-motor scene does (a verdict says when a motor saturates); the spherical joint's motors (the parent's x, y and the child's spine) are not its ball's axes there and run unbounded, so its verdict is the flight's (flip and peak), not a motor's at its limit."
                );
            }
        }
        let _ = writeln!(s, "\nThe cats:\n");
        for r in &self.rows {
            let _ = writeln!(s, "- {}: {}; {} motors.", r.label, r.cat, r.motors);
        }
        s
    }

    /// The cheapest row against the others, in words.
    fn lead(&self, best: &ModelRow) -> String {
        let Some(o) = &best.optimum else { return String::new() };
        let value = o.objective_value(self.objective);
        // A row whose number is an upper bound says so wherever the lead quotes it.
        let bounded = |r: &ModelRow| if r.is_upper_bound() { " (an upper bound, `upper-bound`)" } else { "" };
        let mut s = match self.objective {
            Objective::Peak => format!("peak {:.4} N·m", o.peak_torque_nm),
            Objective::Energy => format!("energy {:.6} N²·m²·s", o.energy),
            Objective::MinTime => {
                format!("least fall time {:.4} s, a drop of {:.4} m", o.fall_time_s, o.drop_height_m)
            }
        };
        s.push_str(bounded(best));
        let others: Vec<String> = self
            .rows
            .iter()
            .filter(|r| r.key != best.key)
            .filter_map(|r| {
                r.optimum.as_ref().map(|x| {
                    format!("{:.3}× that with {}{}", x.objective_value(self.objective) / value, r.label, bounded(r))
                })
            })
            .collect();
        if !others.is_empty() {
            let _ = write!(s, "; {}", others.join("; "));
        }
        if let Some(v) = &best.rapier {
            let _ = write!(s, "; its rapier verdict: {}", v.status);
        }
        s
    }

    /// One row per model; absent numbers are empty cells. Written by
    /// [`crate::exchange::table::csv_table`], so that a field with a comma (a start refined,
    /// "universal optimum from paper, refined"; a problem's name) is quoted, not split.
    pub fn to_csv(&self) -> String {
        const HEADER: [&str; 20] = [
            "problem",
            "model",
            "joint",
            "motors",
            "halves",
            "status",
            "start",
            "iterations",
            "peak_torque_nm",
            "energy",
            "max_bend_deg",
            "bend_turns",
            "twist_deg",
            "swing_deg",
            "fall_time_s",
            "drop_height_m",
            "schedule_twist_deg",
            "schedule_peak_nm",
            "rapier",
            "seconds",
        ];
        let rows = self.rows.iter().map(|r| {
            let o = r.optimum.as_ref();
            let f = r.schedule.as_ref();
            let halves = if r.has_unequal_halves() { "unequal" } else { "equal" };
            vec![
                self.problem.clone(),
                r.key.clone(),
                r.joint.name().to_string(),
                r.motors.to_string(),
                halves.to_string(),
                r.status.clone(),
                o.map_or_else(String::new, |o| o.start.clone()),
                o.map_or_else(String::new, |o| o.iterations.to_string()),
                cell(o.map(|o| o.peak_torque_nm)),
                cell(o.map(|o| o.energy)),
                cell(o.map(|o| o.max_bend_deg)),
                cell(o.map(|o| o.bend_turns)),
                cell(o.map(|o| o.twist_deg)),
                cell(o.map(|o| o.swing_deg)),
                cell(o.map(|o| o.fall_time_s)),
                cell(o.map(|o| o.drop_height_m)),
                cell(f.map(|f| f.twist_deg)),
                cell(f.map(|f| f.peak_torque_nm)),
                r.rapier.as_ref().map_or_else(String::new, |v| v.status.to_string().replace(' ', "-")),
                r.seconds.to_string(),
            ]
        });
        crate::exchange::table::csv_table(&HEADER, rows)
    }

    /// The optima's bends over the fall, one line per model with an optimum.
    pub fn bend_plot(&self) -> LinePlot {
        let series = self
            .rows
            .iter()
            .filter(|r| !r.bend.is_empty())
            .map(|r| Series::new(r.key.clone(), r.bend.clone()).in_slot(row_slot(r)))
            .collect();
        LinePlot::new(
            "models_bend",
            format!("Bend of each cat model's whole optimum, problem \u{201c}{}\u{201d}", self.problem),
            "time t (s)",
            "bend: angle between the spine axes (°)",
            series,
        )
    }

    /// Writes `models.md`, `models.csv`, `models.json`, the bend plot, one filmstrip per optimum
    /// (`<key>_filmstrip.png`) and, for each model beyond two motors with an optimum, its model
    /// and schedule files (`<key>/model.xml`, `model.urdf`, `whole-optimum.csv`, `.json`) into
    /// `<out>/<problem>-models/`, all or nothing.
    pub fn write(&self, out: &Path) -> Result<PathBuf, WriteError> {
        let staging = Staging::begin(out, &format!("{}-models", self.problem))?;
        let json = serde_json::to_string_pretty(self)
            .map_err(|source| WriteError::Json { what: "the model comparison", source })?;
        let md = crate::report::provenance::header(&self.title(), &self.command, &self.settings_toml) + &self.body();
        for (name, text) in [("models.md", md), ("models.csv", self.to_csv()), ("models.json", json)] {
            let path = staging.dir().join(name);
            std::fs::write(&path, text).map_err(|source| WriteError::Io { path: staging.shown(&path), source })?;
        }
        if self.rows.iter().any(|r| !r.bend.is_empty()) {
            line_plot(staging.dir(), &self.bend_plot())?;
        }
        for r in self.rows.iter().filter(|r| !r.files.is_empty()) {
            let folder = staging.dir().join(&r.key);
            std::fs::create_dir_all(&folder)
                .map_err(|source| WriteError::Io { path: staging.shown(&folder), source })?;
            for (name, text) in &r.files {
                let path = folder.join(name);
                std::fs::write(&path, text).map_err(|source| WriteError::Io { path: staging.shown(&path), source })?;
            }
        }
        for r in &self.rows {
            let Some(spline) = &r.spline else { continue };
            let path = staging.dir().join(format!("{}_filmstrip.png", r.key));
            let name = format!("{}, whole optimum", r.label);
            match &r.tree {
                Some(tree) => tree_filmstrip(&path, &r.problem, &name, tree, &SplineShape(spline), spline)?,
                None => flip_filmstrip(&path, &r.problem, &name, spline)?,
            };
        }
        Ok(staging.commit()?)
    }
}

#[cfg(test)]
mod tests {
    use super::{palette_slot, Joint};

    /// One model keeps one look in every comparison (a reader found the no-twist joint orange in
    /// one bend plot and purple in another): the slot follows the model, not its row; the
    /// problem's own unequal halves take the same colour, dashed (the palette's second pass).
    #[test]
    fn a_model_keeps_its_colour_across_comparisons() {
        let mut models = vec![(Joint::Spherical, false, false)];
        for joint in [Joint::Universal, Joint::NoTwist] {
            for (tail, legs) in [(false, false), (true, false), (false, true), (true, true)] {
                models.push((joint, tail, legs));
            }
        }
        let slots: Vec<usize> = models.iter().map(|&(j, t, l)| palette_slot(j, t, l, false)).collect();
        let mut distinct = slots.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), models.len(), "{slots:?}");
        assert!(slots.iter().all(|&s| s < 10), "{slots:?}: one pass of the palette, solid");
        for &(j, t, l) in &models {
            assert_eq!(palette_slot(j, t, l, true), palette_slot(j, t, l, false) + 10);
        }
    }
}
