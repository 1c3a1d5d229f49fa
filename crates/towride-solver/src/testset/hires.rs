//! HIRES (test set problem `hires`): "High Irradiance RESponse" of photomorphogenesis
//! on the basis of phytochrome (Schäfer 1975), 8 stiff ODEs, t in [0, 321.8122].
//!
//! ```text
//! y1' = -1.71 y1 + 0.43 y2 + 8.32 y3 + 0.0007
//! y2' =  1.71 y1 - 8.75 y2
//! y3' = -10.03 y3 + 0.43 y4 + 0.035 y5
//! y4' =  8.32 y2 + 1.71 y3 - 1.12 y4
//! y5' = -1.745 y5 + 0.43 y6 + 0.43 y7
//! y6' = -280 y6 y8 + 0.69 y4 + 1.71 y5 - 0.43 y6 + 0.69 y7
//! y7' =  280 y6 y8 - 1.81 y7
//! y8' = -y7'
//! ```
//!
//! y0 = (1, 0, 0, 0, 0, 0, 0, 0.0057).
//!
//! # Sources
//!
//! * Right-hand side, Jacobian, interval and initial values: the test-set file
//!   `hires.f` (`$Id: hires.F,v 1.2 2006/10/02 10:29:14 testset Exp $`), copy in
//!   repository `volpatto/pside`, `problems/HIRES/hires.f` (subroutines `prob`, `init`,
//!   `feval`, `jeval`). The parametrised version `rforge/bvpsolve`
//!   `pkg/deTestSet/src/Ex_hires.f` with the rate constants of
//!   `pkg/deTestSet/R/ex_hires.R` (k1 = 1.71, k2 = 0.43, k3 = 8.32, k4 = 0.69,
//!   k5 = 0.035, k6 = 8.32, k7 = 280, k8 = 0.69, k9 = 0.69, Oks = 0.0007) gives the same
//!   coefficients.
//! * Reference at t = 321.8122: subroutine `solut` of `hires.f` (RADAU5 in true double
//!   precision on a Cray C90, uround = 1.01e-19, rtol = atol = h0 = 1.1e-18), identical
//!   to `hiressol` in `Ex_hires.f` and to `reference("hires")` in
//!   `pkg/deTestSet/R/ex_reference.R`. scd over all 8 components (no skip entry in
//!   `report.f`).

use super::{Benchmark, OdeAsDae, StiffOde, StiffOdeCase};

/// End of the interval.
pub const T_END: f64 = 321.8122;

/// Reference solution at t = 321.8122 (`solut` in `hires.f`).
pub const REFERENCE: [f64; 8] = [
    0.7371312573325668e-3,
    0.1442485726316185e-3,
    0.5888729740967575e-4,
    0.1175651343283149e-2,
    0.2386356198831331e-2,
    0.6238968252742796e-2,
    0.2849998395185769e-2,
    0.2850001604814231e-2,
];

/// Initial values (`init` in `hires.f`).
pub const Y0: [f64; 8] = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0057];

/// The HIRES right-hand side.
#[derive(Clone, Copy, Debug, Default)]
pub struct Hires;

impl StiffOde for Hires {
    fn dim(&self) -> usize {
        8
    }

    fn rhs(&self, _t: f64, y: &[f64], f: &mut [f64]) {
        f[0] = -1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007;
        f[1] = 1.71 * y[0] - 8.75 * y[1];
        f[2] = -10.03 * y[2] + 0.43 * y[3] + 0.035 * y[4];
        f[3] = 8.32 * y[1] + 1.71 * y[2] - 1.12 * y[3];
        f[4] = -1.745 * y[4] + 0.43 * (y[5] + y[6]);
        f[5] = -280.0 * y[5] * y[7] + 0.69 * y[3] + 1.71 * y[4] - 0.43 * y[5] + 0.69 * y[6];
        f[6] = 280.0 * y[5] * y[7] - 1.81 * y[6];
        f[7] = -f[6];
    }

    fn rhs_jacobian(&self, _t: f64, y: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        out.extend([
            (0, 0, -1.71),
            (0, 1, 0.43),
            (0, 2, 8.32),
            (1, 0, 1.71),
            (1, 1, -8.75),
            (2, 2, -10.03),
            (2, 3, 0.43),
            (2, 4, 0.035),
            (3, 1, 8.32),
            (3, 2, 1.71),
            (3, 3, -1.12),
            (4, 4, -1.745),
            (4, 5, 0.43),
            (4, 6, 0.43),
            (5, 3, 0.69),
            (5, 4, 1.71),
            (5, 5, -280.0 * y[7] - 0.43),
            (5, 6, 0.69),
            (5, 7, -280.0 * y[5]),
            (6, 5, 280.0 * y[7]),
            (6, 6, -1.81),
            (6, 7, 280.0 * y[5]),
            (7, 5, -280.0 * y[7]),
            (7, 6, 1.81),
            (7, 7, -280.0 * y[5]),
        ]);
    }

