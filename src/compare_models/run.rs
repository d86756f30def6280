//! Running the comparison: each model's optimum, its library schedule and, when asked, rapier's
//! verdict, the models solved in parallel.

use std::time::Instant;

use nalgebra::Vector3;
use rayon::prelude::*;

use super::{variants, Beyond, ModelComparison, ModelRow, OptimumFigures, ScheduleFigures, Variant};
use crate::engines::models;
use crate::engines::rapier::tree_run::verify_tree;
use crate::engines::rapier::tree_scene::bounds_motors;
use crate::engines::rapier::{RapierError, RapierOptions, Reference};
use crate::engines::reduction;
use crate::engines::resolved::Resolved;
use crate::engines::shape::{Held, ShapeTrajectory};
use crate::exchange::tree_file::STEPS_PER_SPAN;
use crate::exchange::tree_model::NamedTree;
use crate::exchange::{tree_files, ExchangeError, ExportOptions};
use crate::measure::whole::whole;
use crate::model::motor::Motors;
use crate::model::tree::Tree;
use crate::model::{Cat, Joint};
use crate::numeric::roots::RootStatus;
use crate::optimize::whole::spline::SplineShape;
use crate::optimize::whole::{optimize_whole, BSpline, WholeCat, WholeError};
use crate::problem::manoeuvre::Circulation;
use crate::problem::{Problem, ProblemError};

/// Instants per second of fall at which the optimum's bend is sampled for the plot.
const BEND_SAMPLES_PER_S: f64 = 600.0;

