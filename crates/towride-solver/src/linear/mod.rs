//! The Newton iteration matrix J = dF/dy + cj dF/dy': storage, finite-difference
//! assembly by column colouring, scaling and LU factorisation: nalgebra's dense LU for
//! small systems (faer's dense LU costs about twice as much per solve at n < 40), the
//! refactorising sparse LU of [`super::sparse_lu`] on faer's approximate-minimum-degree
//! order for large ones.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SymbolicSparseColMat;
use nalgebra::{DMatrix, DVectorViewMut, Dyn, LU};

use super::sparse_lu::{Refactor, SparseLu};
use super::SolverError;

pub mod basis;
mod cholesky;
mod complex;
pub use basis::{ColumnBasis, Offer};
pub use cholesky::SparseCholesky;
pub use complex::ComplexMatrix;

/// Why a factorisation or solve failed; the solver turns this into a step cut or an error.
#[derive(Debug, Clone)]
pub struct Singular {
    /// Unknowns (columns) or equations (rows) involved, as indices.
    pub columns: Vec<usize>,
    /// Equations (rows) involved, as indices.
    pub rows: Vec<usize>,
    /// What failed, in words, for the error message.
    pub detail: String,
}

#[allow(clippy::large_enum_variant)] // one per solver, never moved in a hot path
enum Storage {
    Dense {
        a: DMatrix<f64>,
        lu: Option<LU<f64, Dyn, Dyn>>,
    },
    Sparse {
        values: Vec<f64>,
        scaled: Vec<f64>,
        lu: SparseLu<f64>,
        factored: bool,
    },
}

/// The iteration matrix with its sparsity structure and current factorisation.
pub struct NewtonMatrix {
    n: usize,
    storage: Storage,
    /// Column-major structure (also used by the dense path for colouring).
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Groups of structurally orthogonal columns for finite differences, made on first
    /// use: a problem with an analytic matrix never needs them, and at 1150 unknowns
    /// they were a quarter of the integrator's set-up.
    colours: Option<Vec<Vec<usize>>>,
    row_scale: Vec<f64>,
    col_scale: Vec<f64>,
    work: Vec<f64>,
    /// Where each `add` since the last `clear` landed, (r, c, index into the values): an
    /// assembly repeats its sequence of entries, so the next entry is looked up here
    /// before its column is searched.
    trail: Vec<(usize, usize, usize)>,
    cursor: usize,
    /// The trail is being written (first assembly, or after too many misses).
    recording: bool,
    misses: usize,
    /// The matrix at the last evaluation, its leading coefficient, and dF/dy' once
    /// known: J at another cj is `base + (cj - base_cj) yp_part`.
    base: Vec<f64>,
    base_cj: f64,
    yp_part: Option<Vec<f64>>,
}

impl NewtonMatrix {
    /// Builds the structure. `pattern = None` means a full (dense) structure. The diagonal
    /// is always included so scaled and initial-value matrices stay well formed.
    pub fn new(
        n: usize,
        pattern: Option<Vec<(usize, usize)>>,
        dense: bool,
    ) -> Result<Self, SolverError> {
        let (col_ptr, row_idx) = match pattern {
            Some(p) => compressed_columns(n, &p)?,
            None => (
                (0..=n).map(|c| c * n).collect(),
                (0..n).flat_map(|_| 0..n).collect(),
            ),
        };
        let storage = if dense {
            Storage::Dense {
                a: DMatrix::zeros(n, n),
                lu: None,
            }
        } else {
            let nnz = row_idx.len();
            Storage::Sparse {
                values: vec![0.0; nnz],
                scaled: vec![0.0; nnz],
                lu: SparseLu::new(n, fill_reducing_order(n, &col_ptr, &row_idx)?),
                factored: false,
            }
        };
        Ok(Self {
            n,
            storage,
            col_ptr,
            row_idx,
            colours: None,
            row_scale: vec![1.0; n],
            col_scale: vec![1.0; n],
            work: vec![0.0; n],
            trail: Vec::new(),
            cursor: 0,
            recording: true,
            misses: 0,
            base: Vec::new(),
            base_cj: 0.0,
            yp_part: None,
        })
    }

