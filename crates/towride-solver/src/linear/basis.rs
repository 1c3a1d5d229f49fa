//! Independent columns of a sparse matrix, chosen in a fixed order: a left-looking sparse
//! LU, P A = L U, of a tall matrix A whose columns are offered one at a time (Gilbert &
//! Peierls 1988, the column solve of CSparse's `cs_lu`), with a rank test on each column.
//!
//! A column is kept when the part of it that the kept columns cannot reproduce on the
//! rows not yet pivotal (the new column of the Schur complement) has a 2-norm above `tol`
//! times the column's own; otherwise it is reported with the combination of kept columns
//! that reproduces it, U^-1 u from the column's pivotal part u. This is the greedy choice
//! of a modified Gram-Schmidt sweep in the same order (which tests the distance to the
//! span itself): the Schur residual bounds that distance from above and, with the
//! bounded multipliers of threshold pivoting, from below within the growth of L, so
//! the two agree except on columns within that factor of the tolerance.
//!
//! The order of the columns is the caller's (it decides which of two dependent columns is
//! reported); the rows are free. Each pivot is taken among the candidates within
//! [`PIVOT_TOL`] of the column's largest by the fewest entries in columns still to come
//! (Markowitz's rule with the column order fixed): a row no later column touches adds
//! no fill, so the factors of a chain or a ladder of loops grow linearly with it.

use std::collections::BinaryHeap;

const NONE: usize = usize::MAX;

/// A pivot is taken down to this fraction of its column's largest candidate.
pub const PIVOT_TOL: f64 = 0.1;

/// What became of an offered column.
#[derive(Clone, Debug, PartialEq)]
pub enum Offer {
    /// Independent of the columns kept before it: kept, as number [`ColumnBasis::rank`]
    /// - 1.
    Kept,
    /// Within the tolerance of the span of the kept columns: not kept.
    Dependent {
        /// (kept column number, coefficient) of the kept columns that reproduce it,
        /// ascending; empty for a zero (or non-finite) column.
        combination: Vec<(usize, f64)>,
    },
}

/// The factorisation of the kept columns, growing with each offered column.
pub struct ColumnBasis {
    n: usize,
    tol: f64,
    /// Pivot position of each row (`NONE`: not pivotal), and the row at each position.
    pinv: Vec<usize>,
    prow: Vec<usize>,
    /// L by pivot position (unit diagonal not stored), rows in the matrix's numbering.
    lp: Vec<usize>,
    li: Vec<usize>,
    lx: Vec<f64>,
    /// U by kept column: strictly upper entries as (pivot position, value), diagonal in
    /// `ud`.
    up: Vec<usize>,
    ui: Vec<usize>,
    ux: Vec<f64>,
    ud: Vec<f64>,
    /// Entries of each row in the columns not offered yet.
    remaining: Vec<usize>,
    /// Dense work vector over rows, zero between offers; marks by offer number.
    x: Vec<f64>,
    mark: Vec<usize>,
    stamp: usize,
}

impl ColumnBasis {
    /// An empty basis for columns of length `n`. `row_counts[i]`: how many of the
    /// columns that will be offered have an entry in row i (the pivot choice prefers
    /// rows few later columns touch); `tol`: the relative size below which a column's
    /// residual counts as zero.
    pub fn new(n: usize, row_counts: Vec<usize>, tol: f64) -> ColumnBasis {
        debug_assert_eq!(row_counts.len(), n);
        ColumnBasis {
            n,
            tol,
            pinv: vec![NONE; n],
            prow: Vec::new(),
            lp: vec![0],
            li: Vec::new(),
            lx: Vec::new(),
            up: vec![0],
            ui: Vec::new(),
            ux: Vec::new(),
            ud: Vec::new(),
            remaining: row_counts,
            x: vec![0.0; n],
            mark: vec![NONE; n],
            stamp: 0,
        }
    }

    /// Number of columns kept.
    pub fn rank(&self) -> usize {
        self.ud.len()
    }

    /// Non-zeros of L and U (diagonals included).
    pub fn nnz(&self) -> usize {
        self.li.len() + self.ui.len() + 2 * self.rank()
    }

