//! Solver errors: each says what went wrong, where in time, and on which unknowns.

use thiserror::Error;

/// Why an integration stopped early or could not start.
#[derive(Debug, Error, Clone)]
pub enum SolverError {
    #[error("invalid solver setting `{field}`: {why}")]
    InvalidSettings { field: String, why: String },

    #[error("initial state is not finite: {name} = {value}")]
    NonFiniteInitial { name: String, value: f64 },

    #[error("problem size mismatch: {what}")]
    SizeMismatch { what: String },

    #[error(
        "singular Newton matrix at t = {t:.9e} s (step {h:.3e} s): {detail}; \
         check for redundant constraints or unconstrained unknowns"
    )]
    SingularMatrix { t: f64, h: f64, detail: String },

    #[error(
        "Newton iteration failed {failures} times at t = {t:.9e} s (step {h:.3e} s); \
         largest corrections on: {worst}"
    )]
    ConvergenceFailure {
        t: f64,
        h: f64,
        failures: usize,
        worst: String,
    },

    #[error(
        "error test failed {failures} times at t = {t:.9e} s (step {h:.3e} s); \
         largest errors on: {worst}"
    )]
    ErrorTestFailure {
        t: f64,
        h: f64,
        failures: usize,
        worst: String,
    },

    #[error("step size {h:.3e} s fell below the minimum {h_min:.3e} s at t = {t:.9e} s")]
    StepTooSmall { t: f64, h: f64, h_min: f64 },

    #[error("step budget of {max_steps} steps used up at t = {t:.9e} s")]
    TooManySteps { t: f64, max_steps: usize },

    #[error("residual is not finite at t = {t:.9e} s in {equations}")]
    NonFiniteResidual { t: f64, equations: String },

    #[error("consistent initial values not found: {why}")]
    InitialConditions { why: String },

    #[error("output time {tout} s lies before the current time {t} s")]
    BadOutputTime { tout: f64, t: f64 },
}

impl SolverError {
    /// Time at which the failure happened, when it has one.
    pub fn time(&self) -> Option<f64> {
        match self {
            SolverError::SingularMatrix { t, .. }
            | SolverError::ConvergenceFailure { t, .. }
            | SolverError::ErrorTestFailure { t, .. }
            | SolverError::StepTooSmall { t, .. }
            | SolverError::TooManySteps { t, .. }
            | SolverError::NonFiniteResidual { t, .. } => Some(*t),
            _ => None,
        }
    }
}
