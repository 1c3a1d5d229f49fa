//! An objective curve-similarity rating in the spirit of ISO/TS 18571:2014: corridor,
//! phase, magnitude and slope scores, each in [0, 1], combined as
//! R = 0.4 Z + 0.2 E_P + 0.2 E_M + 0.2 E_S. The formulas, the parameter values and where
//! this differs from the standard are in `docs/validation.md`.

use serde::Serialize;

use super::metrics::pearson;

/// Parameters (the standard's values as the defaults).
#[derive(Clone, Copy, Debug)]
pub struct RatingParams {
    /// Inner and outer corridor half-widths relative to max |reference|.
    pub a0: f64,
    /// Outer corridor half-width relative to max |reference|.
    pub b0: f64,
    /// Corridor progression exponent.
    pub kz: f64,
    /// Largest phase shift, as a fraction of the curve length.
    pub eps_p: f64,
    /// Largest magnitude and slope errors (relative L2 norms).
    pub eps_m: f64,
    /// Largest slope error (relative L2 norm).
    pub eps_s: f64,
    /// Sakoe-Chiba band of the dynamic time warping, as a fraction of the length.
    pub dtw_band: f64,
}

impl Default for RatingParams {
    fn default() -> Self {
        RatingParams {
            a0: 0.05,
            b0: 0.5,
            kz: 2.0,
            eps_p: 0.2,
            eps_m: 0.5,
            eps_s: 2.0,
            dtw_band: 0.1,
        }
    }
}

/// The rating and its four sub-scores.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct Rating {
    /// Combined rating R = 0.4 Z + 0.2 E_P + 0.2 E_M + 0.2 E_S, in [0, 1] (1: identical).
    pub overall: f64,
    /// Corridor score Z.
    pub corridor: f64,
    /// Phase score E_P.
    pub phase: f64,
    /// Magnitude score E_M.
    pub magnitude: f64,
    /// Slope score E_S.
    pub slope: f64,
}

/// Rates `compared` (simulation) against `reference` (measurement), both sampled every
/// `dt` seconds on the same grid.
pub fn iso_rating(reference: &[f64], compared: &[f64], dt: f64) -> Rating {
    iso_rating_with(reference, compared, dt, &RatingParams::default())
}

/// [`iso_rating`] with explicit parameters.
pub fn iso_rating_with(reference: &[f64], compared: &[f64], dt: f64, p: &RatingParams) -> Rating {
    let n = reference.len().min(compared.len());
    let (t, c) = (&reference[..n], &compared[..n]);
    let corridor = corridor_score(t, c, p);
    let (lag, phase) = phase_score(t, c, p);
    // Magnitude and slope are judged on the phase-corrected pair.
    let (ts, cs) = if lag >= 0 {
        (&t[..n - lag as usize], &c[lag as usize..])
    } else {
        (&t[(-lag) as usize..], &c[..n - (-lag) as usize])
    };
    let magnitude = magnitude_score(ts, cs, p);
    let slope = slope_score(ts, cs, dt, p);
    Rating {
        overall: 0.4 * corridor + 0.2 * phase + 0.2 * magnitude + 0.2 * slope,
        corridor,
        phase,
        magnitude,
        slope,
    }
}

/// Share-of-points score inside a corridor around the reference: 1 inside the inner
/// corridor, 0 outside the outer, ((delta_o - |d|) / (delta_o - delta_i))^kz between.
pub fn corridor_score(t: &[f64], c: &[f64], p: &RatingParams) -> f64 {
    let tnorm = t.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if tnorm == 0.0 {
        return if c.iter().all(|x| *x == 0.0) {
            1.0
        } else {
            0.0
        };
    }
    let (di, d_o) = (p.a0 * tnorm, p.b0 * tnorm);
    let sum: f64 = t
        .iter()
        .zip(c)
        .map(|(a, b)| {
            let d = (a - b).abs();
            if d <= di {
                1.0
            } else if d >= d_o {
                0.0
            } else {
                ((d_o - d) / (d_o - di)).powf(p.kz)
            }
        })
        .sum();
    sum / t.len().max(1) as f64
}

/// (lag of `c` behind `t` in samples, phase score): the lag within eps_p n maximising
/// the correlation of the overlapping parts (smaller |lag| wins ties), scored linearly
/// from 1 (no lag) to 0 (eps_p n).
pub fn phase_score(t: &[f64], c: &[f64], p: &RatingParams) -> (i64, f64) {
    let n = t.len();
    let kmax = (p.eps_p * n as f64).floor() as i64;
    if kmax < 1 {
        return (0, 1.0);
    }
    let mut best = (pearson(t, c), 0_i64);
    for k in 1..kmax {
        let ku = k as usize;
        // +k: c is late, c[i + k] matches t[i]; -k: c is early, c[i] matches t[i + k].
        for (rho, lag) in [
            (pearson(&t[..n - ku], &c[ku..]), k),
            (pearson(&t[ku..], &c[..n - ku]), -k),
        ] {
            if rho > best.0 {
                best = (rho, lag);
            }
        }
    }
    let score = (kmax - best.1.abs()) as f64 / kmax as f64;
    (best.1, score.max(0.0))
}

