//! One interface over the integrators, chosen by [`SolverOptions::method`]: the BDF
//! ([`Bdf`], `variable` and `fixed-coefficient`) or Radau IIA ([`Radau5`], `radau5`).
//! The model layer drives either through it.

use crate::bdf::{Advance, Bdf};
use crate::error::SolverError;
use crate::options::{Method, SolverOptions, Stats};
use crate::problem::DaeProblem;
use crate::radau::Radau5;

/// An integrator bound to one problem.
pub enum Integrator<'a, P: DaeProblem + ?Sized> {
    /// The BDF (`variable` or `fixed-coefficient`).
    Bdf(Box<Bdf<'a, P>>),
    /// Radau IIA (`radau5`).
    Radau5(Box<Radau5<'a, P>>),
}

impl<'a, P: DaeProblem + ?Sized> Integrator<'a, P> {
    /// Sets up the method `opts.method` at (t0, y0, y'0); the initial values must be
    /// consistent.
    pub fn new(
        prob: &'a P,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        opts: SolverOptions,
    ) -> Result<Self, SolverError> {
        Ok(match opts.method {
            Method::Radau5 => Integrator::Radau5(Box::new(Radau5::new(prob, t0, y0, yp0, opts)?)),
            Method::Variable | Method::FixedCoefficient => {
                Integrator::Bdf(Box::new(Bdf::new(prob, t0, y0, yp0, opts)?))
            }
        })
    }

    /// Never step past `tstop`.
    pub fn set_stop_time(&mut self, tstop: f64) {
        match self {
            Integrator::Bdf(b) => b.set_stop_time(tstop),
            Integrator::Radau5(r) => r.set_stop_time(tstop),
        }
    }

    /// Integrates until the internal time reaches `tout` or an event function changes sign.
    pub fn advance(&mut self, tout: f64) -> Result<Advance, SolverError> {
        match self {
            Integrator::Bdf(b) => b.advance(tout),
            Integrator::Radau5(r) => r.advance(tout),
        }
    }

    /// y and y' at `t` within the last step, from the method's interpolant.
    pub fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]) {
        match self {
            Integrator::Bdf(b) => b.interpolate(t, y, yp),
            Integrator::Radau5(r) => r.interpolate(t, y, yp),
        }
    }

    /// Current internal time (the end of the last accepted step).
    pub fn t(&self) -> f64 {
        match self {
            Integrator::Bdf(b) => b.t(),
            Integrator::Radau5(r) => r.t(),
        }
    }

    /// Counters of the integration so far.
    pub fn stats(&self) -> &Stats {
        match self {
            Integrator::Bdf(b) => b.stats(),
            Integrator::Radau5(r) => r.stats(),
        }
    }

    /// The `k` unknowns that dominated the error estimate in the most accepted steps.
    pub fn step_limiters(&self, k: usize) -> Vec<(String, usize)> {
        match self {
            Integrator::Bdf(b) => b.step_limiters(k),
            Integrator::Radau5(r) => r.step_limiters(k),
        }
    }
}

/// What the shared driver needs of a one-step method (diffsol's pattern: the loop to an
/// output time is written once, on `step`).
pub(crate) trait Stepping {
    /// The time reached.
    fn now(&self) -> f64;
    /// Lands exactly on the stop time once within round-off of it.
    fn finish_at(&mut self, t: f64);
    /// The time not to step past.
    fn stop_time(&self) -> Option<f64>;
    /// Step budget of one call.
    fn max_steps(&self) -> usize;
    /// One accepted step (with its own retries).
    fn step(&mut self) -> Result<(), SolverError>;
    /// An event in the last step, if any.
    fn check_roots(&mut self) -> Option<Advance>;
}

/// Round-off units within which the stop time counts as reached.
const TSTOP_UROUNDS: f64 = 4.0;

/// Steps `s` until `tout` (or its stop time, or an event) is reached.
pub(crate) fn drive<S: Stepping>(s: &mut S, tout: f64) -> Result<Advance, SolverError> {
    let mut steps_here = 0usize;
    while s.now() < tout {
        if let Some(ts) = s.stop_time() {
            if s.now() >= ts - TSTOP_UROUNDS * f64::EPSILON * ts.abs().max(1.0) {
                s.finish_at(ts);
                return Ok(Advance::Reached);
            }
        }
        if steps_here >= s.max_steps() {
            return Err(SolverError::TooManySteps {
                t: s.now(),
                max_steps: s.max_steps(),
            });
        }
        s.step()?;
        steps_here += 1;
        if let Some(r) = s.check_roots() {
            return Ok(r);
        }
    }
    Ok(Advance::Reached)
}
