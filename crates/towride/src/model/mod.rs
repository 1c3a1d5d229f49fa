//! The multibody modelling layer: rigid bodies in absolute coordinates with quaternions,
//! ideal joints, force elements and prescribed motions, assembled into a DAE the solver
//! integrates (see [`system`]), plus the analyses run before trusting a model: kinematic
//! assembly, statics, linearisation and the numerical doctor.
//!
//! Data flows one way: a mechanism file ([`spec`]) or a vehicle template produces a
//! validated [`desc::Model`]; [`system::System`] turns it into equations.

pub mod desc;
pub mod doctor;
pub mod dual;
pub mod energy;
pub mod force;
pub mod function;
pub mod ic;
pub mod joint;
pub mod linear;
pub mod math;
pub mod output;
pub mod redundancy;
pub mod run;
pub mod spec;
pub mod start;
pub mod statics;
pub mod system;

pub use desc::Model;
pub use system::System;