    /// The stored values (column-major for the dense path, structure order otherwise).
    fn values_mut(&mut self) -> &mut [f64] {
        match &mut self.storage {
            Storage::Dense { a, .. } => a.as_mut_slice(),
            Storage::Sparse { values, .. } => values,
        }
    }

    /// Keeps the matrix just assembled, J = dF/dy + cj dF/dy', as the base of later
    /// recombinations; dF/dy' is not known yet.
    pub fn keep_as_base(&mut self, cj: f64) {
        let mut base = std::mem::take(&mut self.base);
        base.clear();
        base.extend_from_slice(self.values_mut());
        self.base = base;
        self.base_cj = cj;
        self.yp_part = None;
    }

    /// Whether a base matrix is kept, and whether its dF/dy' part is known.
    pub fn has_base(&self) -> bool {
        !self.base.is_empty()
    }

    /// Whether the dF/dy' part of the base matrix is known (needed by
    /// [`NewtonMatrix::recombine`]).
    pub fn has_yp_part(&self) -> bool {
        self.yp_part.is_some()
    }

    /// dF/dy' at the base's state from its entries (r, c, value; repeats add up), as a
    /// problem reports them with the evaluation.
    pub fn set_yp_part(&mut self, entries: &[(usize, usize, f64)]) {
        let mut yp = vec![0.0; self.base.len()];
        for &(r, c, v) in entries {
            let k = match &self.storage {
                Storage::Dense { .. } => Some(c * self.n + r),
                Storage::Sparse { .. } => {
                    let lo = self.col_ptr[c];
                    self.row_idx[lo..self.col_ptr[c + 1]]
                        .binary_search(&r)
                        .ok()
                        .map(|k| lo + k)
                }
            };
            if let Some(k) = k {
                yp[k] += v;
            }
        }
        self.yp_part = Some(yp);
    }

    /// The matrix just assembled is dF/dy at the base's state (cj = 0): dF/dy' follows as
    /// (base - it) / base_cj. Leaves the base in place.
    pub fn take_yp_part(&mut self) {
        let cj = self.base_cj;
        let base = std::mem::take(&mut self.base);
        let yp: Vec<f64> = self
            .values_mut()
            .iter()
            .zip(&base)
            .map(|(fy, b)| (b - fy) / cj)
            .collect();
        self.values_mut().copy_from_slice(&base);
        self.base = base;
        self.yp_part = Some(yp);
    }

    /// Sets the values to base + (cj - base_cj) dF/dy' (the matrix at a new leading
    /// coefficient, same state); needs [`NewtonMatrix::take_yp_part`] first.
    pub fn recombine(&mut self, cj: f64) {
        let d = cj - self.base_cj;
        let base = std::mem::take(&mut self.base);
        let yp = self
            .yp_part
            .take()
            .expect("dF/dy' part taken before recombining");
        for ((v, b), p) in self.values_mut().iter_mut().zip(&base).zip(&yp) {
            *v = b + d * p;
        }
        self.base = base;
        self.yp_part = Some(yp);
    }

    /// The kept evaluation as (J at `base_cj`, `base_cj`, dF/dy'), in storage order
    /// (structure order for the sparse path, column-major n x n for the dense one), once
    /// dF/dy' is known. J at any shift s is `base + (s - base_cj) dF/dy'`.
    pub fn shifted_parts(&self) -> Option<(&[f64], f64, &[f64])> {
        let yp = self.yp_part.as_deref()?;
        (!self.base.is_empty()).then_some((self.base.as_slice(), self.base_cj, yp))
    }

    /// Column-major structure (column pointers, row indices).
    pub(crate) fn structure(&self) -> (&[usize], &[usize]) {
        (&self.col_ptr, &self.row_idx)
    }

    /// True when the dense (not sparse) storage is in use.
    pub fn is_dense(&self) -> bool {
        matches!(self.storage, Storage::Dense { .. })
    }

    /// Number of structurally non-zero entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Non-zeros of the sparse LU factors (L + U), once factorised; `None` on the dense path.
    pub fn lu_nnz(&self) -> Option<usize> {
        match &self.storage {
            Storage::Sparse { lu, factored, .. } => factored.then(|| lu.nnz()),
            Storage::Dense { .. } => None,
        }
    }

