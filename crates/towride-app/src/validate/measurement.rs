//! A recorded run in SI units: the descriptor's columns read ([`super::csv_reader`]),
//! converted with their units, gains and signs, gravity removed where asked, the speed
//! channel in m/s, and the samples at a sensor's range marked as clipped.

use std::collections::BTreeMap;
use std::path::PathBuf;

use towride_mbs::input::InputError;

use super::csv_reader::{err, read_table_with, TimeSpec};
use super::descriptor::{AcqFilter, Descriptor};
use super::timebase::TimeBase;
use super::units::{SpeedUnit, Unit};
use super::G_MPS2;
use crate::signal::butterworth::Butterworth;

/// A sample is clipped when it reaches this share of the sensor's range.
pub const CLIP_SHARE: f64 = 0.999;

/// Ranges of accelerometers as sold [g]: a flat top at one of these is a clipped sensor.
pub const STANDARD_RANGES_G: [f64; 16] = [
    1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 16.0, 20.0, 25.0, 30.0, 50.0, 100.0, 200.0, 500.0,
];

/// A recorded run in SI units, keyed by simulated channel name.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// The CSV file read.
    pub file: PathBuf,
    /// Sample times on the recording's clock [s].
    pub time_s: Vec<f64>,
    /// Channels in SI units (gain, sign, unit and gravity applied), by simulated name.
    pub channels: BTreeMap<String, Vec<f64>>,
    /// Sample rate [Hz].
    pub rate_hz: f64,
    /// How the sample times were found.
    pub time_base: TimeBase,
    /// The vehicle-speed channel [m/s], if recorded.
    pub speed_mps: Option<Vec<f64>>,
    /// Per channel with a range: which samples are clipped.
    pub clipped: BTreeMap<String, Vec<bool>>,
    /// One line per repair or inference made while reading.
    pub notes: Vec<String>,
}

impl Measurement {
    /// Clipped samples of `channel` (0 without a range).
    pub fn clipped_samples(&self, channel: &str) -> usize {
        self.clipped
            .get(channel)
            .map_or(0, |m| m.iter().filter(|c| **c).count())
    }
}

/// The standard range a channel's flat top sits at, if it looks clipped: its largest
/// magnitude [g] repeated in a run of at least three samples within 1 % of a range.
pub fn flat_top_range(values_g: &[f64]) -> Option<f64> {
    let top = values_g.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let at_top = |v: &f64| v.abs() >= top * (1.0 - 1e-9);
    let run = values_g.windows(3).any(|w| w.iter().all(at_top));
    if !run || top == 0.0 {
        return None;
    }
    STANDARD_RANGES_G
        .iter()
        .copied()
        .find(|r| (top / r - 1.0).abs() < 0.01)
}

