//! Running the comparison: each model's optimum, its library schedule and, when asked, rapier's
//! verdict, the models solved in parallel.

use std::time::Instant;

use rayon::prelude::*;

use super::{variants, ModelComparison, ModelRow, OptimumFigures, ScheduleFigures, Variant};
use crate::engines::rapier::RapierError;
use crate::engines::resolved::Resolved;
use crate::measure::whole::whole;
use crate::optimize::whole::{WholeCat, WholeError};
use crate::problem::{Problem, ProblemError};

/// Instants per second of fall at which the optimum's bend is sampled for the plot.
const BEND_SAMPLES_PER_S: f64 = 600.0;

/// Why the comparison cannot be made (a model without an optimum is a row, not an error).
#[derive(Debug, thiserror::Error)]
pub enum CompareModelsError {
    /// A model's problem is refused (its field named).
    #[error("compare-models")]
    Problem(#[from] ProblemError),
    /// The whole optimiser refuses the problem's settings.
    #[error("compare-models: the whole optimiser")]
    Whole(#[from] WholeError),
    /// Rapier cannot build or run a model's scene.
    #[error("compare-models --verify: rapier")]
    Rapier(#[from] RapierError),
    /// The problem could not be written as TOML for the report's provenance.
    #[error("compare-models: the problem as TOML")]
    Toml(#[from] toml::ser::Error),
}

/// The whole optimum of every model of `problem`'s cat ([`variants`]) on its fall, each checked
/// by rapier when `verify`; `command` is the one that regenerates it.
pub fn compare_models(problem: &Problem, verify: bool, command: &str) -> Result<ModelComparison, CompareModelsError> {
    let clock = Instant::now();
    let rows = variants(problem)?.into_par_iter().map(|v| row(v, verify)).collect::<Result<Vec<_>, _>>()?;
    let objective = problem.optimize.whole.objective;
    let cheapest = rows
        .iter()
        .filter_map(|r| r.optimum.as_ref().map(|o| (r, o.objective_value(objective))))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(r, _)| r.key.clone());
    Ok(ModelComparison {
        problem: problem.name.clone(),
        command: command.to_string(),
        objective,
        fall_time_s: problem.drop.fall_time(),
        angular_momentum_nms: problem.drop.angular_momentum,
        verified_in_rapier: verify,
        rows,
        cheapest,
        seconds: clock.elapsed().as_secs_f64(),
        settings_toml: toml::to_string(problem)?,
    })
}

/// One model's row.
fn row(v: Variant, verify: bool) -> Result<ModelRow, CompareModelsError> {
    let clock = Instant::now();
    let cat = v.problem.cat.model();
    let mut row = ModelRow {
        key: v.key,
        label: v.label,
        joint: cat.joint,
        cat: cat.describe(),
        status: String::new(),
        optimum: None,
        schedule: None,
        rapier: None,
        seconds: 0.0,
        problem: v.problem,
        spline: None,
        bend: Vec::new(),
    };
    let r = match Resolved::new(&row.problem) {
        Ok(r) => r,
        Err(e) => {
            row.status = format!("not run: the problem's schedule has no circulation on this model ({e})");
            row.seconds = clock.elapsed().as_secs_f64();
            return Ok(row);
        }
    };
    let e = r.evaluate(&r.schedule);
    row.schedule =
        Some(ScheduleFigures { twist_deg: e.twist_deg(), swing_deg: e.swing_deg(), peak_torque_nm: e.peaks.max });
    let mut report = whole(&r)?;
    if verify {
        report.verify(&r)?;
    }
    row.status = report.status.clone();
    if let (Some(b), Some(m)) = (report.best(), report.measured.as_ref()) {
        let e = &m.exact;
        row.optimum = Some(OptimumFigures {
            start: b.start.clone(),
            iterations: b.iterations,
            twist_deg: e.twist_deg(),
            swing_deg: e.swing_deg(),
            peak_torque_nm: e.peak(),
            peak_time_s: e.peak_time(),
            energy: b.energy,
            max_bend_deg: b.max_bend_deg,
            bend_turns: b.bend_turns,
            fall_time_s: b.fall_time_s,
            drop_height_m: r.problem.drop.height_for(b.fall_time_s),
        });
        let n = ((BEND_SAMPLES_PER_S * b.fall_time_s).ceil() as usize).max(64);
        let cat = WholeCat::from(r.model());
        row.bend = (0..=n)
            .map(|k| {
                let t = b.fall_time_s * k as f64 / n as f64;
                (t, cat.bend_cosine(&b.spline.angles(t)).0.clamp(-1.0, 1.0).acos().to_degrees())
            })
            .collect();
        row.spline = Some(b.spline.clone());
        row.rapier = report.verification().cloned();
    }
    row.seconds = clock.elapsed().as_secs_f64();
    Ok(row)
}