    /// The column colouring for finite differences, made now if it was not kept; give it
    /// back with [`Self::keep_colours`].
    pub fn take_colours(&mut self) -> Vec<Vec<usize>> {
        self.colours
            .take()
            .unwrap_or_else(|| colour_columns(self.n, &self.col_ptr, &self.row_idx))
    }

    /// Keeps the colouring taken by [`Self::take_colours`] for the next evaluation.
    pub fn keep_colours(&mut self, colours: Vec<Vec<usize>>) {
        self.colours = Some(colours);
    }

    /// Rows of column `c` in the structure.
    pub fn column_rows(&self, c: usize) -> &[usize] {
        &self.row_idx[self.col_ptr[c]..self.col_ptr[c + 1]]
    }

    /// Zeroes the values for a new assembly, keeping the structure (and the recorded
    /// assembly order while it keeps matching).
    pub fn clear(&mut self) {
        // Re-record when the last assembly followed another order.
        if self.recording {
            self.recording = self.trail.is_empty();
        } else if 8 * self.misses > self.trail.len() {
            self.trail.clear();
            self.recording = true;
        }
        self.cursor = 0;
        self.misses = 0;
        match &mut self.storage {
            Storage::Dense { a, .. } => a.fill(0.0),
            Storage::Sparse { values, .. } => values.fill(0.0),
        }
    }

    /// Adds `v` at (r, c); entries outside the structure are an error of the problem.
    pub fn add(&mut self, r: usize, c: usize, v: f64) -> Result<(), (usize, usize)> {
        if r >= self.n || c >= self.n {
            return Err((r, c));
        }
        match &mut self.storage {
            Storage::Dense { a, .. } => {
                a[(r, c)] += v;
                Ok(())
            }
            Storage::Sparse { values, .. } => {
                // Entries skipped as zero this time: look a few places ahead.
                let ahead = &self.trail[self.cursor.min(self.trail.len())..];
                if let Some(j) = ahead.iter().take(4).position(|e| (e.0, e.1) == (r, c)) {
                    values[ahead[j].2] += v;
                    self.cursor += j + 1;
                    return Ok(());
                }
                let lo = self.col_ptr[c];
                let rows = &self.row_idx[lo..self.col_ptr[c + 1]];
                match rows.binary_search(&r) {
                    Ok(k) => {
                        values[lo + k] += v;
                        if self.recording {
                            self.trail.push((r, c, lo + k));
                            self.cursor = self.trail.len();
                        } else {
                            self.misses += 1;
                        }
                        Ok(())
                    }
                    Err(_) => Err((r, c)),
                }
            }
        }
    }

    /// Sets column `c` from a dense vector of differences, on its structural rows.
    pub fn set_column_from(&mut self, c: usize, col: &[f64]) {
        let (lo, hi) = (self.col_ptr[c], self.col_ptr[c + 1]);
        match &mut self.storage {
            Storage::Dense { a, .. } => {
                for &r in &self.row_idx[lo..hi] {
                    a[(r, c)] = col[r];
                }
            }
            Storage::Sparse { values, .. } => {
                for k in lo..hi {
                    values[k] = col[self.row_idx[k]];
                }
            }
        }
    }

    /// Value at (r, c), zero outside the structure.
    #[cfg(test)]
    pub fn get(&self, r: usize, c: usize) -> f64 {
        match &self.storage {
            Storage::Dense { a, .. } => a[(r, c)],
            Storage::Sparse { values, .. } => {
                let lo = self.col_ptr[c];
                let rows = &self.row_idx[lo..self.col_ptr[c + 1]];
                rows.binary_search(&r)
                    .map(|k| values[lo + k])
                    .unwrap_or(0.0)
            }
        }
    }