    /// Offers the next column (entries (row, value); a row may repeat, its values add).
    pub fn offer(&mut self, col: &[(usize, f64)]) -> Offer {
        for &(r, _) in col {
            self.remaining[r] = self.remaining[r].saturating_sub(1);
        }
        self.stamp += 1;
        let k = self.stamp;
        // Rows of x = L \ a: the pivotal ones in topological order (`topo`, reverse
        // post-order of the depth-first search over L's columns), the others in
        // `pattern`.
        let mut topo: Vec<usize> = Vec::new();
        let mut pattern: Vec<usize> = Vec::new();
        let mut stack: Vec<(usize, usize)> = Vec::new();
        for &(r, _) in col {
            if self.mark[r] == k {
                continue;
            }
            self.mark[r] = k;
            if self.pinv[r] == NONE {
                pattern.push(r);
                continue;
            }
            stack.push((r, self.lp[self.pinv[r]]));
            while let Some(&mut (row, ref mut next)) = stack.last_mut() {
                let end = self.lp[self.pinv[row] + 1];
                let mut pushed = false;
                while *next < end {
                    let child = self.li[*next];
                    *next += 1;
                    if self.mark[child] == k {
                        continue;
                    }
                    self.mark[child] = k;
                    if self.pinv[child] == NONE {
                        pattern.push(child);
                    } else {
                        stack.push((child, self.lp[self.pinv[child]]));
                        pushed = true;
                        break;
                    }
                }
                if !pushed {
                    stack.pop();
                    topo.push(row);
                }
            }
        }
        for &(r, v) in col {
            self.x[r] += v;
        }
        // Every row of the column is in `topo` or `pattern`; the others hold zero yet.
        let norm0 = topo
            .iter()
            .chain(&pattern)
            .map(|&r| self.x[r] * self.x[r])
            .sum::<f64>()
            .sqrt();
        // The pivotal part u (by pivot position) and the Schur residual.
        let mut u: Vec<(usize, f64)> = Vec::with_capacity(topo.len());
        for &r in topo.iter().rev() {
            let p = self.pinv[r];
            let xr = self.x[r];
            self.x[r] = 0.0;
            if xr != 0.0 {
                for t in self.lp[p]..self.lp[p + 1] {
                    self.x[self.li[t]] -= self.lx[t] * xr;
                }
            }
            u.push((p, xr));
        }
        let residual = pattern
            .iter()
            .map(|&r| self.x[r] * self.x[r])
            .sum::<f64>()
            .sqrt();
        let finite = norm0.is_finite() && residual.is_finite();
        if !(finite && norm0 > 0.0 && residual > self.tol * norm0) {
            for &r in &pattern {
                self.x[r] = 0.0;
            }
            let combination = if finite && norm0 > 0.0 {
                self.combination(&u)
            } else {
                Vec::new()
            };
            return Offer::Dependent { combination };
        }
        // Threshold pivoting, then the fewest entries in the columns to come.
        let big = pattern.iter().fold(0.0f64, |m, &r| m.max(self.x[r].abs()));
        let mut best = NONE;
        for &r in &pattern {
            let a = self.x[r].abs();
            if a < PIVOT_TOL * big {
                continue;
            }
            let better = best == NONE
                || self.remaining[r] < self.remaining[best]
                || (self.remaining[r] == self.remaining[best] && a > self.x[best].abs());
            if better {
                best = r;
            }
        }
        let piv = self.x[best];
        let pos = self.rank();
        self.pinv[best] = pos;
        self.prow.push(best);
        for &r in &pattern {
            let xr = self.x[r];
            self.x[r] = 0.0;
            if r != best && xr != 0.0 {
                self.li.push(r);
                self.lx.push(xr / piv);
            }
        }
        self.lp.push(self.li.len());
        for &(p, v) in &u {
            if v != 0.0 {
                self.ui.push(p);
                self.ux.push(v);
            }
        }
        self.up.push(self.ui.len());
        self.ud.push(piv);
        Offer::Kept
    }

    /// c = U^-1 u for the pivotal part u of a dependent column: the kept columns times c
    /// reproduce it. U's entries lie above its diagonal, so taking the positions from
    /// the highest down settles each before it is used.
    fn combination(&self, u: &[(usize, f64)]) -> Vec<(usize, f64)> {
        let mut w: std::collections::HashMap<usize, f64> = std::collections::HashMap::new();
        let mut heap: BinaryHeap<usize> = BinaryHeap::new();
        for &(p, v) in u {
            if v != 0.0 {
                if !w.contains_key(&p) {
                    heap.push(p);
                }
                *w.entry(p).or_insert(0.0) += v;
            }
        }
        let mut out = Vec::new();
        while let Some(p) = heap.pop() {
            let c = w[&p] / self.ud[p];
            if c == 0.0 {
                continue;
            }
            out.push((p, c));
            for t in self.up[p]..self.up[p + 1] {
                let j = self.ui[t];
                let e = w.entry(j).or_insert_with(|| {
                    heap.push(j);
                    0.0
                });
                *e -= self.ux[t] * c;
            }
        }
        out.reverse();
        out
    }

