//! Constraint rows with their derivatives.
//!
//! Each row is a dot product of the two marker frames' origins and axes (`joint.rs`), so
//! its gradient with respect to a small motion of either frame (origin displacement and
//! rotation, world axes) has a closed form ([`row_grad`]). A rigid side maps that to its
//! body's virtual translation and body-axes rotation; a marker on a modal body maps it to
//! all the body's unknowns (modal ones included) with the marker's velocity Jacobian
//! ([`super::flexmarker`]). Written generic over the scalar, the same code in dual numbers
//! over the positions gives the Newton matrix's d B / d q for rigid elements. For elements
//! on modal markers d B / d q is left out of the iteration matrix (it only speeds up Newton
//! by the geometric stiffness of the reaction, small against the body's own stiffness) and
//! the constraint acceleration term is differentiated numerically along the motion.

use super::{ConElem, ConRow, ConstraintSet, Owner, System};
use crate::model::desc::{MarkerHandle, MotionDof};
use crate::model::dual::{Dual, Scalar};
use crate::model::joint::{motion_value, row_value, MFrame, Row};
use crate::model::math::{
    add, col, cross, cst3, cst33, dot, mm, mtv, mvc, qmul, rot, sub, M3, Q4, V3,
};

/// One direction inside one direction: the constraint acceleration term.
type G1 = Dual<f64, 1>;
type G2 = Dual<G1, 1>;

/// Constraint rows of one element with their first derivatives.
#[derive(Default)]
pub struct ConEval {
    /// Constraint values g, one per row [m or rad].
    pub g: Vec<f64>,
    /// d g / d(v_a, v_b), row-major: per row the velocity unknowns of side a, then of
    /// side b (see [`ConEval::at`]).
    pub b: Vec<f64>,
    /// Partial time derivative dg/dt per row (non-zero for prescribed motions).
    pub gt: Vec<f64>,
    /// Number of velocity unknowns of each side (6 + modes; 6 for ground).
    pub w: [usize; 2],
}

impl ConEval {
    /// Entry of row r for velocity unknown c of `side`.
    pub fn at(&self, r: usize, side: usize, c: usize) -> f64 {
        self.b[r * (self.w[0] + self.w[1]) + side * self.w[0] + c]
    }
}

/// How a small motion of one side's marker frame (origin displacement and rotation,
/// world axes) maps to that side's velocity unknowns.
enum SideMap {
    Ground,
    /// Rigid body: virtual translation (world) and rotation (body axes) with the body's
    /// rotation matrix and the marker origin relative to the centre of mass (world).
    Rigid {
        a: [[f64; 3]; 3],
        rho: [f64; 3],
    },
    /// Marker on a modal body: its velocity Jacobian.
    Flex(super::flexmarker::FlexFrame),
}

/// Value, time derivative and gradients of one row with respect to each side's frame
/// motion: origin displacement (`go`) and small rotation of the axes (`gphi`), world.
struct RowGrad<S: Scalar> {
    g: S,
    gt: S,
    go: [V3<S>; 2],
    gphi: [V3<S>; 2],
}

