//! The run's speed and where it comes from: the foils (least squares, [`super::trigger`]),
//! a recorded speed channel (its mean over the passage, its spread there and its drift
//! over the run), or the descriptor's nominal speed, in that order of precedence.

use serde::Serialize;

use super::trigger::FoilSpeed;

/// Where the simulated speed comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SpeedSource {
    /// The foil pulses.
    Foils,
    /// The recorded speed channel, averaged over the passage.
    Channel,
    /// The descriptor's nominal speed.
    Descriptor,
}

/// The speed of a run.
#[derive(Clone, Debug, Serialize)]
pub struct SpeedInfo {
    /// The speed simulated (corrected comparison) [m/s].
    pub speed_mps: f64,
    /// Where it comes from.
    pub source: SpeedSource,
    /// The foils' fit, when there are foils.
    pub foils: Option<FoilSpeed>,
    /// The speed channel's mean over `window_s` [m/s].
    pub channel_mean_mps: Option<f64>,
    /// Its smallest and largest value there [m/s].
    pub channel_range_mps: Option<[f64; 2]>,
    /// Its change over the whole recording, from a straight-line fit, relative to its
    /// mean [%].
    pub channel_drift_pct: Option<f64>,
    /// The passage window the channel is averaged over (recording's clock) [s].
    pub window_s: Option<[f64; 2]>,
    /// Stretches where the speed channel dropped out ([`dropouts`]), left out of the
    /// mean (recording's clock) [s].
    pub channel_dropouts_s: Vec<[f64; 2]>,
}

/// A car's speed cannot change faster than its tyres' grip allows (road friction
/// coefficients stay below about 1.2, so below 1.2 g); a step in the speed channel
/// beyond this rate [m/s^2] is the logger's, not the car's.
const MAX_RATE_MPS2: f64 = 1.5 * 9.81;
/// A dropout departs from the window's median by more than this share.
const DROP_SHARE: f64 = 0.25;

/// The stretches of `v` (samples at `t`) inside [lo, hi] where the channel departs from
/// its median there by more than a quarter and was entered by a step no car can make
/// (faster than 1.5 g): a dropout of the logger's speed source, not a deceleration.
/// A stretch entered gradually is the car's and stays.
pub fn dropouts(t: &[f64], v: &[f64], lo: f64, hi: f64) -> Vec<[f64; 2]> {
    let idx: Vec<usize> = (0..t.len().min(v.len()))
        .filter(|&k| t[k] >= lo && t[k] <= hi)
        .collect();
    let mut sorted: Vec<f64> = idx
        .iter()
        .map(|&k| v[k])
        .filter(|x| x.is_finite())
        .collect();
    if sorted.len() < 3 {
        return Vec::new();
    }
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let out = |k: usize| (v[k] - median).abs() > DROP_SHARE * median.abs();
    let mut found = Vec::new();
    let mut k = 0;
    while k < idx.len() {
        let i = idx[k];
        let abrupt = k > 0 && {
            let p = idx[k - 1];
            let dt = t[i] - t[p];
            dt > 0.0 && ((v[i] - v[p]) / dt).abs() > MAX_RATE_MPS2 && !out(p)
        };
        if out(i) && abrupt {
            let mut j = k;
            while j + 1 < idx.len() && out(idx[j + 1]) {
                j += 1;
            }
            found.push([t[i], t[idx[j]]]);
            k = j + 1;
        } else {
            k += 1;
        }
    }
    found
}

/// Mean, range over [`lo`, `hi`] and drift over the record of the speed channel `v`.
pub fn channel_stats(
    t: &[f64],
    v: &[f64],
    lo: f64,
    hi: f64,
    skip: &[[f64; 2]],
) -> (f64, [f64; 2], f64) {
    let kept = |ti: f64| !skip.iter().any(|d| ti >= d[0] && ti <= d[1]);
    let inside: Vec<f64> = t
        .iter()
        .zip(v)
        .filter(|(ti, _)| **ti >= lo && **ti <= hi && kept(**ti))
        .map(|(_, x)| *x)
        .collect();
    let pick = if inside.is_empty() {
        v.to_vec()
    } else {
        inside
    };
    let mean = pick.iter().sum::<f64>() / pick.len().max(1) as f64;
    let range = pick
        .iter()
        .fold([f64::INFINITY, f64::NEG_INFINITY], |r, x| {
            [r[0].min(*x), r[1].max(*x)]
        });
    // Least-squares slope over the whole record.
    let n = t.len() as f64;
    let (mt, mv) = (t.iter().sum::<f64>() / n, v.iter().sum::<f64>() / n);
    let (mut stt, mut stv) = (0.0, 0.0);
    for (ti, vi) in t.iter().zip(v) {
        stt += (ti - mt).powi(2);
        stv += (ti - mt) * (vi - mv);
    }
    let slope = if stt > 0.0 { stv / stt } else { 0.0 };
    let span = t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0);
    (mean, range, 100.0 * slope * span / mv)
}
