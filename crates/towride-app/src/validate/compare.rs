//! One comparison of a measured run with a simulation on the measurement's samples:
//! the time shift (optional), then per channel the figures and the rating, clipped
//! samples left out.

use std::collections::BTreeMap;

use serde::Serialize;

use super::align::best_shift;
use super::filter::Acquired;
use super::metrics::{gain_ratio, peak, pearson, rms_diff};
use super::pipeline::Options;
use super::rating::{iso_rating, Rating};
use super::G_MPS2;

/// Figures of one channel in one comparison (SI units).
#[derive(Clone, Debug, Serialize)]
pub struct ChannelFigures {
    /// Simulated channel name.
    pub channel: String,
    /// Measured value of largest magnitude [m/s^2].
    pub peak_measured_mps2: f64,
    /// When it occurs (recording's clock) [s].
    pub t_peak_measured_s: f64,
    /// Simulated value of largest magnitude [m/s^2].
    pub peak_simulated_mps2: f64,
    /// When it occurs (recording's clock) [s].
    pub t_peak_simulated_s: f64,
    /// RMS of measured minus simulated [m/s^2].
    pub rms_diff_mps2: f64,
    /// Pearson correlation of the two curves [-].
    pub correlation: f64,
    /// Least-squares amplitude ratio measured / simulated (a gain-error estimate).
    pub gain_ratio: f64,
    /// ISO/TS 18571-style rating of the simulated curve against the measured one.
    pub rating: Rating,
    /// Interval the channel was rated on (recording's clock) [s].
    pub interval_s: [f64; 2],
    /// Clipped measured samples inside the interval, left out of every figure.
    pub clipped_samples: usize,
    /// Simulated samples in the evaluation window at which a sensor of the channel's
    /// range would clip (gravity included on z).
    pub simulated_clipped_samples: usize,
    /// RMS of the measured channel over its interval divided by its RMS on the quiet
    /// road before the obstacle (`None` without enough quiet samples).
    pub signal_to_noise: Option<f64>,
    /// The measured channel stands above its noise ([`SIGNAL_MIN`]): only such channels
    /// enter the mean rating (a channel of sensor noise alone rates its noise).
    pub has_signal: bool,
}

/// Smallest ratio of a channel's RMS over its interval to its RMS on the quiet road for
/// the channel to count as carrying a signal: noise alone gives about 1.
pub const SIGNAL_MIN: f64 = 3.0;
/// The quiet road ends this far before the obstacle [m]: a tyre feels an obstacle
/// before its centre is over it (radius and enveloping, about 0.3-0.5 m), and the
/// acquisition filter spreads the response earlier still ...
const QUIET_LEAD_M: f64 = 1.0;
/// ... or this long before it [s], whichever is earlier (the filters' lead) ...
const QUIET_TO_S: f64 = 0.05;
/// ... and spans this long [s].
const QUIET_SPAN_S: f64 = 0.5;
/// Fewest quiet samples a noise estimate needs.
const QUIET_MIN_SAMPLES: usize = 20;

/// One comparison of a run (corrected or uncorrected).
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// "corrected" or "uncorrected".
    pub label: &'static str,
    /// Speed simulated [m/s].
    pub speed_mps: f64,
    /// Time shift found by the cross-correlation [s] (0 when uncorrected): the events are
    /// stamped this much later than the data show them (a trigger delay).
    pub shift_s: f64,
    /// The shift is at the search bound (the true shift may be larger).
    pub shift_at_bound: bool,
    /// Mean correlation of the channels at the shift found (`None` when uncorrected):
    /// how well the shapes agree once aligned.
    pub shift_correlation: Option<f64>,
    /// When the front wheels reach the obstacle, on the recording's clock [s].
    pub obstacle_time_s: f64,
    /// Mean overall rating over the channels with a signal (`has_signal`).
    pub mean_rating: f64,
    /// Channels left out of the mean: no signal above their noise.
    pub without_signal: Vec<String>,
    /// Figures per channel.
    pub channels: Vec<ChannelFigures>,
    /// The compared curves on the evaluation window (for plots).
    #[serde(skip)]
    pub time_s: Vec<f64>,
    /// Measured curves by channel name [m/s^2].
    #[serde(skip)]
    pub measured: BTreeMap<String, Vec<f64>>,
    /// Simulated curves on the same samples [m/s^2].
    #[serde(skip)]
    pub simulated: BTreeMap<String, Vec<f64>>,
    /// Per channel with a range: the recording's clipped samples on the same samples.
    #[serde(skip)]
    pub clipped: BTreeMap<String, Vec<bool>>,
}

/// A channel's sensor: its axis and range [g], for the clipping flags.
pub(super) struct Sensor<'a> {
    pub name: &'a str,
    pub axis: char,
    pub range_g: Option<f64>,
    /// The recording's clipped samples (whole record), if the channel has a range.
    pub clipped: Option<&'a [bool]>,
}

