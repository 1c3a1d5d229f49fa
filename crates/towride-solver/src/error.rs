//! Solver errors: each says what went wrong, where in time, and on which unknowns.

use thiserror::Error;

/// Why an integration stopped early or could not start.
#[derive(Debug, Error, Clone)]
pub enum SolverError {
    /// A setting is out of range or inconsistent with the problem (checked before the start).
    #[error("invalid solver setting `{field}`: {why}")]
    InvalidSettings {
        /// Name of the offending setting.
        field: String,
        /// What is wrong with its value.
        why: String,
    },

    /// t0, an initial value or an initial derivative is NaN or infinite.
    #[error("initial state is not finite: {name} = {value}")]
    NonFiniteInitial {
        /// Name of the unknown (or "t0"), as the problem reports it.
        name: String,
        /// The offending value.
        value: f64,
    },

    /// Vector lengths or the sparsity pattern do not fit the problem's number of unknowns.
    #[error("problem size mismatch: {what}")]
    SizeMismatch {
        /// Which sizes disagree.
        what: String,
    },

    /// The Newton iteration matrix could not be factorised (zero pivot, empty row or a
    /// non-finite entry) in `max_convergence_failures` attempts at one step.
    #[error(
        "singular Newton matrix at t = {t:.9e} s (step {h:.3e} s): {detail}; \
         check for redundant constraints or unconstrained unknowns"
    )]
    SingularMatrix {
        /// Time of the failed step [s].
        t: f64,
        /// Step size of the failed attempt [s].
        h: f64,
        /// The factorisation's account of the failure (unknowns or equations involved).
        detail: String,
    },

    /// Newton did not converge in `max_convergence_failures` attempts at one step.
    #[error(
        "Newton iteration failed {failures} times at t = {t:.9e} s (step {h:.3e} s); \
         largest corrections on: {worst}"
    )]
    ConvergenceFailure {
        /// Time of the failed step [s].
        t: f64,
        /// Step size of the last attempt [s].
        h: f64,
        /// Convergence failures counted in this step.
        failures: usize,
        /// The unknowns with the largest Newton corrections, by name.
        worst: String,
    },

    /// The local error test failed `max_error_failures` times at one step.
    #[error(
        "error test failed {failures} times at t = {t:.9e} s (step {h:.3e} s); \
         largest errors on: {worst}"
    )]
    ErrorTestFailure {
        /// Time of the failed step [s].
        t: f64,
        /// Step size of the last attempt [s].
        h: f64,
        /// Error-test failures counted in this step.
        failures: usize,
        /// The unknowns with the largest weighted error estimates, by name.
        worst: String,
    },

    /// The step size needed for accuracy or convergence fell below `h_min`.
    #[error("step size {h:.3e} s fell below the minimum {h_min:.3e} s at t = {t:.9e} s")]
    StepTooSmall {
        /// Time reached [s].
        t: f64,
        /// The step size after the last cut [s].
        h: f64,
        /// The configured minimum step [s].
        h_min: f64,
    },

    /// `max_steps` steps were taken in one call without reaching the output time.
    #[error("step budget of {max_steps} steps used up at t = {t:.9e} s")]
    TooManySteps {
        /// Time reached when the budget ran out [s].
        t: f64,
        /// The step budget.
        max_steps: usize,
    },

    /// The residual came back NaN or infinite in `max_convergence_failures` attempts at one
    /// step.
    #[error("residual is not finite at t = {t:.9e} s in {equations}")]
    NonFiniteResidual {
        /// Time of the evaluation [s].
        t: f64,
        /// The non-finite equations, by name.
        equations: String,
    },

    /// No consistent y, y' could be computed from the given start values (index-1 solve
    /// failed, or the problem has index-2/3 unknowns the solve cannot handle).
    #[error("consistent initial values not found: {why}")]
    InitialConditions {
        /// The reason, from the solve or the factorisation.
        why: String,
    },

    /// An output time before the solver's current time was requested.
    #[error("output time {tout} s lies before the current time {t} s")]
    BadOutputTime {
        /// The requested output time [s].
        tout: f64,
        /// The solver's current time [s].
        t: f64,
    },
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
