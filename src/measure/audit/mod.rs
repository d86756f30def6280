//! The paper audit (`catflip audit`): every number the paper states or implies in §2–§9, three
//! times over: as **published**, as **literally** recomputed with the paper's own formula and
//! inputs for the problem's cat, and **corrected**; each difference explained in one line.
//!
//! ## Columns
//! - `published`: the number printed in the paper. Numbers of the §7 worked example are shown
//!   only when the problem *is* that example ([`is_worked_example`]: `m = 1`, `l = 1`, `r = 0.1`,
//!   `θ = 45°`, `h = 10`, `g = 9.8`; the phases do not enter any printed number). The paper's
//!   general statements, which hold for any cat (`L ≥ √3 R`, the range `π/2 ≤ θ ≤ π`), are
//!   published for every problem.
//! - `literal`: the paper's formula, slips included, with the problem's mass, length, radius,
//!   `θ = manoeuvre.theta_deg`, fall time `√(2h/g)` and phases. Where the paper's numbers use
//!   the slipped transverse inertia `m(r² + l²)/12` (§6.3 code and §7), so does `literal`.
//! - `corrected`: the right value: solid-cylinder inertia `m(3r² + l²)/12`, `C` in the code's form
//!   `C = 1 − I_z'z' sin(θ/2)/I_yy` ([`crate::schedule::paper_c`]), the twist phase
//!   `T2 = phases[1] · t_fall`, amplitude-corrected torque bounds.
//! - `exact`: left `None` here and filled by the exact engine with [`Audit::set_exact`], except
//!   for the model question ([`models`]: `turn_no_twist`, `turn_universal`), whose entries are the
//!   exact engine's turns and carry them from the start.
//!
//! A literal value *reproduces* a published one when, rounded or truncated to the printed number
//! of decimals, it equals the printed number (the paper truncates `Δt = 1.42857…` to 1.428 and
//! rounds elsewhere); published values given exactly (`√3`, `π/2`) must agree to 1e-9.
//!
//! ## Equations (paper's §2 axes, per half)
//! The paper's axes: `x` normal to the plane of the bend; `y` in that plane, perpendicular to the
//! bisector of the angle `θ` between the halves (π = straight), through both halves' centres (for
//! the straight cat, the spine: our `z`, DESIGN.md §1); `z` along the bisector. Then
//!
//! $$ I_{yy} = I_{y'y'}\cos^2\tfrac\theta2 + I_{z'z'}\sin^2\tfrac\theta2, \quad
//!    I_{zz} = I_{y'y'}\sin^2\tfrac\theta2 + I_{z'z'}\cos^2\tfrac\theta2 + \tfrac{m l^2}{4}\sin^2\tfrac\theta2, \quad
//!    I_{xx} = I_{x'x'} + \tfrac{m l^2}{4}\sin^2\tfrac\theta2 $$
//!
//! (§3 omits the parallel-axis terms), `C = 1 − I_z'z' sin(θ/2)/I_yy`, circulation `π/C`,
//! `ω0 = π/(C T2)`, `I* = m(3r² + 4l²)/12`; peak torques `I* (β/2) π²/T1²`, `I* ω0 π/T2`,
//! `I* (β/2) π²/T3²` with `β = π − θ`; §9's one-turn condition `C(θ) = α`, which with
//! `x = sin(θ/2)` is the quadratic `(I_y − I_z) x² + k I_z x − I_y = 0` with `k = 1/(1 − α)`
//! (the paper's equation has `k = 2(α + 1)`), solved both in closed form and by a bracketing
//! root find ([`crate::numeric::roots::first_root`]).
//!
//! The model question ([`models`]): the paper's `π/C` turns the cat by exactly π through Kane
//! and Scher's no-twist joint, and falls short through the universal joint, whose relative twist
//! (and, on the joint circle, wandering bend) §5's momentum balance does not count.
//!
//! ## JSON
//! [`Audit`] serialises to one object; `entries` is a **map keyed by the stable snake_case key**,
//! in the order of the report, each value an [`Entry`] with `published`, `literal`, `corrected`,
//! `exact` (numbers or `null`), `published_decimals`, `literal_reproduces_published`, `section`,
//! `quantity`, `unit`, `explanation` and the alternative `readings` considered.
//! `omega_readings` (worked example only, else `null`) is the [`readings`] search: how many
//! readings of §7's ω were tried and the nearest ones, ranked.
//!
//! ## References
//! - A. Rasmussen, S. Richardson, W. McDermott, *Cat Flipping* (student paper), §2–§9;
//! - T. R. Kane and M. P. Scher, *A dynamical explanation of the falling cat phenomenon*,
//!   Int. J. Solids Structures 5 (1969) 663–670;
//! - any table of moments of inertia (solid cylinder; parallel-axis theorem).

