//! The method [`SolverOptions::method`] names, chosen at run time: the BDF ([`Bdf`],
//! `variable` and `fixed-coefficient`) or Radau IIA ([`Radau5`], `radau5`). The model
//! layer drives either through it; every call goes to the [`DaeMethod`] it derefs to.

use std::ops::{Deref, DerefMut};

use crate::bdf::Bdf;
use crate::error::SolverError;
use crate::method::DaeMethod;
use crate::options::{Method, SolverOptions};
use crate::problem::DaeProblem;
use crate::radau::Radau5;

/// An integrator bound to one problem: the method of its options behind [`DaeMethod`].
pub struct Integrator<'a, P: DaeProblem + ?Sized + 'a>(Box<dyn DaeMethod<'a, P> + 'a>);

impl<'a, P: DaeProblem + ?Sized + 'a> Integrator<'a, P> {
    /// Sets up the method `opts.method` at (t0, y0, y'0); the initial values must be
    /// consistent.
    pub fn new(
        prob: &'a P,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        opts: SolverOptions,
    ) -> Result<Self, SolverError> {
        Ok(Self(match opts.method {
            Method::Radau5 => Box::new(Radau5::new(prob, t0, y0, yp0, opts)?),
            Method::Variable | Method::FixedCoefficient => {
                Box::new(Bdf::new(prob, t0, y0, yp0, opts)?)
            }
        }))
    }
}

impl<'a, P: DaeProblem + ?Sized + 'a> Deref for Integrator<'a, P> {
    type Target = dyn DaeMethod<'a, P> + 'a;
    fn deref(&self) -> &Self::Target {
        &*self.0
    }
}

impl<'a, P: DaeProblem + ?Sized + 'a> DerefMut for Integrator<'a, P> {
    fn deref_mut(&mut self) -> &mut Self::Target {
        &mut *self.0
    }
}
