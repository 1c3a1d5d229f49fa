//! Force elements (springs, bushings, rotational springs, applied loads) as generalised
//! forces on the bodies, and the total load vector.
//!
//! Elements are written once, generic over a scalar: dual numbers over the two bodies'
//! (q, v) give the iteration-matrix entries of rigid elements. An element on a marker of a
//! modal body sees that marker's deformed frame and rates, and its load is mapped to all
//! the body's unknowns (modal ones included) by the marker's velocity Jacobian; its
//! iteration-matrix entries come from finite differences (`jacobian.rs`).

use super::flexmarker::FlexFrame;
use super::System;
use crate::model::desc::{ElementHandle, MarkerHandle};
use crate::model::dual::{Dual, Scalar};
use crate::model::elements::{generalised, ElementLoad, Rate};
use crate::model::joint::MFrame;
use crate::model::math::{cross, cst33, mvc, qdot, qmul, quat_from_matrix, rot, Q4, V3};

/// A body's (r, p, u, omega) in some scalar.
pub type BodyPose<S> = (V3<S>, Q4<S>, V3<S>, V3<S>);
/// An element's bodies, their generalised loads (6 + modes per side) and its measures.
pub type ElementForces<S> = ([Option<usize>; 2], [Vec<S>; 2], Vec<(S, S, S)>);
/// A marker frame with rates and its quaternion.
type RateFrame<S> = (MFrame<Rate<S>>, Q4<Rate<S>>);

type S26 = Dual<f64, 26>;

impl System {
    /// True when force element `fe` touches a marker that moves with modal coordinates.
    pub fn force_is_flex(&self, fe: ElementHandle) -> bool {
        let (mi, mj) = self.model.forces[fe].markers();
        self.is_flex_marker(mi) || mj.is_some_and(|m| self.is_flex_marker(m))
    }

    /// Loads of force element `fe` as generalised forces on its (up to) two bodies, with
    /// derivatives when `S` is a dual over (q_a, v_a, q_b, v_b) (13 per side, rigid
    /// elements only). `q`, `v` are read for markers on modal bodies.
    fn force_generalised<S: Scalar>(
        &self,
        fe: ElementHandle,
        t: f64,
        pose: &dyn Fn(usize, usize) -> BodyPose<S>,
        q: &[f64],
        v: &[f64],
    ) -> ElementForces<S> {
        let (mi, mj) = self.model.forces[fe].markers();
        let bi = self.body_of(mi);
        let bj = mj.and_then(|m| self.body_of(m));
        let (l, p, [ffi, ffj]) = self.element_load(fe, t, pose, q, v);
        let (force, torque, measures) = (l.force, l.torque, l.measures);
        let on = |ff: &Option<FlexFrame>, b: usize, side: usize, f: &V3<S>, tq: &V3<S>| -> Vec<S> {
            if let Some(ff) = ff {
                // J^T (f, tq) with the marker's velocity Jacobian; a two-marker element
                // acts at marker i's origin, so marker j's side gets the moment of the
                // offset as well (zero for coincident markers).
                let arm: V3<S> = std::array::from_fn(|c| p[c] - S::cst(ff.origin[c]));
                let m = cross(&arm, f);
                ff.jt
                    .iter()
                    .zip(&ff.jw)
                    .map(|(a, b)| {
                        let mut s = S::cst(0.0);
                        for c in 0..3 {
                            s = s + f[c] * a[c] + (tq[c] + m[c]) * b[c];
                        }
                        s
                    })
                    .collect()
            } else {
                let (r, pq, _, _) = pose(b, side);
                let mut out = generalised(&r, &rot(&pq), &p, f, tq).to_vec();
                out.extend(std::iter::repeat_n(S::cst(0.0), self.nm[b]));
                out
            }
        };
        let mut out = [Vec::new(), Vec::new()];
        if let Some(b) = bi {
            out[0] = on(&ffi, b, 0, &force, &torque);
        }
        if let (Some(b), Some(_)) = (bj, mj) {
            let nf = force.map(|x| -x);
            let nt = torque.map(|x| -x);
            out[1] = on(&ffj, b, 1, &nf, &nt);
        }
        ([bi, bj], out, measures)
    }

