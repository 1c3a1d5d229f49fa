//! towride: a car towing a light trailer over road obstacles, simulated with flexible
//! bodies and a Swift-like tyre, integrated by an implicit BDF DAE solver and checked
//! against recorded accelerometer data.

// Numerical kernels index several arrays in step; iterator chains would obscure them.
#![allow(clippy::needless_range_loop)]
#![warn(missing_docs)]

pub mod error;
pub mod flex;
pub mod input;
pub mod job;
pub mod model;
pub mod progress;
pub mod report;
pub mod road;
pub mod scene;
pub mod study;
pub mod sweep;
pub mod tyre;
pub mod validate;
pub mod vehicle;

pub use error::{Error, Result};

/// What most programs need: jobs and their results, loading with overrides, progress,
/// the model builder's inputs, and the error type.
pub mod prelude {
    pub use crate::error::{Error, Result};
    pub use crate::input::{Loader, Override};
    pub use crate::job::{Job, RunResult, RunSummary, StartPolicy};
    pub use crate::progress::{Progress, Silent};
    pub use crate::scene::{Changes, Scene};
    pub use towride_solver::SolverOptions;
}
