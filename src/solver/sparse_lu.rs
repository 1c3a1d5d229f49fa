//! Sparse LU for the Newton iteration matrix: a left-looking factorisation with threshold
//! partial pivoting (Gilbert & Peierls 1988, as in CSparse's `cs_lu`), and a
//! refactorisation that keeps the pivot sequence and the structure of L and U (KLU's
//! `klu_refactor`, Davis & Palamadai Natarajan 2010).
//!
//! Why not faer's sparse LU alone: the iteration matrix keeps its structure for a whole
//! run and, with row equilibration, its pivots for nearly every factorisation, so after
//! the first factorisation only the arithmetic on a fixed structure is needed. At the
//! vehicle's size (about 500 unknowns, 10 k non-zeros) faer's supernodal kernels spend
//! most of their time on bookkeeping for supernodes of a few columns. The refactorisation
//! checks each pivot against the column's other candidates and asks for a new pivoting
//! factorisation when one has become small.

/// In the pivoting factorisation the diagonal candidate is preferred down to this
/// fraction of the column's largest candidate (keeps the fill of the symmetric
/// fill-reducing order; the threshold of MA48).
const PIVOT_TOL: f64 = 0.1;

/// A kept pivot is used down to this fraction of its column's largest candidate (KLU's
/// default pivot tolerance); below it, a new pivoting factorisation. The gap between the
/// two keeps pivots chosen near the threshold from failing at the next refactorisation
/// (measured on the default scene: 22 pivoting factorisations with one threshold for
/// both, 4 with these two).
const KEEP_TOL: f64 = 1e-3;

/// A column that has no usable pivot (its candidates are all zero or not finite).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ZeroPivot {
    /// The column (unknown) in the matrix's own numbering.
    pub column: usize,
}

/// What a refactorisation found.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Refactor {
    Done,
    /// A kept pivot became too small or zero: factorise with pivoting instead.
    NeedsPivoting,
}

/// LU factors P A Q = L U of a square matrix in compressed-column form, with the
/// structures needed to refactorise the same pattern.
pub(crate) struct SparseLu {
    n: usize,
    /// Column order: pivot column k is column `q[k]` of A.
    q: Vec<usize>,
    /// Row order: `pinv[r]` is the pivot position of row r, `p[k]` the row at position k.
    pinv: Vec<usize>,
    p: Vec<usize>,
    /// L (unit diagonal not stored), columns in pivot order, rows as pivot positions,
    /// ascending.
    lp: Vec<usize>,
    li: Vec<u32>,
    lx: Vec<f64>,
    /// U without its diagonal (kept in `ud`), same conventions.
    up: Vec<usize>,
    ui: Vec<u32>,
    ux: Vec<f64>,
    ud: Vec<f64>,
    /// Per pivot column: (pivot position of the row, index into A's values).
    ap: Vec<usize>,
    amap: Vec<(u32, u32)>,
    /// Dense work vector, zero between uses.
    x: Vec<f64>,
    /// Pivots and structure established by a pivoting factorisation.
    factored: bool,
}

impl SparseLu {
    /// An empty factorisation for an n x n matrix with column order `q` (a fill-reducing
    /// permutation of 0..n).
    pub fn new(n: usize, q: Vec<usize>) -> Self {
        debug_assert_eq!(q.len(), n);
        SparseLu {
            n,
            q,
            pinv: vec![0; n],
            p: vec![0; n],
            lp: vec![0; n + 1],
            li: Vec::new(),
            lx: Vec::new(),
            up: vec![0; n + 1],
            ui: Vec::new(),
            ux: Vec::new(),
            ud: vec![0.0; n],
            ap: vec![0; n + 1],
            amap: Vec::new(),
            x: vec![0.0; n],
            factored: false,
        }
    }

    /// Whether a pivot sequence is kept (a refactorisation is possible).
    pub fn has_pivots(&self) -> bool {
        self.factored
    }

    /// Non-zeros of L and U (without L's unit diagonal).
    #[cfg(test)]
    pub fn nnz(&self) -> usize {
        self.li.len() + self.ui.len() + self.n
    }

