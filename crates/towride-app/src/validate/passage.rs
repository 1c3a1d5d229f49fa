//! The obstacle passage found in the signals, without a trigger.
//!
//! Each axle's unsprung vertical accelerations are combined into one envelope: every
//! channel less its mean over the 0.05 s before (gravity, offsets and the body's slow
//! motion go), squared, averaged over the channels, smoothed over 5 ms and rooted. The
//! front axle's passage is the largest peak of its envelope; it is visible when that
//! peak stands at least [`SNR_MIN`] times above the envelope's median (the noise), else
//! detection fails with an error rather than a guess. Its onset is where the envelope
//! last rose above max(4 x median, 5 % of the peak) before the peak, gaps below that
//! bridged when shorter than 30 ms (zero crossings of the wheel hop) or than the time to
//! travel [`QUIET_M`] (the dip between an obstacle's entry and its exit: at 10 km/h the
//! exit of a 0.5 m bump is a second event 0.2 s after the entry, often the larger one,
//! and a time-only bridge put the onset at the exit, 0.5 m late).
//!
//! The rear axle (and a trailer's axle) is then looked for where the wheelbase at the
//! measured speed puts it, within +-40 % of that delay, by the same rule on its own
//! channels; the distance travelled between the onsets (the speed integrated) is the
//! implied wheelbase. The same rule applied to the simulation gives the onset's offset
//! from the true passage, so detector lag cancels in the alignment.

use std::collections::BTreeMap;

use serde::Serialize;

use super::descriptor::PassageSpec;
pub use crate::error::{OnsetError, PassageError};
use crate::signal::butterworth::interp;

/// The front axle's envelope peak must stand this many times above its median.
pub const SNR_MIN: f64 = 8.0;
/// Window of the moving mean taken off every channel [s].
const DETREND_S: f64 = 0.05;
/// Smoothing of the squared signal [s].
const SMOOTH_S: f64 = 0.005;
/// Dips below the threshold shorter than this are bridged [s].
const QUIET_S: f64 = 0.03;
/// Dips shorter than this much travel are bridged too [m]: an obstacle's entry and exit
/// are one passage (the plan's bump and ramp are 0.5 m long; the dip between their
/// events is at most 0.2 m of travel at 10 km/h, see the module text).
pub const QUIET_M: f64 = 0.5;

/// The longest dip bridged at `speed_mps` [s] (30 ms when the speed is unknown).
fn quiet_s(speed_mps: f64) -> f64 {
    if speed_mps.is_finite() && speed_mps > 0.0 {
        QUIET_S.max(QUIET_M / speed_mps)
    } else {
        QUIET_S
    }
}
/// The rear axle is searched within this share of the expected delay around it.
const REAR_WINDOW: f64 = 0.4;

/// Position along the road against time: the speed integrated.
#[derive(Clone, Debug)]
pub struct Track {
    t: Vec<f64>,
    x: Vec<f64>,
}

impl Track {
    /// Constant speed `v` [m/s].
    pub fn constant(v: f64) -> Track {
        Track {
            // Two points and exact linear extension: no rounding from far-off ends.
            t: vec![0.0, 1.0],
            x: vec![0.0, v],
        }
    }

    /// The speed samples `v` [m/s] at `t` integrated by the trapezoidal rule.
    pub fn from_speed(t: &[f64], v: &[f64]) -> Track {
        let mut x = Vec::with_capacity(t.len());
        let mut s = 0.0;
        for k in 0..t.len() {
            if k > 0 {
                s += 0.5 * (v[k] + v[k - 1]) * (t[k] - t[k - 1]);
            }
            x.push(s);
        }
        Track { t: t.to_vec(), x }
    }

    /// Distance travelled at time `t` [m] (linear beyond the ends).
    pub fn position(&self, t: f64) -> f64 {
        let n = self.t.len();
        if n < 2 {
            return 0.0;
        }
        let (i, j) = if t < self.t[0] {
            (0, 1)
        } else if t > self.t[n - 1] {
            (n - 2, n - 1)
        } else {
            return interp(&self.t, &self.x, t);
        };
        let v = (self.x[j] - self.x[i]) / (self.t[j] - self.t[i]);
        let (t0, x0) = if t < self.t[0] {
            (self.t[0], self.x[0])
        } else {
            (self.t[n - 1], self.x[n - 1])
        };
        x0 + v * (t - t0)
    }