    /// Factorises diag(row) * J * diag(col_scale). `col_scale` scales unknowns (h^(k-1) for
    /// index-k unknowns); rows are then equilibrated to unit maximum when `equilibrate`.
    pub fn factor(&mut self, col_scale: &[f64], equilibrate: bool) -> Result<(), Singular> {
        let n = self.n;
        self.col_scale.copy_from_slice(col_scale);
        let mut row_max = vec![0.0f64; n];
        // The values in structure order (the dense path gathers them once).
        let gathered;
        let vals: &[f64] = match &self.storage {
            Storage::Sparse { values, .. } => values,
            Storage::Dense { .. } => {
                gathered = (0..n)
                    .flat_map(|c| (self.col_ptr[c]..self.col_ptr[c + 1]).map(move |k| (k, c)))
                    .map(|(k, c)| self.value_at(k, c))
                    .collect::<Vec<f64>>();
                &gathered
            }
        };
        for c in 0..n {
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                let r = self.row_idx[k];
                let v = (vals[k] * col_scale[c]).abs();
                if v.is_nan() || v.is_infinite() {
                    return Err(Singular {
                        columns: vec![c],
                        rows: vec![r],
                        detail: format!("non-finite Jacobian entry at equation {r}, unknown {c}"),
                    });
                }
                row_max[r] = row_max[r].max(v);
            }
        }
        if let Some(r) = row_max.iter().position(|m| *m == 0.0) {
            return Err(Singular {
                columns: vec![],
                rows: vec![r],
                detail: format!("equation {r} has an all-zero row"),
            });
        }
        for r in 0..n {
            self.row_scale[r] = if equilibrate { 1.0 / row_max[r] } else { 1.0 };
        }
        let (col_ptr, row_idx) = (&self.col_ptr, &self.row_idx);
        let (rs, cs) = (&self.row_scale, &self.col_scale);
        match &mut self.storage {
            Storage::Dense { a, lu } => {
                // Partial pivoting permutes rows only, so U's diagonal index is the unknown.
                let f = DMatrix::from_fn(n, n, |r, c| a[(r, c)] * rs[r] * cs[c]).lu();
                let (small, umax) = {
                    let lu_mat = f.lu_internal();
                    let umax = (0..n).map(|i| lu_mat[(i, i)].abs()).fold(0.0, f64::max);
                    let tiny = umax * f64::EPSILON * (n as f64);
                    let small: Vec<usize> = (0..n)
                        .filter(|&i| lu_mat[(i, i)].abs() <= tiny || lu_mat[(i, i)].is_nan())
                        .collect();
                    (small, umax)
                };
                if !small.is_empty() {
                    *lu = None;
                    return Err(Singular {
                        detail: format!(
                            "zero pivot for unknown(s) {:?} (|u_ii| <= {:.1e} * max {:.1e})",
                            small,
                            f64::EPSILON * n as f64,
                            umax
                        ),
                        columns: small,
                        rows: vec![],
                    });
                }
                *lu = Some(f);
                Ok(())
            }
            Storage::Sparse {
                values,
                scaled,
                lu,
                factored,
            } => {
                for c in 0..n {
                    for k in col_ptr[c]..col_ptr[c + 1] {
                        scaled[k] = values[k] * rs[row_idx[k]] * cs[c];
                    }
                }
                *factored = false;
                // The kept pivots first; a new pivoting factorisation when one of them
                // has become small against its column.
                if lu.has_pivots() && lu.refactor(scaled) == Refactor::Done {
                    *factored = true;
                    return Ok(());
                }
                match lu.factor(col_ptr, row_idx, scaled) {
                    Ok(()) => {
                        *factored = true;
                        Ok(())
                    }
                    Err(z) => Err(Singular {
                        columns: vec![z.column],
                        rows: vec![],
                        detail: format!(
                            "no usable pivot for unknown {} in the sparse LU",
                            z.column
                        ),
                    }),
                }
            }
        }
    }

    fn value_at(&self, k: usize, c: usize) -> f64 {
        match &self.storage {
            Storage::Dense { a, .. } => a[(self.row_idx[k], c)],
            Storage::Sparse { values, .. } => values[k],
        }
    }

    /// Solves J x = b in place (b in, x out) with the current factorisation.
    pub fn solve(&mut self, b: &mut [f64]) -> Result<(), Singular> {
        let n = self.n;
        for (w, (bi, rs)) in self.work.iter_mut().zip(b.iter().zip(&self.row_scale)) {
            *w = bi * rs;
        }
        match &mut self.storage {
            Storage::Dense { lu, .. } => {
                let lu = lu.as_ref().expect("solve called before factor");
                let mut v = DVectorViewMut::from_slice(&mut self.work, n);
                if !lu.solve_mut(&mut v) {
                    return Err(Singular {
                        columns: vec![],
                        rows: vec![],
                        detail: "singular dense LU".into(),
                    });
                }
            }
            Storage::Sparse { lu, factored, .. } => {
                assert!(*factored, "solve called before factor");
                lu.solve(&mut self.work);
            }
        }
        if let Some(i) = self.work.iter().position(|v| !v.is_finite()) {
            return Err(Singular {
                columns: vec![i],
                rows: vec![],
                detail: format!("non-finite Newton correction on unknown {i}"),
            });
        }
        for (bi, (w, cs)) in b.iter_mut().zip(self.work.iter().zip(&self.col_scale)) {
            *bi = w * cs;
        }
        Ok(())
    }
}

