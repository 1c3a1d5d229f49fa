//! The `full` coupling level: the floating-frame equations of a modal body without
//! truncation (Shabana, Dynamics of Multibody Systems, 4th ed., ch. 5; Wallrapp's SID).
//!
//! A material point at undeformed position s (body axes, from the undeformed centre of
//! mass, the body's reference point) sits at rho = s + Phi eta and moves with
//! x' = u + A (omega x rho + Phi zeta), u = r' in world axes, omega in body axes. Virtual
//! power int rho dx'^T x'' = dW gives, with S = int rho rho (first moment),
//! J = int rho ~rho^T ~rho, R_k = int rho rho phi_k^T and V = Phi zeta:
//!
//! ```text
//! m u' + A (-~S omega' + I3 zeta') + A (omega x (omega x S) + 2 omega x I3 zeta)  = F
//! ~S A^T u' + J omega' + W zeta' + omega x J omega + 2 (omega tr C - C^T omega)  = T
//! I3^T A^T u' + W^T omega' + I6 zeta' + h_k + K eta + D zeta                    = Q
//! W_k = axial(R_k) = I4_k + I5_k eta,  C = sum_k zeta_k R_k,
//! h_k = omega^T R_k omega - |omega|^2 tr R_k + 2 omega . sum_l zeta_l I5_lk
//! ```
//!
//! The velocity terms are exactly those of the state-dependent mass matrix (derived from
//! the same kinetic energy), so kinetic plus strain energy and angular momentum are
//! conserved by the exact solution; gravity adds S x A^T g and I3 . A^T g.
//!
//! The tensors come from the invariants, in projection form: P_k = int rho s phi_k^T
//! and Q_jk = int rho phi_j phi_k^T are recovered exactly from I8 and I9
//! (I8_k = tr(P_k) 1 - P_k^T, I9_jk = Q_jk^T - tr(Q_jk) 1), then shifted from the FE
//! origin to the centre of mass with I3. Computed once per body at assembly.

use nalgebra::{DMatrix, Matrix3, Vector3};

use super::System;
use crate::model::desc::{Body, Coupling};
use crate::model::math::rot;

/// Per modal body at the `full` level: the tensors of the mass matrix about the CM.
#[derive(Clone, Debug)]
pub struct FullTensors {
    /// First moment of the undeformed body about its CM (zero up to rounding).
    s0: Vector3<f64>,
    /// I3_k = int rho phi_k.
    i3: Vec<Vector3<f64>>,
    /// P_k = int rho s phi_k^T, s from the CM.
    p: Vec<Matrix3<f64>>,
    /// Q_jk = int rho phi_j phi_k^T.
    q: Vec<Vec<Matrix3<f64>>>,
    /// Generalised modal mass I6 (identity for orthonormal modes).
    i6: DMatrix<f64>,
    mass: f64,
    j0: Matrix3<f64>,
}

/// The deformation-dependent quantities at one eta.
struct Deformed {
    s: Vector3<f64>,
    j: Matrix3<f64>,
    /// R_k = P_k + sum_j eta_j Q_jk.
    r: Vec<Matrix3<f64>>,
    /// W_k = axial(R_k): the rotation-modal coupling columns.
    w: Vec<Vector3<f64>>,
}

fn m3(a: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|r, c| a[r][c])
}

/// axial(A) for A = int rho a b^T: int rho a x b.
fn axial(a: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        a[(1, 2)] - a[(2, 1)],
        a[(2, 0)] - a[(0, 2)],
        a[(0, 1)] - a[(1, 0)],
    )
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    v.cross_matrix()
}

impl FullTensors {
    /// The tensors of `body` if it is a modal body at the `full` level.
    pub fn of(body: &Body) -> Option<FullTensors> {
        let m = body.modal.as_ref()?;
        if m.coupling != Coupling::Full {
            return None;
        }
        let inv = &m.data.invariants;
        let n = inv.i3.len();
        let c = Vector3::from(inv.centre_of_mass());
        let eye = Matrix3::identity();
        let i3: Vec<Vector3<f64>> = inv.i3.iter().map(|v| Vector3::from(*v)).collect();
        let p = (0..n)
            .map(|k| {
                let i8 = m3(&inv.i8[k]);
                let p0 = eye * (0.5 * i8.trace()) - i8.transpose();
                p0 - c * i3[k].transpose()
            })
            .collect();
        let q = (0..n)
            .map(|j| {
                (0..n)
                    .map(|k| {
                        let i9 = m3(&inv.i9[j][k]);
                        i9.transpose() - eye * (0.5 * i9.trace())
                    })
                    .collect()
            })
            .collect();
        Some(FullTensors {
            s0: Vector3::from(inv.i2) - c * inv.i1,
            i3,
            p,
            q,
            i6: DMatrix::from_fn(n, n, |j, k| inv.i6[j][k]),
            mass: body.mass,
            j0: m3(&body.inertia),
        })
    }