    /// When the distance `x` is reached [s] (the speed is positive).
    pub fn time_at(&self, x: f64) -> f64 {
        let n = self.t.len();
        if n >= 2 && x >= self.x[0] && x <= self.x[n - 1] && self.x.windows(2).all(|w| w[1] >= w[0])
        {
            return interp(&self.x, &self.t, x);
        }
        let (i, j) = if x < self.x[0] {
            (0, 1)
        } else {
            (n - 2, n - 1)
        };
        let v = (self.x[j] - self.x[i]) / (self.t[j] - self.t[i]);
        let (t0, x0) = if x < self.x[0] {
            (self.t[0], self.x[0])
        } else {
            (self.t[n - 1], self.x[n - 1])
        };
        t0 + (x - x0) / v
    }
}

/// The channels of each axle, by simulated channel name.
#[derive(Clone, Debug, Default, Serialize)]
pub struct AxleSets {
    /// Front axle's unsprung accelerations.
    pub front: Vec<String>,
    /// Rear axle's.
    pub rear: Vec<String>,
    /// The trailer axle's.
    pub trailer: Vec<String>,
}

/// The axle channels: the descriptor's lists, else the vertical channels named `wheel`
/// (or `unsprung`, `hub`) and `front`, `rear` or `trailer`.
pub fn axle_sets(spec: &PassageSpec, names: &[String]) -> AxleSets {
    let pick = |given: &Option<Vec<String>>, axle: &str, not: &[&str]| -> Vec<String> {
        if let Some(g) = given {
            return g.clone();
        }
        names
            .iter()
            .filter(|n| {
                let l = n.to_lowercase();
                ["wheel", "unsprung", "hub"].iter().any(|w| l.contains(w))
                    && l.contains(axle)
                    && !not.iter().any(|x| l.contains(x))
                    && !l.ends_with("_x")
                    && !l.ends_with("_y")
            })
            .cloned()
            .collect()
    };
    AxleSets {
        front: pick(&spec.front, "front", &["trailer"]),
        rear: pick(&spec.rear, "rear", &["trailer"]),
        trailer: pick(&spec.trailer, "trailer", &[]),
    }
}

/// Centred moving mean of `y` over `w` samples (shorter at the ends).
fn moving_mean(y: &[f64], w: usize) -> Vec<f64> {
    let n = y.len();
    let mut prefix = vec![0.0; n + 1];
    for k in 0..n {
        prefix[k + 1] = prefix[k] + y[k];
    }
    let h = w / 2;
    (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(h), (k + h + 1).min(n));
            (prefix[b] - prefix[a]) / (b - a) as f64
        })
        .collect()
}

/// Mean of `y` over the `w` samples before each one (fewer at the start): a trailing
/// mean, so a large event does not raise the level before it (a centred mean would
/// leak half its window ahead of the event and move the onset early by up to that).
fn trailing_mean(y: &[f64], w: usize) -> Vec<f64> {
    let mut prefix = vec![0.0; y.len() + 1];
    for k in 0..y.len() {
        prefix[k + 1] = prefix[k] + y[k];
    }
    (0..y.len())
        .map(|k| {
            let a = k.saturating_sub(w);
            let b = (k.max(1)).min(y.len());
            let a = a.min(b - 1);
            (prefix[b] - prefix[a]) / (b - a) as f64
        })
        .collect()
}

/// The combined envelope of `channels` sampled every `dt` [s].
pub fn envelope(channels: &[&[f64]], dt: f64) -> Vec<f64> {
    let n = channels.iter().map(|c| c.len()).min().unwrap_or(0);
    let mut p = vec![0.0; n];
    let wd = ((DETREND_S / dt).round() as usize).max(3);
    for c in channels {
        let m = trailing_mean(&c[..n], wd);
        for k in 0..n {
            p[k] += (c[k] - m[k]).powi(2);
        }
    }
    let nc = channels.len().max(1) as f64;
    p.iter_mut().for_each(|v| *v /= nc);
    let ws = ((SMOOTH_S / dt).round() as usize).max(1);
    moving_mean(&p, ws).into_iter().map(f64::sqrt).collect()
}

