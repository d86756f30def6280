//! The schedule file of a cat beyond two motors: `whole-optimum.csv` and its sidecar
//! `whole-optimum.json` ([`TreeSidecar`]), beside the tree's model files
//! ([`mod@crate::exchange::tree_model`]): what a replay of the spherical joint's or a tailed cat's
//! whole optimum needs, from the files alone.
//!
//! # Columns
//!
//! `t_s, phase, boundary` as every schedule file ([`crate::exchange::schedule_file`]); then, for
//! the tree's `n` coordinates numbered over the whole tree (link by link, `k = 1 … n`):
//! `q<k>_rad`, `qd<k>_rad_s`, `qdd<k>_rad_s2` and `tau<k>_nm`, the motor's torque about its axis
//! ([`crate::model::Joint::motor_axes`]); A's orientation `qw, qx, qy, qz, twist_deg, swing_deg`;
//! then for every link whose joint is a ball in the model files (no-twist, spherical), named by
//! its child `c`: `c_rel_qw … c_rel_qz`, the child's orientation relative to its parent (`w ≥ 0`;
//! MuJoCo's ball `qpos`), `c_rel_wx_rad_s … c_rel_wz_rad_s`, its angular velocity relative to the
//! parent in its own frame (the ball's `qvel`), and `c_couple_x_nm … c_couple_z_nm`, the joint's
//! whole couple on the child's side about the joint point in the child's frame: what the ball's
//! three motors apply (on the no-twist joint, motors and the joint's structure together).
//!
//! # What it carries
//!
//! Every number is the general core's on the tree ([`crate::engines::reduction`]): the torques
//! and couples of the zero-momentum motion at each row, and A's orientation carried from row to
//! row by sixth-order Magnus steps no longer than the flip's own
//! ([`crate::engines::exact::Flip::steps_per_phase`] per piece), so the last row agrees with the
//! flip to about the tolerance. The pieces are the spline's spans, named `span-1`, `span-2`, …,
//! each cut into [`crate::exchange::ExportOptions::steps_per_piece`] equal intervals (or the rows
//! on a uniform grid at `rate_hz`), both ends written (`end` and `start`, as at every piece
//! boundary): within a span every column is smooth, across one the torques kink (the jerk jumps).
//! The rates are continuous, so there are no jumps. The peaks are the largest `|tau<k>|` of the
//! rows.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::engines::exact::Flip;
use crate::engines::reduction;
use crate::engines::shape::ShapeTrajectory;
use crate::engines::torque::Peak;
use crate::exchange::links::num;
use crate::exchange::schedule_file::{
    csv_error, csv_text, orientations, piece_infos, plan_rows, relative_motion, ExportOptions, COLUMNS,
};
use crate::exchange::sidecar::{Column, JumpRecord, OrientationInfo, PieceInfo, Sampling, Source};
use crate::exchange::tree_model::{arr, NamedTree};
use crate::exchange::{ExchangeError, MJCF_FILE, URDF_FILE};
use crate::model::Joint;
use crate::problem::Problem;

/// The sidecar's format tag.
pub const TREE_FORMAT: &str = "catflip-tree-schedule/1";

/// Intervals per span of the optimum's spline in the files `compare-models` writes: the rows a
/// replay interpolates by cubics never straddle a knot, where the torques kink (the jerk jumps).
/// Measured on the unequal halves' spherical optimum (222 spans, MuJoCo at 0.1 ms): with 4 per
/// span (1 110 rows) the replay lands 3.8e-6° from the flip, with 400 rows over the whole fall
/// (843) 1.2e-3°.
pub const STEPS_PER_SPAN: usize = 4;

/// The file's name without its extension.
pub const TREE_SCHEDULE: &str = "whole-optimum";

