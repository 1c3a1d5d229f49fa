//! Modal damping ratios of a modal body: by frequency band, with per-mode overrides.
//!
//! The default bands are the common practice of multibody codes for flexible bodies
//! (MSC Adams' default CRATIO: 1 % of critical below 100 Hz, 10 % from 100 Hz to
//! 1 kHz, 100 % above): high modes the model cannot resolve anyway are damped out
//! instead of ringing at the integrator's expense.

use std::collections::BTreeMap;

use super::input::DampingIn;
use crate::input::{InputError, Source};
use crate::path;

/// Damping ratio zeta per mode: the first band with f < up_to_hz, else `above_ratio`;
/// `per_mode` (mode-table numbers, 1-based) wins over the bands.
#[derive(Clone, Debug, PartialEq)]
pub struct Damping {
    /// (up_to_hz, ratio), ascending.
    pub bands: Vec<(f64, f64)>,
    /// Damping ratio above the last band.
    pub above_ratio: f64,
    /// Damping ratio per mode-table number (1-based); overrides the bands.
    pub per_mode: BTreeMap<usize, f64>,
}

impl Default for Damping {
    fn default() -> Self {
        Damping {
            bands: vec![(100.0, 0.01), (1000.0, 0.10)],
            above_ratio: 1.0,
            per_mode: BTreeMap::new(),
        }
    }
}

impl Damping {
    /// The ratio of mode number `index` (mode table numbering) at `frequency_hz`.
    pub fn ratio(&self, index: usize, frequency_hz: f64) -> f64 {
        if let Some(&z) = self.per_mode.get(&index) {
            return z;
        }
        self.bands
            .iter()
            .find(|(up, _)| frequency_hz < *up)
            .map_or(self.above_ratio, |&(_, z)| z)
    }

    /// Reads the `[damping]` table; absent parts keep the defaults.
    pub fn from_input(src: &Source, d: &DampingIn) -> Result<Damping, InputError> {
        let mut out = Damping::default();
        if let Some(bands) = &d.band {
            out.bands.clear();
            let mut last = 0.0;
            for (i, b) in bands.iter().enumerate() {
                let up = src.positive(&path!["damping", "band", i, "up_to_hz"], b.up_to_hz)?;
                if up <= last {
                    return Err(src.error(
                        &path!["damping", "band", i, "up_to_hz"],
                        "bands must be in ascending order of up_to_hz",
                    ));
                }
                last = up;
                let z = src.non_negative(&path!["damping", "band", i, "ratio"], b.ratio)?;
                out.bands.push((up, z));
            }
        }
        if let Some(z) = d.above_ratio {
            out.above_ratio = src.non_negative(&path!["damping", "above_ratio"], z)?;
        }
        for (i, m) in d.mode.iter().enumerate() {
            if m.index <= 6 {
                return Err(src.error(
                    &path!["damping", "mode", i, "index"],
                    "modes 1..6 are the rigid-body modes and have no damping",
                ));
            }
            let z = src.non_negative(&path!["damping", "mode", i, "ratio"], m.ratio)?;
            out.per_mode.insert(m.index, z);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_bands() {
        let d = Damping::default();
        assert_eq!(d.ratio(7, 50.0), 0.01);
        assert_eq!(d.ratio(7, 317.0), 0.10);
        assert_eq!(d.ratio(7, 1155.6), 1.0);
        let mut d = d;
        d.per_mode.insert(7, 0.02);
        assert_eq!(d.ratio(7, 317.0), 0.02);
        assert_eq!(d.ratio(8, 317.0), 0.10);
    }
}
