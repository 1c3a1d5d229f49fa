//! ISO 8608 random road: two seeded tracks with a power-law displacement PSD and a stated
//! left/right coherence, built as a two-track [`TrackProfile`] (linear between samples).
//!
//! **Spectrum** (ISO 8608:2016 as reproduced by Loprencipe & Zoccali 2017, J. Mod.
//! Transport. 25(1):24-33, doi:10.1007/s40534-017-0122-1; see `docs/roads.md`):
//! the one-sided displacement PSD is `Gd(n) = Gd(n0) (n / n0)^-w` with n0 = 0.1 cycles/m
//! and waviness w = 2 for the class table. Classes A..H have geometric-mean
//! `Gd(n0)` = 16, 64, 256, 1024, 4096, 16384, 65536, 262144 x 1e-6 m^3 (each 4x the one
//! before); a class spans from half to twice its mean (A: < 32e-6, B: 32e-6..128e-6,
//! C: 128e-6..512e-6, ...).
//!
//! **Synthesis**: a sum of harmonics at the frequencies n_k = k / L (k = 1..N/2, L the
//! length, N = L / dx samples) inside [n_min, n_max], each with amplitude
//! `A_k = sqrt(2 Gd(n_k) / L)` (its mean square A_k^2/2 is the PSD times the spacing
//! 1/L) and a uniform random phase; evaluated by one inverse real FFT (`realfft`), as in
//! the harmonic method of Cebon & Newland (1983) / Da Silva (2004). With the harmonics on
//! the FFT grid the profile is periodic over L and each track's periodogram equals
//! Gd(n_k) exactly; the randomness is in the phases only.
//!
//! **Coherence** (a stated model, not the isotropic one): the right track has the same
//! amplitudes and the phases of the left track shifted by `delta_k`, drawn uniformly in
//! [-a_k, a_k]. Its expected normalised cross-spectrum (coherency) is
//! `E[exp(i delta)] = sin(a_k) / a_k`, chosen equal to `gamma(n) = exp(-c n B)` (B the track
//! width, c `coherence_decay`), an exponential decay of the form of Davenport's (1961)
//! spatial coherence. The magnitude-squared coherence an estimator returns is gamma^2.
//!
//! **Randomness**: SplitMix64 (Steele, Lea & Flood 2014, the reference code by Vigna),
//! integer arithmetic only, so the stream is the same on every platform; uniform doubles
//! from its top 53 bits. Phases come in order k = 1, 2, ... (left phase, then shift).
//! Heights then go through `cos`/`sin` and an FFT, which may differ in the last bit
//! between platforms' maths libraries.
//!
//! Each track is shifted by a constant so that it starts (and, being periodic, ends) at
//! z = 0; a constant does not change the PSD. Outside [0, L] the road is flat at z = 0.

use std::f64::consts::PI;

use realfft::RealFftPlanner;
use serde::Deserialize;

use super::{RoadError, TrackProfile};
use crate::input::{InputError, Source};
use crate::path;

/// ISO 8608's reference spatial frequency n0 [cycles/m] (a definition of the standard).
pub const N0: f64 = 0.1;

/// Geometric-mean `Gd(n0)` [m^3] of ISO 8608 class `class` ('A'..='H'), else `None`.
pub fn class_gd_n0(class: char) -> Option<f64> {
    let i = "ABCDEFGH".find(class.to_ascii_uppercase())?;
    // Class A's mean is 16e-6 m^3; each class is 4 times (two octaves of Gd) the last.
    Some(16e-6 * 4f64.powi(i as i32))
}

/// Lower and upper limit of the class whose geometric mean is `gd_n0` (half and twice).
pub fn class_band(gd_n0: f64) -> (f64, f64) {
    (gd_n0 / 2.0, gd_n0 * 2.0)
}

