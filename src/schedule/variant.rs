//! Which schedule is which: the typed names of the schedules catflip evaluates.
//!
//! A [`Variant`] is an [`Origin`] (where the twist profile comes from: the paper, the profile
//! library, the profile QP, the exact-dynamics refinement of the twist or of every phase) and a
//! [`VariantCirculation`] (the problem's own circulation, or the calibrated one that makes the
//! exact twist π). Its `Display` is the name users see in files and tables, e.g. `cycloidal`,
//! `qp-optimal`, `exact-refined-all-phases-calibrated`. A [`ScheduleName`] names any trajectory
//! a command measures: a variant, the problem's own schedule, the whole-manoeuvre optimum, a
//! certified retiming, or a file read back.

use std::fmt;

use serde::{Serialize, Serializer};

use crate::problem::ProfileKind;

/// Where a schedule's twist profile comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Origin {
    /// A library profile (the paper's cosine among them).
    Library(ProfileKind),
    /// The profile QP's optimum on the paper's model.
    Qp,
    /// The exact-dynamics refinement of the twist phase.
    Refined,
    /// Every phase (bend, twist, unbend) retimed against its exact peak.
    RefinedAllPhases,
}

impl Origin {
    /// The name of the origin's twist profile: a library name, `qp-optimal`, `exact-refined`
    /// or `exact-refined-all-phases`.
    pub fn profile_name(self) -> &'static str {
        match self {
            Origin::Library(kind) => kind.name(),
            Origin::Qp => "qp-optimal",
            Origin::Refined => "exact-refined",
            Origin::RefinedAllPhases => "exact-refined-all-phases",
        }
    }

    /// The origin's column in tables: `paper`, `library`, `qp`, `refined`, `refined-all-phases`.
    pub fn name(self) -> &'static str {
        match self {
            Origin::Library(ProfileKind::PaperCosine) => "paper",
            Origin::Library(_) => "library",
            Origin::Qp => "qp",
            Origin::Refined => "refined",
            Origin::RefinedAllPhases => "refined-all-phases",
        }
    }

    /// Whether an optimiser made it (its schedule is exported for robots and simulators).
    pub fn is_optimised(self) -> bool {
        !matches!(self, Origin::Library(_))
    }
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for Origin {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// Which circulation a variant runs with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum VariantCirculation {
    /// The problem's own (paper's, given or calibrated, as its file says).
    Problem,
    /// The circulation a converged calibration found for this joint path.
    Calibrated,
}

/// A named schedule: its origin and its circulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Variant {
    /// Where its twist profile comes from.
    pub origin: Origin,
    /// Which circulation it runs with.
    pub circulation: VariantCirculation,
}

impl Variant {
    /// A variant with the problem's circulation.
    pub fn new(origin: Origin) -> Variant {
        Variant { origin, circulation: VariantCirculation::Problem }
    }

    /// The same origin with the calibrated circulation.
    pub fn calibrated(self) -> Variant {
        Variant { circulation: VariantCirculation::Calibrated, ..self }
    }

    /// Whether it runs with the calibrated circulation.
    pub fn is_calibrated(self) -> bool {
        self.circulation == VariantCirculation::Calibrated
    }
}

impl fmt::Display for Variant {
    /// The profile's name, with `-calibrated` appended for the calibrated circulation.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.origin.profile_name())?;
        if self.is_calibrated() {
            f.write_str("-calibrated")?;
        }
        Ok(())
    }
}

impl Serialize for Variant {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// The name of the whole-manoeuvre optimum in files and tables.
pub const WHOLE: &str = "whole-optimum";

/// The name of any trajectory catflip measures ([`crate::engines::measured::Measured`]), as
/// files and tables show it (`Display`).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum ScheduleName {
    /// A library or optimised schedule on the problem's joint path (`cycloidal`,
    /// `exact-refined-calibrated`, …).
    Variant(Variant),
    /// The problem's own schedule (`problem`).
    Problem,
    /// The whole-manoeuvre optimum (`whole-optimum`): both joint paths optimised over the fall.
    WholeOptimum,
    /// The certified convex retiming of a schedule along its own path (`<name>-retimed`).
    Retimed(Box<ScheduleName>),
    /// A schedule file read back (its path).
    File(String),
}

impl ScheduleName {
    /// The library profile `kind` on the problem's circulation.
    pub fn library(kind: ProfileKind) -> ScheduleName {
        ScheduleName::Variant(Variant::new(Origin::Library(kind)))
    }

    /// The variant, when this names one.
    pub fn variant(&self) -> Option<Variant> {
        match self {
            ScheduleName::Variant(v) => Some(*v),
            _ => None,
        }
    }
}

impl From<Variant> for ScheduleName {
    fn from(v: Variant) -> ScheduleName {
        ScheduleName::Variant(v)
    }
}

impl fmt::Display for ScheduleName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScheduleName::Variant(v) => v.fmt(f),
            ScheduleName::Problem => f.write_str("problem"),
            ScheduleName::WholeOptimum => f.write_str(WHOLE),
            ScheduleName::Retimed(of) => write!(f, "{of}-retimed"),
            ScheduleName::File(path) => f.write_str(path),
        }
    }
}

impl Serialize for ScheduleName {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_the_ones_in_the_results_files() {
        assert_eq!(Variant::new(Origin::Library(ProfileKind::PaperCosine)).to_string(), "paper-cosine");
        assert_eq!(Origin::Library(ProfileKind::PaperCosine).to_string(), "paper");
        assert_eq!(Origin::Library(ProfileKind::SCurve).to_string(), "library");
        assert_eq!(Variant::new(Origin::Qp).to_string(), "qp-optimal");
        assert_eq!(
            Variant::new(Origin::RefinedAllPhases).calibrated().to_string(),
            "exact-refined-all-phases-calibrated"
        );
        assert_eq!(ScheduleName::WholeOptimum.to_string(), "whole-optimum");
        assert_eq!(ScheduleName::Retimed(Box::new(ScheduleName::Problem)).to_string(), "problem-retimed");
    }
}