    fn deformed(&self, eta: &[f64]) -> Deformed {
        let n = eta.len();
        let mut s = self.s0;
        let mut de = Matrix3::zeros();
        let mut r = Vec::with_capacity(n);
        for k in 0..n {
            s += self.i3[k] * eta[k];
            let mut rk = self.p[k];
            for (j, e) in eta.iter().enumerate() {
                rk += self.q[j][k] * *e;
            }
            de += (rk + self.p[k].transpose()) * eta[k];
            r.push(rk);
        }
        let j = self.j0 + Matrix3::identity() * de.trace() - de;
        let w = r.iter().map(axial).collect();
        Deformed { s, j, r, w }
    }

    /// The body's velocity-space mass block (u world, omega body, zeta) at eta, for
    /// orientation `a` (body to world).
    fn mass(&self, a: &Matrix3<f64>, eta: &[f64]) -> DMatrix<f64> {
        let n = eta.len();
        let d = self.deformed(eta);
        let mut m = DMatrix::zeros(6 + n, 6 + n);
        let aus = -(a * skew(&d.s));
        for r in 0..3 {
            m[(r, r)] = self.mass;
            for c in 0..3 {
                m[(r, 3 + c)] = aus[(r, c)];
                m[(3 + c, r)] = aus[(r, c)];
                m[(3 + r, 3 + c)] = d.j[(r, c)];
            }
        }
        for k in 0..n {
            let ai3 = a * self.i3[k];
            for r in 0..3 {
                m[(r, 6 + k)] = ai3[r];
                m[(6 + k, r)] = ai3[r];
                m[(3 + r, 6 + k)] = d.w[k][r];
                m[(6 + k, 3 + r)] = d.w[k][r];
            }
            for l in 0..n {
                m[(6 + k, 6 + l)] = self.i6[(k, l)];
            }
        }
        m
    }

    /// Quadratic-velocity and gravity terms on the left-hand side (u world, omega body,
    /// zeta rows): h(q, v) - (0, S x A^T g, I3^T A^T g).
    fn velocity_terms(
        &self,
        a: &Matrix3<f64>,
        eta: &[f64],
        om: &Vector3<f64>,
        zeta: &[f64],
        g: &Vector3<f64>,
    ) -> Vec<f64> {
        let n = eta.len();
        let d = self.deformed(eta);
        let mut i3z = Vector3::zeros();
        let mut c = Matrix3::zeros();
        for k in 0..n {
            i3z += self.i3[k] * zeta[k];
            c += d.r[k] * zeta[k];
        }
        let gb = a.transpose() * g;
        let hu = a * (om.cross(&om.cross(&d.s)) + 2.0 * om.cross(&i3z));
        let hw =
            om.cross(&(d.j * om)) + 2.0 * (om * c.trace() - c.transpose() * om) - d.s.cross(&gb);
        let mut out = vec![0.0; 6 + n];
        for r in 0..3 {
            out[r] = hu[r];
            out[3 + r] = hw[r];
        }
        let w2 = om.norm_squared();
        for k in 0..n {
            let mut vk = Matrix3::zeros();
            for (l, z) in zeta.iter().enumerate() {
                vk += self.q[l][k] * *z;
            }
            out[6 + k] = om.dot(&(d.r[k] * om)) - w2 * d.r[k].trace() + 2.0 * om.dot(&axial(&vk))
                - self.i3[k].dot(&gb);
        }
        out
    }
}

impl System {
    fn full_parts<'a>(
        &'a self,
        k: usize,
        q: &'a [f64],
    ) -> (&'a FullTensors, Matrix3<f64>, &'a [f64]) {
        let t = self.full[k].as_ref().expect("a full-coupling body");
        let o = self.qo[k];
        let a = m3(&rot(&[q[o + 3], q[o + 4], q[o + 5], q[o + 6]]));
        (t, a, &q[o + 7..o + 7 + self.nm[k]])
    }

    /// The velocity-space mass block of body `k` at `q` when it is a `full` modal body.
    pub(super) fn full_mass(&self, k: usize, q: &[f64]) -> Option<DMatrix<f64>> {
        self.full[k].as_ref()?;
        let (t, a, eta) = self.full_parts(k, q);
        Some(t.mass(&a, eta))
    }

    /// Left-hand quadratic-velocity and gravity-coupling terms of a `full` body.
    pub(super) fn full_velocity_terms(&self, k: usize, q: &[f64], v: &[f64]) -> Vec<f64> {
        let (t, a, eta) = self.full_parts(k, q);
        let w = self.vo[k];
        let om = Vector3::new(v[w + 3], v[w + 4], v[w + 5]);
        let zeta = &v[w + 6..w + 6 + self.nm[k]];
        t.velocity_terms(&a, eta, &om, zeta, &Vector3::from(self.model.gravity))
    }
}
