//! Built-in verification problems from the "Test Set for IVP Solvers" (F. Mazzia,
//! C. Magherini, F. Iavernaro, University of Bari, release 2.3/2.4,
//! <http://www.dm.uniba.it/~testset/>).
//!
//! Every problem is written in the residual form F(t, y, y') = 0 of
//! [`DaeProblem`], with its parameters, consistent initial values (y0 *and* y'0), the
//! reference solution at the end of the interval and an analytic iteration matrix
//! dF/dy + cj dF/dy'. The formulas, parameters and reference numbers were transcribed
//! from public copies of the test-set sources; each problem file names the copies it used.
//!
//! | name      | problem                         | type            | file            |
//! |-----------|---------------------------------|-----------------|-----------------|
//! | `caraxis` | car axis                        | index-3 DAE, 10 | [`caraxis`]     |
//! | `andrews` | Andrews' squeezing mechanism    | index-3 DAE, 27 | [`andrews`]     |
//! | `hires`   | HIRES (plant physiology)        | stiff ODE, 8    | [`hires`]       |
//! | `vdpol`   | van der Pol, eps = 1e-6         | stiff ODE, 2    | [`vdpol`]       |
//! | `rober`   | Robertson chemical kinetics     | stiff ODE, 3    | [`rober`]       |
//!
//! The stiff ODEs are also available in explicit form y' = f(t, y) through [`StiffOde`] /
//! [`stiff_odes`], so they can be fed to other integrators for comparison; [`OdeAsDae`]
//! turns any of them into a [`DaeProblem`] with F = y' - f(t, y).
//!
//! # Accuracy measure
//!
//! [`scd`] computes the number of significant correct digits exactly as the test set's
//! own driver does (subroutine `getscd` in `report.f`, revision 1.20, test set release
//! 2.3; the copy read was found through the public code index, its file header reads
//! `$Id: report.F,v 1.20 2006/10/31 09:00:44 testset Exp $`):
//!
//! ```text
//! scd = -log10( max_{i in comps, |ref_i| >= 1e-200} |ref_i - y_i| / |ref_i| )
//! ```
//!
//! * Components whose reference value is zero (|ref_i| < 1e-200) are **left out** of the
//!   relative error; `getscd` does *not* switch to the absolute error for them (it only
//!   uses the absolute error for the whole scd of the problem `medakzo`, which is not
//!   here). Their absolute error enters only the separate absolute-error figure, see
//!   [`scd_absolute`].
//! * If the maximum error is exactly zero it is replaced by the rounding unit 1e-16, so a
//!   perfect answer scores 16.
//! * Components excluded per problem (`andrews`: only y1..y7 count) come from the
//!   `skipi` list in `getscd`; here they are the benchmark's `scd_components`. One
//!   deliberate difference: for `caraxis` the benchmark uses y1..y8, whereas `getscd`
//!   has no skip entry for it and takes all 10 components (multipliers included).
//!
//! [`mescd`] is the mixed error measure -log10 max |ref - y| / (atol/rtol + |ref|) that
//! the same routine (and the R package deTestSet) prints alongside.

use crate::problem::{DaeProblem, JacobianSink};

pub mod andrews;
pub mod caraxis;
pub mod ggl_forms;
pub mod hires;
pub mod radau5_runs;
pub mod rober;
pub mod runner;
pub mod vdpol;

/// One built-in verification problem with everything needed to run and judge it.
pub struct Benchmark {
    /// Short name: "caraxis", "andrews", "hires", "vdpol", "rober".
    pub name: &'static str,
    /// Human-readable title, e.g. "Car axis problem (index 3, 10 unknowns)".
    pub title: &'static str,
    /// The residual F(t, y, y') = 0 with analytic Jacobian and sparsity pattern.
    pub problem: Box<dyn DaeProblem + Send + Sync>,
    /// Start of the integration interval.
    pub t0: f64,
    /// End of the integration interval (where `reference` holds).
    pub t_end: f64,
    /// Consistent initial values.
    pub y0: Vec<f64>,
    /// Consistent initial derivatives (F(t0, y0, yp0) = 0).
    pub yp0: Vec<f64>,
    /// Reference solution at `t_end`, all components, in test-set order.
    pub reference: Vec<f64>,
    /// 0-based components the scd is taken over.
    pub scd_components: Vec<usize>,
    /// Published run statistics of an established code, where recorded.
    pub published_steps: Option<PublishedStats>,
    /// Where the problem, its data and its reference come from.
    pub source: &'static str,
    /// Absolute tolerance as a multiple of the relative one in `verify` and `bench`
    /// (Robertson: 1e-4, as the SUNDIALS driver for the test-set problem uses, because
    /// its y1 ~ 2e-8 and y2 ~ 8e-14 are otherwise below atol and uncontrolled).
    pub atol_scale: f64,
    /// The stabilised index-2 (GGL) form of an index-3 problem, when it has one.
    pub ggl: Option<GglForm>,
}

