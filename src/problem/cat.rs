//! The problem file's `[cat]` section: the cat's halves and their joint (DESIGN.md §8, §10).
//!
//! `[cat]`'s `mass`, `length` and `radius` (kg, m, m) are the shorthand for two equal halves, the
//! paper's cat. `[cat.front]` and `[cat.rear]` give a half of its own: each field a half leaves
//! out is the shorthand's, so `[cat.rear] mass = 1.5` makes only the rear half heavier. `joint`
//! is `"universal"` (the paper's `R_AB = Rx(q1) Ry(q2)`, the default), `"no-twist"` (Kane and
//! Scher's `R_AB = exp([q1, q2, 0]×)`) or `"spherical"` (three coordinates, the relative twist
//! the third; refused until a schedule drives it: the library schedules give two coordinates).
//! `[cat.tail]` hangs a rod from the rear half ([`TailSection`]) and `[cat.legs]` a pair of legs
//! from each half ([`LegsSection`]): `catflip compare-models` plans the cat with them; every other
//! command refuses them ([`crate::engines::measured::Rig::new`], [`appendage_refused`]).
//!
//! The model the engines run is [`CatSection::model`]. The paper's cat (equal halves on the
//! universal joint) runs every command; any other two-motor model runs the exact engine's
//! commands (`simulate`, the calibration, `compare`), rapier, the whole optimiser and `run` (less
//! its parts for the paper's cat, [`crate::measure::run::PaperOnly`]), and every other command
//! refuses it by name ([`crate::problem::Problem::require_paper_cat`]).

use serde::{Deserialize, Serialize};

use crate::model::cat::Appendages;
use crate::model::{Cat, Cylinder, Joint};
use crate::numeric::numfmt::echo;
use crate::problem::error::{bad, positive, ProblemError};
use crate::problem::limits::{self, in_range};

/// The `[cat]` section.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CatSection {
    /// Mass of a half, kg (both halves unless `[cat.front]`/`[cat.rear]` say otherwise).
    pub mass: f64,
    /// Length of a half, m.
    pub length: f64,
    /// Radius of a half, m.
    pub radius: f64,
    /// How the rear half is joined to the front half.
    #[serde(skip_serializing_if = "is_universal")]
    pub joint: Joint,
    /// The front half A, where it differs from the shorthand.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub front: Option<HalfSection>,
    /// The rear half B, where it differs from the shorthand.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rear: Option<HalfSection>,
    /// A tail on the rear half ([`TailSection`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tail: Option<TailSection>,
    /// Legs on both halves ([`LegsSection`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub legs: Option<LegsSection>,
}

fn is_universal(j: &Joint) -> bool {
    *j == Joint::Universal
}

/// A rod's numbers as a section names them: a half's, a tail's, a pair of legs'.
pub const ROD_KEYS: [&str; 3] = ["mass", "length", "radius"];

/// `[cat.front]` or `[cat.rear]`: a half's own numbers, each defaulting to `[cat]`'s; as
/// `[cat.legs.front]` or `[cat.legs.rear]`, a pair of legs' own, each defaulting to `[cat.legs]`'s.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HalfSection {
    /// Mass, kg.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// Length, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub length: Option<f64>,
    /// Radius, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
}

impl HalfSection {
    /// `base` with the numbers this section gives.
    pub fn over(own: Option<HalfSection>, base: Cylinder) -> Cylinder {
        let own = own.unwrap_or_default();
        Cylinder {
            mass: own.mass.unwrap_or(base.mass),
            length: own.length.unwrap_or(base.length),
            radius: own.radius.unwrap_or(base.radius),
        }
    }

    /// The number this section gives for `key` ([`ROD_KEYS`]).
    fn get(&self, key: &str) -> Option<f64> {
        match key {
            "mass" => self.mass,
            "length" => self.length,
            _ => self.radius,
        }
    }

