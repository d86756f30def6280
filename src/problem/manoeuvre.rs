//! The manoeuvre's settings: bend angle, phase split, smoothing profile, circulation, bend path
//! (DESIGN.md §3). The schedule built from them lives in [`crate::schedule`].

use serde::{de, Deserialize, Deserializer, Serialize, Serializer};

use super::error::{bad, ProblemError};
use crate::numeric::numfmt::echo;
use crate::problem::limits;

/// The smoothing profile of the circulation rate `ω(s)` in the twist phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ProfileKind {
    /// The paper's `ω0 (1 − cos(π s/T))`, exactly as published: ends at `2 ω0`, not at rest.
    PaperCosine,
    /// `ω0 (1 − cos(2π s/T))`: rest to rest, peak acceleration coefficient 2π.
    Cycloidal,
    /// Constant acceleration then constant deceleration: coefficient 4.
    BangBang,
    /// Acceleration `+a, 0, −a` over thirds: coefficient 4.5.
    Trapezoid,
    /// Trapezoidal acceleration with quarter-sine ramps over eighths: coefficient ≈ 4.888.
    ModifiedTrapezoid,
    /// Modified sine (quarter-sine, three-quarter long sine, quarter-sine): coefficient ≈ 5.528.
    ModifiedSine,
    /// Position `10u³ − 15u⁴ + 6u⁵`: coefficient ≈ 5.774.
    #[serde(rename = "poly-345")]
    Poly345,
    /// Position `35u⁴ − 84u⁵ + 70u⁶ − 20u⁷`: coefficient `840/(25√20) ≈ 7.513`.
    #[serde(rename = "poly-4567")]
    Poly4567,
    /// Jerk-limited S-curve: trapezoidal acceleration with linear ramps over eighths.
    SCurve,
}

impl ProfileKind {
    /// Every profile of the library, the paper's first.
    pub const ALL: [ProfileKind; 9] = [
        ProfileKind::PaperCosine,
        ProfileKind::Cycloidal,
        ProfileKind::BangBang,
        ProfileKind::Trapezoid,
        ProfileKind::ModifiedTrapezoid,
        ProfileKind::ModifiedSine,
        ProfileKind::Poly345,
        ProfileKind::Poly4567,
        ProfileKind::SCurve,
    ];

    /// The kebab-case name used in problem files.
    pub fn name(self) -> &'static str {
        match self {
            ProfileKind::PaperCosine => "paper-cosine",
            ProfileKind::Cycloidal => "cycloidal",
            ProfileKind::BangBang => "bang-bang",
            ProfileKind::Trapezoid => "trapezoid",
            ProfileKind::ModifiedTrapezoid => "modified-trapezoid",
            ProfileKind::ModifiedSine => "modified-sine",
            ProfileKind::Poly345 => "poly-345",
            ProfileKind::Poly4567 => "poly-4567",
            ProfileKind::SCurve => "s-curve",
        }
    }
}

/// The path of the bend direction through the joint during the twist phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BendPath {
    /// The paper's `(q1, q2) = (β cos φ, β sin φ)`; does not keep the angle between the halves.
    JointCircle,
    /// B's axis keeps the angle β to A's axis while its direction φ circulates.
    Cone,
}

impl std::fmt::Display for ProfileKind {
    /// The kebab-case name used in problem files.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::fmt::Display for BendPath {
    /// The kebab-case name used in problem files.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            BendPath::JointCircle => "joint-circle",
            BendPath::Cone => "cone",
        })
    }
}

/// How far the bend direction circulates during the twist phase, `∫ω ds`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Circulation {
    /// The paper's `π / C`, with `C` in the code's form and the correct inertia.
    Paper,
    /// Found by a root find on the exact engine so that the cat turns by exactly π.
    Calibrated,
    /// A given angle, rad.
    Angle(f64),
}

impl Serialize for Circulation {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Circulation::Paper => s.serialize_str("paper"),
            Circulation::Calibrated => s.serialize_str("calibrated"),
            Circulation::Angle(a) => s.serialize_f64(*a),
        }
    }
}

