//! Settings of the engines and optimisers, one struct each, with their defaults in one place.

use serde::{Deserialize, Serialize};

use super::error::{bad, positive, positive_opt, ProblemError};
use crate::numeric::numfmt::echo;
use crate::problem::limits::{self, count_in_range, in_range};

/// Settings of the exact (momentum-map) engine.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExactSettings {
    /// Target error of the final twist and swing, rad; the integrator refines its steps until
    /// its error estimate is below it.
    pub tolerance: f64,
    /// Samples per phase on which torques are evaluated before refining each peak.
    pub torque_samples: usize,
}

impl Default for ExactSettings {
    fn default() -> Self {
        Self { tolerance: 1e-10, torque_samples: 400 }
    }
}

impl ExactSettings {
    pub(crate) fn validate(&self) -> Result<(), ProblemError> {
        positive("exact.tolerance", self.tolerance)?;
        if self.tolerance < 1e-14 {
            return Err(bad(
                "exact.tolerance",
                echo(self.tolerance),
                "is below what double precision can deliver (≥ 1e-14)",
            ));
        }
        in_range("exact.tolerance", self.tolerance, limits::EXACT_TOLERANCE)?;
        if self.torque_samples < 8 {
            return Err(bad("exact.torque_samples", self.torque_samples, "must be at least 8"));
        }
        count_in_range("exact.torque_samples", self.torque_samples, limits::TORQUE_SAMPLES)
    }
}

/// How rapier's time step is chosen.
///
/// In a problem file `dt = "auto"` (the default) or `dt = 0.0005` (seconds); `catflip simulate
/// --dt S` sets `Fixed(S)`. Either way it is the *first* step of a verification, which then
/// halves it until rapier's own error estimate meets the tolerances
/// ([`crate::engines::rapier::verify`]); a single run ([`crate::engines::rapier::simulate`]) uses it as is.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum TimeStep {
    /// From the trajectory's own time scales ([`crate::engines::rapier::TimeScales`]).
    #[default]
    Auto,
    /// The user's step, s.
    Fixed(f64),
}

impl std::fmt::Display for TimeStep {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TimeStep::Auto => f.write_str("auto"),
            TimeStep::Fixed(dt) => write!(f, "{dt:.3e} s"),
        }
    }
}

impl Serialize for TimeStep {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            TimeStep::Auto => s.serialize_str("auto"),
            TimeStep::Fixed(dt) => s.serialize_f64(*dt),
        }
    }
}

impl<'de> Deserialize<'de> for TimeStep {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Seconds(f64),
            Word(String),
        }
        match Raw::deserialize(d) {
            Ok(Raw::Seconds(dt)) => Ok(TimeStep::Fixed(dt)),
            Ok(Raw::Word(w)) if w == "auto" => Ok(TimeStep::Auto),
            _ => Err(serde::de::Error::custom("expected \"auto\" or a time step in seconds")),
        }
    }
}

/// Settings of the rapier3d verification.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RapierSettings {
    /// Time step: automatic, or the user's first step, s.
    pub dt: TimeStep,
    /// Mass of the cross of the universal joint as a fraction of a half's mass (rapier needs a
    /// body there; it should be negligible).
    pub cross_mass_fraction: f64,
    /// A verification agrees on the twist when rapier's extrapolated twist is this close to the
    /// exact engine's, degrees.
    pub twist_tolerance_deg: f64,
    /// The same for the swing, degrees.
    pub swing_tolerance_deg: f64,
    /// The same for the peak torque, relative to the exact engine's.
    pub peak_torque_tolerance: f64,
    /// Rapier steps a verification may take, all its runs together: no finer step is tried when
    /// it would overrun them. A budget in steps keeps verdicts the same on every machine and
    /// under any load; rapier takes about 6 µs per step on one core of the development machine.
    pub step_budget: usize,
    /// Wall-clock time a verification may spend in rapier, s; none when absent (verdicts may
    /// then depend on the machine's speed and load).
    pub time_budget_s: Option<f64>,
}

impl Default for RapierSettings {
    fn default() -> Self {
        Self {
            dt: TimeStep::Auto,
            cross_mass_fraction: 1e-6,
            twist_tolerance_deg: 0.5,
            swing_tolerance_deg: 0.5,
            peak_torque_tolerance: 0.02,
            step_budget: 150_000,
            time_budget_s: None,
        }
    }
}

/// The largest twist or swing tolerance of a rapier verdict, degrees.
pub const MAX_ANGLE_TOLERANCE_DEG: f64 = 10.0;
/// The largest relative peak-torque tolerance of a rapier verdict.
pub const MAX_PEAK_TOLERANCE: f64 = 0.5;

