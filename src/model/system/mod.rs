//! The assembled equations of a [`Model`]: a stabilised index-2 (GGL) DAE in absolute
//! coordinates with quaternions, implementing [`DaeProblem`] with an exact, sparse
//! iteration matrix.
//!
//! Unknowns, per body k: r (3, centre of mass, world), p (4, quaternion), u = r' (3) and
//! omega (3, body axes); then the multipliers lambda (one per kept constraint row) and the
//! GGL multipliers mu. Equations:
//!
//! ```text
//! r' - u + B_u^T mu                       = 0      (3 per body)
//! p' - Q(p) (omega - B_w^T mu) / 2        = 0      (4 per body)
//! m u' - m g - F + B_u^T lambda           = 0      (3 per body)
//! J omega' + omega x J omega - T + B_w^T lambda = 0  (3 per body)
//! g(q, t)                                 = 0      (one per kept row)
//! B v + g_t                               = 0      (one per kept row)
//! ```
//!
//! B = dg/dx is the constraint Jacobian in velocity space (virtual displacement and
//! body-axes rotation), F and T the element loads. The mu terms make the position and
//! velocity constraints hold together (Gear, Gupta & Leimkuhler 1985); mu = 0 on the exact
//! solution, so its O(mu) second-derivative terms are left out of the iteration matrix.

use super::desc::{Force, Model, MotionDof};
use super::dual::{Dual, Scalar};
use super::force::{element_load, generalised, Rate};
use super::joint::{motion_value, row_value, rows, MFrame, Row};
use super::math::{cst33, mm, mvc, qdot, qmul, quat_from_matrix, rot, Q4, V3};
use crate::solver::problem::{DaeProblem, JacobianSink, VarKind};

mod jacobian;

/// Who owns a constraint row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Owner {
    Joint(usize),
    Motion(usize),
}

/// One constraint row of an element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConRow {
    Prim(Row),
    Drive(MotionDof),
}

/// A constraint element: a joint or a motion, its markers and rows.
#[derive(Clone, Debug)]
pub struct ConElem {
    pub owner: Owner,
    pub mi: usize,
    pub mj: usize,
    pub rows: Vec<ConRow>,
    /// Global multiplier index of each row, `None` when the row was found redundant.
    pub slot: Vec<Option<usize>>,
}

/// A dropped row and the kept rows it depends on.
#[derive(Clone, Debug)]
pub struct Redundant {
    pub elem: usize,
    pub row: usize,
    /// (element, row, coefficient) of the kept rows that reproduce it.
    pub depends_on: Vec<(usize, usize, f64)>,
}

/// A body's (r, p, u, omega) in some scalar.
pub type BodyPose<S> = (V3<S>, Q4<S>, V3<S>, V3<S>);
/// An element's bodies, their generalised loads and its measures.
pub type ElementForces<S> = ([Option<usize>; 2], [[S; 6]; 2], Vec<(S, S, S)>);
/// A marker frame with rates, its quaternion, the body position and rotation.
type RateFrame<S> = (MFrame<Rate<S>>, Q4<Rate<S>>, V3<S>, [[S; 3]; 3]);
/// Kept constraint rows: g, g_t and B as (row, velocity column, value) triplets.
pub type ConstraintSet = (Vec<f64>, Vec<f64>, Vec<(usize, usize, f64)>);

type T1 = Dual<f64, 13>;
type T2 = Dual<T1, 15>;
type S26 = Dual<f64, 26>;

/// The assembled mechanism.
pub struct System {
    pub model: Model,
    pub cons: Vec<ConElem>,
    pub redundant: Vec<Redundant>,
    /// Number of kept constraint rows.
    pub m: usize,
    /// Marker axes as quaternions (body frame), for bushings.
    mquat: Vec<[f64; 4]>,
    /// Force elements: (index in model.forces, marker i, marker j or None).
    felems: Vec<(usize, usize, Option<usize>)>,
}

/// Constraint rows of one element with their first derivatives.
pub struct ConEval {
    pub g: Vec<f64>,
    /// d g / d(x_a, x_b), 12 columns.
    pub b: Vec<[f64; 12]>,
    pub gt: Vec<f64>,
}

/// Constraint rows with second derivatives (iteration matrix, accelerations).
pub struct ConEval2 {
    pub first: ConEval,
    /// d g / d(q_a, q_b), 14 columns.
    pub gq: Vec<[f64; 14]>,
    /// d B_k / d(q_a, q_b, t): [row][k][l], k < 13 (12 = g_t), l < 15 (14 = t).
    pub dbq: Vec<[[f64; 15]; 13]>,
}