mod entries;
pub mod formulas;
pub mod models;
mod notes;
pub mod readings;

use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;

use crate::engines::resolved::Resolved;
use crate::problem::Problem;
use crate::schedule::Phase;

/// `α` of §9's one-turn question: the cat turns at half the circulation rate (printed "θ = 1/2").
pub const ALPHA_ONE_TURN: f64 = 0.5;

/// Why an audit could not be amended.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum AuditError {
    /// The problem asks for what this computation does not model (the problem's message).
    #[error("{0}")]
    Problem(String),
    /// No entry has this key.
    #[error("the audit has no entry `{0}`")]
    UnknownKey(String),
}

/// The problem's refusal, in its words.
impl From<crate::problem::ProblemError> for AuditError {
    fn from(e: crate::problem::ProblemError) -> Self {
        AuditError::Problem(e.to_string())
    }
}

/// One alternative reading of a formula that was tried, with its value.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Reading {
    /// What was computed, in words and symbols.
    pub label: String,
    /// Its value in the entry's unit, `None` when undefined.
    pub value: Option<f64>,
}

/// One audited quantity.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Entry {
    /// Stable snake_case key, e.g. `i_star`.
    pub key: &'static str,
    /// Paper section, e.g. `§7`.
    pub section: &'static str,
    /// What the quantity is.
    pub quantity: String,
    /// Unit, SI (angles of `θ` in degrees, as in the problem file).
    pub unit: &'static str,
    /// The number printed in the paper, when one applies to this problem.
    pub published: Option<f64>,
    /// Decimals printed with `published`; `None` when it is exact (e.g. `√3`).
    pub published_decimals: Option<u32>,
    /// The paper's formula and inputs, literally, for this problem.
    pub literal: Option<f64>,
    /// The right value.
    pub corrected: Option<f64>,
    /// The exact engine's value, when one has been set.
    pub exact: Option<f64>,
    /// Whether `literal` reproduces `published` to the printed digits; `None` without both.
    pub literal_reproduces_published: Option<bool>,
    /// One line explaining every difference between the columns, or "agrees".
    pub explanation: String,
    /// Other readings of the formula that were tried.
    pub readings: Vec<Reading>,
}

/// A slip in the paper's text or code that has no number of its own.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Note {
    /// Paper section.
    pub section: &'static str,
    /// What is wrong and what is meant.
    pub text: &'static str,
}

/// The audit of the paper for one problem.
#[derive(Clone, Debug, Serialize)]
pub struct Audit {
    /// The problem's name.
    pub problem: String,
    /// Whether the problem is the paper's §7 worked example (so §7's numbers are published).
    pub worked_example: bool,
    /// The audited quantities, keyed by [`Entry::key`] in JSON.
    #[serde(serialize_with = "entries_as_map")]
    pub entries: Vec<Entry>,
    /// The problem's warnings (the paper's §3 assumptions), from [`Problem::warnings`].
    pub warnings: Vec<String>,
    /// Slips without a number of their own.
    pub notes: Vec<Note>,
    /// The nearest readings of §7's ω from the paper's own ingredients ([`readings::search`]);
    /// `None` unless the problem is the worked example.
    pub omega_readings: Option<readings::ReadingSearch>,
}

fn entries_as_map<S: Serializer>(entries: &[Entry], s: S) -> Result<S::Ok, S::Error> {
    let mut map = s.serialize_map(Some(entries.len()))?;
    for e in entries {
        map.serialize_entry(e.key, e)?;
    }
    map.end()
}