/// Reads the CSV of a descriptor and converts every channel to SI.
pub fn read_measurement(desc: &Descriptor) -> Result<Measurement, InputError> {
    let mut names: Vec<&str> = desc.channels.iter().map(|c| c.column.as_str()).collect();
    if let Some(s) = &desc.speed {
        names.push(&s.column);
    }
    let time = TimeSpec {
        column: Some(desc.time_column.clone()),
        rate_hz: desc.sample_rate_hz,
        fall_back_to_rate: !desc.time_column_given,
    };
    let mut table = read_table_with(&desc.data, &time, &names)?;
    let unit_line = table.units_line.unwrap_or(table.header_line);
    let mut channels = BTreeMap::new();
    let mut clipped = BTreeMap::new();
    let mut notes = std::mem::take(&mut table.notes);
    for (k, spec) in desc.channels.iter().enumerate() {
        let header_unit = match &table.units[k] {
            None => None,
            Some(u) => Some(Unit::parse(u).ok_or_else(|| {
                err(
                    &table.file,
                    Some(unit_line),
                    None,
                    &spec.column,
                    format!("unit `{u}` is not m/s^2, g or gn"),
                )
            })?),
        };
        let unit = match (spec.unit, header_unit) {
            (Some(d), Some(h)) if d != h => {
                return Err(err(
                    &table.file,
                    Some(unit_line),
                    None,
                    &spec.column,
                    format!(
                        "header says {} but the descriptor {} says {}",
                        h.label(),
                        desc.path.display(),
                        d.label()
                    ),
                ))
            }
            (Some(u), _) | (None, Some(u)) => u,
            (None, None) => return Err(err(
                &table.file,
                Some(table.header_line),
                None,
                &spec.column,
                "no unit in the header (`name [unit]`), a units row nor the descriptor's channel"
                    .into(),
            )),
        };
        // The sensor's reading in g, gravity included: what its range applies to.
        let reading_g: Vec<f64> = table.columns[k]
            .iter()
            .map(|x| x * spec.gain * unit.to_si() / G_MPS2)
            .collect();
        match spec.range_g {
            Some(r) => {
                let mask: Vec<bool> = reading_g
                    .iter()
                    .map(|v| v.abs() >= CLIP_SHARE * r)
                    .collect();
                let n = mask.iter().filter(|c| **c).count();
                if n > 0 {
                    notes.push(format!(
                        "{}: {n} sample(s) at the sensor's range of {r} g are clipped and left out of the rating",
                        spec.column
                    ));
                }
                clipped.insert(spec.simulated.clone(), mask);
            }
            None => {
                if let Some(r) = flat_top_range(&reading_g) {
                    notes.push(format!(
                        "{}: a flat top at {r} g looks like a clipped sensor; give the channel's range_g to leave those samples out",
                        spec.column
                    ));
                }
            }
        }
        let f = unit.to_si() * spec.gain * spec.sign;
        let g = if spec.remove_gravity { G_MPS2 } else { 0.0 } + spec.offset_g * G_MPS2;
        channels.insert(
            spec.simulated.clone(),
            table.columns[k].iter().map(|x| x * f - g).collect(),
        );
    }
    let speed_mps = match &desc.speed {
        None => None,
        Some(s) => {
            let k = desc.channels.len();
            let header_unit = table.units[k].as_ref().map(|u| {
                SpeedUnit::parse(u).ok_or_else(|| {
                    err(
                        &table.file,
                        Some(unit_line),
                        None,
                        &s.column,
                        format!("unit `{u}` is not km/h, m/s or mph"),
                    )
                })
            });
            let header_unit = header_unit.transpose()?;
            let unit = match (s.unit, header_unit) {
                (Some(d), Some(h)) if d != h => {
                    return Err(err(
                        &table.file,
                        Some(unit_line),
                        None,
                        &s.column,
                        format!(
                            "header says {} but the descriptor says {}",
                            h.label(),
                            d.label()
                        ),
                    ))
                }
                (Some(u), _) | (None, Some(u)) => u,
                (None, None) => {
                    return Err(err(
                        &table.file,
                        Some(table.header_line),
                        None,
                        &s.column,
                        "the speed channel has no unit (header, units row or [speed] unit)".into(),
                    ))
                }
            };
            Some(table.columns[k].iter().map(|v| v * unit.to_si()).collect())
        }
    };
    Ok(Measurement {
        file: table.file,
        rate_hz: table.time_base.rate_hz,
        time_s: table.time_s,
        channels,
        time_base: table.time_base,
        speed_mps,
        clipped,
        notes,
    })
}

/// Passes the recording through the acquisition low-pass as well (for a logger sampling
/// far above the band compared, whose own anti-alias filter is not known), then keeps
/// every q-th sample where the rate exceeds ten times the cut-off q >= 2 times. The filter
/// spreads a clipped sample over its settling time (2 / cut-off), which is marked clipped
/// too.
pub fn condition(m: &mut Measurement, f: AcqFilter) -> Result<(), super::ValidateError> {
    let lp = Butterworth::low_pass(f.order, f.cutoff_hz, m.rate_hz)?;
    for y in m.channels.values_mut() {
        *y = lp.apply(y);
    }
    let settle = (2.0 / f.cutoff_hz * m.rate_hz).ceil() as usize;
    for mask in m.clipped.values_mut() {
        let mut left = 0;
        for c in mask.iter_mut() {
            if *c {
                left = settle;
            } else if left > 0 {
                *c = true;
                left -= 1;
            }
        }
    }
    let q = (m.rate_hz / (10.0 * f.cutoff_hz)).floor() as usize;
    let mut note = format!(
        "the recording passed through the acquisition low-pass ({}th-order Butterworth, {} Hz) like the simulation",
        f.order, f.cutoff_hz
    );
    if q >= 2 {
        let keep = |v: &mut Vec<f64>| *v = v.iter().step_by(q).copied().collect();
        keep(&mut m.time_s);
        m.channels.values_mut().for_each(keep);
        if let Some(v) = m.speed_mps.as_mut() {
            keep(v);
        }
        for mask in m.clipped.values_mut() {
            *mask = mask.iter().step_by(q).copied().collect();
        }
        note.push_str(&format!(
            ", then every {q}th sample kept for the comparison ({} -> {} Hz)",
            m.rate_hz,
            m.rate_hz / q as f64
        ));
        m.rate_hz /= q as f64;
    }
    m.notes.push(note);
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn flat_tops_at_standard_ranges() {
        let mut v: Vec<f64> = (0..100).map(|k| 3.0 * (k as f64 * 0.1).sin()).collect();
        assert_eq!(super::flat_top_range(&v), None);
        for x in v.iter_mut() {
            *x = x.clamp(-2.0, 2.0);
        }
        assert_eq!(super::flat_top_range(&v), Some(2.0));
    }
}
