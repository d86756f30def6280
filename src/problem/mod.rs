//! The problem file: what a user asks catflip about (DESIGN.md §8).
//!
//! A problem is TOML, SI units, unknown keys rejected. It holds the cat, the drop, the manoeuvre
//! and the settings of each engine and optimiser; every section and field has a default, kept
//! in one `impl Default`. [`Problem::from_toml`] parses, applies `--set key=value` overrides and
//! validates, so that a problem that loads is one every engine can run.

pub mod actuator;
pub mod cat;
pub mod error;
mod file;
pub mod limits;
pub mod manoeuvre;
mod overrides;
mod plausible;
pub use plausible::PLAUSIBLE_HEIGHT_M;
pub mod robust;
pub mod settings;
pub mod whole;

use std::path::Path;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::model::motor::held_to_torque_limit;
use crate::model::Joint;
use crate::numeric::numfmt::{echo, num};
use crate::problem::settings::{ExactSettings, OptimizeSettings, RapierSettings};
use limits::in_range;

pub use actuator::{Actuator, PerJoint};
pub use cat::{CatSection, HalfSection};
pub use error::ProblemError;
pub(crate) use error::{bad, not_positive};
pub use manoeuvre::{BendPath, Circulation, Manoeuvre, ProfileKind};

/// The drop: how long the cat has to turn over, and the spin it is released with.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Drop {
    /// Height the cat falls before landing, m.
    pub height: f64,
    /// Gravitational acceleration, m/s² (positive).
    pub gravity: f64,
    /// Total angular momentum about the centre of mass at release, `[Lx, Ly, Lz]`, N·m·s
    /// (kg·m²/s), in the world frame (A's frame at release: `z` along the spine towards the
    /// head). Constant through the fall; zero is a release without spin (DESIGN.md §9).
    #[serde(skip_serializing_if = "is_zero")]
    pub angular_momentum: [f64; 3],
}

fn is_zero(v: &[f64; 3]) -> bool {
    v.iter().all(|x| x.abs() <= 0.0)
}

impl Default for Drop {
    fn default() -> Self {
        Self { height: 10.0, gravity: 9.8, angular_momentum: [0.0; 3] }
    }
}

impl Drop {
    /// Fall time `sqrt(2h/g)`, s.
    pub fn fall_time(&self) -> f64 {
        (2.0 * self.height / self.gravity).sqrt()
    }

    /// The drop height that gives a fall of `fall_time` s, `g t²/2`, m (the inverse of
    /// [`Drop::fall_time`] at this gravity).
    pub fn height_for(&self, fall_time: f64) -> f64 {
        0.5 * self.gravity * fall_time * fall_time
    }

    /// The release spin `L` (world frame), N·m·s.
    pub fn spin(&self) -> Vector3<f64> {
        Vector3::from(self.angular_momentum)
    }

    /// Whether the cat is released with spin.
    pub fn spins(&self) -> bool {
        !is_zero(&self.angular_momentum)
    }

    /// How far the release spin alone turns the straight cat during the fall, rigidly, in turns:
    /// `|I⁻¹ L| T / 2π`, with `I = diag(I_t, I_t, I_a)` the straight cat's inertia about its
    /// centre of mass ([`crate::model::Cat::straight_inertia`]; a symmetric top turns at the
    /// constant rate `|I⁻¹ L|` about its centre).
    pub fn spin_turns(&self, cat: &crate::model::Cat) -> f64 {
        let (transverse, axial) = cat.straight_inertia();
        let l = self.angular_momentum;
        let rate = (l[0] / transverse).hypot(l[1] / transverse).hypot(l[2] / axial);
        rate * self.fall_time() / std::f64::consts::TAU
    }
}

/// Most turns the release spin may give the straight cat during the fall ([`Drop::spin_turns`]);
/// beyond it the fall is a spin, not a flip, and the integrators' step budgets run out.
pub const MAX_SPIN_TURNS: f64 = 100.0;
/// Turns of the straight cat during the fall above which the release spin is warned about (a
/// cat released by hand turns a fraction of a turn).
pub const WARN_SPIN_TURNS: f64 = 2.0;