/// A benchmark rewritten in GGL form ([`crate::Ggl`]), with the map from its
/// solution (y, y') back to the test set's components.
pub struct GglForm {
    /// The residual of the GGL form.
    pub problem: Box<dyn DaeProblem + Send + Sync>,
    /// Consistent initial values of the GGL unknowns.
    pub y0: Vec<f64>,
    /// Consistent initial derivatives of the GGL unknowns.
    pub yp0: Vec<f64>,
    /// Maps the GGL solution (y, y') to the test set's components, for scoring against
    /// `reference`.
    pub to_testset: fn(&[f64], &[f64]) -> Vec<f64>,
}

/// Run statistics of an established code on a benchmark, as published.
#[derive(Clone, Debug, PartialEq)]
pub struct PublishedStats {
    /// The code, e.g. "MEBDFI".
    pub code: &'static str,
    /// rtol = atol used for the run.
    pub tol: f64,
    /// Number of integration steps.
    pub steps: usize,
    /// Number of residual (f) evaluations, if published.
    pub residual_evals: Option<usize>,
    /// Number of Jacobian evaluations, if published.
    pub jacobian_evals: Option<usize>,
}

/// All built-in benchmarks, in a fixed order.
pub fn all() -> Vec<Benchmark> {
    vec![
        caraxis::benchmark(),
        andrews::benchmark(),
        hires::benchmark(),
        vdpol::benchmark(),
        rober::benchmark(),
    ]
}

/// The benchmark called `name` ("caraxis", "andrews", "hires", "vdpol", "rober").
pub fn by_name(name: &str) -> Option<Benchmark> {
    match name {
        "caraxis" => Some(caraxis::benchmark()),
        "andrews" => Some(andrews::benchmark()),
        "hires" => Some(hires::benchmark()),
        "vdpol" => Some(vdpol::benchmark()),
        "rober" => Some(rober::benchmark()),
        _ => None,
    }
}

/// The rounding unit `getscd` substitutes for an error of exactly zero.
const SCD_UROUND: f64 = 1e-16;
/// Reference components smaller than this in magnitude count as zero (`min_value` in
/// `getscd`).
const SCD_MIN_VALUE: f64 = 1e-200;

/// Significant correct digits of `y` against `reference` over the components `comps`,
/// exactly as the test set's `getscd` (report.f) defines the scd:
///
/// scd = -log10(max_i |y_i - ref_i| / |ref_i|) over the i in `comps` with
/// |ref_i| >= 1e-200. Components with a zero reference are skipped (the test set does not
/// use the absolute error for them); a maximum error of exactly 0 counts as 1e-16
/// (scd = 16).
///
/// Deviation for robustness: if any used component's error is not finite (NaN or
/// infinite solution), the result is `f64::NEG_INFINITY`.
///
/// # Panics
/// If a component index is out of range of `y` or `reference`.
pub fn scd(y: &[f64], reference: &[f64], comps: &[usize]) -> f64 {
    let mut max_rel: f64 = 0.0;
    for &i in comps {
        let r = reference[i];
        if r.abs() < SCD_MIN_VALUE {
            continue;
        }
        let rel = ((r - y[i]) / r).abs();
        if !rel.is_finite() {
            return f64::NEG_INFINITY;
        }
        max_rel = max_rel.max(rel);
    }
    if max_rel == 0.0 {
        max_rel = SCD_UROUND;
    }
    -max_rel.log10()
}