    /// Factorises A (CSC: `col_ptr`, `row_idx`, `val`) with threshold partial pivoting,
    /// preferring the diagonal entry of the column (row `q[k]` for pivot column k).
    pub fn factor(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[usize],
        val: &[f64],
    ) -> Result<(), ZeroPivot> {
        let n = self.n;
        const NONE: usize = usize::MAX;
        self.factored = false;
        // L with original row numbers while factorising.
        let mut lrow: Vec<usize> = Vec::with_capacity(4 * val.len());
        let mut lval: Vec<f64> = Vec::with_capacity(4 * val.len());
        let mut lp = vec![0usize; n + 1];
        let mut urow: Vec<usize> = Vec::with_capacity(4 * val.len());
        let mut uval: Vec<f64> = Vec::with_capacity(4 * val.len());
        let mut up = vec![0usize; n + 1];
        let mut pinv = vec![NONE; n];
        let x = &mut self.x;
        // Depth-first search state.
        let mut mark = vec![NONE; n];
        let mut stack: Vec<(usize, usize)> = Vec::with_capacity(n);
        let mut topo: Vec<usize> = Vec::with_capacity(n);
        let mut pattern: Vec<usize> = Vec::with_capacity(n);
        for k in 0..n {
            let col = self.q[k];
            // Pattern of x = L \ A(:, col): the rows of A(:, col) and everything reachable
            // from the pivotal ones through L's columns, in topological order.
            topo.clear();
            pattern.clear();
            for &r in &row_idx[col_ptr[col]..col_ptr[col + 1]] {
                if mark[r] == k {
                    continue;
                }
                if pinv[r] == NONE {
                    mark[r] = k;
                    pattern.push(r);
                    continue;
                }
                // Iterative DFS from pivotal row r over L's columns.
                mark[r] = k;
                stack.push((r, lp[pinv[r]]));
                while let Some(&mut (row, ref mut next)) = stack.last_mut() {
                    let c = pinv[row];
                    let end = lp[c + 1];
                    let mut pushed = false;
                    while *next < end {
                        let child = lrow[*next];
                        *next += 1;
                        if mark[child] == k {
                            continue;
                        }
                        mark[child] = k;
                        if pinv[child] == NONE {
                            pattern.push(child);
                        } else {
                            stack.push((child, lp[pinv[child]]));
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
            // Numeric solve with L in topological order (reverse post-order).
            for kk in col_ptr[col]..col_ptr[col + 1] {
                x[row_idx[kk]] += val[kk];
            }
            for &r in topo.iter().rev() {
                let c = pinv[r];
                let xr = x[r];
                if xr != 0.0 {
                    for t in lp[c]..lp[c + 1] {
                        x[lrow[t]] -= lval[t] * xr;
                    }
                }
                urow.push(c);
                uval.push(xr);
                x[r] = 0.0;
            }
            up[k + 1] = urow.len();
            // Pivot: the diagonal row if it is within PIVOT_TOL of the largest candidate.
            let mut best = NONE;
            let mut big = 0.0f64;
            for &r in &pattern {
                let a = x[r].abs();
                if a > big || (best == NONE && a.is_nan()) {
                    big = a;
                    best = r;
                }
            }
            let diag = col;
            if mark[diag] == k && pinv[diag] == NONE && x[diag].abs() >= PIVOT_TOL * big {
                best = diag;
            }
            if best == NONE || big == 0.0 || !big.is_finite() || !x[best].is_finite() {
                for &r in &pattern {
                    x[r] = 0.0;
                }
                return Err(ZeroPivot { column: col });
            }
            let piv = x[best];
            pinv[best] = k;
            self.ud[k] = piv;
            for &r in &pattern {
                if r != best {
                    lrow.push(r);
                    lval.push(x[r] / piv);
                }
                x[r] = 0.0;
            }
            lp[k + 1] = lrow.len();
        }
        // Rows as pivot positions, sorted ascending within each column (a topological
        // order for the refactorisation and the solves).
        for (k, &r) in pinv.iter().enumerate() {
            self.p[r] = k;
        }
        self.pinv = pinv;
        let sort_cols = |ptr: &[usize], rows: &mut Vec<usize>, vals: &mut Vec<f64>| {
            let mut pairs: Vec<(usize, f64)> = Vec::new();
            for c in 0..n {
                pairs.clear();
                pairs.extend((ptr[c]..ptr[c + 1]).map(|t| (rows[t], vals[t])));
                pairs.sort_unstable_by_key(|e| e.0);
                for (o, (r, v)) in pairs.iter().enumerate() {
                    rows[ptr[c] + o] = *r;
                    vals[ptr[c] + o] = *v;
                }
            }
        };
        for r in lrow.iter_mut() {
            *r = self.pinv[*r];
        }
        sort_cols(&lp, &mut lrow, &mut lval);
        sort_cols(&up, &mut urow, &mut uval);
        self.li = lrow.iter().map(|&r| r as u32).collect();
        self.lx = lval;
        self.lp = lp;
        self.ui = urow.iter().map(|&r| r as u32).collect();
        self.ux = uval;
        self.up = up;
        // Where each entry of A lands in the refactorisation.
        self.amap.clear();
        self.ap[0] = 0;
        for k in 0..n {
            let col = self.q[k];
            for t in col_ptr[col]..col_ptr[col + 1] {
                self.amap.push((self.pinv[row_idx[t]] as u32, t as u32));
            }
            self.ap[k + 1] = self.amap.len();
        }
        self.factored = true;
        Ok(())
    }

    /// Factorises A anew on the kept pivots and structure (same pattern as the last
    /// pivoting factorisation).
    pub fn refactor(&mut self, val: &[f64]) -> Refactor {
        debug_assert!(self.factored);
        let n = self.n;
        let x = &mut self.x;
        for k in 0..n {
            for &(r, t) in &self.amap[self.ap[k]..self.ap[k + 1]] {
                x[r as usize] += val[t as usize];
            }
            for t in self.up[k]..self.up[k + 1] {
                let c = self.ui[t] as usize;
                let xc = x[c];
                x[c] = 0.0;
                self.ux[t] = xc;
                if xc != 0.0 {
                    for s in self.lp[c]..self.lp[c + 1] {
                        x[self.li[s] as usize] -= self.lx[s] * xc;
                    }
                }
            }
            let piv = x[k];
            x[k] = 0.0;
            let (lo, hi) = (self.lp[k], self.lp[k + 1]);
            let mut big = 0.0f64;
            for s in lo..hi {
                big = big.max(x[self.li[s] as usize].abs());
            }
            // (big NaN: the comparison fails too, and the pivoting factorisation reports it)
            let kept = piv.is_finite() && piv != 0.0 && piv.abs() >= KEEP_TOL * big;
            if !kept {
                for s in lo..hi {
                    x[self.li[s] as usize] = 0.0;
                }
                for v in x.iter_mut() {
                    *v = 0.0;
                }
                self.factored = false;
                return Refactor::NeedsPivoting;
            }
            self.ud[k] = piv;
            let inv = 1.0 / piv;
            for s in lo..hi {
                let r = self.li[s] as usize;
                self.lx[s] = x[r] * inv;
                x[r] = 0.0;
            }
        }
        Refactor::Done
    }

    /// Solves A x = b in place.
    pub fn solve(&mut self, b: &mut [f64]) {
        let n = self.n;
        let y = &mut self.x;
        for k in 0..n {
            y[k] = b[self.p[k]];
        }
        for k in 0..n {
            let yk = y[k];
            if yk != 0.0 {
                for s in self.lp[k]..self.lp[k + 1] {
                    y[self.li[s] as usize] -= self.lx[s] * yk;
                }
            }
        }
        for k in (0..n).rev() {
            let yk = y[k] / self.ud[k];
            y[k] = yk;
            if yk != 0.0 {
                for s in self.up[k]..self.up[k + 1] {
                    y[self.ui[s] as usize] -= self.ux[s] * yk;
                }
            }
        }
        for k in 0..n {
            b[self.q[k]] = y[k];
            y[k] = 0.0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Probe on a matrix file (development only).
    #[test]
    #[ignore]
    fn probe_matrix_market() {
        use faer::dyn_stack::{MemBuffer, MemStack};
        let text = std::fs::read_to_string("/tmp/J.mtx").unwrap();
        let kinds: Vec<i32> = std::fs::read_to_string("/tmp/J_kinds.txt")
            .unwrap()
            .lines()
            .map(|l| l.trim().parse().unwrap())
            .collect();
        let mut lines = text.lines().filter(|l| !l.starts_with('%'));
        let head: Vec<usize> = lines
            .next()
            .unwrap()
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        let n = head[0];
        let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        let h = 1.0 / 2000.0;
        for l in lines {
            let v: Vec<&str> = l.split_whitespace().collect();
            let (r, c, x): (usize, usize, f64) = (
                v[0].parse().unwrap(),
                v[1].parse().unwrap(),
                v[2].parse().unwrap(),
            );
            let s = if kinds[c - 1] > 1 { 1.0 / h } else { 1.0 };
            cols[c - 1].push((r - 1, x * s));
        }
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut val = Vec::new();
        for c in cols.iter_mut() {
            if !c.iter().any(|e| e.0 == col_ptr.len() - 1) {
                c.push((col_ptr.len() - 1, 0.0));
            }
            c.sort_by_key(|e| e.0);
            for &(r, x) in c.iter() {
                row_idx.push(r);
                val.push(x);
            }
            col_ptr.push(row_idx.len());
        }
        // row equilibration
        let mut rmax = vec![0.0f64; n];
        for c in 0..n {
            for t in col_ptr[c]..col_ptr[c + 1] {
                rmax[row_idx[t]] = rmax[row_idx[t]].max(val[t].abs());
            }
        }
        for c in 0..n {
            for t in col_ptr[c]..col_ptr[c + 1] {
                val[t] /= rmax[row_idx[t]];
            }
        }
        let sym = faer::sparse::SymbolicSparseColMat::new_checked(
            n,
            n,
            col_ptr.clone(),
            None,
            row_idx.clone(),
        );
        // COLAMD order
        let mut perm = vec![0usize; n];
        let mut pinv = vec![0usize; n];
        let req = faer::sparse::linalg::colamd::order_scratch::<usize>(n, n, row_idx.len());
        let mut mem = MemBuffer::new(req);
        faer::sparse::linalg::colamd::order(
            &mut perm,
            &mut pinv,
            sym.as_ref(),
            Default::default(),
            MemStack::new(&mut mem),
        )
        .unwrap();
        let mut perm2 = vec![0usize; n];
        let mut pinv2 = vec![0usize; n];
        let req =
            faer::sparse::linalg::amd::order_maybe_unsorted_scratch::<usize>(n, row_idx.len());
        let mut mem = MemBuffer::new(req);
        faer::sparse::linalg::amd::order_maybe_unsorted(
            &mut perm2,
            &mut pinv2,
            sym.as_ref(),
            Default::default(),
            MemStack::new(&mut mem),
        )
        .unwrap();
        let xs: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
        let mut b = vec![0.0; n];
        for c in 0..n {
            for t in col_ptr[c]..col_ptr[c + 1] {
                b[row_idx[t]] += val[t] * xs[c];
            }
        }
        for (name, q) in [
            ("colamd", perm.clone()),
            ("amd", perm2.clone()),
            ("natural", (0..n).collect()),
        ] {
            let mut lu = SparseLu::new(n, q);
            let t0 = std::time::Instant::now();
            lu.factor(&col_ptr, &row_idx, &val).unwrap();
            let tf = t0.elapsed().as_secs_f64();
            let t0 = std::time::Instant::now();
            let reps = 200;
            for _ in 0..reps {
                assert_eq!(lu.refactor(&val), Refactor::Done);
            }
            let tr = t0.elapsed().as_secs_f64() / reps as f64;
            let mut x = b.clone();
            let t0 = std::time::Instant::now();
            for _ in 0..reps {
                x.copy_from_slice(&b);
                lu.solve(&mut x);
            }
            let ts = t0.elapsed().as_secs_f64() / reps as f64;
            let err = x
                .iter()
                .zip(&xs)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            eprintln!(
                "{name}: nnz(L+U) {} factor {:.0} us refactor {:.0} us solve {:.1} us err {:.1e}",
                lu.nnz(),
                tf * 1e6,
                tr * 1e6,
                ts * 1e6,
                err
            );
        }
    }
}