/// A whole problem file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Problem {
    /// Name of the problem; results go to `results/<name>/`.
    pub name: String,
    /// The cat: its halves (equal by default) and their joint.
    pub cat: CatSection,
    /// The drop.
    pub drop: Drop,
    /// The manoeuvre: bend, twist, unbend.
    pub manoeuvre: Manoeuvre,
    /// The joint motors' limits (`[actuator]`); absent means ideal motors.
    pub actuator: Actuator,
    /// Settings of the exact engine.
    pub exact: ExactSettings,
    /// Settings of the rapier3d verification.
    pub rapier: RapierSettings,
    /// Settings of the optimisers.
    pub optimize: OptimizeSettings,
    /// Settings of the robustness check (`catflip robust`).
    pub robust: robust::RobustSettings,
    /// What the file left to the defaults, as warnings ([`Problem::load`]; none for text parsed
    /// by [`Problem::from_toml`]).
    #[serde(skip)]
    pub omissions: Vec<String>,
}

impl Default for Problem {
    fn default() -> Self {
        Self {
            name: "paper".to_string(),
            cat: CatSection::default(),
            drop: Drop::default(),
            manoeuvre: Manoeuvre::default(),
            actuator: Actuator::default(),
            exact: ExactSettings::default(),
            rapier: RapierSettings::default(),
            optimize: OptimizeSettings::default(),
            robust: robust::RobustSettings::default(),
            omissions: Vec::new(),
        }
    }
}

