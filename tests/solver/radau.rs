//! Radau IIA (`Method::Radau5`) against independent references: its order on a problem
//! with a closed-form solution, its stability function on linear test equations, the
//! published reference solutions of the test set (and the Fortran RADAU5's own step counts
//! on them, `docs/data/radau5_testset.csv`), its dense output against a closed form, and
//! events.

use nalgebra::Complex;
use towride_solver::testset::{self, radau5_runs, runner};
use towride_solver::{
    solve_to, Advance, Bdf, DaeProblem, Integrator, JacobianSink, Method, SolverError,
    SolverOptions,
};

use crate::pendulum::{start as pendulum_start, Pendulum, PERIOD};

fn radau(rtol: f64, atol: f64) -> SolverOptions {
    SolverOptions {
        method: Method::Radau5,
        ..SolverOptions::with_tol(rtol, atol)
    }
}

/// Fixed steps of size h: the first step and the largest step are h, and the tolerance is
/// loose enough that no step is rejected (the tests check the step count).
fn fixed_step(h: f64) -> SolverOptions {
    SolverOptions {
        h_init: Some(h),
        h_max: h,
        ..radau(1e-1, 1e-1)
    }
}

/// Prothero-Robinson: y' = lambda (y - sin t) + cos t, y(0) = 0, solution y = sin t.
struct ProtheroRobinson {
    lambda: f64,
}

impl DaeProblem for ProtheroRobinson {
    fn size(&self) -> usize {
        1
    }
    fn residual(&self, t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) {
        r[0] = yp[0] - self.lambda * (y[0] - t.sin()) - t.cos();
    }
    fn jacobian(&self, _t: f64, _y: &[f64], _yp: &[f64], cj: f64, j: &mut JacobianSink) -> bool {
        j.add(0, 0, -self.lambda);
        j.add_scaled(0, 0, cj, 1.0);
        true
    }
}

#[test]
fn global_error_falls_with_the_fifth_power_of_the_step() {
    let p = ProtheroRobinson { lambda: -2.0 };
    let t_end = 2.0;
    let errs: Vec<f64> = [0.4, 0.2, 0.1]
        .iter()
        .map(|&h| {
            let end = solve_to(&p, 0.0, &[0.0], &[1.0], t_end, &fixed_step(h)).unwrap();
            assert_eq!(end.stats.steps, (t_end / h).round() as usize, "fixed steps");
            (end.y[0] - t_end.sin()).abs()
        })
        .collect();
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(
            (4.7..5.5).contains(&order),
            "observed order {order}: {errs:?}"
        );
    }
}

/// The stability function of the 3-stage Radau IIA method (Hairer & Wanner II, IV.5):
/// R(z) = (1 + 2z/5 + z^2/20) / (1 - 3z/5 + 3z^2/20 - z^3/60).
fn stability(z: Complex<f64>) -> Complex<f64> {
    let num = 1.0 + z * 0.4 + z * z / 20.0;
    let den = 1.0 - z * 0.6 + z * z * 0.15 - z * z * z / 60.0;
    num / den
}

/// u' = a u - b v, v' = b u + a v: u + i v follows the scalar equation w' = (a + i b) w.
struct Rotation {
    a: f64,
    b: f64,
}

impl DaeProblem for Rotation {
    fn size(&self) -> usize {
        2
    }
    fn residual(&self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) {
        r[0] = yp[0] - (self.a * y[0] - self.b * y[1]);
        r[1] = yp[1] - (self.b * y[0] + self.a * y[1]);
    }
    fn jacobian(&self, _t: f64, _y: &[f64], _yp: &[f64], cj: f64, j: &mut JacobianSink) -> bool {
        j.add(0, 0, -self.a);
        j.add(0, 1, self.b);
        j.add(1, 0, -self.b);
        j.add(1, 1, -self.a);
        j.add_scaled(0, 0, cj, 1.0);
        j.add_scaled(1, 1, cj, 1.0);
        true
    }
}

/// One step of size 1 from w = 1: the result is R(lambda).
fn one_step(lambda: Complex<f64>) -> Complex<f64> {
    let p = Rotation {
        a: lambda.re,
        b: lambda.im,
    };
    // A tolerance no step of interest fails (h omega up to 1e3 is far from accurate).
    let opts = SolverOptions {
        rtol: 1e3,
        atol: vec![1e3],
        ..fixed_step(1.0)
    };
    let end = solve_to(&p, 0.0, &[1.0, 0.0], &[lambda.re, lambda.im], 1.0, &opts).unwrap();
    assert_eq!(end.stats.steps, 1, "one step for {lambda}");
    Complex::new(end.y[0], end.y[1])
}

