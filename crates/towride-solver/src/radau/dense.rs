//! Dense output: the collocation polynomial of the last step (RADAU5's CONT and CONTR5),
//! the cubic through y0 and the three stage values, in Newton form on the nodes
//! s = 0, c2 - 1, c1 - 1 (and -1) of s = (t - t_new)/h.

use super::tableau::{C1, C2};

/// Stores the polynomial of the step that ended at `y` with stage increments `z`.
pub(super) fn update(cont: &mut [Vec<f64>; 4], y: &[f64], z: &[Vec<f64>; 3]) {
    let (c1m1, c2m1) = (C1 - 1.0, C2 - 1.0);
    let c1mc2 = C1 - C2;
    for i in 0..y.len() {
        let (z1, z2, z3) = (z[0][i], z[1][i], z[2][i]);
        cont[0][i] = y[i];
        cont[1][i] = (z2 - z3) / c2m1;
        let ak = (z1 - z2) / c1mc2;
        let acont3 = (ak - z1 / C1) / C2;
        cont[2][i] = (ak - cont[1][i]) / c1m1;
        cont[3][i] = cont[2][i] - acont3;
    }
}

/// Value and time derivative at `t` of the polynomial of the step of size `h` that
/// ended at `t_new`.
pub(super) fn eval(
    cont: &[Vec<f64>; 4],
    t_new: f64,
    h: f64,
    t: f64,
    y: &mut [f64],
    yp: &mut [f64],
) {
    let (c1m1, c2m1) = (C1 - 1.0, C2 - 1.0);
    let s = (t - t_new) / h;
    let (a, b) = (s - c2m1, s - c1m1);
    for i in 0..y.len() {
        let (k1, k2, k3) = (cont[1][i], cont[2][i], cont[3][i]);
        let inner = k2 + b * k3;
        y[i] = cont[0][i] + s * (k1 + a * inner);
        // d/ds of s (k1 + (s - c2m1)(k2 + (s - c1m1) k3)).
        let ds = k1 + a * inner + s * (inner + a * k3);
        yp[i] = ds / h;
    }
}
