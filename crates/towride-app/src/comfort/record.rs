//! Acceleration channels of a CSV file for the comfort measures: one column per axis,
//! its unit from the header (`[m/s^2]` or `[g]`, anything else refused), the sample
//! rate from a time column (uniform within 1 %) or given. Read with
//! [`crate::durability::csv::read_columns`]: the header is the first line not starting
//! with `#`, every cell a finite number, errors name file, line and column.

use std::path::Path;

use super::Weighting;
use crate::durability::csv::{err, read_columns};
use towride_mbs::input::InputError;

/// Standard gravity [m/s^2] for columns in `g` (3rd CGPM 1901; ISO 80000-3:2006 item 3-9
/// note).
pub const STANDARD_GRAVITY_M_S2: f64 = 9.80665;

/// Largest deviation of a time step from the mean step, as a fraction of it: the
/// weighting filters are designed for one sample rate.
pub const TIME_JITTER: f64 = 0.01;

/// A measuring axis of ISO 2631-1 (figure 1, seated person: x back to chest, y right to
/// left, z buttocks to head). It decides the weighting for comfort and health on the
/// seat surface (Table 1: Wd for x and y, Wk for z) and the axis's k factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// Fore-aft.
    X,
    /// Lateral.
    Y,
    /// Vertical.
    Z,
}

impl Axis {
    /// `x`, `y` or `z` (any case).
    pub fn parse(s: &str) -> Option<Axis> {
        match s.trim().to_ascii_lowercase().as_str() {
            "x" => Some(Axis::X),
            "y" => Some(Axis::Y),
            "z" => Some(Axis::Z),
            _ => None,
        }
    }

    /// The axis a channel's name ends in (`acc_driver_floor_z`: z), if any.
    pub fn of_name(name: &str) -> Option<Axis> {
        let (_, last) = name.rsplit_once('_')?;
        Axis::parse(last)
    }

    /// 0, 1, 2 for x, y, z.
    pub fn index(self) -> usize {
        self as usize
    }

    /// The seat-surface weighting of the axis (ISO 2631-1 Table 1, 8.2.2): Wd
    /// horizontal, Wk vertical.
    pub fn weighting(self) -> Weighting {
        match self {
            Axis::Z => Weighting::Wk,
            Axis::X | Axis::Y => Weighting::Wd,
        }
    }
}

/// One column to evaluate: its name in the header, its axis and its weighting.
#[derive(Clone, Debug)]
pub struct ColumnSpec {
    /// Header name, with or without the ` [unit]`.
    pub column: String,
    /// The axis it measures.
    pub axis: Axis,
    /// The weighting applied ([`Axis::weighting`] unless chosen).
    pub weighting: Weighting,
}

/// Where the sample rate comes from.
#[derive(Clone, Debug)]
pub enum TimeBase {
    /// A time column in seconds (`time [s]` in a run's `outputs.csv`).
    Column(String),
    /// A given rate [Hz], the rows taken as equally spaced.
    RateHz(f64),
}

/// An acceleration column read, in m/s^2.
#[derive(Clone, Debug)]
pub struct Channel {
    /// The column's name without its unit.
    pub name: String,
    /// The unit as the header wrote it (`m/s^2`, `g`).
    pub unit: String,
    /// What the column is evaluated as.
    pub spec: ColumnSpec,
    /// Values [m/s^2].
    pub values_m_s2: Vec<f64>,
}

/// The factor to m/s^2 of a header unit: `m/s^2` (also `m/s2`, `m/s²`, `m s^-2`) 1,
/// `g` or `gn` (any case) [`STANDARD_GRAVITY_M_S2`].
pub fn unit_factor(unit: &str) -> Option<f64> {
    match unit.trim() {
        "m/s^2" | "m/s2" | "m/s²" | "m s^-2" | "m*s^-2" => Some(1.0),
        u if u.eq_ignore_ascii_case("g") || u.eq_ignore_ascii_case("gn") => {
            Some(STANDARD_GRAVITY_M_S2)
        }
        _ => None,
    }
}

/// Reads `specs` from `file` with the sample rate from `time`: the rate [Hz] and the
/// channels in m/s^2.
pub fn read(
    file: &Path,
    time: &TimeBase,
    specs: &[ColumnSpec],
) -> Result<(f64, Vec<Channel>), InputError> {
    let mut names: Vec<&str> = specs.iter().map(|s| s.column.as_str()).collect();
    if let TimeBase::Column(t) = time {
        names.push(t);
    }
    let table = read_columns(file, &names)?;
    let (header_line, mut cols) = (table.header_line, table.columns);
    let rate = match time {
        TimeBase::RateHz(r) if r.is_finite() && *r > 0.0 => *r,
        TimeBase::RateHz(r) => {
            return Err(err(
                file,
                None,
                "rate_hz",
                format!("{r}: the sample rate must be a positive number"),
            ))
        }
        TimeBase::Column(_) => {
            let t = cols.pop().expect("the time column was asked for last");
            if t.unit.as_deref().is_some_and(|u| u != "s") {
                return Err(err(
                    file,
                    Some(header_line),
                    &t.name,
                    format!(
                        "unit [{}]: the time column must be in seconds, [s]",
                        t.unit.as_deref().unwrap_or_default()
                    ),
                ));
            }
            rate_of(file, &table.lines, &t.name, &t.values)?
        }
    };
    let mut out = Vec::with_capacity(specs.len());
    for (c, spec) in cols.into_iter().zip(specs) {
        let unit = c.unit.clone().unwrap_or_default();
        let f = unit_factor(&unit).ok_or_else(|| {
            err(
                file,
                Some(header_line),
                &c.name,
                if unit.is_empty() {
                    "no unit in the header: write `name [m/s^2]` or `name [g]`".into()
                } else {
                    format!("unit [{unit}] is not an acceleration: use [m/s^2] or [g]")
                },
            )
        })?;
        out.push(Channel {
            name: c.name,
            unit,
            spec: spec.clone(),
            values_m_s2: c.values.iter().map(|v| v * f).collect(),
        });
    }
    Ok((rate, out))
}

/// The sample rate of the time column `t` [s]: the mean step's inverse, every step
/// within [`TIME_JITTER`] of the mean.
fn rate_of(file: &Path, lines: &[usize], name: &str, t: &[f64]) -> Result<f64, InputError> {
    if t.len() < 2 {
        return Err(err(
            file,
            None,
            name,
            format!("{} rows: need at least 2", t.len()),
        ));
    }
    let mean = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    // Also false for a NaN mean (cells are finite, so it cannot be).
    let rising = mean > 0.0;
    for (i, w) in t.windows(2).enumerate() {
        let dt = w[1] - w[0];
        if !rising || (dt - mean).abs() > TIME_JITTER * mean {
            return Err(err(
                file,
                Some(lines[i + 1]),
                name,
                format!(
                    "time step {dt:e} s from the line before is not within {} % of the mean step {mean:e} s: the weightings need a uniform rate (resample, or give --rate-hz)",
                    TIME_JITTER * 100.0
                ),
            ));
        }
    }
    Ok(1.0 / mean)
}
