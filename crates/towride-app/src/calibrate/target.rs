//! One recorded run as a calibration target: the measured curves as `validate` aligns
//! them, band-limited and thinned, with a weight per channel, and the same processing
//! for any simulation of the run.
//!
//! The alignment (true speed from the foils or the speed channel, obstacle time refined
//! by the cross-correlation) comes from a validation of the run with the model at the
//! current values and is then held fixed while the values move: the cross-correlation's
//! shift is piecewise in the sample grid, and a residual that jumped with it would make
//! finite-difference sensitivities meaningless. The fit re-aligns between its rounds.
//!
//! Each channel's residual is divided by the measured channel's noise, its RMS on the
//! quiet road before the obstacle (`validate`'s signal-to-noise figure): a channel then
//! counts by how far its misfit stands above what the sensor and road can resolve, not
//! by its units or its amplitude.
//!
//! The residual is the thinned time histories, the curves' features ([`super::features`]:
//! the largest maximum and minimum and the next extremum, value and time), or both.
//! With features alone the run's time shift is not a fitted value: each simulation is
//! aligned to the recording by the cross-correlation first (`validate`'s, refined
//! between samples), so a feature's time misfit is its timing relative to the others.
//! Samples a clipped sensor recorded are left out (their residual is zero): the
//! recording's clipped stretches as `validate` marks them, widened by the band filter's
//! settling time (2 / its corner) on each side when a band is applied.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::features::{self, Feature};
use crate::signal::acquisition::AcqFilter;
use crate::signal::butterworth::Butterworth;
use crate::validate::descriptor::Descriptor;
use crate::validate::filter::acquire;
use crate::validate::pipeline::{zero, ZERO_MARGIN_S};
use crate::validate::{simulator_with, validate_run, Options, RunValidation};
use towride_mbs::input::Loader;

/// A noise estimate is never taken below this share of the channel's RMS over the
/// window: a nearly noise-free channel (a synthetic one) would otherwise outweigh the
/// others by orders of magnitude.
const NOISE_FLOOR_SHARE: f64 = 0.01;
/// Without a quiet road to measure the noise on, it is taken as this share of the
/// channel's RMS over the window (stated in the result).
const NOISE_FALLBACK_SHARE: f64 = 0.05;
/// The thinned curves keep at least this many samples per period of the highest
/// frequency they carry.
const SAMPLES_PER_TOP_PERIOD: f64 = 4.0;
/// Order of each pass of the zero-phase band filter (forward and backward: twice it).
const BAND_ORDER: usize = 2;

/// What the residual is made of.
#[derive(Clone, Copy, Debug, Default, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Residual {
    /// The thinned, band-limited time histories.
    #[default]
    History,
    /// Each channel's extrema and their times.
    Features,
    /// Both.
    Both,
}

impl Residual {
    fn history(self) -> bool {
        self != Residual::Features
    }
    fn features(self) -> bool {
        self != Residual::History
    }
}

/// A frequency band [Hz] applied to measured and simulated curves alike.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct Band {
    /// High-pass corner [Hz] (0: none).
    pub lo_hz: f64,
    /// Low-pass corner [Hz].
    pub hi_hz: f64,
}

/// One channel of a target.
#[derive(Clone, Debug, Serialize)]
pub struct TargetChannel {
    /// Simulated channel name.
    pub name: String,
    /// The noise the residual is divided by [m/s^2].
    pub noise_mps2: f64,
    /// Where the noise figure comes from.
    pub noise_from: &'static str,
    /// Samples of the evaluation window left out as clipped (filter settling included).
    pub clipped_samples: usize,
    /// The measured curve's features (with `--residual features` or `both`).
    pub features: Vec<Feature>,
    /// Subtract the mean before the obstacle (the descriptor's `zero_before_obstacle`).
    #[serde(skip)]
    zero: bool,
}

