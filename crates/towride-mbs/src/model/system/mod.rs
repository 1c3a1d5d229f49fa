//! The assembled equations of a [`Model`]: a stabilised index-2 (GGL) DAE in absolute
//! coordinates with quaternions, implementing [`DaeProblem`] with a sparse iteration
//! matrix.
//!
//! Unknowns, per body k: q_k = (r (3, centre of mass, world), p (4, quaternion), eta
//! (modal coordinates of a modal body)), v_k = (u = r' (3), omega (3, body axes), zeta =
//! eta'); then the multipliers lambda (one per kept constraint row), the GGL multipliers
//! mu, and the states of the extension elements (tyres, speed controllers). Equations:
//!
//! ```text
//! r' - u + B_u^T mu                                 = 0   (3 per body)
//! p' - Q(p) (omega - B_w^T mu) / 2                  = 0   (4 per body)
//! eta' - zeta + B_eta^T mu                          = 0   (modes)
//! m u' - m g - F + B_u^T lambda                     = 0   (3 per body)
//! J omega' + omega x J omega - T + B_w^T lambda     = 0   (3 per body)
//! zeta' + C zeta + K eta - Q_eta + B_eta^T lambda   = 0   (modes)
//! g(q, t)                                           = 0   (one per kept row)
//! B v + g_t                                         = 0   (one per kept row)
//! extension residuals (tyre states, controller integrators)
//! ```
//!
//! B = dg/dx is the constraint Jacobian in velocity space (virtual displacement, body-axes
//! rotation, modal coordinates); F, T and Q_eta are the element and extension loads. The
//! mu terms make position and velocity constraints hold together (Gear, Gupta &
//! Leimkuhler 1985); mu = 0 on the exact solution, so its O(mu) second-derivative terms are
//! left out of the iteration matrix. Modal bodies: unit modal mass, modal stiffness and
//! damping, mass coupling per [`crate::model::desc::Coupling`] (see `modal.rs`); a body
//! at the `full` level has M(q) v' over its whole velocity block (`full.rs`).

use nalgebra::DMatrix;

use super::desc::{BodyHandle, JointHandle, MarkerHandle, Model};
use super::joint::{rows, Row};
use super::math::{cst33, mvc, qdot, quat_from_matrix, rot};
use towride_solver::problem::{DaeProblem, JacobianSink, VarKind};

mod constraint;
pub(crate) mod control;
pub(crate) mod ext;
pub(crate) mod flexmarker;
mod forces;
mod full;
mod jacobian;
mod modal;
mod transport;

pub use constraint::{ConEval, ConEval2};
pub use ext::{Ext, ExtKind};
pub use forces::{BodyPose, ElementForces};

/// Who owns a constraint row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Owner {
    /// A joint.
    Joint(JointHandle),
    /// A prescribed motion (index into `Model::motions`).
    Motion(usize),
}

/// One constraint row of an element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConRow {
    /// A primitive joint row (what it locks).
    Prim(Row),
    /// The driving row of a prescribed motion.
    Drive(super::desc::MotionDof),
}

/// A constraint element: a joint or a motion, its markers and rows.
#[derive(Clone, Debug)]
pub struct ConElem {
    /// The joint or motion.
    pub owner: Owner,
    /// Marker I.
    pub mi: MarkerHandle,
    /// Marker J.
    pub mj: MarkerHandle,
    /// The element's constraint rows.
    pub rows: Vec<ConRow>,
    /// Global multiplier index of each row, `None` when the row was found redundant.
    pub slot: Vec<Option<usize>>,
}

/// A dropped row and the kept rows it depends on.
#[derive(Clone, Debug)]
pub struct Redundant {
    /// The constraint element (index into `System::cons`).
    pub elem: usize,
    /// The dropped row within the element.
    pub row: usize,
    /// (element, row, coefficient) of the kept rows that reproduce it.
    pub depends_on: Vec<(usize, usize, f64)>,
}

/// One body's block of the velocity-space mass matrix.
pub enum MassBlock {
    /// m I, the inertia J (body axes) and the unit modal mass: rigid bodies and modal
    /// bodies without deformation-dependent inertia coupling.
    Diagonal {
        /// Body mass [kg].
        mass: f64,
        /// Inertia tensor about the centre of mass, body axes [kg m^2].
        inertia: [[f64; 3]; 3],
    },
    /// The whole (6 + modes) block of a `full` modal body.
    Full(DMatrix<f64>),
}

/// How far ahead (in travel time) the road is checked for obstacles before a step [s]:
/// also the largest step taken on flat road, below a tenth of the body modes' periods.
const ROAD_LOOK_AHEAD_S: f64 = 0.02;

