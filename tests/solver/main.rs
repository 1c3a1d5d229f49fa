//! Integration tests of `towride-solver`: the BDF and Radau IIA integrators on problems with closed-form
//! or published reference solutions. One test binary per crate (as ripgrep does): each
//! area is a module here.

mod index1;
mod pendulum;
mod radau;
mod stald;
mod testset;