impl Problem {
    /// Reads, overrides and validates a problem file ([`Problem::from_user_text`]); a file
    /// without `name` is named after its stem.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Self, ProblemError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| ProblemError::Io { path: path.display().to_string(), source })?;
        let origin = path.display().to_string();
        let table = parse_table(&text, &origin)?;
        let named = file::names_itself(&table, overrides);
        let mut problem = Self::from_user_table(&text, table, &origin, overrides)?;
        if !named {
            let (name, warning) = file::name_from_stem(path)?;
            problem.name = name;
            problem.omissions.extend(warning);
        }
        Ok(problem)
    }

    /// A problem a user wrote (a file's text, or the Python package's `loads`): as
    /// [`Problem::from_toml`], but a key its overrides set twice is refused (the library's
    /// overrides apply in order, the last winning), a text that holds no field is refused, and what it leaves to
    /// the defaults (a section, the drop height, a last line cut short) is kept as a warning
    /// ([`Problem::warnings`]).
    pub fn from_user_text(text: &str, origin: &str, overrides: &[String]) -> Result<Self, ProblemError> {
        Self::from_user_table(text, parse_table(text, origin)?, origin, overrides)
    }

    /// [`Problem::from_user_text`] of `text` already parsed as `table`.
    fn from_user_table(
        text: &str,
        table: toml::Table,
        origin: &str,
        overrides: &[String],
    ) -> Result<Self, ProblemError> {
        overrides::refuse_repeats(overrides)?;
        let omissions = file::omissions(text, &table, origin, overrides)?;
        let mut problem = Self::from_table(table, origin, overrides)?;
        problem.omissions = omissions;
        Ok(problem)
    }

    /// Parses TOML text, applies `key=value` overrides (values in TOML syntax; a bare word is
    /// taken as a string) and validates.
    pub fn from_toml(text: &str, origin: &str, overrides: &[String]) -> Result<Self, ProblemError> {
        Self::from_table(parse_table(text, origin)?, origin, overrides)
    }

    /// [`Problem::from_toml`] of text already parsed as `table`.
    fn from_table(mut table: toml::Table, origin: &str, overrides: &[String]) -> Result<Self, ProblemError> {
        // The file alone first, so that a value it holds is blamed on it and one an override
        // brings in on that override.
        let from_file: Result<Problem, toml::de::Error> = table.clone().try_into();
        from_file.map_err(|e| ProblemError::Parse { origin: origin.to_string(), message: user_message(&e) })?;
        for assignment in overrides {
            overrides::apply(&mut table, assignment)?;
        }
        let problem: Problem = table.clone().try_into().map_err(|e: toml::de::Error| {
            let message = user_message(&e);
            ProblemError::BadOverride { assignment: blamed(overrides, &message), reason: message }
        })?;
        problem.validate().map_err(|e| said_default(e, &table))?;
        Ok(problem)
    }

    /// The problem with rapier's first step set to `dt` seconds when given (the command line's
    /// `--dt`, which overrides `rapier.dt`), refused unless finite and positive.
    pub fn with_rapier_dt(mut self, dt: Option<f64>) -> Result<Problem, ProblemError> {
        let Some(dt) = dt else { return Ok(self) };
        if !dt.is_finite() || dt <= 0.0 {
            return Err(ProblemError::BadOption {
                option: "--dt".into(),
                value: crate::numeric::numfmt::echo(dt),
                reason: "must be a finite, positive time step in seconds".into(),
            });
        }
        self.rapier = self.rapier.with_dt(dt);
        Ok(self)
    }

    /// Checks every field a model or engine relies on; names the first bad one.
    pub fn validate(&self) -> Result<(), ProblemError> {
        if !names_a_folder(&self.name) {
            return Err(bad(
                "name",
                &self.name,
                "must be non-empty and use only letters, digits, '-' and '_' (it names a results folder)",
            ));
        }
        self.cat.validate()?;
        in_range("drop.height", self.drop.height, limits::HEIGHT)?;
        in_range("drop.gravity", self.drop.gravity, limits::GRAVITY)?;
        let fall = self.drop.fall_time();
        if !(limits::FALL_TIME.min..=limits::FALL_TIME.max).contains(&fall) {
            return Err(bad(
                "drop.height",
                echo(self.drop.height),
                &format!(
                    "with drop.gravity = {} m/s² the fall takes {} s; the fall time √(2h/g) must lie in {}",
                    echo(self.drop.gravity),
                    num(fall),
                    limits::FALL_TIME
                ),
            ));
        }
        self.validate_spin()?;
        self.manoeuvre.validate()?;
        if self.cat.joint == Joint::NoTwist && self.manoeuvre.bend_path == BendPath::Cone {
            return Err(bad(
                "manoeuvre.bend_path",
                "\"cone\"",
                "the cone's joint angles are the universal joint's; on cat.joint = \"no-twist\" the joint circle is the cone (it keeps the bend |q| exactly): set bend_path = \"joint-circle\"",
            ));
        }
        self.actuator.validate()?;
        self.exact.validate()?;
        self.rapier.validate()?;
        self.optimize.validate()?;
        self.robust.validate()?;
        if self.optimize.whole.objective == whole::Objective::MinTime && self.actuator.motors().is_ideal() {
            return Err(bad("optimize.whole.objective", "\"min-time\"", whole::MIN_TIME_NEEDS_LIMITS));
        }
        Ok(())
    }

    /// Whether every cat the robustness study draws around this one is a cat the loader takes
    /// ([`CatSection::validate_spreads`]): checked by the commands that run the study (`robust`,
    /// `run`), not on loading, so that a cat near a bound is not refused by a study it never runs.
    pub fn validate_robust_draws(&self) -> Result<(), ProblemError> {
        let r = &self.robust;
        self.cat.validate_spreads([
            ("robust.mass_pct", r.mass_pct),
            ("robust.length_pct", r.length_pct),
            ("robust.radius_pct", r.radius_pct),
        ])
    }

    /// `drop.angular_momentum`: finite, and not so large that the fall is a spin.
    fn validate_spin(&self) -> Result<(), ProblemError> {
        let l = self.drop.angular_momentum;
        if let Some(i) = l.iter().position(|x| !x.is_finite()) {
            return Err(bad(&format!("drop.angular_momentum[{i}]"), echo(l[i]), "must be a finite number (N·m·s)"));
        }
        let turns = self.drop.spin_turns(&self.cat.model());
        if turns > MAX_SPIN_TURNS {
            return Err(bad(
                "drop.angular_momentum",
                format!("[{}, {}, {}]", echo(l[0]), echo(l[1]), echo(l[2])),
                &format!(
                    "would spin the straight cat {} turns during the {} s fall (at most {}): is it in N·m·s (kg·m²/s)?",
                    num(turns),
                    num(self.drop.fall_time()),
                    MAX_SPIN_TURNS
                ),
            ));
        }
        Ok(())
    }

    /// Refuses a release with spin for a computation that plans or measures zero-momentum flips
    /// only (`what` names it in the message).
    pub fn require_no_spin(&self, what: &str) -> Result<(), ProblemError> {
        if !self.drop.spins() {
            return Ok(());
        }
        let l = self.drop.angular_momentum;
        Err(bad(
            "drop.angular_momentum",
            format!("[{}, {}, {}]", echo(l[0]), echo(l[1]), echo(l[2])),
            &format!("{what} assumes a release without spin; `simulate` (also with --schedule), `compare`, `robust` and `optimize --whole` (without --out) take a spin (set it to [0, 0, 0] here)"),
        ))
    }

    /// Refuses a cat other than the paper's (equal halves on the universal joint) for a
    /// computation that models the paper's cat only (`what` names it in the message), naming the
    /// field that departs from it.
    pub fn require_paper_cat(&self, what: &str) -> Result<(), ProblemError> {
        if let Some((field, shown)) = self.cat.appendage() {
            return Err(bad(field, shown, &cat::appendage_refused(field)));
        }
        let Some((field, value)) = self.cat.departure() else { return Ok(()) };
        Err(bad(
            &field,
            value,
            &format!("{what} models the paper's cat only (equal halves on the universal joint) so far; `simulate` (exact engine and rapier), `compare`, `optimize --whole [--verify]`, `compare-models`, `run` (without the audit and the profile QP) and `robust` with robust.engine = \"exact\" run this cat (its circulation given or calibrated)"),
        ))
    }

    /// Refuses the spherical joint for a computation that builds the two-motor joints only (the
    /// schedule files and the model files; `what` names it in the message), naming `cat.joint`;
    /// the universal and no-twist joints pass, on equal or unequal halves.
    pub fn require_two_motor_joint(&self, what: &str) -> Result<(), ProblemError> {
        if self.cat.joint != Joint::Spherical {
            return Ok(());
        }
        Err(bad(
            "cat.joint",
            format!("\"{}\"", self.cat.joint.name()),
            &format!("{what} builds the universal and no-twist joints only (two motors) so far; the spherical joint's third coordinate has no schedule, and its twist held at zero is exactly cat.joint = \"no-twist\""),
        ))
    }

    /// A warning for each half shorter than `√3 ×` its radius (the paper's stability argument,
    /// §3), naming the half as the problem file does (`cat`, or `cat.front` and `cat.rear`).
    pub fn short_halves(&self) -> Vec<String> {
        let halves = if self.cat.front() == self.cat.rear() {
            vec![("cat", self.cat.front())]
        } else {
            vec![("cat.front", self.cat.front()), ("cat.rear", self.cat.rear())]
        };
        halves
            .into_iter()
            .filter(|(_, h)| !h.is_long_enough())
            .map(|(name, half)| {
                format!(
                    "{name}.length = {} < √3 · {name}.radius = {:.4}: the paper's stability argument (§3) needs L ≥ √3 R",
                    half.length,
                    3f64.sqrt() * half.radius
                )
            })
            .collect()
    }

    /// [`Self::warnings`] but those of `[manoeuvre]` (each names its field or section first), for a
    /// command that measures a schedule file on the problem's cat and does not use its manoeuvre
    /// (`simulate --schedule`): a careless mass or drop height is still warned of, the paper's θ
    /// is not.
    pub fn warnings_without_manoeuvre(&self) -> Vec<String> {
        self.warnings().into_iter().filter(|w| !w.starts_with("manoeuvre.") && !w.contains("[manoeuvre]")).collect()
    }

    /// Warnings about a problem that loads but sits outside the paper's assumptions (§3).
    pub fn warnings(&self) -> Vec<String> {
        let mut out = self.omissions.clone();
        let turns = self.drop.spin_turns(&self.cat.model());
        if turns > WARN_SPIN_TURNS {
            out.push(format!(
                "drop.angular_momentum turns the straight cat {} turns during the fall: a cat released by hand turns a fraction of a turn (is it in N·m·s, kg·m²/s?)",
                num(turns)
            ));
        }
        out.extend(plausible::warnings(self));
        out.extend(self.short_halves());
        if self.manoeuvre.theta_deg < 90.0 {
            out.push(format!(
                "manoeuvre.theta_deg = {} < 90: outside the paper's stability range π/2 ≤ θ ≤ π (§3, printed as \"π ≤ θ ≤ π/2\")",
                self.manoeuvre.theta_deg
            ));
        }
        // The tracked trials' servo is sized on the paper's half (robust; README, "Will it land
        // on its feet, and how often?").
        let half = self.cat.half();
        let stiffening = (0.5 * half.end_transverse() / half.axial()).sqrt();
        out.extend(self.robust.warnings(self.drop.fall_time(), stiffening));
        out.extend(self.method_warning());
        out
    }

    /// The interior-point method asked for by name where the trust-region loop plans instead
    /// (`auto` says nothing where it does not apply): it solves
    /// the least peak with ideal motors, without spin and without a bend limit (and so a cat of
    /// more than two motors within one torque limit on every motor, planned as that least peak
    /// and then slowed, whatever its objective).
    fn method_warning(&self) -> Option<String> {
        let w = &self.optimize.whole;
        if w.method != whole::Method::InteriorPoint {
            return None;
        }
        let motors = self.actuator.motors();
        let joints = self.cat.model().dof() + self.cat.appendages().map_or(0, |a| a.dof());
        let held = held_to_torque_limit(joints, &motors).is_some();
        let elsewhere = [
            (w.objective != whole::Objective::Peak && !held, format!("objective = \"{}\"", w.objective.name())),
            (!motors.is_ideal() && !held, "the [actuator] limits".to_string()),
            (self.drop.spins(), "drop.angular_momentum".to_string()),
            (w.min_angle_deg.is_some(), "optimize.whole.min_angle_deg".to_string()),
        ];
        let why: Vec<String> = elsewhere.into_iter().filter(|(on, _)| *on).map(|(_, what)| what).collect();
        (!why.is_empty()).then(|| {
            format!(
                "optimize.whole.method = \"interior-point\" solves the least peak with ideal motors, without spin and without a bend limit: with {} this problem is planned by the trust-region loop",
                why.join(" and ")
            )
        })
    }
}

