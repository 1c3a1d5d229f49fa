//! Runs a benchmark at given settings and scores it against its reference.

use std::time::Instant;

use super::{mescd, scd, Benchmark};
use crate::{solve_to, Method, SolverOptions, Stats};

/// How an index-3 benchmark is handed to the solver.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Formulation {
    /// Stabilised index 2 (GGL) when the benchmark has that form, else as published.
    #[default]
    Ggl,
    /// As published (index 3 with h-scaled multipliers).
    Index3,
}

/// One benchmark run: settings, end state, accuracy and cost.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct CaseResult {
    /// Benchmark name.
    pub problem: String,
    /// Formulation actually used (`Ggl` falls back to `Index3` without a GGL form).
    pub formulation: Formulation,
    /// BDF coefficient method.
    pub method: Method,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// End of the interval, where the reference holds.
    pub t_end: f64,
    /// Solution at `t_end`, in the test set's component order (empty if the run failed).
    pub y: Vec<f64>,
    /// Significant correct digits over the benchmark's SCD components (`None` if failed).
    pub scd: Option<f64>,
    /// Mixed-error digits over all components (test set's `mescd`).
    pub mescd: Option<f64>,
    /// "ok" or "failed".
    pub status: String,
    /// The solver's error message when the run failed.
    pub error: Option<String>,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected step attempts.
    pub rejected_steps: usize,
    /// Residual evaluations.
    pub residual_evals: usize,
    /// Iteration-matrix evaluations.
    pub jacobian_evals: usize,
    /// LU factorisations.
    pub lu_factorizations: usize,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Local error-test failures.
    pub error_test_failures: usize,
    /// Newton convergence failures.
    pub convergence_failures: usize,
    /// Wall time of one run [s] (the fastest of `repeats` runs).
    pub wall_s: f64,
    /// How many times the run was repeated for timing.
    pub repeats: usize,
    /// The published step count this problem is compared against, when there is one.
    pub published_code: Option<String>,
    /// Tolerance of the published run.
    pub published_tol: Option<f64>,
    /// Step count of the published run.
    pub published_steps: Option<usize>,
}

/// Runs `b` with rtol = `rtol`, atol = `atol`. With `min_wall_s > 0` the run is repeated
/// until that much time has passed (at most 50 times) and the fastest time is kept.
pub fn run_case(
    b: &Benchmark,
    rtol: f64,
    atol: f64,
    method: Method,
    formulation: Formulation,
    min_wall_s: f64,
) -> CaseResult {
    let opts = SolverOptions {
        method,
        ..SolverOptions::with_tol(rtol, atol)
    };
    run_with(b, &opts, formulation, min_wall_s)
}

/// Runs `b` with explicit options (tolerances taken from `opts`).
pub fn run_with(
    b: &Benchmark,
    opts: &SolverOptions,
    formulation: Formulation,
    min_wall_s: f64,
) -> CaseResult {
    let ggl = b.ggl.as_ref().filter(|_| formulation == Formulation::Ggl);
    let formulation = if ggl.is_some() {
        Formulation::Ggl
    } else {
        Formulation::Index3
    };
    let clock = Instant::now();
    let mut best = f64::INFINITY;
    let mut repeats = 0;
    let outcome = loop {
        let r = match ggl {
            Some(g) => {
                solve_to(g.problem.as_ref(), b.t0, &g.y0, &g.yp0, b.t_end, opts).map(|mut e| {
                    e.y = (g.to_testset)(&e.y, &e.yp);
                    e
                })
            }
            None => solve_to(b.problem.as_ref(), b.t0, &b.y0, &b.yp0, b.t_end, opts),
        };
        repeats += 1;
        match &r {
            Ok(end) => best = best.min(end.wall_s),
            Err(_) => break r,
        }
        if clock.elapsed().as_secs_f64() >= min_wall_s || repeats >= 50 {
            break r;
        }
    };
    let published = b.published_steps.as_ref();
    let mut res = CaseResult {
        problem: b.name.to_string(),
        formulation,
        method: opts.method,
        rtol: opts.rtol,
        atol: opts.atol[0],
        t_end: b.t_end,
        y: Vec::new(),
        scd: None,
        mescd: None,
        status: "ok".into(),
        error: None,
        steps: 0,
        rejected_steps: 0,
        residual_evals: 0,
        jacobian_evals: 0,
        lu_factorizations: 0,
        newton_iterations: 0,
        error_test_failures: 0,
        convergence_failures: 0,
        wall_s: if best.is_finite() {
            best
        } else {
            clock.elapsed().as_secs_f64()
        },
        repeats,
        published_code: published.map(|p| p.code.to_string()),
        published_tol: published.map(|p| p.tol),
        published_steps: published.map(|p| p.steps),
    };
    match outcome {
        Ok(end) => {
            let all: Vec<usize> = (0..b.reference.len()).collect();
            res.scd = Some(scd(&end.y, &b.reference, &b.scd_components));
            res.mescd = Some(mescd(&end.y, &b.reference, &all, opts.rtol, opts.atol[0]));
            res.y = end.y;
            fill_stats(&mut res, &end.stats);
        }
        Err(e) => {
            res.status = "failed".into();
            res.error = Some(e.to_string());
        }
    }
    res
}

fn fill_stats(r: &mut CaseResult, s: &Stats) {
    r.steps = s.steps;
    r.rejected_steps = s.rejected_steps;
    r.residual_evals = s.residual_evals;
    r.jacobian_evals = s.jacobian_evals;
    r.lu_factorizations = s.lu_factorizations;
    r.newton_iterations = s.newton_iterations;
    r.error_test_failures = s.error_test_failures;
    r.convergence_failures = s.convergence_failures;
}