impl Audit {
    /// The entry with a given key.
    pub fn entry(&self, key: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.key == key)
    }

    /// Sets the exact engine's value of an entry (same unit as the entry).
    pub fn set_exact(&mut self, key: &str, value: f64) -> Result<(), AuditError> {
        let entry =
            self.entries.iter_mut().find(|e| e.key == key).ok_or_else(|| AuditError::UnknownKey(key.to_string()))?;
        entry.exact = Some(value);
        Ok(())
    }
}

/// Whether a problem is the paper's §7 worked example: `m = 1`, `l = 1`, `r = 0.1`, `θ = 45°`,
/// `h = 10`, `g = 9.8` (to 1e-9 relative).
pub fn is_worked_example(problem: &Problem) -> bool {
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
    near(problem.cat.mass, 1.0)
        && near(problem.cat.length, 1.0)
        && near(problem.cat.radius, 0.1)
        && near(problem.manoeuvre.theta_deg, 45.0)
        && near(problem.drop.height, 10.0)
        && near(problem.drop.gravity, 9.8)
}

/// The paper audit of a problem.
pub fn audit(problem: &Problem) -> Audit {
    let worked_example = is_worked_example(problem);
    Audit {
        problem: problem.name.clone(),
        worked_example,
        entries: entries::build(problem, worked_example),
        warnings: problem.warnings(),
        notes: notes::NOTES.to_vec(),
        omega_readings: readings::search(problem),
    }
}

/// Whether `literal`, rounded or truncated to `decimals`, equals `published`; exact published
/// values (`decimals = None`) need agreement to 1e-9 relative.
pub(crate) fn reproduces(published: f64, decimals: Option<u32>, literal: f64) -> bool {
    match decimals {
        None => (literal - published).abs() <= 1e-9 * published.abs().max(1.0),
        Some(d) => {
            let scale = 10f64.powi(d as i32);
            let target = (published * scale).round();
            let (r, t) = ((literal * scale).round(), (literal * scale).trunc());
            // Integers held exactly in f64: compare their difference with one half.
            (r - target).abs() < 0.5 || (t - target).abs() < 0.5
        }
    }
}

/// The audit with its `exact` column filled in by the exact engine: the peak torques of the
/// problem's own schedule per phase (largest of the two joints) and the calibrated circulation
/// (left empty when the calibration failed).
pub fn audit_with_exact(r: &Resolved) -> Result<Audit, AuditError> {
    r.require_paper_cat("the audit of the paper's numbers")?;
    let mut a = audit(&r.problem);
    let mut values = Vec::new();
    let peaks = r.own().exact.phase_peaks();
    values.extend([
        ("tau_bend", peaks.phase_max(Phase::Bend)),
        ("tau_twist", peaks.phase_max(Phase::Twist)),
        ("tau_unbend", peaks.phase_max(Phase::Unbend)),
    ]);
    if let Some(c) = r.calibrated() {
        values.push(("circulation", c.radians));
    }
    for (key, value) in values {
        a.set_exact(key, value)?;
    }
    Ok(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_rounds_or_truncates_to_the_printed_digits() {
        assert!(reproduces(1.428, Some(3), 1.4285714)); // truncated
        assert!(reproduces(0.3342, Some(4), 0.3341667)); // rounded
        assert!(!reproduces(2.2514, Some(4), 2.2512762));
        assert!(!reproduces(1.655, Some(3), 1.6599));
        assert!(reproduces(3f64.sqrt(), None, 3f64.sqrt()));
        assert!(!reproduces(3f64.sqrt(), None, 5f64.sqrt()));
    }

    #[test]
    fn set_exact_names_an_unknown_key() {
        let mut a = audit(&Problem::default());
        assert_eq!(a.set_exact("no_such_key", 1.0), Err(AuditError::UnknownKey("no_such_key".into())));
        assert!(a.set_exact("tau_twist", 2.5).is_ok());
        assert_eq!(a.entry("tau_twist").and_then(|e| e.exact).map(|x| x.to_bits()), Some(2.5f64.to_bits()));
    }
}
