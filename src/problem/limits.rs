//! The ranges a problem's numbers must lie in, in one place, and the checks that name the field.
//!
//! The physics is scale-invariant (DESIGN.md §2): the twist and swing do not depend on the mass
//! and depend on the sizes only through `r/l`; the torques scale as `m l²/T²`. So nothing is lost
//! by refusing values far outside any cat's, while double precision is: a subnormal mass or a
//! height of `1e300` makes `I_lock`, `√(2h/g)` or the torque scale overflow or underflow, and the
//! engines return NaN. Each range below is wide (at least the ranges a user of the workbench
//! needs: `r/l ∈ [10⁻³, 1]`, mass `10⁻³…10³` kg, fall time `0.1…10` s, θ `10°…180°`) and every
//! product the engines form from values inside them stays far from overflow and underflow.
//!
//! Counts (samples, nodes, iterations) are bounded too, so that no setting runs for ever. The
//! optimiser's cost grows faster than linearly in its nodes: `catflip optimize
//! problems/paper.toml --set optimize.nodes=N` took 5.8 s (N = 200, the default), 23.9 s
//! (600) and 246 s (2000) on the project's shared 2-core machine, and did not end within 300 s
//! at 20000; hence [`NODES`]' maximum of 1000. `catflip simulate problems/paper.toml --set
//! exact.torque_samples=100000` took 0.6 s (10⁷ took 17 s).
//!
//! The messages read `cat.mass = 1e300: must lie in [1e-6, 1e6] kg`, with the field named as the
//! user writes it and the value shortened by [`crate::numeric::numfmt::echo`].

use crate::numeric::numfmt::echo;
use crate::problem::error::{bad, ProblemError};

/// A closed range of a problem's number, with its unit for messages.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Smallest value accepted.
    pub min: f64,
    /// Largest value accepted.
    pub max: f64,
    /// Unit written after the range in messages (empty for none).
    pub unit: &'static str,
}

/// Mass of a half, kg.
pub const MASS: Range = Range { min: 1e-6, max: 1e6, unit: "kg" };
/// Length of a half, m.
pub const LENGTH: Range = Range { min: 1e-3, max: 1e3, unit: "m" };
/// Radius over length of a half, `r/l` (dimensionless): from a thin rod to a disc as long as wide.
pub const RADIUS_OVER_LENGTH: Range = Range { min: 1e-4, max: 1.0, unit: "" };
/// Drop height, m.
pub const HEIGHT: Range = Range { min: 1e-4, max: 1e5, unit: "m" };
/// Gravitational acceleration, m/s².
pub const GRAVITY: Range = Range { min: 1e-3, max: 1e3, unit: "m/s²" };
/// Fall time `√(2h/g)`, s.
pub const FALL_TIME: Range = Range { min: 0.01, max: 100.0, unit: "s" };
/// Angle between the halves while twisting, degrees (180 is straight).
pub const THETA_DEG: Range = Range { min: 1.0, max: 180.0, unit: "degrees" };
/// Smallest fraction of the fall time one phase may take.
pub const MIN_PHASE_FRACTION: f64 = 1e-3;
/// Target error of the exact engine, rad.
pub const EXACT_TOLERANCE: Range = Range { min: 1e-14, max: 1e-2, unit: "rad" };
/// Largest smoothness weight λ of the profile QP (dimensionless): beyond it the smoothness term
/// swamps the peak by more than double precision resolves.
pub const MAX_SMOOTHNESS: f64 = 1e6;

/// Torque samples per phase of the exact engine (`exact.torque_samples`).
pub const TORQUE_SAMPLES: CountRange = CountRange { min: 8, max: 100_000 };
/// Rate nodes of the profile QP and the refinements (`optimize.nodes`).
pub const NODES: CountRange = CountRange { min: 4, max: 1000 };
/// Outer iterations of each exact-dynamics refinement (`optimize.refine_iterations`).
pub const REFINE_ITERATIONS: CountRange = CountRange { min: 0, max: 1000 };

/// A closed range of a count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CountRange {
    /// Smallest count accepted.
    pub min: usize,
    /// Largest count accepted.
    pub max: usize,
}

impl std::fmt::Display for Range {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "[{}, {}]", echo(self.min), echo(self.max))?;
        if !self.unit.is_empty() {
            write!(f, " {}", self.unit)?;
        }
        Ok(())
    }
}

/// Requires a finite value in `range`; the error names `field` and the range.
pub fn in_range(field: &str, value: f64, range: Range) -> Result<(), ProblemError> {
    if !value.is_finite() {
        return Err(bad(field, echo(value), "must be a finite number"));
    }
    if value <= 0.0 && range.min > 0.0 {
        return Err(bad(field, echo(value), "must be positive"));
    }
    if value < range.min || value > range.max {
        return Err(bad(field, echo(value), &format!("must lie in {range}")));
    }
    Ok(())
}

/// Requires a count in `range`; the error names `field` and the range.
pub fn count_in_range(field: &str, value: usize, range: CountRange) -> Result<(), ProblemError> {
    if value < range.min || value > range.max {
        return Err(bad(field, value, &format!("must lie in [{}, {}]", range.min, range.max)));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_read_without_round_off() {
        assert_eq!(MASS.to_string(), "[1e-6, 1e6] kg");
        assert_eq!(RADIUS_OVER_LENGTH.to_string(), "[1e-4, 1]");
        assert_eq!(FALL_TIME.to_string(), "[0.01, 100] s");
    }

    #[test]
    fn the_required_ranges_are_admitted() {
        // Issue 9: r/l ∈ [1e-3, 1], mass 1e-3…1e3 kg, fall time 0.1…10 s, θ 10°…180°.
        for (r, lo, hi) in
            [(RADIUS_OVER_LENGTH, 1e-3, 1.0), (MASS, 1e-3, 1e3), (FALL_TIME, 0.1, 10.0), (THETA_DEG, 10.0, 180.0)]
        {
            assert!(r.min <= lo && hi <= r.max, "{r} does not admit [{lo}, {hi}]");
        }
    }
}
