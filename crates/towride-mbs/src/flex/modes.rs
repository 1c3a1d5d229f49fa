//! Normal modes: the generalised symmetric-definite eigenproblem K phi = omega^2 M phi,
//! dense.
//!
//! Cholesky reduction to standard form (Golub & Van Loan, Matrix Computations, 4th ed.,
//! sec. 8.7.2, algorithm 8.7.1): M = L L^T, C = L^-1 K L^-T, C = U Lambda U^T (faer's
//! self-adjoint eigensolver, tridiagonalisation + divide and conquer), phi = L^-T U. The
//! modes come out mass-orthonormal (phi^T M phi = I) with omega^2 ascending. Dense
//! O(n^3): fine for the few hundred to ~1500 DOF of beam models.

use super::FlexError;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, MatRef, Par, Side};

/// Eigenpairs: omega^2 ascending, mass-orthonormal vectors as columns.
#[derive(Clone, Debug)]
pub struct Eigen {
    /// omega^2 per mode, ascending [1/s^2].
    pub omega2: Vec<f64>,
    /// Mass-orthonormal mode shapes as columns, in the order of `omega2`.
    pub vectors: Mat<f64>,
}

/// Signed frequency in Hz: sign(omega^2) sqrt(|omega^2|) / (2 pi), as modal files
/// report slightly negative rigid-body eigenvalues.
pub fn frequency_hz(omega2: f64) -> f64 {
    omega2.signum() * omega2.abs().sqrt() / (2.0 * std::f64::consts::PI)
}

/// (A + A^T) / 2: products like T^T K T are symmetric only up to rounding.
pub fn symmetrize(a: &mut Mat<f64>) {
    let n = a.nrows();
    for i in 0..n {
        for j in 0..i {
            let v = 0.5 * (a[(i, j)] + a[(j, i)]);
            a[(i, j)] = v;
            a[(j, i)] = v;
        }
    }
}

/// Rows `rows` and columns `cols` of `a`.
pub fn submatrix(a: MatRef<'_, f64>, rows: &[usize], cols: &[usize]) -> Mat<f64> {
    Mat::from_fn(rows.len(), cols.len(), |i, j| a[(rows[i], cols[j])])
}

/// Solves K phi = omega^2 M phi for all pairs; M must be positive definite.
pub fn generalized_eigen(k: MatRef<'_, f64>, m: MatRef<'_, f64>) -> Result<Eigen, FlexError> {
    let n = k.nrows();
    let llt = m.llt(Side::Lower).map_err(|e| {
        FlexError::Numerics(format!("the mass matrix is not positive definite ({e:?})"))
    })?;
    let l = llt.L();
    // C = L^-1 K L^-T: X = L^-1 K, then C = L^-1 X^T (K symmetric).
    let mut x = k.to_owned();
    solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
    let mut c = x.transpose().to_owned();
    solve_lower_triangular_in_place(l, c.as_mut(), Par::Seq);
    symmetrize(&mut c);
    let evd = c
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| FlexError::Numerics(format!("eigensolver failed ({e:?})")))?;
    let mut v = evd.U().to_owned();
    solve_upper_triangular_in_place(l.transpose(), v.as_mut(), Par::Seq);
    let s = evd.S();
    let omega2 = (0..n).map(|i| s[i]).collect();
    Ok(Eigen { omega2, vectors: v })
}

/// Modes with the DOFs in `fixed` held at zero; vectors are returned full-size (zeros
/// at the held DOFs).
pub fn constrained_eigen(
    k: MatRef<'_, f64>,
    m: MatRef<'_, f64>,
    fixed: &[usize],
) -> Result<Eigen, FlexError> {
    let n = k.nrows();
    let free: Vec<usize> = (0..n).filter(|i| !fixed.contains(i)).collect();
    let e = generalized_eigen(
        submatrix(k, &free, &free).as_ref(),
        submatrix(m, &free, &free).as_ref(),
    )?;
    let mut v = Mat::zeros(n, free.len());
    for (r, &i) in free.iter().enumerate() {
        for c in 0..free.len() {
            v[(i, c)] = e.vectors[(r, c)];
        }
    }
    Ok(Eigen {
        omega2: e.omega2,
        vectors: v,
    })
}

/// Static solution of K u = f with the DOFs in `fixed` held at zero.
pub fn static_solution(
    k: MatRef<'_, f64>,
    fixed: &[usize],
    f: &[f64],
) -> Result<Vec<f64>, FlexError> {
    let n = k.nrows();
    let free: Vec<usize> = (0..n).filter(|i| !fixed.contains(i)).collect();
    let kf = submatrix(k, &free, &free);
    let llt = kf.llt(Side::Lower).map_err(|_| {
        FlexError::Numerics(
            "the held structure is a mechanism (stiffness not positive definite)".to_string(),
        )
    })?;
    let mut rhs = Mat::from_fn(free.len(), 1, |i, _| f[free[i]]);
    faer::linalg::solvers::Solve::solve_in_place(&llt, rhs.as_mut());
    let mut u = vec![0.0; n];
    for (r, &i) in free.iter().enumerate() {
        u[i] = rhs[(r, 0)];
    }
    Ok(u)
}

/// Number of rigid-body modes at the start of an ascending spectrum of a free body:
/// six, whose eigenvalues must be rounding-level next to the first elastic one.
pub fn count_rigid(omega2: &[f64]) -> Result<usize, FlexError> {
    if omega2.len() < 7 {
        return Err(FlexError::Numerics(format!(
            "{} modes cannot hold six rigid-body modes and an elastic one",
            omega2.len()
        )));
    }
    let first_elastic = omega2[6];
    let sixth = omega2[5].abs();
    // Rounding puts rigid-body eigenvalues near eps * omega^2_max; a gap of six orders
    // (three in frequency) separates them from any physical mode of a connected body.
    if !(first_elastic > 0.0 && sixth < 1e-6 * first_elastic) {
        return Err(FlexError::Numerics(format!(
            "cannot separate six rigid-body modes: mode 6 at {:.4} Hz, mode 7 at {:.4} Hz \
             (a mechanism, or a body held somewhere)",
            frequency_hz(omega2[5]),
            frequency_hz(omega2[6])
        )));
    }
    Ok(6)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_masses_and_a_spring() {
        // m1 = 1, m2 = 2 joined by k = 3, free: omega^2 = 0 and k (1/m1 + 1/m2) = 4.5.
        let k = Mat::from_fn(2, 2, |i, j| if i == j { 3.0 } else { -3.0 });
        let m = Mat::from_fn(2, 2, |i, j| if i == j { (i + 1) as f64 } else { 0.0 });
        let e = generalized_eigen(k.as_ref(), m.as_ref()).unwrap();
        assert!(e.omega2[0].abs() < 1e-12);
        assert!((e.omega2[1] - 4.5).abs() < 1e-12);
        let p = e.vectors.transpose() * &m * &e.vectors;
        for i in 0..2 {
            for j in 0..2 {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((p[(i, j)] - want).abs() < 1e-12);
            }
        }
    }
}
