//! towride-mbs: the physics of towride, a multibody system (MBS) of rigid and flexible
//! bodies on Swift-like tyres over a road, assembled into the DAE that `towride-solver`
//! integrates.
//!
//! Modules, lowest first; a module uses only those above it in this list (checked by
//! the test `module_order` of `tests/app`, against `docs/architecture.md`):
//!
//! | module | what it holds |
//! | --- | --- |
//! | [`progress`] | the observer long work reports to (the caller draws it) |
//! | [`input`] | property files: TOML, `.tir`, CSV tables; overrides; errors naming file, line and field; provenance |
//! | [`flex`] | beam finite-element models, Craig-Bampton reduction, mode selection |
//! | [`road`] | roads and obstacles |
//! | [`tyre`] | the rigid-ring tyre with tandem-cam enveloping, the point follower, tyre rigs |
//! | [`model`] | the multibody model: builder, elements, equations, start, statics, linearisation, runs |
//!
//! The crate reads files and computes; it writes no files and draws nothing: the
//! application crate (`towride-app`) writes outputs and reports.
//!
//! A mechanism file run from Rust: the pendulum released from horizontal, whose link
//! tension peaks at 3 m g at the bottom.
//!
//! ```
//! use std::path::Path;
//! use towride_mbs::input::Loader;
//! use towride_mbs::model::{run::simulate, spec, System};
//! use towride_mbs::progress::Silent;
//!
//! let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/examples/pendulum.toml");
//! let mech = spec::load(&file, &Loader::new())?;
//! let sys = System::new(mech.model);
//! let run = simulate(&sys, 0.0, mech.run.end_time_s, mech.run.sample_rate_hz, &mech.solver, None, &Silent);
//! let tension = run.channel("pivot.force.z").expect("the joint's force channel");
//! let peak = tension.iter().fold(f64::MIN, |m, &v| m.max(v));
//! assert!((peak / (3.0 * 9.81) - 1.0).abs() < 1e-3);
//! # Ok::<(), towride_mbs::input::InputError>(())
//! ```

// Numerical kernels index several arrays in step; iterator chains would obscure them.
#![allow(clippy::needless_range_loop)]
#![warn(missing_docs)]

pub mod progress;

pub mod input;

pub mod flex;

pub mod road;

pub mod tyre;

pub mod model;
