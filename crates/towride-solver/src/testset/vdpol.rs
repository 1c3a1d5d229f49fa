//! Van der Pol oscillator in the test set's stiff, rescaled form (problem `vdpol`),
//! 2 ODEs, t in [0, 2]:
//!
//! ```text
//! y1' = y2
//! y2' = ((1 - y1^2) y2 - y1) / eps,     eps = 1e-6
//! ```
//!
//! y0 = (2, 0).
//!
//! # Sources
//!
//! * Equations (`feval`, `jeval` with the literal 1.0d-6), interval (`t(1) = 2.0d0`),
//!   initial values and reference: the test-set file `vdpol.f`
//!   (`$Id: vdpol.F,v 1.2 2006/10/02 10:29:14 testset Exp $`), copy in repository
//!   `volpatto/pside`, `problems/VdPol/vdpol.f`. The reference was computed with RADAU
//!   on an Alphaserver DS20E, uround = 1.01e-19, rtol = atol = h0 = 1.1e-18. The same
//!   numbers are in `mauro3`'s IVPTestSuite.jl (found through the public code index).
//! * Do not confuse with the test set's `vdpolm` (mu = 1000 unscaled, t in [0, 2000]),
//!   whose reference (1.706167732170469, -0.8928097010248125e-3) is what
//!   `reference("vdpol")` of deTestSet's `ex_reference.R` returns: its y2 is the
//!   unscaled velocity, 1/1000 of the y2 here.
//! * scd over both components (no skip entry in `report.f`).

use super::{Benchmark, OdeAsDae, StiffOde, StiffOdeCase};

/// The stiffness parameter of the test set.
pub const EPS: f64 = 1e-6;

/// End of the interval.
pub const T_END: f64 = 2.0;

/// Reference solution at t = 2 (`solut` in `vdpol.f`).
pub const REFERENCE: [f64; 2] = [0.1706167732170483e1, -0.8928097010247975e0];

/// Initial values.
pub const Y0: [f64; 2] = [2.0, 0.0];

/// The scaled van der Pol right-hand side.
#[derive(Clone, Copy, Debug)]
pub struct VanDerPol {
    /// Stiffness parameter eps (1e-6 in the test set).
    pub eps: f64,
}

impl Default for VanDerPol {
    fn default() -> Self {
        VanDerPol { eps: EPS }
    }
}

impl StiffOde for VanDerPol {
    fn dim(&self) -> usize {
        2
    }

    fn rhs(&self, _t: f64, y: &[f64], f: &mut [f64]) {
        f[0] = y[1];
        f[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / self.eps;
    }

    fn rhs_jacobian(&self, _t: f64, y: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        out.extend([
            (0, 1, 1.0),
            (1, 0, (-2.0 * y[0] * y[1] - 1.0) / self.eps),
            (1, 1, (1.0 - y[0] * y[0]) / self.eps),
        ]);
    }

    fn name(&self) -> &'static str {
        "vdpol"
    }
}

/// Van der Pol in explicit form with its data.
pub fn ode_case() -> StiffOdeCase {
    StiffOdeCase {
        ode: Box::new(VanDerPol::default()),
        t0: 0.0,
        t_end: T_END,
        y0: Y0.to_vec(),
        reference: REFERENCE.to_vec(),
    }
}

/// Van der Pol as a benchmark (F = y' - f(t, y)).
pub fn benchmark() -> Benchmark {
    let ode = VanDerPol::default();
    let mut yp0 = vec![0.0; 2];
    ode.rhs(0.0, &Y0, &mut yp0);
    Benchmark {
        name: "vdpol",
        title: "Van der Pol, eps = 1e-6 (stiff ODE, 2 unknowns)",
        problem: Box::new(OdeAsDae(ode)),
        t0: 0.0,
        t_end: T_END,
        y0: Y0.to_vec(),
        yp0,
        reference: REFERENCE.to_vec(),
        scd_components: vec![0, 1],
        published_steps: None,
        source: "Test Set for IVP Solvers (Mazzia, Magherini, Iavernaro; Bari), problem \
                 'vdpol' (vdpol.f rev 1.2, 2006): equations, y0, t_end and reference (RADAU, \
                 uround 1.01e-19) from volpatto/pside problems/VdPol/vdpol.f.",
        atol_scale: 1.0,
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
        for cj in [1.0, 1e6] {
            check_jacobian(p, 0.0, &b.y0, &b.yp0, cj, 1e-6);
            check_jacobian(p, 1.0, &REFERENCE, &[0.3, -4.0], cj, 1e-6);
            check_jacobian(p, 1.5, &[-1.2, 0.7], &[0.7, 2.0], cj, 1e-6);
        }
    }

    #[test]
    fn pattern_covers_jacobian() {
        let b = benchmark();
        check_pattern(b.problem.as_ref(), 0.0, &b.y0, &b.yp0, 1.0);
        // df/dy has 3 entries; the pattern adds (0, 0).
        assert_eq!(b.problem.jacobian_pattern().unwrap().len(), 4);
    }

    #[test]
    fn initial_derivative_is_consistent() {
        let b = benchmark();
        check_benchmark_shape(&b);
        assert_eq!(b.yp0, vec![0.0, -2.0e6]);
        assert_eq!(residual_norm(b.problem.as_ref(), 0.0, &b.y0, &b.yp0), 0.0);
    }

    #[test]
    fn scaled_and_unscaled_references_agree() {
        // vdpolm (mu = 1000, t = 2000) reference from deTestSet's ex_reference.R: the
        // scaled y2 is 1000 times the unscaled one.
        let vdpolm = [0.1706167732170469e1, -0.8928097010248125e-3];
        let rescaled = [vdpolm[0], 1e3 * vdpolm[1]];
        let s = super::super::scd(&rescaled, &REFERENCE, &[0, 1]);
        assert!(s > 12.0, "scd = {s}");
    }
}
