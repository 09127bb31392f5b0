//! The scene's errors: which field, what is wrong, what is allowed.

use signorini_run::text::tidy_numbers;
use std::fmt;

/// A scene error: which field, what is wrong, what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The TOML itself (message includes line and column when the error
    /// comes from the scene's text).
    #[error("scene file: {0}")]
    Toml(#[source] toml::de::Error),
    /// A value out of its range or inconsistent with others.
    #[error("{field}: {message}")]
    Field {
        /// Dotted path of the field (`bar.dt`).
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
}

/// A field's error; very large and very small numbers in the message get
/// an exponent ([`tidy_numbers`]).
pub fn field(f: &str, m: impl fmt::Display) -> SceneError {
    SceneError::Field { field: f.to_string(), message: tidy_numbers(&m.to_string()) }
}

pub(crate) fn positive(name: &str, v: f64) -> Result<f64, SceneError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(field(name, format!("{v} is not allowed: finite and > 0")))
    }
}

pub(crate) fn finite(name: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(field(name, format!("{v} is not allowed: a finite number")))
    }
}
