//! Robertson's chemical kinetics (test set problem `rober`), 3 stiff ODEs,
//! t in [0, 1e11]:
//!
//! ```text
//! y1' = -k1 y1 + k3 y2 y3
//! y2' =  k1 y1 - k2 y2^2 - k3 y2 y3
//! y3' =  k2 y2^2
//! ```
//!
//! k1 = 0.04, k2 = 3e7, k3 = 1e4, y0 = (1, 0, 0).
//!
//! # Sources
//!
//! * Equations, rate constants and y0: repository `rforge/bvpsolve`,
//!   `pkg/deTestSet/R/ex_rober.R` (derived from the test set's `rober.f`).
//! * Reference at t = 1e11: `reference("rober")` in `pkg/deTestSet/R/ex_reference.R`;
//!   the end time 1e11 belongs to this reference as used by `mauro3`'s IVPTestSuite.jl
//!   (`tspan = [0, 1e11]`) and the ODE.jl / pyodesys tests that quote the same three
//!   numbers (found through the public code index). The original `rober.f` itself was
//!   not found in the stored copies.
//! * scd over all three components (no skip entry in `report.f`); y2 is of order 1e-13
//!   but non-zero, so it enters the relative error.

use super::{Benchmark, OdeAsDae, StiffOde, StiffOdeCase};

/// End of the interval.
pub const T_END: f64 = 1e11;

/// Reference solution at t = 1e11.
#[allow(clippy::excessive_precision)] // digits kept exactly as published
pub const REFERENCE: [f64; 3] = [
    0.2083340149701255e-7,
    0.8333360770334713e-13,
    0.9999999791665050,
];

/// Initial values.
pub const Y0: [f64; 3] = [1.0, 0.0, 0.0];

/// The Robertson right-hand side with its rate constants.
#[derive(Clone, Copy, Debug)]
pub struct Robertson {
    /// Rate constant of y1 -> y2.
    pub k1: f64,
    /// Rate constant of 2 y2 -> y2 + y3.
    pub k2: f64,
    /// Rate constant of y2 + y3 -> y1 + y3.
    pub k3: f64,
}

impl Default for Robertson {
    fn default() -> Self {
        Robertson {
            k1: 0.04,
            k2: 3e7,
            k3: 1e4,
        }
    }
}

impl StiffOde for Robertson {
    fn dim(&self) -> usize {
        3
    }

    fn rhs(&self, _t: f64, y: &[f64], f: &mut [f64]) {
        f[0] = -self.k1 * y[0] + self.k3 * y[1] * y[2];
        f[1] = self.k1 * y[0] - self.k2 * y[1] * y[1] - self.k3 * y[1] * y[2];
        f[2] = self.k2 * y[1] * y[1];
    }

    fn rhs_jacobian(&self, _t: f64, y: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        out.extend([
            (0, 0, -self.k1),
            (0, 1, self.k3 * y[2]),
            (0, 2, self.k3 * y[1]),
            (1, 0, self.k1),
            (1, 1, -2.0 * self.k2 * y[1] - self.k3 * y[2]),
            (1, 2, -self.k3 * y[1]),
            (2, 1, 2.0 * self.k2 * y[1]),
        ]);
    }

    fn name(&self) -> &'static str {
        "rober"
    }
}

/// Robertson in explicit form with its data.
pub fn ode_case() -> StiffOdeCase {
    StiffOdeCase {
        ode: Box::new(Robertson::default()),
        t0: 0.0,
        t_end: T_END,
        y0: Y0.to_vec(),
        reference: REFERENCE.to_vec(),
    }
}

/// Robertson as a benchmark (F = y' - f(t, y)).
pub fn benchmark() -> Benchmark {
    let ode = Robertson::default();
    let mut yp0 = vec![0.0; 3];
    ode.rhs(0.0, &Y0, &mut yp0);
    Benchmark {
        name: "rober",
        title: "Robertson chemical kinetics (stiff ODE, 3 unknowns)",
        problem: Box::new(OdeAsDae(ode)),
        t0: 0.0,
        t_end: T_END,
        y0: Y0.to_vec(),
        yp0,
        reference: REFERENCE.to_vec(),
        scd_components: vec![0, 1, 2],
        published_steps: None,
        source: "Test Set for IVP Solvers (Mazzia, Magherini, Iavernaro; Bari), problem \
                 'rober': equations and y0 from rforge/bvpsolve pkg/deTestSet/R/ex_rober.R, \
                 reference at t = 1e11 from pkg/deTestSet/R/ex_reference.R.",
        atol_scale: 1e-4,
        ggl: None,
    }
}

#[cfg(test)]
mod tests {
    use super::super::testutil::*;
    use super::*;

    #[test]
    fn jacobian_matches_finite_differences() {
        let b = benchmark();
        let p = b.problem.as_ref();
        let y1 = [0.7, 3e-5, 0.3];
        for cj in [1.0, 1e5] {
            check_jacobian(p, 0.0, &b.y0, &b.yp0, cj, 1e-6);
            check_jacobian(p, 10.0, &y1, &b.yp0, cj, 1e-6);
        }
    }

    #[test]
    fn pattern_covers_jacobian() {
        let b = benchmark();
        check_pattern(b.problem.as_ref(), 0.0, &b.y0, &b.yp0, 1.0);
        check_pattern(b.problem.as_ref(), 1.0, &[0.7, 3e-5, 0.3], &b.yp0, 1.0);
        // 7 entries of df/dy plus the missing diagonal (2, 2).
        assert_eq!(b.problem.jacobian_pattern().unwrap().len(), 8);
    }

    #[test]
    fn mass_is_conserved_by_the_reference() {
        // y1 + y2 + y3 = 1 is invariant; the reference respects it.
        let s: f64 = REFERENCE.iter().sum();
        assert!((s - 1.0).abs() < 1e-13, "sum = {s}");
        let b = benchmark();
        check_benchmark_shape(&b);
        assert_eq!(residual_norm(b.problem.as_ref(), 0.0, &b.y0, &b.yp0), 0.0);
    }
}
