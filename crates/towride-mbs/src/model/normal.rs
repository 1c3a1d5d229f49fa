//! The normal-equation matrix B W B^T of the kept constraint rows, W block diagonal by
//! body (the identity for minimum-norm corrections, M^-1 for the multipliers), built body
//! by body: rows i and j meet only where they share a body, so the matrix is as sparse
//! as the mechanism is local (block tridiagonal for a chain).
//!
//! Dense up to [`DENSE_ROWS`] kept rows (the figures of the models that ran before the
//! sparse path existed stay bit for bit, and the dense path is as fast there); a sparse
//! Cholesky factorisation above, on a pattern analysed once per [`System`].

use std::cell::RefMut;

use super::system::System;
use super::ModelError;
use towride_solver::linear::SparseCholesky;

/// Up to this many kept constraint rows the start and outputs use dense algebra.
/// Measured (assembly, projection and accelerations; docs/performance.md, "What is
/// sparse"): the two cost the same near 50 to 60 rows and the dense path is 3x slower
/// at 100 (0.31 against 0.10 ms): kept up to 100 so the vehicle (71 rows) keeps its
/// figures bit for bit.
pub const DENSE_ROWS: usize = 100;

/// Kept constraint rows as (multiplier index, [(velocity unknown, B entry)]).
pub type Rows = Vec<(usize, Vec<(usize, f64)>)>;

/// Whether a system with `m` kept rows uses the dense path.
pub fn dense(m: usize) -> bool {
    m <= DENSE_ROWS
}

/// B from (row, column, value) triplets (repeated positions add up).
pub fn rows_of(m: usize, b: &[(usize, usize, f64)]) -> Rows {
    let mut rows: Rows = (0..m).map(|r| (r, Vec::new())).collect();
    for &(r, c, v) in b {
        rows[r].1.push((c, v));
    }
    rows
}

/// Each body's part of B: the rows touching it (positions in `rows`) and their entries
/// on its velocity unknowns, row-major (one row of the body's width per touching row).
pub struct Blocks {
    /// Per body: (positions in `rows`, entries).
    pub body: Vec<(Vec<usize>, Vec<f64>)>,
}

impl Blocks {
    /// The blocks of `rows`.
    pub fn of(sys: &System, rows: &Rows) -> Blocks {
        let nb = sys.nb();
        let mut owner = vec![0; sys.nv];
        for b in 0..nb {
            owner[sys.vo[b]..sys.vo[b] + sys.width(Some(b))].fill(b);
        }
        let mut touching: Vec<Vec<usize>> = vec![Vec::new(); nb];
        for (k, (_, entries)) in rows.iter().enumerate() {
            for &(c, _) in entries {
                let b = owner[c];
                if touching[b].last() != Some(&k) {
                    touching[b].push(k);
                }
            }
        }
        let body = touching
            .into_iter()
            .enumerate()
            .map(|(b, rk)| {
                let (w, o) = (sys.width(Some(b)), sys.vo[b]);
                let mut bb = vec![0.0; rk.len() * w];
                for (i, &k) in rk.iter().enumerate() {
                    for &(c, val) in &rows[k].1 {
                        if owner[c] == b {
                            bb[i * w + c - o] += val;
                        }
                    }
                }
                (rk, bb)
            })
            .collect();
        Blocks { body }
    }
}

/// Adds one body's part of B W B^T: `bb` its block of B, `xb` W applied to each of its
/// rows, `rk` the rows' positions in `rows`. `put(i, j, value)` receives every pair
/// (both orders) when `both`, else each pair once (i <= j by multiplier index).
pub fn add_body(
    rows: &Rows,
    rk: &[usize],
    w: usize,
    bb: &[f64],
    xb: &[f64],
    both: bool,
    put: &mut impl FnMut(usize, usize, f64),
) {
    for (i, &ki) in rk.iter().enumerate() {
        let bi = &bb[i * w..(i + 1) * w];
        let ri = rows[ki].0;
        for (j, &kj) in rk.iter().enumerate() {
            let rj = rows[kj].0;
            if both || ri <= rj {
                put(ri, rj, dot(bi, &xb[j * w..(j + 1) * w]));
            }
        }
    }
}

/// a . b
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The system's sparse symmetric matrix on the pattern of B W B^T (pairs of kept rows
/// sharing a body), cleared; its symbolic analysis is made on first use and kept.
pub fn matrix(sys: &System) -> Result<RefMut<'_, SparseCholesky>, ModelError> {
    let mut cache = sys.normal.borrow_mut();
    if cache.is_none() {
        *cache = Some(SparseCholesky::new(sys.m, pattern(sys))?);
    }
    let mut a = RefMut::map(cache, |c| c.as_mut().expect("built above"));
    a.clear();
    Ok(a)
}

/// Pairs of kept rows that share a body.
fn pattern(sys: &System) -> Vec<(usize, usize)> {
    let mut touching: Vec<Vec<usize>> = vec![Vec::new(); sys.nb()];
    for e in &sys.cons {
        for b in sys.bodies_of(e.mi, e.mj).iter().flatten() {
            touching[*b].extend(e.slot.iter().flatten());
        }
    }
    let mut p = Vec::new();
    for rows in &touching {
        for (i, &a) in rows.iter().enumerate() {
            for &b in &rows[i + 1..] {
                p.push((a, b));
            }
        }
    }
    p
}

/// Minimum-norm solution of B x = rhs by the sparse normal equations:
/// x = B^T (B B^T)^-1 rhs; `None` when B B^T is not positive definite (dependent rows).
pub fn min_norm_sparse(
    sys: &System,
    rows: &Rows,
    rhs: &[f64],
) -> Result<Option<Vec<f64>>, ModelError> {
    let blocks = Blocks::of(sys, rows);
    let mut a = matrix(sys)?;
    let mut put = |i: usize, j: usize, v: f64| {
        a.add(i, j, v).expect("pair of rows sharing a body");
    };
    for (b, (rk, bb)) in blocks.body.iter().enumerate() {
        add_body(rows, rk, sys.width(Some(b)), bb, bb, false, &mut put);
    }
    if a.factor().is_err() {
        return Ok(None);
    }
    let mut y = rhs.to_vec();
    a.solve(&mut y);
    let mut x = vec![0.0; sys.nv];
    for (row, entries) in rows {
        for &(c, v) in entries {
            x[c] += v * y[*row];
        }
    }
    Ok(x.iter().all(|v| v.is_finite()).then_some(x))
}