/// `text` as a TOML table, or the parser's error on the line it names ([`toml_error`]).
fn parse_table(text: &str, origin: &str) -> Result<toml::Table, ProblemError> {
    text.parse().map_err(|e: toml::de::Error| {
        let (origin, message) = toml_error(text, origin, &e);
        ProblemError::Parse { origin, message }
    })
}

/// The TOML error `e` in `text` (read from `origin`) as `origin, line N` and the parser's
/// message on one line (without its quotation of the file): the line counted from 1 (a span at a
/// line's start is on that line, not the one before), a duplicate key named (toml says
/// "duplicate key" without it; its span holds it). The problem files' and the sweep files' form.
pub(crate) fn toml_error(text: &str, origin: &str, e: &toml::de::Error) -> (String, String) {
    let line = e.span().map(|s| text.as_bytes()[..s.start.min(text.len())].iter().filter(|&&b| b == b'\n').count() + 1);
    let quoted = e.span().and_then(|s| text.get(s)).map(str::trim).filter(|k| !k.is_empty() && !k.contains('\n'));
    let message = match quoted {
        Some(key) if e.message().trim() == "duplicate key" => format!("duplicate key `{key}`"),
        _ => one_line(e.message()),
    };
    (line.map_or(origin.to_string(), |l| format!("{origin}, line {l}")), message)
}