/// The measured side of a comparison: samples `idx` of the recording.
pub(super) struct Recorded<'a> {
    pub time_s: &'a [f64],
    pub channels: &'a BTreeMap<String, Vec<f64>>,
    pub rate_hz: f64,
    pub idx: &'a [usize],
}

/// Compares on the samples `rec.idx`; with `search = Some(bound)` the time shift is
/// found by the cross-correlation first.
#[allow(clippy::too_many_arguments)]
pub(super) fn compare(
    label: &'static str,
    rec: &Recorded,
    sensors: &[Sensor],
    acq: &Acquired,
    speed_mps: f64,
    t_obs: f64,
    search: Option<f64>,
    opts: &Options,
) -> Comparison {
    let idx = rec.idx;
    let t: Vec<f64> = idx.iter().map(|&k| rec.time_s[k]).collect();
    let measured: BTreeMap<String, Vec<f64>> = sensors
        .iter()
        .map(|s| {
            let c = &rec.channels[s.name];
            (s.name.to_string(), idx.iter().map(|&k| c[k]).collect())
        })
        .collect();
    let offset = t_obs - acq.obstacle_time_s;
    let curves: Vec<&[f64]> = sensors
        .iter()
        .map(|s| acq.channels.get(s.name).map_or(&[][..], Vec::as_slice))
        .collect();
    let sim_at = |c: usize, ti: f64, shift: f64| match curves[c] {
        [] => f64::NAN,
        y => acq.sample(y, ti - offset + shift),
    };
    let dt = 1.0 / rec.rate_hz;
    let (shift, at_bound, correlation) = match search {
        Some(bound) => {
            let m: Vec<&[f64]> = sensors
                .iter()
                .map(|s| measured[s.name].as_slice())
                .collect();
            let a = best_shift(&t, &m, &sim_at, dt, bound);
            (a.shift_s, a.at_bound, Some(a.correlation))
        }
        None => (0.0, false, None),
    };
    let simulated: BTreeMap<String, Vec<f64>> = sensors
        .iter()
        .enumerate()
        .map(|(c, s)| {
            (
                s.name.to_string(),
                t.iter().map(|&ti| sim_at(c, ti, shift)).collect(),
            )
        })
        .collect();
    let channels: Vec<ChannelFigures> = sensors
        .iter()
        .map(|s| {
            let n = s.name;
            let (a, b) = active(
                &measured[n],
                &simulated[n],
                opts.active_threshold,
                (opts.active_pad_s / dt) as usize,
            );
            // Clipped samples are left out of both curves alike.
            let keep: Vec<usize> = (a..b)
                .filter(|&k| !s.clipped.is_some_and(|c| c[idx[k]]))
                .collect();
            let pick = |y: &[f64]| -> Vec<f64> { keep.iter().map(|&k| y[k]).collect() };
            let (m, sm, tt) = (pick(&measured[n]), pick(&simulated[n]), pick(&t));
            let (pm, tpm) = peak(&tt, &m);
            let (ps, tps) = peak(&tt, &sm);
            let sim_clipped = s.range_g.map_or(0, |r| {
                let g0 = if s.axis == 'z' { 1.0 } else { 0.0 };
                simulated[n]
                    .iter()
                    .filter(|v| (*v / G_MPS2 + g0).abs() >= super::measurement::CLIP_SHARE * r)
                    .count()
            });
            let quiet_end = t_obs - QUIET_TO_S.max(QUIET_LEAD_M / speed_mps.max(0.1));
            let snr = noise_rms(rec, n, quiet_end).map(|q| rms(&m) / q);
            ChannelFigures {
                signal_to_noise: snr,
                has_signal: snr.is_none_or(|r| r >= SIGNAL_MIN),
                channel: n.to_string(),
                peak_measured_mps2: pm,
                t_peak_measured_s: tpm,
                peak_simulated_mps2: ps,
                t_peak_simulated_s: tps,
                rms_diff_mps2: rms_diff(&m, &sm),
                correlation: pearson(&m, &sm),
                gain_ratio: gain_ratio(&m, &sm),
                rating: iso_rating(&m, &sm, dt),
                interval_s: [t[a], t[b - 1]],
                clipped_samples: (b - a) - keep.len(),
                simulated_clipped_samples: sim_clipped,
            }
        })
        .collect();
    let rated: Vec<&ChannelFigures> = channels.iter().filter(|c| c.has_signal).collect();
    let mean_rating =
        rated.iter().map(|c| c.rating.overall).sum::<f64>() / rated.len().max(1) as f64;
    let without_signal = channels
        .iter()
        .filter(|c| !c.has_signal)
        .map(|c| c.channel.clone())
        .collect();
    Comparison {
        label,
        speed_mps,
        shift_s: shift,
        shift_at_bound: at_bound,
        shift_correlation: correlation,
        obstacle_time_s: t_obs - shift,
        mean_rating,
        without_signal,
        channels,
        time_s: t,
        measured,
        simulated,
        clipped: sensors
            .iter()
            .filter_map(|s| {
                let c = s.clipped?;
                Some((s.name.to_string(), idx.iter().map(|&k| c[k]).collect()))
            })
            .collect(),
    }
}

