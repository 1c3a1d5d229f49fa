//! Features of a band-limited curve as calibration residuals (`calibrate --residual
//! features|both`): the largest maximum, the largest minimum and the next-largest
//! extremum apart from both, each with its time. For a wheel crossing a bump these are
//! the impact, the trough over the crest and the landing peak, in whatever order the
//! recording has them; for a body channel its pitch and heave extremes.
//!
//! Each extremum is refined between samples by the parabola through it and its two
//! neighbours, so its value and time move smoothly with the model's values (the
//! finite-difference sensitivities need that). Its width w is the mean time from the
//! extremum to where the curve has fallen to [`WIDTH_LEVEL`] of it on either side. On the
//! simulated curve the extremum of the same sign is searched up to half-way to the
//! measured curve's nearest extremum of that sign and at least half its height, one top
//! period away or more: a model whose events come a few milliseconds early or late still
//! has its own peak found, and never the neighbouring one.
//!
//! Weights. A value's misfit is divided by the channel's noise, as the time histories'.
//! A time's misfit is divided by the time over which the peak falls by the noise. Near an
//! extremum of height A the curve is A - k t^2 / 2 with k = 2 (1 - L) A / w^2 (it falls
//! to L A at w), so it falls by sigma_n at dt = sqrt(2 sigma_n / k) =
//! w sqrt(sigma_n / ((1 - L) A)), never less than the recording's time quantum (sample
//! interval / sqrt(12)). The width is read at a level well above the noise, where a
//! three-sample curvature of a 5 kHz record would be mostly noise. An extremum below
//! [`MIN_HEIGHT_NOISE`] noise levels has no defined time and is not used; nor is one
//! whose shape reaches a clipped stretch (its true height is unknown). The calibration
//! takes no features from a channel that clipped anywhere in the window: which extremum
//! is the largest is then unknown.

use serde::Serialize;

/// Extrema smaller than this many noise levels are not features.
pub const MIN_HEIGHT_NOISE: f64 = 3.0;
/// The width of an extremum is read where the curve has fallen to this share of it.
pub const WIDTH_LEVEL: f64 = 0.8;

/// Which extremum.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// The largest maximum.
    Maximum,
    /// The largest minimum (most negative value).
    Minimum,
    /// The largest |extremum| at least one top period from the other two.
    Third,
}

/// One feature of a measured curve.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Feature {
    /// Which extremum.
    pub kind: Kind,
    /// +1 for a maximum, -1 for a minimum.
    pub sign: f64,
    /// Its time on the recording's clock [s].
    pub time_s: f64,
    /// Its value [m/s^2].
    pub value: f64,
    /// The time's weight [s] (see the module notes).
    pub sigma_t_s: f64,
    /// The extremum's width w [s].
    pub width_s: f64,
    /// The simulated extremum is searched within this time of `time_s` [s].
    pub search_s: f64,
}

/// The features of curve `y` on times `t` (uniform), samples with `keep[k]` false
/// (clipped) excluded; `top_hz` the band's top frequency (extrema closer than one period
/// are the same event), `noise` the channel's noise, `quantum_s` the recording's sample
/// interval.
pub fn extract(
    t: &[f64],
    y: &[f64],
    keep: &[bool],
    top_hz: f64,
    noise: f64,
    quantum_s: f64,
) -> Vec<Feature> {
    let n = y.len().min(t.len()).min(keep.len());
    // Interior local extrema on kept samples whose neighbours are kept too.
    let usable = |k: usize| k > 0 && k + 1 < n && keep[k - 1] && keep[k] && keep[k + 1];
    let is_ext = |k: usize, s: f64| s * y[k] >= s * y[k - 1] && s * y[k] >= s * y[k + 1];
    let best = |s: f64, skip: &dyn Fn(usize) -> bool| -> Option<(usize, f64)> {
        (0..n)
            .filter(|&k| usable(k) && is_ext(k, s) && !skip(k))
            .map(|k| (k, s))
            .max_by(|a, b| (a.1 * y[a.0]).total_cmp(&(b.1 * y[b.0])))
    };
    let none = |_: usize| false;
    let mut found: Vec<(Kind, usize, f64)> = Vec::new();
    if let Some((k, s)) = best(1.0, &none) {
        found.push((Kind::Maximum, k, s));
    }
    if let Some((k, s)) = best(-1.0, &none) {
        found.push((Kind::Minimum, k, s));
    }
    let period = 1.0 / top_hz;
    let far = |k: usize| found.iter().all(|&(_, j, _)| (t[k] - t[j]).abs() >= period);
    let third = [1.0, -1.0]
        .into_iter()
        .filter_map(|s| best(s, &|k| !far(k)))
        .max_by(|a, b| (a.1 * y[a.0]).total_cmp(&(b.1 * y[b.0])));
    if let Some((k, s)) = third {
        found.push((Kind::Third, k, s));
    }
    let dt = t.get(1).zip(t.first()).map_or(quantum_s, |(b, a)| b - a);
    found
        .into_iter()
        .filter_map(|(kind, k, s)| {
            let (tk, yk) = refine(t[k], dt, y[k - 1], y[k], y[k + 1]);
            let height = yk.abs();
            if height < MIN_HEIGHT_NOISE * noise {
                return None;
            }
            // The kept stretch around the extremum: its shape must fall to the width
            // level inside it, and the simulated one is searched inside it.
            let a = (0..k).rev().find(|&j| !keep[j]).map_or(0, |j| j + 1);
            let b = (k + 1..n).find(|&j| !keep[j]).unwrap_or(n);
            let w = width(&t[a..b], &y[a..b], k - a, s)?;
            let resolution = w * (noise / ((1.0 - WIDTH_LEVEL) * height)).sqrt();
            let rival = (0..n)
                .filter(|&j| j != k && usable(j) && is_ext(j, s) && s * y[j] >= 0.5 * s * y[k])
                .map(|j| (t[j] - t[k]).abs())
                .filter(|d| *d >= period)
                .fold(f64::INFINITY, f64::min);
            let record = (t[k] - t[a]).min(t[b - 1] - t[k]);
            Some(Feature {
                kind,
                sign: s,
                time_s: tk,
                value: yk,
                sigma_t_s: resolution.max(quantum_s / 12f64.sqrt()),
                width_s: w,
                search_s: (0.5 * rival).max(0.5 * period).min(record),
            })
        })
        .collect()
}

