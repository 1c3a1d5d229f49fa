//! towride: a car towing a light trailer over road obstacles, simulated with flexible
//! bodies and a Swift-like tyre, integrated by an implicit BDF DAE solver and checked
//! against recorded accelerometer data.

// Numerical kernels index several arrays in step; iterator chains would obscure them.
#![allow(clippy::needless_range_loop)]

pub mod flex;
pub mod input;
pub mod model;
pub mod progress;
pub mod report;
pub mod road;
pub mod scene;
pub mod sweep;
pub mod tyre;
pub mod validate;
pub mod vehicle;