/// Rows of the joint primitives (`joint.rs`) and motions with their exact gradients: for
/// d = o_I - o_J and axis columns u of I and w of J, d . w varies by
/// (d o_I - d o_J) . w + d phi_J . (w x d), and u . w by d phi_I . (u x w) +
/// d phi_J . (w x u). Generic: in f64 for the residual, in duals over the positions for
/// the Newton matrix's d B / d q.
fn row_grad<S: Scalar>(row: ConRow, drive: (S, S), fi: &MFrame<S>, fj: &MFrame<S>) -> RowGrad<S> {
    let z = [S::cst(0.0); 3];
    let d = sub(&fi.origin, &fj.origin);
    let along = |k: usize| {
        let w = col(&fj.axes, k);
        RowGrad {
            g: dot(&d, &w),
            gt: S::cst(0.0),
            go: [w, w.map(|x| -x)],
            gphi: [z, cross(&w, &d)],
        }
    };
    let about = |ki: usize, kj: usize, sign: f64| {
        let (u, w) = (col(&fi.axes, ki), col(&fj.axes, kj));
        let uw = cross(&u, &w);
        RowGrad {
            g: dot(&u, &w) * sign,
            gt: S::cst(0.0),
            go: [z, z],
            gphi: [uw.map(|x| x * sign), uw.map(|x| x * -sign)],
        }
    };
    match row {
        ConRow::Prim(Row::AlongX) => along(0),
        ConRow::Prim(Row::AlongY) => along(1),
        ConRow::Prim(Row::AlongZ) => along(2),
        ConRow::Prim(Row::AboutX) => about(2, 1, 1.0),
        ConRow::Prim(Row::AboutY) => about(2, 0, -1.0),
        ConRow::Prim(Row::AboutZ) => about(0, 1, 1.0),
        ConRow::Prim(Row::Perpendicular) => about(2, 2, 1.0),
        ConRow::Drive(MotionDof::Translation) => {
            let mut r = along(2);
            r.g = r.g - drive.0;
            r.gt = -drive.1;
            r
        }
        ConRow::Drive(MotionDof::Rotation) => {
            // (x_I . y_J) cos s - (x_I . x_J) sin s
            let (c, sn) = (drive.0.cos(), drive.0.sin());
            let (a, b) = (about(0, 1, 1.0), about(0, 0, 1.0));
            let mix = |p: V3<S>, q: V3<S>| std::array::from_fn(|k| c * p[k] - sn * q[k]);
            RowGrad {
                g: a.g * c - b.g * sn,
                gt: -drive.1 * (a.g * sn + b.g * c),
                go: [z, z],
                gphi: [mix(a.gphi[0], b.gphi[0]), mix(a.gphi[1], b.gphi[1])],
            }
        }
    }
}

/// A rigid side's row of B: d o = d r + d phi x rho, d phi = A d theta (body axes), so
/// (go, A^T (rho x go + gphi)).
fn rigid_b<S: Scalar>(a: &M3<S>, rho: &V3<S>, go: &V3<S>, gphi: &V3<S>) -> [S; 6] {
    let m = add(&cross(rho, go), gphi);
    let w = mtv(a, &m);
    [go[0], go[1], go[2], w[0], w[1], w[2]]
}

/// Constraint rows with second derivatives (iteration matrix, accelerations).
pub struct ConEval2 {
    /// The rows with their first derivatives.
    pub first: ConEval,
    /// d g / d(q_a, q_b): per row, the position unknowns of side a (7 + modes) then b.
    pub gq: Vec<Vec<f64>>,
    /// Rigid elements only: d B_k / d(q_a, q_b, t): [row][k][l], k < 13 (12 = g_t),
    /// l < 15 (14 = t).
    pub dbq: Option<Vec<[[f64; 15]; 13]>>,
}

impl System {
    fn rows_of<T: Scalar>(&self, e: &ConElem, t: T, fi: &MFrame<T>, fj: &MFrame<T>) -> Vec<T> {
        e.rows
            .iter()
            .map(|r| match r {
                ConRow::Prim(p) => row_value(*p, fi, fj),
                ConRow::Drive(d) => motion_value(*d, self.drive_rates(e, t).0, fi, fj),
            })
            .collect()
    }

    /// Marker frame from a body pose in any scalar (rigid markers).
    pub(super) fn frame_of<T: Scalar>(&self, k: MarkerHandle, r: &V3<T>, p: &Q4<T>) -> MFrame<T> {
        self.rigid_frame(k, r, p).0
    }

    /// [`System::frame_of`] with the body's rotation matrix A and the marker origin
    /// relative to the centre of mass, A s (world): what maps a frame motion to the
    /// body's virtual translation and rotation ([`rigid_b`]).
    fn rigid_frame<T: Scalar>(
        &self,
        k: MarkerHandle,
        r: &V3<T>,
        p: &Q4<T>,
    ) -> (MFrame<T>, M3<T>, V3<T>) {
        let mk = &self.model.markers[k];
        let a = rot(p);
        let rho = mvc(&a, &mk.position);
        let f = MFrame {
            origin: add(r, &rho),
            axes: mm(&a, &cst33(&mk.axes)),
        };
        (f, a, rho)
    }