/// The mean time from extremum `k` (sign `s`) of `y` to where `s y` falls to
/// [`WIDTH_LEVEL`] of it, on either side (linear between samples); `None` when either
/// side leaves the curve first (a peak at the record's or a clipped stretch's edge has
/// no shape to time it by).
fn width(t: &[f64], y: &[f64], k: usize, s: f64) -> Option<f64> {
    let level = WIDTH_LEVEL * s * y[k];
    let cross = |j: usize, i: usize| {
        // s y falls through `level` between samples i (above) and j (below).
        let (a, b) = (s * y[i] - level, s * y[j] - level);
        (t[i] + (t[j] - t[i]) * a / (a - b) - t[k]).abs()
    };
    let right = (k + 1..y.len())
        .find(|&j| s * y[j] <= level)
        .map(|j| cross(j, j - 1));
    let left = (0..k)
        .rev()
        .find(|&j| s * y[j] <= level)
        .map(|j| cross(j, j + 1));
    Some(0.5 * (left? + right?))
}

/// The extremum of `f`'s sign on curve `y` (times `t`) within `f.search_s` of
/// `f.time_s`, on the samples `keep` marks (a clipped stretch of the recording hides the
/// simulated peak there too): its refined time and value.
pub fn locate(t: &[f64], y: &[f64], keep: &[bool], f: &Feature) -> (f64, f64) {
    let n = y.len().min(t.len());
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let w = f.search_s;
    let lo = t.partition_point(|&x| x < f.time_s - w);
    let hi = t.partition_point(|&x| x <= f.time_s + w).min(n);
    let (lo, hi) = if lo < hi {
        (lo, hi)
    } else {
        (lo.min(n - 1), lo.min(n - 1) + 1)
    };
    let k = (lo..hi)
        .filter(|&j| keep.get(j).copied().unwrap_or(true))
        .max_by(|&a, &b| (f.sign * y[a]).total_cmp(&(f.sign * y[b])))
        .unwrap_or(lo);
    if k == 0 || k + 1 >= n {
        return (t[k], y[k]);
    }
    let dt = t[1] - t[0];
    refine(t[k], dt, y[k - 1], y[k], y[k + 1])
}

