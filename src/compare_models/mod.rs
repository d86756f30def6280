//! `catflip compare-models`: the whole-manoeuvre optimum of every cat model on the same cat and
//! fall, side by side: which body flips most cheaply (issue 22; DESIGN.md §10).
//!
//! ## The models
//! From the problem's cat ([`variants`]): its halves on the universal joint (the paper's
//! `R_AB = Rx(q1) Ry(q2)`) and on Kane and Scher's no-twist joint (`R_AB = exp([q1, q2, 0]×)`).
//! When the problem's halves differ, the same two joints also join two equal halves of their
//! mean half ([`crate::model::Cat::mean_half`]: the means of the masses, lengths and radii, so
//! the same total mass and length): four models, the first two of equal halves. Each set of
//! halves is also joined by the spherical joint (three motors: the bend's two and the relative
//! twist, [`crate::optimize::whole::WholeCat::Spherical`]), and with `[cat.tail]` or `[cat.legs]`
//! the problem's own cat gets them ([`crate::optimize::whole::WholeCat::Appended`]). These models
//! ([`Beyond`]) are planned on every motor, re-measured by the general core on their tree of
//! bodies and verified in rapier's tree scene; they take no spin, and ideal motors or one torque
//! limit on every motor ([`crate::optimize::whole::torque_limited`]), and a row says so otherwise;
//! their library schedule is the problem's with the further coordinates held at
//! zero (the twist, the tail straight, the legs standing out), a calibrated circulation
//! calibrated on the model itself (on a tail or legs, the whole tree with them held still).
//!
//! Every model gets the problem's fall, release (`drop.angular_momentum`), motors and
//! `[optimize.whole]`; the problem's bend path `"cone"` becomes `"joint-circle"` on the no-twist
//! joint, where the joint circle is the cone (it keeps the bend `|q|` exactly).
//!
//! ## What each row is
//! The optimum of [`crate::measure::whole::whole`] on that model (beyond two motors, of
//! [`crate::optimize::whole::optimize_whole`] on every motor), every number re-measured by the
//! model's exact engine (the general core on any cat but the paper's): peak torque, energy
//! `∫τ·τ dt`, the largest bend and the turns of the bend direction; beside it the problem's own
//! library schedule on that model ([`crate::engines::resolved::Resolved::evaluate`]), and with
//! `--verify` rapier's verdict on the optimum ([`crate::measure::whole::WholeReport::verify`]). A model
//! without an optimum says why, and its numbers are absent, never zero.
//!
//! ## References
//! - T. R. Kane and M. P. Scher, *A dynamical explanation of the falling cat phenomenon*,
//!   Int. J. Solids Structures 5 (1969) 663–670 (the no-twist joint);
//! - the paper, §2 and §7 (the universal joint's cat and its worked example).

mod report;
mod run;

pub use run::{compare_models, CompareModelsError};

use serde::Serialize;

use crate::engines::rapier::Verification;
use crate::model::cat::Appendages;
use crate::model::tree::Tree;
use crate::model::Joint;
use crate::numeric::numfmt::echo;
use crate::optimize::whole::{BSpline, Objective, WholeStatus};
use crate::problem::cat::CatSection;
use crate::problem::manoeuvre::BendPath;
use crate::problem::{Problem, ProblemError};

/// One model of the comparison: its key (file names, CSV), its words and its problem (the
/// problem's fall and settings with this model's cat).
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// `universal`, `no-twist`, `spherical`, their `mean-…` and `unequal-…`, and the problem's
    /// own cat with its tail, `…-tail`.
    pub key: String,
    /// The model in words, e.g. "equal halves, no-twist joint (Kane and Scher's)".
    pub label: String,
    /// The problem with this model's `[cat]` (validated; the no-twist joint's for the spherical
    /// joint, whose starts are that joint's).
    pub problem: Problem,
    /// What the model has beyond two halves on a two-motor joint.
    pub beyond: Beyond,
}

/// What a model has beyond two halves on a two-motor joint: such models are planned by the whole
/// optimiser on every motor, re-measured by the general core and verified in rapier's tree scene
/// ([`crate::engines::rapier::tree_run`]); the one rig the other rows are measured on has two
/// motors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Beyond {
    /// Nothing: two halves on the universal or the no-twist joint.
    TwoMotors,
    /// The halves on the spherical joint: a third motor, the relative twist.
    Spherical,
    /// The problem's cat with its `[cat.tail]` and `[cat.legs]`.
    Appendages(Appendages),
}

/// The status of a row whose model was tried and found no optimum ([`ModelRow::reason`] says why).
pub const NO_OPTIMUM: &str = "no-optimum";
/// The status of a row whose model cannot be planned here ([`ModelRow::reason`] says why).
pub const NOT_RUN: &str = "not-run";