/// Whether `name` can name a results folder: non-empty, letters, digits, `-` and `_` only.
pub(crate) fn names_a_folder(name: &str) -> bool {
    !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
}

/// A parse error in the user's words: serde's type names replaced by the file's section names and
/// plain descriptions (`expected struct CatSection` reads `expected the [cat] section`).
fn user_message(e: &toml::de::Error) -> String {
    const NAMES: [(&str, &str); 20] = [
        ("invalid type: unit variant, expected string only", "expected a name in quotes"),
        ("struct TailSection", "the [cat.tail] section"),
        ("struct LegsSection", "the [cat.legs] section"),
        ("struct Cylinder", "a body's mass, length and radius"),
        (
            "data did not match any variant of untagged enum PerJoint",
            "expected a number (both joints) or a pair [joint 1, joint 2]",
        ),
        ("struct Actuator", "the [actuator] section"),
        ("struct Problem", "a problem file"),
        ("struct CatSection", "the [cat] section"),
        ("struct HalfSection", "the [cat.front] or [cat.rear] section"),
        ("struct Drop", "the [drop] section"),
        ("struct Manoeuvre", "the [manoeuvre] section"),
        ("struct ExactSettings", "the [exact] section"),
        ("struct RapierSettings", "the [rapier] section"),
        ("struct OptimizeSettings", "the [optimize] section"),
        ("struct RobustSettings", "the [robust] section"),
        ("expected f64", "expected a number"),
        ("expected usize", "expected a whole number"),
        ("expected u32", "expected a whole number"),
        ("expected u64", "expected a whole number"),
        ("expected i64", "expected a whole number"),
    ];
    let message = NAMES.iter().fold(one_line(&e.to_string()), |m, (from, to)| m.replace(from, to));
    // One list of joints serves the halves and the tail; the halves' cannot be a hinge.
    if message.ends_with("in `cat.joint`") {
        return message.replace(", `hinge`", " (a hinge joins a tail only)");
    }
    message
}

