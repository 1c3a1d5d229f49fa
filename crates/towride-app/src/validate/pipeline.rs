//! One measured run against the simulation: corrected (measured speed, the passage as
//! found, time shift from the cross-correlation) and uncorrected (nominal speed, event
//! timing only).

use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use super::compare::{compare, Recorded, Sensor};
use super::descriptor::Descriptor;
use super::filter::{acquire, Acquired};
use super::measurement::{condition, read_measurement, Measurement};
use super::passage::{self, axle_sets, Passage, Track};
use super::speed::{channel_stats, SpeedInfo, SpeedSource};
use super::timebase::TimeBase;
use super::trigger::{obstacle_time, speed_from_foils};
use super::{Simulator, ValidateError};
use crate::signal::spectrum::{self, Dominant};

pub use super::compare::{ChannelFigures, Comparison};

/// Settings of the comparison.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Also make the corrected comparison (off: `--no-correct`).
    pub correct: bool,
    /// Bound of the cross-correlation search [s].
    pub max_shift_s: f64,
    /// Part before the obstacle kept in the evaluation window [s].
    pub pre_s: f64,
    /// A channel is rated where either curve exceeds this share of its largest
    /// magnitude, padded by `active_pad_s` (the long quiet parts would inflate every score).
    pub active_threshold: f64,
    /// Padding around the active part [s].
    pub active_pad_s: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            correct: true,
            max_shift_s: 0.1,
            pre_s: 0.25,
            active_threshold: 0.05,
            active_pad_s: 0.05,
        }
    }
}

/// What a run says per channel beyond the comparisons: clipping and spectra.
#[derive(Clone, Debug, Serialize)]
pub struct ChannelRecord {
    /// Simulated channel name.
    pub channel: String,
    /// The sensor's range [g], if given.
    pub range_g: Option<f64>,
    /// Clipped samples in the whole recording.
    pub clipped_samples: usize,
    /// Simulated samples at which a sensor of that range would clip (primary
    /// comparison's window).
    pub simulated_clipped_samples: usize,
    /// Dominant frequencies of the measured curve (primary comparison's window).
    pub measured_hz: Dominant,
    /// Dominant frequencies of the simulated curve.
    pub simulated_hz: Dominant,
}

/// A validated run.
#[derive(Clone, Debug, Serialize)]
pub struct RunValidation {
    /// Run name (the descriptor's file stem).
    pub name: String,
    /// The descriptor file.
    pub descriptor: String,
    /// Labelled synthetic (not a measurement).
    pub synthetic: bool,
    /// Name of the obstacle driven over.
    pub obstacle: String,
    /// The obstacle geometry the scene assumes and where its values come from.
    pub obstacle_geometry: Option<super::geometry::ObstacleGeometry>,
    /// Trailer load case (empty: the scene's).
    pub load_case: String,
    /// Nominal (speedometer) speed [m/s]: the descriptor's, else the measured one.
    pub nominal_speed_mps: f64,
    /// The speed and where it comes from.
    pub speed: SpeedInfo,
    /// Sample rate of the recording [Hz].
    pub sample_rate_hz: f64,
    /// Sample rate of the simulation before the acquisition chain [Hz] (NaN: unknown).
    pub simulation_rate_hz: f64,
    /// Cut-off of the acquisition low-pass [Hz] (the descriptor's).
    pub acquisition_cutoff_hz: f64,
    /// How the recording's sample times were found.
    pub time_base: TimeBase,
    /// The passage as found in the signals, when searched for.
    pub passage: Option<Passage>,
    /// When the front wheels reach the obstacle (primary comparison), recording's clock [s].
    pub obstacle_time_s: f64,
    /// When the rear wheels reach it, from the signals [s].
    pub rear_axle_time_s: Option<f64>,
    /// The distance between the front and rear axles' passages [m].
    pub implied_wheelbase_m: Option<f64>,
    /// The model's wheelbase [m], when known.
    pub wheelbase_m: Option<f64>,
    /// Repairs and inferences made while reading and processing.
    pub notes: Vec<String>,
    /// Per channel: clipping and dominant frequencies.
    pub channels: Vec<ChannelRecord>,
    /// Comparison with speed and time shift corrected; `None` with `--no-correct`.
    pub corrected: Option<Comparison>,
    /// Comparison at the nominal speed with event timing only.
    pub uncorrected: Comparison,
    /// Wall-clock time of the run's validation [s].
    pub wall_s: f64,
}

