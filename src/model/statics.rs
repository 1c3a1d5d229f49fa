//! Static equilibrium: find q and lambda with f(q, 0) = B(q)^T lambda and g(q) = 0.
//!
//! Damped Newton in velocity space (translations and small rotations of each body) on the
//! saddle-point system [K B^T; B 0], with K the tangent stiffness including the
//! geometric terms d(B^T lambda)/dq, step limiting and a backtracking line search. When
//! that fails from a start far from equilibrium, the dynamics are run with strong
//! artificial damping (dynamic relaxation) and Newton is tried again from where they
//! settle.

use nalgebra::{DMatrix, DVector};

use super::ic::{apply_increment, assemble};
use super::math::qmat;
use super::system::System;
use crate::solver::problem::{DaeProblem, JacobianSink, VarKind};
use crate::solver::SolverOptions;

#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct StaticsReport {
    pub iterations: usize,
    /// Largest force/moment imbalance left [N or N m].
    pub residual_force: f64,
    /// Largest constraint violation left [m or rad].
    pub residual_constraint: f64,
    pub relaxation_used: bool,
    pub wall_s: f64,
}

/// The equilibrium as a solver state.
pub struct Statics {
    pub y: Vec<f64>,
    pub yp: Vec<f64>,
    pub report: StaticsReport,
}

/// Tangent matrices at a state with zero velocity, in velocity space: the stiffness
/// K = d(-f + B^T lambda)/dx (6nb x 6nb) and B (m x 6nb), from the system's analytic
/// iteration matrix at cj = 0.
pub fn tangent(sys: &System, t: f64, y: &[f64]) -> (DMatrix<f64>, DMatrix<f64>) {
    let nb = sys.nb();
    let (_, ov, ol, om) = sys.offsets();
    let mut e = Vec::new();
    sys.jacobian_entries(t, y, 0.0, &mut JacobianSink { entries: &mut e }, false);
    let mut dq = DMatrix::zeros(6 * nb + sys.m, 7 * nb);
    for &(r, c, v) in &e {
        if c < 7 * nb {
            if (ov..ol).contains(&r) {
                dq[(r - ov, c)] += v;
            } else if (ol..om).contains(&r) {
                dq[(6 * nb + r - ol, c)] += v;
            }
        }
    }
    // chain with dq/dx: r <- dr, p <- Q(p) dtheta / 2
    let mut h = DMatrix::zeros(7 * nb, 6 * nb);
    for k in 0..nb {
        for c in 0..3 {
            h[(7 * k + c, 6 * k + c)] = 1.0;
        }
        let qm = qmat(&[y[7 * k + 3], y[7 * k + 4], y[7 * k + 5], y[7 * k + 6]]);
        for a in 0..4 {
            for c in 0..3 {
                h[(7 * k + 3 + a, 6 * k + 3 + c)] = 0.5 * qm[a][c];
            }
        }
    }
    let kx = &dq * &h;
    (
        kx.rows(0, 6 * nb).into_owned(),
        kx.rows(6 * nb, sys.m).into_owned(),
    )
}

/// Finds the static equilibrium nearest the model's initial positions.
pub fn equilibrium(sys: &System, t: f64, opts: &SolverOptions) -> Result<Statics, String> {
    let wall = std::time::Instant::now();
    let (mut q, mut v) = sys.initial_q_v();
    assemble(sys, t, &mut q, &mut v)?;
    let mut lam = vec![0.0; sys.m];
    let mut rep = StaticsReport::default();
    let ok = newton(sys, t, &mut q, &mut lam, &mut rep);
    if !ok {
        // Dynamic relaxation: settle with heavy damping, then polish with Newton.
        rep.relaxation_used = true;
        let relaxed = Relaxed { sys, rate: 20.0 };
        let (y0, yp0, _) = super::ic::initial_state(sys, t, &mut q, &mut vec![0.0; 6 * sys.nb()])?;
        let mut o = opts.clone();
        o.rtol = o.rtol.max(1e-5);
        let end = crate::solver::solve_to(&relaxed, t, &y0, &yp0, t + 5.0, &o)
            .map_err(|e| format!("dynamic relaxation failed: {e}"))?;
        q.copy_from_slice(&end.y[..7 * sys.nb()]);
        lam.copy_from_slice(&end.y[sys.offsets().2..sys.offsets().3]);
        if !newton(sys, t, &mut q, &mut lam, &mut rep) {
            return Err(format!(
                "static equilibrium not found after {} Newton iterations and dynamic relaxation: force imbalance {:.3e}, constraint violation {:.3e}",
                rep.iterations, rep.residual_force, rep.residual_constraint
            ));
        }
    }
    let nb = sys.nb();
    let mut y = q.clone();
    y.extend(std::iter::repeat_n(0.0, 6 * nb));
    y.extend_from_slice(&lam);
    y.extend(std::iter::repeat_n(0.0, sys.m));
    let yp = vec![0.0; y.len()];
    rep.wall_s = wall.elapsed().as_secs_f64();
    Ok(Statics { y, yp, report: rep })
}