/// RMS of the measured channel `name` on the quiet road ending at `end` (the
/// recording's clock; the pipeline has zeroed its mean there).
fn noise_rms(rec: &Recorded, name: &str, end: f64) -> Option<f64> {
    let c = rec.channels.get(name)?;
    let quiet: Vec<f64> = rec
        .time_s
        .iter()
        .zip(c)
        .filter(|(t, _)| **t >= end - QUIET_SPAN_S && **t <= end)
        .map(|(_, v)| *v)
        .collect();
    let q = rms(&quiet);
    (quiet.len() >= QUIET_MIN_SAMPLES && q > 0.0).then_some(q)
}

fn rms(y: &[f64]) -> f64 {
    (y.iter().map(|v| v * v).sum::<f64>() / y.len().max(1) as f64).sqrt()
}

/// Index range where |m| or |s| exceeds `share` of its own largest magnitude, widened by
/// `pad` samples each side.
fn active(m: &[f64], s: &[f64], share: f64, pad: usize) -> (usize, usize) {
    let n = m.len();
    let mut range: Option<(usize, usize)> = None;
    for y in [m, s] {
        let top = y.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let first = y.iter().position(|v| v.abs() >= share * top && top > 0.0);
        let last = y.iter().rposition(|v| v.abs() >= share * top && top > 0.0);
        if let (Some(f), Some(l)) = (first, last) {
            range = Some(range.map_or((f, l), |(a, b)| (a.min(f), b.max(l))));
        }
    }
    match range {
        Some((a, b)) if b + 1 - a >= 10 => (a.saturating_sub(pad), (b + 1 + pad).min(n)),
        _ => (0, n),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Samples of a 6 g, 5 Hz sine over 5 periods at 1 kHz where a 5 g sensor clips,
    /// against the time the sine spends beyond the range (analytical): on z the sensor
    /// reads a/g + 1, so it clips for sin >= (5 - 1) / 6 and for sin <= -(5 + 1) / 6; on x
    /// for |sin| >= 5 / 6. Each clipped stretch holds its duration x rate samples to within
    /// one, so the counts agree to within the number of stretches.
    #[test]
    fn simulated_clipping_matches_the_time_beyond_the_range() {
        let (rate, f, amp_g, range_g) = (1000.0, 5.0, 6.0, 5.0);
        let n = 1000;
        let t: Vec<f64> = (0..n).map(|k| k as f64 / rate).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|&ti| amp_g * G_MPS2 * (2.0 * PI * f * ti).sin())
            .collect();
        let names = ["acc_z", "acc_x", "acc_free"];
        let channels: BTreeMap<String, Vec<f64>> =
            names.iter().map(|c| (c.to_string(), y.clone())).collect();
        // The recording's own clipping marks must not change the simulated count.
        let marks = vec![true; n];
        let sensors = [
            Sensor {
                name: "acc_z",
                axis: 'z',
                range_g: Some(range_g),
                clipped: Some(&marks),
            },
            Sensor {
                name: "acc_x",
                axis: 'x',
                range_g: Some(range_g),
                clipped: None,
            },
            Sensor {
                name: "acc_free",
                axis: 'z',
                range_g: None,
                clipped: None,
            },
        ];
        let idx: Vec<usize> = (0..n).collect();
        let rec = Recorded {
            time_s: &t,
            channels: &channels,
            rate_hz: rate,
            idx: &idx,
        };
        let acq = Acquired {
            t0_s: 0.0,
            dt_s: 1.0 / rate,
            channels: channels.clone(),
            obstacle_time_s: 0.0,
        };
        let c = compare(
            "uncorrected",
            &rec,
            &sensors,
            &acq,
            10.0,
            0.0,
            None,
            &Options::default(),
        );
        let periods = f * n as f64 / rate;
        // Share of a period with sin >= s.
        let above = |s: f64| (PI - 2.0 * s.asin()) / (2.0 * PI);
        let r = super::super::measurement::CLIP_SHARE * range_g;
        let z = periods * rate / f * (above((r - 1.0) / amp_g) + above((r + 1.0) / amp_g));
        let x = periods * rate / f * 2.0 * above(r / amp_g);
        let got = |i: usize| c.channels[i].simulated_clipped_samples as f64;
        assert!(
            (got(0) - z).abs() <= 2.0 * periods,
            "z: {} vs {z:.1}",
            got(0)
        );
        assert!(
            (got(1) - x).abs() <= 2.0 * periods,
            "x: {} vs {x:.1}",
            got(1)
        );
        assert_eq!(c.channels[2].simulated_clipped_samples, 0);
        // Gravity on z moves the threshold: the two axes differ by far more than the
        // rounding allows, so an axis mix-up would fail.
        assert!(x - z > 4.0 * periods);
    }
}