impl RunValidation {
    /// The comparison that counts: corrected when made.
    pub fn primary(&self) -> &Comparison {
        self.corrected.as_ref().unwrap_or(&self.uncorrected)
    }
}

/// Validates the run described by `descriptor` against `sim`.
pub fn validate_run(
    descriptor: &Path,
    sim: &dyn Simulator,
    opts: &Options,
) -> Result<RunValidation, ValidateError> {
    let wall = Instant::now();
    let desc = Descriptor::from_file(descriptor)?;
    if !desc.scene.is_file() {
        // Named with the descriptor's line, not as an unreadable file out of context.
        let src = towride_mbs::input::Source::read(descriptor)?;
        let message = format!("no file {}", desc.scene.display());
        return Err(src.error(&towride_mbs::path!["scene"], message).into());
    }
    let at =
        |e: &dyn std::fmt::Display| ValidateError::Signal(format!("{}: {e}", desc.path.display()));
    let mut meas = read_measurement(&desc)?;
    if desc.filter_measurement {
        condition(&mut meas, desc.filter).map_err(|e| at(&e))?;
    }
    let names: Vec<String> = desc.channels.iter().map(|c| c.simulated.clone()).collect();
    let sets = axle_sets(&desc.passage, &names);
    let model_axles = sim.axles(&desc.scene);
    let wheelbase = desc.passage.wheelbase_m.or(model_axles.0);
    let trailer_axle = desc.passage.trailer_axle_m.or(model_axles.1);
    let foils = match &desc.trigger {
        Some(t) => Some(speed_from_foils(&t.foils).map_err(|e| at(&e))?),
        None => None,
    };
    let mut notes = std::mem::take(&mut meas.notes);
    // A first speed for the passage search: foils, the channel's, the nominal one.
    let track = match &meas.speed_mps {
        Some(v) => Track::from_speed(&meas.time_s, v),
        None => Track::constant(
            foils
                .map(|f| f.speed_mps)
                .or(desc.nominal_speed_mps)
                .unwrap_or(f64::NAN),
        ),
    };
    let passage = if sets.front.is_empty() {
        if desc.trigger.is_none() {
            return Err(at(&format!(
                "no trigger and no front-axle unsprung channel to find the passage in (name them in [passage] front; channels: {names:?})"
            )));
        }
        None
    } else {
        match passage::detect(
            &meas.time_s,
            &meas.channels,
            &sets,
            &track,
            (wheelbase, trailer_axle),
            desc.passage.search_s,
            &mut notes,
        ) {
            Ok(p) => Some(p),
            Err(e) if desc.trigger.is_none() => return Err(at(&e)),
            Err(e) => {
                notes.push(format!(
                    "passage not found in the signals (the photocell is used): {e}"
                ));
                None
            }
        }
    };
    let speed = speed_info(
        &desc,
        &meas,
        foils,
        passage.as_ref(),
        &track,
        trailer_axle.or(wheelbase),
    );
    let nominal = desc.nominal_speed_mps.unwrap_or(speed.speed_mps);
    if desc.nominal_speed_mps.is_none() {
        notes.push("no nominal speed in the descriptor: the uncorrected comparison uses the measured speed".into());
    }
    let load = desc.load_case.clone().unwrap_or_default();
    // The simulation's own sample rate (before the acquisition chain resamples it): its
    // curves carry nothing above half of it.
    let sim_rate = std::cell::Cell::new(f64::NAN);
    let run_sim = |v: f64| -> Result<(Acquired, Option<f64>), ValidateError> {
        let s = sim
            .simulate(&desc.scene, v, &load)
            .map_err(|e| ValidateError::Simulation(Box::new(e)))?;
        if let [t0, .., t1] = s.time_s[..] {
            sim_rate.set((s.time_s.len() - 1) as f64 / (t1 - t0));
        }
        for c in &desc.channels {
            if !s.channels.contains_key(&c.simulated) {
                let known: Vec<&String> = s.channels.keys().collect();
                return Err(ValidateError::Mismatch(format!(
                    "{}: the simulation has no channel `{}` (it has {known:?})",
                    desc.path.display(),
                    c.simulated
                )));
            }
        }
        let a = acquire(&s, desc.filter).map_err(|e| at(&e))?;
        // The detector's lag in the simulation: its onset less the true passage.
        let lag = passage.as_ref().and_then(|_| {
            let n = a.channels.values().next().map_or(0, |v| v.len());
            let t: Vec<f64> = (0..n).map(|k| a.t0_s + k as f64 * a.dt_s).collect();
            let w = [a.obstacle_time_s - 0.3, a.obstacle_time_s + 0.5];
            passage::front_onset(&t, &a.channels, &sets.front, Some(w), v)
                .ok()
                .map(|o| o.time_s - a.obstacle_time_s)
        });
        Ok((a, lag))
    };
    let (mut plain, plain_lag) = run_sim(nominal)?;
    let mut fitted = if opts.correct {
        Some(run_sim(speed.speed_mps)?)
    } else {
        None
    };
    // The obstacle on the recording's clock: the photocell, else the detected onset less
    // the detector's lag in the simulation (each comparison its own simulation's lag:
    // the onset detector fires some milliseconds after the true passage, on the
    // recording as on the model, so the uncorrected baseline is aligned by the same
    // detector and differs from the corrected one only by the speed and the shift).
    let (t_obs, t_obs_nominal) = match (&desc.trigger, &passage) {
        (Some(tr), _) => (
            obstacle_time(tr, speed.speed_mps),
            obstacle_time(tr, nominal),
        ),
        (None, Some(p)) => {
            let lag = fitted.as_ref().and_then(|f| f.1);
            if fitted.is_some() && lag.is_none() {
                notes.push(
                    "the front axle's onset was not found in the simulation: no lag correction"
                        .into(),
                );
            }
            if plain_lag.is_none() {
                notes.push(
                    "the front axle's onset was not found in the nominal-speed simulation: the uncorrected comparison is aligned on the raw onset".into(),
                );
            }
            (
                p.front_onset_s - lag.unwrap_or(0.0),
                p.front_onset_s - plain_lag.unwrap_or(0.0),
            )
        }
        (None, None) => unreachable!("no trigger means a passage or an error"),
    };
    for c in desc.channels.iter().filter(|c| c.zero_before_obstacle) {
        zero(
            &meas.time_s,
            meas.channels.get_mut(&c.simulated),
            t_obs - ZERO_MARGIN_S,
        );
        for a in [Some(&mut plain), fitted.as_mut().map(|f| &mut f.0)]
            .into_iter()
            .flatten()
        {
            let n = a.channels.get(&c.simulated).map_or(0, |v| v.len());
            let t: Vec<f64> = (0..n).map(|k| a.t0_s + k as f64 * a.dt_s).collect();
            let t_end = a.obstacle_time_s - ZERO_MARGIN_S;
            zero(&t, a.channels.get_mut(&c.simulated), t_end);
        }
    }
    // One evaluation window for both comparisons: from just before the obstacle to the
    // end of the recording, inside both simulations' spans (with room for the shift).
    let mut lo = (t_obs.min(t_obs_nominal) - opts.pre_s).max(meas.time_s[0]);
    let mut hi = *meas.time_s.last().unwrap_or(&lo);
    for (acq, t_ev, margin) in [
        (Some(&plain), t_obs_nominal, 0.0),
        (fitted.as_ref().map(|f| &f.0), t_obs, opts.max_shift_s),
    ] {
        if let Some(a) = acq {
            let (s0, s1) = a.span();
            let offset = t_ev - a.obstacle_time_s;
            lo = lo.max(s0 + offset + margin);
            hi = hi.min(s1 + offset - margin);
        }
    }
    let idx: Vec<usize> = (0..meas.time_s.len())
        .filter(|&k| meas.time_s[k] >= lo && meas.time_s[k] <= hi)
        .collect();
    if idx.len() < 20 {
        return Err(at(&format!(
            "the recording and the simulation overlap on only {} samples ({lo:.3} .. {hi:.3} s)",
            idx.len()
        )));
    }
    let sensors: Vec<Sensor> = desc
        .channels
        .iter()
        .map(|c| Sensor {
            name: &c.simulated,
            axis: c.axis,
            range_g: c.range_g,
            clipped: meas.clipped.get(&c.simulated).map(|m| m.as_slice()),
        })
        .collect();
    let rec = Recorded {
        time_s: &meas.time_s,
        channels: &meas.channels,
        rate_hz: meas.rate_hz,
        idx: &idx,
    };
    let uncorrected = compare(
        "uncorrected",
        &rec,
        &sensors,
        &plain,
        nominal,
        t_obs_nominal,
        None,
        opts,
    );
    let corrected = fitted.as_ref().map(|(acq, _)| {
        compare(
            "corrected",
            &rec,
            &sensors,
            acq,
            speed.speed_mps,
            t_obs,
            Some(opts.max_shift_s),
            opts,
        )
    });
    let primary = corrected.as_ref().unwrap_or(&uncorrected);
    let dt = 1.0 / meas.rate_hz;
    let channels = desc
        .channels
        .iter()
        .zip(&primary.channels)
        .map(|(c, f)| ChannelRecord {
            channel: c.simulated.clone(),
            range_g: c.range_g,
            clipped_samples: meas.clipped_samples(&c.simulated),
            simulated_clipped_samples: f.simulated_clipped_samples,
            measured_hz: spectrum::dominant(&primary.measured[&c.simulated], dt),
            simulated_hz: spectrum::dominant(&primary.simulated[&c.simulated], dt),
        })
        .collect();
    let rear = passage.as_ref().and_then(|p| {
        p.rear_onset_s
            .map(|r| primary.obstacle_time_s + r - p.front_onset_s)
    });
    Ok(RunValidation {
        name: desc.name(),
        descriptor: desc.path.display().to_string(),
        synthetic: desc.synthetic,
        obstacle: desc.obstacle.clone(),
        obstacle_geometry: sim.obstacle_geometry(&desc.scene),
        load_case: load.clone(),
        nominal_speed_mps: nominal,
        sample_rate_hz: meas.time_base.rate_hz,
        simulation_rate_hz: sim_rate.get(),
        acquisition_cutoff_hz: desc.filter.cutoff_hz,
        time_base: meas.time_base.clone(),
        obstacle_time_s: primary.obstacle_time_s,
        rear_axle_time_s: rear,
        implied_wheelbase_m: passage.as_ref().and_then(|p| p.implied_wheelbase_m),
        wheelbase_m: wheelbase,
        passage,
        speed,
        notes,
        channels,
        corrected,
        uncorrected,
        wall_s: wall.elapsed().as_secs_f64(),
    })
}