impl<'de> Deserialize<'de> for Circulation {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl de::Visitor<'_> for Visitor {
            type Value = Circulation;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"paper\", \"calibrated\" or a number of radians")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Circulation, E> {
                match v {
                    "paper" => Ok(Circulation::Paper),
                    "calibrated" => Ok(Circulation::Calibrated),
                    other => other
                        .parse::<f64>()
                        .map(Circulation::Angle)
                        .map_err(|_| E::invalid_value(de::Unexpected::Str(other), &self)),
                }
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Circulation, E> {
                Ok(Circulation::Angle(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Circulation, E> {
                Ok(Circulation::Angle(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Circulation, E> {
                Ok(Circulation::Angle(v as f64))
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// The manoeuvre section of a problem file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Manoeuvre {
    /// Angle between the halves while twisting, degrees; 180 is straight. The bend is `β = 180 − θ`.
    pub theta_deg: f64,
    /// Fractions of the fall time spent bending, twisting and unbending; positive, summing to 1.
    pub phases: [f64; 3],
    /// Shape of the circulation rate in the twist phase.
    pub profile: ProfileKind,
    /// How far the bend direction circulates.
    pub circulation: Circulation,
    /// Path of the bend direction through the joint.
    pub bend_path: BendPath,
}

impl Default for Manoeuvre {
    fn default() -> Self {
        Self {
            theta_deg: 45.0,
            phases: [0.2, 0.6, 0.2],
            profile: ProfileKind::PaperCosine,
            circulation: Circulation::Paper,
            bend_path: BendPath::JointCircle,
        }
    }
}

/// Largest circulation a schedule may ask for, rad: beyond it the fall is spent on hundreds of
/// turns of the bend (the paper's `π/C` grows without bound as the cat straightens, `C → 0`).
pub const MAX_CIRCULATION: f64 = 1000.0;

/// Half-width of the band around β = 90° in which the cone path is refused: the joint rate needed
/// to follow the cone grows like `|tan β|` and becomes unbounded at gimbal lock.
pub const CONE_GIMBAL_MARGIN_DEG: f64 = 5.0;

impl Manoeuvre {
    /// The bend `β = π − θ`, rad.
    pub fn bend(&self) -> f64 {
        (180.0 - self.theta_deg).to_radians()
    }

    /// The angle between the halves, rad.
    pub fn theta(&self) -> f64 {
        self.theta_deg.to_radians()
    }

    pub(crate) fn validate(&self) -> Result<(), ProblemError> {
        let t = self.theta_deg;
        if !t.is_finite() {
            return Err(bad("manoeuvre.theta_deg", echo(t), "must be a finite number"));
        }
        if t <= 0.0 || t > 180.0 {
            return Err(bad("manoeuvre.theta_deg", echo(t), "must lie in (0, 180] degrees (180 is a straight cat)"));
        }
        if t < limits::THETA_DEG.min {
            return Err(bad(
                "manoeuvre.theta_deg",
                echo(t),
                &format!("must lie in {}: the halves would fold onto each other", limits::THETA_DEG),
            ));
        }
        let shown = format!("[{}]", self.phases.map(echo).join(", "));
        for (i, f) in self.phases.iter().enumerate() {
            let field = format!("manoeuvre.phases[{i}]");
            if !f.is_finite() {
                return Err(bad(&field, echo(*f), "must be a finite number"));
            }
            if *f <= 0.0 {
                return Err(bad(&field, echo(*f), "each phase must take a positive fraction of the fall"));
            }
            if *f < limits::MIN_PHASE_FRACTION {
                return Err(bad(
                    &field,
                    echo(*f),
                    &format!("each phase must take at least {} of the fall", echo(limits::MIN_PHASE_FRACTION)),
                ));
            }
        }
        let sum: f64 = self.phases.iter().sum();
        if (sum - 1.0).abs() > 1e-9 {
            return Err(bad(
                "manoeuvre.phases",
                shown,
                &format!("fractions must sum to 1 (they sum to {})", echo(sum)),
            ));
        }
        if let Circulation::Angle(a) = self.circulation {
            if !a.is_finite() {
                return Err(bad("manoeuvre.circulation", echo(a), "must be a finite number of radians"));
            }
            if a == 0.0 {
                return Err(bad(
                    "manoeuvre.circulation",
                    echo(a),
                    "must be non-zero: without circulation the cat does not twist",
                ));
            }
            if a.abs() > MAX_CIRCULATION {
                return Err(bad(
                    "manoeuvre.circulation",
                    echo(a),
                    &format!("must be at most {MAX_CIRCULATION} rad in magnitude (about 160 turns of the bend)"),
                ));
            }
        }
        if self.circulation == Circulation::Calibrated && t >= 180.0 {
            return Err(bad(
                "manoeuvre.circulation",
                "\"calibrated\"",
                "a straight cat (theta_deg = 180) has no bend to circulate, so no circulation turns it",
            ));
        }
        if self.bend_path == BendPath::Cone && (self.bend().to_degrees() - 90.0).abs() < CONE_GIMBAL_MARGIN_DEG {
            return Err(bad(
                "manoeuvre.theta_deg",
                echo(t),
                &format!(
                    "the cone path meets gimbal lock of the Rx·Ry joint when the bend is within {CONE_GIMBAL_MARGIN_DEG}° of 90° (B's spine along joint 1's axis); choose another θ or bend_path = \"joint-circle\""
                ),
            ));
        }
        Ok(())
    }
}
