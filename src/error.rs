//! The library's error type: every failure names what went wrong and, for a bad parameter, the
//! parameter (by its FMU variable name) and the limit it broke.

use std::fmt;

/// Everything that can stop a simulation from being set up or advanced.
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// A parameter is non-finite or outside its physical or numerical range.
    InvalidParameter {
        /// FMU variable name, e.g. `material.poisson_ratio`.
        name: String,
        /// The rejected value, as text.
        value: String,
        /// The limit that was broken, e.g. `must lie in [0, 0.5)`.
        limit: String,
    },
    /// The base displacement z(t) left the open gap (g1, g2) (`docs/model.md` §5).
    BaseOutsideGap {
        /// Time at which the base was to be applied (s).
        time: f64,
        /// Base displacement z(t) (m).
        base: f64,
        /// Lower obstacle level, if enabled (m).
        lower: Option<f64>,
        /// Upper obstacle level, if enabled (m).
        upper: Option<f64>,
    },
    /// A saved state cannot be restored: one of its fields is malformed or physically impossible.
    InvalidState {
        /// The field, e.g. `current[12]` or `base[1]`.
        field: String,
        /// The rejected value, as text.
        value: String,
        /// What the field must satisfy, e.g. `must be finite`.
        limit: String,
    },
    /// A linear algebra step failed (a matrix that should be positive definite is not, numerically),
    /// or a step's result overflowed.
    Numerical(String),
    /// The contact problem of a step could not be solved to the required accuracy.
    ContactSolver(String),
}

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    pub fn invalid(name: &str, value: impl fmt::Display, limit: &str) -> Error {
        Error::InvalidParameter {
            name: name.to_string(),
            value: value.to_string(),
            limit: limit.to_string(),
        }
    }
}

impl Error {
    /// Shorthand for [`Error::InvalidState`].
    pub fn invalid_state(field: &str, value: impl fmt::Display, limit: &str) -> Error {
        Error::InvalidState {
            field: field.to_string(),
            value: value.to_string(),
            limit: limit.to_string(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidParameter { name, value, limit } => {
                write!(f, "parameter {name} = {value} is invalid: it {limit}")
            }
            Error::BaseOutsideGap {
                time,
                base,
                lower,
                upper,
            } => {
                let level = |g: &Option<f64>| g.map_or("none".to_string(), |g| format!("{g} m"));
                write!(
                    f,
                    "at t = {time} s the base displacement z = {base} m is not strictly between the \
                     obstacles (lower {}, upper {}): the clamped edge would enter an obstacle",
                    level(lower),
                    level(upper)
                )
            }
            Error::InvalidState {
                field,
                value,
                limit,
            } => write!(
                f,
                "saved state field {field} = {value} is invalid: it {limit}"
            ),
            Error::Numerical(msg) => write!(f, "numerical failure: {msg}"),
            Error::ContactSolver(msg) => write!(f, "contact solver failure: {msg}"),
        }
    }
}

impl std::error::Error for Error {}