/// A recorded run prepared for the fit.
#[derive(Clone, Debug, Serialize)]
pub struct Target {
    /// Run name.
    pub name: String,
    /// Its descriptor.
    pub descriptor: PathBuf,
    /// Scene simulated.
    pub scene: PathBuf,
    /// Load case.
    pub load_case: String,
    /// Speed simulated [m/s].
    pub speed_mps: f64,
    /// Obstacle time on the recording's clock, shift included [s].
    pub obstacle_time_s: f64,
    /// The cross-correlation's shift at preparation [s].
    pub shift_s: f64,
    /// What the residual is made of.
    pub residual: Residual,
    /// Channels fitted.
    pub channels: Vec<TargetChannel>,
    /// Thinned sample times (recording's clock) [s].
    #[serde(skip)]
    pub time_s: Vec<f64>,
    /// Measured curves on `time_s`, band-limited [m/s^2].
    #[serde(skip)]
    pub measured: Vec<Vec<f64>>,
    /// Per channel, on `time_s`: the sample counts (not clipped).
    #[serde(skip)]
    keep: Vec<Vec<bool>>,
    /// Measured curves on the evaluation window, band-limited (features only).
    #[serde(skip)]
    full: Vec<Vec<f64>>,
    /// Per channel, on the evaluation window: the sample counts (not clipped).
    #[serde(skip)]
    keep_window: Vec<Vec<bool>>,
    /// Largest time shift the alignment searches [s].
    #[serde(skip)]
    max_shift_s: f64,
    /// Sample times of the evaluation window before thinning.
    #[serde(skip)]
    window_s: Vec<f64>,
    /// Thinning step (samples of the recording per kept sample).
    pub step: usize,
    /// Rate of the kept samples [Hz].
    pub rate_hz: f64,
    /// Highest frequency the curves carry [Hz] (band or acquisition cut-off).
    pub top_hz: f64,
    #[serde(skip)]
    band: Option<Band>,
    #[serde(skip)]
    filter: AcqFilter,
}

impl Target {
    /// Validates the run at `descriptor` with the model read through `loader` and keeps
    /// its aligned curves (`channels`: those fitted, empty: every channel with a signal
    /// above its noise). Returns the validation too (its ratings are the "before").
    pub fn prepare(
        descriptor: &Path,
        loader: &Loader,
        channels: &[String],
        band: Option<Band>,
        residual: Residual,
        opts: &Options,
    ) -> Result<(Target, RunValidation), crate::Error> {
        let sim = simulator_with(loader.clone());
        let v = validate_run(descriptor, sim.as_ref(), opts)?;
        let desc = Descriptor::from_file(descriptor)?;
        let c = v.primary();
        let names: Vec<String> = if channels.is_empty() {
            c.channels
                .iter()
                .filter(|f| f.has_signal)
                .map(|f| f.channel.clone())
                .collect()
        } else {
            for n in channels {
                if !c.measured.contains_key(n) {
                    return Err(crate::validate::ValidateError::Mismatch(format!(
                        "{}: --channels names `{n}`, which the descriptor does not map (it maps {:?})",
                        descriptor.display(),
                        c.measured.keys().collect::<Vec<_>>()
                    ))
                    .into());
                }
            }
            channels.to_vec()
        };
        if names.is_empty() {
            return Err(crate::validate::ValidateError::Signal(format!(
                "{}: no channel stands above its noise: nothing to fit",
                descriptor.display()
            ))
            .into());
        }
        let rate = v.sample_rate_hz;
        let top = band.map_or(desc.filter.cutoff_hz, |b| {
            b.hi_hz.min(desc.filter.cutoff_hz)
        });
        let step = ((rate / (SAMPLES_PER_TOP_PERIOD * top)).floor() as usize).max(1);
        let mut out = Target {
            name: v.name.clone(),
            descriptor: descriptor.to_path_buf(),
            scene: desc.scene.clone(),
            load_case: desc.load_case.clone().unwrap_or_default(),
            speed_mps: c.speed_mps,
            obstacle_time_s: c.obstacle_time_s,
            shift_s: c.shift_s,
            residual,
            channels: Vec::new(),
            time_s: c.time_s.iter().step_by(step).copied().collect(),
            measured: Vec::new(),
            keep: Vec::new(),
            full: Vec::new(),
            keep_window: Vec::new(),
            max_shift_s: opts.max_shift_s,
            window_s: c.time_s.clone(),
            step,
            rate_hz: rate / step as f64,
            top_hz: top,
            band,
            filter: desc.filter,
        };
        for n in &names {
            let m = &c.measured[n];
            let fig = c.channels.iter().find(|f| &f.channel == n);
            let window_rms = rms(m);
            // The quiet-road noise: the channel's RMS over its rated interval divided by
            // the signal-to-noise figure `validate` measured.
            let quiet = fig.and_then(|f| {
                let snr = f.signal_to_noise?;
                let inside: Vec<f64> = c
                    .time_s
                    .iter()
                    .zip(m)
                    .filter(|(t, _)| **t >= f.interval_s[0] && **t <= f.interval_s[1])
                    .map(|(_, y)| *y)
                    .collect();
                (snr > 0.0).then(|| rms(&inside) / snr)
            });
            let (noise, from) = match quiet {
                Some(q) if q >= NOISE_FLOOR_SHARE * window_rms => (q, "quiet road"),
                Some(_) => (NOISE_FLOOR_SHARE * window_rms, "floor (1 % of the RMS)"),
                None => (
                    NOISE_FALLBACK_SHARE * window_rms,
                    "no quiet road: 5 % of the RMS",
                ),
            };
            let zero = desc
                .channels
                .iter()
                .any(|d| &d.simulated == n && d.zero_before_obstacle);
            let keep = out.unclipped(c.clipped.get(n), rate);
            let full = out.band_limit(m)?;
            // A clipped channel's largest extrema are unknown, so "the largest maximum"
            // and its rank are undefined: it has no features.
            let feats = if residual.features() && keep.iter().all(|k| *k) {
                features::extract(&out.window_s, &full, &keep, top, noise, 1.0 / rate)
            } else {
                Vec::new()
            };
            out.measured.push(out.thin(&full));
            if residual == Residual::Features {
                out.full.push(full);
            }
            out.keep.push(out.thin(&keep));
            out.keep_window.push(keep.clone());
            out.channels.push(TargetChannel {
                name: n.clone(),
                noise_mps2: noise.max(f64::MIN_POSITIVE),
                noise_from: from,
                clipped_samples: keep.iter().filter(|k| !**k).count(),
                features: feats,
                zero,
            });
        }
        if residual == Residual::Features && out.channels.iter().all(|c| c.features.is_empty()) {
            return Err(crate::validate::ValidateError::Signal(format!(
                "{}: no channel has an extremum {} times its noise: no features to fit",
                descriptor.display(),
                features::MIN_HEIGHT_NOISE
            ))
            .into());
        }
        Ok((out, v))
    }

