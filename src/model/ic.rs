//! Consistent initial state: kinematic assembly (positions onto the constraints),
//! velocity projection, and the accelerations and multipliers that go with them.

use nalgebra::{DMatrix, DVector};

use super::math::{qmat, qmul};
use super::system::System;

/// What the initial-state analysis did.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct AssemblyReport {
    pub iterations: usize,
    /// Largest position-constraint violation before and after [m or rad].
    pub violation_before: f64,
    pub violation_after: f64,
    /// Largest velocity correction applied [m/s or rad/s].
    pub velocity_correction: f64,
}

/// Applies a velocity-space increment dx (6 per body) to positions: r += dr,
/// p <- p (x) exp(dtheta / 2), renormalised.
pub fn apply_increment(q: &mut [f64], dx: &[f64]) {
    let nb = q.len() / 7;
    for k in 0..nb {
        for c in 0..3 {
            q[7 * k + c] += dx[6 * k + c];
        }
        let th = [dx[6 * k + 3], dx[6 * k + 4], dx[6 * k + 5]];
        let a = (th[0] * th[0] + th[1] * th[1] + th[2] * th[2]).sqrt();
        let (s, c) = if a > 1e-12 {
            ((0.5 * a).sin() / a, (0.5 * a).cos())
        } else {
            (0.5, 1.0)
        };
        let e = [c, s * th[0], s * th[1], s * th[2]];
        let p = [q[7 * k + 3], q[7 * k + 4], q[7 * k + 5], q[7 * k + 6]];
        let np = qmul(&p, &e);
        let n = np.iter().map(|x| x * x).sum::<f64>().sqrt();
        for c in 0..4 {
            q[7 * k + 3 + c] = np[c] / n;
        }
    }
}

fn dense_b(sys: &System, b: &[(usize, usize, f64)]) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(sys.m, 6 * sys.nb());
    for &(r, c, v) in b {
        m[(r, c)] += v;
    }
    m
}

/// Minimum-norm solution of B x = rhs (B full row rank after redundancy elimination).
fn min_norm(b: &DMatrix<f64>, rhs: &DVector<f64>) -> Option<DVector<f64>> {
    let bbt = b * b.transpose();
    let y = bbt.lu().solve(rhs)?;
    Some(b.transpose() * y)
}

/// Moves q onto g(q, t) = 0 by Gauss-Newton with minimum-norm corrections, then projects
/// v onto B v + g_t = 0. Returns an error naming the worst row if it cannot.
pub fn assemble(
    sys: &System,
    t: f64,
    q: &mut [f64],
    v: &mut [f64],
) -> Result<AssemblyReport, String> {
    let mut rep = AssemblyReport::default();
    if sys.m == 0 {
        return Ok(rep);
    }
    let inf = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for it in 0..50 {
        let (g, _, b) = sys.constraints(t, q);
        let viol = inf(&g);
        if it == 0 {
            rep.violation_before = viol;
        }
        rep.violation_after = viol;
        if viol < 1e-12 {
            break;
        }
        if it == 49 {
            let worst = g.iter().enumerate().fold((0, 0.0f64), |a, (i, x)| {
                if x.abs() > a.1 {
                    (i, x.abs())
                } else {
                    a
                }
            });
            return Err(format!(
                "kinematic assembly did not converge: largest violation {:.3e} on {}",
                worst.1,
                sys.equation_name(sys.offsets().2 + worst.0)
            ));
        }
        let bm = dense_b(sys, &b);
        let dx = min_norm(&bm, &DVector::from_vec(g.iter().map(|x| -x).collect()))
            .ok_or("constraint Jacobian is rank-deficient during assembly")?;
        apply_increment(q, dx.as_slice());
        rep.iterations = it + 1;
    }
    let (_, gt, b) = sys.constraints(t, q);
    let bm = dense_b(sys, &b);
    let vv = DVector::from_column_slice(v);
    let r = &bm * &vv + DVector::from_vec(gt);
    let dv = min_norm(&bm, &(-r)).ok_or("constraint Jacobian is rank-deficient")?;
    rep.velocity_correction = inf(dv.as_slice());
    for (a, d) in v.iter_mut().zip(dv.iter()) {
        *a += d;
    }
    Ok(rep)
}