    pub(super) fn ground_frame<T: Scalar>(&self, k: MarkerHandle) -> MFrame<T> {
        let mk = &self.model.markers[k];
        MFrame {
            origin: cst3(&mk.position),
            axes: cst33(&mk.axes),
        }
    }

    /// True when a side of `e` is a modal body (its rows take the chain-rule path).
    pub(super) fn has_flex(&self, e: &ConElem) -> bool {
        self.bodies_of(e.mi, e.mj)
            .iter()
            .any(|b| b.is_some_and(|b| self.nm[b] > 0))
    }

    /// Constraint rows of element `e` with B and g_t (all rows, kept or not).
    pub fn con_eval(&self, e: &ConElem, t: f64, q: &[f64]) -> ConEval {
        let mut out = ConEval::default();
        self.con_eval_into(e, t, q, &mut out);
        out
    }

    /// One side's marker frame (world) and the map of its motion to the side's unknowns.
    fn side(&self, mk: MarkerHandle, body: Option<usize>, q: &[f64]) -> (MFrame<f64>, SideMap) {
        match body {
            None => (self.ground_frame::<f64>(mk), SideMap::Ground),
            Some(_) if self.is_flex_marker(mk) => {
                let ff = self.flex_frame(q, mk);
                let f = MFrame {
                    origin: ff.origin,
                    axes: ff.axes,
                };
                (f, SideMap::Flex(ff))
            }
            Some(b) => {
                let o = self.qo[b];
                let (f, a, rho) = self.rigid_frame(
                    mk,
                    &[q[o], q[o + 1], q[o + 2]],
                    &[q[o + 3], q[o + 4], q[o + 5], q[o + 6]],
                );
                (f, SideMap::Rigid { a, rho })
            }
        }
    }

    /// [`System::con_eval`] into `out`, re-using its storage. The rows are written on
    /// the marker frames with their gradients in closed form ([`row_grad`]), mapped to
    /// the unknowns by each side's [`SideMap`]; the same B as the dual-number rows of
    /// [`System::con_eval2`], without their cost in every residual.
    pub fn con_eval_into(&self, e: &ConElem, t: f64, q: &[f64], out: &mut ConEval) {
        let bodies = self.bodies_of(e.mi, e.mj);
        let w = [self.width(bodies[0]), self.width(bodies[1])];
        let (fi, mi) = self.side(e.mi, bodies[0], q);
        let (fj, mj) = self.side(e.mj, bodies[1], q);
        let drive = self.drive_rates(e, t);
        let nr = e.rows.len();
        let wt = w[0] + w[1];
        out.w = w;
        out.g.clear();
        out.gt.clear();
        out.b.clear();
        out.b.resize(nr * wt, 0.0);
        for (r, row) in e.rows.iter().enumerate() {
            let rg = row_grad(*row, drive, &fi, &fj);
            out.g.push(rg.g);
            out.gt.push(rg.gt);
            for (side, map) in [&mi, &mj].into_iter().enumerate() {
                let dst = &mut out.b[r * wt + side * w[0]..r * wt + side * w[0] + w[side]];
                let (go, gphi) = (rg.go[side], rg.gphi[side]);
                match map {
                    SideMap::Ground => {}
                    SideMap::Rigid { a, rho } => {
                        dst[..6].copy_from_slice(&rigid_b(a, rho, &go, &gphi));
                    }
                    SideMap::Flex(ff) => {
                        for (k, (jt, jw)) in ff.jt.iter().zip(&ff.jw).enumerate() {
                            dst[k] = jt[0] * go[0]
                                + jt[1] * go[1]
                                + jt[2] * go[2]
                                + jw[0] * gphi[0]
                                + jw[1] * gphi[1]
                                + jw[2] * gphi[2];
                        }
                    }
                }
            }
        }
    }

    /// The drive value s and its rate s' of a motion's row as scalars of time `t` (s
    /// exact to second order in nested duals; s' to first order, s''' being unknown).
    fn drive_rates<T: Scalar>(&self, e: &ConElem, t: T) -> (T, T) {
        match e.owner {
            Owner::Motion(k) => {
                let (s, ds, d2s) = self.model.motions[k].eval(t.re());
                (t.chain(s, ds, d2s), t.chain(ds, d2s, 0.0))
            }
            Owner::Joint(_) => (T::cst(0.0), T::cst(0.0)),
        }
    }