/// The models compared on `problem`'s cat: equal halves (the problem's, or their mean half when
/// they differ) on the universal, the no-twist and the spherical joint, then, when the problem's
/// halves differ, those halves on the three joints, and with `[cat.tail]`, `[cat.legs]` the
/// problem's own cat with them. Each variant's problem is validated, so a field the new model
/// refuses is named.
pub fn variants(problem: &Problem) -> Result<Vec<Variant>, ProblemError> {
    let cat = problem.cat.model();
    let equal = cat.has_equal_halves();
    let half = if equal { cat.front } else { cat.mean_half() };
    // The mean half's models are keyed `mean-…` (their rows, legends and files), so that a
    // reader of a problem with unequal halves never takes them for its own cat.
    let mut halves = vec![if equal {
        (String::new(), "equal halves", CatSection::from(half))
    } else {
        ("mean-".to_string(), "equal halves (the mean half)", CatSection::from(half))
    }];
    if !equal {
        halves.push(("unequal-".to_string(), "unequal halves (the problem's)", problem.cat));
    }
    let mut out = Vec::new();
    for (prefix, halves_label, section) in halves {
        for joint in [Joint::Universal, Joint::NoTwist] {
            let mut p = problem.clone();
            p.cat = CatSection { joint, ..section.halves_only() };
            if joint == Joint::NoTwist && p.manoeuvre.bend_path == BendPath::Cone {
                p.manoeuvre.bend_path = BendPath::JointCircle;
            }
            p.validate()?;
            let whose = match (joint, prefix != "unequal-") {
                (Joint::Universal, true) => " (the paper's model)",
                (Joint::NoTwist, true) => " (Kane and Scher's)",
                _ => "",
            };
            out.push(Variant {
                key: format!("{prefix}{}", joint.name()),
                label: format!("{halves_label}, {} joint{whose}", joint.name()),
                problem: p,
                beyond: Beyond::TwoMotors,
            });
        }
        // The spherical joint: its problem (the library schedule) the no-twist joint's; its
        // starts also the universal joint's optimum (`optimize::whole::lift`).
        if let Some(no_twist) = out.last().map(|v: &Variant| v.problem.clone()) {
            out.push(Variant {
                key: format!("{prefix}spherical"),
                label: format!("{halves_label}, spherical joint (three motors)"),
                problem: no_twist,
                beyond: Beyond::Spherical,
            });
        }
    }
    let appendages = problem.cat.appendages()?;
    if !appendages.is_empty() {
        // The problem's own cat with its tail and legs; its starts are its halves' with them held
        // still, calibrated on its whole tree.
        let own = if equal { String::new() } else { "unequal-".to_string() };
        let key = format!("{own}{}", problem.cat.joint.name());
        if let Some(base) = out.iter().find(|v| v.key == key) {
            let mut p = base.problem.clone();
            (p.cat.tail, p.cat.legs) = (problem.cat.tail, problem.cat.legs);
            let mut label = base.label.clone();
            let mut key = key.clone();
            if let Some(tail) = problem.cat.tail {
                label += &format!(
                    ", with a tail of {} kg, {} m on a {} joint",
                    echo(tail.mass),
                    echo(tail.length),
                    tail.joint.name()
                );
                key += "-tail";
            }
            if let Some([front, rear]) = appendages.legs {
                label += &if front == rear {
                    format!(", with legs of {} kg a pair, {} m", echo(front.mass), echo(front.length))
                } else {
                    format!(
                        ", with front legs of {} kg a pair, {} m, hind legs of {} kg, {} m",
                        echo(front.mass),
                        echo(front.length),
                        echo(rear.mass),
                        echo(rear.length)
                    )
                };
                key += "-legs";
            }
            out.push(Variant { key, label, problem: p, beyond: Beyond::Appendages(appendages) });
        }
    }
    Ok(out)
}

/// The optimum's numbers on one model, re-measured by its exact engine.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OptimumFigures {
    /// The start it came from.
    pub start: String,
    /// The optimiser's iterations (the trust region's or the interior-point method's).
    pub iterations: usize,
    /// How the optimiser ended, in its words (its stopping test; on the spherical joint planned by
    /// the trust region also the universal optimum it started from when it did, and when its
    /// stage stopped at its budget below that optimum, that its value is an upper bound on the
    /// model's optimum).
    pub reason: String,
    /// Signed twist, degrees.
    pub twist_deg: f64,
    /// Swing, degrees.
    pub swing_deg: f64,
    /// Peak motor torque over the fall, N·m.
    pub peak_torque_nm: f64,
    /// When it peaks, s.
    pub peak_time_s: f64,
    /// `∫ τ·τ dt`, N²·m²·s.
    pub energy: f64,
    /// The largest bend (angle between the spine axes), degrees.
    pub max_bend_deg: f64,
    /// How far the bend direction turns over the fall, turns.
    pub bend_turns: f64,
    /// The fall time, s (with the objective `min-time` the least fall time within the motors).
    pub fall_time_s: f64,
    /// The drop height of that fall, `g t²/2`, m (with `min-time` the least drop height from
    /// which this cat turns over within its motors).
    pub drop_height_m: f64,
}

