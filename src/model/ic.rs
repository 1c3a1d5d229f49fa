//! Consistent initial state: kinematic assembly (positions onto the constraints),
//! velocity projection, and the accelerations and multipliers that go with them.

use nalgebra::{DMatrix, DVector};

use super::system::System;
use crate::solver::linear::NewtonMatrix;

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

fn dense_b(sys: &System, b: &[(usize, usize, f64)]) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(sys.m, sys.nv);
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
        sys.apply_increment(q, dx.as_slice());
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

/// Accelerations v' and multipliers lambda for consistent q, v:
/// [M B^T; B 0] [v'; lambda] = [f; gamma], gamma = -d(B v + g_t)/dt at fixed v.
pub fn accelerations(
    sys: &System,
    t: f64,
    q: &[f64],
    v: &[f64],
    x: &[f64],
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let (n, m) = (sys.nv, sys.m);
    let mut cache = sys.accel.borrow_mut();
    if cache.is_none() {
        *cache = Some(NewtonMatrix::new(
            n + m,
            Some(accel_pattern(sys)),
            n + m <= 60,
        )?);
    }
    let a = cache.as_mut().expect("built above");
    a.clear();
    let put = |a: &mut NewtonMatrix, r: usize, c: usize, v: f64| {
        a.add(r, c, v).expect("entry in the acceleration pattern");
    };
    let mut rhs = sys.loads(t, q, v, x, None);
    rhs.resize(n + m, 0.0);
    for (r, c, val) in sys.mass_entries_at(q) {
        put(a, r, c, val);
    }
    for e in &sys.cons {
        if e.slot.iter().all(|s| s.is_none()) {
            continue;
        }
        let ev = sys.con_eval(e, t, q);
        let gamma = sys.con_gamma(e, t, q, v);
        let bodies = sys.bodies_of(e.mi, e.mj);
        for (r, slot) in e.slot.iter().enumerate() {
            let Some(row) = *slot else { continue };
            for (side, body) in bodies.iter().enumerate() {
                if let Some(b) = body {
                    for c in 0..ev.w[side] {
                        let val = ev.at(r, side, c);
                        put(a, n + row, sys.vo[*b] + c, val);
                        put(a, sys.vo[*b] + c, n + row, val);
                    }
                }
            }
            rhs[n + row] = -gamma[r];
        }
    }
    let singular = |e: crate::solver::linear::Singular| {
        format!(
            "the augmented mass matrix is singular (a body without mass or inertia, or a redundant constraint left in): {}",
            e.detail
        )
    };
    a.factor(&vec![1.0; n + m], true).map_err(singular)?;
    a.solve(&mut rhs).map_err(singular)?;
    let lam = rhs.split_off(n);
    Ok((rhs, lam))
}

/// Structure of [M B^T; B 0]: the mass blocks and every kept row against its bodies.
fn accel_pattern(sys: &System) -> Vec<(usize, usize)> {
    let n = sys.nv;
    let mut p: Vec<(usize, usize)> = sys.mass_entries().iter().map(|&(r, c, _)| (r, c)).collect();
    for e in &sys.cons {
        let bodies = sys.bodies_of(e.mi, e.mj);
        for row in e.slot.iter().flatten() {
            for b in bodies.iter().flatten() {
                for c in sys.vo[*b]..sys.vo[*b] + 6 + sys.nm[*b] {
                    p.push((n + row, c));
                    p.push((c, n + row));
                }
            }
        }
    }
    p
}

/// Rates of the extension states at (q, v, x): the extension residuals are affine in the
/// rates, so one solve with their finite-difference Jacobian gives them.
pub fn ext_rates(
    sys: &System,
    t: f64,
    q: &[f64],
    v: &[f64],
    x: &[f64],
) -> Result<Vec<f64>, String> {
    let mut xd = vec![0.0; sys.ne];
    let mut f = vec![0.0; sys.nv];
    for e in &sys.ext {
        let r = e.off..e.off + e.n;
        let mut r0 = vec![0.0; e.n];
        let zero = vec![0.0; e.n];
        sys.ext_eval(e, t, q, v, &x[r.clone()], &zero, &mut r0, &mut f);
        let mut jm = DMatrix::zeros(e.n, e.n);
        for k in 0..e.n {
            let mut d = zero.clone();
            d[k] = 1.0;
            let mut r1 = vec![0.0; e.n];
            sys.ext_eval(e, t, q, v, &x[r.clone()], &d, &mut r1, &mut f);
            for i in 0..e.n {
                jm[(i, k)] = r1[i] - r0[i];
            }
        }
        let sol = jm
            .lu()
            .solve(&DVector::from_iterator(e.n, r0.iter().map(|z| -z)))
            .ok_or_else(|| format!("{}: singular rate equations", sys.ext_state_name(e, 0)))?;
        xd[r].copy_from_slice(sol.as_slice());
    }
    Ok(xd)
}

/// The full consistent solver state (y, y') at t for positions q, velocities v and
/// extension states x; q and v are assembled and projected first.
pub fn initial_state(
    sys: &System,
    t: f64,
    q: &mut [f64],
    v: &mut [f64],
    x: &[f64],
) -> Result<(Vec<f64>, Vec<f64>, AssemblyReport), String> {
    let rep = assemble(sys, t, q, v)?;
    let (vd, lam) = accelerations(sys, t, q, v, x)?;
    let qd = sys.qdot_of(q, v);
    let xd = ext_rates(sys, t, q, v, x)?;
    let mut y = q.to_vec();
    y.extend_from_slice(v);
    y.extend_from_slice(&lam);
    y.extend(std::iter::repeat_n(0.0, sys.m));
    y.extend_from_slice(x);
    let mut yp = qd;
    yp.extend_from_slice(&vd);
    yp.extend(std::iter::repeat_n(0.0, 2 * sys.m));
    yp.extend_from_slice(&xd);
    Ok((y, yp, rep))
}