/// Why the comparison cannot be made (a model without an optimum is a row, not an error).
#[derive(Debug, thiserror::Error)]
pub enum CompareModelsError {
    /// A model's problem is refused (its field named).
    #[error("compare-models")]
    Problem(#[from] ProblemError),
    /// A model's files cannot be written.
    #[error("compare-models: the model files")]
    Exchange(#[from] ExchangeError),
    /// The whole optimiser refuses the problem's settings.
    #[error("compare-models: the whole optimiser")]
    Whole(#[from] WholeError),
    /// Rapier cannot build or run a model's scene.
    #[error("compare-models --verify: rapier")]
    Rapier(#[from] RapierError),
    /// The problem could not be written as TOML for the report's provenance.
    #[error("compare-models: the problem as TOML")]
    Toml(#[from] toml::ser::Error),
    /// The problem's own halves cannot take its schedule (its field named).
    #[error("compare-models: the problem's own cat")]
    OwnCat(#[from] crate::engines::circulation::CirculationError),
}

/// The whole optimum of every model of `problem`'s cat ([`variants`]) on its fall, each checked
/// by rapier when `verify`; `command` is the one that regenerates it.
pub fn compare_models(problem: &Problem, verify: bool, command: &str) -> Result<ModelComparison, CompareModelsError> {
    let clock = Instant::now();
    // The problem's own halves take its schedule, as every command's must: a circulation they do
    // not define (the paper's C on unequal halves) is refused, as `simulate` refuses it, not made
    // into rows that were not run beside the models that could.
    Resolved::new(&Problem { cat: problem.cat.halves_only(), ..problem.clone() })?;
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
    let cat = match v.beyond {
        Beyond::TwoMotors => None,
        Beyond::Spherical => WholeCat::spherical(Cat { joint: Joint::Spherical, ..v.problem.cat.model() }),
        Beyond::Appendages(appendages) => WholeCat::appended(v.problem.cat.model(), appendages),
    };
    let joint = if v.beyond == Beyond::Spherical { Joint::Spherical } else { v.problem.cat.joint };
    let mut row = ModelRow {
        key: v.key,
        label: v.label,
        joint,
        motors: cat.as_ref().map_or(2, WholeCat::joints),
        cat: cat.as_ref().map_or_else(|| v.problem.cat.model().describe(), WholeCat::describe),
        status: String::new(),
        reason: None,
        optimum: None,
        schedule: None,
        rapier: None,
        seconds: 0.0,
        problem: v.problem,
        spline: None,
        tree: None,
        bend: Vec::new(),
        files: Vec::new(),
    };
    match (v.beyond, cat) {
        (Beyond::TwoMotors, _) => {}
        (_, Some(cat)) => {
            beyond_two_motors(&mut row, &cat, verify)?;
            row.seconds = clock.elapsed().as_secs_f64();
            return Ok(row);
        }
        (_, None) => {
            row.not_run("an appendage's joint must have one or two motors (cat.tail.joint = \"universal\", \"no-twist\" or \"hinge\")".into());
            return Ok(row);
        }
    }
    let r = match Resolved::new(&row.problem) {
        Ok(r) => r,
        Err(e) => {
            row.not_run(format!("the problem's schedule has no circulation on this model ({e})"));
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
    match report.best() {
        Some(_) => row.status = report.status.clone(),
        None => row.no_optimum(report.status.clone()),
    }
    if let (Some(b), Some(m)) = (report.best(), report.measured.as_ref()) {
        let e = &m.exact;
        row.optimum = Some(OptimumFigures {
            start: b.start.clone(),
            iterations: b.iterations,
            reason: b.reason.clone(),
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
        row.bend = bend_samples(&WholeCat::from(r.model()), &b.spline, b.fall_time_s);
        row.spline = Some(b.spline.clone());
        row.rapier = report.verification().cloned();
    }
    row.seconds = clock.elapsed().as_secs_f64();
    Ok(row)
}

/// The row of a model beyond two motors ([`Beyond`]): its whole optimum on every motor, the flip
/// re-measured by the general core's adaptive engine on its tree of bodies, and with `verify`
/// rapier's tree scene; ideal motors or one torque limit on every motor, and no spin
/// ([`crate::optimize::whole::beyond_two_motors`], its refusal the row's status).
fn beyond_two_motors(row: &mut ModelRow, cat: &WholeCat, verify: bool) -> Result<(), CompareModelsError> {
    let p = &row.problem;
    let (spin, motors) = (p.drop.spin(), p.actuator.motors());
    if let Err(e) = crate::optimize::whole::beyond_two_motors(cat, p.optimize.whole.objective, &motors, &spin) {
        row.not_run(e.to_string());
        return Ok(());
    }
    let tree = cat.tree();
    row.schedule = held_schedule(p, cat, &tree);
    let (settings, tolerance, fall) = (&p.optimize.whole, p.exact.tolerance, p.drop.fall_time());
    let outcome = optimize_whole(cat, fall, &p.manoeuvre, settings, &motors, tolerance)?;
    let Some(b) = outcome.best() else {
        row.no_optimum(outcome.no_optimum(settings, tolerance));
        return Ok(());
    };
    let flip = models::flip_on(&tree, &SplineShape(&b.spline), &spin, tolerance);
    row.status = b.status.to_string();
    row.optimum = Some(OptimumFigures {
        start: b.start.clone(),
        iterations: b.iterations,
        reason: b.reason.clone(),
        twist_deg: flip.twist.to_degrees(),
        swing_deg: flip.swing.to_degrees(),
        peak_torque_nm: b.peak_torque_nm,
        peak_time_s: b.peak_time,
        energy: b.energy,
        max_bend_deg: b.max_bend_deg,
        bend_turns: b.bend_turns,
        fall_time_s: b.fall_time_s,
        drop_height_m: p.drop.height_for(b.fall_time_s),
    });
    row.bend = bend_samples(cat, &b.spline, b.fall_time_s);
    let named = NamedTree::of(cat, p.rapier.cross_mass_fraction)?;
    row.files = tree_files(
        p,
        &named,
        &SplineShape(&b.spline),
        &flip,
        &ExportOptions { rate_hz: None, steps_per_piece: STEPS_PER_SPAN },
    )?;
    if verify {
        let reference = Reference { twist: flip.twist, swing: flip.swing, peak_torque: b.peak_torque_nm };
        let shape = SplineShape(&b.spline);
        // Rapier bounds the universal and no-twist joints' motors by the torque limit; the
        // spherical joint's motors are not its ball's axes there, and run unbounded.
        let bounded = bounds_motors(&tree);
        let opts = RapierOptions { motors: if bounded { motors } else { Motors::ideal() }, ..RapierOptions::default() };
        row.rapier = Some(verify_tree(&tree, &shape, &p.rapier, &reference, &opts)?);
    }
    row.spline = Some(b.spline.clone());
    row.tree = Some(tree);
    Ok(())
}

/// Instants per phase at which [`held_schedule`] samples the motors' torques.
const HELD_SAMPLES: usize = 4000;

/// The problem's library schedule on a model beyond two motors, its further coordinates held at
/// zero ([`Held`]: the spherical joint's relative twist, a tail straight behind the cat, the legs
/// standing out): its flip
/// by the general core on `tree`, and its peak over every motor, sampled at [`HELD_SAMPLES`] + 1
/// instants of each phase (each phase's own formula at its ends). A calibrated circulation turns
/// this model by π: on a cat with a tail or legs it is calibrated again on the whole tree, the
/// appendages held still ([`WholeCat::calibrate`]; held still, they are parts of their halves and
/// move the flip), from the halves' own. `None` (the table's "—") when the schedule's
/// circulation cannot be resolved on the cat's two-motor halves, or a calibrated one on the tree.
fn held_schedule(p: &Problem, cat: &WholeCat, tree: &Tree) -> Option<ScheduleFigures> {
    let halves = Problem { cat: p.cat.halves_only(), ..p.clone() };
    let mut schedule = Resolved::new(&halves).ok()?.schedule;
    let zero = Vector3::zeros();
    if p.manoeuvre.circulation == Circulation::Calibrated && matches!(cat, WholeCat::Appended(_)) {
        let cal = cat.calibrate(&schedule, &zero, p.exact.tolerance);
        // Not the halves' circulation under the name "calibrated": no schedule.
        if cal.status != RootStatus::Converged {
            return None;
        }
        schedule = schedule.with_circulation(cal.circulation);
    }
    let held = Held(&schedule, tree.dof().saturating_sub(2));
    let flip = models::flip_on(tree, &held, &zero, p.exact.tolerance);
    let peak = ShapeTrajectory::piece_durations(&held)
        .into_iter()
        .enumerate()
        .flat_map(|(piece, d)| (0..=HELD_SAMPLES).map(move |k| (piece, d * k as f64 / HELD_SAMPLES as f64)))
        .flat_map(|(piece, s)| reduction::joint_torques(tree, &held.piece_shape(piece, s), &zero))
        .flat_map(|link| link.tau)
        .fold(0.0, |m: f64, t| m.max(t.abs()));
    Some(ScheduleFigures {
        twist_deg: flip.twist.to_degrees(),
        swing_deg: flip.swing.to_degrees(),
        peak_torque_nm: peak,
    })
}

/// The bend (angle between the spine axes, degrees) of `spline` on `cat` over `fall` s, densely.
fn bend_samples(cat: &WholeCat, spline: &BSpline, fall: f64) -> Vec<(f64, f64)> {
    let n = ((BEND_SAMPLES_PER_S * fall).ceil() as usize).max(64);
    (0..=n)
        .map(|k| {
            let t = fall * k as f64 / n as f64;
            (t, cat.bend_cosine(&spline.angles(t)).0.clamp(-1.0, 1.0).acos().to_degrees())
        })
        .collect()
}