    /// Which window samples count: not clipped, nor within the band filter's settling
    /// time of a clipped one.
    fn unclipped(&self, clipped: Option<&Vec<bool>>, rate: f64) -> Vec<bool> {
        let n = self.window_s.len();
        let Some(c) = clipped else {
            return vec![true; n];
        };
        let reach = self.band.map_or(0, |b| {
            (2.0 / b.hi_hz.min(self.top_hz) * rate).ceil() as usize
        });
        let mut keep = vec![true; n];
        for (k, _) in c.iter().enumerate().filter(|(_, x)| **x) {
            let (a, b) = (k.saturating_sub(reach), (k + reach + 1).min(n));
            keep[a..b].iter_mut().for_each(|x| *x = false);
        }
        keep
    }

    /// The simulated curves of this run by the model `loader` reads, processed as the
    /// measured ones (acquisition chain, alignment moved by `shift_s`, zeroing, band) on
    /// the evaluation window's samples; [`Target::thinned`] thins them.
    pub fn simulate(&self, loader: &Loader, shift_s: f64) -> Result<Vec<Vec<f64>>, crate::Error> {
        let sim = crate::validate::vehicle_sim::VehicleSimulator {
            loader: loader.clone(),
        };
        use crate::validate::Simulator as _;
        let s = sim.simulate(&self.scene, self.speed_mps, &self.load_case)?;
        let mut acq = acquire(&s, self.filter)?;
        let n = acq.channels.values().next().map_or(0, |v| v.len());
        let t_acq: Vec<f64> = (0..n).map(|k| acq.t0_s + k as f64 * acq.dt_s).collect();
        let mut out = Vec::with_capacity(self.channels.len());
        for ch in &self.channels {
            if !acq.channels.contains_key(&ch.name) {
                return Err(crate::validate::ValidateError::Mismatch(format!(
                    "{}: the simulation has no channel `{}`",
                    self.descriptor.display(),
                    ch.name
                ))
                .into());
            }
            if ch.zero {
                let end = acq.obstacle_time_s - ZERO_MARGIN_S;
                zero(&t_acq, acq.channels.get_mut(&ch.name), end);
            }
            let offset = self.obstacle_time_s + shift_s - acq.obstacle_time_s;
            let y: Vec<f64> = self
                .window_s
                .iter()
                .map(|&t| acq.at(&ch.name, t - offset))
                .collect();
            out.push(self.band_limit(&y)?);
        }
        Ok(out)
    }