    /// The numbers this section gives, as the problem file writes them (`mass = 0.3, …`).
    fn shown(&self) -> String {
        [("mass", self.mass), ("length", self.length), ("radius", self.radius)]
            .into_iter()
            .filter_map(|(key, value)| value.map(|v| format!("{key} = {}", echo(v))))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Why a command other than `compare-models` refuses the appendage `[section]` (`cat.tail`,
/// `cat.legs`).
pub fn appendage_refused(section: &str) -> String {
    format!("a cat with a tail or legs is planned and verified by `catflip compare-models` only, so far; this command measures the two halves (the schedules, their tables and the model files have two bodies): remove [{section}] here")
}

/// `[cat.tail]`: a rod hung from the rear half's end by its own front end, straight behind the
/// cat at zero ([`Cat::tree_with`]), with two motors (`joint = "universal"`, the default, or
/// `"no-twist"`) or one (`"hinge"`, about the rear half's `x`). `catflip compare-models` plans and
/// verifies the cat with it beside the cat without; every other command measures two bodies and
/// refuses it ([`appendage_refused`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TailSection {
    /// Mass, kg.
    pub mass: f64,
    /// Length, m.
    pub length: f64,
    /// Radius, m.
    pub radius: f64,
    /// How it is joined to the rear half.
    #[serde(default)]
    pub joint: Joint,
}

/// `[cat.legs]`: each half's pair of legs as one rod of the pair's mass, hung by its top end from
/// the hips on the belly's midline at the drawn legs' station, on a hinge about the half's `x` (one
/// motor a pair): at zero the legs stand out along the belly, and they swing towards the head or
/// the tail by at most 90° (parallel to the spine; [`Cat::tree_with`]). Its numbers are both
/// pairs' unless `[cat.legs.front]` or `[cat.legs.rear]` give a pair its own (as `[cat.front]`
/// and `[cat.rear]` do for the halves); each number a pair needs must come from one of the two
/// ([`LegsSection::pairs`]). Refused as `[cat.tail]` is by every command but `compare-models`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LegsSection {
    /// Mass of each pair, kg (none when each pair gives its own).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// Length of a leg, m (none when each pair gives its own).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length: Option<f64>,
    /// Radius of a leg, m (none when each pair gives its own).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// The front half's pair, where it differs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub front: Option<HalfSection>,
    /// The rear half's pair, where it differs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rear: Option<HalfSection>,
}

impl LegsSection {
    /// The numbers `[cat.legs]` itself gives (both pairs' unless a pair gives its own).
    fn shorthand(&self) -> HalfSection {
        HalfSection { mass: self.mass, length: self.length, radius: self.radius }
    }

    /// Each pair's field and own section: `cat.legs.front`, then `cat.legs.rear`.
    fn own(&self) -> [(&'static str, Option<HalfSection>); 2] {
        [("cat.legs.front", self.front), ("cat.legs.rear", self.rear)]
    }

    /// Each pair's numbers ([`ROD_KEYS`]) with the field each comes from: the pair's own section's
    /// when it gives it (`cat.legs.front.mass`), else `[cat.legs]`'s (`cat.legs.mass`); refused
    /// as [`Self::pairs`] says.
    fn sourced(&self) -> Result<[[(String, f64); 3]; 2], ProblemError> {
        let shorthand = self.shorthand();
        let own = self.own();
        let mut out: [[(String, f64); 3]; 2] = Default::default();
        for (k, key) in ROD_KEYS.into_iter().enumerate() {
            let lacking: Vec<usize> = (0..2).filter(|&p| own[p].1.and_then(|o| o.get(key)).is_none()).collect();
            for pair in 0..2 {
                let (field, section) = own[pair];
                out[pair][k] = match (section.and_then(|o| o.get(key)), shorthand.get(key)) {
                    (Some(v), _) => (format!("{field}.{key}"), v),
                    (None, Some(v)) => (format!("cat.legs.{key}"), v),
                    (None, None) => {
                        let (at, reason) = match section {
                            _ if lacking.len() == 2 => (
                                format!("cat.legs.{key}"),
                                "neither pair's section gives it, nor [cat.legs]".to_string(),
                            ),
                            Some(_) => {
                                (format!("{field}.{key}"), format!("given neither in [{field}] nor in [cat.legs]"))
                            }
                            None => {
                                let name = field.trim_start_matches("cat.legs.");
                                (format!("cat.legs.{key}"), format!("the {name} pair has no [{field}] to give it"))
                            }
                        };
                        return Err(bad(
                            &at,
                            "(not given)",
                            &format!("{reason}: each pair of legs needs a mass, a length and a radius"),
                        ));
                    }
                };
            }
        }
        Ok(out)
    }

    /// The front pair's rod and the rear pair's, each number its own section's, else
    /// `[cat.legs]`'s; a number neither gives is refused, named where one line supplies it
    /// (`cat.legs.radius` when both pairs lack it or the pair has no section of its own, else the
    /// pair's own field).
    pub fn pairs(&self) -> Result<[Cylinder; 2], ProblemError> {
        Ok(self.sourced()?.map(|[(_, mass), (_, length), (_, radius)]| Cylinder { mass, length, radius }))
    }

    /// Checks every number: each `[cat.legs]` gives (used by a pair or not), then each pair's
    /// rod, each number named where it comes from.
    fn validate(&self) -> Result<(), ProblemError> {
        let shorthand = self.shorthand();
        validate_numbers(&ROD_KEYS.map(|key| format!("cat.legs.{key}")), ROD_KEYS.map(|key| shorthand.get(key)))?;
        for [(mass_field, mass), (length_field, length), (radius_field, radius)] in self.sourced()? {
            validate_rod(&[mass_field, length_field, radius_field], &Cylinder { mass, length, radius })?;
        }
        Ok(())
    }

    /// Each pair with a section of its own: `(field, its section)` for `cat.legs.front` and
    /// `cat.legs.rear`.
    pub fn own_pairs(&self) -> impl Iterator<Item = (&'static str, HalfSection)> {
        self.own().into_iter().filter_map(|(field, own)| own.map(|o| (field, o)))
    }

    /// The section as the problem file writes it, for messages.
    pub fn shown(&self) -> String {
        let mut parts = vec![self.shorthand().shown()];
        for (name, own) in [("front", self.front), ("rear", self.rear)] {
            if let Some(own) = own {
                parts.push(format!("{name} = {{ {} }}", own.shown()));
            }
        }
        let parts: Vec<String> = parts.into_iter().filter(|p| !p.is_empty()).collect();
        format!("{{ {} }}", parts.join(", "))
    }
}

impl TailSection {
    /// The rod.
    pub fn rod(&self) -> Cylinder {
        Cylinder { mass: self.mass, length: self.length, radius: self.radius }
    }