impl System {
    /// Assembles a validated model at its initial configuration: numbers the constraint
    /// rows and drops the redundant ones (see [`super::redundancy`]).
    pub fn new(model: Model) -> System {
        let mut cons = Vec::new();
        for (k, j) in model.joints.iter().enumerate() {
            let rs: Vec<ConRow> = rows(j.kind).iter().map(|r| ConRow::Prim(*r)).collect();
            cons.push(ConElem {
                owner: Owner::Joint(k),
                mi: j.i,
                mj: j.j,
                slot: vec![None; rs.len()],
                rows: rs,
            });
        }
        for (k, mo) in model.motions.iter().enumerate() {
            let j = &model.joints[mo.joint];
            cons.push(ConElem {
                owner: Owner::Motion(k),
                mi: j.i,
                mj: j.j,
                rows: vec![ConRow::Drive(mo.dof)],
                slot: vec![None],
            });
        }
        let mquat = model
            .markers
            .iter()
            .map(|m| quat_from_matrix(&m.axes))
            .collect();
        let felems = model
            .forces
            .iter()
            .enumerate()
            .map(|(k, f)| match f {
                Force::Spring(s) => (k, s.i, Some(s.j)),
                Force::Bushing(b) => (k, b.i, Some(b.j)),
                Force::Rot(r) => (k, r.i, Some(r.j)),
                Force::Applied(a) => (k, a.i, None),
            })
            .collect();
        let mut sys = System {
            model,
            cons,
            redundant: Vec::new(),
            m: 0,
            mquat,
            felems,
        };
        let (q, _) = sys.initial_q_v();
        let (kept, redundant) = super::redundancy::select_rows(&sys, 0.0, &q);
        let mut m = 0;
        for (e, r) in kept {
            sys.cons[e].slot[r] = Some(m);
            m += 1;
        }
        sys.m = m;
        sys.redundant = redundant;
        sys
    }

    pub fn nb(&self) -> usize {
        self.model.bodies.len()
    }

    /// Offsets: q block, v block, lambda, mu.
    pub fn offsets(&self) -> (usize, usize, usize, usize) {
        let nb = self.nb();
        (0, 7 * nb, 13 * nb, 13 * nb + self.m)
    }

    /// Positions and velocities from the bodies' initial values (world angular velocity
    /// turned into body axes).
    pub fn initial_q_v(&self) -> (Vec<f64>, Vec<f64>) {
        let mut q = Vec::with_capacity(7 * self.nb());
        let mut v = Vec::with_capacity(6 * self.nb());
        for b in &self.model.bodies {
            q.extend_from_slice(&b.position);
            q.extend_from_slice(&b.orientation);
            let a = rot(&b.orientation);
            let wb = super::math::mtv(&a, &b.angular_velocity);
            v.extend_from_slice(&b.velocity);
            v.extend_from_slice(&wb);
        }
        (q, v)
    }

    /// World frame of marker `k` for given positions (f64).
    pub fn marker_frame(&self, q: &[f64], k: usize) -> MFrame<f64> {
        let mk = &self.model.markers[k];
        match mk.body {
            None => MFrame {
                origin: mk.position,
                axes: mk.axes,
            },
            Some(b) => {
                let r = [q[7 * b], q[7 * b + 1], q[7 * b + 2]];
                let p = [q[7 * b + 3], q[7 * b + 4], q[7 * b + 5], q[7 * b + 6]];
                let a = rot(&p);
                let o = mvc(&a, &mk.position);
                MFrame {
                    origin: [r[0] + o[0], r[1] + o[1], r[2] + o[2]],
                    axes: mm(&a, &mk.axes),
                }
            }
        }
    }

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

    /// Marker frame from a body pose in any scalar.
    fn frame_of<T: Scalar>(&self, k: usize, r: &V3<T>, p: &Q4<T>) -> MFrame<T> {
        let mk = &self.model.markers[k];
        let a = rot(p);
        let o = mvc(&a, &mk.position);
        MFrame {
            origin: [r[0] + o[0], r[1] + o[1], r[2] + o[2]],
            axes: mm(&a, &cst33(&mk.axes)),
        }
    }

    fn ground_frame<T: Scalar>(&self, k: usize) -> MFrame<T> {
        let mk = &self.model.markers[k];
        MFrame {
            origin: super::math::cst3(&mk.position),
            axes: cst33(&mk.axes),
        }
    }

    /// The bodies (or ground) of an element's two markers.
    pub fn bodies_of(&self, mi: usize, mj: usize) -> [Option<usize>; 2] {
        [self.model.markers[mi].body, self.model.markers[mj].body]
    }

