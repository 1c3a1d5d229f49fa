//! Elastic loads of modal bodies.
//!
//! With unit modal mass the modal equations are zeta' + 2 xi_j w_j zeta_j + w_j^2 eta_j =
//! Q_j. Because the kept modes are mass-orthogonal to the six rigid-body modes, the
//! invariants I3 (translation coupling) and I4 (rotation coupling) vanish, so at eta = 0
//! the mass matrix is block diagonal: that is the `constant` coupling level. The
//! `partial` level adds the centrifugal load of the frame's rotation on the modes,
//! Q_j = -int rho phi_j . (omega x (omega x s)) dV = omega^T I8_j omega (body axes), the
//! only coupling term that does not vanish at eta = 0. Terms of first order in eta (the
//! deformation-dependent inertia, Coriolis coupling through I5) are left out at both
//! levels: for the hitch they are below 1e-6 of the elastic forces (docs/flex.md). The
//! `full` level keeps them all (`full.rs`): its quadratic-velocity terms are added here.

use super::System;
use crate::model::desc::{Coupling, Modal};

impl System {
    /// Adds the modal stiffness, damping and coupling loads of body `k` to `f`.
    pub(super) fn modal_loads(&self, k: usize, m: &Modal, q: &[f64], v: &[f64], f: &mut [f64]) {
        let (o, w) = (self.qo[k], self.vo[k]);
        let om = [v[w + 3], v[w + 4], v[w + 5]];
        for (j, mode) in m.data.modes.iter().enumerate() {
            let eta = q[o + 7 + j];
            let zeta = v[w + 6 + j];
            let wn = mode.stiffness.max(0.0).sqrt();
            let mut load = -mode.stiffness * eta - 2.0 * mode.damping_ratio * wn * zeta;
            if m.coupling == Coupling::Partial {
                let i8 = &m.data.invariants.i8[j];
                for a in 0..3 {
                    for b in 0..3 {
                        load += om[a] * i8[a][b] * om[b];
                    }
                }
            }
            f[w + 6 + j] += load;
        }
        if m.coupling == Coupling::Full {
            for (r, h) in self.full_velocity_terms(k, q, v).iter().enumerate() {
                f[w + r] -= h;
            }
        }
    }

    /// Strain energy of modal body `k`: sum of w_j^2 eta_j^2 / 2 [J], and per mode.
    pub fn strain_energy(&self, k: usize, q: &[f64]) -> (f64, Vec<f64>) {
        let Some(m) = &self.model.bodies[k].modal else {
            return (0.0, Vec::new());
        };
        let o = self.qo[k];
        let per: Vec<f64> = m
            .data
            .modes
            .iter()
            .enumerate()
            .map(|(j, mode)| 0.5 * mode.stiffness * q[o + 7 + j].powi(2))
            .collect();
        (per.iter().sum(), per)
    }
}