    /// The section as the problem file writes it, for messages.
    pub fn shown(&self) -> String {
        format!(
            "{{ mass = {}, length = {}, radius = {}, joint = \"{}\" }}",
            echo(self.mass),
            echo(self.length),
            echo(self.radius),
            self.joint.name()
        )
    }
}

impl Default for CatSection {
    fn default() -> Self {
        CatSection::from(Cylinder::default())
    }
}

impl From<Cylinder> for CatSection {
    /// The paper's cat with halves `half`.
    fn from(half: Cylinder) -> Self {
        CatSection {
            mass: half.mass,
            length: half.length,
            radius: half.radius,
            joint: Joint::Universal,
            front: None,
            rear: None,
            tail: None,
            legs: None,
        }
    }
}

impl CatSection {
    /// The appendages as the model's ([`Appendages`]).
    pub fn appendages(&self) -> Result<Appendages, ProblemError> {
        Ok(Appendages { tail: self.tail.map(|t| (t.rod(), t.joint)), legs: self.legs.map(|l| l.pairs()).transpose()? })
    }

    /// The two halves alone: this section without its tail and legs.
    pub fn halves_only(self) -> CatSection {
        CatSection { tail: None, legs: None, ..self }
    }

    /// The first appendage section present, `(field, as written)`, for refusals.
    pub fn appendage(&self) -> Option<(&'static str, String)> {
        self.tail.map(|t| ("cat.tail", t.shown())).or_else(|| self.legs.map(|l| ("cat.legs", l.shown())))
    }

    /// The shorthand's half: both halves of the paper's cat. A command that models the paper's
    /// cat only uses it after [`crate::problem::Problem::require_paper_cat`].
    pub fn half(&self) -> Cylinder {
        Cylinder { mass: self.mass, length: self.length, radius: self.radius }
    }

    /// The front half A.
    pub fn front(&self) -> Cylinder {
        self.resolve(self.front)
    }

    /// The rear half B.
    pub fn rear(&self) -> Cylinder {
        self.resolve(self.rear)
    }

    fn resolve(&self, own: Option<HalfSection>) -> Cylinder {
        HalfSection::over(own, self.half())
    }

    /// The model the engines run.
    pub fn model(&self) -> Cat {
        Cat { front: self.front(), rear: self.rear(), joint: self.joint }
    }

    /// Whether this is the paper's cat: equal halves on the universal joint.
    pub fn is_paper(&self) -> bool {
        self.model().paper().is_some()
    }

    /// The field a reader should look at for what makes this cat not the paper's, with its value.
    pub fn departure(&self) -> Option<(String, String)> {
        if self.joint != Joint::Universal {
            return Some(("cat.joint".into(), format!("\"{}\"", self.joint.name())));
        }
        self.unequal_halves()
    }