    /// Constraint rows of element `e` with B and g_t (all rows, kept or not).
    pub fn con_eval(&self, e: &ConElem, t: f64, q: &[f64]) -> ConEval {
        let bodies = self.bodies_of(e.mi, e.mj);
        let mut frames = Vec::with_capacity(2);
        for (side, (mk, b)) in [e.mi, e.mj].into_iter().zip(bodies).enumerate() {
            frames.push(match b {
                None => self.ground_frame::<T1>(mk),
                Some(b) => {
                    let r: V3<T1> = std::array::from_fn(|c| T1::var(q[7 * b + c], 6 * side + c));
                    let p0: Q4<T1> = std::array::from_fn(|c| T1::cst(q[7 * b + 3 + c]));
                    let dp: Q4<T1> = [
                        T1::cst(1.0),
                        T1::var(0.0, 6 * side + 3) * 0.5,
                        T1::var(0.0, 6 * side + 4) * 0.5,
                        T1::var(0.0, 6 * side + 5) * 0.5,
                    ];
                    self.frame_of(mk, &r, &qmul(&p0, &dp))
                }
            });
        }
        let vals = self.rows_of(e, T1::var(t, 12), &frames[0], &frames[1]);
        ConEval {
            g: vals.iter().map(|v| v.v).collect(),
            b: vals
                .iter()
                .map(|v| std::array::from_fn(|k| v.d[k]))
                .collect(),
            gt: vals.iter().map(|v| v.d[12]).collect(),
        }
    }

    /// Constraint rows with second derivatives.
    pub fn con_eval2(&self, e: &ConElem, t: f64, q: &[f64]) -> ConEval2 {
        let bodies = self.bodies_of(e.mi, e.mj);
        let mut frames = Vec::with_capacity(2);
        for (side, (mk, b)) in [e.mi, e.mj].into_iter().zip(bodies).enumerate() {
            frames.push(match b {
                None => self.ground_frame::<T2>(mk),
                Some(b) => {
                    let r: V3<T2> = std::array::from_fn(|c| T2 {
                        v: T1::var(q[7 * b + c], 6 * side + c),
                        d: std::array::from_fn(|l| {
                            T1::cst(if l == 7 * side + c { 1.0 } else { 0.0 })
                        }),
                    });
                    let p0: Q4<T2> = std::array::from_fn(|c| T2 {
                        v: T1::cst(q[7 * b + 3 + c]),
                        d: std::array::from_fn(|l| {
                            T1::cst(if l == 7 * side + 3 + c { 1.0 } else { 0.0 })
                        }),
                    });
                    let dth = |c: usize| T2::constant(T1::var(0.0, 6 * side + 3 + c)) * 0.5;
                    let dp: Q4<T2> = [T2::cst(1.0), dth(0), dth(1), dth(2)];
                    self.frame_of(mk, &r, &qmul(&p0, &dp))
                }
            });
        }
        let tt = T2 {
            v: T1::var(t, 12),
            d: std::array::from_fn(|l| T1::cst(if l == 14 { 1.0 } else { 0.0 })),
        };
        let vals = self.rows_of(e, tt, &frames[0], &frames[1]);
        ConEval2 {
            first: ConEval {
                g: vals.iter().map(|v| v.v.v).collect(),
                b: vals
                    .iter()
                    .map(|v| std::array::from_fn(|k| v.v.d[k]))
                    .collect(),
                gt: vals.iter().map(|v| v.v.d[12]).collect(),
            },
            gq: vals
                .iter()
                .map(|v| std::array::from_fn(|l| v.d[l].v))
                .collect(),
            dbq: vals
                .iter()
                .map(|v| std::array::from_fn(|k| std::array::from_fn(|l| v.d[l].d[k])))
                .collect(),
        }
    }