/// Damped Newton; true on convergence.
fn newton(sys: &System, t: f64, q: &mut [f64], lam: &mut [f64], rep: &mut StaticsReport) -> bool {
    let nb = sys.nb();
    let (_, ov, ol, om) = sys.offsets();
    let weight: f64 =
        sys.model.bodies.iter().map(|b| b.mass).sum::<f64>() * norm3(&sys.model.gravity);
    let f_ref = weight.max(1.0);
    let state = |q: &[f64], lam: &[f64]| {
        let mut y = q.to_vec();
        y.extend(std::iter::repeat_n(0.0, 6 * nb));
        y.extend_from_slice(lam);
        y.extend(std::iter::repeat_n(0.0, sys.m));
        y
    };
    let resid = |y: &[f64]| {
        let mut r = vec![0.0; y.len()];
        sys.residual(t, y, &vec![0.0; y.len()], &mut r);
        (r[ov..ol].to_vec(), r[ol..om].to_vec())
    };
    let merit = |rf: &[f64], rg: &[f64]| inf(rf) / f_ref + inf(rg);
    for _ in 0..100 {
        let y = state(q, lam);
        let (rf, rg) = resid(&y);
        rep.residual_force = inf(&rf);
        rep.residual_constraint = inf(&rg);
        let phi = merit(&rf, &rg);
        let (k, b) = tangent(sys, t, &y);
        let n = 6 * nb + sys.m;
        let mut a = DMatrix::zeros(n, n);
        a.view_mut((0, 0), (6 * nb, 6 * nb)).copy_from(&k);
        a.view_mut((0, 6 * nb), (6 * nb, sys.m))
            .copy_from(&b.transpose());
        a.view_mut((6 * nb, 0), (sys.m, 6 * nb)).copy_from(&b);
        let rhs = DVector::from_iterator(n, rf.iter().chain(&rg).map(|x| -x));
        let Some(d) = a.lu().solve(&rhs) else {
            return false;
        };
        rep.iterations += 1;
        // Step limits: 0.1 m and 0.2 rad per iteration.
        let mut scale = 1.0f64;
        for kb in 0..nb {
            let tr = norm3(&[d[6 * kb], d[6 * kb + 1], d[6 * kb + 2]]);
            let ro = norm3(&[d[6 * kb + 3], d[6 * kb + 4], d[6 * kb + 5]]);
            scale = scale.min(0.1 / tr.max(1e-300)).min(0.2 / ro.max(1e-300));
        }
        let dx_max = (0..6 * nb).fold(0.0f64, |m, i| m.max(d[i].abs()));
        let mut alpha = scale.min(1.0);
        loop {
            let mut qn = q.to_vec();
            let dx: Vec<f64> = (0..6 * nb).map(|i| alpha * d[i]).collect();
            apply_increment(&mut qn, &dx);
            let ln: Vec<f64> = (0..sys.m).map(|i| lam[i] + alpha * d[6 * nb + i]).collect();
            let (rf2, rg2) = resid(&state(&qn, &ln));
            if merit(&rf2, &rg2) < phi || alpha < 1e-3 || phi < 1e-12 {
                q.copy_from_slice(&qn);
                lam.copy_from_slice(&ln);
                rep.residual_force = inf(&rf2);
                rep.residual_constraint = inf(&rg2);
                break;
            }
            alpha *= 0.5;
        }
        if alpha * dx_max < 1e-11
            && rep.residual_force < 1e-7 * f_ref
            && rep.residual_constraint < 1e-10
        {
            return true;
        }
    }
    false
}

fn inf(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

fn norm3(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The system with mass-proportional damping `rate` [1/s] added, for dynamic relaxation.
struct Relaxed<'a> {
    sys: &'a System,
    rate: f64,
}

impl DaeProblem for Relaxed<'_> {
    fn size(&self) -> usize {
        self.sys.size()
    }
    fn residual(&self, t: f64, y: &[f64], yp: &[f64], res: &mut [f64]) {
        self.sys.residual(t, y, yp, res);
        let ov = self.sys.offsets().1;
        for (k, b) in self.sys.model.bodies.iter().enumerate() {
            for c in 0..3 {
                res[ov + 6 * k + c] += self.rate * b.mass * y[ov + 6 * k + c];
                for d in 0..3 {
                    res[ov + 6 * k + 3 + c] += self.rate * b.inertia[c][d] * y[ov + 6 * k + 3 + d];
                }
            }
        }
    }
    fn var_kinds(&self) -> Vec<VarKind> {
        self.sys.var_kinds()
    }
    fn jacobian_pattern(&self) -> Option<Vec<(usize, usize)>> {
        self.sys.jacobian_pattern()
    }
    fn jacobian(&self, t: f64, y: &[f64], yp: &[f64], cj: f64, jac: &mut JacobianSink) -> bool {
        self.sys.jacobian(t, y, yp, cj, jac);
        let ov = self.sys.offsets().1;
        for (k, b) in self.sys.model.bodies.iter().enumerate() {
            for c in 0..3 {
                jac.add(ov + 6 * k + c, ov + 6 * k + c, self.rate * b.mass);
                for d in 0..3 {
                    jac.add(
                        ov + 6 * k + 3 + c,
                        ov + 6 * k + 3 + d,
                        self.rate * b.inertia[c][d],
                    );
                }
            }
        }
        true
    }
}