    /// The world force and torque element `fe` puts on marker I's body and the point it
    /// acts at (I's origin); J's body takes the opposite force at the same point.
    pub fn element_wrench(
        &self,
        fe: ElementHandle,
        t: f64,
        q: &[f64],
        v: &[f64],
    ) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let pose = |b: usize, _side: usize| {
            let (r, p) = self.pose(q, b);
            let (u, w) = self.twist(v, b);
            (r, p, u, w)
        };
        let (l, p, _) = self.element_load::<f64>(fe, t, &pose, q, v);
        (l.force, l.torque, p)
    }

    /// Element `fe`'s load (on I, world) at marker I's origin, and the deformed frames of
    /// its markers on modal bodies (per side) for mapping the load back.
    fn element_load<S: Scalar>(
        &self,
        fe: ElementHandle,
        t: f64,
        pose: &dyn Fn(usize, usize) -> BodyPose<S>,
        q: &[f64],
        v: &[f64],
    ) -> (ElementLoad<S>, V3<S>, [Option<FlexFrame>; 2]) {
        let element = &self.model.forces[fe];
        // The frame of a marker on a modal body comes with its velocity Jacobian, kept
        // (per side) for mapping the load back.
        let mut flex: [Option<FlexFrame>; 2] = [None, None];
        let rate_frame = |mk: MarkerHandle, side: usize| -> RateFrame<S> {
            let mq = self.marker_quat(mk);
            match self.body_of(mk) {
                None => (self.ground_frame::<Rate<S>>(mk), mq.map(Rate::<S>::cst)),
                Some(b) if self.is_flex_marker(mk) => {
                    let ff = self.flex_frame(q, mk);
                    let vb = &v[self.vo[b]..self.vo[b] + 6 + self.nm[b]];
                    let (vo, w) = ff.rates(vb);
                    let pq = quat_from_matrix(&ff.axes);
                    let wl = crate::model::math::mtv(&ff.axes, &w);
                    let pd = qdot(&pq, &wl);
                    let r: V3<Rate<S>> = std::array::from_fn(|c| Rate {
                        v: S::cst(ff.origin[c]),
                        d: [S::cst(vo[c])],
                    });
                    let p: Q4<Rate<S>> = std::array::from_fn(|c| Rate {
                        v: S::cst(pq[c]),
                        d: [S::cst(pd[c])],
                    });
                    let a = rot(&p);
                    flex[side] = Some(ff);
                    (MFrame { origin: r, axes: a }, p)
                }
                Some(b) => {
                    let (r, p, u, w) = pose(b, side);
                    let pd = qdot(&p, &w);
                    let rr: V3<Rate<S>> = std::array::from_fn(|c| Rate { v: r[c], d: [u[c]] });
                    let pp: Q4<Rate<S>> = std::array::from_fn(|c| Rate {
                        v: p[c],
                        d: [pd[c]],
                    });
                    let f = self.frame_of(mk, &rr, &pp);
                    let mqs: Q4<Rate<S>> = mq.map(Rate::<S>::cst);
                    (f, qmul(&pp, &mqs))
                }
            }
        };
        let (l, frame_i) = element.load(t, rate_frame);
        let p: V3<S> = frame_i.0.origin.map(|x| x.v);
        (l, p, flex)
    }

    /// Element loads and measures at f64 (residual, outputs).
    pub fn force_eval(
        &self,
        fe: ElementHandle,
        t: f64,
        q: &[f64],
        v: &[f64],
    ) -> ElementForces<f64> {
        let pose = |b: usize, _side: usize| {
            let (r, p) = self.pose(q, b);
            let (u, w) = self.twist(v, b);
            (r, p, u, w)
        };
        self.force_generalised::<f64>(fe, t, &pose, q, v)
    }

    /// Element loads with derivatives d/d(q_a, v_a, q_b, v_b), 26 columns (rigid
    /// elements: see [`System::force_is_flex`]).
    pub fn force_eval_dual(
        &self,
        fe: ElementHandle,
        t: f64,
        q: &[f64],
        v: &[f64],
    ) -> ([Option<usize>; 2], [Vec<S26>; 2]) {
        let pose = |b: usize, side: usize| {
            let o = 13 * side;
            let (qo, vo) = (self.qo[b], self.vo[b]);
            (
                std::array::from_fn(|c| S26::var(q[qo + c], o + c)),
                std::array::from_fn(|c| S26::var(q[qo + 3 + c], o + 3 + c)),
                std::array::from_fn(|c| S26::var(v[vo + c], o + 7 + c)),
                std::array::from_fn(|c| S26::var(v[vo + 3 + c], o + 10 + c)),
            )
        };
        let (b, g, _) = self.force_generalised::<S26>(fe, t, &pose, q, v);
        (b, g)
    }

    /// Name of force element `fe`.
    pub fn force_name(&self, fe: ElementHandle) -> String {
        self.model.forces[fe].name().to_string()
    }

    /// Bodies of force element `fe` (numbered as [`System::body_of`]).
    pub fn force_bodies(&self, fe: ElementHandle) -> [Option<usize>; 2] {
        let (mi, mj) = self.model.forces[fe].markers();
        [self.body_of(mi), mj.and_then(|m| self.body_of(m))]
    }

    /// Gravity, gyroscopic, elastic-modal and element loads: the generalised force vector
    /// f(q, v, x) with M v' = f - B^T lambda (nv entries), without extension loads.
    pub fn element_loads(&self, t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
        let mut f = vec![0.0; self.nv];
        let g = self.model.gravity;
        for (k, b) in self.model.bodies.iter().enumerate() {
            let w = self.vo[k];
            let om = [v[w + 3], v[w + 4], v[w + 5]];
            let jw = mvc(&cst33::<f64>(&b.inertia), &om);
            // A `full` modal body's gyroscopic term uses its deformed inertia (modal.rs).
            let gyro = if self.full[k].is_some() {
                [0.0; 3]
            } else {
                cross(&om, &jw)
            };
            for c in 0..3 {
                f[w + c] += b.mass * g[c];
                f[w + 3 + c] -= gyro[c];
            }
            if let Some(m) = &b.modal {
                self.modal_loads(k, m, q, v, &mut f);
            }
        }
        for (fe, _) in self.model.each_element() {
            let (bs, gl, _) = self.force_eval(fe, t, q, v);
            for s in 0..2 {
                if let Some(b) = bs[s] {
                    for (c, x) in gl[s].iter().enumerate() {
                        f[self.vo[b] + c] += x;
                    }
                }
            }
        }
        f
    }

    /// All loads: [`System::element_loads`] plus the extension elements' (tyres,
    /// drivelines). With `ext_res`, also writes the extension residuals for states `x`
    /// and their rates.
    pub fn loads(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        x: &[f64],
        ext_res: Option<(&[f64], &mut [f64])>,
    ) -> Vec<f64> {
        let mut f = self.element_loads(t, q, v);
        match ext_res {
            Some((xd, res)) => self.ext_loads(t, q, v, x, xd, res, &mut f),
            None => {
                let xd = vec![0.0; self.ne];
                let mut res = vec![0.0; self.ne];
                self.ext_loads(t, q, v, x, &xd, &mut res, &mut f);
            }
        }
        f
    }

    /// The total load vector for a full solver state y (q, v and extension states).
    pub fn applied(&self, t: f64, y: &[f64]) -> Vec<f64> {
        let (_, ov, ol, _) = self.offsets();
        self.loads(t, &y[..ov], &y[ov..ol], &y[self.oe()..], None)
    }
}
