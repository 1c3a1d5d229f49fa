//! Redundant constraints: found by a rank-revealing (modified Gram-Schmidt, twice)
//! sweep over the rows of the velocity-space constraint Jacobian B in model order, and
//! eliminated before the run.
//!
//! A row whose component outside the span of the rows already kept is below a relative
//! tolerance restates constraints that are already there (a planar loop built in 3D, a
//! body held by two fixed joints). Keeping it would make the Newton matrix singular; the
//! commercial tool of the thesis zeroes such reactions silently (4.1.2.1). Here the row is
//! dropped, its reaction is carried by the rows it depends on, and the dependency is
//! reported by name so `doctor` can say which joints over-constrain which.

use super::system::{Redundant, System};

/// Relative size below which a row counts as dependent.
const TOL: f64 = 1e-8;

/// Returns the kept rows (element, row) in order and the redundant ones.
pub fn select_rows(sys: &System, t: f64, q: &[f64]) -> (Vec<(usize, usize)>, Vec<Redundant>) {
    let n = sys.nv;
    let mut basis: Vec<Vec<f64>> = Vec::new();
    // r_cols[k][j] = component of kept row k on basis vector j (upper triangular R).
    let mut r_cols: Vec<Vec<f64>> = Vec::new();
    let mut kept = Vec::new();
    let mut redundant = Vec::new();
    for (ei, e) in sys.cons.iter().enumerate() {
        let ev = sys.con_eval(e, t, q);
        let bodies = sys.bodies_of(e.mi, e.mj);
        for r in 0..e.rows.len() {
            let mut b = vec![0.0; n];
            for (side, body) in bodies.iter().enumerate() {
                if let Some(k) = body {
                    for c in 0..ev.w[side] {
                        b[sys.vo[*k] + c] += ev.at(r, side, c);
                    }
                }
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
                kept.push((ei, r));
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
                let big = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let depends_on = c
                    .iter()
                    .enumerate()
                    .filter(|(_, x)| x.abs() > 1e-6 * big)
                    .map(|(j, x)| (kept[j].0, kept[j].1, *x))
                    .collect();
                redundant.push(Redundant {
                    elem: ei,
                    row: r,
                    depends_on,
                });
            }
        }
    }
    (kept, redundant)
}