fn median(v: &[f64]) -> f64 {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if s.is_empty() {
        return f64::NAN;
    }
    s.sort_by(f64::total_cmp);
    s[s.len() / 2]
}

/// An onset found in an envelope.
#[derive(Clone, Copy, Debug)]
pub struct Onset {
    /// Onset time [s].
    pub time_s: f64,
    /// Time of the envelope's peak [s].
    pub peak_s: f64,
    /// Peak over the median of the envelope.
    pub snr: f64,
}

/// The onset of the largest event of `env` (times `t`) inside [`lo`, `hi`]; the noise is
/// the median over `noise` (indices); dips shorter than `quiet_s` [s] are bridged. An
/// error when the peak is not `snr_min` above the noise or the event runs into the
/// window's start.
pub fn onset(
    t: &[f64],
    env: &[f64],
    [lo, hi]: [f64; 2],
    noise: &[f64],
    snr_min: f64,
    quiet_s: f64,
) -> Result<Onset, OnsetError> {
    let idx: Vec<usize> = (0..env.len())
        .filter(|&k| t[k] >= lo && t[k] <= hi)
        .collect();
    let (Some(&first), Some(_)) = (idx.first(), idx.last()) else {
        return Err(OnsetError::EmptyWindow { lo, hi });
    };
    let peak = idx
        .iter()
        .copied()
        .max_by(|&a, &b| env[a].total_cmp(&env[b]))
        .unwrap_or(first);
    let n0 = median(noise).max(1e-300);
    let snr = env[peak] / n0;
    if snr.is_nan() || snr < snr_min {
        return Err(OnsetError::BelowNoise {
            peak: env[peak],
            peak_s: t[peak],
            snr,
            noise: n0,
            snr_min,
        });
    }
    let thr = (4.0 * n0).max(0.05 * env[peak]);
    let mut above = peak;
    let mut k = peak;
    while k > first {
        k -= 1;
        if env[k] > thr {
            above = k;
        } else if t[above] - t[k] > quiet_s {
            break;
        }
    }
    if k == first && env[first] > thr {
        return Err(OnsetError::RunsIntoWindow {
            peak_s: t[peak],
            lo,
        });
    }
    let time_s = if above > 0 && env[above] > env[above - 1] {
        let a = above - 1;
        t[a] + (thr - env[a]) / (env[above] - env[a]) * (t[above] - t[a])
    } else {
        t[above]
    };
    Ok(Onset {
        time_s,
        peak_s: t[peak],
        snr,
    })
}

/// The passage as found.
#[derive(Clone, Debug, Serialize)]
pub struct Passage {
    /// Onset of the front axle's event (detector time, recording's clock) [s].
    pub front_onset_s: f64,
    /// The front axle's envelope peak over its noise.
    pub snr: f64,
    /// Onset of the rear axle's event [s].
    pub rear_onset_s: Option<f64>,
    /// Onset of the trailer axle's event [s].
    pub trailer_onset_s: Option<f64>,
    /// Distance travelled between the front and rear onsets [m].
    pub implied_wheelbase_m: Option<f64>,
    /// Distance travelled between the front and trailer-axle onsets [m].
    pub implied_trailer_axle_m: Option<f64>,
    /// The channels used.
    pub axles: AxleSets,
}

/// The channels of `names` in `channels` as slices (the missing ones are skipped).
fn slices<'a>(channels: &'a BTreeMap<String, Vec<f64>>, names: &[String]) -> Vec<&'a [f64]> {
    names
        .iter()
        .filter_map(|n| channels.get(n).map(|v| v.as_slice()))
        .collect()
}