#[test]
fn one_step_applies_the_stability_function_and_stiff_modes_die_out() {
    // Stiff decay: R(z) -> 0 like 3/|z| (L-stability).
    let mut prev = f64::INFINITY;
    for z in [-1.0, -10.0, -1e2, -1e4, -1e6, -1e8] {
        let w = one_step(Complex::new(z, 0.0));
        let r = stability(Complex::new(z, 0.0));
        // The stage system's condition grows like |z|: so does the rounding error.
        let tol = 1e-14 * z.abs().max(1.0) * r.norm();
        assert!((w - r).norm() <= tol, "z {z}: {w} against {r}");
        if z <= -1e2 {
            assert!(w.norm() <= 3.1 / z.abs(), "z {z}: |R| = {}", w.norm());
        }
        assert!(w.norm() < prev);
        prev = w.norm();
    }
    // Lightly damped modes (damping ratio 0.05) at h omega from 0.5 to 1e3: never
    // amplified (A-stability), where BDF4-5 amplify those at h omega 1-4; the fast ones
    // are damped out.
    for homega in [0.5, 2.0, 4.0, 100.0, 1e3] {
        let z = Complex::new(-0.05, (1.0f64 - 0.05 * 0.05).sqrt()) * homega;
        let w = one_step(z);
        let r = stability(z);
        assert!((w - r).norm() <= 1e-11, "h omega {homega}: {w} against {r}");
        assert!(w.norm() < 1.0, "h omega {homega}: |R| = {}", w.norm());
    }
    assert!(one_step(Complex::new(-50.0, 1e3)).norm() < 4e-3);
}

fn case(name: &str, tol: f64, form: runner::Formulation) -> runner::CaseResult {
    let b = testset::by_name(name).unwrap();
    let opts = SolverOptions {
        h_init: Some(tol), // rtol = atol = h0, as the test set runs RADAU5
        ..radau(tol, tol * b.atol_scale)
    };
    let r = runner::run_with(&b, &opts, form, 0.0);
    assert_eq!(r.status, "ok", "{name} {tol:e}: {:?}", r.error);
    r
}

#[test]
fn mechanisms_reach_five_digits_at_1e_9() {
    use runner::Formulation::{Ggl, Index3};
    for (name, form, min) in [
        ("caraxis", Ggl, 5.0),
        ("andrews", Ggl, 5.0),
        ("andrews", Index3, 5.0),
    ] {
        let r = case(name, 1e-9, form);
        let scd = r.scd.unwrap();
        assert!(scd >= min, "{name} {form:?}: scd {scd}");
    }
    // The car axis as published (index 3): Radau IIA controls the velocities only to
    // tol / h, so their digits wander with the step sequence (RADAU5 itself scores 4.1 to
    // 5.4 over y1..y8 between rtol 2e-10 and 3e-11); the positions are held.
    let b = testset::by_name("caraxis").unwrap();
    let r = case("caraxis", 1e-9, Index3);
    let positions = testset::scd(&r.y, &b.reference, &[0, 1, 2, 3]);
    assert!(positions >= 5.5, "car axis positions: scd {positions}");
}

#[test]
fn stiff_odes_match_the_fortran_radau5() {
    // Same method, same controller: the accepted steps agree with RADAU5's own runs
    // (docs/data/radau5_testset.csv) and so does the accuracy.
    for name in ["hires", "vdpol", "rober"] {
        let b = testset::by_name(name).unwrap();
        for tol in [1e-6, 1e-9] {
            let ours = case(name, tol, runner::Formulation::Ggl);
            let theirs = radau5_runs::find(name, tol).expect("a RADAU5 run");
            let (s, f) = (ours.steps as f64, theirs.accepted as f64);
            assert!(
                (s - f).abs() <= 0.03 * f + 2.0,
                "{name} {tol:e}: {s} steps, RADAU5 {f}"
            );
            let (a, c) = (ours.scd.unwrap(), theirs.scd(&b));
            assert!(a >= c - 0.5, "{name} {tol:e}: scd {a}, RADAU5 {c}");
        }
    }
}

