//! The iteration matrix dF/dy + cj dF/dy' of [`System`]: analytic for bodies, rigid force
//! elements and constraints, finite differences over the few unknowns they touch for
//! elements on modal markers and for extension elements (tyres, controllers).

use super::{ConElem, ConRow, Ext, Owner, System};
use crate::model::desc::{ElementHandle, MotionDof};
use crate::model::math::{cst33, mvc, qmat};
use towride_solver::problem::JacobianSink;

impl System {
    /// A generic state for the sparsity pattern: unit quaternions, every other unknown 1
    /// so no derivative is accidentally zero.
    pub fn structural_state(&self) -> Vec<f64> {
        let mut y = vec![1.0; self.size()];
        let (q0, _) = self.initial_q_v();
        y[..self.nq].copy_from_slice(&q0);
        y
    }

    /// Iteration matrix entries; with `structural`, every possible non-zero is emitted
    /// (values meaningless) so the pattern does not depend on the state.
    pub fn jacobian_entries(
        &self,
        t: f64,
        y: &[f64],
        cj: f64,
        jac: &mut JacobianSink,
        structural: bool,
    ) {
        let (_, ov, ol, om) = self.offsets();
        let q = &y[..ov];
        let v = &y[ov..ol];
        let lam = &y[ol..om];
        let pick = |x: f64| if structural { 1.0 } else { x };
        self.body_blocks(q, v, cj, jac, structural);
        // Force elements: -dQ/d(q, v).
        for (fe, _) in self.model.each_element() {
            if self.force_is_flex(fe) {
                self.fd_force(fe, t, q, v, jac, structural);
                continue;
            }
            let (bs, gl) = self.force_eval_dual(fe, t, q, v);
            for s in 0..2 {
                let Some(b) = bs[s] else { continue };
                for c in 0..6 {
                    let d = &gl[s][c].d;
                    for (side, body) in bs.iter().enumerate() {
                        let Some(bb) = body else { continue };
                        for l in 0..13 {
                            let val = -d[13 * side + l];
                            if structural || val != 0.0 {
                                let col = if l < 7 {
                                    self.qo[*bb] + l
                                } else {
                                    ov + self.vo[*bb] + l - 7
                                };
                                jac.add(ov + self.vo[b] + c, col, pick(val));
                            }
                        }
                    }
                }
            }
        }
        self.constraint_blocks(t, q, v, lam, jac, structural);
        let oe = self.oe();
        for e in &self.ext {
            self.fd_ext(e, t, y, cj, jac, structural, oe);
        }
    }