/// What a random road is made of (all SI; frequencies in cycles/m).
#[derive(Clone, Debug, PartialEq)]
pub struct RandomSpec {
    /// The ISO class letter, if given by class.
    pub class: Option<char>,
    /// `Gd(n0)` [m^3].
    pub gd_n0: f64,
    /// Waviness w [-].
    pub waviness: f64,
    /// Length L [m].
    pub length: f64,
    /// Sample spacing [m].
    pub dx: f64,
    /// Seed of the SplitMix64 stream.
    pub seed: u64,
    /// Lowest and highest harmonic [cycles/m].
    pub n_min: f64,
    /// See `n_min`.
    pub n_max: f64,
    /// Lateral distance of the tracks [m].
    pub track_width: f64,
    /// c in gamma(n) = exp(-c n B) [-].
    pub coherence_decay: f64,
}

impl RandomSpec {
    /// The displacement PSD Gd(n) [m^3] the road is built to.
    pub fn gd(&self, n: f64) -> f64 {
        self.gd_n0 * (n / N0).powf(-self.waviness)
    }

    /// The stated left/right coherency gamma(n) (magnitude-squared coherence: its square).
    pub fn coherence(&self, n: f64) -> f64 {
        (-self.coherence_decay * n * self.track_width).exp()
    }

    /// Number of samples N (the road has N + 1 points, the last equal to the first).
    pub fn samples(&self) -> usize {
        (self.length / self.dx).round() as usize
    }

    /// Builds the two tracks (x, left, right), x = 0, dx, ..., L.
    pub fn tracks(&self) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let n = self.samples();
        let dx = self.length / n as f64;
        let mut rng = SplitMix64(self.seed);
        let mut planner = RealFftPlanner::<f64>::new();
        let ifft = planner.plan_fft_inverse(n);
        let mut left = ifft.make_input_vec();
        let mut right = ifft.make_input_vec();
        // Harmonic k sits in bin k; the inverse FFT sums X_k e^{2 pi i k j / N} over both
        // halves, so X_k = A_k / 2 e^{i phi} gives A_k cos(2 pi n_k x + phi).
        for k in 1..left.len() {
            let nk = k as f64 / self.length;
            let phi = 2.0 * PI * rng.uniform();
            let a = inverse_sinc(self.coherence(nk));
            let delta = a * (2.0 * rng.uniform() - 1.0);
            // The Nyquist bin of an even N must be real: leave it (and out-of-band) empty.
            if nk < self.n_min || nk > self.n_max || (n.is_multiple_of(2) && k == n / 2) {
                continue;
            }
            let amp = (2.0 * self.gd(nk) / self.length).sqrt() / 2.0;
            left[k] = realfft::num_complex::Complex::from_polar(amp, phi);
            right[k] = realfft::num_complex::Complex::from_polar(amp, phi + delta);
        }
        let mut zl = ifft.make_output_vec();
        let mut zr = ifft.make_output_vec();
        // Lengths match by construction (same plan), so the transform cannot fail.
        let ok =
            ifft.process(&mut left, &mut zl).is_ok() && ifft.process(&mut right, &mut zr).is_ok();
        debug_assert!(ok);
        let (l0, r0) = (zl[0], zr[0]);
        zl.iter_mut().for_each(|z| *z -= l0);
        zr.iter_mut().for_each(|z| *z -= r0);
        zl.push(0.0);
        zr.push(0.0);
        let x = (0..=n).map(|j| j as f64 * dx).collect();
        (x, zl, zr)
    }

    /// The road as a two-track profile (flat at 0 outside [0, L]).
    pub fn profile(&self) -> Result<TrackProfile, RoadError> {
        let (x, l, r) = self.tracks();
        TrackProfile::new(x, l, r, self.track_width, Some(0.0))
    }
}