    /// Loads of force element `fe` as generalised forces on its (up to) two bodies, with
    /// derivatives when `S` is a dual over (q_a, v_a, q_b, v_b) (13 per side).
    fn force_generalised<S: Scalar>(
        &self,
        fe: usize,
        t: f64,
        pose: &dyn Fn(usize, usize) -> BodyPose<S>,
    ) -> ElementForces<S> {
        let (k, mi, mj) = self.felems[fe];
        let bi = self.model.markers[mi].body;
        let bj = mj.and_then(|m| self.model.markers[m].body);
        // Frames as Rate<S> (value + time derivative along the motion).
        let rate_frame = |mk: usize, side: usize, b: Option<usize>| -> RateFrame<S> {
            let mq = self.mquat[mk];
            match b {
                None => {
                    let f = self.ground_frame::<Rate<S>>(mk);
                    let id = [
                        [S::cst(1.0), S::cst(0.0), S::cst(0.0)],
                        [S::cst(0.0), S::cst(1.0), S::cst(0.0)],
                        [S::cst(0.0), S::cst(0.0), S::cst(1.0)],
                    ];
                    (f, mq.map(Rate::<S>::cst), [S::cst(0.0); 3], id)
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
                    (f, qmul(&pp, &mqs), r, rot(&p))
                }
            }
        };
        let (fi, qi, ri, ai) = rate_frame(mi, 0, bi);
        let mut out = [[S::cst(0.0); 6]; 2];
        let measures;
        let (force, torque);
        match &self.model.forces[k] {
            Force::Applied(app) => {
                let (tf, ax) = (t, app.in_marker_axes);
                let comp = |fs: &[Option<super::function::TimeFunction>; 3]| -> V3<S> {
                    let local: [f64; 3] =
                        std::array::from_fn(|c| fs[c].as_ref().map_or(0.0, |f| f.eval(tf).0));
                    if ax {
                        let a: [[S; 3]; 3] = fi.axes.map(|r| r.map(|x| x.v));
                        mvc(&a, &local)
                    } else {
                        super::math::cst3(&local)
                    }
                };
                force = comp(&app.force);
                torque = comp(&app.torque);
                measures = (0..3)
                    .map(|c| (force[c], S::cst(0.0), S::cst(0.0)))
                    .chain((0..3).map(|c| (torque[c], S::cst(0.0), S::cst(0.0))))
                    .collect();
            }
            f => {
                let mj = mj.expect("two-marker element");
                let (fj, qj, _, _) = rate_frame(mj, 1, bj);
                let l = element_load(f, &fi, &fj, &qi, &qj);
                force = l.force;
                torque = l.torque;
                measures = l.measures;
            }
        }
        let p: V3<S> = fi.origin.map(|x| x.v);
        if bi.is_some() {
            out[0] = generalised(&ri, &ai, &p, &force, &torque);
        }
        if let Some(b) = bj {
            let (rj, pj, _, _) = pose(b, 1);
            let aj = rot(&pj);
            let nf = force.map(|x| -x);
            let nt = torque.map(|x| -x);
            out[1] = generalised(&rj, &aj, &p, &nf, &nt);
        }
        ([bi, bj], out, measures)
    }

    /// Element loads and measures at f64 (residual, outputs).
    pub fn force_eval(&self, fe: usize, t: f64, q: &[f64], v: &[f64]) -> ElementForces<f64> {
        let pose = |b: usize, _side: usize| {
            (
                [q[7 * b], q[7 * b + 1], q[7 * b + 2]],
                [q[7 * b + 3], q[7 * b + 4], q[7 * b + 5], q[7 * b + 6]],
                [v[6 * b], v[6 * b + 1], v[6 * b + 2]],
                [v[6 * b + 3], v[6 * b + 4], v[6 * b + 5]],
            )
        };
        self.force_generalised::<f64>(fe, t, &pose)
    }

    /// Element loads with derivatives d/d(q_a, v_a, q_b, v_b), 26 columns.
    pub fn force_eval_dual(
        &self,
        fe: usize,
        t: f64,
        q: &[f64],
        v: &[f64],
    ) -> ([Option<usize>; 2], [[S26; 6]; 2]) {
        let pose = |b: usize, side: usize| {
            let o = 13 * side;
            (
                std::array::from_fn(|c| S26::var(q[7 * b + c], o + c)),
                std::array::from_fn(|c| S26::var(q[7 * b + 3 + c], o + 3 + c)),
                std::array::from_fn(|c| S26::var(v[6 * b + c], o + 7 + c)),
                std::array::from_fn(|c| S26::var(v[6 * b + 3 + c], o + 10 + c)),
            )
        };
        let (b, g, _) = self.force_generalised::<S26>(fe, t, &pose);
        (b, g)
    }

    /// Name of force element `fe`.
    pub fn force_name(&self, fe: usize) -> String {
        self.model.forces[self.felems[fe].0].name().to_string()
    }

    /// Number of force elements.
    pub fn n_forces(&self) -> usize {
        self.felems.len()
    }