    fn body_blocks(&self, q: &[f64], v: &[f64], cj: f64, jac: &mut JacobianSink, structural: bool) {
        let ov = self.nq;
        let pick = |x: f64| if structural { 1.0 } else { x };
        for (k, body) in self.model.bodies.iter().enumerate() {
            let (o, w) = (self.qo[k], self.vo[k]);
            let (qr, qp, vu, vw) = (o, o + 3, ov + w, ov + w + 3);
            let full = self.full[k].is_some();
            // cj terms through add_scaled: they are dF/dy' (identity, mass, inertia).
            for c in 0..3 {
                jac.add_scaled(qr + c, qr + c, cj, 1.0);
                jac.add(qr + c, vu + c, -1.0);
                if !full {
                    jac.add_scaled(vu + c, vu + c, cj, body.mass);
                }
            }
            let p = [q[qp], q[qp + 1], q[qp + 2], q[qp + 3]];
            let om = [v[w + 3], v[w + 4], v[w + 5]];
            // d(p (x) (0,w))/dp (B^T mu term dropped, mu = 0 on the solution)
            let rw = [
                [0.0, -om[0], -om[1], -om[2]],
                [om[0], 0.0, om[2], -om[1]],
                [om[1], -om[2], 0.0, om[0]],
                [om[2], om[1], -om[0], 0.0],
            ];
            let qm = qmat(&p);
            for a in 0..4 {
                for bcol in 0..4 {
                    let val = -0.5 * rw[a][bcol];
                    if structural || val != 0.0 {
                        jac.add(qp + a, qp + bcol, pick(val));
                    }
                }
                jac.add_scaled(qp + a, qp + a, cj, 1.0);
                for c in 0..3 {
                    jac.add(qp + a, vw + c, pick(-0.5 * qm[a][c]));
                }
            }
            if full {
                self.full_blocks(k, q, v, cj, jac, structural);
            }
            // J w' + w x J w: d(w x Jw)/dw = [w]x J - [Jw]x
            let jm = body.inertia;
            let jw = mvc(&cst33::<f64>(&jm), &om);
            let skew = |a: [f64; 3]| [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
            let sw = skew(om);
            let sjw = skew(jw);
            for r in 0..3 {
                for c in 0..3 {
                    let mut val = -sjw[r][c];
                    for l in 0..3 {
                        val += sw[r][l] * jm[l][c];
                    }
                    if !full {
                        jac.add(vw + r, vw + c, pick(val));
                        jac.add_scaled(vw + r, vw + c, cj, jm[r][c]);
                    }
                }
            }
            let Some(m) = &body.modal else { continue };
            for (j, mode) in m.data.modes.iter().enumerate() {
                let (qe, ve) = (o + 7 + j, ov + w + 6 + j);
                jac.add_scaled(qe, qe, cj, 1.0);
                jac.add(qe, ve, -1.0);
                let wn = mode.stiffness.max(0.0).sqrt();
                if !full {
                    jac.add_scaled(ve, ve, cj, 1.0);
                }
                jac.add(ve, ve, pick(2.0 * mode.damping_ratio * wn));
                jac.add(ve, qe, pick(mode.stiffness));
                if m.coupling == crate::model::desc::Coupling::Partial {
                    let i8 = &m.data.invariants.i8[j];
                    for a in 0..3 {
                        let d: f64 = (0..3).map(|b| (i8[a][b] + i8[b][a]) * om[b]).sum();
                        jac.add(ve, vw + a, pick(-d));
                    }
                }
            }
        }
    }

    /// A `full` modal body: cj M(q) over its velocity block, and the derivatives of its
    /// quadratic-velocity terms by finite differences over omega, zeta and eta. The
    /// terms dM/d(eta, p) v' are left out (modified Newton; the residual is exact).
    fn full_blocks(
        &self,
        k: usize,
        q: &[f64],
        v: &[f64],
        cj: f64,
        jac: &mut JacobianSink,
        structural: bool,
    ) {
        let (ov, o, w, n) = (self.nq, self.qo[k], self.vo[k], 6 + self.nm[k]);
        let cols: Vec<(bool, usize)> = (3..n)
            .map(|c| (false, w + c))
            .chain((0..self.nm[k]).map(|j| (true, o + 7 + j)))
            .collect();
        if structural {
            for r in 0..n {
                for c in 0..n {
                    jac.add(ov + w + r, ov + w + c, 1.0);
                }
                for &(is_q, i) in &cols {
                    jac.add(ov + w + r, if is_q { i } else { ov + i }, 1.0);
                }
            }
            return;
        }
        let mb = self.full_mass(k, q).expect("a full body");
        for r in 0..n {
            for c in 0..n {
                jac.add_scaled(ov + w + r, ov + w + c, cj, mb[(r, c)]);
            }
        }
        let base = self.full_velocity_terms(k, q, v);
        let (mut qq, mut vv) = (q.to_vec(), v.to_vec());
        for (is_q, i) in cols {
            let x = if is_q { &mut qq } else { &mut vv };
            let x0 = x[i];
            let h = 1e-7 * (1.0 + x0.abs());
            x[i] += h;
            let pert = self.full_velocity_terms(k, &qq, &vv);
            if is_q {
                qq[i] = x0;
            } else {
                vv[i] = x0;
            }
            let col = if is_q { i } else { ov + i };
            for r in 0..n {
                jac.add(ov + w + r, col, (pert[r] - base[r]) / h);
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn constraint_blocks(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        lam: &[f64],
        jac: &mut JacobianSink,
        structural: bool,
    ) {
        for e in &self.cons {
            if e.slot.iter().all(|s| s.is_none()) {
                continue;
            }
            if structural && !self.has_flex(e) {
                self.rigid_constraint_pattern(e, jac);
            } else {
                self.constraint_block(e, t, q, v, lam, jac, structural);
            }
        }
    }

    /// The entries [`Self::constraint_block`] emits for a constraint between rigid
    /// bodies with `structural` set (every entry, both sides 6 velocities and 7
    /// coordinates wide, second derivatives present), without evaluating it: the
    /// evaluation with dual numbers was most of the integrator's set-up on a chain.
    fn rigid_constraint_pattern(&self, e: &ConElem, jac: &mut JacobianSink) {
        let (_, ov, ol, om) = self.offsets();
        let bodies = self.bodies_of(e.mi, e.mj);
        for slot in &e.slot {
            let Some(row) = *slot else { continue };
            for b in bodies.iter().flatten() {
                let (o, w) = (self.qo[*b], self.vo[*b]);
                for c in 0..6 {
                    jac.add(ov + w + c, ol + row, 1.0);
                    jac.add(om + row, ov + w + c, 1.0);
                    if c < 3 {
                        jac.add(o + c, om + row, 1.0);
                    } else {
                        for a in 0..4 {
                            jac.add(o + 3 + a, om + row, 1.0);
                        }
                    }
                }
                for l in 0..7 {
                    jac.add(ol + row, o + l, 1.0);
                }
            }
            for qb in bodies.iter().flatten() {
                for l in 0..7 {
                    for b in bodies.iter().flatten() {
                        for c in 0..6 {
                            jac.add(ov + self.vo[*b] + c, self.qo[*qb] + l, 1.0);
                        }
                    }
                    jac.add(om + row, self.qo[*qb] + l, 1.0);
                }
            }
        }
    }

    /// The iteration-matrix entries of constraint element `e` (with `structural`, every
    /// possible one, values meaningless).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn constraint_block(
        &self,
        e: &ConElem,
        t: f64,
        q: &[f64],
        v: &[f64],
        lam: &[f64],
        jac: &mut JacobianSink,
        structural: bool,
    ) {
        let (_, ov, ol, om) = self.offsets();
        let pick = |x: f64| if structural { 1.0 } else { x };
        {
            let ev = self.con_eval2(e, t, q);
            let bodies = self.bodies_of(e.mi, e.mj);
            let wq = [ev.first.w[0] + 1, ev.first.w[1] + 1];
            for (r, slot) in e.slot.iter().enumerate() {
                let Some(row) = *slot else { continue };
                for (side, body) in bodies.iter().enumerate() {
                    let Some(b) = body else { continue };
                    let (o, w) = (self.qo[*b], self.vo[*b]);
                    for c in 0..ev.first.w[side] {
                        let bval = ev.first.at(r, side, c);
                        if !structural && bval == 0.0 {
                            continue;
                        }
                        let bval = pick(bval);
                        // dyn rows: B^T lambda; gv rows: B v
                        jac.add(ov + w + c, ol + row, bval);
                        jac.add(om + row, ov + w + c, bval);
                        // kinematic rows: B^T mu
                        if c < 3 {
                            jac.add(o + c, om + row, bval);
                        } else if c < 6 {
                            let p = [q[o + 3], q[o + 4], q[o + 5], q[o + 6]];
                            let qm = qmat(&p);
                            for a in 0..4 {
                                jac.add(o + 3 + a, om + row, pick(0.5 * qm[a][c - 3] * bval));
                            }
                        } else {
                            jac.add(o + 1 + c, om + row, bval);
                        }
                    }
                    for l in 0..wq[side] {
                        let gq = ev.gq[r][side * wq[0] + l];
                        if structural || gq != 0.0 {
                            jac.add(ol + row, o + l, pick(gq));
                        }
                    }
                }
                // Second-derivative terms: d(B^T lambda)/dq and d(B v + g_t)/dq.
                let Some(dbq) = &ev.dbq else { continue };
                for (qside, qbody) in bodies.iter().enumerate() {
                    let Some(qb) = qbody else { continue };
                    for l in 0..7 {
                        let lq = 7 * qside + l;
                        let mut dbv = dbq[r][12][lq];
                        for (side, body) in bodies.iter().enumerate() {
                            let Some(b) = body else { continue };
                            for c in 0..6 {
                                let d = dbq[r][6 * side + c][lq];
                                dbv += d * v[self.vo[*b] + c];
                                let val = d * lam[row];
                                if structural || val != 0.0 {
                                    jac.add(ov + self.vo[*b] + c, self.qo[*qb] + l, pick(val));
                                }
                            }
                        }
                        if structural || dbv != 0.0 {
                            jac.add(om + row, self.qo[*qb] + l, pick(dbv));
                        }
                    }
                }
            }
        }
    }

    /// Finite-difference block of a force element on a modal marker: -d f / d(q, v) of
    /// its bodies.
    fn fd_force(
        &self,
        fe: ElementHandle,
        t: f64,
        q: &[f64],
        v: &[f64],
        jac: &mut JacobianSink,
        structural: bool,
    ) {
        let ov = self.nq;
        let mut bodies: Vec<usize> = self.force_bodies(fe).into_iter().flatten().collect();
        bodies.dedup();
        let gather = |q: &[f64], v: &[f64]| -> Vec<(usize, f64)> {
            let (bs, gl, _) = self.force_eval(fe, t, q, v);
            let mut out = Vec::new();
            for s in 0..2 {
                if let Some(b) = bs[s] {
                    for (c, x) in gl[s].iter().enumerate() {
                        out.push((self.vo[b] + c, *x));
                    }
                }
            }
            out
        };
        let base = gather(q, v);
        let (mut qq, mut vv) = (q.to_vec(), v.to_vec());
        for &b in &bodies {
            let cols: Vec<(bool, usize)> = (self.qo[b]..self.qo[b] + 7 + self.nm[b])
                .map(|i| (true, i))
                .chain((self.vo[b]..self.vo[b] + 6 + self.nm[b]).map(|i| (false, i)))
                .collect();
            for (is_q, i) in cols {
                let col = if is_q { i } else { ov + i };
                if structural {
                    for &(r, _) in &base {
                        jac.add(ov + r, col, 1.0);
                    }
                    continue;
                }
                let x0 = if is_q { qq[i] } else { vv[i] };
                let h = 1e-7 * (1.0 + x0.abs());
                if is_q {
                    qq[i] += h;
                } else {
                    vv[i] += h;
                }
                let pert = gather(&qq, &vv);
                if is_q {
                    qq[i] = x0;
                } else {
                    vv[i] = x0;
                }
                for (&(r, a), &(_, b)) in base.iter().zip(&pert) {
                    let d = -(b - a) / h;
                    if d != 0.0 {
                        jac.add(ov + r, col, d);
                    }
                }
            }
        }
    }

    /// Finite-difference block of an extension element: its own rows and the loaded
    /// bodies' force rows, over the bodies' (q, v), its states and (times cj) their rates.
    #[allow(clippy::too_many_arguments)]
    fn fd_ext(
        &self,
        e: &Ext,
        t: f64,
        y: &[f64],
        cj: f64,
        jac: &mut JacobianSink,
        structural: bool,
        oe: usize,
    ) {
        let (_, ov, ol, _) = self.offsets();
        let bodies = self.ext_bodies(e);
        let rows_f: Vec<usize> = bodies
            .iter()
            .flat_map(|&b| self.vo[b]..self.vo[b] + 6 + self.nm[b])
            .collect();
        let mut cols: Vec<usize> = bodies
            .iter()
            .flat_map(|&b| {
                (self.qo[b]..self.qo[b] + 7 + self.nm[b])
                    .chain(ov + self.vo[b]..ov + self.vo[b] + 6 + self.nm[b])
            })
            .collect();
        cols.extend(oe + e.off..oe + e.off + e.n);
        if structural {
            for &c in &cols {
                for &r in &rows_f {
                    jac.add(ov + r, c, 1.0);
                }
                for i in 0..e.n {
                    jac.add(oe + e.off + i, c, 1.0);
                }
            }
            return;
        }
        let mut yy = y.to_vec();
        let mut xd = vec![0.0; e.n];
        let eval = |yy: &[f64], xd: &[f64]| -> (Vec<f64>, Vec<f64>) {
            let mut f = vec![0.0; self.nv];
            let mut res = vec![0.0; e.n];
            let x = &yy[oe + e.off..oe + e.off + e.n];
            self.ext_eval(e, t, &yy[..ov], &yy[ov..ol], x, xd, &mut res, &mut f);
            (rows_f.iter().map(|&r| f[r]).collect(), res)
        };
        let (f0, r0) = eval(&yy, &xd);
        // Columns of the rates are dF/dy' entries: added as cj times their coefficient.
        let mut put = |col: usize, f1: &[f64], r1: &[f64], h: f64, rates: bool| {
            let mut one = |row: usize, d: f64| {
                if d != 0.0 {
                    if rates {
                        jac.add_scaled(row, col, cj, d);
                    } else {
                        jac.add(row, col, d);
                    }
                }
            };
            for (k, &r) in rows_f.iter().enumerate() {
                one(ov + r, -(f1[k] - f0[k]) / h);
            }
            for i in 0..e.n {
                one(oe + e.off + i, (r1[i] - r0[i]) / h);
            }
        };
        for &c in &cols {
            let x0 = yy[c];
            let h = 1e-7 * (1.0 + x0.abs());
            yy[c] += h;
            let (f1, r1) = eval(&yy, &xd);
            yy[c] = x0;
            put(c, &f1, &r1, h, false);
        }
        // Rates of the element's own states enter its residual only.
        for i in 0..e.n {
            let h = 1e-7;
            xd[i] += h;
            let (f1, r1) = eval(&yy, &xd);
            xd[i] = 0.0;
            put(oe + e.off + i, &f1, &r1, h, true);
        }
    }

    /// Name of a constraint element (joint or motion) for messages.
    pub fn con_name(&self, e: &ConElem) -> String {
        match e.owner {
            Owner::Joint(k) => format!(
                "{} joint '{}'",
                self.model.joints[k].kind.name(),
                self.model.joints[k].name
            ),
            Owner::Motion(k) => format!("motion '{}'", self.model.motions[k].name),
        }
    }

    /// Description of row r of element e.
    pub fn row_name(&self, e: &ConElem, r: usize) -> String {
        match e.rows[r] {
            ConRow::Prim(p) => format!("{}: {}", self.con_name(e), p.describe()),
            ConRow::Drive(MotionDof::Translation) => {
                format!("{}: prescribed translation", self.con_name(e))
            }
            ConRow::Drive(MotionDof::Rotation) => {
                format!("{}: prescribed rotation", self.con_name(e))
            }
        }
    }

    fn kept_row(&self, row: usize) -> String {
        for e in &self.cons {
            for (r, s) in e.slot.iter().enumerate() {
                if *s == Some(row) {
                    return self.row_name(e, r);
                }
            }
        }
        format!("row {row}")
    }

    /// Name of unknown `i`, with its body and unit, for messages.
    pub fn unknown_name(&self, i: usize) -> String {
        let (_, ov, ol, om) = self.offsets();
        let oe = self.oe();
        const Q: [&str; 7] = ["x [m]", "y [m]", "z [m]", "q0", "q1", "q2", "q3"];
        const V: [&str; 6] = [
            "vx [m/s]",
            "vy [m/s]",
            "vz [m/s]",
            "wx [rad/s]",
            "wy [rad/s]",
            "wz [rad/s]",
        ];
        if i < ov {
            let (b, l) = self.body_at(&self.qo, i);
            match Q.get(l) {
                Some(n) => format!("body '{}' {n}", self.model.bodies[b].name),
                None => format!(
                    "body '{}' modal coordinate {}",
                    self.model.bodies[b].name,
                    l - 6
                ),
            }
        } else if i < ol {
            let (b, l) = self.body_at(&self.vo, i - ov);
            match V.get(l) {
                Some(n) => format!("body '{}' {n}", self.model.bodies[b].name),
                None => format!(
                    "body '{}' modal velocity {}",
                    self.model.bodies[b].name,
                    l - 5
                ),
            }
        } else if i < om {
            format!("multiplier of {}", self.kept_row(i - ol))
        } else if i < oe {
            format!("GGL multiplier of {}", self.kept_row(i - om))
        } else {
            match self.ext_of(i - oe) {
                Some((e, k)) => self.ext_state_name(e, k),
                None => format!("unknown {i}"),
            }
        }
    }

    /// Name of equation `i`, with its body or element, for messages.
    pub fn equation_name(&self, i: usize) -> String {
        let (_, ov, ol, om) = self.offsets();
        let oe = self.oe();
        if i < ov {
            let (b, _) = self.body_at(&self.qo, i);
            format!("kinematics of body '{}'", self.model.bodies[b].name)
        } else if i < ol {
            let (b, l) = self.body_at(&self.vo, i - ov);
            let what = match l {
                0..3 => "force".to_string(),
                3..6 => "moment".to_string(),
                _ => format!("modal force {}", l - 5),
            };
            format!("{what} balance of body '{}'", self.model.bodies[b].name)
        } else if i < om {
            format!("position constraint, {}", self.kept_row(i - ol))
        } else if i < oe {
            format!("velocity constraint, {}", self.kept_row(i - om))
        } else {
            match self.ext_of(i - oe) {
                Some((e, k)) => format!("equation of {}", self.ext_state_name(e, k)),
                None => format!("equation {i}"),
            }
        }
    }

    /// Checks the Jacobian pattern of every rigid constraint written from its topology
    /// (`rigid_constraint_pattern`) against the entries its structural evaluation emits,
    /// as sets, so the iteration matrix keeps its structure and fill-reducing order.
    /// Returns how many constraints were compared and the names of those that differ or
    /// wrote no entry (empty when all agree). A self-check for tests and `doctor`.
    pub fn check_rigid_patterns(&self) -> (usize, Vec<String>) {
        let y = self.structural_state();
        let (_, ov, ol, om) = self.offsets();
        let set = |f: &dyn Fn(&mut JacobianSink)| {
            let mut v = Vec::new();
            f(&mut JacobianSink::new(&mut v));
            let mut p: Vec<(usize, usize)> = v.into_iter().map(|(r, c, _)| (r, c)).collect();
            p.sort_unstable();
            p.dedup();
            p
        };
        let (mut checked, mut differ) = (0, Vec::new());
        for e in self.cons.iter().filter(|e| !self.has_flex(e)) {
            if e.slot.iter().all(|s| s.is_none()) {
                continue;
            }
            let by_topology = set(&|j| self.rigid_constraint_pattern(e, j));
            let by_evaluation =
                set(&|j| self.constraint_block(e, 0.0, &y[..ov], &y[ov..ol], &y[ol..om], j, true));
            if by_topology.is_empty() || by_topology != by_evaluation {
                differ.push(self.con_name(e));
            }
            checked += 1;
        }
        (checked, differ)
    }

    /// The body whose block (offsets `offs`) holds index i, and the local index.
    fn body_at(&self, offs: &[usize], i: usize) -> (usize, usize) {
        let b = offs.partition_point(|&o| o <= i) - 1;
        (b, i - offs[b])
    }
}