/// Onset of the front axle's event in a uniformly sampled set of channels (`t`), within
/// `window`, driven at `speed_mps` (NaN: unknown), or an error saying why none is visible.
pub fn front_onset(
    t: &[f64],
    channels: &BTreeMap<String, Vec<f64>>,
    front: &[String],
    window: Option<[f64; 2]>,
    speed_mps: f64,
) -> Result<Onset, OnsetError> {
    let ch = slices(channels, front);
    if ch.is_empty() || t.len() < 10 {
        return Err(OnsetError::NoChannel {
            front: front.to_vec(),
        });
    }
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    let env = envelope(&ch, dt);
    let w = window.unwrap_or([t[0], t[t.len() - 1]]);
    onset(t, &env, w, &env, SNR_MIN, quiet_s(speed_mps))
}

/// Finds the passage: the front axle, then the rear and trailer axles where the
/// wheelbase (`axles`: rear and trailer axle behind the front one [m]) puts them.
pub fn detect(
    t: &[f64],
    channels: &BTreeMap<String, Vec<f64>>,
    sets: &AxleSets,
    track: &Track,
    axles: (Option<f64>, Option<f64>),
    window: Option<[f64; 2]>,
    notes: &mut Vec<String>,
) -> Result<Passage, PassageError> {
    // The mean speed over the search: it scales the dips bridged.
    let [lo, hi] = window.unwrap_or([t[0], t[t.len() - 1]]);
    let speed = (track.position(hi) - track.position(lo)) / (hi - lo);
    let front = front_onset(t, channels, &sets.front, window, speed).map_err(|onset| {
        PassageError::NotVisible {
            front: sets.front.clone(),
            onset,
        }
    })?;
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    let x0 = track.position(front.time_s);
    let mut later = |names: &[String],
                     dist: Option<f64>,
                     what: &str|
     -> (Option<f64>, Option<f64>) {
        let ch = slices(channels, names);
        let Some(d) = dist else {
            if !ch.is_empty() {
                notes.push(format!(
                    "{what}: distance from the front axle unknown, passage not checked"
                ));
            }
            return (None, None);
        };
        if ch.is_empty() {
            return (None, None);
        }
        let env = envelope(&ch, dt);
        let expect = track.time_at(x0 + d);
        let delay = expect - front.time_s;
        let (lo, hi) = (
            front.time_s + (1.0 - REAR_WINDOW) * delay,
            expect + REAR_WINDOW * delay,
        );
        // The noise before the front axle's event: the rear channels already see it.
        let quiet: Vec<f64> = (0..env.len())
            .filter(|&k| t[k] < front.time_s)
            .map(|k| env[k])
            .collect();
        let noise = if quiet.len() >= 10 {
            quiet
        } else {
            env.clone()
        };
        let v = d / delay;
        match onset(t, &env, [lo, hi], &noise, SNR_MIN, quiet_s(v)) {
            Ok(o) => {
                let implied = track.position(o.time_s) - x0;
                if (implied / d - 1.0).abs() > 0.1 {
                    notes.push(format!(
                        "{what}: passage at {:.3} s implies {implied:.3} m from the front axle, the vehicle has {d:.3} m: check the speed",
                        o.time_s
                    ));
                }
                (Some(o.time_s), Some(implied))
            }
            Err(e) => {
                notes.push(format!("{what}: passage not found near {expect:.3} s: {e}"));
                (None, None)
            }
        }
    };
    let (rear, wb) = later(&sets.rear, axles.0, "rear axle");
    let (trailer, ta) = later(&sets.trailer, axles.1, "trailer axle");
    Ok(Passage {
        front_onset_s: front.time_s,
        snr: front.snr,
        rear_onset_s: rear,
        trailer_onset_s: trailer,
        implied_wheelbase_m: wb,
        implied_trailer_axle_m: ta,
        axles: sets.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tracks_integrate_and_invert() {
        let t: Vec<f64> = (0..=100).map(|k| k as f64 * 0.01).collect();
        let v: Vec<f64> = t.iter().map(|t| 10.0 + 2.0 * t).collect();
        let tr = Track::from_speed(&t, &v);
        assert!((tr.position(1.0) - 11.0).abs() < 1e-9);
        assert!((tr.time_at(11.0) - 1.0).abs() < 1e-9);
        let c = Track::constant(5.0);
        assert!((c.time_at(c.position(0.3) + 1.0) - 0.5).abs() < 1e-12);
    }
}