/// The sidecar of a tree's schedule file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TreeSidecar {
    /// [`TREE_FORMAT`].
    pub format: String,
    /// The CSV file this describes (same folder).
    pub csv: String,
    /// Where the schedule came from.
    pub source: Source,
    /// The bodies, the joints and the model files beside the CSV.
    pub model: TreeInfo,
    /// Frames, units and signs.
    pub conventions: String,
    /// The CSV's columns in order.
    pub columns: Vec<Column>,
    /// How the rows are spaced.
    pub sampling: Sampling,
    /// The smooth pieces (the spline's spans), in order.
    pub pieces: Vec<PieceInfo>,
    /// Rate jumps: none (the optimum's rates and accelerations are continuous).
    pub jumps: Vec<JumpRecord>,
    /// How the orientation columns were computed, and how accurate they are.
    pub orientation: OrientationInfo,
    /// How to interpolate between rows.
    pub interpolation: String,
    /// The largest `|tau<k>|` of the rows per motor, N·m, and when.
    pub peak_torque_nm: Vec<Peak>,
}

/// The tree as the sidecar describes it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TreeInfo {
    /// The bodies, the base A first.
    pub bodies: Vec<BodyInfo>,
    /// The joints, each hanging one body from another.
    pub links: Vec<LinkInfo>,
    /// Mass of each universal joint's cross in the model files, kg (rapier's joint body).
    pub cross_mass_kg: f64,
    /// Its isotropic moment, kg·m².
    pub cross_moment_kg_m2: f64,
    /// The URDF model file, relative to the CSV (ball joints are pyBullet's `spherical`).
    pub urdf: String,
    /// The MJCF model file, relative to the CSV.
    pub mjcf: String,
}

/// One body: a cylinder.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyInfo {
    /// Its name in the model files.
    pub name: String,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Length, m.
    pub length_m: f64,
    /// Radius, m.
    pub radius_m: f64,
    /// Principal moments about its centre of mass `(I_x, I_y, I_z)`, kg·m².
    pub inertia_kg_m2: [f64; 3],
    /// Its cylinder's axis in its frame: `z` for the halves and a tail, `y` for legs (drawing
    /// only: the inertia above is the body's).
    pub axis: [f64; 3],
}

/// One joint.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinkInfo {
    /// The parent body's name.
    pub parent: String,
    /// The child body's name.
    pub child: String,
    /// `universal`, `no-twist` or `spherical`.
    pub joint: Joint,
    /// Its coordinates' numbers `k` in the CSV (`q<k>_rad`, `tau<k>_nm`).
    pub coordinates: Vec<usize>,
    /// Each coordinate's motor axis in words.
    pub motor_axes: Vec<String>,
    /// The joint point in the parent's body frame, m.
    pub joint_point_in_parent_m: [f64; 3],
    /// The joint point in the child's body frame, m.
    pub joint_point_in_child_m: [f64; 3],
    /// Its joints in the MJCF (two hinges, a ball, or one hinge).
    pub mjcf_joints: Vec<String>,
    /// Its motors in the MJCF.
    pub mjcf_motors: Vec<String>,
}

/// A tree's schedule file: the CSV text and its sidecar.
#[derive(Clone, Debug, PartialEq)]
pub struct TreeFile {
    /// The CSV text.
    pub csv: String,
    /// Its sidecar.
    pub sidecar: TreeSidecar,
}

impl TreeFile {
    /// The sidecar as pretty JSON.
    pub fn sidecar_json(&self) -> Result<String, ExchangeError> {
        serde_json::to_string_pretty(&self.sidecar).map_err(|e| ExchangeError::Json(e.to_string()))
    }
}