/// q' from v (r' = u, p' = Q(p) omega / 2).
pub fn qdot_of(q: &[f64], v: &[f64]) -> Vec<f64> {
    let nb = q.len() / 7;
    let mut qd = vec![0.0; 7 * nb];
    for k in 0..nb {
        qd[7 * k..7 * k + 3].copy_from_slice(&v[6 * k..6 * k + 3]);
        let qm = qmat(&[q[7 * k + 3], q[7 * k + 4], q[7 * k + 5], q[7 * k + 6]]);
        for a in 0..4 {
            qd[7 * k + 3 + a] = 0.5 * (0..3).map(|c| qm[a][c] * v[6 * k + 3 + c]).sum::<f64>();
        }
    }
    qd
}

/// Accelerations v' and multipliers lambda for consistent q, v:
/// [M B^T; B 0] [v'; lambda] = [f; gamma], gamma = -d(B v + g_t)/dt at fixed v.
pub fn accelerations(
    sys: &System,
    t: f64,
    q: &[f64],
    v: &[f64],
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let nb = sys.nb();
    let (n, m) = (6 * nb, sys.m);
    let mut a = DMatrix::zeros(n + m, n + m);
    let mut rhs = DVector::zeros(n + m);
    let f = sys.applied(t, q, v);
    for (k, body) in sys.model.bodies.iter().enumerate() {
        for c in 0..3 {
            a[(6 * k + c, 6 * k + c)] = body.mass;
            for d in 0..3 {
                a[(6 * k + 3 + c, 6 * k + 3 + d)] = body.inertia[c][d];
            }
        }
    }
    for i in 0..n {
        rhs[i] = f[i];
    }
    let qd = qdot_of(q, v);
    for e in &sys.cons {
        if e.slot.iter().all(|s| s.is_none()) {
            continue;
        }
        let ev = sys.con_eval2(e, t, q);
        let bodies = sys.bodies_of(e.mi, e.mj);
        for (r, slot) in e.slot.iter().enumerate() {
            let Some(row) = *slot else { continue };
            // d(Bv + g_t)/dq . q' + d(Bv + g_t)/dt
            let mut gamma = 0.0;
            let dtotal = |l: usize| {
                let mut s = ev.dbq[r][12][l];
                for (side, body) in bodies.iter().enumerate() {
                    if let Some(b) = body {
                        for c in 0..6 {
                            s += ev.dbq[r][6 * side + c][l] * v[6 * b + c];
                        }
                    }
                }
                s
            };
            for (side, body) in bodies.iter().enumerate() {
                if let Some(b) = body {
                    for l in 0..7 {
                        gamma += dtotal(7 * side + l) * qd[7 * b + l];
                    }
                    for c in 0..6 {
                        let val = ev.first.b[r][6 * side + c];
                        a[(n + row, 6 * b + c)] += val;
                        a[(6 * b + c, n + row)] += val;
                    }
                }
            }
            gamma += dtotal(14);
            rhs[n + row] = -gamma;
        }
    }
    let sol = a.lu().solve(&rhs).ok_or("the augmented mass matrix is singular (a body without mass or inertia, or a redundant constraint left in)")?;
    Ok((
        sol.rows(0, n).iter().copied().collect(),
        sol.rows(n, m).iter().copied().collect(),
    ))
}

/// The full consistent solver state (y, y') at t for positions q and velocities v, which
/// are assembled and projected first.
pub fn initial_state(
    sys: &System,
    t: f64,
    q: &mut [f64],
    v: &mut [f64],
) -> Result<(Vec<f64>, Vec<f64>, AssemblyReport), String> {
    let rep = assemble(sys, t, q, v)?;
    let (vd, lam) = accelerations(sys, t, q, v)?;
    let qd = qdot_of(q, v);
    let mut y = q.to_vec();
    y.extend_from_slice(v);
    y.extend_from_slice(&lam);
    y.extend(std::iter::repeat_n(0.0, sys.m));
    let mut yp = qd;
    yp.extend_from_slice(&vd);
    yp.extend(std::iter::repeat_n(0.0, 2 * sys.m));
    Ok((y, yp, rep))
}
