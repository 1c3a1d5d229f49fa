//! Small 3D vector and quaternion algebra, generic over [`Scalar`] so elements can be
//! differentiated exactly.
//!
//! Orientation is a quaternion p = (w, x, y, z), body to world. The rotation matrix is
//! A(p) = R(p) / (p . p) with R the usual quadratic form, so A is a rotation for any
//! p != 0: the norm of p carries no physics, constraints and forces do not depend on it,
//! and its slow numerical drift needs no constraint (the kinematic equation
//! p' = p (x) (0, omega) / 2 keeps |p| constant in exact arithmetic).

use super::dual::Scalar;

/// A 3-vector.
pub type V3<T> = [T; 3];
/// A 3x3 matrix, row-major (`m[row][column]`).
pub type M3<T> = [[T; 3]; 3];
/// A quaternion (w, x, y, z).
pub type Q4<T> = [T; 4];

/// `v` as a constant vector of the scalar type `T`.
#[inline]
pub fn cst3<T: Scalar>(v: &[f64; 3]) -> V3<T> {
    [T::cst(v[0]), T::cst(v[1]), T::cst(v[2])]
}

/// a + b.
#[inline]
pub fn add<T: Scalar>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// a - b.
#[inline]
pub fn sub<T: Scalar>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// s a.
#[inline]
pub fn scale<T: Scalar>(a: &V3<T>, s: T) -> V3<T> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// a . b.
#[inline]
pub fn dot<T: Scalar>(a: &V3<T>, b: &V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a x b.
#[inline]
pub fn cross<T: Scalar>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A v
#[inline]
pub fn mv<T: Scalar>(a: &M3<T>, v: &V3<T>) -> V3<T> {
    [
        a[0][0] * v[0] + a[0][1] * v[1] + a[0][2] * v[2],
        a[1][0] * v[0] + a[1][1] * v[1] + a[1][2] * v[2],
        a[2][0] * v[0] + a[2][1] * v[1] + a[2][2] * v[2],
    ]
}

/// A^T v
#[inline]
pub fn mtv<T: Scalar>(a: &M3<T>, v: &V3<T>) -> V3<T> {
    [
        a[0][0] * v[0] + a[1][0] * v[1] + a[2][0] * v[2],
        a[0][1] * v[0] + a[1][1] * v[1] + a[2][1] * v[2],
        a[0][2] * v[0] + a[1][2] * v[1] + a[2][2] * v[2],
    ]
}

/// A v with a constant f64 vector.
#[inline]
pub fn mvc<T: Scalar>(a: &M3<T>, v: &[f64; 3]) -> V3<T> {
    [
        a[0][0] * v[0] + a[0][1] * v[1] + a[0][2] * v[2],
        a[1][0] * v[0] + a[1][1] * v[1] + a[1][2] * v[2],
        a[2][0] * v[0] + a[2][1] * v[1] + a[2][2] * v[2],
    ]
}

/// Rotation matrix of a (not necessarily unit) quaternion, body to world.
pub fn rot<T: Scalar>(p: &Q4<T>) -> M3<T> {
    let [w, x, y, z] = *p;
    let n = w * w + x * x + y * y + z * z;
    let s = T::cst(1.0) / n;
    let (ww, xx, yy, zz) = (w * w, x * x, y * y, z * z);
    let (xy, xz, yz, wx, wy, wz) = (x * y, x * z, y * z, w * x, w * y, w * z);
    [
        [
            (ww + xx - yy - zz) * s,
            (xy - wz) * s * 2.0,
            (xz + wy) * s * 2.0,
        ],
        [
            (xy + wz) * s * 2.0,
            (ww - xx + yy - zz) * s,
            (yz - wx) * s * 2.0,
        ],
        [
            (xz - wy) * s * 2.0,
            (yz + wx) * s * 2.0,
            (ww - xx - yy + zz) * s,
        ],
    ]
}

/// Quaternion product a (x) b.
#[inline]
pub fn qmul<T: Scalar>(a: &Q4<T>, b: &Q4<T>) -> Q4<T> {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// p' = p (x) (0, omega) / 2 for a body-frame angular velocity omega.
#[inline]
pub fn qdot<T: Scalar>(p: &Q4<T>, omega: &V3<T>) -> Q4<T> {
    let o = [T::cst(0.0), omega[0], omega[1], omega[2]];
    let d = qmul(p, &o);
    [d[0] * 0.5, d[1] * 0.5, d[2] * 0.5, d[3] * 0.5]
}

/// The 4x3 matrix Q(p) with p' = Q(p) omega / 2 (columns: d p'/d omega_k * 2).
pub fn qmat(p: &[f64; 4]) -> [[f64; 3]; 4] {
    let [w, x, y, z] = *p;
    [[-x, -y, -z], [w, -z, y], [z, w, -x], [-y, x, w]]
}

/// Unit quaternion of a rotation matrix (Shepperd's method, robust for all angles).
pub fn quat_from_matrix(a: &[[f64; 3]; 3]) -> [f64; 4] {
    let tr = a[0][0] + a[1][1] + a[2][2];
    let q = if tr > a[0][0].max(a[1][1]).max(a[2][2]) {
        let s = (1.0 + tr).sqrt() * 2.0;
        [
            0.25 * s,
            (a[2][1] - a[1][2]) / s,
            (a[0][2] - a[2][0]) / s,
            (a[1][0] - a[0][1]) / s,
        ]
    } else if a[0][0] >= a[1][1] && a[0][0] >= a[2][2] {
        let s = (1.0 + a[0][0] - a[1][1] - a[2][2]).sqrt() * 2.0;
        [
            (a[2][1] - a[1][2]) / s,
            0.25 * s,
            (a[0][1] + a[1][0]) / s,
            (a[0][2] + a[2][0]) / s,
        ]
    } else if a[1][1] >= a[2][2] {
        let s = (1.0 + a[1][1] - a[0][0] - a[2][2]).sqrt() * 2.0;
        [
            (a[0][2] - a[2][0]) / s,
            (a[0][1] + a[1][0]) / s,
            0.25 * s,
            (a[1][2] + a[2][1]) / s,
        ]
    } else {
        let s = (1.0 + a[2][2] - a[0][0] - a[1][1]).sqrt() * 2.0;
        [
            (a[1][0] - a[0][1]) / s,
            (a[0][2] + a[2][0]) / s,
            (a[1][2] + a[2][1]) / s,
            0.25 * s,
        ]
    };
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let q = q.map(|x| x / n);
    if q[0] < 0.0 {
        q.map(|x| -x)
    } else {
        q
    }
}

/// A right-handed orthonormal frame (columns x, y, z) from a z direction and an optional
/// x direction (made perpendicular to z); without x, any perpendicular is chosen the way
/// Adams does (global x unless z is close to it).
pub fn frame_from_axes(z: [f64; 3], x: Option<[f64; 3]>) -> Option<[[f64; 3]; 3]> {
    let nz = dot(&z, &z).sqrt();
    if nz.is_nan() || nz <= 0.0 {
        return None;
    }
    let z = z.map(|c| c / nz);
    let guess = x.unwrap_or(if z[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    });
    let d = dot(&guess, &z);
    let x = sub(&guess, &scale(&z, d));
    let nx = dot(&x, &x).sqrt();
    if nx.is_nan() || nx <= 1e-9 * dot(&guess, &guess).sqrt() {
        return None;
    }
    let x = x.map(|c| c / nx);
    let y = cross(&z, &x);
    Some([[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]])
}

/// Column k of a matrix.
#[inline]
pub fn col<T: Scalar>(a: &M3<T>, k: usize) -> V3<T> {
    [a[0][k], a[1][k], a[2][k]]
}

/// Rotation vector of a (near-)unit quaternion q: 2 atan2(|v|, w) v / |v|, smooth at 0
/// (a series replaces the ratio there so dual numbers stay finite).
pub fn rotation_vector<T: Scalar>(q: &Q4<T>) -> V3<T> {
    let w = if q[0].re() < 0.0 { -q[0] } else { q[0] };
    let sgn = if q[0].re() < 0.0 { -1.0 } else { 1.0 };
    let v = [q[1] * sgn, q[2] * sgn, q[3] * sgn];
    let s2 = dot(&v, &v);
    let factor = if s2.re() < 1e-10 * w.re() * w.re() {
        // atan(s/w)/s = (1/w)(1 - s^2/(3 w^2) + ...), error < 1e-20 here.
        let w2 = w * w;
        (T::cst(1.0) - s2 / (w2 * 3.0)) / w
    } else {
        let s = s2.sqrt();
        s.atan2(w) / s
    };
    scale(&v, factor * 2.0)
}

/// Conjugate quaternion.
#[inline]
pub fn conj<T: Scalar>(q: &Q4<T>) -> Q4<T> {
    [q[0], -q[1], -q[2], -q[3]]
}

/// Transposes a 3x3 f64 matrix.
pub fn transpose(a: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut t = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            t[i][j] = a[j][i];
        }
    }
    t
}

/// Product of two 3x3 matrices in any scalar.
pub fn mm<T: Scalar>(a: &M3<T>, b: &M3<T>) -> M3<T> {
    let mut c = [[T::cst(0.0); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    c
}

/// A matrix with f64 entries lifted to T.
pub fn cst33<T: Scalar>(a: &[[f64; 3]; 3]) -> M3<T> {
    a.map(|r| r.map(T::cst))
}