/// The absolute-error digits `getscd` reports next to the scd:
/// -log10(max_i |y_i - ref_i|) over `comps` (zero-reference components included);
/// 0 error counts as 1e-16. Non-finite errors give `f64::NEG_INFINITY`.
pub fn scd_absolute(y: &[f64], reference: &[f64], comps: &[usize]) -> f64 {
    let mut max_abs: f64 = 0.0;
    for &i in comps {
        let a = (reference[i] - y[i]).abs();
        if !a.is_finite() {
            return f64::NEG_INFINITY;
        }
        max_abs = max_abs.max(a);
    }
    if max_abs == 0.0 {
        max_abs = SCD_UROUND;
    }
    -max_abs.log10()
}

/// Mixed-error significant digits (`mescd` of `getscd` and of the R package deTestSet):
/// -log10(max_i |y_i - ref_i| / (atol/rtol + |ref_i|)) over `comps`. Note that `getscd`
/// takes the mescd over *all* components (it does not apply the per-problem skip list).
/// 0 error counts as 1e-16; non-finite errors give `f64::NEG_INFINITY`.
pub fn mescd(y: &[f64], reference: &[f64], comps: &[usize], rtol: f64, atol: f64) -> f64 {
    let mut max_mixed: f64 = 0.0;
    for &i in comps {
        let m = ((reference[i] - y[i]) / (atol / rtol + reference[i].abs())).abs();
        if !m.is_finite() {
            return f64::NEG_INFINITY;
        }
        max_mixed = max_mixed.max(m);
    }
    if max_mixed == 0.0 {
        max_mixed = SCD_UROUND;
    }
    -max_mixed.log10()
}

/// A stiff ODE in explicit form y' = f(t, y), for feeding to other integrators.
pub trait StiffOde: Send + Sync {
    /// Number of unknowns.
    fn dim(&self) -> usize;
    /// Writes f(t, y) into `f` (length `dim()`).
    fn rhs(&self, t: f64, y: &[f64], f: &mut [f64]);
    /// Appends the entries (row, col, df_row/dy_col) of the Jacobian df/dy to `out`
    /// (without clearing it). Every *structural* non-zero must be pushed whatever its
    /// value at (t, y), so that the structure does not depend on the point.
    fn rhs_jacobian(&self, t: f64, y: &[f64], out: &mut Vec<(usize, usize, f64)>);
    /// Short name of the problem ("hires", "vdpol", ...).
    fn name(&self) -> &'static str;
    /// Name of unknown `i` (default "y1", "y2", ... as in the test set).
    fn var_name(&self, i: usize) -> String {
        format!("y{}", i + 1)
    }
}

/// A stiff ODE from the test set in explicit form, with its interval, initial values and
/// reference solution.
pub struct StiffOdeCase {
    /// The right-hand side f(t, y) and its Jacobian.
    pub ode: Box<dyn StiffOde>,
    /// Start of the interval.
    pub t0: f64,
    /// End of the interval (where `reference` holds).
    pub t_end: f64,
    /// Initial values.
    pub y0: Vec<f64>,
    /// Reference solution at `t_end`.
    pub reference: Vec<f64>,
}

/// The stiff ODEs of the collection (hires, vdpol, rober) in explicit form.
pub fn stiff_odes() -> Vec<StiffOdeCase> {
    vec![hires::ode_case(), vdpol::ode_case(), rober::ode_case()]
}

/// Wraps a [`StiffOde`] as the DAE F(t, y, y') = y' - f(t, y) = 0, all unknowns
/// differential, with the analytic iteration matrix cj*I - df/dy and the sparsity pattern
/// of df/dy plus the diagonal.
pub struct OdeAsDae<O: StiffOde>(pub O);

impl<O: StiffOde> DaeProblem for OdeAsDae<O> {
    fn size(&self) -> usize {
        self.0.dim()
    }

    fn residual(&self, t: f64, y: &[f64], yp: &[f64], res: &mut [f64]) {
        self.0.rhs(t, y, res);
        for (r, &p) in res.iter_mut().zip(yp) {
            *r = p - *r;
        }
    }