/// EEARTH-style magnitude score: the relative L2 error after dynamic time warping within
/// a band, scored linearly from 1 (no error) to 0 (eps_m).
pub fn magnitude_score(t: &[f64], c: &[f64], p: &RatingParams) -> f64 {
    let (tw, cw) = dtw(t, c, ((p.dtw_band * t.len() as f64).ceil() as usize).max(1));
    let num: f64 = tw.iter().zip(&cw).map(|(a, b)| (a - b).powi(2)).sum();
    let den: f64 = tw.iter().map(|a| a * a).sum();
    score(rel(num, den), p.eps_m)
}

/// Slope score: relative L2 error of the derivatives (central differences smoothed by a
/// 9-point moving average), scored linearly from 1 to 0 at eps_s.
pub fn slope_score(t: &[f64], c: &[f64], dt: f64, p: &RatingParams) -> f64 {
    let (dtd, dcd) = (smooth_derivative(t, dt), smooth_derivative(c, dt));
    let num: f64 = dtd.iter().zip(&dcd).map(|(a, b)| (a - b).powi(2)).sum();
    let den: f64 = dtd.iter().map(|a| a * a).sum();
    score(rel(num, den), p.eps_s)
}

fn rel(num: f64, den: f64) -> f64 {
    if den > 0.0 {
        (num / den).sqrt()
    } else if num == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

fn score(err: f64, max: f64) -> f64 {
    ((max - err) / max).clamp(0.0, 1.0)
}

fn smooth_derivative(y: &[f64], dt: f64) -> Vec<f64> {
    let n = y.len();
    if n < 2 {
        return vec![0.0; n];
    }
    let d: Vec<f64> = (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            (y[b] - y[a]) / ((b - a) as f64 * dt)
        })
        .collect();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(4), (i + 4).min(n - 1));
            d[a..=b].iter().sum::<f64>() / (b - a + 1) as f64
        })
        .collect()
}

/// Dynamic time warping (squared distance) within a Sakoe-Chiba band of half-width `w`;
/// returns both curves along the optimal path.
fn dtw(t: &[f64], c: &[f64], w: usize) -> (Vec<f64>, Vec<f64>) {
    let (n, m) = (t.len(), c.len());
    if n == 0 || m == 0 {
        return (Vec::new(), Vec::new());
    }
    let w = w.max(n.abs_diff(m));
    let width = 2 * w + 1;
    // cost[i][j - i + w], band-stored; from[..] = 0 diagonal, 1 from (i-1, j), 2 from (i, j-1).
    let mut cost = vec![f64::INFINITY; n * width];
    let mut from = vec![0_u8; n * width];
    let at = |i: usize, j: usize| -> Option<usize> {
        (j + w >= i && j <= i + w).then(|| i * width + (j + w - i))
    };
    for i in 0..n {
        for j in i.saturating_sub(w)..(i + w + 1).min(m) {
            let d = (t[i] - c[j]).powi(2);
            let k = at(i, j).unwrap_or(0);
            if i == 0 && j == 0 {
                cost[k] = d;
                continue;
            }
            let mut best = (f64::INFINITY, 0_u8);
            let cand = [
                (i > 0 && j > 0)
                    .then(|| at(i - 1, j - 1))
                    .flatten()
                    .map(|q| (cost[q], 0)),
                (i > 0)
                    .then(|| at(i - 1, j))
                    .flatten()
                    .map(|q| (cost[q], 1)),
                (j > 0)
                    .then(|| at(i, j - 1))
                    .flatten()
                    .map(|q| (cost[q], 2)),
            ];
            for (v, dir) in cand.into_iter().flatten() {
                if v < best.0 {
                    best = (v, dir);
                }
            }
            cost[k] = d + best.0;
            from[k] = best.1;
        }
    }
    let (mut i, mut j) = (n - 1, m - 1);
    let (mut tw, mut cw) = (vec![t[i]], vec![c[j]]);
    while i > 0 || j > 0 {
        match at(i, j).map(|k| from[k]).unwrap_or(0) {
            0 if i > 0 && j > 0 => (i, j) = (i - 1, j - 1),
            1 if i > 0 => i -= 1,
            _ if j > 0 => j -= 1,
            _ => i -= 1,
        }
        tw.push(t[i]);
        cw.push(c[j]);
    }
    (tw, cw)
}
