//! The IIW S-N curve of a weld detail in the nominal-stress approach and the
//! Palmgren-Miner damage of signed nominal stress ranges on it (`docs/durability.md`,
//! "IIW check").
//!
//! Source: Hobbacher, Recommendations for Fatigue Design of Welded Joints and
//! Components, IIW document IIW-2259-15 (2nd ed., Springer 2016; the earlier
//! IIW-1823-07 of 2008 the same in these points), chapter 3 "fatigue resistance",
//! section 3.2 (nominal stress, the FAT classes) and the S-N curves of its
//! Fig. (3.2)-1: for normal stress, N = 2e6 (FAT / dsigma)^3 down to the knee at
//! N = 1e7; below the knee slope m = 22 for constant amplitude (IIW-2259-15 replaced
//! the horizontal fatigue limit of 2008 by it) and, for variable amplitude, slope
//! m = 5 (Haibach's modification of Miner's rule), chapter 4 (assessment of variable
//! amplitude loading, Palmgren-Miner with the damage sum D = 0.5 for steel). Section
//! numbers as we recall them; the curve's shape (2e6, 1e7, 3, 5, 22) is the one quoted
//! across IIW-based codes (e.g. Hobbacher, Int. J. Fatigue 31 (2009) 50-58).
//!
//! The stress ranges are those of one fibre's signed normal stress (rainflow of
//! `hitch_stress_<point>_sx_f<k>`): a range is a difference of two signed stresses,
//! which the von Mises magnitude (always >= 0) would fold.

use super::rainflow::Cycle;
use super::{positive, DurabilityError};

/// Cycles at which IIW defines a FAT class (IIW-2259-15, section 3.2).
pub const N_FAT: f64 = 2.0e6;
/// Cycles at the knee of IIW's normal-stress S-N curves (IIW-2259-15, chapter 3).
pub const N_KNEE: f64 = 1.0e7;
/// Slope above the knee for normal stress ranges (IIW-2259-15, chapter 3).
pub const M_ABOVE: f64 = 3.0;
/// Slope below the knee for variable amplitude (IIW-2259-15: Haibach's m = 5).
pub const M_BELOW_VARIABLE: f64 = 5.0;
/// Slope below the knee for constant amplitude (IIW-2259-15: m = 22).
pub const M_BELOW_CONSTANT: f64 = 22.0;
/// Allowable Miner sum for steel under variable amplitude (IIW-2259-15, chapter 4).
pub const D_ALLOWABLE_STEEL: f64 = 0.5;

/// An IIW S-N curve for normal stress ranges: FAT at 2e6 cycles, slope 3 to the knee
/// at 1e7, `m_below` beyond.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct IiwCurve {
    /// Fatigue class: the stress range allowed 2e6 times [Pa].
    pub fat_pa: f64,
    /// Slope beyond the knee ([`M_BELOW_VARIABLE`] or [`M_BELOW_CONSTANT`]).
    pub m_below: f64,
}

impl IiwCurve {
    /// The curve for variable amplitude loading (a road passage's spectrum).
    pub fn variable_amplitude(fat_pa: f64) -> Result<IiwCurve, DurabilityError> {
        Ok(IiwCurve {
            fat_pa: positive("fat", fat_pa)?,
            m_below: M_BELOW_VARIABLE,
        })
    }

    /// The curve for constant amplitude loading.
    pub fn constant_amplitude(fat_pa: f64) -> Result<IiwCurve, DurabilityError> {
        Ok(IiwCurve {
            fat_pa: positive("fat", fat_pa)?,
            m_below: M_BELOW_CONSTANT,
        })
    }

    /// The range at the knee: FAT (2e6 / 1e7)^(1/3) = 0.585 FAT.
    pub fn knee_pa(&self) -> f64 {
        self.fat_pa * (N_FAT / N_KNEE).powf(1.0 / M_ABOVE)
    }

    /// Cycles to failure at range `s` [Pa] (infinite at 0).
    pub fn cycles_to_failure(&self, s: f64) -> f64 {
        let knee = self.knee_pa();
        if s >= knee {
            N_FAT * (self.fat_pa / s).powf(M_ABOVE)
        } else {
            N_KNEE * (knee / s).powf(self.m_below)
        }
    }

    /// Miner's damage sum of `cycles` (ranges in Pa).
    pub fn damage(&self, cycles: &[Cycle]) -> f64 {
        cycles
            .iter()
            .filter(|c| c.range > 0.0)
            .map(|c| c.count / self.cycles_to_failure(c.range))
            .sum()
    }
}
