//! Markers on modal bodies: their world frame and its velocity Jacobian.
//!
//! A marker attached to modal node n of body b sits at s = s0 + Phi_t eta (body axes,
//! relative to the undeformed centre of mass) and is turned by the node rotation
//! theta = Phi_r eta. The rotation is parametrised by the unnormalised quaternion
//! (1, theta/2) (a Cayley map: exactly orthogonal, equal to exp(theta) to second order),
//! so joint rows built on the marker axes stay exact at any deflection.
//!
//! The velocity Jacobian maps the body's velocity unknowns (u, omega_body, zeta) to the
//! marker origin velocity and the marker angular velocity, both in world axes. Constraint
//! rows and generalised forces of elements on such markers follow from it by the chain
//! rule (see `constraint.rs` and `forces.rs`).

use super::System;
use crate::model::desc::MarkerHandle;
use crate::model::math::{cross, mm, mv, qmat, rot};

/// World frame of a marker with its velocity Jacobian.
pub struct FlexFrame {
    pub origin: [f64; 3],
    /// Axes as columns, world.
    pub axes: [[f64; 3]; 3],
    /// Per velocity unknown of the body (6 + modes): d origin / d v (world).
    pub jt: Vec<[f64; 3]>,
    /// Per velocity unknown: d omega_marker / d v (world).
    pub jw: Vec<[f64; 3]>,
}

impl FlexFrame {
    /// Velocity of the origin and angular velocity (world) for body velocities `vb`.
    pub fn rates(&self, vb: &[f64]) -> ([f64; 3], [f64; 3]) {
        let mut vo = [0.0; 3];
        let mut w = [0.0; 3];
        for (k, x) in vb.iter().enumerate() {
            for c in 0..3 {
                vo[c] += self.jt[k][c] * x;
                w[c] += self.jw[k][c] * x;
            }
        }
        (vo, w)
    }

    /// Generalised force on the body's velocity unknowns of a force f (world) at the
    /// origin and a torque tq (world): J^T (f, tq).
    pub fn generalised(&self, f: &[f64; 3], tq: &[f64; 3]) -> Vec<f64> {
        self.jt
            .iter()
            .zip(&self.jw)
            .map(|(a, b)| {
                a[0] * f[0] + a[1] * f[1] + a[2] * f[2] + b[0] * tq[0] + b[1] * tq[1] + b[2] * tq[2]
            })
            .collect()
    }
}

impl System {
    /// True when marker `k` moves with a modal body's deformation.
    pub fn is_flex_marker(&self, k: MarkerHandle) -> bool {
        self.model.markers[k].node.is_some()
    }

    /// World frame and velocity Jacobian of marker `k` (on a body) at positions `q`.
    /// Works for rigid markers too (no modal columns).
    pub fn flex_frame(&self, q: &[f64], k: MarkerHandle) -> FlexFrame {
        let mk = &self.model.markers[k];
        let b = self.body_of(k).expect("marker on a body");
        let o = self.qo[b];
        let nm = self.nm[b];
        let p = [q[o + 3], q[o + 4], q[o + 5], q[o + 6]];
        let a = rot(&p);
        let mut s = mk.position;
        let mut rn = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        // G maps theta' to the node's angular velocity in body axes.
        let mut g_rot = rn;
        let shapes: &[[f64; 6]] = match (mk.node, &self.model.bodies[b].modal) {
            (Some(n), Some(m)) => &m.data.nodes[n].shapes,
            _ => &[],
        };
        if !shapes.is_empty() {
            let eta = &q[o + 7..o + 7 + nm];
            let mut th = [0.0; 3];
            for (j, sh) in shapes.iter().enumerate() {
                for c in 0..3 {
                    s[c] += sh[c] * eta[j];
                    th[c] += sh[3 + c] * eta[j];
                }
            }
            let pn = [1.0, 0.5 * th[0], 0.5 * th[1], 0.5 * th[2]];
            let n2 = pn.iter().map(|x| x * x).sum::<f64>();
            rn = rot(&pn);
            // omega_node (node axes) = Qv(pn)^T theta' / |pn|^2; in body axes: Rn times it.
            let qm = qmat(&pn);
            let mut gl = [[0.0; 3]; 3];
            for r in 0..3 {
                for c in 0..3 {
                    gl[r][c] = qm[c + 1][r] / n2;
                }
            }
            g_rot = mm(&rn, &gl);
        }
        let origin_b = mv(&a, &s);
        let origin = [
            q[o] + origin_b[0],
            q[o + 1] + origin_b[1],
            q[o + 2] + origin_b[2],
        ];
        let axes = mm(&a, &mm(&rn, &mk.axes));
        let mut jt = Vec::with_capacity(6 + nm);
        let mut jw = Vec::with_capacity(6 + nm);
        for c in 0..3 {
            let mut e = [0.0; 3];
            e[c] = 1.0;
            jt.push(e);
            jw.push([0.0; 3]);
        }
        for c in 0..3 {
            let mut e = [0.0; 3];
            e[c] = 1.0;
            jt.push(mv(&a, &cross(&e, &s)));
            jw.push(mv(&a, &e));
        }
        for j in 0..nm {
            if shapes.is_empty() {
                jt.push([0.0; 3]);
                jw.push([0.0; 3]);
                continue;
            }
            let sh = shapes[j];
            jt.push(mv(&a, &[sh[0], sh[1], sh[2]]));
            jw.push(mv(&a, &mv(&g_rot, &[sh[3], sh[4], sh[5]])));
        }
        FlexFrame {
            origin,
            axes,
            jt,
            jw,
        }
    }
}
