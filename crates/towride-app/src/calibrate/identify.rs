//! What the recordings can pin down: from the sensitivity matrix J = d r / d s (r the
//! noise-normalised residuals, s = ln x for a positive value) the parameters'
//! covariance, their correlations and the collinearity of the set.
//!
//! The covariance is the least-squares one, C = s^2 L (J^T J)^-1 (Bates and Watts,
//! Nonlinear Regression Analysis and Its Applications, 1988, ch. 2), with s^2 the
//! residual variance per sample and L the samples per statistically independent value
//! (band-limited curves kept at several samples per period are correlated from sample to
//! sample; counting every sample as independent would shrink the intervals by sqrt(L)).
//! Before a fit, s^2 = 1 (a fit down to the noise) gives what the recordings could pin
//! down at best; after it, the residual's own variance.
//!
//! The selection follows Brun, Reichert and Kuensch (2001), "Practical identifiability
//! analysis of large environmental simulation models", Water Resources Research 37(4):
//! values are ranked by their sensitivity measure delta_msqr (the RMS of a column of J)
//! and taken in that order while the set stays identifiable: no pair correlated beyond
//! [`MAX_CORRELATION`] and every 95 % interval narrower than [`MAX_HALF_WIDTH`] of the
//! value. Brun et al.'s collinearity index gamma = 1 / sqrt(min eig(S^T S)), S the
//! columns of J scaled to unit length, is reported for the set kept (they suggest
//! 10-15 as the limit beyond which a set is poorly identifiable).

use nalgebra::DMatrix;
use serde::Serialize;

/// Largest |correlation| two kept values may have.
pub const MAX_CORRELATION: f64 = 0.95;
/// Largest 95 % half-width of a kept value, relative (in the fit's scale: ln(1.10) for
/// a positive value, 10 % of the bounds' width otherwise).
pub const MAX_HALF_WIDTH: f64 = 0.10;
/// Normal quantile of a two-sided 95 % interval (the residual count is large).
pub const Z95: f64 = 1.959964;

/// The statistics of a parameter set at a point.
#[derive(Clone, Debug, Serialize)]
pub struct Statistics {
    /// Standard deviation of each value in the fit's scale.
    pub sd_scale: Vec<f64>,
    /// Correlation matrix (row-major, n x n).
    pub correlation: Vec<Vec<f64>>,
    /// Singular values of the normalised sensitivity matrix (descending).
    pub singular_values: Vec<f64>,
    /// Brun et al.'s collinearity index of the set.
    pub collinearity_index: f64,
    /// Sensitivity measure delta_msqr of each value (RMS of its column of J).
    pub sensitivity: Vec<f64>,
}

/// The statistics of the columns `cols` of `jac` with residual variance `s2` and `l`
/// samples per independent value. `None` when J^T J is singular.
pub fn statistics(jac: &DMatrix<f64>, cols: &[usize], s2: f64, l: f64) -> Option<Statistics> {
    let m = jac.nrows();
    let j = DMatrix::from_fn(m, cols.len(), |r, c| jac[(r, cols[c])]);
    let sensitivity: Vec<f64> = (0..cols.len())
        .map(|c| (j.column(c).norm_squared() / m.max(1) as f64).sqrt())
        .collect();
    let jtj = j.transpose() * &j;
    let inv = jtj.clone().try_inverse()?;
    let cov = inv * (s2 * l);
    let n = cols.len();
    let sd: Vec<f64> = (0..n).map(|i| cov[(i, i)].max(0.0).sqrt()).collect();
    let correlation = (0..n)
        .map(|a| {
            (0..n)
                .map(|b| cov[(a, b)] / (sd[a] * sd[b]).max(f64::MIN_POSITIVE))
                .collect()
        })
        .collect();
    let mut scaled = j.clone();
    for c in 0..n {
        let norm = scaled.column(c).norm();
        if norm > 0.0 {
            scaled.column_mut(c).unscale_mut(norm);
        }
    }
    let mut sv: Vec<f64> = scaled
        .clone()
        .svd(false, false)
        .singular_values
        .iter()
        .copied()
        .collect();
    sv.sort_by(|a, b| b.total_cmp(a));
    let smallest = sv.last().copied().unwrap_or(0.0);
    Some(Statistics {
        sd_scale: sd,
        correlation,
        singular_values: sv,
        collinearity_index: if smallest > 0.0 {
            1.0 / smallest
        } else {
            f64::INFINITY
        },
        sensitivity,
    })
}

/// Why a value was left at its file value.
#[derive(Clone, Debug, Serialize)]
pub struct Left {
    /// Index into the candidate list.
    pub index: usize,
    /// The reason, in words.
    pub reason: String,
}

/// The selection: kept indices (into the candidates) and the ones left, with reasons.
#[derive(Clone, Debug, Serialize)]
pub struct Selection {
    /// Candidates kept, in order of decreasing sensitivity.
    pub kept: Vec<usize>,
    /// Candidates left at their file values.
    pub left: Vec<Left>,
}

