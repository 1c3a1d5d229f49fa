//! Palmgren-Miner damage and damage-equivalent loads for a power-law S-N (or load-life)
//! curve N(S) = N_ref (S_ref / S)^m (Basquin form; IIW recommendations, Hobbacher 2008,
//! chapter 3, with S_ref = FAT at N_ref = 2e6 and m = 3). Miner's rule (Miner 1945,
//! J. Appl. Mech. 12, A159) sums n_i / N(S_i):
//!
//! D = sum n_i (S_i / S_ref)^m / N_ref.
//!
//! The damage-equivalent load is the constant range that, repeated N_eq times, does the
//! same damage on any curve of slope m (no knee, no endurance limit):
//!
//! DEL = (sum n_i S_i^m / N_eq)^(1/m).
//!
//! Ranges, not amplitudes: S is a range throughout, as IIW's FAT is a stress range.

use super::rainflow::Cycle;
use super::{positive, DurabilityError};

/// A power-law S-N or load-life curve through (N_ref, S_ref) with slope m.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SnCurve {
    /// Inverse slope m of log N against log S.
    pub m: f64,
    /// Range the curve allows `n_ref` times (signal unit; IIW: FAT in MPa).
    pub s_ref: f64,
    /// Cycles to failure at `s_ref`.
    pub n_ref: f64,
}

impl SnCurve {
    /// A curve of slope `m` through (`n_ref`, `s_ref`); each must be finite and > 0.
    pub fn new(m: f64, s_ref: f64, n_ref: f64) -> Result<SnCurve, DurabilityError> {
        Ok(SnCurve {
            m: positive("m", m)?,
            s_ref: positive("s_ref", s_ref)?,
            n_ref: positive("n_ref", n_ref)?,
        })
    }

    /// Cycles to failure at range `s` (infinite at 0).
    pub fn cycles_to_failure(&self, s: f64) -> f64 {
        self.n_ref * (self.s_ref / s).powf(self.m)
    }
}

/// Miner's damage sum of `cycles` on `curve`.
pub fn damage(cycles: &[Cycle], curve: &SnCurve) -> f64 {
    cycles
        .iter()
        .map(|c| c.count * (c.range / curve.s_ref).powf(curve.m))
        .sum::<f64>()
        / curve.n_ref
}

/// The damage-equivalent range of `cycles` at `n_eq` cycles for slope `m`.
pub fn del(cycles: &[Cycle], m: f64, n_eq: f64) -> Result<f64, DurabilityError> {
    let m = positive("m", m)?;
    let n_eq = positive("n_eq", n_eq)?;
    let sum: f64 = cycles.iter().map(|c| c.count * c.range.powf(m)).sum();
    Ok((sum / n_eq).powf(1.0 / m))
}
