//! Dominant frequencies of a channel: the body bounce and the wheel hop, the peaks of its
//! amplitude spectrum in two bands.
//!
//! The curve (mean removed) is Hann-windowed and zero-padded to at least eight times its
//! length and a 0.01 Hz bin (realfft); the largest bin inside a band, refined by a
//! parabola through the log-magnitudes of it and its neighbours, is the band's dominant
//! frequency. A maximum on the band's edge is no peak (`None`). On a transient of a few
//! seconds the resolution is coarse (a 2 s window: 0.5 Hz between independent bins), the
//! refined peak is good to a small fraction of that for a single dominant mode.

use realfft::RealFftPlanner;
use serde::Serialize;

/// Body modes (bounce and pitch of car bodies, trailer bounce up to ~5 Hz) [Hz].
pub const BODY_BAND_HZ: [f64; 2] = [0.5, 6.0];
/// Wheel hop of cars and light trucks [Hz].
pub const WHEEL_BAND_HZ: [f64; 2] = [6.0, 30.0];

/// The dominant frequencies of one curve.
#[derive(Clone, Copy, Debug, Default, Serialize, PartialEq)]
pub struct Dominant {
    /// Peak in [`BODY_BAND_HZ`] [Hz].
    pub body_hz: Option<f64>,
    /// Peak in [`WHEEL_BAND_HZ`] [Hz].
    pub wheel_hz: Option<f64>,
}

/// Amplitude spectrum of `y` sampled every `dt` [s]: (bin width [Hz], magnitudes).
pub fn amplitude(y: &[f64], dt: f64) -> (f64, Vec<f64>) {
    let n = y.len();
    if n < 4 || dt.is_nan() || dt <= 0.0 {
        return (f64::NAN, Vec::new());
    }
    let mean = y.iter().sum::<f64>() / n as f64;
    let min_len = (8 * n).max((1.0 / (0.01 * dt)).ceil() as usize);
    let len = min_len.next_power_of_two();
    let mut buf = vec![0.0; len];
    for (k, v) in y.iter().enumerate() {
        let w = 0.5 - 0.5 * (2.0 * std::f64::consts::PI * k as f64 / (n - 1) as f64).cos();
        buf[k] = (v - mean) * w;
    }
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(len);
    let mut out = fft.make_output_vec();
    if fft.process(&mut buf, &mut out).is_err() {
        return (f64::NAN, Vec::new());
    }
    (
        1.0 / (len as f64 * dt),
        out.iter().map(|c| c.norm()).collect(),
    )
}

/// The dominant frequency of `y` (every `dt` s) inside `band` [Hz].
pub fn peak_in(y: &[f64], dt: f64, band: [f64; 2]) -> Option<f64> {
    let (df, mag) = amplitude(y, dt);
    peak_of(df, &mag, band)
}

fn peak_of(df: f64, mag: &[f64], band: [f64; 2]) -> Option<f64> {
    if mag.len() < 3 || df.is_nan() || df <= 0.0 {
        return None;
    }
    let lo = ((band[0] / df).ceil() as usize).max(1);
    let hi = ((band[1] / df).floor() as usize).min(mag.len() - 2);
    if hi <= lo + 1 {
        return None;
    }
    let k = (lo..=hi).max_by(|&a, &b| mag[a].total_cmp(&mag[b]))?;
    if k == lo || k == hi || mag[k] <= 0.0 {
        return None;
    }
    let l = |i: usize| mag[i].max(1e-300).ln();
    let (a, b, c) = (l(k - 1), l(k), l(k + 1));
    let den = a - 2.0 * b + c;
    let frac = if den < 0.0 {
        (0.5 * (a - c) / den).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    Some((k as f64 + frac) * df)
}

/// Body-bounce and wheel-hop peaks of `y`.
pub fn dominant(y: &[f64], dt: f64) -> Dominant {
    let (df, mag) = amplitude(y, dt);
    Dominant {
        body_hz: peak_of(df, &mag, BODY_BAND_HZ),
        wheel_hz: peak_of(df, &mag, WHEEL_BAND_HZ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_two_decaying_modes() {
        let dt = 1e-3;
        let y: Vec<f64> = (0..2500)
            .map(|k| {
                let t = k as f64 * dt;
                let w1 = 2.0 * std::f64::consts::PI * 1.3;
                let w2 = 2.0 * std::f64::consts::PI * 12.5;
                (-0.4 * t).exp() * (w1 * t).sin() + 0.5 * (-3.0 * t).exp() * (w2 * t).sin()
            })
            .collect();
        let d = dominant(&y, dt);
        assert!((d.body_hz.unwrap() - 1.3).abs() < 0.05, "{d:?}");
        assert!((d.wheel_hz.unwrap() - 12.5).abs() < 0.1, "{d:?}");
    }
}
