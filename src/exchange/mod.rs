//! Exchange with other tools: the model as URDF and MJCF, schedules as CSV with a JSON sidecar,
//! and schedules from elsewhere read back (DESIGN.md §7).
//!
//! - [`links`]: the links (A, the universal joint's cross, B) with their true mass properties;
//! - [`mod@urdf`], [`mod@mjcf`]: the model files (`model.urdf`, `model.xml`; the no-twist joint
//!   is a ball joint in the MJCF and pyBullet's non-standard spherical joint in the URDF);
//! - [`schedule_file`] and [`sidecar`]: `NAME.csv` and `NAME.json`: units in the column names,
//!   an optional uniform rate, boundary rows marked, jumps with their impulses, orientation
//!   columns to the exact engine's tolerance;
//! - [`import`] and [`interp`]: a CSV of `t, q1, q2` (optionally `q̇`, `q̈`) read into a
//!   [`crate::schedule::Trajectory`], interpolated by a stated scheme;
//! - [`tree_model`] and [`tree_file`]: the same for a cat beyond two motors (the spherical
//!   joint, a tail), any tree of cylinders: its model files and its whole optimum's schedule file;
//! - [`table`]: every tidy CSV table, written with the `csv` crate;
//! - [`arrays`]: a schedule given as columns of numbers (the Python package's numpy arrays),
//!   read by the same parser;
//! - [`checks`]: what is refused and what is warned of an imported schedule (units, duration,
//!   ends, rates against angles, sampling); [`crate::measure::import`] measures it.
//!
//! Conventions (the README's "Replay elsewhere"): body frames at the centres of mass with `z` towards the head,
//! joint point `(0, 0, −l/2)` in A and `(0, 0, +l/2)` in B, `R_AB = Rx(q1) · Ry(q2)` on the
//! universal joint and `exp([q1, q2, 0]×)` on the no-twist joint; SI units; quaternions scalar
//! first `(w, x, y, z)`.

pub mod arrays;
pub mod checks;
pub mod cuts;
pub mod import;
pub mod interp;
pub mod links;
pub mod mjcf;
pub mod schedule_file;
pub mod sidecar;
pub mod table;
pub mod tree_file;
pub mod tree_model;
pub mod urdf;

pub use arrays::schedule_from_columns;
pub use import::{read_schedule, ImportError, ImportedSchedule, Interpolation};
pub use links::Links;
pub use mjcf::{mjcf, MjcfOptions};
pub use schedule_file::{write_schedule, write_trajectory, write_whole_optimum, ExportOptions, ScheduleFile};
pub use sidecar::Sidecar;
pub use urdf::urdf;

use crate::engines::measured::Measured;
use crate::problem::Problem;
use crate::schedule::Schedule;

/// File name of the URDF model beside the schedules.
pub const URDF_FILE: &str = "model.urdf";
/// File name of the MJCF model beside the schedules.
pub const MJCF_FILE: &str = "model.xml";

/// Why an export failed.
#[derive(Debug, thiserror::Error)]
pub enum ExchangeError {
    /// The `--rate` cannot make a grid.
    #[error("--rate {rate_hz}: {reason}")]
    BadRate {
        /// The rate given, Hz.
        rate_hz: f64,
        /// Why it is rejected.
        reason: String,
    },
    /// The steps per piece cannot make a grid.
    #[error("{0} steps per piece: must be between 1 and {max}", max = schedule_file::MAX_ROWS)]
    BadSteps(usize),
    /// The CSV writer failed.
    #[error("writing a schedule CSV: {0}")]
    Csv(String),
    /// The sidecar could not be serialised.
    #[error("writing a schedule sidecar: {0}")]
    Json(String),
    /// The problem cannot be written as a schedule file (a release with spin).
    #[error(transparent)]
    Problem(#[from] crate::problem::ProblemError),
    /// The cat model cannot run the trajectory.
    #[error(transparent)]
    Model(#[from] crate::engines::models::ModelError),
}

/// The model files of a problem's cat: `(file name, contents)` for [`URDF_FILE`] and
/// [`MJCF_FILE`]: on the universal joint two revolutes with the cross of the rapier scene, on the
/// no-twist joint a ball (MJCF) and pyBullet's spherical joint (URDF, [`mod@urdf`]); the falling
/// frame's zero gravity. The spherical joint is refused, naming `cat.joint`.
pub fn model_files(problem: &Problem) -> Result<Vec<(String, String)>, ExchangeError> {
    problem.require_two_motor_joint("the URDF/MJCF export")?;
    let links = Links::new(&problem.cat.model(), problem.rapier.cross_mass_fraction);
    let name = format!("catflip-{}", problem.name);
    Ok(vec![
        (URDF_FILE.to_string(), urdf(&links, &name)),
        (MJCF_FILE.to_string(), mjcf(&links, &name, &MjcfOptions::default())),
    ])
}

/// Everything `catflip run` writes under `schedules/`: for each measured schedule,
/// `schedules/NAME.csv` and `schedules/NAME.json`, then the model files ([`model_files`]) once. Returned as `(path relative to the results folder, contents)`.
pub fn results_files(
    problem: &Problem,
    schedules: &[&Measured<Schedule>],
    options: &ExportOptions,
) -> Result<Vec<(String, String)>, ExchangeError> {
    let mut out = schedule_files(problem, schedules, options)?;
    out.extend(model_files(problem)?.into_iter().map(|(n, text)| (format!("schedules/{n}"), text)));
    Ok(out)
}

/// Each measured schedule's CSV and sidecar as (path in a results folder, contents), computed in
/// parallel and listed in the given order (sidecar first): [`results_files`] without the model
/// files.
pub fn schedule_files(
    problem: &Problem,
    schedules: &[&Measured<Schedule>],
    options: &ExportOptions,
) -> Result<Vec<(String, String)>, ExchangeError> {
    use rayon::prelude::*;
    let files = schedules
        .par_iter()
        .map(|m| {
            let file = write_schedule(problem, m, options)?;
            let name = &m.name;
            Ok([(format!("schedules/{name}.json"), file.sidecar_json()?), (format!("schedules/{name}.csv"), file.csv)])
        })
        .collect::<Result<Vec<_>, ExchangeError>>()?;
    Ok(files.into_iter().flatten().collect())
}

/// The files of a cat beyond two motors' whole optimum `traj` (its flip `flip` on the tree), as
/// `(file name, contents)`: [`URDF_FILE`], [`MJCF_FILE`] and `whole-optimum.csv` with its sidecar
/// ([`tree_file`]).
pub fn tree_files(
    problem: &Problem,
    model: &tree_model::NamedTree,
    traj: &impl crate::engines::shape::ShapeTrajectory,
    flip: &crate::engines::exact::Flip,
    options: &ExportOptions,
) -> Result<Vec<(String, String)>, ExchangeError> {
    let file = tree_file::write_tree_optimum(problem, model, traj, flip, options)?;
    let name = format!("catflip-{}", problem.name);
    Ok(vec![
        (URDF_FILE.to_string(), tree_model::tree_urdf(model, &name)),
        (MJCF_FILE.to_string(), tree_model::tree_mjcf(model, &name, &MjcfOptions::default())),
        (format!("{}.json", tree_file::TREE_SCHEDULE), file.sidecar_json()?),
        (format!("{}.csv", tree_file::TREE_SCHEDULE), file.csv),
    ])
}
