//! The complex iteration matrix of Radau IIA, J_y + s J_y' with s = (alpha + i beta)/h
//! (Hairer & Wanner II, IV.8, "the complex system"; RADAU5's DECOMC and SOLC), built from
//! the parts a [`NewtonMatrix`] keeps (its last evaluation and dF/dy') and factorised in
//! complex arithmetic: the sparse LU of [`crate::sparse_lu`] on the same structure and
//! fill-reducing order as the real matrix, or nalgebra's dense complex LU for small
//! problems.
//!
//! Why complex and not the real 2n x 2n form [[A, -B], [B, A]] (A = J_y + alpha/h J_y',
//! B = beta/h J_y'): measured on the vehicle's matrix (494 unknowns), see
//! `docs/solver.md`, "Radau IIA: the complex system".

use nalgebra::{Complex, DMatrix, DVectorViewMut, Dyn, LU};

use super::{fill_reducing_order, NewtonMatrix, Singular};
use crate::sparse_lu::{Refactor, SparseLu};
use crate::SolverError;

type C64 = Complex<f64>;

#[allow(clippy::large_enum_variant)] // one per solver, never moved in a hot path
enum Storage {
    Dense {
        lu: Option<LU<C64, Dyn, Dyn>>,
    },
    Sparse {
        values: Vec<C64>,
        lu: SparseLu<C64>,
        factored: bool,
    },
}

/// A complex matrix on the structure of a [`NewtonMatrix`], with its factorisation.
pub struct ComplexMatrix {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    storage: Storage,
    row_scale: Vec<f64>,
    col_scale: Vec<f64>,
    work: Vec<C64>,
}

impl ComplexMatrix {
    /// A complex companion of `m`: the same structure, dense when `m` is dense.
    pub fn like(m: &NewtonMatrix) -> Result<Self, SolverError> {
        let n = m.n;
        let (col_ptr, row_idx) = m.structure();
        let storage = if m.is_dense() {
            Storage::Dense { lu: None }
        } else {
            Storage::Sparse {
                values: vec![C64::new(0.0, 0.0); row_idx.len()],
                lu: SparseLu::new(n, fill_reducing_order(n, col_ptr, row_idx)?),
                factored: false,
            }
        };
        Ok(Self {
            n,
            col_ptr: col_ptr.to_vec(),
            row_idx: row_idx.to_vec(),
            storage,
            row_scale: vec![1.0; n],
            col_scale: vec![1.0; n],
            work: vec![C64::new(0.0, 0.0); n],
        })
    }

    /// Factorises diag(row) (J_y + shift J_y') diag(col_scale) from the parts kept by `m`
    /// ([`NewtonMatrix::shifted_parts`]); rows are equilibrated to unit largest magnitude
    /// when `equilibrate`, as the real matrix is.
    ///
    /// # Panics
    /// If `m` keeps no evaluation with its dF/dy' part.
    pub fn factor(
        &mut self,
        m: &NewtonMatrix,
        shift: C64,
        col_scale: &[f64],
        equilibrate: bool,
    ) -> Result<(), Singular> {
        let n = self.n;
        let (base, base_cj, yp) = m
            .shifted_parts()
            .expect("the real matrix keeps its evaluation and dF/dy'");
        let d = shift - base_cj;
        self.col_scale.copy_from_slice(col_scale);
        // Value of storage entry k in column c, scaled by the column.
        let entry = |k: usize, c: usize| (d * yp[k] + base[k]) * col_scale[c];
        let mut row_max = vec![0.0f64; n];
        let dense = matches!(self.storage, Storage::Dense { .. });
        for c in 0..n {
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                let r = self.row_idx[k];
                let v = entry(if dense { c * n + r } else { k }, c);
                if !(v.re.is_finite() && v.im.is_finite()) {
                    return Err(Singular {
                        columns: vec![c],
                        rows: vec![r],
                        detail: format!("non-finite Jacobian entry at equation {r}, unknown {c}"),
                    });
                }
                row_max[r] = row_max[r].max(v.norm());
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
        let rs = &self.row_scale;
        match &mut self.storage {
            Storage::Dense { lu } => {
                let f = DMatrix::from_fn(n, n, |r, c| entry(c * n + r, c) * rs[r]).lu();
                let diag: Vec<f64> = (0..n).map(|i| f.lu_internal()[(i, i)].norm()).collect();
                let umax = diag.iter().copied().fold(0.0, f64::max);
                let tiny = umax * f64::EPSILON * n as f64;
                let small: Vec<usize> = (0..n)
                    .filter(|&i| diag[i] <= tiny || diag[i].is_nan())
                    .collect();
                if !small.is_empty() {
                    *lu = None;
                    return Err(Singular {
                        detail: format!("zero pivot for unknown(s) {small:?} in the complex LU"),
                        columns: small,
                        rows: vec![],
                    });
                }
                *lu = Some(f);
                Ok(())
            }
            Storage::Sparse {
                values,
                lu,
                factored,
            } => {
                for c in 0..n {
                    for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                        values[k] = entry(k, c) * rs[self.row_idx[k]];
                    }
                }
                *factored = false;
                if lu.has_pivots() && lu.refactor(values) == Refactor::Done {
                    *factored = true;
                    return Ok(());
                }
                lu.factor(&self.col_ptr, &self.row_idx, values)
                    .map_err(|z| Singular {
                        columns: vec![z.column],
                        rows: vec![],
                        detail: format!(
                            "no usable pivot for unknown {} in the complex sparse LU",
                            z.column
                        ),
                    })?;
                *factored = true;
                Ok(())
            }
        }
    }