/// Kept constraint rows: g, g_t and B as (row, velocity column, value) triplets.
pub type ConstraintSet = (Vec<f64>, Vec<f64>, Vec<(usize, usize, f64)>);

/// The assembled mechanism.
pub struct System {
    /// The model the system was assembled from.
    pub model: Model,
    /// Constraint elements (joints and motions) with their rows.
    pub cons: Vec<ConElem>,
    /// Rows dropped as redundant, with the kept rows they depend on.
    pub redundant: Vec<Redundant>,
    /// Number of kept constraint rows.
    pub m: usize,
    /// Per body: offset of its position unknowns in q, of its velocity unknowns in v, and
    /// its number of modal coordinates.
    pub qo: Vec<usize>,
    /// Velocity-unknown offset of each body in v.
    pub vo: Vec<usize>,
    /// Number of modal coordinates of each body.
    pub nm: Vec<usize>,
    /// Sizes of the q and v blocks.
    pub nq: usize,
    /// Size of the v block.
    pub nv: usize,
    /// Extension elements (tyres, speed controllers) and their total number of states.
    pub ext: Vec<Ext>,
    /// Total number of extension states.
    pub ne: usize,
    /// Speed controllers act (false during statics: a car at rest is not driven).
    pub controls_active: std::cell::Cell<bool>,
    /// The sparse matrix [M B^T; B 0] of the acceleration-level solve, structure built
    /// once (outputs solve it at every sample).
    pub(crate) accel: std::cell::RefCell<Option<towride_solver::linear::NewtonMatrix>>,
    /// The sparse symmetric matrix B W B^T of the start and the outputs on large models
    /// (`model::normal`), symbolic analysis made once.
    pub(crate) normal: std::cell::RefCell<Option<towride_solver::linear::SparseCholesky>>,
    /// Marker axes as quaternions (body frame), for bushings; in `Model::markers` order.
    mquat: Vec<[f64; 4]>,
    /// Per body: the mass-matrix tensors of a modal body at the `full` coupling level.
    full: Vec<Option<full::FullTensors>>,
    /// The wheels whose frames a re-used iteration matrix follows (`transport.rs`).
    spinning: Vec<usize>,
}