    /// With features alone: curves from [`Target::simulate`] moved by the shift that best
    /// aligns them with the recording (mean correlation over the channels); else as they
    /// are.
    pub fn aligned(&self, simulated: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        if self.residual != Residual::Features || self.window_s.len() < 2 {
            return simulated;
        }
        let t = &self.window_s;
        let dt = t[1] - t[0];
        // `signal::butterworth::interp` on a uniform grid, by index instead of a search:
        // the alignment calls it for every lag, sample and channel of every evaluation.
        let at = |y: &[f64], x: f64| {
            let u = ((x - t[0]) / dt).clamp(0.0, (y.len() - 1) as f64);
            let k = (u.floor() as usize).min(y.len().saturating_sub(2));
            let f = u - k as f64;
            y[k] * (1.0 - f) + y[(k + 1).min(y.len() - 1)] * f
        };
        // On the thinned samples over the whole search range, then on every sample
        // within one thinned step of that.
        let thin_m: Vec<&[f64]> = self.measured.iter().map(Vec::as_slice).collect();
        let coarse = crate::validate::align::best_shift(
            &self.time_s,
            &thin_m,
            &|c, ti, sh| at(&simulated[c], ti + sh),
            dt * self.step as f64,
            self.max_shift_s,
        );
        let m: Vec<&[f64]> = self.full.iter().map(Vec::as_slice).collect();
        let fine = crate::validate::align::best_shift(
            t,
            &m,
            &|c, ti, sh| at(&simulated[c], ti + coarse.shift_s + sh),
            dt,
            dt * self.step as f64,
        );
        let shift = coarse.shift_s + fine.shift_s;
        simulated
            .iter()
            .map(|y| t.iter().map(|&ti| at(y, ti + shift)).collect())
            .collect()
    }

    /// Curves from [`Target::simulate`] on the thinned samples `time_s`.
    pub fn thinned(&self, simulated: &[Vec<f64>]) -> Vec<Vec<f64>> {
        simulated.iter().map(|y| self.thin(y)).collect()
    }

    /// Channel after channel: the history's (simulated - measured) / noise on the
    /// thinned samples (0 where clipped), then each feature's value misfit / noise and
    /// time misfit / its time weight.
    pub fn residual(&self, simulated: Vec<Vec<f64>>) -> Vec<f64> {
        let simulated = self.aligned(simulated);
        let mut r = Vec::with_capacity(self.len());
        for (c, ch) in self.channels.iter().enumerate() {
            let s = &simulated[c];
            if self.residual.history() {
                let thin = s.iter().step_by(self.step);
                r.extend(
                    self.measured[c]
                        .iter()
                        .zip(thin)
                        .zip(&self.keep[c])
                        .map(|((m, s), k)| if *k { (s - m) / ch.noise_mps2 } else { 0.0 }),
                );
            }
            for f in &ch.features {
                let (t, y) = features::locate(&self.window_s, s, &self.keep_window[c], f);
                r.push((y - f.value) / ch.noise_mps2);
                r.push((t - f.time_s) / f.sigma_t_s);
            }
        }
        r
    }

    /// Number of residuals.
    pub fn len(&self) -> usize {
        let history = if self.residual.history() {
            self.measured.iter().map(Vec::len).sum()
        } else {
            0
        };
        history
            + 2 * self
                .channels
                .iter()
                .map(|c| c.features.len())
                .sum::<usize>()
    }

    /// No residuals.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Residuals per statistically independent sample: a curve limited to `top_hz` and
    /// kept at `rate_hz` has about 2 `top_hz` independent values per second.
    pub fn samples_per_independent(&self) -> f64 {
        if !self.residual.history() {
            return 1.0;
        }
        (self.rate_hz / (2.0 * self.top_hz)).max(1.0)
    }

    fn thin<T: Copy>(&self, y: &[T]) -> Vec<T> {
        y.iter().step_by(self.step).copied().collect()
    }

    /// The zero-phase band filter (forward and backward), or the curve as it is.
    fn band_limit(&self, y: &[f64]) -> Result<Vec<f64>, crate::Error> {
        let Some(b) = self.band else {
            return Ok(y.to_vec());
        };
        let rate = self.rate_hz * self.step as f64;
        let filtfilt = |fc: f64, x: &[f64]| -> Result<Vec<f64>, crate::Error> {
            let f = Butterworth::low_pass(BAND_ORDER, fc, rate)?;
            let mut once = f.apply(x);
            once.reverse();
            let mut twice = f.apply(&once);
            twice.reverse();
            Ok(twice)
        };
        let low = filtfilt(b.hi_hz, y)?;
        if b.lo_hz <= 0.0 {
            return Ok(low);
        }
        let slow = filtfilt(b.lo_hz, &low)?;
        Ok(low.iter().zip(&slow).map(|(a, s)| a - s).collect())
    }
}

fn rms(y: &[f64]) -> f64 {
    (y.iter().map(|v| v * v).sum::<f64>() / y.len().max(1) as f64).sqrt()
}
