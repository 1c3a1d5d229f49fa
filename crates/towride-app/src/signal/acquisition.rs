//! An instrument's acquisition chain: the analog low-pass a data acquisition puts in front
//! of its sampler, modelled as a digital Butterworth low-pass
//! ([`super::butterworth`]) run causally, so its phase lag is reproduced.
//!
//! A scene declares one (`[acquisition]`, default [`AcqFilter::THESIS`]: the thesis's
//! fourth-order 100 Hz low-pass) and a run reports its sensor, force and deflection
//! channels through it beside the raw ones ([`band_limit`]); validation puts a
//! simulation through a measured run's ([`crate::validate::filter`]).
//!
//! To stay close to the analog filter the signal is filtered on a uniform grid of at
//! least 40 fc: a run sampled at 1 kHz is interpolated linearly onto 4 kHz for a 100 Hz
//! filter (below that the bilinear transform's warping bends the phase near fc).

use super::butterworth::{interp, Butterworth};
use crate::error::SignalError;

/// The acquisition low-pass: a Butterworth of `order` with -3 dB at `cutoff_hz`,
/// applied causally.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AcqFilter {
    /// Filter order.
    pub order: usize,
    /// -3 dB cut-off frequency [Hz].
    pub cutoff_hz: f64,
}

/// Finest grid over cutoff: the filter runs at a rate of at least this times fc.
pub const GRID_OVER_CUTOFF: f64 = 40.0;

impl AcqFilter {
    /// The thesis's measurement chain (section 2): fourth-order Butterworth, 100 Hz.
    pub const THESIS: AcqFilter = AcqFilter {
        order: 4,
        cutoff_hz: 100.0,
    };

    /// The rate the filter runs at for samples at `native_hz`: max(native, 40 fc).
    pub fn grid_rate(&self, native_hz: f64) -> f64 {
        native_hz.max(GRID_OVER_CUTOFF * self.cutoff_hz)
    }

    /// The suffix of a band-limited channel's name: `_lp100` for a 100 Hz low-pass
    /// (`acc_hitch_z_lp100`).
    pub fn suffix(&self) -> String {
        format!("_lp{}", self.cutoff_hz)
    }

    /// In words: `4th-order Butterworth low-pass at 100 Hz, causal`.
    pub fn describe(&self) -> String {
        let th = match self.order {
            1 => "1st".to_string(),
            2 => "2nd".to_string(),
            3 => "3rd".to_string(),
            n => format!("{n}th"),
        };
        format!(
            "{th}-order Butterworth low-pass at {} Hz, causal",
            self.cutoff_hz
        )
    }
}

/// `y` (sampled at the increasing times `t`, uniform but perhaps for the last) through
/// the low-pass `f`, read at the same times: interpolated linearly onto a uniform grid
/// from `t[0]` at the smallest integer multiple of `native_hz` that reaches
/// [`AcqFilter::grid_rate`] (so every uniform sample time is a grid point), filtered
/// causally from the steady state of `y[0]`, and read back (linearly between grid points
/// where a time is not one).
pub fn band_limit(
    f: &AcqFilter,
    t: &[f64],
    y: &[f64],
    native_hz: f64,
) -> Result<Vec<f64>, SignalError> {
    let n = t.len().min(y.len());
    if n < 2 {
        return Ok(y[..n].to_vec());
    }
    let m = (f.grid_rate(native_hz) / native_hz).ceil().max(1.0);
    let rate = m * native_hz;
    let lp = Butterworth::low_pass(f.order, f.cutoff_hz, rate)?;
    let dt = 1.0 / rate;
    // The grid covers the last sample (one point past it when it is off the grid).
    let span = (t[n - 1] - t[0]) * rate;
    let points = (span - 1e-9).ceil().max(0.0) as usize + 1;
    let grid: Vec<f64> = (0..points).map(|k| t[0] + k as f64 * dt).collect();
    let u: Vec<f64> = grid.iter().map(|&tq| interp(&t[..n], &y[..n], tq)).collect();
    let v = lp.apply(&u);
    Ok(t[..n].iter().map(|&tq| interp(&grid, &v, tq)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_words() {
        assert_eq!(AcqFilter::THESIS.suffix(), "_lp100");
        let f = AcqFilter {
            order: 2,
            cutoff_hz: 62.5,
        };
        assert_eq!(f.suffix(), "_lp62.5");
        assert_eq!(f.describe(), "2nd-order Butterworth low-pass at 62.5 Hz, causal");
        assert_eq!(AcqFilter::THESIS.grid_rate(1000.0), 4000.0);
        assert_eq!(AcqFilter::THESIS.grid_rate(5000.0), 5000.0);
    }

    #[test]
    fn a_constant_passes_unchanged_and_short_signals_are_kept() {
        let t: Vec<f64> = (0..50).map(|k| k as f64 * 1e-3).collect();
        let y = vec![3.5; 50];
        let b = band_limit(&AcqFilter::THESIS, &t, &y, 1000.0).unwrap();
        assert!(b.iter().all(|v| (v - 3.5).abs() < 1e-12), "{b:?}");
        assert_eq!(
            band_limit(&AcqFilter::THESIS, &[0.0], &[2.0], 1000.0).unwrap(),
            vec![2.0]
        );
    }
}