    fn jacobian_pattern(&self) -> Option<Vec<(usize, usize)>> {
        let n = self.0.dim();
        // The structure does not depend on the point (see `StiffOde::rhs_jacobian`).
        let mut entries = Vec::new();
        self.0.rhs_jacobian(0.0, &vec![1.0; n], &mut entries);
        let mut pattern: Vec<(usize, usize)> = entries.iter().map(|&(r, c, _)| (r, c)).collect();
        pattern.extend((0..n).map(|i| (i, i)));
        pattern.sort_unstable();
        pattern.dedup();
        Some(pattern)
    }

    fn jacobian(&self, t: f64, y: &[f64], _yp: &[f64], cj: f64, jac: &mut JacobianSink) -> bool {
        let mut entries = Vec::new();
        self.0.rhs_jacobian(t, y, &mut entries);
        for (r, c, v) in entries {
            jac.add(r, c, -v);
        }
        for i in 0..self.0.dim() {
            jac.add_scaled(i, i, cj, 1.0);
        }
        true
    }

    fn var_name(&self, i: usize) -> String {
        self.0.var_name(i)
    }

    fn eq_name(&self, i: usize) -> String {
        format!("{}' = f{}", self.0.var_name(i), i + 1)
    }
}

/// Shared checks for the unit tests of the problem files.
#[cfg(test)]
pub(crate) mod testutil {
    use crate::problem::{DaeProblem, JacobianSink};
    use std::collections::HashSet;

    /// The analytic iteration matrix as a dense matrix (duplicates summed).
    pub fn analytic_dense(
        p: &dyn DaeProblem,
        t: f64,
        y: &[f64],
        yp: &[f64],
        cj: f64,
    ) -> Vec<Vec<f64>> {
        let n = p.size();
        let mut entries = Vec::new();
        let given = p.jacobian(t, y, yp, cj, &mut JacobianSink::new(&mut entries));
        assert!(given, "problem offers no analytic Jacobian");
        let mut a = vec![vec![0.0; n]; n];
        for (r, c, v) in entries {
            assert!(r < n && c < n, "Jacobian entry ({r}, {c}) out of range");
            a[r][c] += v;
        }
        a
    }