    /// Constraint rows with second derivatives: the closed-form rows and B of
    /// [`System::con_eval_into`] evaluated in duals over both sides' seven position
    /// unknowns and time.
    pub fn con_eval2(&self, e: &ConElem, t: f64, q: &[f64]) -> ConEval2 {
        if self.has_flex(e) {
            return self.con_eval2_flex(e, t, q);
        }
        type Q15 = Dual<f64, 15>;
        /// A side's frame, and its body's rotation and marker offset (rigid sides).
        type Side = (MFrame<Q15>, Option<(M3<Q15>, V3<Q15>)>);
        let bodies = self.bodies_of(e.mi, e.mj);
        let side = |side: usize, mk: MarkerHandle, b: Option<usize>| -> Side {
            match b {
                None => (self.ground_frame::<Q15>(mk), None),
                Some(b) => {
                    let o = self.qo[b];
                    let r: V3<Q15> = std::array::from_fn(|c| Q15::var(q[o + c], 7 * side + c));
                    let p: Q4<Q15> =
                        std::array::from_fn(|c| Q15::var(q[o + 3 + c], 7 * side + 3 + c));
                    let (f, a, rho) = self.rigid_frame(mk, &r, &p);
                    (f, Some((a, rho)))
                }
            }
        };
        let (fi, mi) = side(0, e.mi, bodies[0]);
        let (fj, mj) = side(1, e.mj, bodies[1]);
        let drive = self.drive_rates(e, Q15::var(t, 14));
        let nr = e.rows.len();
        let mut first = ConEval {
            g: Vec::with_capacity(nr),
            b: vec![0.0; nr * 12],
            gt: Vec::with_capacity(nr),
            w: [6, 6],
        };
        let mut gq = Vec::with_capacity(nr);
        let mut dbq = Vec::with_capacity(nr);
        for (r, row) in e.rows.iter().enumerate() {
            let rg = row_grad(*row, drive, &fi, &fj);
            first.g.push(rg.g.v);
            first.gt.push(rg.gt.v);
            gq.push(rg.g.d[..14].to_vec());
            let mut d = [[0.0; 15]; 13];
            for (s, map) in [&mi, &mj].into_iter().enumerate() {
                let Some((a, rho)) = map else { continue };
                let bs = rigid_b(a, rho, &rg.go[s], &rg.gphi[s]);
                for (c, x) in bs.iter().enumerate() {
                    first.b[r * 12 + 6 * s + c] = x.v;
                    d[6 * s + c] = x.d;
                }
            }
            d[12] = rg.gt.d;
            dbq.push(d);
        }
        ConEval2 {
            first,
            gq,
            dbq: Some(dbq),
        }
    }

    /// First derivatives only, with d g / d q = B dx/dq.
    fn con_eval2_flex(&self, e: &ConElem, t: f64, q: &[f64]) -> ConEval2 {
        let first = self.con_eval(e, t, q);
        let bodies = self.bodies_of(e.mi, e.mj);
        let gq = first
            .b
            .chunks(first.w[0] + first.w[1])
            .map(|row| {
                let mut out = Vec::new();
                for (side, body) in bodies.iter().enumerate() {
                    let off = side * first.w[0];
                    let Some(b) = body else {
                        out.extend(std::iter::repeat_n(0.0, 7));
                        continue;
                    };
                    let o = self.qo[*b];
                    let p = [q[o + 3], q[o + 4], q[o + 5], q[o + 6]];
                    let n2 = p.iter().map(|x| x * x).sum::<f64>();
                    let qm = crate::model::math::qmat(&p);
                    out.extend_from_slice(&row[off..off + 3]);
                    // omega_body = 2 Q(p)^T p' / |p|^2
                    for qa in qm.iter() {
                        out.push((0..3).map(|c| row[off + 3 + c] * 2.0 * qa[c] / n2).sum());
                    }
                    out.extend_from_slice(&row[off + 6..off + first.w[side]]);
                }
                out
            })
            .collect();
        ConEval2 {
            first,
            gq,
            dbq: None,
        }
    }

