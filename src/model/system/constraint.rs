//! Constraint rows with their derivatives.
//!
//! Rigid markers: rows are written once, generic over a scalar; dual numbers over the
//! two bodies' virtual motions (translation, body-axes rotation) give B exactly, and duals
//! of duals give d B / d q. A marker on a modal body is treated as a frame of its own
//! (its world origin and axes): the rows are differentiated with respect to that frame's
//! virtual motion and mapped to the body's unknowns (including modal coordinates) with
//! the marker's velocity Jacobian ([`super::flexmarker`]). For such elements the second
//! derivatives d B / d q are left out of the iteration matrix (they only speed up Newton
//! by the geometric stiffness of the reaction, small against the body's own stiffness)
//! and the constraint acceleration term is differentiated numerically along the motion.

use super::{ConElem, ConRow, ConstraintSet, Owner, System};
use crate::model::dual::{Dual, Scalar};
use crate::model::joint::{motion_value, row_value, MFrame};
use crate::model::math::{cst3, cst33, mm, mvc, qmul, quat_from_matrix, rot, Q4, V3};

type T1 = Dual<f64, 13>;
type T2 = Dual<T1, 15>;
/// One side's virtual motions, and those inside its seven position unknowns.
type S1 = Dual<f64, 6>;
type S2 = Dual<S1, 7>;

/// A 6-wide dual placed at `off` in a 13-wide one.
fn widen(x: &S1, off: usize) -> T1 {
    let mut d = [0.0; 13];
    d[off..off + 6].copy_from_slice(&x.d);
    T1 { v: x.v, d }
}

fn map_frame<A: Scalar, B: Scalar>(f: &MFrame<A>, m: impl Fn(&A) -> B) -> MFrame<B> {
    MFrame {
        origin: std::array::from_fn(|c| m(&f.origin[c])),
        axes: std::array::from_fn(|r| std::array::from_fn(|c| m(&f.axes[r][c]))),
    }
}

/// The quaternion (1, theta/2) of a small body-axes rotation theta.
fn half_turn<T: Scalar>(theta: impl Fn(usize) -> T) -> Q4<T> {
    [T::cst(1.0), theta(0) * 0.5, theta(1) * 0.5, theta(2) * 0.5]
}
/// One direction inside one direction: the constraint acceleration term.
type G1 = Dual<f64, 1>;
type G2 = Dual<G1, 1>;

/// Constraint rows of one element with their first derivatives.
pub struct ConEval {
    pub g: Vec<f64>,
    /// d g / d(v_a, v_b): per row, the velocity unknowns of side a then side b.
    pub b: Vec<Vec<f64>>,
    pub gt: Vec<f64>,
    /// Number of velocity unknowns of each side (6 + modes; 6 for ground).
    pub w: [usize; 2],
}

impl ConEval {
    /// Entry of row r for velocity unknown c of `side`.
    pub fn at(&self, r: usize, side: usize, c: usize) -> f64 {
        self.b[r][side * self.w[0] + c]
    }
}

/// Constraint rows with second derivatives (iteration matrix, accelerations).
pub struct ConEval2 {
    pub first: ConEval,
    /// d g / d(q_a, q_b): per row, the position unknowns of side a (7 + modes) then b.
    pub gq: Vec<Vec<f64>>,
    /// Rigid elements only: d B_k / d(q_a, q_b, t): [row][k][l], k < 13 (12 = g_t),
    /// l < 15 (14 = t).
    pub dbq: Option<Vec<[[f64; 15]; 13]>>,
}

impl System {
    /// Motion value s(t) as a scalar of time `t`.
    fn drive<T: Scalar>(&self, e: &ConElem, t: T) -> T {
        match e.owner {
            Owner::Motion(k) => {
                let (s, ds, d2s) = self.model.motions[k].eval(t.re());
                t.chain(s, ds, d2s)
            }
            Owner::Joint(_) => T::cst(0.0),
        }
    }