/// The speed from the foils, the channel (mean over the passage) or the descriptor.
fn speed_info(
    desc: &Descriptor,
    meas: &Measurement,
    foils: Option<super::trigger::FoilSpeed>,
    passage: Option<&Passage>,
    track: &Track,
    last_axle: Option<f64>,
) -> SpeedInfo {
    let mut info = SpeedInfo {
        speed_mps: f64::NAN,
        source: SpeedSource::Descriptor,
        foils,
        channel_mean_mps: None,
        channel_range_mps: None,
        channel_drift_pct: None,
        window_s: None,
        channel_dropouts_s: Vec::new(),
    };
    if let Some(v) = &meas.speed_mps {
        // The passage: from just before the front axle's onset to just after the last
        // axle's (found, or where the geometry puts it).
        let t = &meas.time_s;
        let (lo, hi) = match passage {
            Some(p) => {
                let last = p
                    .trailer_onset_s
                    .or(p.rear_onset_s)
                    .or_else(|| {
                        last_axle.map(|d| track.time_at(track.position(p.front_onset_s) + d))
                    })
                    .unwrap_or(p.front_onset_s);
                (p.front_onset_s - 0.25, last + 0.25)
            }
            None => (t[0], t[t.len() - 1]),
        };
        // A logger's dropout is no deceleration: left out of the mean, and said.
        let drops = super::speed::dropouts(t, v, lo, hi);
        let (mean, range, drift) = channel_stats(t, v, lo, hi, &drops);
        info.channel_dropouts_s = drops;
        info.channel_mean_mps = Some(mean);
        info.channel_range_mps = Some(range);
        info.channel_drift_pct = Some(drift);
        info.window_s = Some([lo, hi]);
    }
    (info.speed_mps, info.source) = match (foils, info.channel_mean_mps, desc.nominal_speed_mps) {
        (Some(f), _, _) => (f.speed_mps, SpeedSource::Foils),
        (None, Some(m), _) => (m, SpeedSource::Channel),
        (None, None, Some(n)) => (n, SpeedSource::Descriptor),
        (None, None, None) => (f64::NAN, SpeedSource::Descriptor),
    };
    info
}

/// The zeroing mean is taken up to this long before the obstacle [s].
pub(crate) const ZERO_MARGIN_S: f64 = 0.1;

/// Subtracts from `y` its mean over t < `t_end` (needs 10 samples there).
pub(crate) fn zero(t: &[f64], y: Option<&mut Vec<f64>>, t_end: f64) {
    let Some(y) = y else { return };
    let n = t.iter().take_while(|&&ti| ti < t_end).count().min(y.len());
    if n >= 10 {
        let mean = y[..n].iter().sum::<f64>() / n as f64;
        y.iter_mut().for_each(|v| *v -= mean);
    }
}
