//! The 3-stage Radau IIA method (order 5, stage order 3, L-stable, stiffly accurate) and
//! the constants of its implementation in RADAU5 (Hairer & Wanner, Solving ODEs II,
//! IV.5 table 5.6 and IV.8; RADAU5 of July 9, 1996, subroutine RADCOR).

// RADAU5's transformation constants are kept with the 20 digits it publishes.
#![allow(clippy::excessive_precision)]

const SQ6: f64 = 2.449_489_742_783_178;

/// The first collocation node, c1 = (4 - sqrt 6)/10.
pub const C1: f64 = (4.0 - SQ6) / 10.0;
/// The second collocation node, c2 = (4 + sqrt 6)/10.
pub const C2: f64 = (4.0 + SQ6) / 10.0;
/// The collocation nodes (c3 = 1: the method is stiffly accurate).
pub const C: [f64; 3] = [C1, C2, 1.0];

/// The Runge-Kutta matrix A (Hairer & Wanner II, table IV.5.6).
pub const A: [[f64; 3]; 3] = [
    [
        (88.0 - 7.0 * SQ6) / 360.0,
        (296.0 - 169.0 * SQ6) / 1800.0,
        (-2.0 + 3.0 * SQ6) / 225.0,
    ],
    [
        (296.0 + 169.0 * SQ6) / 1800.0,
        (88.0 + 7.0 * SQ6) / 360.0,
        (-2.0 - 3.0 * SQ6) / 225.0,
    ],
    [(16.0 - SQ6) / 36.0, (16.0 + SQ6) / 36.0, 1.0 / 9.0],
];

/// Eigenvalues of A^-1: gamma (real) and alpha +- i beta (RADAU5's U1 and ALPH, BETA
/// after their inversion), from the closed forms with 81^(1/3) and 9^(1/3).
pub const GAMMA: f64 = 3.637_834_252_744_496;
/// Real part of the complex eigenvalue pair of A^-1.
pub const ALPHA: f64 = 2.681_082_873_627_752;
/// Imaginary part of the complex eigenvalue pair of A^-1.
pub const BETA: f64 = 3.050_430_199_247_411;

/// T with T^-1 A^-1 T = [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]] (RADAU5's
/// T11..T31; T32 = 1, T33 = 0).
pub const T: [[f64; 3]; 3] = [
    [
        9.123_239_487_089_294_279_2e-2,
        -0.141_255_295_020_954_208_43,
        -3.002_919_410_514_742_449_2e-2,
    ],
    [
        0.241_717_932_707_107_018_96,
        0.204_129_352_293_799_931_99,
        0.382_942_112_757_261_937_79,
    ],
    [0.966_048_182_615_092_936_19, 1.0, 0.0],
];

/// T^-1 (RADAU5's TI11..TI33).
pub const TI: [[f64; 3]; 3] = [
    [
        4.325_579_890_063_155_351_0,
        0.339_199_251_815_809_869_54,
        0.541_770_539_935_874_871_19,
    ],
    [
        -4.178_718_591_551_904_727_3,
        -0.327_682_820_761_062_387_08,
        0.476_623_554_500_550_451_96,
    ],
    [
        -0.502_872_634_945_786_875_95,
        2.571_926_949_855_605_429_2,
        -0.596_039_204_828_224_924_97,
    ],
];

/// Coefficients of the embedded error estimate, e_i / gamma0 with gamma0 = 1/GAMMA
/// (RADAU5's DD1..DD3): err = (I - h gamma0 J)^-1 (gamma0 h y'0 + sum e_i Z_i).
pub const DD: [f64; 3] = [
    -(13.0 + 7.0 * SQ6) / 3.0,
    (-13.0 + 7.0 * SQ6) / 3.0,
    -1.0 / 3.0,
];

/// A^-1, the map from the stage increments Z_i = Y_i - y0 to h times the stage
/// derivatives: h Y'_i = sum_j (A^-1)_ij Z_j.
pub fn a_inverse() -> [[f64; 3]; 3] {
    let a = A;
    let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    let mut inv = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            // Cofactor of a[j][i].
            let (r0, r1) = ((j + 1) % 3, (j + 2) % 3);
            let (c0, c1) = ((i + 1) % 3, (i + 2) % 3);
            inv[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
        }
    }
    inv
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        m
    }

    #[test]
    fn collocation_conditions_hold() {
        // Stage order 3: sum_j a_ij c_j^(k-1) = c_i^k / k for k = 1, 2, 3.
        for i in 0..3 {
            for k in 1..=3 {
                let lhs: f64 = (0..3).map(|j| A[i][j] * C[j].powi(k - 1)).sum();
                assert!((lhs - C[i].powi(k) / k as f64).abs() < 1e-15, "i {i} k {k}");
            }
        }
    }

    #[test]
    fn transformation_block_diagonalises_a_inverse() {
        let ai = a_inverse();
        assert!((mul(&A, &ai)[1][1] - 1.0).abs() < 1e-14);
        let l = mul(&mul(&TI, &ai), &T);
        let want = [[GAMMA, 0.0, 0.0], [0.0, ALPHA, -BETA], [0.0, BETA, ALPHA]];
        for i in 0..3 {
            for j in 0..3 {
                assert!(
                    (l[i][j] - want[i][j]).abs() < 1e-12,
                    "({i},{j}): {}",
                    l[i][j]
                );
            }
        }
        let id = mul(&T, &TI);
        for i in 0..3 {
            for j in 0..3 {
                assert!((id[i][j] - (i == j) as u8 as f64).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn eigenvalue_constants_match_their_closed_forms() {
        let (c81, c9) = (81f64.cbrt(), 9f64.cbrt());
        let u1 = (6.0 + c81 - c9) / 30.0;
        let (al, be) = ((12.0 - c81 + c9) / 60.0, (c81 + c9) * 3f64.sqrt() / 60.0);
        let cno = al * al + be * be;
        assert!((GAMMA - 1.0 / u1).abs() < 1e-14);
        assert!((ALPHA - al / cno).abs() < 1e-14);
        assert!((BETA - be / cno).abs() < 1e-14);
    }

    #[test]
    fn embedded_estimate_is_exact_for_cubics() {
        // gamma0 h y'(0) + sum e_i Z_i vanishes for y = t, t^2, t^3 (y(0) = 0): with
        // dd_i = e_i / gamma0, sum dd_i c_i = -1 and sum dd_i c_i^k = 0 for k = 2, 3.
        let s = |k: i32| (0..3).map(|i| DD[i] * C[i].powi(k)).sum::<f64>();
        assert!((s(1) + 1.0).abs() < 1e-13);
        assert!(s(2).abs() < 1e-13 && s(3).abs() < 1e-13);
    }
}
