//! The analytic iteration matrix of [`System`] and the names of its unknowns and
//! equations (for solver messages).

use super::{ConElem, ConRow, Owner, System};
use crate::model::desc::MotionDof;
use crate::model::math::{cst33, mvc, qmat};
use crate::solver::problem::JacobianSink;

impl System {
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
        let nb = self.nb();
        let (_, ov, ol, om) = self.offsets();
        let q_owned;
        let q: &[f64] = if structural {
            // A generic configuration (unit quaternions) so no derivative is accidentally 0.
            let (q0, _) = self.initial_q_v();
            q_owned = q0;
            &q_owned
        } else {
            &y[..7 * nb]
        };
        let v = &y[ov..ol];
        let lam = &y[ol..om];
        let pick = |x: f64| if structural { 1.0 } else { x };
        // Rigid-body blocks.
        for (k, body) in self.model.bodies.iter().enumerate() {
            let (qr, qp, vu, vw) = (7 * k, 7 * k + 3, ov + 6 * k, ov + 6 * k + 3);
            for c in 0..3 {
                jac.add(qr + c, qr + c, cj);
                jac.add(qr + c, vu + c, -1.0);
                jac.add(vu + c, vu + c, cj * body.mass);
            }
            let p = [q[qp], q[qp + 1], q[qp + 2], q[qp + 3]];
            let w = [v[6 * k + 3], v[6 * k + 4], v[6 * k + 5]];
            // d(p (x) (0,w))/dp (B^T mu term dropped, mu = 0 on the solution)
            let rw = [
                [0.0, -w[0], -w[1], -w[2]],
                [w[0], 0.0, w[2], -w[1]],
                [w[1], -w[2], 0.0, w[0]],
                [w[2], w[1], -w[0], 0.0],
            ];
            let qm = qmat(&p);
            for a in 0..4 {
                for bcol in 0..4 {
                    let val = -0.5 * rw[a][bcol] + if a == bcol { cj } else { 0.0 };
                    if structural || val != 0.0 {
                        jac.add(qp + a, qp + bcol, pick(val));
                    }
                }
                for c in 0..3 {
                    jac.add(qp + a, vw + c, pick(-0.5 * qm[a][c]));
                }
            }
            // J w' + w x J w
            let jm = body.inertia;
            let jw = mvc(&cst33::<f64>(&jm), &w);
            // d(w x Jw)/dw = [w]x J - [Jw]x
            let skew = |a: [f64; 3]| [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
            let sw = skew(w);
            let sjw = skew(jw);
            for r in 0..3 {
                for c in 0..3 {
                    let mut val = cj * jm[r][c] - sjw[r][c];
                    for l in 0..3 {
                        val += sw[r][l] * jm[l][c];
                    }
                    jac.add(vw + r, vw + c, pick(val));
                }
            }
        }
        // Force elements: -dQ/d(q, v).
        for fe in 0..self.felems.len() {
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
                                    7 * bb + l
                                } else {
                                    ov + 6 * bb + l - 7
                                };
                                jac.add(ov + 6 * b + c, col, pick(val));
                            }
                        }
                    }
                }
            }
        }
        // Constraint elements.
        for e in &self.cons {
            if e.slot.iter().all(|s| s.is_none()) {
                continue;
            }
            let ev = self.con_eval2(e, t, q);
            let bodies = self.bodies_of(e.mi, e.mj);
            for (r, slot) in e.slot.iter().enumerate() {
                let Some(row) = *slot else { continue };
                for (side, body) in bodies.iter().enumerate() {
                    let Some(b) = body else { continue };
                    for c in 0..6 {
                        let bval = ev.first.b[r][6 * side + c];
                        if !structural && bval == 0.0 {
                            continue;
                        }
                        let bval = pick(bval);
                        // dyn rows: B^T lambda; gv rows: B v
                        jac.add(ov + 6 * b + c, ol + row, bval);
                        jac.add(om + row, ov + 6 * b + c, bval);
                        // kinematic rows: B^T mu
                        if c < 3 {
                            jac.add(7 * b + c, om + row, bval);
                        } else {
                            let p = [q[7 * b + 3], q[7 * b + 4], q[7 * b + 5], q[7 * b + 6]];
                            let qm = qmat(&p);
                            for a in 0..4 {
                                jac.add(7 * b + 3 + a, om + row, pick(0.5 * qm[a][c - 3] * bval));
                            }
                        }
                    }
                    for l in 0..7 {
                        let gq = ev.gq[r][7 * side + l];
                        if structural || gq != 0.0 {
                            jac.add(ol + row, 7 * b + l, pick(gq));
                        }
                    }
                }
                // Second-derivative terms: d(B^T lambda)/dq and d(B v + g_t)/dq.
                for (qside, qbody) in bodies.iter().enumerate() {
                    let Some(qb) = qbody else { continue };
                    for l in 0..7 {
                        let lq = 7 * qside + l;
                        let mut dbv = ev.dbq[r][12][lq];
                        for (side, body) in bodies.iter().enumerate() {
                            let Some(b) = body else { continue };
                            for c in 0..6 {
                                let d = ev.dbq[r][6 * side + c][lq];
                                dbv += d * v[6 * b + c];
                                let val = d * lam[row];
                                if structural || val != 0.0 {
                                    jac.add(ov + 6 * b + c, 7 * qb + l, pick(val));
                                }
                            }
                        }
                        if structural || dbv != 0.0 {
                            jac.add(om + row, 7 * qb + l, pick(dbv));
                        }
                    }
                }
            }
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

    pub fn unknown_name(&self, i: usize) -> String {
        let nb = self.nb();
        let (_, ov, ol, om) = self.offsets();
        const Q: [&str; 7] = ["x [m]", "y [m]", "z [m]", "q0", "q1", "q2", "q3"];
        const V: [&str; 6] = [
            "vx [m/s]",
            "vy [m/s]",
            "vz [m/s]",
            "wx [rad/s]",
            "wy [rad/s]",
            "wz [rad/s]",
        ];
        if i < 7 * nb {
            format!("body '{}' {}", self.model.bodies[i / 7].name, Q[i % 7])
        } else if i < ol {
            let k = i - ov;
            format!("body '{}' {}", self.model.bodies[k / 6].name, V[k % 6])
        } else if i < om {
            format!("multiplier of {}", self.kept_row(i - ol))
        } else {
            format!("GGL multiplier of {}", self.kept_row(i - om))
        }
    }

    pub fn equation_name(&self, i: usize) -> String {
        let nb = self.nb();
        let (_, ov, ol, om) = self.offsets();
        if i < 7 * nb {
            format!("kinematics of body '{}'", self.model.bodies[i / 7].name)
        } else if i < ol {
            let k = i - ov;
            let what = if k % 6 < 3 { "force" } else { "moment" };
            format!("{what} balance of body '{}'", self.model.bodies[k / 6].name)
        } else if i < om {
            format!("position constraint, {}", self.kept_row(i - ol))
        } else {
            format!("velocity constraint, {}", self.kept_row(i - om))
        }
    }
}
