//! The acquisition chain applied to a simulation: the same low-pass as the data
//! acquisition, then sampling at the measurement's instants.
//!
//! The low-pass is a digital Butterworth filter ([`crate::signal::butterworth`]), run
//! causally as the analog acquisition filter does, so its phase lag is reproduced. To
//! stay close to the analog filter the simulation is filtered on a uniform grid of at
//! least 40 fc.

use super::ValidateError;
use crate::signal::butterworth::{interp, Butterworth};
use std::collections::BTreeMap;

use super::descriptor::AcqFilter;
use super::SimChannels;

/// A simulation after the acquisition filter, on a uniform grid.
#[derive(Clone, Debug)]
pub struct Acquired {
    /// Time of the first sample, on the simulation's clock [s].
    pub t0_s: f64,
    /// Sample interval [s].
    pub dt_s: f64,
    /// Filtered channels, by simulated channel name [SI units].
    pub channels: BTreeMap<String, Vec<f64>>,
    /// When the front wheels reach the obstacle, on the simulation's clock [s].
    pub obstacle_time_s: f64,
}

impl Acquired {
    /// Time span covered [s].
    pub fn span(&self) -> (f64, f64) {
        let n = self.channels.values().next().map_or(0, |v| v.len());
        (
            self.t0_s,
            self.t0_s + n.saturating_sub(1) as f64 * self.dt_s,
        )
    }

    /// Channel `name` at simulation time `t` (linear between grid points, held outside).
    pub fn at(&self, name: &str, t: f64) -> f64 {
        match self.channels.get(name) {
            Some(y) => self.sample(y, t),
            None => f64::NAN,
        }
    }

    /// Samples `y` (one of the channels, looked up once by the caller: the lookup by name
    /// cost more than the interpolation in the alignment's search) at time `t`.
    pub fn sample(&self, y: &[f64], t: f64) -> f64 {
        if y.is_empty() {
            return f64::NAN;
        }
        let u = ((t - self.t0_s) / self.dt_s).clamp(0.0, (y.len() - 1) as f64);
        let i = (u.floor() as usize).min(y.len().saturating_sub(2));
        let f = u - i as f64;
        if y.len() == 1 {
            return y[0];
        }
        y[i] + f * (y[i + 1] - y[i])
    }
}

/// Passes a simulation through the acquisition low-pass: resampled to a uniform grid at
/// max(its own rate, 40 fc), then filtered.
pub fn acquire(sim: &SimChannels, f: AcqFilter) -> Result<Acquired, ValidateError> {
    let t = &sim.time_s;
    if t.len() < 3 || !t.windows(2).all(|w| w[1] > w[0]) {
        return Err(ValidateError::Signal(
            "simulation time must have at least 3 increasing samples".into(),
        ));
    }
    let mut dts: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    dts.sort_by(f64::total_cmp);
    let native = 1.0 / dts[dts.len() / 2];
    let rate = f.grid_rate(native);
    let lp = Butterworth::low_pass(f.order, f.cutoff_hz, rate)?;
    let dt = 1.0 / rate;
    let n = ((t[t.len() - 1] - t[0]) / dt).floor() as usize + 1;
    let grid: Vec<f64> = (0..n).map(|k| t[0] + k as f64 * dt).collect();
    let mut channels = BTreeMap::new();
    for (name, y) in &sim.channels {
        if y.len() != t.len() {
            return Err(ValidateError::Signal(format!(
                "simulated channel {name}: {} samples for {} times",
                y.len(),
                t.len()
            )));
        }
        let u: Vec<f64> = grid.iter().map(|&tq| interp(t, y, tq)).collect();
        channels.insert(name.clone(), lp.apply(&u));
    }
    Ok(Acquired {
        t0_s: t[0],
        dt_s: dt,
        channels,
        obstacle_time_s: sim.obstacle_time_s,
    })
}
