//! Errors of the whole-manoeuvre optimisation; its settings live with the problem file
//! ([`crate::problem::whole`]).

pub use crate::problem::whole::{Method, Objective, StartKind, WholeSettings};

/// Why the whole-manoeuvre optimisation could not run.
#[derive(Debug, thiserror::Error)]
pub enum WholeError {
    /// A setting or input has a value the optimisation cannot use.
    #[error("{field} = {value}: {reason}")]
    BadFieldValue {
        /// Dotted path of the field, e.g. `optimize.control_points`.
        field: &'static str,
        /// The value found.
        value: String,
        /// Why it is rejected.
        reason: String,
    },
    /// A setting of `[optimize.whole]` is out of range.
    #[error(transparent)]
    Settings(#[from] crate::problem::ProblemError),
    /// Clarabel refused a subproblem's data.
    #[error(transparent)]
    Conic(#[from] crate::optimize::conic::ConicError),
}

fn bad(field: &'static str, value: impl std::fmt::Display, reason: &str) -> WholeError {
    WholeError::BadFieldValue { field, value: value.to_string(), reason: reason.to_string() }
}

fn positive(field: &'static str, value: f64) -> Result<(), WholeError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(bad(field, value, "must be finite and positive"))
    }
}

/// Requires a finite positive input of the entry points.
pub(crate) fn positive_input(field: &'static str, value: f64) -> Result<(), WholeError> {
    positive(field, value)
}

pub use crate::problem::whole::MIN_TIME_NEEDS_LIMITS;

/// Requires motor limits for the `min-time` objective.
pub(crate) fn needs_limits(objective: Objective, motors: &crate::model::motor::Motors) -> Result<(), WholeError> {
    if objective == Objective::MinTime && motors.is_ideal() {
        return Err(bad("optimize.whole.objective", "\"min-time\"", MIN_TIME_NEEDS_LIMITS));
    }
    Ok(())
}