/// The columns of `model`'s file (module docs).
pub fn tree_columns(model: &NamedTree) -> Vec<Column> {
    let col = |name: String, unit: &str, meaning: String| Column { name, unit: unit.into(), meaning };
    let (named, tree) = (&model.bodies, &model.tree);
    // The columns every schedule file has, by name.
    let common = |names: &[&str]| -> Vec<Column> {
        COLUMNS.iter().filter(|c| names.contains(&c.0)).map(|c| col(c.0.into(), c.1, c.2.into())).collect()
    };
    let mut out = common(&["t_s", "phase", "boundary"]);
    let mut coordinates: Vec<(usize, String, String)> = Vec::new();
    for (i, l) in tree.links().iter().enumerate() {
        let (parent, child) = (named[l.parent].name, named[i + 1].name);
        for ((k, h), axis) in tree.coordinates(i).zip(1..).zip(model.motor_axes(i)) {
            coordinates.push((k + 1, format!("coordinate {h} of the {} joint of {child} on {parent}", l.joint), axis));
        }
    }
    for (k, what, _) in &coordinates {
        out.push(col(format!("q{k}_rad"), "rad", what.clone()));
    }
    for (k, what, _) in &coordinates {
        out.push(col(format!("qd{k}_rad_s"), "rad/s", format!("rate of {what}")));
    }
    for (k, what, _) in &coordinates {
        out.push(col(format!("qdd{k}_rad_s2"), "rad/s²", format!("acceleration of {what}")));
    }
    for (k, _, axis) in &coordinates {
        out.push(col(
            format!("tau{k}_nm"),
            "N·m",
            format!("motor {k}'s torque: the joint's couple on its child's side about {axis}"),
        ));
    }
    out.extend(common(&["qw", "qx", "qy", "qz", "twist_deg", "swing_deg"]));
    for i in (0..tree.links().len()).filter(|&i| model.is_ball(i)) {
        let c = named[i + 1].name;
        let p = named[tree.links()[i].parent].name;
        for part in ["w", "x", "y", "z"] {
            out.push(col(
                format!("{c}_rel_q{part}"),
                "",
                format!("{c}'s orientation relative to {p}, quaternion {part} (w ≥ 0; MuJoCo's ball qpos)"),
            ));
        }
        for part in ["x", "y", "z"] {
            out.push(col(
                format!("{c}_rel_w{part}_rad_s"),
                "rad/s",
                format!("{c}'s angular velocity relative to {p}, {c}'s frame, {part} (the ball's qvel)"),
            ));
        }
        for part in ["x", "y", "z"] {
            out.push(col(format!("{c}_couple_{part}_nm"), "N·m", format!("the joint's whole couple on {c}'s side about the joint point, {c}'s frame, {part}: the ball's motor {c}_b{part}")));
        }
    }
    out
}

/// The whole optimum `traj` of `model` (its flip measured as `flip` on the tree, at zero
/// momentum) as its schedule file (module docs).
pub fn write_tree_optimum(
    problem: &Problem,
    model: &NamedTree,
    traj: &impl ShapeTrajectory,
    flip: &Flip,
    options: &ExportOptions,
) -> Result<TreeFile, ExchangeError> {
    let tree = &model.tree;
    let durations = traj.piece_durations();
    let duration: f64 = durations.iter().sum();
    options.validate(duration)?;
    let labels: Vec<String> = (0..durations.len()).map(|k| format!("span-{}", k + 1)).collect();
    let plan = plan_rows(&durations, &labels, options);
    let steps = flip.steps_per_phase.max(1) as f64;
    let h_max: Vec<f64> = durations.iter().map(|d| d / steps).collect();
    let zero = Vector3::zeros();
    let attitude =
        orientations(|piece, s| reduction::body_rate(tree, &traj.piece_shape(piece, s), &zero), &plan, &h_max);
    let columns = tree_columns(model);
    let mut peaks = vec![Peak { value: 0.0, time: 0.0 }; tree.dof()];
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(columns.iter().map(|c| c.name.as_str())).map_err(csv_error)?;
    for (row, (q, angles)) in plan.iter().zip(&attitude) {
        let shape = traj.piece_shape(row.piece, row.local);
        let d = reduction::dynamics(tree, &shape, &zero);
        let links = reduction::torques_on(tree, &d);
        let tau: Vec<f64> = links.iter().flat_map(|l| l.tau.iter().copied()).collect();
        for (p, t) in peaks.iter_mut().zip(&tau) {
            if t.abs() > p.value {
                *p = Peak { value: t.abs(), time: row.time };
            }
        }
        let mut numbers: Vec<f64> = [&shape.q, &shape.qd, &shape.qdd, &tau].into_iter().flatten().copied().collect();
        numbers.extend([q.w, q.i, q.j, q.k, angles.twist.to_degrees(), angles.swing.to_degrees()]);
        for (i, l) in tree.links().iter().enumerate().filter(|(i, _)| model.is_ball(*i)) {
            let (qi, qdi, _) = shape.slice(tree.coordinates(i));
            numbers.extend(relative_motion(l.joint, qi, qdi));
            let couple = d.motion.bodies[i + 1].rotation.transpose() * links[i].couple;
            numbers.extend([couple.x, couple.y, couple.z]);
        }
        let mut record = vec![num(row.time), labels[row.piece].clone(), row.marker.text().to_string()];
        record.extend(numbers.into_iter().map(num));
        w.write_record(&record).map_err(csv_error)?;
    }
    let csv = csv_text(w)?;
    let sidecar = TreeSidecar {
        format: TREE_FORMAT.into(),
        csv: format!("{TREE_SCHEDULE}.csv"),
        source: Source {
            schedule: TREE_SCHEDULE.into(),
            problem: problem.name.clone(),
            description: "the whole-manoeuvre optimum on every motor: each coordinate a clamped cubic B-spline over the whole fall".into(),
            problem_file: serde_json::to_value(problem).map_err(|e| ExchangeError::Json(e.to_string()))?,
        },
        model: tree_info(model),
        conventions: CONVENTIONS.into(),
        columns,
        sampling: Sampling {
            kind: if options.rate_hz.is_some() { "uniform" } else { "per-piece" }.into(),
            rate_hz: options.rate_hz,
            steps_per_piece: options.rate_hz.is_none().then_some(options.steps_per_piece),
            rows: plan.len(),
            duration_s: duration,
        },
        pieces: piece_infos(&plan, |k| labels[k].clone()),
        jumps: Vec::new(),
        orientation: OrientationInfo {
            engine: "exact (the general core on the tree of bodies)".into(),
            tolerance_rad: problem.exact.tolerance,
            max_step_s: h_max.iter().copied().fold(0.0, f64::max),
            error_estimate_rad: flip.error_estimate,
            converged: flip.converged,
            final_twist_deg: flip.twist.to_degrees(),
            final_swing_deg: flip.swing.to_degrees(),
        },
        interpolation: "Interpolate within a span (a piece: from its 'start' row to the next): q with q̇ and q̈ by quintic Hermite, or any column by a cubic through four of its rows. The spans join with continuous q, q̇ and q̈ (each 'end' row has a 'start' twin with the same values to rounding), but the torques kink there (the jerk jumps): a cubic through rows on both sides smears the kink.".into(),
        peak_torque_nm: peaks,
    };
    Ok(TreeFile { csv, sidecar })
}

