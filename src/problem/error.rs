//! Why a problem could not be loaded, and the checks every section's `validate()` shares.
//!
//! The lowest file of [`crate::problem`]: the problem file, the manoeuvre and the settings all
//! report a bad field through [`ProblemError::BadFieldValue`] (Clarabel's `BadFieldValue`),
//! naming the dotted field, the value found and why it is rejected.

/// Why a problem could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ProblemError {
    /// The file could not be read.
    #[error("cannot read problem file {path}")]
    Io {
        /// The path given.
        path: String,
        /// What the OS said.
        source: std::io::Error,
    },
    /// The text is not valid TOML, or does not match the problem's shape.
    #[error("problem file {origin}: {message}")]
    Parse {
        /// The file (or `--set`) the text came from.
        origin: String,
        /// The parser's message, naming the key.
        message: String,
    },
    /// A `--set key=value` override is malformed.
    #[error("--set {}: {}", one_line(assignment), one_line(reason))]
    BadOverride {
        /// The override as given.
        assignment: String,
        /// Why it cannot be applied.
        reason: String,
    },
    /// A command-line option that sets a field has a value the model cannot use.
    #[error("{option} {value}: {reason}")]
    BadOption {
        /// The option, e.g. `--dt`.
        option: String,
        /// The value given.
        value: String,
        /// Why it is rejected.
        reason: String,
    },
    /// A field has a value the model cannot use.
    #[error("{field} = {value}: {reason}")]
    BadFieldValue {
        /// Dotted path of the field, e.g. `cat.mass`.
        field: String,
        /// The value found.
        value: String,
        /// Why it is rejected.
        reason: String,
    },
}

/// A `BadFieldValue` error. Control characters in the value are escaped (`\n`, `\u{0}`), so
/// that the message stays one line whatever the user wrote.
pub(crate) fn bad(field: &str, value: impl std::fmt::Display, reason: &str) -> ProblemError {
    ProblemError::BadFieldValue {
        field: field.to_string(),
        value: one_line(&value.to_string()),
        reason: reason.to_string(),
    }
}

/// `text` with its control characters escaped (`\n`, `\u{0}`), so that a message quoting what
/// the user wrote stays one line.
pub(crate) fn one_line(text: &str) -> String {
    text.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.to_string() }).collect()
}

/// Why a value is not finite and strictly positive, if it is not.
pub(crate) fn not_positive(value: f64) -> Option<&'static str> {
    if !value.is_finite() {
        Some("must be a finite number")
    } else if value <= 0.0 {
        Some("must be positive")
    } else {
        None
    }
}

/// Requires a finite, strictly positive value.
pub(crate) fn positive(field: &str, value: f64) -> Result<(), ProblemError> {
    not_positive(value).map_or(Ok(()), |reason| Err(bad(field, crate::numeric::numfmt::echo(value), reason)))
}

/// Requires `None` or a finite, strictly positive value.
pub(crate) fn positive_opt(field: &str, value: Option<f64>) -> Result<(), ProblemError> {
    value.map_or(Ok(()), |v| positive(field, v))
}
