//! The index-3 benchmarks written as [`MechanicalDae`]s, so the solver can integrate their
//! stabilised index-2 (GGL) form; results are mapped back to the test set's components.

use super::andrews::{Andrews, Trig};
use super::caraxis::CarAxis;
use crate::{Ggl, MechanicalDae};

impl MechanicalDae for CarAxis {
    fn n_pos(&self) -> usize {
        4
    }
    fn n_con(&self) -> usize {
        2
    }
    fn dynamics(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        vdot: &[f64],
        lambda: &[f64],
        out: &mut [f64],
    ) {
        let y: Vec<f64> = [q, v, lambda].concat();
        let mut f = [0.0; 10];
        self.rhs(t, &y, &mut f);
        let k = self.k();
        for i in 0..4 {
            out[i] = k * vdot[i] - f[4 + i];
        }
    }
    fn constraints(&self, t: f64, q: &[f64], out: &mut [f64]) {
        let (xb, yb) = self.road(t);
        out[0] = xb * q[0] + yb * q[1];
        out[1] = (q[0] - q[2]).powi(2) + (q[1] - q[3]).powi(2) - self.l * self.l;
    }
    fn constraint_jacobian(&self, t: f64, q: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        let (xb, yb) = self.road(t);
        let (dx, dy) = (q[0] - q[2], q[1] - q[3]);
        out.extend([
            (0, 0, xb),
            (0, 1, yb),
            (1, 0, 2.0 * dx),
            (1, 1, 2.0 * dy),
            (1, 2, -2.0 * dx),
            (1, 3, -2.0 * dy),
        ]);
    }
    fn constraint_time_derivative(&self, t: f64, q: &[f64], out: &mut [f64]) {
        let (xb, yb) = self.road(t);
        let ybd = self.r * self.w * (self.w * t).cos();
        let xbd = -yb * ybd / xb;
        out[0] = xbd * q[0] + ybd * q[1];
        out[1] = 0.0;
    }
    fn pos_name(&self, i: usize) -> String {
        ["xl", "yl", "xr", "yr"][i].to_string()
    }
}

impl MechanicalDae for Andrews {
    fn n_pos(&self) -> usize {
        7
    }
    fn n_con(&self) -> usize {
        6
    }
    fn dynamics(
        &self,
        _t: f64,
        q: &[f64],
        v: &[f64],
        vdot: &[f64],
        lambda: &[f64],
        out: &mut [f64],
    ) {
        out.copy_from_slice(&self.equations_of_motion(&Trig::new(q), v, vdot, lambda));
    }
    fn constraints(&self, _t: f64, q: &[f64], out: &mut [f64]) {
        out.copy_from_slice(&self.constraints(&Trig::new(q)));
    }
    fn constraint_jacobian(&self, _t: f64, q: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        let gp = self.gp(&Trig::new(q));
        for (k, row) in gp.iter().enumerate() {
            for (c, &v) in row.iter().enumerate() {
                if v != 0.0 || Andrews::gp_nonzero(k, c) {
                    out.push((k, c, v));
                }
            }
        }
    }
    fn pos_name(&self, i: usize) -> String {
        ["beta", "theta", "gamma", "phi", "delta", "omega", "epsilon"][i].to_string()
    }
}

/// GGL state of the car axis from the test set's y0, y'0 (positions, velocities, v', lambda).
pub fn caraxis_ggl(y0: &[f64], yp0: &[f64]) -> (Ggl<CarAxis>, Vec<f64>, Vec<f64>) {
    let g = Ggl::new(CarAxis::default());
    let (y, yp) = g.state(&y0[0..4], &y0[4..8], &yp0[4..8], &y0[8..10]);
    (g, y, yp)
}

/// Test-set components of the car axis from a GGL solution: (q, v, lambda).
pub fn caraxis_from_ggl(y: &[f64], _yp: &[f64]) -> Vec<f64> {
    [&y[0..8], &y[8..10]].concat()
}

/// GGL state of Andrews' mechanism from the test set's y0 (q, v, w = v', lambda).
pub fn andrews_ggl(y0: &[f64], _yp0: &[f64]) -> (Ggl<Andrews>, Vec<f64>, Vec<f64>) {
    let g = Ggl::new(Andrews::default());
    let (y, yp) = g.state(&y0[0..7], &y0[7..14], &y0[14..21], &y0[21..27]);
    (g, y, yp)
}

/// Test-set components of Andrews from a GGL solution: q, v, w = v' (from the
/// interpolating polynomial's derivative), lambda.
pub fn andrews_from_ggl(y: &[f64], yp: &[f64]) -> Vec<f64> {
    [&y[0..7], &y[7..14], &yp[7..14], &y[14..20]].concat()
}