const CONVENTIONS: &str = "SI units (s, rad, rad/s, rad/s², N·m), twist and swing in degrees, each column's name ending with its unit; every body's frame at its centre of mass, z along its axis towards the head (a leg's axis is its frame's y, towards the paw: its frame is its half's with the legs standing out); the world frame falls with the centre of mass, aligned with A's frame at t = 0; quaternions scalar first (w, x, y, z); twist of A about its initial +z (continued), swing of its spine axis; a torque is the joint's couple on the child's side (the child and what hangs from it) about the joint point.";

/// The sidecar's model (module docs).
fn tree_info(model: &NamedTree) -> TreeInfo {
    let tree = &model.tree;
    let bodies = model
        .bodies
        .iter()
        .zip(tree.bodies())
        .map(|(named, b)| BodyInfo {
            name: named.name.into(),
            mass_kg: b.mass,
            length_m: named.cylinder.length,
            radius_m: named.cylinder.radius,
            inertia_kg_m2: arr(&b.inertia.diagonal()),
            axis: arr(&named.axis),
        })
        .collect();
    let links = tree
        .links()
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let motors = model.motors(i);
            let mut joints: Vec<String> = motors.iter().map(|m| m.1.clone()).collect();
            joints.dedup();
            let (parent, child) = (model.name(l.parent), model.name(i + 1));
            LinkInfo {
                parent: parent.into(),
                child: child.into(),
                joint: l.joint,
                coordinates: tree.coordinates(i).map(|k| k + 1).collect(),
                motor_axes: model.motor_axes(i),
                joint_point_in_parent_m: arr(&l.at_parent),
                joint_point_in_child_m: arr(&l.at_child),
                mjcf_joints: joints,
                mjcf_motors: motors.into_iter().map(|m| m.0).collect(),
            }
        })
        .collect();
    TreeInfo {
        bodies,
        links,
        cross_mass_kg: model.cross.0,
        cross_moment_kg_m2: model.cross.1,
        urdf: URDF_FILE.into(),
        mjcf: MJCF_FILE.into(),
    }
}