    fn rows_of<T: Scalar>(&self, e: &ConElem, t: T, fi: &MFrame<T>, fj: &MFrame<T>) -> Vec<T> {
        e.rows
            .iter()
            .map(|r| match r {
                ConRow::Prim(p) => row_value(*p, fi, fj),
                ConRow::Drive(d) => motion_value(*d, self.drive(e, t), fi, fj),
            })
            .collect()
    }

    /// Marker frame from a body pose in any scalar (rigid markers).
    pub(super) fn frame_of<T: Scalar>(&self, k: usize, r: &V3<T>, p: &Q4<T>) -> MFrame<T> {
        let mk = &self.model.markers[k];
        let a = rot(p);
        let o = mvc(&a, &mk.position);
        MFrame {
            origin: [r[0] + o[0], r[1] + o[1], r[2] + o[2]],
            axes: mm(&a, &cst33(&mk.axes)),
        }
    }

    pub(super) fn ground_frame<T: Scalar>(&self, k: usize) -> MFrame<T> {
        let mk = &self.model.markers[k];
        MFrame {
            origin: cst3(&mk.position),
            axes: cst33(&mk.axes),
        }
    }

    /// True when a side of `e` is a modal body (its rows take the chain-rule path).
    fn has_flex(&self, e: &ConElem) -> bool {
        self.bodies_of(e.mi, e.mj)
            .iter()
            .any(|b| b.is_some_and(|b| self.nm[b] > 0))
    }

    /// Constraint rows of element `e` with B and g_t (all rows, kept or not).
    pub fn con_eval(&self, e: &ConElem, t: f64, q: &[f64]) -> ConEval {
        let bodies = self.bodies_of(e.mi, e.mj);
        let w = [self.width(bodies[0]), self.width(bodies[1])];
        // Each side's frame depends on that side's six virtual motions only: computed in
        // 6-wide duals and placed into the 13-wide ones the rows need.
        let mut frames = Vec::with_capacity(2);
        let mut maps = [None, None];
        for (side, (mk, b)) in [e.mi, e.mj].into_iter().zip(bodies).enumerate() {
            let local: MFrame<S1> = match b {
                None => self.ground_frame::<S1>(mk),
                Some(_) if self.is_flex_marker(mk) => {
                    // The marker as a frame of its own: virtual translation (world) and
                    // rotation (marker axes).
                    let ff = self.flex_frame(q, mk);
                    let o: V3<S1> = std::array::from_fn(|c| S1::var(ff.origin[c], c));
                    let pq = quat_from_matrix(&ff.axes).map(S1::cst);
                    let axes = rot(&qmul(&pq, &half_turn::<S1>(|c| S1::var(0.0, 3 + c))));
                    maps[side] = Some(ff);
                    MFrame { origin: o, axes }
                }
                Some(b) => {
                    let o = self.qo[b];
                    let r: V3<S1> = std::array::from_fn(|c| S1::var(q[o + c], c));
                    let p0: Q4<S1> = std::array::from_fn(|c| S1::cst(q[o + 3 + c]));
                    let dp = half_turn::<S1>(|c| S1::var(0.0, 3 + c));
                    self.frame_of(mk, &r, &qmul(&p0, &dp))
                }
            };
            frames.push(map_frame(&local, |x| widen(x, 6 * side)));
        }
        let vals = self.rows_of(e, T1::var(t, 12), &frames[0], &frames[1]);
        let b = vals
            .iter()
            .map(|v| {
                let mut row = vec![0.0; w[0] + w[1]];
                for side in 0..2 {
                    let d = &v.d[6 * side..6 * side + 6];
                    let off = side * w[0];
                    match &maps[side] {
                        None => row[off..off + 6].copy_from_slice(d),
                        Some(ff) => {
                            // d_phi (marker axes) = X^T omega_world.
                            let x = ff.axes;
                            for (k, (jt, jw)) in ff.jt.iter().zip(&ff.jw).enumerate() {
                                let mut s = 0.0;
                                for c in 0..3 {
                                    s += d[c] * jt[c];
                                    let phi_c = x[0][c] * jw[0] + x[1][c] * jw[1] + x[2][c] * jw[2];
                                    s += d[3 + c] * phi_c;
                                }
                                row[off + k] = s;
                            }
                        }
                    }
                }
                row
            })
            .collect();
        ConEval {
            g: vals.iter().map(|v| v.v).collect(),
            b,
            gt: vals.iter().map(|v| v.d[12]).collect(),
            w,
        }
    }