/// The vertex of the parabola through (t - dt, a), (t, b), (t + dt, c): its time and
/// value, the sample itself when the three are collinear.
fn refine(t: f64, dt: f64, a: f64, b: f64, c: f64) -> (f64, f64) {
    let curvature = a - 2.0 * b + c;
    if curvature.abs() <= f64::EPSILON * (a.abs() + b.abs() + c.abs()) {
        return (t, b);
    }
    let d = (0.5 * (a - c) / curvature).clamp(-0.5, 0.5);
    (t + d * dt, b - 0.25 * (a - c) * d)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize, dt: f64) -> Vec<f64> {
        (0..n).map(|k| k as f64 * dt).collect()
    }

    /// A decaying two-sided pulse: the features land on the analytic extrema, between
    /// samples, to a small share of the sample interval.
    #[test]
    fn extrema_of_a_sampled_pulse_are_found_between_samples() {
        let dt = 1e-3;
        let t = grid(600, dt);
        // y = sin(2 pi 10 (t - 0.1)) e^(-(t - 0.1)/0.05) for t > 0.1
        let f = |x: f64| {
            let s = x - 0.1;
            if s <= 0.0 {
                0.0
            } else {
                (2.0 * std::f64::consts::PI * 10.0 * s).sin() * (-s / 0.05).exp()
            }
        };
        let y: Vec<f64> = t.iter().map(|&x| 10.0 * f(x)).collect();
        let keep = vec![true; y.len()];
        // Extrema 50 ms apart; one top period (40 ms) keeps the third apart from both.
        let feats = extract(&t, &y, &keep, 25.0, 0.01, dt);
        assert_eq!(feats.len(), 3);
        // Analytic maxima/minima: tan(w s) = w tau, s_k = (atan(w tau) + k pi) / w.
        let w = 2.0 * std::f64::consts::PI * 10.0;
        let s0 = (w * 0.05).atan() / w;
        let expect = |k: f64| 0.1 + s0 + k * std::f64::consts::PI / w;
        let max = feats.iter().find(|f| f.kind == Kind::Maximum).unwrap();
        let min = feats.iter().find(|f| f.kind == Kind::Minimum).unwrap();
        let third = feats.iter().find(|f| f.kind == Kind::Third).unwrap();
        assert!(
            (max.time_s - expect(0.0)).abs() < 0.05 * dt,
            "{}",
            max.time_s
        );
        assert!(
            (min.time_s - expect(1.0)).abs() < 0.05 * dt,
            "{}",
            min.time_s
        );
        assert!(
            (third.time_s - expect(2.0)).abs() < 0.05 * dt,
            "{}",
            third.time_s
        );
        assert!((max.value - 10.0 * f(expect(0.0))).abs() < 1e-3 * max.value);
        // The same feature found on a copy moved by 1.3 ms, a little larger.
        let shifted: Vec<f64> = t.iter().map(|&x| 11.0 * f(x - 1.3e-3)).collect();
        let (ts, ys) = locate(&t, &shifted, &keep, max);
        assert!((ts - max.time_s - 1.3e-3).abs() < 0.05 * dt);
        assert!((ys / max.value - 1.1).abs() < 1e-3);
    }

    /// Clipped samples hide the largest maximum: the next one is taken, and a peak
    /// below three noise levels is not a feature.
    #[test]
    fn clipped_and_small_extrema_are_left_out() {
        let dt = 1e-3;
        let t = grid(400, dt);
        let y: Vec<f64> = t
            .iter()
            .map(|&x| {
                let a = if x < 0.3 { 5.0 } else { 2.0 };
                a * (2.0 * std::f64::consts::PI * 5.0 * x).sin()
            })
            .collect();
        let mut keep = vec![true; y.len()];
        // Clip the first maximum (t = 0.05 s).
        for k in 40..=60 {
            keep[k] = false;
        }
        let feats = extract(&t, &y, &keep, 20.0, 0.01, dt);
        let max = feats.iter().find(|f| f.kind == Kind::Maximum).unwrap();
        assert!((max.time_s - 0.25).abs() < 1e-4, "{}", max.time_s);
        assert!((max.value - 5.0).abs() < 1e-3);
        let quiet = extract(&t, &y, &vec![true; y.len()], 20.0, 2.0, dt);
        // 5 >= 3 x 2 fails: only extremes of at least 6 are features.
        assert!(quiet.is_empty(), "{quiet:?}");
    }

    /// The width of a sine's peak, acos(0.8) / omega, and the time weight
    /// w sqrt(sigma / (0.2 A)), floored at the time quantum.
    #[test]
    fn time_weight_follows_the_peak_width() {
        let dt = 1e-4;
        let t = grid(6000, dt);
        let omega = 2.0 * std::f64::consts::PI * 2.0;
        let y: Vec<f64> = t.iter().map(|&x| 4.0 * (omega * x).sin()).collect();
        let feats = extract(&t, &y, &vec![true; y.len()], 50.0, 0.02, dt);
        let max = feats.iter().find(|f| f.kind == Kind::Maximum).unwrap();
        let w = WIDTH_LEVEL.acos() / omega;
        assert!(
            (max.width_s / w - 1.0).abs() < 1e-4,
            "{} vs {w}",
            max.width_s
        );
        let expect = w * (0.02 / (0.2 * 4.0f64)).sqrt();
        assert!((max.sigma_t_s / expect - 1.0).abs() < 1e-4);
        // Within the width, a peak shifted by half of it is found.
        let shifted: Vec<f64> = t
            .iter()
            .map(|&x| 4.0 * (omega * (x - 0.5 * w)).sin())
            .collect();
        let (ts, _) = locate(&t, &shifted, &[], max);
        assert!((ts - max.time_s - 0.5 * w).abs() < 1e-6);
        let coarse = extract(&t, &y, &vec![true; y.len()], 50.0, 0.02, 1.0);
        assert!((coarse[0].sigma_t_s - 1.0 / 12f64.sqrt()).abs() < 1e-12);
    }
}
