//! towride-app: the towride application. A car towing a light trailer over road
//! obstacles, built from vehicle templates on the physics crate `towride-mbs`, run
//! through one pipeline, post-processed, compared with recorded accelerometer data and
//! written as figures and reports.
//!
//! Files become a [`job::Job`] (the model, solver options, run settings, start policy);
//! [`job::Job::run`] returns the samples and a typed summary as data, and
//! [`report::write_run`] writes them. `docs/architecture.md` maps the crates.
//!
//! Modules, lowest first; a module uses only those above it in this list (checked by
//! the test `module_order` of `tests/app`, against `docs/architecture.md`):
//!
//! | module | what it holds |
//! | --- | --- |
//! | [`atomic`] | files written whole or not at all |
//! | [`error`] | the application's errors and [`Error`] |
//! | [`signal`] | filters, spectra, power spectral densities |
//! | [`comfort`] | ride comfort after ISO 2631-1: weightings, a_w, VDV, MTVV |
//! | [`durability`] | rainflow counting, Miner damage, damage-equivalent loads |
//! | [`vehicle`] | vehicle templates: property files into builder calls |
//! | [`scene`] | scenes and plans: a vehicle on a road, what to run and record |
//! | [`job`] | the run pipeline and its summary (data, no files) |
//! | [`report`] | figures and reports; a run's files |
//! | [`sweep`] | parameter sweeps, shards, their page |
//! | [`validate`] | comparison with recorded runs |
//! | [`study`] | bench, stress, scaling and sensitivity studies |
//!
//! A mechanism file run from Rust: the pendulum released from horizontal, whose link
//! tension peaks at 3 m g at the bottom.
//!
//! ```
//! use std::path::Path;
//! use towride_app::prelude::*;
//!
//! let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/examples/pendulum.toml");
//! let run = Job::from_file(&file, &Loader::new())?.run(&Silent)?;
//! let tension = run.summary.channels["pivot.force.z"].extremes.max;
//! assert!((tension / (3.0 * 9.81) - 1.0).abs() < 1e-4);
//! println!("peak link tension {tension:.4} N in {} steps", run.summary.solver.steps);
//! # Ok::<(), towride_app::Error>(())
//! ```
//!
//! The default scene (the thesis's ramp at 50 km/h) run from Rust, the extremes of its
//! hitch force printed (max, min and |peak|; no signed peak) and of a sensor as the
//! instrument saw it (its band-limited twin, through the scene's 100 Hz acquisition
//! low-pass):
//!
//! ```
//! use std::path::Path;
//! use towride_app::prelude::*;
//! use towride_app::scene::channels::HITCH_FX;
//!
//! let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/default.toml");
//! let run = Job::from_file(&scene, &Loader::new())?.run(&Silent)?;
//! let fx = run.extremes(HITCH_FX).expect("a scene has the hitch_fx channel");
//! println!(
//!     "hitch_fx max {:.1} N at {:.3} s, min {:.1} N at {:.3} s, |peak| {:.1} N",
//!     fx.max, fx.t_max, fx.min, fx.t_min, fx.abs_peak
//! );
//! assert!(run.completed() && (3e3..1e4).contains(&fx.abs_peak));
//! let seen = run.abs_peak("acc_hitch_z_lp100").expect("the band-limited twin");
//! assert!(seen < run.abs_peak("acc_hitch_z").unwrap());
//! # Ok::<(), towride_app::Error>(())
//! ```

// Numerical kernels index several arrays in step; iterator chains would obscure them.
#![allow(clippy::needless_range_loop)]
#![warn(missing_docs)]

pub mod atomic;

pub mod error;

pub mod signal;

pub mod durability;

pub mod comfort;

pub mod vehicle;

pub mod scene;

pub mod job;

pub mod report;

pub mod validate;

pub mod study;

pub mod sweep;

pub mod calibrate;

pub use error::{Error, Result};

/// What most programs need: jobs and their results, loading with overrides, progress,
/// the model builder's inputs, and the error type.
pub mod prelude {
    pub use crate::error::{Error, Result};
    pub use crate::job::{Job, RunResult, RunSummary, StartPolicy};
    pub use crate::scene::{Changes, Scene};
    pub use towride_mbs::input::{Loader, Override};
    pub use towride_mbs::progress::{Progress, Silent};
    pub use towride_solver::SolverOptions;
}
