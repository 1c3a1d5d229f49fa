//! Step-size changes of the fixed-coefficient BDF: the backward differences of the
//! history are re-sampled onto the new equally spaced grid.

use super::MAXORD;

/// Interpolates backward differences phi[1..=k] of the step h onto the step r*h (the
/// polynomial through the last k+1 points is kept; ode15s's difRU transformation).
pub(crate) fn rescale_differences(phi: &mut [Vec<f64>], k: usize, r: f64) {
    // T[j][m] = sum_i (-1)^i C(j,i) prod_{l=0}^{m-1} (l - i r) / m!
    let mut t = [[0.0f64; MAXORD + 2]; MAXORD + 2];
    for j in 1..=k {
        for m in 1..=k {
            let mut s = 0.0;
            let mut binom = 1.0;
            for i in 0..=j {
                if i > 0 {
                    binom *= (j - i + 1) as f64 / i as f64;
                }
                let mut p = 1.0;
                for l in 0..m {
                    p *= (l as f64 - i as f64 * r) / (l as f64 + 1.0);
                }
                s += if i % 2 == 0 { binom * p } else { -binom * p };
            }
            t[j][m] = s;
        }
    }
    let n = phi[0].len();
    let mut new = vec![0.0; k + 1];
    for i in 0..n {
        for (j, nj) in new.iter_mut().enumerate().skip(1) {
            *nj = (1..=k).map(|m| t[j][m] * phi[m][i]).sum();
        }
        for j in 1..=k {
            phi[j][i] = new[j];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rescaling_keeps_the_polynomial() {
        // y(t) = 1 + 2t - 3t^2 + t^3 sampled at t = 0, -h, -2h, -3h.
        let p = |t: f64| 1.0 + 2.0 * t - 3.0 * t * t + t * t * t;
        let (h, r, k) = (0.1, 0.37, 3);
        let back = |step: f64| -> Vec<Vec<f64>> {
            let ys: Vec<f64> = (0..=k).map(|i| p(-(i as f64) * step)).collect();
            // Backward differences of order 0..=k at t = 0.
            let mut d = vec![ys.clone()];
            for j in 1..=k {
                let prev = &d[j - 1];
                d.push((0..=k - j).map(|i| prev[i] - prev[i + 1]).collect());
            }
            (0..=k).map(|j| vec![d[j][0]]).collect()
        };
        let mut phi = back(h);
        phi.resize(MAXORD + 2, vec![0.0]);
        rescale_differences(&mut phi, k, r);
        let expect = back(r * h);
        for j in 0..=k {
            assert!((phi[j][0] - expect[j][0]).abs() < 1e-13, "j={j}");
        }
        // r = 1 is the identity.
        let mut same = back(h);
        same.resize(MAXORD + 2, vec![0.0]);
        rescale_differences(&mut same, k, 1.0);
        for j in 0..=k {
            assert!((same[j][0] - back(h)[j][0]).abs() < 1e-15);
        }
    }
}