    /// gamma = d(B v + g_t)/dt at fixed v, along the motion (q' from v): the constraint
    /// acceleration term of [M B^T; B 0] [v'; lambda] = [f; -gamma].
    pub fn con_gamma(&self, e: &ConElem, t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
        let bodies = self.bodies_of(e.mi, e.mj);
        let bv = |ev: &ConEval| -> Vec<f64> {
            (0..ev.g.len())
                .map(|r| {
                    let mut s = ev.gt[r];
                    for (side, body) in bodies.iter().enumerate() {
                        if let Some(b) = body {
                            for c in 0..ev.w[side] {
                                s += ev.at(r, side, c) * v[self.vo[*b] + c];
                            }
                        }
                    }
                    s
                })
                .collect()
        };
        if self.has_flex(e) {
            // Central difference along (q', 1) in (q, t).
            let qd = self.qdot_of(q, v);
            let scale = q.iter().fold(1.0f64, |m, x| m.max(x.abs()));
            let h = 1e-6 / (1.0 + qd.iter().fold(0.0f64, |m, x| m.max(x.abs())) / scale);
            let qp: Vec<f64> = q.iter().zip(&qd).map(|(a, b)| a + h * b).collect();
            let qm: Vec<f64> = q.iter().zip(&qd).map(|(a, b)| a - h * b).collect();
            let a = bv(&self.con_eval(e, t + h, &qp));
            let b = bv(&self.con_eval(e, t - h, &qm));
            return a.iter().zip(&b).map(|(x, y)| (x - y) / (2.0 * h)).collect();
        }
        // Second directional derivative with a dual of duals in one direction each:
        // inner along (v, 1) gives B v + g_t, outer along (q', 1) differentiates it.
        let qd = self.qdot_of(q, v);
        let mut frames = Vec::with_capacity(2);
        for (mk, b) in [e.mi, e.mj].into_iter().zip(bodies) {
            frames.push(match b {
                None => self.ground_frame::<G2>(mk),
                Some(b) => {
                    let (o, w) = (self.qo[b], self.vo[b]);
                    let r: V3<G2> = std::array::from_fn(|c| G2 {
                        v: G1 {
                            v: q[o + c],
                            d: [v[w + c]],
                        },
                        d: [G1::cst(qd[o + c])],
                    });
                    let p0: Q4<G2> = std::array::from_fn(|c| G2 {
                        v: G1::cst(q[o + 3 + c]),
                        d: [G1::cst(qd[o + 3 + c])],
                    });
                    let dth = |c: usize| {
                        G2::constant(G1 {
                            v: 0.0,
                            d: [v[w + 3 + c]],
                        }) * 0.5
                    };
                    let dp: Q4<G2> = [G2::cst(1.0), dth(0), dth(1), dth(2)];
                    self.frame_of(mk, &r, &qmul(&p0, &dp))
                }
            });
        }
        let tt = G2 {
            v: G1 { v: t, d: [1.0] },
            d: [G1::cst(1.0)],
        };
        self.rows_of(e, tt, &frames[0], &frames[1])
            .iter()
            .map(|x| x.d[0].d[0])
            .collect()
    }

    /// Kept constraint rows: g, g_t and B as (row, velocity column, value) triplets with
    /// the velocity column counted from 0 (the v block).
    pub fn constraints(&self, t: f64, q: &[f64]) -> ConstraintSet {
        let mut g = vec![0.0; self.m];
        let mut gt = vec![0.0; self.m];
        let mut b = Vec::with_capacity(24 * self.m);
        let mut ev = ConEval::default();
        for e in &self.cons {
            if e.slot.iter().all(|s| s.is_none()) {
                continue;
            }
            self.con_eval_into(e, t, q, &mut ev);
            let bodies = self.bodies_of(e.mi, e.mj);
            for (r, slot) in e.slot.iter().enumerate() {
                let Some(row) = *slot else { continue };
                g[row] = ev.g[r];
                gt[row] = ev.gt[r];
                for (side, body) in bodies.iter().enumerate() {
                    if let Some(bb) = body {
                        for c in 0..ev.w[side] {
                            let val = ev.at(r, side, c);
                            if val != 0.0 {
                                b.push((row, self.vo[*bb] + c, val));
                            }
                        }
                    }
                }
            }
        }
        (g, gt, b)
    }
}