/// Brun et al.'s forward selection over the columns of `jac` (d r / d s of every
/// candidate); `names` for the reasons; `width_scale[i]` the bounds' width in the fit's
/// scale (to judge a linear value's interval); at most `max_kept`.
pub fn select(
    jac: &DMatrix<f64>,
    names: &[String],
    log: &[bool],
    width_scale: &[f64],
    l: f64,
    max_kept: usize,
) -> Selection {
    let n = jac.ncols();
    let m = jac.nrows().max(1) as f64;
    let delta: Vec<f64> = (0..n)
        .map(|c| (jac.column(c).norm_squared() / m).sqrt())
        .collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| delta[b].total_cmp(&delta[a]));
    let limit = |i: usize| {
        if log[i] {
            (1.0 + MAX_HALF_WIDTH).ln()
        } else {
            MAX_HALF_WIDTH * width_scale[i]
        }
    };
    let mut kept: Vec<usize> = Vec::new();
    let mut left = Vec::new();
    for &i in &order {
        if kept.len() >= max_kept {
            left.push(Left {
                index: i,
                reason: format!("beyond the {max_kept} most effective values"),
            });
            continue;
        }
        if delta[i] == 0.0 {
            left.push(Left {
                index: i,
                reason: "no effect on the fitted channels".into(),
            });
            continue;
        }
        let mut trial = kept.clone();
        trial.push(i);
        let Some(st) = statistics(jac, &trial, 1.0, l) else {
            left.push(Left {
                index: i,
                reason: "its sensitivity is a combination of the kept values' (singular)".into(),
            });
            continue;
        };
        let last = trial.len() - 1;
        let (partner, corr) = (0..last)
            .map(|k| (k, st.correlation[last][k]))
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .unwrap_or((0, 0.0));
        if last > 0 && corr.abs() > MAX_CORRELATION {
            left.push(Left {
                index: i,
                reason: format!(
                    "{} and {} move the fitted channels together: correlation {corr:.2}",
                    names[i], names[trial[partner]]
                ),
            });
            continue;
        }
        let hw = Z95 * st.sd_scale[last];
        if hw > limit(i) {
            let what = if log[i] {
                format!("+-{:.0} %", (hw.exp() - 1.0) * 100.0)
            } else {
                format!("+-{:.3}", hw)
            };
            left.push(Left {
                index: i,
                reason: format!(
                    "too little effect: even a fit down to the noise would pin it only to {what} (95 %)"
                ),
            });
            continue;
        }
        // A value that widens a kept one's interval beyond the limit is refused too.
        if (0..last).any(|k| Z95 * st.sd_scale[k] > limit(trial[k])) {
            left.push(Left {
                index: i,
                reason: format!(
                    "it would blur a kept value beyond +-{:.0} % (correlation with {} {corr:.2})",
                    MAX_HALF_WIDTH * 100.0,
                    names[trial[partner]]
                ),
            });
            continue;
        }
        kept.push(i);
    }
    Selection { kept, left }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A nearly collinear column is refused with its correlation; an orthogonal one is
    /// kept; the covariance of a linear model equals (J^T J)^-1 in closed form.
    #[test]
    fn collinear_columns_are_left_and_the_covariance_is_the_textbook_one() {
        let m = 200;
        let a: Vec<f64> = (0..m).map(|k| (k as f64 * 0.1).sin()).collect();
        let b: Vec<f64> = (0..m).map(|k| (k as f64 * 0.37).cos()).collect();
        let jac = DMatrix::from_fn(m, 3, |r, c| match c {
            0 => 30.0 * a[r],
            1 => 20.0 * b[r],
            _ => 15.0 * a[r] + 0.5 * b[r],
        });
        let names: Vec<String> = ["a", "b", "a2"].iter().map(|s| s.to_string()).collect();
        let s = select(&jac, &names, &[true; 3], &[1.0; 3], 1.0, 10);
        assert_eq!(s.kept, vec![0, 1]);
        assert_eq!(s.left.len(), 1);
        assert!(
            s.left[0].reason.contains("correlation"),
            "{}",
            s.left[0].reason
        );
        // Var(s_a) for column 30a alone: 1 / (900 |a|^2).
        let st = statistics(&jac, &[0], 1.0, 1.0).unwrap();
        let aa: f64 = a.iter().map(|v| v * v).sum();
        assert!((st.sd_scale[0] - (1.0 / (900.0 * aa)).sqrt()).abs() < 1e-12);
        // L samples per independent value widen the interval by sqrt(L).
        let st4 = statistics(&jac, &[0], 1.0, 4.0).unwrap();
        assert!((st4.sd_scale[0] / st.sd_scale[0] - 2.0).abs() < 1e-12);
    }
}