    /// A basis of the null space of the kept columns' transpose, {y : a_k^T y = 0 for
    /// every kept a_k}: one vector per row that is not pivotal, 1 there, 0 on the other
    /// such rows (from L^T P y = 0, as U is regular). Dense, n long each; not
    /// orthonormal.
    pub fn null_space(&self) -> Vec<Vec<f64>> {
        let free: Vec<usize> = (0..self.n).filter(|&r| self.pinv[r] == NONE).collect();
        free.iter()
            .map(|&j| {
                let mut z = vec![0.0; self.n];
                z[j] = 1.0;
                for p in (0..self.rank()).rev() {
                    let s: f64 = (self.lp[p]..self.lp[p + 1])
                        .map(|t| self.lx[t] * z[self.li[t]])
                        .sum();
                    z[self.prow[p]] = -s;
                }
                z
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(n: usize, cols: &[Vec<(usize, f64)>]) -> Vec<usize> {
        let mut c = vec![0; n];
        for col in cols {
            for &(r, _) in col {
                c[r] += 1;
            }
        }
        c
    }

    /// A column equal to 2 a0 - a2 is found dependent with that combination; a zero
    /// column is dependent with none.
    #[test]
    fn dependent_column_and_its_combination() {
        let a0 = vec![(0, 1.0), (1, 2.0), (3, -1.0)];
        let a1 = vec![(1, 1.0), (2, 4.0)];
        let a2 = vec![(0, 3.0), (2, 1.0), (4, 1.0)];
        let a3 = vec![(0, -1.0), (1, 4.0), (2, -1.0), (3, -2.0), (4, -1.0)];
        let cols = vec![a0, a1, a2, a3, vec![]];
        let mut b = ColumnBasis::new(5, counts(5, &cols), 1e-8);
        assert_eq!(b.offer(&cols[0]), Offer::Kept);
        assert_eq!(b.offer(&cols[1]), Offer::Kept);
        assert_eq!(b.offer(&cols[2]), Offer::Kept);
        let Offer::Dependent { combination } = b.offer(&cols[3]) else {
            panic!("a3 = 2 a0 - a2 is dependent");
        };
        let c: Vec<(usize, f64)> = combination
            .into_iter()
            .filter(|(_, v)| v.abs() > 1e-12)
            .collect();
        assert_eq!(c.len(), 2, "{c:?}");
        assert_eq!(c[0].0, 0);
        assert!((c[0].1 - 2.0).abs() < 1e-14);
        assert_eq!(c[1].0, 2);
        assert!((c[1].1 + 1.0).abs() < 1e-14);
        assert_eq!(
            b.offer(&cols[4]),
            Offer::Dependent {
                combination: vec![]
            }
        );
        assert_eq!(b.rank(), 3);
        // The null space is orthogonal to every kept column, and 5 - 3 wide.
        let ns = b.null_space();
        assert_eq!(ns.len(), 2);
        for z in &ns {
            for col in &cols[..3] {
                let d: f64 = col.iter().map(|&(r, v)| v * z[r]).sum();
                assert!(d.abs() < 1e-14, "{d}");
            }
        }
    }

    /// A chain of n two-row blocks with a dependent column per block: the factors stay
    /// linear in n (the Markowitz rule pivots on rows no later column touches).
    #[test]
    fn chain_fill_is_linear() {
        let nnz = |nb: usize| {
            let n = 3 * nb;
            let mut cols = Vec::new();
            for k in 0..nb {
                let r = 3 * k;
                let mut c1 = vec![(r, -1.0), (r + 2, 0.3)];
                let mut c2 = vec![(r + 1, -1.0), (r + 2, 0.7)];
                if k > 0 {
                    c1.extend([(r - 3, 1.0), (r - 2, 0.5)]);
                    c2.push((r - 2, 1.0));
                }
                let c3: Vec<(usize, f64)> = c1
                    .iter()
                    .map(|&(i, v)| (i, 2.0 * v))
                    .chain(c2.iter().map(|&(i, v)| (i, -v)))
                    .collect();
                cols.extend([c1, c2, c3]);
            }
            let mut b = ColumnBasis::new(n, counts(n, &cols), 1e-8);
            let mut dependent = 0;
            for c in &cols {
                if let Offer::Dependent { combination } = b.offer(c) {
                    let big = combination.iter().filter(|e| e.1.abs() > 1e-12).count();
                    assert_eq!(big, 2, "{combination:?}");
                    dependent += 1;
                }
            }
            assert_eq!(dependent, nb);
            b.nnz()
        };
        let (small, large) = (nnz(100), nnz(1000));
        assert!(large <= 11 * small, "{small} -> {large}");
    }
}
