//! Consistent initial state: kinematic assembly (positions onto the constraints),
//! velocity projection, and the accelerations and multipliers that go with them.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::normal::{self, add_body, dot, Blocks, Rows};
use super::system::{MassBlock, System};
use super::ModelError;
use towride_solver::linear::NewtonMatrix;

/// What the initial-state analysis did.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct AssemblyReport {
    /// Newton iterations of the position projection onto the constraints.
    pub iterations: usize,
    /// Largest position-constraint violation before and after [m or rad].
    pub violation_before: f64,
    /// Largest violation left after the projection [m or rad].
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
) -> Result<AssemblyReport, ModelError> {
    assemble_with(sys, t, q, v, normal::dense(sys.m))
}

/// [`assemble`] on the dense (`dense`) or the sparse path; [`assemble`] chooses by
/// [`normal::DENSE_ROWS`].
pub fn assemble_with(
    sys: &System,
    t: f64,
    q: &mut [f64],
    v: &mut [f64],
    dense: bool,
) -> Result<AssemblyReport, ModelError> {
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
            return Err(ModelError::Assembly(format!(
                "kinematic assembly did not converge: largest violation {:.3e} on {}",
                worst.1,
                sys.equation_name(sys.offsets().2 + worst.0)
            )));
        }
        let neg_g: Vec<f64> = g.iter().map(|x| -x).collect();
        let dx = correction(sys, &b, neg_g, dense)?.ok_or_else(|| {
            ModelError::Assembly("constraint Jacobian is rank-deficient during assembly".into())
        })?;
        sys.apply_increment(q, &dx);
        rep.iterations = it + 1;
    }
    let (_, gt, b) = sys.constraints(t, q);
    // -(B v + g_t)
    let r: Vec<f64> = if dense {
        let res = dense_b(sys, &b) * DVector::from_column_slice(v) + DVector::from_vec(gt);
        (-res).as_slice().to_vec()
    } else {
        let mut r: Vec<f64> = gt.iter().map(|x| -x).collect();
        for &(row, c, val) in &b {
            r[row] -= val * v[c];
        }
        r
    };
    let dv = correction(sys, &b, r, dense)?
        .ok_or_else(|| ModelError::Assembly("constraint Jacobian is rank-deficient".into()))?;
    rep.velocity_correction = inf(&dv);
    for (a, d) in v.iter_mut().zip(dv.iter()) {
        *a += d;
    }
    Ok(rep)
}

/// The minimum-norm x with B x = rhs (B as triplets); `None` when B B^T is singular.
fn correction(
    sys: &System,
    b: &[(usize, usize, f64)],
    rhs: Vec<f64>,
    dense: bool,
) -> Result<Option<Vec<f64>>, ModelError> {
    if dense {
        let bm = dense_b(sys, b);
        return Ok(min_norm(&bm, &DVector::from_vec(rhs)).map(|x| x.as_slice().to_vec()));
    }
    normal::min_norm_sparse(sys, &normal::rows_of(sys.m, b), &rhs)
}

/// Accelerations v' and multipliers lambda for consistent q, v:
/// [M B^T; B 0] [v'; lambda] = [f; gamma], gamma = -d(B v + g_t)/dt at fixed v.
///
/// M is block diagonal (one block per body), so the multipliers follow from the Schur
/// complement (B M^-1 B^T) lambda = B M^-1 f - gamma, positive definite when the kept
/// rows are independent, and v' = M^-1 (f - B^T lambda). Per output sample this costs
/// a quarter of a sparse LU of the whole saddle-point matrix. The Schur complement is
/// dense up to [`normal::DENSE_ROWS`] rows and sparse (rows meet where they share a
/// body) above. When its Cholesky factor does not exist (a massless body, a dependent
/// row left in), the sparse LU is used, which reports the singularity.
pub fn accelerations(
    sys: &System,
    t: f64,
    q: &[f64],
    v: &[f64],
    x: &[f64],
) -> Result<(Vec<f64>, Vec<f64>), ModelError> {
    accelerations_with(sys, t, q, v, x, normal::dense(sys.m))
}

/// [`accelerations`] with the Schur complement dense (`dense`) or sparse;
/// [`accelerations`] chooses by [`normal::DENSE_ROWS`].
pub fn accelerations_with(
    sys: &System,
    t: f64,
    q: &[f64],
    v: &[f64],
    x: &[f64],
    dense: bool,
) -> Result<(Vec<f64>, Vec<f64>), ModelError> {
    let f = sys.loads(t, q, v, x, None);
    let (rows, rhs_c) = kept_rows(sys, t, q, v);
    if let Some(sol) = schur_solve(sys, q, &f, &rows, &rhs_c, dense)? {
        return Ok(sol);
    }
    saddle_point_lu(sys, q, f, &rows, &rhs_c)
}