/// Approximate minimum degree order of the pattern of A + A^T (faer's AMD): the
/// iteration matrix is nearly structurally symmetric and its pivots mostly on the
/// diagonal, where this gives a quarter less fill than COLAMD's unsymmetric order
/// (measured on the vehicle: 23 k against 30 k non-zeros in L + U).
pub(crate) fn fill_reducing_order(
    n: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> Result<Vec<usize>, SolverError> {
    let sym = SymbolicSparseColMat::new_checked(n, n, col_ptr.to_vec(), None, row_idx.to_vec());
    let (mut perm, mut perm_inv) = (vec![0usize; n], vec![0usize; n]);
    let req = faer::sparse::linalg::amd::order_maybe_unsorted_scratch::<usize>(n, row_idx.len());
    let mut mem = MemBuffer::new(req);
    faer::sparse::linalg::amd::order_maybe_unsorted(
        &mut perm,
        &mut perm_inv,
        sym.as_ref(),
        Default::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| SolverError::SizeMismatch {
        what: format!("fill-reducing order failed: {e:?}"),
    })?;
    Ok(perm)
}

/// Compressed columns of `pattern` plus the diagonal, rows ascending and unique, by a
/// counting sort in O(entries): a vector per column and a sort of each cost a fifth of
/// the integrator's set-up on a chain of 50 links.
fn compressed_columns(
    n: usize,
    pattern: &[(usize, usize)],
) -> Result<(Vec<usize>, Vec<usize>), SolverError> {
    if let Some(&(r, c)) = pattern.iter().find(|&&(r, c)| r >= n || c >= n) {
        return Err(SolverError::SizeMismatch {
            what: format!("pattern entry ({r}, {c}) outside a {n} x {n} matrix"),
        });
    }
    // Bucket by row first, then by column: each column's rows come out ascending.
    let mut row_start = vec![0usize; n + 1];
    for &(r, _) in pattern {
        row_start[r + 1] += 1;
    }
    for r in 0..n {
        row_start[r + 1] += row_start[r] + 1;
    }
    let mut by_row = vec![0usize; pattern.len() + n];
    let mut fill = row_start.clone();
    for c in 0..n {
        by_row[fill[c]] = c;
        fill[c] += 1;
    }
    for &(r, c) in pattern {
        by_row[fill[r]] = c;
        fill[r] += 1;
    }
    let mut col_count = vec![0usize; n + 1];
    let mut seen = vec![usize::MAX; n];
    let mut triples = Vec::with_capacity(by_row.len());
    for r in 0..n {
        for &c in &by_row[row_start[r]..row_start[r + 1]] {
            // Rows are visited in order, so `seen[c] == r` marks a repeat in this row.
            if seen[c] != r {
                seen[c] = r;
                col_count[c + 1] += 1;
                triples.push((r, c));
            }
        }
    }
    for c in 0..n {
        col_count[c + 1] += col_count[c];
    }
    let mut row_idx = vec![0usize; triples.len()];
    let mut fill = col_count.clone();
    for (r, c) in triples {
        row_idx[fill[c]] = r;
        fill[c] += 1;
    }
    Ok((col_count, row_idx))
}

/// Greedy distance-2 colouring: columns of one colour share no row, so one residual
/// evaluation perturbing all of them gives each column's finite difference (Curtis,
/// Powell & Reid 1974).
fn colour_columns(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Vec<Vec<usize>> {
    // The transpose (columns of each row, ascending), flat: per-row vectors cost a
    // third of the colouring at 18 k unknowns.
    let mut row_ptr = vec![0usize; n + 1];
    for &r in row_idx {
        row_ptr[r + 1] += 1;
    }
    for r in 0..n {
        row_ptr[r + 1] += row_ptr[r];
    }
    let mut fill = row_ptr.clone();
    let mut row_cols = vec![0usize; row_idx.len()];
    for c in 0..n {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            row_cols[fill[r]] = c;
            fill[r] += 1;
        }
    }
    let mut colour = vec![usize::MAX; n];
    let mut forbidden_mark = vec![usize::MAX; n + 1];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for c in 0..n {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            // Only the columns before c are coloured yet.
            for &k in row_cols[row_ptr[r]..row_ptr[r + 1]]
                .iter()
                .take_while(|&&k| k < c)
            {
                forbidden_mark[colour[k]] = c;
            }
        }
        let g = (0..)
            .find(|g| forbidden_mark[*g] != c)
            .expect("a free colour");
        colour[c] = g;
        if g == groups.len() {
            groups.push(Vec::new());
        }
        groups[g].push(c);
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tridiag(n: usize) -> Vec<(usize, usize)> {
        let mut p = Vec::new();
        for i in 0..n {
            p.push((i, i));
            if i > 0 {
                p.push((i, i - 1));
                p.push((i - 1, i));
            }
        }
        p
    }

    #[test]
    fn compressed_columns_sort_deduplicate_and_add_the_diagonal() {
        // Repeats, any order, a missing diagonal: the reference is a sorted set.
        let p = vec![
            (3, 0),
            (1, 2),
            (0, 0),
            (3, 0),
            (2, 1),
            (0, 3),
            (1, 2),
            (2, 0),
        ];
        let (ptr, rows) = compressed_columns(4, &p).unwrap();
        let mut want: Vec<(usize, usize)> = p.iter().map(|&(r, c)| (c, r)).collect();
        want.extend((0..4).map(|i| (i, i)));
        want.sort_unstable();
        want.dedup();
        let got: Vec<(usize, usize)> = (0..4)
            .flat_map(|c| rows[ptr[c]..ptr[c + 1]].iter().map(move |&r| (c, r)))
            .collect();
        assert_eq!(got, want);
        assert!(compressed_columns(4, &[(4, 0)]).is_err());
    }

    #[test]
    fn colouring_of_tridiagonal_needs_three_colours() {
        let mut m = NewtonMatrix::new(10, Some(tridiag(10)), false).unwrap();
        let colours = m.take_colours();
        assert_eq!(colours.len(), 3);
        // No two columns of one colour share a row.
        for g in &colours {
            let mut seen = [false; 10];
            for &c in g {
                for &r in m.column_rows(c) {
                    assert!(!seen[r]);
                    seen[r] = true;
                }
            }
        }
    }

    #[test]
    fn sparse_and_dense_solve_agree_with_known_solution() {
        let n = 8;
        for dense in [true, false] {
            let mut m = NewtonMatrix::new(n, Some(tridiag(n)), dense).unwrap();
            for i in 0..n {
                m.add(i, i, 4.0 + i as f64).unwrap();
                if i > 0 {
                    m.add(i, i - 1, -1.0).unwrap();
                    m.add(i - 1, i, -2.0).unwrap();
                }
            }
            let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let mut b = vec![0.0; n];
            for r in 0..n {
                for c in 0..n {
                    b[r] += m.get(r, c) * x[c];
                }
            }
            let scale: Vec<f64> = (0..n)
                .map(|i| if i % 3 == 0 { 1e-4 } else { 1.0 })
                .collect();
            m.factor(&scale, true).unwrap();
            m.solve(&mut b).unwrap();
            for i in 0..n {
                assert!((b[i] - x[i]).abs() < 1e-12, "dense={dense} i={i}");
            }
        }
    }

    #[test]
    fn singular_matrix_is_reported_not_panicking() {
        let mut m = NewtonMatrix::new(3, None, true).unwrap();
        m.add(0, 0, 1.0).unwrap();
        m.add(1, 1, 1.0).unwrap();
        m.add(2, 0, 1.0).unwrap();
        m.add(2, 1, 1.0).unwrap();
        // Column 2 is zero: no pivot for unknown 2.
        let err = m.factor(&[1.0; 3], true).unwrap_err();
        assert!(err.columns.contains(&2), "{err:?}");
        // Entry outside a sparse pattern is refused.
        let mut s = NewtonMatrix::new(3, Some(vec![(0, 1)]), false).unwrap();
        assert!(s.add(2, 0, 1.0).is_err());
    }
}
