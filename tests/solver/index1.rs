//! An index-1 DAE with an analytical solution: consistent initial values from a wrong
//! guess, then integration, both against the closed form.

use towride_solver::{consistent_index1, solve_to, DaeProblem, SolverOptions, VarKind};

/// y1' = -y1 + y2, 0 = y2 - 2 y1 - 1  =>  y1' = y1 + 1, y1 = (y1(0) + 1) e^t - 1.
struct Linear;

impl DaeProblem for Linear {
    fn size(&self) -> usize {
        2
    }
    fn residual(&self, _t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) {
        r[0] = yp[0] + y[0] - y[1];
        r[1] = y[1] - 2.0 * y[0] - 1.0;
    }
    fn var_kinds(&self) -> Vec<VarKind> {
        vec![VarKind::Differential, VarKind::Algebraic1]
    }
}

#[test]
fn consistent_initial_values_then_closed_form() {
    let opts = SolverOptions::with_tol(1e-10, 1e-10);
    let (mut y, mut yp) = (vec![1.0, 0.0], vec![0.0, 0.0]);
    consistent_index1(&Linear, 0.0, &mut y, &mut yp, &opts).unwrap();
    assert!((y[0] - 1.0).abs() < 1e-14, "differential unknown kept");
    assert!(
        (y[1] - 3.0).abs() < 1e-9 && (yp[0] - 2.0).abs() < 1e-9,
        "{y:?} {yp:?}"
    );
    let end = solve_to(&Linear, 0.0, &y, &yp, 1.0, &opts).unwrap();
    let exact = 2.0 * 1f64.exp() - 1.0;
    assert!(
        (end.y[0] - exact).abs() < 1e-8 * exact,
        "{} vs {exact}",
        end.y[0]
    );
    assert!(
        (end.y[1] - (2.0 * exact + 1.0)).abs() < 1e-7,
        "{}",
        end.y[1]
    );
}
