//! Power spectral densities for a validated run's page: fine enough in frequency to tell
//! body modes 1-2.5 Hz apart, and only over the band the data carry.
//!
//! A compared window lasts a few seconds; Welch's method with at least four segments
//! (the run report's) cuts a 2 s window at 500 Hz (a 50 km/h passage) into 256-sample
//! segments, 1.95 Hz apart, which puts bounce and pitch into one bin. Here a segment is the whole window up to
//! [`SEGMENT_S`] (Hann-windowed, mean removed; longer records are averaged over
//! half-overlapping segments of that length), zero-padded so the bins are at most
//! [`MAX_BIN_HZ`] apart. The resolution proper is 1 / segment length, said on the page.

use realfft::RealFftPlanner;

/// Longest segment [s]: 0.125 Hz resolution; longer records are averaged.
pub const SEGMENT_S: f64 = 8.0;
/// Widest bin drawn [Hz] (zero padding below the resolution of a short window).
pub const MAX_BIN_HZ: f64 = 0.25;

/// A one-sided power spectral density up to a band's top.
#[derive(Clone, Debug, PartialEq)]
pub struct Spectrum {
    /// Frequencies [Hz], from 0 up to the band's top.
    pub freq: Vec<f64>,
    /// Density [unit²/Hz] at each frequency.
    pub density: Vec<f64>,
    /// Segment length [s]: the resolution is its inverse.
    pub segment_s: f64,
    /// Segments averaged.
    pub segments: usize,
}

/// The density of `y` sampled at `fs` [Hz], bins up to `max_hz`; `None` for fewer than
/// 16 samples or a non-finite value.
pub fn density(y: &[f64], fs: f64, max_hz: f64) -> Option<Spectrum> {
    let n = y.len();
    if n < 16 || fs.is_nan() || fs <= 0.0 || y.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let len = n.min((SEGMENT_S * fs).round() as usize).max(16);
    let nfft = len
        .max((fs / MAX_BIN_HZ).ceil() as usize)
        .next_power_of_two();
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(nfft);
    // Periodic Hann window over the segment; the padding is zeros.
    let window: Vec<f64> = (0..len)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / len as f64).cos())
        .collect();
    let w2: f64 = window.iter().map(|w| w * w).sum();
    let mut input = fft.make_input_vec();
    let mut out = fft.make_output_vec();
    let bins = ((max_hz * nfft as f64 / fs).floor() as usize + 1).min(out.len());
    let mut acc = vec![0.0; bins];
    let (mut segments, mut start) = (0, 0);
    while start + len <= n {
        let seg = &y[start..start + len];
        let mean = seg.iter().sum::<f64>() / len as f64;
        input.iter_mut().for_each(|x| *x = 0.0);
        for ((x, v), w) in input.iter_mut().zip(seg).zip(&window) {
            *x = (v - mean) * w;
        }
        fft.process(&mut input, &mut out).ok()?;
        for (a, c) in acc.iter_mut().zip(&out) {
            *a += c.norm_sqr();
        }
        segments += 1;
        start += (len / 2).max(1);
    }
    // One-sided: every bin but DC and Nyquist carries its negative-frequency twin. Zero
    // padding keeps the scale: the window's energy is over the segment's samples.
    let scale = 1.0 / (fs * w2 * segments as f64);
    let nyquist = nfft / 2;
    let density = acc
        .iter()
        .enumerate()
        .map(|(k, a)| a * scale * if k == 0 || k == nyquist { 1.0 } else { 2.0 })
        .collect();
    Some(Spectrum {
        freq: (0..bins).map(|k| k as f64 * fs / nfft as f64).collect(),
        density,
        segment_s: len as f64 / fs,
        segments,
    })
}

/// The band both curves of a run carry [Hz]: the lower of the recording's and the
/// simulation's Nyquist frequencies and the acquisition low-pass's cut-off (each when
/// known, i.e. finite and positive).
pub fn band_hz(recording_hz: f64, simulation_hz: f64, cutoff_hz: f64) -> f64 {
    [0.5 * recording_hz, 0.5 * simulation_hz, cutoff_hz]
        .into_iter()
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold(f64::INFINITY, f64::min)
}