/// y1' = y2, y2' = -y1: y = (sin t, cos t).
struct Oscillator;

impl DaeProblem for Oscillator {
    fn size(&self) -> usize {
        2
    }
    fn residual(&self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) {
        r[0] = yp[0] - y[1];
        r[1] = yp[1] + y[0];
    }
}

#[test]
fn dense_output_follows_the_closed_form_between_steps() {
    let tol = 1e-8;
    let mut integ =
        Integrator::new(&Oscillator, 0.0, &[0.0, 1.0], &[1.0, 0.0], radau(tol, tol)).unwrap();
    integ.set_stop_time(10.0);
    let (mut y, mut yp) = ([0.0; 2], [0.0; 2]);
    let (mut err_y, mut err_yp, mut err_end) = (0.0f64, 0.0f64, 0.0f64);
    let mut err_end_yp = 0.0f64;
    for k in 1..=1000 {
        let t = 0.01 * k as f64;
        while integ.t() < t {
            assert_eq!(integ.advance(t).unwrap(), Advance::Reached);
            // At a step's end the polynomial gives the step's solution.
            integ.interpolate(integ.t(), &mut y, &mut yp);
            let te = integ.t();
            err_end = err_end.max((y[0] - te.sin()).abs().max((y[1] - te.cos()).abs()));
            err_end_yp = err_end_yp.max((yp[0] - te.cos()).abs().max((yp[1] + te.sin()).abs()));
        }
        integ.interpolate(t, &mut y, &mut yp);
        err_y = err_y.max((y[0] - t.sin()).abs().max((y[1] - t.cos()).abs()));
        err_yp = err_yp.max((yp[0] - t.cos()).abs().max((yp[1] + t.sin()).abs()));
    }
    let steps = integ.stats().steps;
    assert!(
        steps < 200,
        "{steps} steps: the outputs must fall inside steps"
    );
    // At the step ends: the method's order 5 (value) and the last stage derivative.
    assert!(err_end < 20.0 * tol, "step ends: {err_end:e}");
    assert!(
        err_end_yp < 20.0 * tol,
        "step ends, derivative: {err_end_yp:e}"
    );
    // Between them the collocation polynomial is of order 3 (the stage order): an error
    // O(h^4) in the value and O(h^3) in its derivative, h ~ 0.1 here (measured 2.0e-7 and
    // 2.3e-5).
    assert!(err_y < 50.0 * tol, "dense output: {err_y:e}");
    assert!(err_yp < 5e3 * tol, "dense derivative: {err_yp:e}");
}

#[test]
fn events_find_the_passes_under_the_pivot_as_the_bdf_does() {
    let (y0, yp0) = pendulum_start();
    let p = Pendulum { analytic: true };
    let roots_of = |mut integ: Integrator<'_, Pendulum>| {
        integ.set_stop_time(0.9 * PERIOD);
        let mut roots = Vec::new();
        while let Advance::Root { t, .. } = integ.advance(0.9 * PERIOD).unwrap() {
            let (mut y, mut yp) = (vec![0.0; 5], vec![0.0; 5]);
            integ.interpolate(t, &mut y, &mut yp);
            assert!(y[0].abs() < 1e-10, "x = {} at the root", y[0]);
            roots.push(t);
        }
        roots
    };
    let tol = 1e-9;
    let ours = roots_of(Integrator::new(&p, 0.0, &y0, &yp0, radau(tol, tol)).unwrap());
    let bdf =
        roots_of(Integrator::new(&p, 0.0, &y0, &yp0, SolverOptions::with_tol(tol, tol)).unwrap());
    assert_eq!(ours.len(), 2, "{ours:?}");
    assert_eq!(bdf.len(), 2, "{bdf:?}");
    for (k, frac) in [0.25, 0.75].iter().enumerate() {
        assert!((ours[k] - frac * PERIOD).abs() < 1e-5, "{ours:?}");
        assert!((ours[k] - bdf[k]).abs() < 2e-5, "{ours:?} against {bdf:?}");
    }
}

