//! Power spectral density by Welch's method: Hann-windowed segments with half overlap,
//! each less its mean, averaged periodograms, one-sided (the report's spectra).

use realfft::RealFftPlanner;

/// A one-sided power spectral density.
#[derive(Clone, Debug, PartialEq)]
pub struct Psd {
    /// Frequencies [Hz], 0 to the Nyquist frequency.
    pub freq: Vec<f64>,
    /// Density at each frequency [unit²/Hz].
    pub density: Vec<f64>,
}

/// Segment length for `n` samples: the largest power of two up to `max_len` that gives
/// at least four half-overlapping segments (at least 16 samples).
pub fn segment_length(n: usize, max_len: usize) -> usize {
    let mut len = 16;
    while len * 2 <= max_len && (n.saturating_sub(len * 2)) / len + 1 >= 4 {
        len *= 2;
    }
    len
}

/// Welch PSD of `y` sampled at `fs` [Hz] with segments of `len` samples (a power of two
/// is fastest); `None` when `y` is shorter than one segment or holds a non-finite value.
pub fn welch(y: &[f64], fs: f64, len: usize) -> Option<Psd> {
    if len < 2 || y.len() < len || y.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(len);
    let window: Vec<f64> = (0..len)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / len as f64).cos())
        .collect();
    let w2: f64 = window.iter().map(|w| w * w).sum();
    let hop = len / 2;
    let mut input = fft.make_input_vec();
    let mut spectrum = fft.make_output_vec();
    let mut acc = vec![0.0; len / 2 + 1];
    let mut segments = 0;
    let mut start = 0;
    while start + len <= y.len() {
        let seg = &y[start..start + len];
        let mean = seg.iter().sum::<f64>() / len as f64;
        for ((x, v), w) in input.iter_mut().zip(seg).zip(&window) {
            *x = (v - mean) * w;
        }
        fft.process(&mut input, &mut spectrum).ok()?;
        for (a, c) in acc.iter_mut().zip(&spectrum) {
            *a += c.norm_sqr();
        }
        segments += 1;
        start += hop;
    }
    // One-sided: every bin but DC and Nyquist carries its negative-frequency twin.
    let scale = 1.0 / (fs * w2 * segments as f64);
    let last = acc.len() - 1;
    let density = acc
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let twice = if k == 0 || (k == last && len.is_multiple_of(2)) {
                1.0
            } else {
                2.0
            };
            a * scale * twice
        })
        .collect();
    let freq = (0..acc.len()).map(|k| k as f64 * fs / len as f64).collect();
    Some(Psd { freq, density })
}
