//! Time alignment refined by a bounded cross-correlation.
//!
//! The trigger and obstacle events give a first alignment. A constant timing error (a
//! trigger delay) shifts every channel alike, so one shift is found per run: the lag, on
//! the measurement's sample grid within +-`max_shift_s`, that maximises the mean over the
//! channels of the Pearson correlation between measured and simulated curves, refined
//! below one sample by a parabola through the best lag and its two neighbours.

use super::metrics::pearson;

/// The result of the search.
#[derive(Clone, Copy, Debug)]
pub struct Alignment {
    /// Shift [s]: the events are stamped this much later than the data show them.
    pub shift_s: f64,
    /// Mean correlation at the best integer lag.
    pub correlation: f64,
    /// True when the best lag is at the search bound (the shift may be larger).
    pub at_bound: bool,
}

/// `measured[c][k]` at times `t[k]` against `simulated(c, t, shift)`, the simulation
/// channel c mapped to measurement time t with a trial shift.
pub fn best_shift(
    t: &[f64],
    measured: &[&[f64]],
    simulated: &dyn Fn(usize, f64, f64) -> f64,
    dt_s: f64,
    max_shift_s: f64,
) -> Alignment {
    let kmax = (max_shift_s / dt_s).floor().max(1.0) as i64;
    let score = |shift: f64| -> f64 {
        let mut sum = 0.0;
        for (c, m) in measured.iter().enumerate() {
            let s: Vec<f64> = t.iter().map(|&ti| simulated(c, ti, shift)).collect();
            sum += pearson(m, &s);
        }
        sum / measured.len().max(1) as f64
    };
    let scores: Vec<f64> = (-kmax..=kmax).map(|k| score(k as f64 * dt_s)).collect();
    let best = (0..scores.len())
        .max_by(|&a, &b| scores[a].total_cmp(&scores[b]))
        .unwrap_or(kmax as usize);
    let mut frac = 0.0;
    if best > 0 && best + 1 < scores.len() {
        let (a, b, c) = (scores[best - 1], scores[best], scores[best + 1]);
        let den = a - 2.0 * b + c;
        if den < 0.0 {
            frac = (0.5 * (a - c) / den).clamp(-0.5, 0.5);
        }
    }
    Alignment {
        shift_s: (best as f64 - kmax as f64 + frac) * dt_s,
        correlation: scores[best],
        at_bound: best == 0 || best + 1 == scores.len(),
    }
}