impl System {
    /// Assembles a validated model at its initial configuration: lays out the unknowns,
    /// numbers the constraint rows and drops the redundant ones (see
    /// [`super::redundancy`]).
    pub fn new(model: Model) -> System {
        let mut cons = Vec::new();
        for (k, j) in model.each_joint() {
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
        let (mut qo, mut vo, mut nm) = (Vec::new(), Vec::new(), Vec::new());
        let (mut nq, mut nv) = (0, 0);
        for b in &model.bodies {
            let n = b.modal.as_ref().map_or(0, |m| m.data.modes.len());
            qo.push(nq);
            vo.push(nv);
            nm.push(n);
            nq += 7 + n;
            nv += 6 + n;
        }
        let (ext, ne) = ext::layout(&model);
        let full = model.bodies.iter().map(full::FullTensors::of).collect();
        let mut sys = System {
            model,
            cons,
            redundant: Vec::new(),
            m: 0,
            qo,
            vo,
            nm,
            nq,
            nv,
            ext,
            ne,
            controls_active: std::cell::Cell::new(true),
            accel: std::cell::RefCell::new(None),
            normal: std::cell::RefCell::new(None),
            mquat,
            full,
            spinning: Vec::new(),
        };
        sys.spinning = sys.spinning_bodies();
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

    /// Number of bodies.
    pub fn nb(&self) -> usize {
        self.model.bodies.len()
    }

    /// Offsets: q block, v block, lambda, mu.
    pub fn offsets(&self) -> (usize, usize, usize, usize) {
        (0, self.nq, self.nq + self.nv, self.nq + self.nv + self.m)
    }

    /// Offset of the extension states.
    pub fn oe(&self) -> usize {
        self.nq + self.nv + 2 * self.m
    }

    /// Total number of unknowns.
    pub fn size(&self) -> usize {
        self.oe() + self.ne
    }

    /// Position and quaternion of body `b`.
    pub fn pose(&self, q: &[f64], b: usize) -> ([f64; 3], [f64; 4]) {
        let o = self.qo[b];
        (
            [q[o], q[o + 1], q[o + 2]],
            [q[o + 3], q[o + 4], q[o + 5], q[o + 6]],
        )
    }

    /// Velocity of the centre of mass (world) and angular velocity (body axes) of body `b`.
    pub fn twist(&self, v: &[f64], b: usize) -> ([f64; 3], [f64; 3]) {
        let o = self.vo[b];
        ([v[o], v[o + 1], v[o + 2]], [v[o + 3], v[o + 4], v[o + 5]])
    }

    /// Positions and velocities from the bodies' initial values (world angular velocity
    /// turned into body axes, modal coordinates zero).
    pub fn initial_q_v(&self) -> (Vec<f64>, Vec<f64>) {
        let mut q = Vec::with_capacity(self.nq);
        let mut v = Vec::with_capacity(self.nv);
        for (k, b) in self.model.bodies.iter().enumerate() {
            q.extend_from_slice(&b.position);
            q.extend_from_slice(&b.orientation);
            q.extend(std::iter::repeat_n(0.0, self.nm[k]));
            let a = rot(&b.orientation);
            let wb = super::math::mtv(&a, &b.angular_velocity);
            v.extend_from_slice(&b.velocity);
            v.extend_from_slice(&wb);
            v.extend(std::iter::repeat_n(0.0, self.nm[k]));
        }
        (q, v)
    }

    /// Applies a velocity-space increment dx to positions: r += dr,
    /// p <- p (x) exp(dtheta / 2) renormalised, eta += deta.
    pub fn apply_increment(&self, q: &mut [f64], dx: &[f64]) {
        for k in 0..self.nb() {
            let (o, w) = (self.qo[k], self.vo[k]);
            for c in 0..3 {
                q[o + c] += dx[w + c];
            }
            let th = [dx[w + 3], dx[w + 4], dx[w + 5]];
            let a = (th[0] * th[0] + th[1] * th[1] + th[2] * th[2]).sqrt();
            let (s, c) = if a > 1e-12 {
                ((0.5 * a).sin() / a, (0.5 * a).cos())
            } else {
                (0.5, 1.0)
            };
            let e = [c, s * th[0], s * th[1], s * th[2]];
            let p = [q[o + 3], q[o + 4], q[o + 5], q[o + 6]];
            let np = super::math::qmul(&p, &e);
            let n = np.iter().map(|x| x * x).sum::<f64>().sqrt();
            for c in 0..4 {
                q[o + 3 + c] = np[c] / n;
            }
            for j in 0..self.nm[k] {
                q[o + 7 + j] += dx[w + 6 + j];
            }
        }
    }

    /// q' from v (r' = u, p' = Q(p) omega / 2, eta' = zeta).
    pub fn qdot_of(&self, q: &[f64], v: &[f64]) -> Vec<f64> {
        let mut qd = vec![0.0; self.nq];
        for k in 0..self.nb() {
            let (o, w) = (self.qo[k], self.vo[k]);
            qd[o..o + 3].copy_from_slice(&v[w..w + 3]);
            let pd = qdot(
                &[q[o + 3], q[o + 4], q[o + 5], q[o + 6]],
                &[v[w + 3], v[w + 4], v[w + 5]],
            );
            qd[o + 3..o + 7].copy_from_slice(&pd);
            qd[o + 7..o + 7 + self.nm[k]].copy_from_slice(&v[w + 6..w + 6 + self.nm[k]]);
        }
        qd
    }

    /// dq/dx: the map from velocity-space increments to position increments at q
    /// (nq x nv, as (row, column, value) triplets).
    pub fn q_map(&self, q: &[f64]) -> Vec<(usize, usize, f64)> {
        let mut out = Vec::new();
        for k in 0..self.nb() {
            let (o, w) = (self.qo[k], self.vo[k]);
            for c in 0..3 {
                out.push((o + c, w + c, 1.0));
            }
            let qm = super::math::qmat(&[q[o + 3], q[o + 4], q[o + 5], q[o + 6]]);
            for a in 0..4 {
                for c in 0..3 {
                    out.push((o + 3 + a, w + 3 + c, 0.5 * qm[a][c]));
                }
            }
            for j in 0..self.nm[k] {
                out.push((o + 7 + j, w + 6 + j, 1.0));
            }
        }
        out
    }

    /// The velocity-space mass matrix at the initial positions (see
    /// [`System::mass_entries_at`]).
    pub fn mass_entries(&self) -> Vec<(usize, usize, f64)> {
        self.mass_entries_at(&self.initial_q_v().0)
    }

    /// The velocity-space mass matrix at positions `q` as (row, column, value) triplets:
    /// block diagonal (m I, J, identity modal mass) except for `full` modal bodies, whose
    /// whole block depends on q (same entries at every q).
    pub fn mass_entries_at(&self, q: &[f64]) -> Vec<(usize, usize, f64)> {
        let mut out = Vec::new();
        for k in 0..self.nb() {
            let w = self.vo[k];
            match self.mass_block(k, q) {
                MassBlock::Full(mb) => {
                    for r in 0..mb.nrows() {
                        for c in 0..mb.ncols() {
                            out.push((w + r, w + c, mb[(r, c)]));
                        }
                    }
                }
                MassBlock::Diagonal { mass, inertia } => {
                    for c in 0..3 {
                        out.push((w + c, w + c, mass));
                        for d in 0..3 {
                            out.push((w + 3 + c, w + 3 + d, inertia[c][d]));
                        }
                    }
                    for j in 0..self.nm[k] {
                        out.push((w + 6 + j, w + 6 + j, 1.0));
                    }
                }
            }
        }
        out
    }

    /// Body `k`'s block of the velocity-space mass matrix at `q`.
    pub fn mass_block(&self, k: usize, q: &[f64]) -> MassBlock {
        match self.full_mass(k, q) {
            Some(mb) => MassBlock::Full(mb),
            None => {
                let b = &self.model.bodies[k];
                MassBlock::Diagonal {
                    mass: b.mass,
                    inertia: b.inertia,
                }
            }
        }
    }

    /// World frame of marker `k` for given positions (f64).
    pub fn marker_frame(&self, q: &[f64], k: MarkerHandle) -> super::joint::MFrame<f64> {
        let mk = &self.model.markers[k];
        match mk.body {
            None => super::joint::MFrame {
                origin: mk.position,
                axes: mk.axes,
            },
            Some(_) => {
                let f = self.flex_frame(q, k);
                super::joint::MFrame {
                    origin: f.origin,
                    axes: f.axes,
                }
            }
        }
    }

    /// The body (`None`: ground) of marker `k` as the system numbers bodies, the index of
    /// its offsets in `qo`, `vo` and `nm`.
    pub fn body_of(&self, k: MarkerHandle) -> Option<usize> {
        // The one place a body handle becomes the system's body number: the equations
        // lay the bodies out in the model's order.
        self.model.markers[k].body.map(BodyHandle::index)
    }

    /// The bodies (or ground) of an element's two markers, numbered as [`System::body_of`].
    pub fn bodies_of(&self, mi: MarkerHandle, mj: MarkerHandle) -> [Option<usize>; 2] {
        [self.body_of(mi), self.body_of(mj)]
    }

    /// Marker `k`'s axes as a quaternion in its body's frame.
    pub(crate) fn marker_quat(&self, k: MarkerHandle) -> [f64; 4] {
        // A table in the model's marker order, built once at assembly.
        self.mquat[k.index()]
    }

    /// Absolute tolerances per unknown for a run: 1e-6 m / 1e-6 (quaternions) / 1e-7 on
    /// modal coordinates (unit modal mass: about 0.5 micrometre on a few-kg crossbeam),
    /// 1e-4 m/s on velocities, 1e-2 on multipliers (N, N m; their error is scaled by the
    /// step), the extension elements' own hints. All times `scale`.
    pub fn atol(&self, scale: f64) -> Vec<f64> {
        let mut out = vec![1e-6 * scale; self.nq];
        for b in 0..self.nb() {
            for j in 0..self.nm[b] {
                out[self.qo[b] + 7 + j] = 1e-7 * scale;
            }
        }
        out.extend(std::iter::repeat_n(1e-4 * scale, self.nv));
        for b in 0..self.nb() {
            for j in 0..self.nm[b] {
                out[self.nq + self.vo[b] + 6 + j] = 1e-4 * scale;
            }
        }
        out.extend(std::iter::repeat_n(1e-2 * scale, 2 * self.m));
        out.extend(self.ext_atol(scale));
        out
    }

    /// Number of velocity unknowns of a body (6 for ground).
    pub fn width(&self, b: Option<usize>) -> usize {
        b.map_or(6, |b| 6 + self.nm[b])
    }
}

impl DaeProblem for System {
    fn size(&self) -> usize {
        System::size(self)
    }

    /// Each body's rotation quaternion and its angular velocity in body axes.
    fn magnitude_groups(&self) -> Vec<std::ops::Range<usize>> {
        let mut g = Vec::new();
        for b in 0..self.nb() {
            g.push(self.qo[b] + 3..self.qo[b] + 7);
            g.push(self.nq + self.vo[b] + 3..self.nq + self.vo[b] + 6);
        }
        g
    }

    fn residual(&self, t: f64, y: &[f64], yp: &[f64], res: &mut [f64]) {
        let (_, ov, ol, om) = self.offsets();
        let oe = self.oe();
        let q = &y[..ov];
        let v = &y[ov..ol];
        let lam = &y[ol..om];
        let mu = &y[om..oe];
        let x = &y[oe..];
        // Loads and extension residuals.
        let f = self.loads(t, q, v, x, Some((&yp[oe..], &mut res[oe..])));
        // B^T mu and B^T lambda accumulated in velocity space
        let mut btmu = vec![0.0; self.nv];
        let mut btl = vec![0.0; self.nv];
        let (g, gt, b) = self.constraints(t, q);
        let mut bv = gt;
        for &(r, c, val) in &b {
            btmu[c] += val * mu[r];
            btl[c] += val * lam[r];
            bv[r] += val * v[c];
        }
        for (k, body) in self.model.bodies.iter().enumerate() {
            let (o, w) = (self.qo[k], self.vo[k]);
            let p = [q[o + 3], q[o + 4], q[o + 5], q[o + 6]];
            for c in 0..3 {
                res[o + c] = yp[o + c] - v[w + c] + btmu[w + c];
            }
            let wv = [
                v[w + 3] - btmu[w + 3],
                v[w + 4] - btmu[w + 4],
                v[w + 5] - btmu[w + 5],
            ];
            let pd = qdot(&p, &wv);
            for c in 0..4 {
                res[o + 3 + c] = yp[o + 3 + c] - pd[c];
            }
            for j in 0..self.nm[k] {
                res[o + 7 + j] = yp[o + 7 + j] - v[w + 6 + j] + btmu[w + 6 + j];
            }
            if let Some(mb) = self.full_mass(k, q) {
                // M(q) v' over the whole block of a `full` modal body.
                let n = 6 + self.nm[k];
                let vd = &yp[ov + w..ov + w + n];
                for r in 0..n {
                    let mv: f64 = (0..n).map(|c| mb[(r, c)] * vd[c]).sum();
                    res[ov + w + r] = mv - f[w + r] + btl[w + r];
                }
                continue;
            }
            let vd = &yp[ov + w..ov + w + 6];
            let jwd = mvc(&cst33::<f64>(&body.inertia), &[vd[3], vd[4], vd[5]]);
            for c in 0..3 {
                res[ov + w + c] = body.mass * vd[c] - f[w + c] + btl[w + c];
                res[ov + w + 3 + c] = jwd[c] - f[w + 3 + c] + btl[w + 3 + c];
            }
            for j in 0..self.nm[k] {
                res[ov + w + 6 + j] = yp[ov + w + 6 + j] - f[w + 6 + j] + btl[w + 6 + j];
            }
        }
        res[ol..om].copy_from_slice(&g);
        res[om..oe].copy_from_slice(&bv);
    }

    fn max_step(&self, _t: f64, y: &[f64]) -> Option<f64> {
        let (_, ov, ol, _) = self.offsets();
        self.road_step_limit(&y[..ov], &y[ov..ol], ROAD_LOOK_AHEAD_S)
    }

    fn var_kinds(&self) -> Vec<VarKind> {
        let mut k = vec![VarKind::Differential; self.nq + self.nv];
        k.extend(std::iter::repeat_n(VarKind::Index2, 2 * self.m));
        k.extend(self.ext_var_kinds());
        k
    }

    fn jacobian_pattern(&self) -> Option<Vec<(usize, usize)>> {
        let mut e = Vec::new();
        let y = self.structural_state();
        let mut sink = JacobianSink::new(&mut e);
        self.jacobian_entries(0.0, &y, 1.0, &mut sink, true);
        // Bucketed by column and deduplicated with a marker, in O(entries): the
        // structural evaluation repeats entries (about 2.6 times on a chain), and a
        // comparison sort of them was 60 % of the integrator's set-up at 18 k unknowns.
        let n = self.size();
        let mut start = vec![0usize; n + 1];
        for &(_, c, _) in &e {
            start[c + 1] += 1;
        }
        for c in 0..n {
            start[c + 1] += start[c];
        }
        let mut rows = vec![0usize; e.len()];
        let mut fill = start.clone();
        for &(r, c, _) in &e {
            rows[fill[c]] = r;
            fill[c] += 1;
        }
        let mut seen = vec![usize::MAX; n];
        let mut p = Vec::with_capacity(e.len());
        for c in 0..n {
            for &r in &rows[start[c]..start[c + 1]] {
                if seen[r] != c {
                    seen[r] = c;
                    p.push((r, c));
                }
            }
        }
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

    fn transport(
        &self,
        built: &[f64],
        now: &[f64],
        v: &mut [f64],
        side: towride_solver::problem::Transport,
    ) {
        self.transport_frames(built, now, v, side);
    }

    fn has_transport(&self) -> bool {
        !self.spinning.is_empty()
    }
}
