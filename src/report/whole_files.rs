//! `catflip optimize --whole --out DIR`: the optimum's results folder `DIR/<name>-whole/`,
//! written whole or not at all ([`crate::report::results_dir`]).
//!
//! - `whole.md` (the provenance header, then the report; with `--verify`, rapier's section) and
//!   `whole.json` (what `--json` prints);
//! - `whole-optimum.csv` and `whole-optimum.json`: the optimum as a schedule file and its sidecar
//!   ([`crate::exchange`]), which `catflip simulate PROBLEM --schedule` reads back and MuJoCo or
//!   pyBullet replay with the model files;
//! - `model.urdf` and `model.xml`: the cat's halves and joint ([`crate::exchange::model_files`];
//!   the no-twist joint is a ball joint in `model.xml` and pyBullet's spherical joint in
//!   `model.urdf`);
//! - `whole_filmstrip.png`: the flip, frame by frame.
//!
//! The files build the universal and no-twist joints, equal or unequal halves, released without
//! spin: the command refuses `--out` for any other problem (the spherical joint, a spin) before it
//! optimises ([`files_refusal`]).

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::exchange::model_files;
use crate::exchange::write_whole_optimum;
use crate::measure::whole::WholeReport;
use crate::problem::{Problem, ProblemError};
use crate::report::plot::flip_filmstrip;
use crate::report::results_dir::{Staging, WriteError};
use crate::schedule::variant::WHOLE;

/// Why the optimum's files cannot be built for `problem`, before anything is computed: the
/// files build the two-motor joints only (universal and no-twist), and the schedule file's
/// orientation and torque columns are the zero-momentum flip's.
pub fn files_refusal(problem: &Problem) -> Result<(), ProblemError> {
    let what = "optimize --whole --out (the optimum's schedule file and URDF/MJCF)";
    problem.require_two_motor_joint(what)?;
    problem.require_no_spin(what)
}

/// Writes `out/<name>-whole/` (module docs) for `report`'s optimum, with the report as
/// `markdown` and `json`; returns the folder. Nothing is written when there is no optimum.
pub fn write_whole(
    out: &Path,
    problem: &Problem,
    report: &WholeReport,
    json: &impl Serialize,
    markdown: &str,
    command: &str,
) -> Result<Option<PathBuf>, WriteError> {
    let Some(m) = report.measured.as_ref() else { return Ok(None) };
    let file = write_whole_optimum(problem, m, &Default::default())?;
    let spline = &m.trajectory;
    let staging = Staging::begin(out, &format!("{}-whole", problem.name))?;
    let settings = toml::to_string(problem).map_err(|source| WriteError::Toml { what: "the problem", source })?;
    let title = format!("catflip whole-manoeuvre optimum: {}", problem.name);
    let md = crate::report::provenance::header(&title, command, &settings) + markdown;
    let json = serde_json::to_string_pretty(json).map_err(|source| WriteError::Json { what: "the optimum", source })?;
    let sidecar = file.sidecar_json()?;
    let mut files = vec![
        ("whole.md".to_string(), md),
        ("whole.json".to_string(), json),
        (format!("{WHOLE}.csv"), file.csv),
        (format!("{WHOLE}.json"), sidecar),
    ];
    files.extend(model_files(problem)?);
    for (name, text) in files {
        let path = staging.dir().join(name);
        std::fs::write(&path, text).map_err(|source| WriteError::Io { path: staging.shown(&path), source })?;
    }
    flip_filmstrip(&staging.dir().join("whole_filmstrip.png"), problem, "whole optimum", spline)?;
    Ok(Some(staging.commit()?))
}