impl OptimumFigures {
    /// The value the objective minimised.
    pub fn objective_value(&self, objective: Objective) -> f64 {
        match objective {
            Objective::Peak => self.peak_torque_nm,
            Objective::Energy => self.energy,
            Objective::MinTime => self.fall_time_s,
        }
    }
}

/// The problem's own library schedule on one model, by its exact engine.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScheduleFigures {
    /// Signed twist, degrees.
    pub twist_deg: f64,
    /// Swing, degrees.
    pub swing_deg: f64,
    /// Peak motor torque, N·m.
    pub peak_torque_nm: f64,
}

/// One model's row.
#[derive(Clone, Debug, Serialize)]
pub struct ModelRow {
    /// [`Variant::key`].
    pub key: String,
    /// [`Variant::label`].
    pub label: String,
    /// The joint of the halves.
    pub joint: Joint,
    /// Its motors: two, three on the spherical joint, two more with a tail.
    pub motors: usize,
    /// The cat in words ([`crate::model::Cat::describe`]; beyond two motors
    /// [`crate::optimize::whole::WholeCat::describe`], the tail's too).
    pub cat: String,
    /// How the optimum ended (`converged`, or `upper-bound`: its last stage stopped at its budget
    /// below what it started from, [`WholeStatus::UpperBound`]), or that there is none:
    /// `no-optimum` (tried, none found) or `not-run` (the model cannot be planned here), with
    /// `reason`.
    pub status: String,
    /// Why there is no optimum (the statuses `no-optimum` and `not-run`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// The optimum, when one flips the cat.
    pub optimum: Option<OptimumFigures>,
    /// The problem's library schedule on this model (absent when its circulation cannot be
    /// resolved on this model; `reason` says why).
    pub schedule: Option<ScheduleFigures>,
    /// Rapier's verification of the optimum (`--verify` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rapier: Option<Verification>,
    /// Wall-clock seconds of this model's optimisation (and verification).
    pub seconds: f64,
    /// The model's problem (for the pictures).
    #[serde(skip)]
    pub problem: Problem,
    /// The optimum's trajectory.
    #[serde(skip)]
    pub spline: Option<BSpline>,
    /// Beyond two motors, the model's tree of bodies (its pictures place every body on it).
    #[serde(skip)]
    pub tree: Option<Tree>,
    /// The optimum's bend (angle between the spine axes) over the fall, `(t s, degrees)`,
    /// sampled densely (for the plot).
    #[serde(skip)]
    pub bend: Vec<(f64, f64)>,
    /// Beyond two motors, the optimum's model and schedule files ([`crate::exchange::tree_files`]),
    /// `(file name, contents)`, written into `<key>/`.
    #[serde(skip)]
    pub files: Vec<(String, String)>,
}

impl ModelRow {
    /// The optimum's peak torque, when there is one.
    pub fn peak(&self) -> Option<f64> {
        self.optimum.as_ref().map(|o| o.peak_torque_nm)
    }

    /// Whether its optimum's number is an upper bound ([`WholeStatus::UpperBound`]).
    pub fn is_upper_bound(&self) -> bool {
        self.optimum.is_some() && self.status == WholeStatus::UpperBound.to_string()
    }

    /// Whether the row is the problem's own unequal halves (keyed `unequal-…`, [`variants`]).
    pub fn has_unequal_halves(&self) -> bool {
        self.key.starts_with("unequal-")
    }

    /// The row of a model that cannot be planned here, and why.
    pub(crate) fn not_run(&mut self, reason: String) {
        (self.status, self.reason) = (NOT_RUN.into(), Some(reason));
    }

    /// The row of a model tried without an optimum, and why.
    pub(crate) fn no_optimum(&mut self, reason: String) {
        (self.status, self.reason) = (NO_OPTIMUM.into(), Some(reason));
    }
}

/// The comparison: every model's row on the same fall.
#[derive(Clone, Debug, Serialize)]
pub struct ModelComparison {
    /// The problem's name.
    pub problem: String,
    /// The command that regenerates it.
    pub command: String,
    /// What the optimiser minimised.
    pub objective: Objective,
    /// The fall time, s.
    pub fall_time_s: f64,
    /// The release's total angular momentum, N·m·s (world frame).
    pub angular_momentum_nms: [f64; 3],
    /// Whether rapier verified the optima.
    pub verified_in_rapier: bool,
    /// One row per model, in [`variants`]' order.
    pub rows: Vec<ModelRow>,
    /// The key of the model whose optimum is cheapest by the objective (none without an optimum).
    pub cheapest: Option<String>,
    /// Wall-clock seconds of the whole comparison.
    pub seconds: f64,
    /// The problem as TOML, every default filled in (the report's provenance header).
    #[serde(skip)]
    pub settings_toml: String,
}

impl ModelComparison {
    /// The cheapest model's row.
    pub fn cheapest_row(&self) -> Option<&ModelRow> {
        self.cheapest.as_ref().and_then(|k| self.rows.iter().find(|r| &r.key == k))
    }
}