    /// Non-zeros of the sparse LU factors (L + U), once factorised; `None` on the dense path.
    pub fn lu_nnz(&self) -> Option<usize> {
        match &self.storage {
            Storage::Sparse { lu, factored, .. } => factored.then(|| lu.nnz()),
            Storage::Dense { .. } => None,
        }
    }

    /// Solves (J_y + shift J_y') (x_re + i x_im) = b_re + i b_im in place.
    pub fn solve(&mut self, re: &mut [f64], im: &mut [f64]) -> Result<(), Singular> {
        let n = self.n;
        for i in 0..n {
            self.work[i] = C64::new(re[i], im[i]) * self.row_scale[i];
        }
        match &mut self.storage {
            Storage::Dense { lu } => {
                let lu = lu.as_ref().expect("solve called before factor");
                let mut v = DVectorViewMut::from_slice(&mut self.work, n);
                if !lu.solve_mut(&mut v) {
                    return Err(Singular {
                        columns: vec![],
                        rows: vec![],
                        detail: "singular dense complex LU".into(),
                    });
                }
            }
            Storage::Sparse { lu, factored, .. } => {
                assert!(*factored, "solve called before factor");
                lu.solve(&mut self.work);
            }
        }
        for i in 0..n {
            let x = self.work[i] * self.col_scale[i];
            if !(x.re.is_finite() && x.im.is_finite()) {
                return Err(Singular {
                    columns: vec![i],
                    rows: vec![],
                    detail: format!("non-finite Newton correction on unknown {i}"),
                });
            }
            re[i] = x.re;
            im[i] = x.im;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The complex solve agrees with the real 2n x 2n form it replaces, on both paths.
    #[test]
    fn complex_solve_matches_real_block_form() {
        let n = 7;
        let mut pattern = Vec::new();
        for i in 0..n {
            pattern.push((i, i));
            pattern.push((i, (i + 2) % n));
            pattern.push(((i + 3) % n, i));
        }
        let fy = |r: usize, c: usize| {
            1.0 + 0.3 * r as f64 - 0.7 * c as f64 + (r == c) as u8 as f64 * 4.0
        };
        let fyp = |r: usize, c: usize| {
            if r == c && r % 3 != 2 {
                1.0 + 0.1 * r as f64
            } else {
                0.0
            }
        };
        let (alpha, beta, cj) = (2.7, 3.1, 3.6);
        for dense in [true, false] {
            let mut m = NewtonMatrix::new(n, Some(pattern.clone()), dense).unwrap();
            let mut yp_entries = Vec::new();
            for &(r, c) in &pattern {
                m.add(r, c, fy(r, c) + cj * fyp(r, c)).unwrap();
                yp_entries.push((r, c, fyp(r, c)));
            }
            m.keep_as_base(cj);
            m.set_yp_part(&yp_entries);
            let mut cm = ComplexMatrix::like(&m).unwrap();
            let scale: Vec<f64> = (0..n)
                .map(|i| if i % 2 == 0 { 1.0 } else { 0.01 })
                .collect();
            cm.factor(&m, C64::new(alpha, beta), &scale, true).unwrap();
            // b = (A + iB)(x + iy) with A = fy + alpha fyp, B = beta fyp, from the block form.
            let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.9).cos()).collect();
            let y: Vec<f64> = (0..n).map(|i| (i as f64 * 0.4).sin()).collect();
            let (mut bre, mut bim) = (vec![0.0; n], vec![0.0; n]);
            for &(r, c) in &pattern {
                let a = fy(r, c) + alpha * fyp(r, c);
                let b = beta * fyp(r, c);
                bre[r] += a * x[c] - b * y[c];
                bim[r] += b * x[c] + a * y[c];
            }
            cm.solve(&mut bre, &mut bim).unwrap();
            for i in 0..n {
                assert!((bre[i] - x[i]).abs() < 1e-12, "dense={dense} re {i}");
                assert!((bim[i] - y[i]).abs() < 1e-12, "dense={dense} im {i}");
            }
        }
    }
}