    fn name(&self) -> &'static str {
        "hires"
    }
}

/// HIRES in explicit form with its data.
pub fn ode_case() -> StiffOdeCase {
    StiffOdeCase {
        ode: Box::new(Hires),
        t0: 0.0,
        t_end: T_END,
        y0: Y0.to_vec(),
        reference: REFERENCE.to_vec(),
    }
}

/// HIRES as a benchmark (F = y' - f(t, y)).
pub fn benchmark() -> Benchmark {
    let mut yp0 = vec![0.0; 8];
    Hires.rhs(0.0, &Y0, &mut yp0);
    Benchmark {
        name: "hires",
        title: "HIRES (stiff ODE, 8 unknowns)",
        problem: Box::new(OdeAsDae(Hires)),
        t0: 0.0,
        t_end: T_END,
        y0: Y0.to_vec(),
        yp0,
        reference: REFERENCE.to_vec(),
        scd_components: (0..8).collect(),
        published_steps: None,
        source: "Test Set for IVP Solvers (Mazzia, Magherini, Iavernaro; Bari), problem \
                 'hires' (hires.f rev 1.2, 2006): equations, y0, t_end and reference (RADAU5, \
                 Cray C90, uround 1.01e-19) from volpatto/pside problems/HIRES/hires.f; \
                 cross-checked with rforge/bvpsolve pkg/deTestSet/src/Ex_hires.f and \
                 pkg/deTestSet/R/ex_reference.R.",
        atol_scale: 1.0,
        ggl: None,
    }
}

#[cfg(test)]
mod tests {
    use super::super::testutil::*;
    use super::*;
    use crate::problem::DaeProblem;

    #[test]
    fn rate_constants_match_the_parametrised_form() {
        // Ex_hires.f / ex_hires.R: f in terms of k1..k9, Oks.
        let (k1, k2, k3, k4, k5, k6, k7, k8, k9, oks) = (
            1.71, 0.43, 8.32, 0.69, 0.035, 8.32, 280.0, 0.69, 0.69, 0.0007,
        );
        let y = [0.3, 0.02, 0.07, 0.11, 0.05, 0.013, 0.021, 0.004];
        let mut f = [0.0; 8];
        Hires.rhs(0.0, &y, &mut f);
        let g = [
            -k1 * y[0] + k2 * y[1] + k6 * y[2] + oks,
            k1 * y[0] - (k2 + k3) * y[1],
            -(k6 + k1) * y[2] + k2 * y[3] + k5 * y[4],
            k3 * y[1] + k1 * y[2] - (k4 + k2) * y[3],
            -(k5 + k1) * y[4] + k2 * (y[5] + y[6]),
            -k7 * y[5] * y[7] + k8 * y[3] + k1 * y[4] - k2 * y[5] + k8 * y[6],
            k7 * y[5] * y[7] - (k2 + k8 + k9) * y[6],
            -(k7 * y[5] * y[7] - (k2 + k8 + k9) * y[6]),
        ];
        for i in 0..8 {
            assert!(
                (f[i] - g[i]).abs() < 1e-15,
                "f{} = {} vs {}",
                i + 1,
                f[i],
                g[i]
            );
        }
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let b = benchmark();
        let p = b.problem.as_ref();
        let y1 = perturbed(&REFERENCE, 1e-3);
        for cj in [1.0, 4.2e2] {
            check_jacobian(p, 0.0, &b.y0, &b.yp0, cj, 1e-6);
            check_jacobian(p, 100.0, &y1, &b.yp0, cj, 1e-6);
        }
    }

    #[test]
    fn pattern_covers_jacobian() {
        let b = benchmark();
        check_pattern(b.problem.as_ref(), 0.0, &b.y0, &b.yp0, 1.0);
        check_pattern(b.problem.as_ref(), T_END, &REFERENCE, &b.yp0, 7.0);
        // 25 entries of df/dy; the diagonal is among them.
        assert_eq!(b.problem.jacobian_pattern().unwrap().len(), 25);
    }

    #[test]
    fn reference_keeps_the_invariant() {
        // y8' = -y7', so y7 + y8 = 0.0057 for all t; the reference respects it.
        let s = REFERENCE[6] + REFERENCE[7];
        assert!((s - Y0[6] - Y0[7]).abs() < 1e-17, "y7 + y8 = {s}");
    }

    #[test]
    fn initial_derivative_is_consistent() {
        let b = benchmark();
        check_benchmark_shape(&b);
        assert_eq!(residual_norm(b.problem.as_ref(), 0.0, &b.y0, &b.yp0), 0.0);
        assert_eq!(OdeAsDae(Hires).var_name(7), "y8");
    }
}