/// The kept constraint rows and the right-hand side -gamma of B v' = -gamma.
fn kept_rows(sys: &System, t: f64, q: &[f64], v: &[f64]) -> (Rows, Vec<f64>) {
    let mut rows = Vec::with_capacity(sys.m);
    let mut rhs_c = vec![0.0; sys.m];
    for e in &sys.cons {
        if e.slot.iter().all(|s| s.is_none()) {
            continue;
        }
        let ev = sys.con_eval(e, t, q);
        let gamma = sys.con_gamma(e, t, q, v);
        let bodies = sys.bodies_of(e.mi, e.mj);
        for (r, slot) in e.slot.iter().enumerate() {
            let Some(row) = *slot else { continue };
            let mut entries = Vec::new();
            for (side, body) in bodies.iter().enumerate() {
                if let Some(b) = body {
                    for c in 0..ev.w[side] {
                        entries.push((sys.vo[*b] + c, ev.at(r, side, c)));
                    }
                }
            }
            rows.push((row, entries));
            rhs_c[row] = -gamma[r];
        }
    }
    (rows, rhs_c)
}

/// M^-1 of one body ([`MassBlock`]): 1/m, J^-1 and the unit modal mass, or a Cholesky
/// factor where the block depends on the deformation (`full` coupling).
enum BodyInverse {
    Diagonal { inv_mass: f64, inv_j: Matrix3<f64> },
    Full(nalgebra::Cholesky<f64, nalgebra::Dyn>),
}

impl BodyInverse {
    fn apply(&self, x: &mut [f64]) {
        match self {
            BodyInverse::Diagonal { inv_mass, inv_j } => {
                for v in &mut x[..3] {
                    *v *= inv_mass;
                }
                let w = inv_j * Vector3::new(x[3], x[4], x[5]);
                x[3..6].copy_from_slice(w.as_slice());
            }
            BodyInverse::Full(ch) => {
                let mut v = DVector::from_column_slice(x);
                ch.solve_mut(&mut v);
                x.copy_from_slice(v.as_slice());
            }
        }
    }
}

/// Accelerations v' and multipliers lambda.
type Solution = (Vec<f64>, Vec<f64>);

/// The Schur-complement solve, S dense or sparse; `None` when a mass block or
/// S = B M^-1 B^T is not positive definite.
fn schur_solve(
    sys: &System,
    q: &[f64],
    f: &[f64],
    rows: &Rows,
    rhs_c: &[f64],
    dense: bool,
) -> Result<Option<Solution>, ModelError> {
    let m = sys.m;
    let blocks = Blocks::of(sys, rows);
    let mut s_dense = faer::Mat::<f64>::zeros(if dense { m } else { 0 }, if dense { m } else { 0 });
    let mut s_sparse = if dense {
        None
    } else {
        Some(normal::matrix(sys)?)
    };
    let mut lam = vec![0.0; m];
    for (row, _) in rows {
        lam[*row] = -rhs_c[*row];
    }
    let mut acc = f.to_vec();
    // Per body: M^-1 times its rows of B, kept for v' = M^-1 f - (M^-1 B^T) lambda.
    let mut parts: Vec<Vec<f64>> = Vec::with_capacity(sys.nb());
    for (b, (rk, bb)) in blocks.body.iter().enumerate() {
        let (w, o) = (sys.width(Some(b)), sys.vo[b]);
        let inv = match sys.mass_block(b, q) {
            MassBlock::Full(mb) => match mb.cholesky() {
                Some(ch) => BodyInverse::Full(ch),
                None => return Ok(None),
            },
            MassBlock::Diagonal { mass, inertia } => {
                match Matrix3::from_fn(|r, c| inertia[r][c]).cholesky() {
                    Some(ch) => BodyInverse::Diagonal {
                        inv_mass: 1.0 / mass,
                        inv_j: ch.inverse(),
                    },
                    None => return Ok(None),
                }
            }
        };
        inv.apply(&mut acc[o..o + w]);
        let mut xb = bb.clone();
        for x in xb.chunks_mut(w) {
            inv.apply(x);
        }
        let u = &acc[o..o + w];
        for (i, &ki) in rk.iter().enumerate() {
            lam[rows[ki].0] += dot(&bb[i * w..(i + 1) * w], u);
        }
        match s_sparse.as_mut() {
            None => add_body(rows, rk, w, bb, &xb, true, &mut |i, j, v| {
                s_dense[(i, j)] += v
            }),
            Some(a) => add_body(rows, rk, w, bb, &xb, false, &mut |i, j, v| {
                a.add(i, j, v).expect("pair of rows sharing a body")
            }),
        }
        parts.push(xb);
    }
    match s_sparse.as_mut() {
        None => {
            let Ok(llt) = s_dense.llt(faer::Side::Lower) else {
                return Ok(None);
            };
            let mut l = faer::Mat::<f64>::from_fn(m, 1, |i, _| lam[i]);
            faer::linalg::solvers::Solve::solve_in_place(&llt, l.as_mut());
            lam = (0..m).map(|i| l[(i, 0)]).collect();
        }
        Some(a) => {
            if a.factor().is_err() {
                return Ok(None);
            }
            a.solve(&mut lam);
        }
    }
    for (b, xb) in parts.iter().enumerate() {
        let (w, o) = (sys.width(Some(b)), sys.vo[b]);
        for (i, &k) in blocks.body[b].0.iter().enumerate() {
            let l = lam[rows[k].0];
            for c in 0..w {
                acc[o + c] -= xb[i * w + c] * l;
            }
        }
    }
    Ok(acc.iter().all(|a| a.is_finite()).then_some((acc, lam)))
}