    /// Sum of element loads, gravity and gyroscopic terms: the generalised force vector
    /// f(q, v) with M v' = f - B^T lambda (6 per body).
    pub fn applied(&self, t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
        let nb = self.nb();
        let mut f = vec![0.0; 6 * nb];
        let g = self.model.gravity;
        for (k, b) in self.model.bodies.iter().enumerate() {
            let w = [v[6 * k + 3], v[6 * k + 4], v[6 * k + 5]];
            let jw = mvc(&cst33::<f64>(&b.inertia), &w);
            let gyro = super::math::cross(&w, &jw);
            for c in 0..3 {
                f[6 * k + c] += b.mass * g[c];
                f[6 * k + 3 + c] -= gyro[c];
            }
        }
        for fe in 0..self.felems.len() {
            let (bs, gl, _) = self.force_eval(fe, t, q, v);
            for s in 0..2 {
                if let Some(b) = bs[s] {
                    for c in 0..6 {
                        f[6 * b + c] += gl[s][c];
                    }
                }
            }
        }
        f
    }

    /// Kept constraint rows: g, g_t and B as (row, velocity column, value) triplets with
    /// the velocity column counted from 0 (6 per body).
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
                        for c in 0..6 {
                            let val = ev.b[r][6 * side + c];
                            if val != 0.0 {
                                b.push((row, 6 * bb + c, val));
                            }
                        }
                    }
                }
            }
        }
        (g, gt, b)
    }
}

impl DaeProblem for System {
    fn size(&self) -> usize {
        13 * self.nb() + 2 * self.m
    }

    fn residual(&self, t: f64, y: &[f64], yp: &[f64], res: &mut [f64]) {
        let nb = self.nb();
        let (_, ov, ol, om) = self.offsets();
        let q = &y[..7 * nb];
        let v = &y[ov..ol];
        let lam = &y[ol..om];
        let mu = &y[om..];
        // kinematics and dynamics without constraint terms
        let f = self.applied(t, q, v);
        // B^T mu and B^T lambda accumulated in velocity space
        let mut btmu = vec![0.0; 6 * nb];
        let mut btl = vec![0.0; 6 * nb];
        let (g, gt, b) = self.constraints(t, q);
        let mut bv = gt;
        for &(r, c, val) in &b {
            btmu[c] += val * mu[r];
            btl[c] += val * lam[r];
            bv[r] += val * v[c];
        }
        for (k, body) in self.model.bodies.iter().enumerate() {
            let p = [q[7 * k + 3], q[7 * k + 4], q[7 * k + 5], q[7 * k + 6]];
            for c in 0..3 {
                res[7 * k + c] = yp[7 * k + c] - v[6 * k + c] + btmu[6 * k + c];
            }
            let w = [
                v[6 * k + 3] - btmu[6 * k + 3],
                v[6 * k + 4] - btmu[6 * k + 4],
                v[6 * k + 5] - btmu[6 * k + 5],
            ];
            let pd = qdot(&p, &w);
            for c in 0..4 {
                res[7 * k + 3 + c] = yp[7 * k + 3 + c] - pd[c];
            }
            let vd = &yp[ov + 6 * k..ov + 6 * k + 6];
            let jwd = mvc(&cst33::<f64>(&body.inertia), &[vd[3], vd[4], vd[5]]);
            for c in 0..3 {
                res[ov + 6 * k + c] = body.mass * vd[c] - f[6 * k + c] + btl[6 * k + c];
                res[ov + 6 * k + 3 + c] = jwd[c] - f[6 * k + 3 + c] + btl[6 * k + 3 + c];
            }
        }
        res[ol..om].copy_from_slice(&g);
        res[om..].copy_from_slice(&bv);
    }

    fn var_kinds(&self) -> Vec<VarKind> {
        let mut k = vec![VarKind::Differential; 13 * self.nb()];
        k.extend(std::iter::repeat_n(VarKind::Index2, 2 * self.m));
        k
    }

    fn jacobian_pattern(&self) -> Option<Vec<(usize, usize)>> {
        let mut e = Vec::new();
        let y = vec![1.0; self.size()];
        let mut sink = JacobianSink { entries: &mut e };
        self.jacobian_entries(0.0, &y, 1.0, &mut sink, true);
        let mut p: Vec<(usize, usize)> = e.iter().map(|&(r, c, _)| (r, c)).collect();
        p.sort_unstable();
        p.dedup();
        Some(p)
    }

    fn jacobian(&self, t: f64, y: &[f64], _yp: &[f64], cj: f64, jac: &mut JacobianSink) -> bool {
        self.jacobian_entries(t, y, cj, jac, false);
        true
    }

    fn var_name(&self, i: usize) -> String {
        self.unknown_name(i)
    }

    fn eq_name(&self, i: usize) -> String {
        self.equation_name(i)
    }
}