    /// Constraint rows with second derivatives.
    pub fn con_eval2(&self, e: &ConElem, t: f64, q: &[f64]) -> ConEval2 {
        if self.has_flex(e) {
            return self.con_eval2_flex(e, t, q);
        }
        let bodies = self.bodies_of(e.mi, e.mj);
        // Per side: 6 virtual motions inside 7 position unknowns, placed into the
        // 13-inside-15 duals of the rows (a quarter of the work on the frames).
        let mut frames = Vec::with_capacity(2);
        for (side, (mk, b)) in [e.mi, e.mj].into_iter().zip(bodies).enumerate() {
            let local: MFrame<S2> = match b {
                None => self.ground_frame::<S2>(mk),
                Some(b) => {
                    let o = self.qo[b];
                    let r: V3<S2> = std::array::from_fn(|c| S2 {
                        v: S1::var(q[o + c], c),
                        d: std::array::from_fn(|l| S1::cst(if l == c { 1.0 } else { 0.0 })),
                    });
                    let p0: Q4<S2> = std::array::from_fn(|c| S2 {
                        v: S1::cst(q[o + 3 + c]),
                        d: std::array::from_fn(|l| S1::cst(if l == 3 + c { 1.0 } else { 0.0 })),
                    });
                    let dp = half_turn::<S2>(|c| S2::constant(S1::var(0.0, 3 + c)));
                    self.frame_of(mk, &r, &qmul(&p0, &dp))
                }
            };
            frames.push(map_frame(&local, |x| T2 {
                v: widen(&x.v, 6 * side),
                d: std::array::from_fn(|l| {
                    if (7 * side..7 * side + 7).contains(&l) {
                        widen(&x.d[l - 7 * side], 6 * side)
                    } else {
                        T1::cst(0.0)
                    }
                }),
            }));
        }
        let tt = T2 {
            v: T1::var(t, 12),
            d: std::array::from_fn(|l| T1::cst(if l == 14 { 1.0 } else { 0.0 })),
        };
        let vals = self.rows_of(e, tt, &frames[0], &frames[1]);
        ConEval2 {
            first: ConEval {
                g: vals.iter().map(|v| v.v.v).collect(),
                b: vals.iter().map(|v| v.v.d[..12].to_vec()).collect(),
                gt: vals.iter().map(|v| v.v.d[12]).collect(),
                w: [6, 6],
            },
            gq: vals
                .iter()
                .map(|v| (0..14).map(|l| v.d[l].v).collect())
                .collect(),
            dbq: Some(
                vals.iter()
                    .map(|v| std::array::from_fn(|k| std::array::from_fn(|l| v.d[l].d[k])))
                    .collect(),
            ),
        }
    }

    /// First derivatives only, with d g / d q = B dx/dq.
    fn con_eval2_flex(&self, e: &ConElem, t: f64, q: &[f64]) -> ConEval2 {
        let first = self.con_eval(e, t, q);
        let bodies = self.bodies_of(e.mi, e.mj);
        let gq = first
            .b
            .iter()
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
        let mut b = Vec::new();
        for e in &self.cons {
            if e.slot.iter().all(|s| s.is_none()) {
                continue;
            }
            let ev = self.con_eval(e, t, q);
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