/// A refused value the user did not write (`table`: the file with the overrides applied) is said
/// to be the default, so that the message does not read as if the user had set it (a rapier step
/// blamed `robust.feedback_hz = 1000`, a default, a QA run found). The cat's fields are left as
/// they are: a half's number can come from `[cat]`'s shorthand, not from a default.
fn said_default(e: ProblemError, table: &toml::Table) -> ProblemError {
    match e {
        ProblemError::BadFieldValue { field, value, reason } if !field.starts_with("cat.") && !gives(table, &field) => {
            ProblemError::BadFieldValue { value: format!("{value} (the default: not set here)"), field, reason }
        }
        other => other,
    }
}

/// Whether `table` gives the dotted `field` (an index such as `phases[2]` is its array's).
fn gives(table: &toml::Table, field: &str) -> bool {
    let path = field.split('[').next().unwrap_or(field);
    let mut at = table;
    let mut keys = path.split('.').peekable();
    while let Some(key) = keys.next() {
        match at.get(key) {
            None => return false,
            Some(toml::Value::Table(inner)) if keys.peek().is_some() => at = inner,
            Some(_) => return keys.peek().is_none(),
        }
    }
    false
}

/// The override(s) a parse error that the file alone does not have must come from: the one whose
/// key the message names (`… in `cat.mass``), else all of them.
fn blamed(overrides: &[String], message: &str) -> String {
    let key = message.rsplit_once(" in `").map(|(_, k)| k.trim_end_matches('`'));
    let named = key.and_then(|key| {
        overrides.iter().rev().find(|o| {
            let k = o.split_once('=').map_or(o.as_str(), |(k, _)| k).trim();
            k == key || k.starts_with(&format!("{key}.")) || key.starts_with(&format!("{k}."))
        })
    });
    match named {
        Some(o) => o.clone(),
        None => overrides.join(" --set "),
    }
}

/// `s` on one line, its runs of white space (line breaks included) made one space.
pub(crate) fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
