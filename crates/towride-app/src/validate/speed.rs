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
}

/// Mean, range over [`lo`, `hi`] and drift over the record of the speed channel `v`.
pub fn channel_stats(t: &[f64], v: &[f64], lo: f64, hi: f64) -> (f64, [f64; 2], f64) {
    let inside: Vec<f64> = t
        .iter()
        .zip(v)
        .filter(|(ti, _)| **ti >= lo && **ti <= hi)
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
