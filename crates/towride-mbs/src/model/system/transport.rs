//! Frame transport of a re-used iteration matrix for the wheels.
//!
//! A wheel's angular velocity and moment balance are written in its body axes, and its
//! orientation is a quaternion; the wheel spins about its axle at 40-50 rad/s, so over the
//! few steps an iteration matrix is re-used, the rows and columns of those unknowns turn
//! by half a radian with the wheel. Newton with such a matrix converges slowly or not at
//! all on the bearing rows (measured: most of the default scene's matrix rebuilds after a
//! convergence failure, and the fixed-coefficient BDF accepting steps whose bearing
//! velocity constraints grow from step to step).
//!
//! Everything that loads a wheel (bearing, tyre, drive torque) and its inertia are
//! symmetric about the axle, so the matrix at the current spin angle is the old one seen
//! through the spin e = p_built^* p_now: J(now) = D_r J(built) D_c^T with D_c taking
//! quaternion columns to dp (x) e and angular-velocity columns to dR^T domega, D_r acting
//! alike on the kinematic rows (r (x) e) and the moment rows (dR^T r), dR = R(e).

use super::System;
use crate::model::math::{mtv, mv, qmul, rot};
use towride_solver::problem::Transport;

impl System {
    /// The bodies whose frames the transport follows: the wheels that carry a tyre
    /// (rigid, so that their block is the 7 + 6 of a rigid body).
    pub(super) fn spinning_bodies(&self) -> Vec<usize> {
        let mut out: Vec<usize> = self
            .model
            .tyres
            .iter()
            .filter_map(|t| self.body_of(t.marker))
            .filter(|&b| self.nm[b] == 0)
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// See [`towride_solver::problem::DaeProblem::transport`].
    pub(super) fn transport_frames(
        &self,
        built: &[f64],
        now: &[f64],
        v: &mut [f64],
        side: Transport,
    ) {
        let ov = self.nq;
        for &b in &self.spinning {
            let o = self.qo[b];
            let pb = [built[o + 3], built[o + 4], built[o + 5], built[o + 6]];
            let pn = [now[o + 3], now[o + 4], now[o + 5], now[o + 6]];
            let mut e = qmul(&[pb[0], -pb[1], -pb[2], -pb[3]], &pn);
            let n = e.iter().map(|x| x * x).sum::<f64>().sqrt();
            if n.is_nan() || n <= 0.0 {
                continue;
            }
            e.iter_mut().for_each(|x| *x /= n);
            let dr = rot(&e);
            let kin = [v[o + 3], v[o + 4], v[o + 5], v[o + 6]];
            let w = ov + self.vo[b] + 3;
            let ang = [v[w], v[w + 1], v[w + 2]];
            let (kin, ang) = match side {
                // D_r^T: kinematic rows r (x) e^*, moment rows dR r.
                Transport::Rows => (qmul(&kin, &[e[0], -e[1], -e[2], -e[3]]), mv(&dr, &ang)),
                // D_c: quaternion columns dp (x) e, angular velocity dR^T domega.
                Transport::Columns => (qmul(&kin, &e), mtv(&dr, &ang)),
            };
            v[o + 3..o + 7].copy_from_slice(&kin);
            v[w..w + 3].copy_from_slice(&ang);
        }
    }
}
