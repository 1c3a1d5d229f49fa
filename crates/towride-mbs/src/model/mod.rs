//! The multibody modelling layer: rigid bodies in absolute coordinates with quaternions,
//! ideal joints, force elements and prescribed motions, assembled into a DAE the solver
//! integrates (see [`system`]), plus the analyses run before trusting a model: kinematic
//! assembly, statics, linearisation and the numerical doctor.
//!
//! Data flows one way: a mechanism file ([`spec`]) or a vehicle template produces a
//! validated [`desc::Model`]; [`system::System`] turns it into equations.

pub mod builder;
pub mod desc;
pub mod doctor;
pub(crate) mod dual;
pub mod elements;
pub mod energy;
pub mod function;
mod function_jerk;
pub mod ic;
pub(crate) mod joint;
pub mod linear;
pub mod math;
pub mod normal;
pub mod output;
pub mod redundancy;
pub mod run;
pub mod spec;
pub mod start;
pub mod statics;
pub mod stick;
pub use crate::input::suggest;
pub mod system;

pub use desc::Model;
pub use system::System;

use towride_solver::SolverError;

/// Why a model could not be built, started or analysed.
#[derive(Debug, Clone, thiserror::Error)]
pub enum ModelError {
    /// A value the model builder refuses, before it is located in a file: `item` names
    /// the body or element, `field` the value (as the file keys name it).
    #[error("{item}: {error}")]
    Build {
        /// The body or element, e.g. `spring 'damper_fl'`.
        item: String,
        /// The field refused, as the file keys name it, and why.
        error: crate::input::FieldError,
    },
    /// Something the solver cannot run (a motion on a direction the joints lock).
    #[error("{0}")]
    Unsupported(String),
    /// Kinematic assembly or the consistent initial state failed.
    #[error("{0}")]
    Assembly(String),
    /// A singular system at the start or at an output.
    #[error("{0}")]
    Singular(String),
    /// The static equilibrium was not found.
    #[error("{0}")]
    Statics(String),
    /// Starting at speed failed.
    #[error("{0}")]
    Start(String),
    /// The linearisation failed.
    #[error("{0}")]
    Linearise(String),
    /// The integrator failed in a model analysis (statics relaxation, settling run).
    #[error(transparent)]
    Solver(#[from] SolverError),
}
