//! The crate's error type: bad input, non-convergence, interruption, domain violations.

use std::fmt;

/// Everything that can go wrong in a computation of this crate.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// An argument is out of range, not finite, or of the wrong size; the message names it.
    InvalidInput(String),
    /// An iterative solver stopped at `iterations` with relative residual `residual`.
    NotConverged {
        /// What was being solved.
        what: String,
        /// Iterations performed.
        iterations: usize,
        /// Relative residual when it stopped.
        residual: f64,
    },
    /// The caller asked to stop (Ctrl-C in Python).
    Interrupted,
    /// The solution left the region the method can represent.
    Domain(String),
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, Error>;

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidInput(m) => write!(f, "invalid input: {m}"),
            Error::NotConverged {
                what,
                iterations,
                residual,
            } => write!(
                f,
                "{what} did not converge: residual {residual:.3e} after {iterations} iterations"
            ),
            Error::Interrupted => write!(f, "interrupted"),
            Error::Domain(m) => write!(f, "{m}"),
        }
    }
}

impl std::error::Error for Error {}

impl Error {
    /// The message without the kind's prefix ("invalid input: ").
    pub fn message(&self) -> String {
        match self {
            Error::InvalidInput(m) | Error::Domain(m) => m.clone(),
            other => other.to_string(),
        }
    }
}

/// Largest magnitude of a physical input, and the inverse of its smallest nonzero one: the
/// solvers multiply and square such values, and beyond this (or below its inverse) their
/// products overflow or underflow double precision. SI values of real problems lie far
/// inside; rescale the units otherwise.
pub const MAGNITUDE: f64 = 1e100;

/// Fails with `InvalidInput` unless `value` is 0 or its magnitude lies in
/// [1 / MAGNITUDE, MAGNITUDE].
pub fn check_magnitude(name: &str, value: f64) -> Result<()> {
    let m = value.abs();
    if value == 0.0 || (1.0 / MAGNITUDE..=MAGNITUDE).contains(&m) {
        Ok(())
    } else {
        Err(Error::InvalidInput(format!(
            "{name} = {value:e} is out of range: physical inputs must lie within 1e-100..1e100 in magnitude (products of larger or smaller ones overflow double precision; rescale the units)"
        )))
    }
}

/// Fails with `InvalidInput` unless `value` is finite and > 0, with a magnitude in
/// [1 / MAGNITUDE, MAGNITUDE].
pub fn check_positive(name: &str, value: f64) -> Result<()> {
    check_finite_positive(name, value)?;
    check_magnitude(name, value)
}

/// Fails with `InvalidInput` unless `value` is finite and > 0 (for step lengths, whose
/// smallness is bounded by the step count instead).
pub fn check_finite_positive(name: &str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidInput(format!(
            "{name} must be a finite positive number, got {value}"
        )))
    }
}

/// Fails with `InvalidInput` unless every entry of `values` is finite.
pub fn check_finite(name: &str, values: &[f64]) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Error::InvalidInput(format!(
            "{name} must be finite everywhere, got {} at flat index {i}",
            values[i]
        ))),
    }
}

/// Fails with `InvalidInput` unless `values` has exactly `expected` entries.
pub fn check_len(name: &str, values: usize, expected: usize) -> Result<()> {
    if values == expected {
        Ok(())
    } else {
        Err(Error::InvalidInput(format!(
            "{name} has {values} entries, expected {expected}"
        )))
    }
}
