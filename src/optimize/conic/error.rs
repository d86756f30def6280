//! Why a conic program could not be set up: an input it cannot use, or Clarabel refusing the
//! data or the settings. How a solve ended is not an error but the solution's
//! [`QpStatus`](super::QpStatus).

/// Why a conic program could not be set up. The layers above join it with `#[from]`.
#[derive(Debug, thiserror::Error)]
pub enum ConicError {
    /// An input has a value the program cannot use. The problem's validation keeps every such input
    /// out of reach of a problem file, so this is a bug to report, and reads as one.
    #[error(
        "internal error: the optimiser was handed {field} = {value} ({reason}); please report it with the problem file"
    )]
    BadInput {
        /// The input's name, e.g. `nodes`.
        field: &'static str,
        /// The value found.
        value: String,
        /// Why it is rejected.
        reason: String,
    },
    /// Clarabel refused the problem data or the settings.
    #[error("Clarabel could not set up the QP: {0}")]
    Setup(String),
}

/// A [`ConicError::BadInput`].
pub(crate) fn bad(field: &'static str, value: impl std::fmt::Display, reason: &str) -> ConicError {
    ConicError::BadInput { field, value: value.to_string(), reason: reason.to_string() }
}

/// Requires a finite, strictly positive value.
pub(crate) fn positive(field: &'static str, value: f64) -> Result<(), ConicError> {
    crate::problem::not_positive(value).map_or(Ok(()), |reason| Err(bad(field, value, reason)))
}

/// Requires an absent or finite, strictly positive value.
pub(crate) fn positive_opt(field: &'static str, value: Option<f64>) -> Result<(), ConicError> {
    value.map_or(Ok(()), |v| positive(field, v))
}
