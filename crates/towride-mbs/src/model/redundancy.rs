//! Redundant constraints: found by a rank-revealing sweep over the rows of the
//! velocity-space constraint Jacobian B in model order, and eliminated before the run.
//!
//! A row whose component outside the span of the rows already kept is below a relative
//! tolerance restates constraints that are already there (a planar loop built in 3D, a
//! body held by two fixed joints). Keeping it would make the Newton matrix singular; the
//! commercial tool of the thesis zeroes such reactions silently (4.1.2.1). Here the row is
//! dropped, its reaction is carried by the rows it depends on, and the dependency is
//! reported by name so `doctor` can say which joints over-constrain which.
//!
//! The sweep is a sparse LU of B^T with the rows as columns in model order
//! ([`towride_solver::linear::ColumnBasis`]: cost linear in a chain or a ladder of
//! loops). Modified Gram-Schmidt, twice, on dense rows ([`select_dense`], cost m^2 n) is
//! kept as the reference it is tested against: on every model of the repository both
//! keep the same rows and name the same dependencies, with coefficients equal to 1e-9,
//! so the run, which sees only the kept rows, is the same to the last digit.

use super::system::{Redundant, System};
use towride_solver::linear::{ColumnBasis, Offer};

/// Relative size below which a row counts as dependent.
const TOL: f64 = 1e-8;

/// One row of B: (element, row within it) and its entries (velocity unknown, value).
pub type JacobianRow = ((usize, usize), Vec<(usize, f64)>);

/// Returns the kept rows (element, row) in order and the redundant ones.
pub fn select_rows(sys: &System, t: f64, q: &[f64]) -> (Vec<(usize, usize)>, Vec<Redundant>) {
    // The dense sweep, used up to 100 rows until the sparse one was trusted, cost
    // 1 ms of a 12 ms run on a ladder of five loops (85 rows) and 8 ms of the vehicle's
    // set-up with 100 hitch modes; the sparse one takes a few tens of microseconds.
    select_sparse(sys.nv, &jacobian_rows(sys, t, q))
}

/// Every row of B at (t, q), kept or not, in model order.
pub fn jacobian_rows(sys: &System, t: f64, q: &[f64]) -> Vec<JacobianRow> {
    let mut out = Vec::new();
    for (ei, e) in sys.cons.iter().enumerate() {
        let ev = sys.con_eval(e, t, q);
        let bodies = sys.bodies_of(e.mi, e.mj);
        for r in 0..e.rows.len() {
            let mut entries = Vec::new();
            for (side, body) in bodies.iter().enumerate() {
                if let Some(k) = body {
                    for c in 0..ev.w[side] {
                        entries.push((sys.vo[*k] + c, ev.at(r, side, c)));
                    }
                }
            }
            out.push(((ei, r), entries));
        }
    }
    out
}

/// The kept rows and the redundant ones with the kept rows they combine (coefficients
/// above 1e-6 of the largest), from the combination over kept rows in order.
fn record(
    kept: &[(usize, usize)],
    id: (usize, usize),
    combination: impl Iterator<Item = (usize, f64)>,
) -> Redundant {
    let c: Vec<(usize, f64)> = combination.collect();
    let big = c.iter().fold(0.0f64, |m, x| m.max(x.1.abs()));
    Redundant {
        elem: id.0,
        row: id.1,
        depends_on: c
            .iter()
            .filter(|(_, x)| x.abs() > 1e-6 * big)
            .map(|&(j, x)| (kept[j].0, kept[j].1, x))
            .collect(),
    }
}

/// The sparse sweep: LU of B^T, rows of B offered in model order.
pub fn select_sparse(nv: usize, rows: &[JacobianRow]) -> (Vec<(usize, usize)>, Vec<Redundant>) {
    let mut counts = vec![0; nv];
    for (_, entries) in rows {
        for &(c, _) in entries {
            counts[c] += 1;
        }
    }
    let mut basis = ColumnBasis::new(nv, counts, TOL);
    let mut kept = Vec::new();
    let mut redundant = Vec::new();
    for (id, entries) in rows {
        match basis.offer(entries) {
            Offer::Kept => kept.push(*id),
            Offer::Dependent { combination } => {
                redundant.push(record(&kept, *id, combination.into_iter()))
            }
        }
    }
    (kept, redundant)
}

/// The dense reference sweep: modified Gram-Schmidt, twice, over the rows in model
/// order.
pub fn select_dense(nv: usize, rows: &[JacobianRow]) -> (Vec<(usize, usize)>, Vec<Redundant>) {
    let mut basis: Vec<Vec<f64>> = Vec::new();
    // r_cols[k][j] = component of kept row k on basis vector j (upper triangular R).
    let mut r_cols: Vec<Vec<f64>> = Vec::new();
    let mut kept = Vec::new();
    let mut redundant = Vec::new();
    for (id, entries) in rows {
        let mut b = vec![0.0; nv];
        for &(c, v) in entries {
            b[c] += v;
        }
        let norm0 = b.iter().map(|x| x * x).sum::<f64>().sqrt();
        let mut alpha = vec![0.0; basis.len()];
        for _pass in 0..2 {
            for (j, qv) in basis.iter().enumerate() {
                let d: f64 = qv.iter().zip(&b).map(|(a, c)| a * c).sum();
                alpha[j] += d;
                for (x, a) in b.iter_mut().zip(qv) {
                    *x -= d * a;
                }
            }
        }
        let norm = b.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm0 > 0.0 && norm > TOL * norm0 {
            for x in b.iter_mut() {
                *x /= norm;
            }
            basis.push(b);
            alpha.push(norm);
            r_cols.push(alpha);
            kept.push(*id);
        } else {
            // Solve R c = alpha for the combination of kept rows.
            let k = r_cols.len();
            let mut c = vec![0.0; k];
            for i in (0..k).rev() {
                let mut s = alpha[i];
                for j in i + 1..k {
                    s -= r_cols[j][i] * c[j];
                }
                c[i] = s / r_cols[i][i];
            }
            redundant.push(record(&kept, *id, c.into_iter().enumerate()));
        }
    }
    (kept, redundant)
}