impl RapierSettings {
    pub(crate) fn validate(&self) -> Result<(), ProblemError> {
        if let TimeStep::Fixed(dt) = self.dt {
            positive("rapier.dt", dt)?;
        }
        positive("rapier.cross_mass_fraction", self.cross_mass_fraction)?;
        if self.cross_mass_fraction > 0.01 {
            return Err(bad(
                "rapier.cross_mass_fraction",
                echo(self.cross_mass_fraction),
                "must be at most 0.01 (the cross is meant to be negligible)",
            ));
        }
        // A verdict is only as strict as its tolerances: beyond these a "verified" could not
        // tell a flip from a miss (a QA run had rapier 27° from the exact twist "verified").
        for (field, value) in [
            ("rapier.twist_tolerance_deg", self.twist_tolerance_deg),
            ("rapier.swing_tolerance_deg", self.swing_tolerance_deg),
        ] {
            positive(field, value)?;
            if value > MAX_ANGLE_TOLERANCE_DEG {
                return Err(bad(
                    field,
                    echo(value),
                    &format!("must be at most {MAX_ANGLE_TOLERANCE_DEG}° (a verdict within more would not tell a flip that lands from one that misses)"),
                ));
            }
        }
        positive("rapier.peak_torque_tolerance", self.peak_torque_tolerance)?;
        if self.peak_torque_tolerance > MAX_PEAK_TOLERANCE {
            return Err(bad(
                "rapier.peak_torque_tolerance",
                echo(self.peak_torque_tolerance),
                &format!("is a fraction (0.02 is 2 %) and must be at most {MAX_PEAK_TOLERANCE}: a peak torque half off would be \"verified\""),
            ));
        }
        positive_opt("rapier.time_budget_s", self.time_budget_s)?;
        if self.step_budget == 0 || self.step_budget > 1_000_000_000 {
            return Err(bad("rapier.step_budget", self.step_budget, "must be between 1 and 1000000000"));
        }
        Ok(())
    }

    /// The same settings with a fixed step `dt`, s.
    pub fn with_dt(&self, dt: f64) -> Self {
        Self { dt: TimeStep::Fixed(dt), ..*self }
    }
}

/// Boundary conditions of the circulation rate in the profile QP.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Boundary {
    /// `ω = 0` at the start only, as the paper's profile.
    StartAtRest,
    /// `ω = 0` at both ends.
    RestToRest,
}

/// Settings of the optimisers (DESIGN.md §5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OptimizeSettings {
    /// Number of nodes of the discretised circulation rate.
    pub nodes: usize,
    /// Boundary conditions of the circulation rate.
    pub boundary: Boundary,
    /// Bound on `|ω|`, rad/s; none when absent.
    pub rate_limit: Option<f64>,
    /// Bound on `|d²ω/ds²|` (the jerk of φ), rad/s³; when present `dω/ds` is also zero at both
    /// ends. None when absent.
    pub jerk_limit: Option<f64>,
    /// Dimensionless weight λ of the smoothness term `λ ∫(P''')² du` of the normalised motion
    /// (see the `qp` module docs); zero for none.
    pub smoothness: f64,
    /// Outer iterations of the exact-dynamics refinement.
    pub refine_iterations: usize,
    /// The whole-manoeuvre path optimisation (`[optimize.whole]`).
    pub whole: super::whole::WholeSettings,
}

impl Default for OptimizeSettings {
    fn default() -> Self {
        Self {
            nodes: 200,
            boundary: Boundary::RestToRest,
            rate_limit: None,
            jerk_limit: None,
            smoothness: 0.0,
            refine_iterations: 60,
            whole: super::whole::WholeSettings::default(),
        }
    }
}

impl OptimizeSettings {
    pub(crate) fn validate(&self) -> Result<(), ProblemError> {
        if self.nodes < 4 {
            return Err(bad("optimize.nodes", self.nodes, "must be at least 4"));
        }
        count_in_range("optimize.nodes", self.nodes, limits::NODES)?;
        count_in_range("optimize.refine_iterations", self.refine_iterations, limits::REFINE_ITERATIONS)?;
        positive_opt("optimize.rate_limit", self.rate_limit)?;
        positive_opt("optimize.jerk_limit", self.jerk_limit)?;
        if !self.smoothness.is_finite() || self.smoothness < 0.0 {
            return Err(bad("optimize.smoothness", echo(self.smoothness), "must be a finite, non-negative weight"));
        }
        if self.smoothness > limits::MAX_SMOOTHNESS {
            return Err(bad(
                "optimize.smoothness",
                echo(self.smoothness),
                &format!("must be at most {}", echo(limits::MAX_SMOOTHNESS)),
            ));
        }
        self.whole.validate()
    }
}