    /// The field that makes the halves differ, with its value: the first number (mass, length,
    /// radius) that differs, on the half whose section writes it (the rear's when both do).
    /// None for equal halves.
    pub fn unequal_halves(&self) -> Option<(String, String)> {
        let (front, rear) = (self.front(), self.rear());
        let r = self.rear.unwrap_or_default();
        let keys = [
            ("mass", front.mass, rear.mass, r.mass.is_some()),
            ("length", front.length, rear.length, r.length.is_some()),
            ("radius", front.radius, rear.radius, r.radius.is_some()),
        ];
        let (key, a, b, in_rear) = keys.into_iter().find(|k| k.1.to_bits() != k.2.to_bits())?;
        // A number differs only where a half's own section writes it: the rear's, else the front's.
        let (half, value) = if in_rear { ("cat.rear", b) } else { ("cat.front", a) };
        Some((format!("{half}.{key}"), echo(value)))
    }

    /// Checks each half's numbers and the joint, naming the field as the user wrote it.
    pub fn validate(&self) -> Result<(), ProblemError> {
        validate_half("cat", &self.half())?;
        // A half of its own: each number named where it comes from, its section's or [cat]'s.
        for (name, own, half) in [("cat.front", self.front, self.front()), ("cat.rear", self.rear, self.rear())] {
            if let Some(own) = own {
                let fields = ROD_KEYS.map(|key| match own.get(key) {
                    Some(_) => format!("{name}.{key}"),
                    None => format!("cat.{key}"),
                });
                validate_rod(&fields, &half)?;
            }
        }
        if let Some(tail) = &self.tail {
            validate_half("cat.tail", &tail.rod())?;
            if tail.joint == Joint::Spherical {
                return Err(bad(
                    "cat.tail.joint",
                    "\"spherical\"",
                    "the tail's joint has one or two motors so far: \"universal\", \"no-twist\" or \"hinge\"",
                ));
            }
        }
        if let Some(legs) = &self.legs {
            legs.validate()?;
        }
        if self.joint == Joint::Hinge {
            return Err(bad(
                "cat.joint",
                "\"hinge\"",
                "a hinge is an appendage's joint (one motor): halves bent in one plane cannot turn over at zero momentum; use \"universal\", \"no-twist\" or \"spherical\"",
            ));
        }
        if self.joint == Joint::Spherical {
            return Err(bad(
                "cat.joint",
                "\"spherical\"",
                "the spherical joint's third coordinate (the relative twist) has no schedule yet: the library schedules drive two coordinates. Its twist held at zero is exactly \"no-twist\"",
            ));
        }
        Ok(())
    }
}

impl CatSection {
    /// Whether every cat a robustness study draws (each half's mass, length and radius scaled by
    /// up to `±pct` percent of itself, [`crate::robust::drawn_cat`]) is one this section would
    /// take: the halves at the corners of the draws, checked as the loader checks a half. The
    /// error names the spread that reaches past (`spreads`: the mass's, the length's and the
    /// radius's field and value) and the half it makes.
    pub fn validate_spreads(&self, spreads: [(&str, f64); 3]) -> Result<(), ProblemError> {
        let factors = |pct: f64| [1.0 - pct / 100.0, 1.0 + pct / 100.0];
        let [(mass_field, m), (length_field, l), (radius_field, r)] = spreads;
        // The halves the draws scale: the shorthand's on the paper's cat, each half's otherwise.
        let halves = if self.is_paper() {
            vec![("cat", self.half())]
        } else {
            vec![("cat.front", self.front()), ("cat.rear", self.rear())]
        };
        let scaled = |c: Cylinder, [fm, fl, fr]: [f64; 3]| Cylinder {
            mass: c.mass * fm,
            length: c.length * fl,
            radius: c.radius * fr,
        };
        for (name, half) in halves {
            for fm in factors(m) {
                for fl in factors(l) {
                    for fr in factors(r) {
                        let drawn = scaled(half, [fm, fl, fr]);
                        let Err(e) = validate_half(name, &drawn) else { continue };
                        // The half itself is valid (checked first): the spread that fails alone
                        // at this corner is blamed, the length's and the radius's together when
                        // only their combination does.
                        let alone = |f: [f64; 3]| validate_half(name, &scaled(half, f)).is_err();
                        let (field, pct) = if alone([fm, 1.0, 1.0]) {
                            (mass_field.to_string(), echo(m))
                        } else if alone([1.0, fl, 1.0]) {
                            (length_field.to_string(), echo(l))
                        } else if alone([1.0, 1.0, fr]) {
                            (radius_field.to_string(), echo(r))
                        } else {
                            (format!("{length_field} and {radius_field}"), format!("{} and {}", echo(l), echo(r)))
                        };
                        return Err(bad(
                            &field,
                            pct,
                            &format!(
                                "the study would draw cats the problem refuses: a half of {} kg, {} m and radius {} m ({e})",
                                echo(drawn.mass),
                                echo(drawn.length),
                                echo(drawn.radius)
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

/// One half's mass, length and radius, fields named `{prefix}.mass` and so on.
fn validate_half(prefix: &str, c: &Cylinder) -> Result<(), ProblemError> {
    validate_rod(&ROD_KEYS.map(|key| format!("{prefix}.{key}")), c)
}

/// Each of a rod's numbers given (`numbers`: mass, length, radius, in the order of
/// [`ROD_KEYS`], named `fields`) on its own: the mass and the length within their ranges, the
/// radius positive.
fn validate_numbers(fields: &[String; 3], numbers: [Option<f64>; 3]) -> Result<(), ProblemError> {
    let ([mass, length, radius], [m, l, r]) = (fields, numbers);
    m.map_or(Ok(()), |m| in_range(mass, m, limits::MASS))?;
    l.map_or(Ok(()), |l| in_range(length, l, limits::LENGTH))?;
    r.map_or(Ok(()), |r| positive(radius, r))
}

/// A rod's (a half's, a tail's, a pair of legs') mass, length and radius, named `fields` (in
/// the order of [`ROD_KEYS`]): each number ([`validate_numbers`]), then the radius against the
/// length.
fn validate_rod(fields: &[String; 3], c: &Cylinder) -> Result<(), ProblemError> {
    validate_numbers(fields, [Some(c.mass), Some(c.length), Some(c.radius)])?;
    let [_, length, radius] = fields;
    let ratio = limits::RADIUS_OVER_LENGTH;
    // A relative slack of 1e-12 admits the bounds themselves despite the rounding of r/l.
    let r_over_l = c.radius / c.length;
    if !(ratio.min * (1.0 - 1e-12)..=ratio.max * (1.0 + 1e-12)).contains(&r_over_l) {
        return Err(bad(
            radius,
            echo(c.radius),
            &format!(
                "must lie in [{}, {}] m, {} times {} = {} m",
                echo(ratio.min * c.length),
                echo(ratio.max * c.length),
                ratio,
                length,
                echo(c.length)
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_half_takes_the_shorthand_for_what_it_leaves_out() {
        let s = CatSection { rear: Some(HalfSection { mass: Some(1.5), ..Default::default() }), ..Default::default() };
        assert_eq!(s.front(), Cylinder::default());
        assert_eq!(s.rear(), Cylinder { mass: 1.5, ..Cylinder::default() });
        assert!(!s.is_paper());
        assert_eq!(s.departure(), Some(("cat.rear.mass".to_string(), "1.5".to_string())));
    }

    #[test]
    fn equal_halves_on_the_universal_joint_are_the_papers_cat() {
        let same = HalfSection { length: Some(1.0), ..Default::default() };
        let s = CatSection { front: Some(same), rear: Some(same), ..Default::default() };
        assert!(s.is_paper());
        assert_eq!(s.departure(), None);
        let k = CatSection { joint: Joint::NoTwist, ..Default::default() };
        assert_eq!(k.departure(), Some(("cat.joint".to_string(), "\"no-twist\"".to_string())));
    }

    /// The halves' difference is named where it is written: the front's mass with the rear's
    /// radius written equal to the shorthand's (a QA run named `cat.rear.mass`), and on the
    /// no-twist joint the halves, not the joint.
    #[test]
    fn unequal_halves_are_named_on_the_half_that_writes_the_difference() {
        let s = CatSection {
            front: Some(HalfSection { mass: Some(0.8), ..Default::default() }),
            rear: Some(HalfSection { radius: Some(0.1), ..Default::default() }),
            ..Default::default()
        };
        assert_eq!(s.unequal_halves(), Some(("cat.front.mass".to_string(), "0.8".to_string())));
        let k = CatSection {
            joint: Joint::NoTwist,
            rear: Some(HalfSection { length: Some(1.2), ..Default::default() }),
            ..Default::default()
        };
        assert_eq!(k.unequal_halves(), Some(("cat.rear.length".to_string(), "1.2".to_string())));
        assert_eq!(k.departure().map(|d| d.0), Some("cat.joint".to_string()));
        assert_eq!(CatSection { joint: Joint::NoTwist, ..Default::default() }.unequal_halves(), None);
    }
}
