//! towride: a car towing a light trailer over road obstacles, simulated with flexible
//! bodies and a Swift-like tyre, integrated by an implicit BDF DAE solver and checked
//! against recorded accelerometer data.
//!
//! Files become a [`job::Job`] (the model, solver options, run settings, start policy);
//! [`job::Job::run`] returns the samples and a typed summary. `docs/architecture.md`
//! maps the crate.
//!
//! A mechanism file run from Rust: the pendulum released from horizontal, whose link
//! tension peaks at 3 m g at the bottom.
//!
//! ```
//! use std::path::Path;
//! use towride::prelude::*;
//!
//! let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/examples/pendulum.toml");
//! let run = Job::from_file(&file, &Loader::new())?.run(&Silent)?;
//! let tension = run.summary.channels["pivot.force.z"].max;
//! assert!((tension / (3.0 * 9.81) - 1.0).abs() < 1e-4);
//! println!("peak link tension {tension:.4} N in {} steps", run.summary.solver.steps);
//! # Ok::<(), towride::Error>(())
//! ```
//!
//! The default scene (the thesis's ramp at 50 km/h) run from Rust, its hitch-force
//! peak printed:
//!
//! ```
//! use std::path::Path;
//! use towride::prelude::*;
//!
//! let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/default.toml");
//! let run = Job::from_file(&scene, &Loader::new())?.run(&Silent)?;
//! let peak = run.peak("hitch_fx").expect("a scene has the hitch_fx channel");
//! println!("hitch_fx peak {peak:.1} N at {:.3} s", run.summary.channels["hitch_fx"].t_peak);
//! assert!(run.completed() && (3e3..1e4).contains(&peak.abs()));
//! # Ok::<(), towride::Error>(())
//! ```

// Numerical kernels index several arrays in step; iterator chains would obscure them.
#![allow(clippy::needless_range_loop)]
#![warn(missing_docs)]

pub mod atomic;
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
