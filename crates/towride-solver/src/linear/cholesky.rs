//! Sparse Cholesky factorisation A = L L^T of a symmetric positive definite matrix with a
//! fixed pattern: faer's (approximate-minimum-degree order, simplicial or supernodal by
//! its own flop rule), the symbolic analysis done once per pattern, sequential.
//!
//! For the normal-equation matrices of the constraint Jacobian, B B^T and B M^-1 B^T,
//! whose pattern (rows sharing a body) is fixed for a model: positive definite when the
//! rows are independent, and then as sparse as the mechanism is local.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

use super::Singular;
use crate::SolverError;

/// A symmetric matrix on a fixed pattern (lower triangle stored) and its Cholesky factor.
pub struct SparseCholesky {
    n: usize,
    /// Lower triangle by columns, rows ascending, diagonal included.
    pattern: SymbolicSparseColMat<usize>,
    values: Vec<f64>,
    symbolic: SymbolicCholesky<usize>,
    factor: Vec<f64>,
    factored: bool,
}

impl SparseCholesky {
    /// The pattern: entries (r, c) in either triangle (mirrored onto the lower one); the
    /// diagonal is always included.
    pub fn new(
        n: usize,
        pattern: impl IntoIterator<Item = (usize, usize)>,
    ) -> Result<Self, SolverError> {
        let mut cols: Vec<Vec<usize>> = (0..n).map(|c| vec![c]).collect();
        for (r, c) in pattern {
            if r >= n || c >= n {
                return Err(SolverError::SizeMismatch {
                    what: format!("pattern entry ({r}, {c}) outside a {n} x {n} matrix"),
                });
            }
            cols[r.min(c)].push(r.max(c));
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for col in cols.iter_mut() {
            col.sort_unstable();
            col.dedup();
            row_idx.extend_from_slice(col);
            col_ptr.push(row_idx.len());
        }
        let nnz = row_idx.len();
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Lower,
            SymmetricOrdering::Amd,
            Default::default(),
        )
        .map_err(|e| SolverError::SizeMismatch {
            what: format!("symbolic Cholesky failed: {e:?}"),
        })?;
        Ok(SparseCholesky {
            n,
            factor: vec![0.0; symbolic.len_val()],
            pattern,
            values: vec![0.0; nnz],
            symbolic,
            factored: false,
        })
    }

    /// Order of the matrix.
    pub fn size(&self) -> usize {
        self.n
    }

    /// Non-zeros of the factor L.
    pub fn factor_nnz(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Zeroes the values, keeping the pattern.
    pub fn clear(&mut self) {
        self.values.fill(0.0);
        self.factored = false;
    }

    /// Adds `v` at (r, c) and, the matrix being symmetric, at (c, r): give each
    /// off-diagonal pair once. Entries outside the pattern are an error of the caller.
    pub fn add(&mut self, r: usize, c: usize, v: f64) -> Result<(), (usize, usize)> {
        let (lo, hi) = (r.min(c), r.max(c));
        if hi >= self.n {
            return Err((r, c));
        }
        let (col_ptr, row_idx) = (self.pattern.col_ptr(), self.pattern.row_idx());
        let start = col_ptr[lo];
        match row_idx[start..col_ptr[lo + 1]].binary_search(&hi) {
            Ok(k) => {
                self.values[start + k] += v;
                Ok(())
            }
            Err(_) => Err((r, c)),
        }
    }

    /// Factorises the matrix; an error when it is not numerically positive definite.
    pub fn factor(&mut self) -> Result<(), Singular> {
        self.factored = false;
        if let Some(k) = self.values.iter().position(|v| !v.is_finite()) {
            return Err(Singular {
                columns: vec![],
                rows: vec![],
                detail: format!("non-finite entry {k} in the symmetric matrix"),
            });
        }
        let a = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        let mut mem = MemBuffer::new(
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        self.symbolic
            .factorize_numeric_llt(
                &mut self.factor,
                a,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| Singular {
                columns: vec![],
                rows: vec![],
                detail: format!("not positive definite: {e:?}"),
            })?;
        self.factored = true;
        Ok(())
    }

    /// Solves A x = b in place with the current factor.
    pub fn solve(&self, b: &mut [f64]) {
        assert!(self.factored, "solve called before a successful factor");
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, self.n, 1),
            Par::Seq,
            MemStack::new(&mut mem),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tridiagonal SPD matrix: the solve reproduces a known solution; an indefinite one
    /// is refused.
    #[test]
    fn solves_tridiagonal_and_refuses_indefinite() {
        let n = 50;
        let pattern = (1..n).map(|i| (i, i - 1));
        let mut a = SparseCholesky::new(n, pattern).unwrap();
        for diag in [4.0, 1.0] {
            a.clear();
            for i in 0..n {
                a.add(i, i, diag).unwrap();
                if i > 0 {
                    a.add(i - 1, i, -1.5).unwrap();
                }
            }
            let x: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).cos()).collect();
            let mut b: Vec<f64> = (0..n)
                .map(|i| {
                    diag * x[i]
                        - 1.5 * if i > 0 { x[i - 1] } else { 0.0 }
                        - 1.5 * if i + 1 < n { x[i + 1] } else { 0.0 }
                })
                .collect();
            if diag < 3.0 {
                assert!(a.factor().is_err(), "1 - 2 x 1.5 cos(..) < 0: indefinite");
                continue;
            }
            a.factor().unwrap();
            a.solve(&mut b);
            for i in 0..n {
                assert!((b[i] - x[i]).abs() < 1e-13);
            }
        }
        assert!(a.add(5, 20, 1.0).is_err());
    }
}
