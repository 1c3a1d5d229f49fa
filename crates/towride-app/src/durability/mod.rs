//! Durability: rainflow counting, Palmgren-Miner damage and damage-equivalent loads of a
//! load or stress history (`docs/durability.md`).
//!
//! - [`rainflow::turning_points`] reduces a history to its reversals (peaks and
//!   valleys), optionally through a hysteresis gate in the signal's unit;
//! - [`rainflow::count`] is the rainflow count of ASTM E1049-85 (reapproved 2017),
//!   section 5.4.4: the three-point method with the starting-point rule, the residue
//!   counted as half cycles; [`rainflow::RangeMeanMatrix`] bins the cycles;
//! - [`damage::SnCurve`] and [`damage::damage`] give the Palmgren-Miner sum
//!   D = sum n_i (S_i / S_ref)^m / N_ref for a power-law S-N (or load-life) curve,
//!   [`damage::del`] the damage-equivalent load DEL = (sum n_i S_i^m / N_eq)^(1/m);
//! - [`csv::read_column`] reads one column of any CSV with units in its header;
//! - [`iiw::IiwCurve`] is IIW's S-N curve of a weld detail (FAT, knee at 1e7) and
//!   [`fat_check`] the damage per passage of a stress point's signed fibre stresses;
//! - [`coupling`] the UN R55 D-value and test force beside a run's ball forces.
//!
//! Defaults ([`DEFAULT_M`], [`DEFAULT_N_REF`]) follow the IIW recommendations for
//! welded steel details (Hobbacher, IIW document IIW-1823-07, 2008, chapter 3: the
//! fatigue class FAT is the characteristic stress range at 2e6 cycles on an S-N curve
//! of slope m = 3 for normal stress ranges).

pub mod coupling;
pub mod csv;
pub mod damage;
pub mod iiw;
pub mod rainflow;

pub use damage::{damage, del, SnCurve};
pub use rainflow::{count, turning_points, Cycle, RangeMeanMatrix};

/// Default S-N slope: m = 3, IIW recommendations (Hobbacher 2008, chapter 3) for
/// normal stress ranges of welded steel details.
pub const DEFAULT_M: f64 = 3.0;

/// Default reference cycle count: 2e6, the count at which IIW defines its FAT classes
/// (Hobbacher 2008, chapter 3), so a DEL at 2e6 compares directly with a FAT value.
pub const DEFAULT_N_REF: f64 = 2.0e6;

/// What is wrong with a durability input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DurabilityError {
    /// A sample is NaN or infinite.
    #[error("sample {index} is not a finite number ({value})")]
    NotFinite {
        /// 0-based index of the sample.
        index: usize,
        /// The value.
        value: f64,
    },
    /// Too few samples to hold one reversal.
    #[error("{found} samples: rainflow counting needs at least 3")]
    TooShort {
        /// Samples given.
        found: usize,
    },
    /// A parameter out of its range.
    #[error("{name} = {value}: {why}")]
    Parameter {
        /// The parameter's name (`m`, `n_ref`, `gate`, ...).
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must be.
        why: &'static str,
    },
}

/// Checks that `value` is finite and positive.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, DurabilityError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(DurabilityError::Parameter {
            name,
            value,
            why: "must be a finite number > 0",
        })
    }
}

/// A run channel's durability figures, for `summary.json` (`docs/durability.md`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ChannelDurability {
    /// The channel (`hitch_fx`, ...).
    pub channel: String,
    /// Its unit (`N`, `N m`, `Pa`): that of the ranges and DELs.
    pub unit: String,
    /// Cycles counted (full plus half of the half cycles), gate 0.
    pub cycles: f64,
    /// Largest range counted (channel unit).
    pub largest_range: f64,
    /// S-N slope m of the DEL ([`DEFAULT_M`]).
    pub m: f64,
    /// Reference cycle count of the DEL ([`DEFAULT_N_REF`]).
    pub n_ref: f64,
    /// DEL at `n_ref` cycles (channel unit): the constant range that, applied `n_ref`
    /// times, does the damage of `n_ref` passages.
    pub del_at_n_ref: f64,
    /// Damage-equivalent range of one passage: DEL at one cycle (channel unit).
    pub del_per_passage: f64,
}

/// The durability figures of one channel of a run at the defaults; `None` when the
/// channel cannot be counted (fewer than 3 samples, a non-finite sample).
pub fn channel_block(channel: &str, unit: &str, values: &[f64]) -> Option<ChannelDurability> {
    let cycles = count(&turning_points(values, 0.0).ok()?);
    Some(ChannelDurability {
        channel: channel.to_string(),
        unit: unit.to_string(),
        cycles: rainflow::total_cycles(&cycles),
        largest_range: cycles.iter().map(|c| c.range).fold(0.0, f64::max),
        m: DEFAULT_M,
        n_ref: DEFAULT_N_REF,
        del_at_n_ref: del(&cycles, DEFAULT_M, DEFAULT_N_REF).ok()?,
        del_per_passage: del(&cycles, DEFAULT_M, 1.0).ok()?,
    })
}

/// A stress point's check against its IIW fatigue class over one passage, for
/// `summary.json` (`docs/durability.md`, "IIW check").
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FatCheck {
    /// The stress point (`hitch_stress_<point>_sx_f<k>` are its fibres).
    pub point: String,
    /// Its fatigue class [MPa] (flex file `fat_class_mpa`).
    pub fat_mpa: f64,
    /// The fibre (1..4) of largest damage.
    pub worst_fibre: usize,
    /// Largest signed-stress range at that fibre [MPa].
    pub largest_range_mpa: f64,
    /// Miner sum of one passage on the variable-amplitude IIW curve (worst fibre).
    pub damage_per_passage: f64,
    /// Passages to the allowable sum [`iiw::D_ALLOWABLE_STEEL`] (infinite: no damage).
    pub passages_to_allowable: f64,
}

/// The IIW check of a point with FAT `fat_pa` whose four fibres' signed stresses [Pa]
/// `fibres` gives; `None` when a fibre cannot be counted.
pub fn fat_check(point: &str, fat_pa: f64, fibres: &[Vec<f64>]) -> Option<FatCheck> {
    let curve = iiw::IiwCurve::variable_amplitude(fat_pa).ok()?;
    let mut worst = (0, 0.0, 0.0);
    for (k, y) in fibres.iter().enumerate() {
        let c = count(&turning_points(y, 0.0).ok()?);
        let d = curve.damage(&c);
        if k == 0 || d > worst.1 {
            worst = (k + 1, d, c.iter().map(|c| c.range).fold(0.0, f64::max));
        }
    }
    Some(FatCheck {
        point: point.to_string(),
        fat_mpa: fat_pa / 1e6,
        worst_fibre: worst.0,
        largest_range_mpa: worst.2 / 1e6,
        damage_per_passage: worst.1,
        passages_to_allowable: iiw::D_ALLOWABLE_STEEL / worst.1,
    })
}