#[test]
fn statistics_count_both_factorisations_and_the_bdf_refuses_the_method() {
    let b = testset::by_name("vdpol").unwrap();
    let end = solve_to(
        b.problem.as_ref(),
        b.t0,
        &b.y0,
        &b.yp0,
        b.t_end,
        &radau(1e-6, 1e-6),
    )
    .unwrap();
    let st = &end.stats;
    assert_eq!(st.lu_factorizations, st.complex_lu_factorizations);
    assert!(st.lu_factorizations >= st.jacobian_evals && st.jacobian_evals > 0);
    // Three stage residuals per Newton iteration and one per error estimate.
    assert!(st.residual_evals >= 3 * st.newton_iterations + st.steps);
    assert_eq!(st.order_counts[4], st.steps);
    // Every factorisation pair has one recorded reason; those on a kept Jacobian are
    // recombinations.
    let why = &st.matrix_rebuilds;
    assert_eq!(
        why.invalid + why.step_change + why.convergence + why.age,
        st.lu_factorizations,
        "{why:?}"
    );
    assert_eq!(why.step_change, st.matrix_recombinations);
    assert!(why.invalid >= 1 && why.step_change > 0, "{why:?}");
    let p = ProtheroRobinson { lambda: -1.0 };
    assert!(matches!(
        Bdf::new(&p, 0.0, &[0.0], &[1.0], radau(1e-6, 1e-6)),
        Err(SolverError::InvalidSettings { .. })
    ));
}

/// A mass on a stiff damper and a spring dragged along a ramp that starts at t_k, as a
/// tyre's ring on its residual spring and damper over an obstacle's foot:
/// m x'' = k (s - x) + c (s' - x') with s(t) = a max(0, t - t_k). With y = x - s the
/// motion is free after the kink, from y = 0 and y' = -a: with r1, r2 the roots of
/// m r^2 + c r + k, y(tau) = -a (e^(r1 tau) - e^(r2 tau)) / (r1 - r2). The acceleration
/// jumps by c a / m at the kink; for steps longer than m / c the error estimate of the
/// fast component stays near 1 whatever the step.
struct KinkedRamp {
    m: f64,
    c: f64,
    k: f64,
    a: f64,
    t_k: f64,
}

impl KinkedRamp {
    fn s(&self, t: f64) -> (f64, f64) {
        if t > self.t_k {
            (self.a * (t - self.t_k), self.a)
        } else {
            (0.0, 0.0)
        }
    }
    /// The exact position at t.
    fn x(&self, t: f64) -> f64 {
        let disc = (self.c * self.c - 4.0 * self.m * self.k).sqrt();
        let (r1, r2) = (
            (-self.c - disc) / (2.0 * self.m),
            (-self.c + disc) / (2.0 * self.m),
        );
        let tau = (t - self.t_k).max(0.0);
        self.s(t).0 - self.a * ((r1 * tau).exp() - (r2 * tau).exp()) / (r1 - r2)
    }
}

impl DaeProblem for KinkedRamp {
    fn size(&self) -> usize {
        2
    }
    fn residual(&self, t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) {
        let (s, ds) = self.s(t);
        r[0] = yp[0] - y[1];
        r[1] = self.m * yp[1] - self.k * (s - y[0]) - self.c * (ds - y[1]);
    }
    fn jacobian(&self, _t: f64, _y: &[f64], _yp: &[f64], cj: f64, j: &mut JacobianSink) -> bool {
        j.add(0, 1, -1.0);
        j.add(1, 0, self.k);
        j.add(1, 1, self.c);
        j.add_scaled(0, 0, cj, 1.0);
        j.add_scaled(1, 1, cj, self.m);
        true
    }
}

#[test]
fn a_stiff_component_crosses_a_kink_in_its_forcing_to_the_closed_form() {
    // The step falls below the fast component's time constant at the kink and grows
    // again after it; the answer is the closed form's to the tolerance.
    let p = KinkedRamp {
        m: 1.0,
        c: 1e6,
        k: 1e6,
        a: 1.0,
        t_k: 0.3,
    };
    let opts = radau(1e-6, 1e-10);
    let end = solve_to(&p, 0.0, &[0.0, 0.0], &[0.0, 0.0], 1.0, &opts).unwrap();
    let exact = p.x(1.0);
    assert!(
        (end.y[0] - exact).abs() < 1e-5 * exact,
        "{} against {exact}",
        end.y[0]
    );
    assert!(end.stats.error_test_failures > 0, "{:?}", end.stats);
}
