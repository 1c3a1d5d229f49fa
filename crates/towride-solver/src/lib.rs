//! Implicit integrators for differential-algebraic equations F(t, y, y') = 0 (a
//! variable-order BDF and the 3-stage Radau IIA method), and the published IVP test-set
//! problems they are verified on ([`testset`]).
//!
//! The solver knows nothing about vehicles: a problem implements [`DaeProblem`]
//! (residual, optional sparsity pattern and analytic iteration matrix, the index of each
//! unknown, event functions) and [`Bdf`] or [`Radau5`] integrates it. Both implement
//! [`DaeMethod`], whose driver (`advance` to an output time, the stop time, events,
//! statistics) is written once on each method's `step`; [`Integrator`] holds the one
//! [`SolverOptions::method`] names. See `docs/solver.md` for the
//! algorithms, the index-3 treatment and the settings.
//!
//! A DAE integrated with the BDF: y1' = -y1 + y2 with the algebraic equation
//! 0 = y2 - 2 y1 - 1, whose solution is y1 = (y1(0) + 1) e^t - 1.
//!
//! ```
//! use towride_solver::{solve_to, DaeProblem, SolverOptions, VarKind};
//!
//! struct Index1;
//!
//! impl DaeProblem for Index1 {
//!     fn size(&self) -> usize {
//!         2
//!     }
//!     fn residual(&self, _t: f64, y: &[f64], yp: &[f64], res: &mut [f64]) {
//!         res[0] = yp[0] + y[0] - y[1];
//!         res[1] = y[1] - 2.0 * y[0] - 1.0;
//!     }
//!     fn var_kinds(&self) -> Vec<VarKind> {
//!         vec![VarKind::Differential, VarKind::Algebraic1]
//!     }
//! }
//!
//! // Consistent start: y1 = 0, y2 = 1, y1' = 1.
//! let opts = SolverOptions::with_tol(1e-8, 1e-10);
//! let end = solve_to(&Index1, 0.0, &[0.0, 1.0], &[1.0, 0.0], 1.0, &opts).unwrap();
//! let exact = std::f64::consts::E - 1.0;
//! assert!((end.y[0] - exact).abs() < 1e-6);
//! println!("y1(1) = {:.9} (exact {exact:.9}), {} steps", end.y[0], end.stats.steps);
//! ```

// Numerical kernels index several arrays in step; iterator chains would obscure them.
#![allow(clippy::needless_range_loop)]
#![warn(missing_docs)]

mod bdf;
mod error;
mod ggl;
mod ic;
mod integrator;
mod jacobian;
pub mod linear;
mod method;
mod options;
pub mod problem;
pub mod radau;
mod roots;
mod sparse_lu;
pub mod testset;

pub use bdf::Bdf;
pub use error::SolverError;
pub use ggl::{Ggl, MechanicalDae};
pub use ic::consistent_index1;
pub use integrator::Integrator;
pub use method::{Advance, Core, DaeMethod, MXNCF, MXNEF};
pub use options::{
    AlgebraicControl, JacobianSource, LinearSolver, MatrixRebuilds, Method, RadauOptions,
    SolverOptions, Stats,
};
pub use problem::{DaeProblem, JacobianSink, VarKind};
pub use radau::Radau5;

use std::time::Instant;

/// The state at the end of a run plus what it cost.
#[derive(Clone, Debug)]
pub struct EndState {
    /// End time reached [s] (the requested `t_end`).
    pub t: f64,
    /// Unknowns at `t`.
    pub y: Vec<f64>,
    /// Their time derivatives at `t`.
    pub yp: Vec<f64>,
    /// Solver counters of the run.
    pub stats: Stats,
    /// Wall-clock time of the run [s].
    pub wall_s: f64,
}

/// Integrates from `t0` to `t_end` with the method of `opts` and returns the state at `t_end` (never stepping past
/// it). Events, if the problem has any, are located and passed over.
pub fn solve_to<P: DaeProblem + ?Sized>(
    prob: &P,
    t0: f64,
    y0: &[f64],
    yp0: &[f64],
    t_end: f64,
    opts: &SolverOptions,
) -> Result<EndState, SolverError> {
    let start = Instant::now();
    let mut integ = Integrator::new(prob, t0, y0, yp0, opts.clone())?;
    if t_end <= t0 {
        return Err(SolverError::BadOutputTime { tout: t_end, t: t0 });
    }
    integ.set_stop_time(t_end);
    while let Advance::Root { .. } = integ.advance(t_end)? {}
    let mut y = vec![0.0; y0.len()];
    let mut yp = vec![0.0; y0.len()];
    integ.interpolate(t_end, &mut y, &mut yp);
    Ok(EndState {
        t: t_end,
        y,
        yp,
        stats: integ.stats().clone(),
        wall_s: start.elapsed().as_secs_f64(),
    })
}