/// The sparse LU of [M B^T; B 0] (kept for what the Schur complement cannot do, and for
/// its singularity report).
fn saddle_point_lu(
    sys: &System,
    q: &[f64],
    f: Vec<f64>,
    rows: &Rows,
    rhs_c: &[f64],
) -> Result<(Vec<f64>, Vec<f64>), ModelError> {
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
    let mut rhs = f;
    rhs.resize(n + m, 0.0);
    for (r, c, val) in sys.mass_entries_at(q) {
        put(a, r, c, val);
    }
    for (row, entries) in rows {
        for &(c, val) in entries {
            put(a, n + row, c, val);
            put(a, c, n + row, val);
        }
        rhs[n + row] = rhs_c[*row];
    }
    let singular = |e: towride_solver::linear::Singular| {
        ModelError::Singular(format!(
            "the augmented mass matrix is singular (a body without mass or inertia, or a redundant constraint left in): {}",
            e.detail
        ))
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
) -> Result<Vec<f64>, ModelError> {
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
            .ok_or_else(|| {
                ModelError::Singular(format!(
                    "{}: singular rate equations",
                    sys.ext_state_name(e, 0)
                ))
            })?;
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
) -> Result<(Vec<f64>, Vec<f64>, AssemblyReport), ModelError> {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The Schur-complement path against the sparse LU of the whole saddle-point matrix,
    /// on Andrews' squeezing mechanism (seven bodies, two closed loops, a motor).
    #[test]
    fn schur_complement_matches_the_saddle_point_lu() {
        let mech = crate::model::spec::load(
            std::path::Path::new(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../../scenes/examples/andrews.toml"
            )),
            &crate::input::Loader::new(),
        )
        .expect("example loads");
        let sys = System::new(mech.model);
        let (mut q, mut v) = sys.initial_q_v();
        assemble(&sys, 0.0, &mut q, &mut v).expect("assembles");
        let x = vec![0.0; sys.ne];
        let f = sys.loads(0.0, &q, &v, &x, None);
        let (a, lam) = accelerations(&sys, 0.0, &q, &v, &x).expect("solves");
        let (rows, rhs_c) = kept_rows(&sys, 0.0, &q, &v);
        let (a2, lam2) = saddle_point_lu(&sys, &q, f, &rows, &rhs_c).expect("solves");
        let rel = |x: &[f64], y: &[f64]| {
            let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            x.iter()
                .zip(y)
                .fold(0.0f64, |m, (p, r)| m.max((p - r).abs()))
                / scale
        };
        assert!(
            rel(&a, &a2) < 1e-9,
            "accelerations differ by {:e}",
            rel(&a, &a2)
        );
        assert!(
            rel(&lam, &lam2) < 1e-9,
            "multipliers differ by {:e}",
            rel(&lam, &lam2)
        );
        assert!(lam2.iter().any(|l| l.abs() > 1.0), "a loaded mechanism");
    }
}
