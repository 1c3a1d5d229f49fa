//! Studies made of many runs of one scene: the work-precision study ([`bench`]) and the
//! stress test of integrator settings and physics ([`stress`]). Both compare runs with a
//! tight-tolerance reference run ([`Reference`]) and run their cases in parallel. The
//! scaling study ([`scaling`]) times runs of growing models by phase.

pub mod bench;
pub mod scaling;
pub mod sensitivity;
pub mod stress;

use crate::error::{Error, Result};
use crate::job::{Extremes, RunResult};
use crate::scene::channels::{ACC_PREFIX, HITCH_FX};
use crate::signal::butterworth::Butterworth;

/// The status of a case or run an interruption (Ctrl-C) kept from starting.
pub const NOT_RUN: &str = "not run: interrupted";

/// The status of a run the interruption stopped midway.
pub fn interrupted_at(t: f64) -> String {
    format!("interrupted at t = {t:.4} s")
}

/// True for a status the interruption gave: not begun or stopped midway.
pub fn stopped(status: &str) -> bool {
    status == NOT_RUN || status.starts_with("interrupted at")
}

/// RMS of the difference of two equally sampled signals, relative to the RMS of `b`.
pub fn rel_rms(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len()).max(1) as f64;
    let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / n;
    let r: f64 = b.iter().map(|y| y * y).sum::<f64>() / n;
    if r > 0.0 {
        (d / r).sqrt()
    } else {
        d.sqrt()
    }
}

/// The reference run's key outputs (plain data, shared by the parallel runs).
pub struct Reference {
    /// `hitch_fx`'s max, min and |peak| [N].
    pub extremes: Extremes,
    /// `hitch_fx` samples [N].
    pub hitch: Vec<f64>,
    /// The acceleration sensors' samples, by channel name.
    pub sensors: Vec<(String, Vec<f64>)>,
    /// The low-pass of the in-band error and the sensors through it.
    pub band: Option<Butterworth>,
    /// The sensors after the band's low-pass.
    pub sensors_band: Vec<Vec<f64>>,
}

/// A run's errors against the reference.
#[derive(Clone, Copy, Debug)]
pub struct Errors {
    /// The run's `hitch_fx` max, min and |peak| [N].
    pub extremes: Extremes,
    /// ||peak| - |reference peak|| / |reference peak|.
    pub abs_peak_error: f64,
    /// RMS of the hitch-force difference over the reference's RMS.
    pub hitch_rms: f64,
    /// Mean over the sensors of their relative RMS errors.
    pub sensor_rms: f64,
}

impl Reference {
    /// The key outputs of the reference run `r`.
    pub fn of(r: &RunResult) -> Reference {
        Reference {
            extremes: hitch_extremes(r),
            hitch: r.channel(HITCH_FX).unwrap_or_default(),
            sensors: r
                .samples
                .channels
                .iter()
                .filter(|c| c.name.starts_with(ACC_PREFIX) && r.is_raw(&c.name))
                .map(|c| (c.name.clone(), r.channel(&c.name).unwrap_or_default()))
                .collect(),
            band: None,
            sensors_band: Vec::new(),
        }
        .without_silent_sensors()
    }

    /// Also measures the sensors' errors after a low-pass at `band_hz`.
    pub fn with_band(mut self, band_hz: f64, rate_hz: f64) -> Result<Self> {
        let f = Butterworth::low_pass(4, band_hz, rate_hz).map_err(Error::from)?;
        self.sensors_band = self.sensors.iter().map(|(_, v)| f.apply(v)).collect();
        self.band = Some(f);
        Ok(self)
    }

    /// Mean relative RMS error of the sensors after the band's low-pass (NaN without one).
    pub fn band_error(&self, r: &RunResult) -> f64 {
        let Some(f) = &self.band else {
            return f64::NAN;
        };
        let e: Vec<f64> = self
            .sensors
            .iter()
            .zip(&self.sensors_band)
            .map(|((n, _), v)| rel_rms(&f.apply(&r.channel(n).unwrap_or_default()), v))
            .collect();
        e.iter().sum::<f64>() / e.len().max(1) as f64
    }

    /// Drops sensors whose reference RMS is below 1 % of the loudest one's (the lateral
    /// axes of a straight, symmetric crossing): their relative error measures rounding
    /// noise, not the integration.
    fn without_silent_sensors(mut self) -> Self {
        let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
        let loudest = self.sensors.iter().map(|(_, v)| rms(v)).fold(0.0, f64::max);
        self.sensors.retain(|(_, v)| rms(v) >= 0.01 * loudest);
        self
    }

    /// Extremes, |peak| error, hitch RMS error and mean sensor RMS error of run `r`.
    pub fn errors(&self, r: &RunResult) -> Errors {
        let extremes = hitch_extremes(r);
        let hitch_rms = rel_rms(&r.channel(HITCH_FX).unwrap_or_default(), &self.hitch);
        let sensors: Vec<f64> = self
            .sensors
            .iter()
            .map(|(n, v)| rel_rms(&r.channel(n).unwrap_or_default(), v))
            .collect();
        Errors {
            extremes,
            abs_peak_error: ((extremes.abs_peak - self.extremes.abs_peak) / self.extremes.abs_peak)
                .abs(),
            hitch_rms,
            sensor_rms: sensors.iter().sum::<f64>() / sensors.len().max(1) as f64,
        }
    }
}

/// `hitch_fx`'s extremes (all NaN without the channel).
fn hitch_extremes(r: &RunResult) -> Extremes {
    r.extremes(HITCH_FX).copied().unwrap_or(Extremes {
        max: f64::NAN,
        t_max: f64::NAN,
        min: f64::NAN,
        t_min: f64::NAN,
        abs_peak: f64::NAN,
        t_abs_peak: f64::NAN,
    })
}

/// A thread pool of `jobs` threads (at least one).
pub(crate) fn pool(jobs: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .build()
        .map_err(|e| Error::io("thread pool", std::io::Error::other(e.to_string())))
}

/// Wall time of a run, start included [s].
pub(crate) fn total_wall(r: &RunResult) -> f64 {
    r.summary.start_wall_s + r.summary.wall_s
}