    /// dF/dy + cj dF/dy' by central differences, column by column, together with an
    /// estimate of the round-off noise of each entry (a few ulps of the residuals
    /// involved, divided by the step).
    pub fn fd_dense(
        p: &dyn DaeProblem,
        t: f64,
        y: &[f64],
        yp: &[f64],
        cj: f64,
    ) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let n = p.size();
        let mut a = vec![vec![0.0; n]; n];
        let mut noise = vec![vec![0.0; n]; n];
        let mut fp = vec![0.0; n];
        let mut fm = vec![0.0; n];
        let ulps = 8.0 * f64::EPSILON;
        for j in 0..n {
            let h = 1e-6 * y[j].abs().max(1.0);
            let mut yy = y.to_vec();
            yy[j] = y[j] + h;
            p.residual(t, &yy, yp, &mut fp);
            yy[j] = y[j] - h;
            p.residual(t, &yy, yp, &mut fm);
            for i in 0..n {
                a[i][j] += (fp[i] - fm[i]) / (2.0 * h);
                noise[i][j] += ulps * fp[i].abs().max(fm[i].abs()) / h;
            }
            let h = 1e-6 * yp[j].abs().max(1.0);
            let mut pp = yp.to_vec();
            pp[j] = yp[j] + h;
            p.residual(t, y, &pp, &mut fp);
            pp[j] = yp[j] - h;
            p.residual(t, y, &pp, &mut fm);
            for i in 0..n {
                a[i][j] += cj * (fp[i] - fm[i]) / (2.0 * h);
                noise[i][j] += cj.abs() * ulps * fp[i].abs().max(fm[i].abs()) / h;
            }
        }
        (a, noise)
    }

    /// Compares the analytic Jacobian with central differences, entry by entry: the
    /// tolerance is `rtol` relative to the entry, plus the estimated round-off noise of
    /// the difference quotient, plus 1e-9 of the largest entry of its row.
    pub fn check_jacobian(p: &dyn DaeProblem, t: f64, y: &[f64], yp: &[f64], cj: f64, rtol: f64) {
        let a = analytic_dense(p, t, y, yp, cj);
        let (f, noise) = fd_dense(p, t, y, yp, cj);
        for i in 0..p.size() {
            let row_scale = a[i]
                .iter()
                .chain(f[i].iter())
                .fold(0.0_f64, |m, v| m.max(v.abs()));
            for j in 0..p.size() {
                let tol = rtol * a[i][j].abs().max(f[i][j].abs()) + noise[i][j] + 1e-9 * row_scale;
                assert!(
                    (a[i][j] - f[i][j]).abs() <= tol,
                    "Jacobian ({i}, {j}) [{} wrt {}] at t = {t}, cj = {cj}: analytic {:e}, \
                     finite difference {:e}",
                    p.eq_name(i),
                    p.var_name(j),
                    a[i][j],
                    f[i][j]
                );
            }
        }
    }

    /// Every entry the Jacobian writes lies in the declared pattern, and the pattern is in
    /// range.
    pub fn check_pattern(p: &dyn DaeProblem, t: f64, y: &[f64], yp: &[f64], cj: f64) {
        let n = p.size();
        let pattern: HashSet<(usize, usize)> = p
            .jacobian_pattern()
            .expect("problem declares no pattern")
            .into_iter()
            .collect();
        for &(r, c) in &pattern {
            assert!(r < n && c < n, "pattern entry ({r}, {c}) out of range");
        }
        let mut entries = Vec::new();
        assert!(p.jacobian(t, y, yp, cj, &mut JacobianSink::new(&mut entries)));
        for (r, c, _) in entries {
            assert!(
                pattern.contains(&(r, c)),
                "Jacobian writes ({r}, {c}) [{} wrt {}] outside the pattern",
                p.eq_name(r),
                p.var_name(c)
            );
        }
    }

    /// A deterministic perturbation of `v`: v_i + scale * sin(1.7 i + 0.3).
    pub fn perturbed(v: &[f64], scale: f64) -> Vec<f64> {
        v.iter()
            .enumerate()
            .map(|(i, &x)| x + scale * (1.7 * i as f64 + 0.3).sin())
            .collect()
    }

    /// max_i |F_i(t, y, yp)|.
    pub fn residual_norm(p: &dyn DaeProblem, t: f64, y: &[f64], yp: &[f64]) -> f64 {
        let mut r = vec![0.0; p.size()];
        p.residual(t, y, yp, &mut r);
        r.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
    }

    /// Structural checks common to every benchmark.
    pub fn check_benchmark_shape(b: &super::Benchmark) {
        let n = b.problem.size();
        assert_eq!(b.y0.len(), n, "{}: y0 length", b.name);
        assert_eq!(b.yp0.len(), n, "{}: yp0 length", b.name);
        assert_eq!(b.reference.len(), n, "{}: reference length", b.name);
        assert_eq!(
            b.problem.var_kinds().len(),
            n,
            "{}: var_kinds length",
            b.name
        );
        assert!(b.t_end > b.t0);
        assert!(b.scd_components.iter().all(|&i| i < n));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scd_hand_computed() {
        let reference = [1.0, 2.0, 0.0, 4.0, -0.5];
        let y = [1.001, 2.0, 7.0, 5.0, -0.5];
        // Component 0: |1 - 1.001| / 1 = 1e-3; component 1 exact; component 2 has a zero
        // reference and is skipped (not turned into an absolute error of 7).
        let s = scd(&y, &reference, &[0, 1, 2]);
        assert!((s - 3.0).abs() < 1e-9, "scd = {s}");
        // Component 3: |4 - 5| / 4 = 0.25 -> -log10(0.25) = 0.60206.
        let s = scd(&y, &reference, &[0, 1, 2, 3]);
        assert!((s - 0.602_059_991_327_962_4).abs() < 1e-12, "scd = {s}");
        // Only exact and zero-reference components: error 0 -> 1e-16 -> 16 digits.
        assert_eq!(scd(&y, &reference, &[1, 2, 4]), 16.0);
        // Components outside `comps` do not count.
        assert!((scd(&y, &reference, &[0]) - 3.0).abs() < 1e-9);
        // A NaN answer never scores.
        let bad = [f64::NAN, 2.0, 0.0, 4.0, -0.5];
        assert_eq!(scd(&bad, &reference, &[0, 1]), f64::NEG_INFINITY);
    }

    #[test]
    fn scd_absolute_and_mixed_hand_computed() {
        let reference = [1.0, 0.0, 100.0];
        let y = [1.01, 1e-5, 100.0];
        // Absolute: max(0.01, 1e-5, 0) = 0.01 -> 2.
        assert!((scd_absolute(&y, &reference, &[0, 1, 2]) - 2.0).abs() < 1e-12);
        // Mixed with rtol = atol: |err| / (1 + |ref|): 0.01/2, 1e-5/1, 0 -> 0.005 -> 2.30103.
        let m = mescd(&y, &reference, &[0, 1, 2], 1e-6, 1e-6);
        assert!((m - 2.301_029_995_663_981).abs() < 1e-12, "mescd = {m}");
    }

    /// A problem whose analytic Jacobian leaves out one entry, to show that the
    /// finite-difference check notices it.
    struct DropEntry<P: DaeProblem> {
        inner: P,
        drop: (usize, usize),
    }

    impl<P: DaeProblem> DaeProblem for DropEntry<P> {
        fn size(&self) -> usize {
            self.inner.size()
        }
        fn residual(&self, t: f64, y: &[f64], yp: &[f64], res: &mut [f64]) {
            self.inner.residual(t, y, yp, res)
        }
        fn jacobian(&self, t: f64, y: &[f64], yp: &[f64], cj: f64, jac: &mut JacobianSink) -> bool {
            let mut entries = Vec::new();
            self.inner
                .jacobian(t, y, yp, cj, &mut JacobianSink::new(&mut entries));
            for (r, c, v) in entries {
                if (r, c) != self.drop {
                    jac.add(r, c, v);
                }
            }
            true
        }
    }

    #[test]
    #[should_panic(expected = "Jacobian (4, 8)")]
    fn jacobian_check_catches_a_missing_caraxis_entry() {
        let b = caraxis::benchmark();
        let p = DropEntry {
            inner: caraxis::CarAxis::default(),
            drop: (4, 8),
        };
        testutil::check_jacobian(&p, 0.0, &b.y0, &b.yp0, 1.0, 1e-6);
    }

    #[test]
    #[should_panic(expected = "Jacobian (16, 16)")]
    fn jacobian_check_catches_a_missing_small_andrews_entry() {
        // -M33 (about 1.6e-5) in a row whose other entries are of order 1e2 at the
        // reference point.
        let b = andrews::benchmark();
        let p = DropEntry {
            inner: andrews::Andrews::default(),
            drop: (16, 16),
        };
        testutil::check_jacobian(&p, 0.03, &andrews::REFERENCE, &b.yp0, 1.0, 1e-6);
    }

    #[test]
    fn registry_is_consistent() {
        let names: Vec<&str> = all().iter().map(|b| b.name).collect();
        assert_eq!(names, ["caraxis", "andrews", "hires", "vdpol", "rober"]);
        for name in names {
            let b = by_name(name).expect("registered");
            assert_eq!(b.name, name);
            testutil::check_benchmark_shape(&b);
            // The reference scores 16 digits against itself.
            assert_eq!(scd(&b.reference, &b.reference, &b.scd_components), 16.0);
        }
        assert!(by_name("nonesuch").is_none());
    }

    #[test]
    fn stiff_odes_match_their_benchmarks() {
        for case in stiff_odes() {
            let b = by_name(case.ode.name()).expect("benchmark of the same name");
            assert_eq!(case.ode.dim(), b.problem.size());
            assert_eq!(case.t0, b.t0);
            assert_eq!(case.t_end, b.t_end);
            assert_eq!(case.y0, b.y0);
            assert_eq!(case.reference, b.reference);
            // yp0 of the DAE form is f(t0, y0).
            let mut f = vec![0.0; case.ode.dim()];
            case.ode.rhs(case.t0, &case.y0, &mut f);
            assert_eq!(f, b.yp0);
        }
    }
}