/// a in [0, pi] with sin(a)/a = g (g in [0, 1]), by bisection (sin(a)/a falls monotonically).
fn inverse_sinc(g: f64) -> f64 {
    if g >= 1.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0f64, PI);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if mid.sin() / mid > g {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// SplitMix64 (Steele, Lea & Flood, OOPSLA 2014; constants of Vigna's reference code).
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) from the top 53 bits.
    fn uniform(&mut self) -> f64 {
        (self.next() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// `[road] kind = "random"` of a road file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RandomToml {
    #[serde(default)]
    class: Option<String>,
    #[serde(default)]
    gd_n0_m3: Option<f64>,
    #[serde(default)]
    waviness: Option<f64>,
    length_m: f64,
    dx_m: f64,
    seed: u64,
    n_min_cycles_per_m: f64,
    n_max_cycles_per_m: f64,
    track_width_m: f64,
    coherence_decay: f64,
}

impl RandomToml {
    /// Checks every field (errors name the file, line and field) and builds the spec.
    pub(crate) fn build(&self, src: &Source) -> Result<RandomSpec, InputError> {
        let at = |k: &str| path!["road", k];
        let (class, gd_n0) = match (&self.class, self.gd_n0_m3) {
            (Some(c), None) => {
                let letter = c.chars().next().filter(|_| c.chars().count() == 1);
                match letter.and_then(|l| class_gd_n0(l).map(|g| (l, g))) {
                    Some((l, g)) => (Some(l.to_ascii_uppercase()), g),
                    None => {
                        return Err(src.error(
                            &at("class"),
                            format!("must be one ISO 8608 class letter A..H, got {c:?}"),
                        ))
                    }
                }
            }
            (None, Some(g)) => (None, src.positive(&at("gd_n0_m3"), g)?),
            _ => {
                return Err(src.error(
                    &at("class"),
                    "give either `class` (A..H) or `gd_n0_m3`, not both or neither",
                ))
            }
        };
        // ISO 8608's fitted waviness for the class table is 2.
        let waviness = match self.waviness {
            Some(w) => src.positive(&at("waviness"), w)?,
            None => 2.0,
        };
        let length = src.positive(&at("length_m"), self.length_m)?;
        let dx = src.positive(&at("dx_m"), self.dx_m)?;
        let n = (length / dx).round();
        if n < 16.0 || ((n * dx - length) / length).abs() > 1e-9 {
            return Err(src.error(
                &at("dx_m"),
                format!(
                    "length_m / dx_m must be a whole number of at least 16, got {}",
                    length / dx
                ),
            ));
        }
        if n > 1e8 {
            return Err(src.error(
                &at("dx_m"),
                format!("{n} samples is too many (at most 1e8)"),
            ));
        }
        let n_min = src.positive(&at("n_min_cycles_per_m"), self.n_min_cycles_per_m)?;
        let n_max = src.positive(&at("n_max_cycles_per_m"), self.n_max_cycles_per_m)?;
        if n_min < 1.0 / length {
            return Err(src.error(
                &at("n_min_cycles_per_m"),
                format!("must be at least 1 / length_m = {} cycles/m", 1.0 / length),
            ));
        }
        if n_max <= n_min || n_max > 0.5 / dx {
            return Err(src.error(
                &at("n_max_cycles_per_m"),
                format!(
                    "must lie above n_min_cycles_per_m and at most the Nyquist frequency 1 / (2 dx_m) = {} cycles/m",
                    0.5 / dx
                ),
            ));
        }
        Ok(RandomSpec {
            class,
            gd_n0,
            waviness,
            length,
            dx,
            seed: self.seed,
            n_min,
            n_max,
            track_width: src.positive(&at("track_width_m"), self.track_width_m)?,
            coherence_decay: src.non_negative(&at("coherence_decay"), self.coherence_decay)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_the_reference_stream() {
        // Rosetta Code "Pseudo-random numbers/Splitmix64": the first outputs for seed 1234567.
        let mut r = SplitMix64(1234567);
        assert_eq!(r.next(), 6457827717110365317);
        assert_eq!(r.next(), 3203168211198807973);
    }

    #[test]
    fn inverse_sinc_inverts() {
        for g in [0.0, 0.1, 0.5, 0.9, 0.999] {
            let a = inverse_sinc(g);
            assert!((a.sin() / a - g).abs() < 1e-12, "{g}");
        }
    }
}
