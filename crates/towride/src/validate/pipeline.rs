//! One measured run against the simulation: corrected (speed from the foils, time shift
//! from the cross-correlation) and uncorrected (nominal speed, event timing only).

use super::ValidateError;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use super::align::best_shift;
use super::csv_reader::{read_measurement, Measurement};
use super::descriptor::Descriptor;
use super::filter::{acquire, Acquired};
use super::metrics::{gain_ratio, peak, pearson, rms_diff};
use super::rating::{iso_rating, Rating};
use super::trigger::{obstacle_time, speed_from_foils, FoilSpeed};
use super::Simulator;

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

/// Figures of one channel in one comparison (SI units).
#[derive(Clone, Debug, Serialize)]
pub struct ChannelFigures {
    /// Simulated channel name.
    pub channel: String,
    /// Measured value of largest magnitude [m/s^2].
    pub peak_measured_mps2: f64,
    /// When it occurs (recording's clock) [s].
    pub t_peak_measured_s: f64,
    /// Simulated value of largest magnitude [m/s^2].
    pub peak_simulated_mps2: f64,
    /// When it occurs (recording's clock) [s].
    pub t_peak_simulated_s: f64,
    /// RMS of measured minus simulated [m/s^2].
    pub rms_diff_mps2: f64,
    /// Pearson correlation of the two curves [-].
    pub correlation: f64,
    /// Least-squares amplitude ratio measured / simulated (a gain-error estimate).
    pub gain_ratio: f64,
    /// ISO/TS 18571-style rating of the simulated curve against the measured one.
    pub rating: Rating,
    /// Interval the channel was rated on (recording's clock) [s].
    pub interval_s: [f64; 2],
}

/// One comparison of a run (corrected or uncorrected).
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// "corrected" or "uncorrected".
    pub label: &'static str,
    /// Speed simulated [m/s].
    pub speed_mps: f64,
    /// Time shift found by the cross-correlation [s] (0 when uncorrected): the events are
    /// stamped this much later than the data show them (a trigger delay).
    pub shift_s: f64,
    /// The shift is at the search bound (the true shift may be larger).
    pub shift_at_bound: bool,
    /// Mean correlation of the channels at the shift found (`None` when uncorrected):
    /// how well the shapes agree once aligned.
    pub shift_correlation: Option<f64>,
    /// When the front wheels reach the obstacle, on the recording's clock [s].
    pub obstacle_time_s: f64,
    /// Mean overall rating over the channels.
    pub mean_rating: f64,
    /// Figures per channel.
    pub channels: Vec<ChannelFigures>,
    /// The compared curves on the evaluation window (for plots).
    #[serde(skip)]
    pub time_s: Vec<f64>,
    /// Measured curves by channel name [m/s^2].
    #[serde(skip)]
    pub measured: BTreeMap<String, Vec<f64>>,
    /// Simulated curves on the same samples [m/s^2].
    #[serde(skip)]
    pub simulated: BTreeMap<String, Vec<f64>>,
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
    /// Trailer load case.
    pub load_case: String,
    /// Nominal (speedometer) speed [m/s].
    pub nominal_speed_mps: f64,
    /// Speed from the foils and the fit residual.
    pub foil_speed: FoilSpeed,
    /// Sample rate of the recording [Hz].
    pub sample_rate_hz: f64,
    /// Repairs made while reading the CSV.
    pub notes: Vec<String>,
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
        let src = crate::input::Source::read(descriptor)?;
        let message = format!("no file {}", desc.scene.display());
        return Err(src.error(&crate::path!["scene"], message).into());
    }
    let mut meas = read_measurement(&desc)?;
    let foil = speed_from_foils(&desc.trigger.foils)
        .map_err(|e| ValidateError::Signal(format!("{}: {e}", desc.path.display())))?;
    let run_sim = |v: f64| -> Result<Acquired, ValidateError> {
        let s = sim
            .simulate(&desc.scene, v, &desc.load_case)
            .map_err(|e| ValidateError::Simulation(Box::new(e)))?;
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
        acquire(&s, desc.filter)
            .map_err(|e| ValidateError::Signal(format!("{}: {e}", desc.path.display())))
    };
    let mut plain = run_sim(desc.nominal_speed_mps)?;
    let mut fitted = if opts.correct {
        Some(run_sim(foil.speed_mps)?)
    } else {
        None
    };
    for c in desc.channels.iter().filter(|c| c.zero_before_obstacle) {
        let t_end = obstacle_time(&desc.trigger, foil.speed_mps) - ZERO_MARGIN_S;
        zero(&meas.time_s, meas.channels.get_mut(&c.simulated), t_end);
        for a in [Some(&mut plain), fitted.as_mut()].into_iter().flatten() {
            let n = a.channels.get(&c.simulated).map_or(0, |v| v.len());
            let t: Vec<f64> = (0..n).map(|k| a.t0_s + k as f64 * a.dt_s).collect();
            let t_end = a.obstacle_time_s - ZERO_MARGIN_S;
            zero(&t, a.channels.get_mut(&c.simulated), t_end);
        }
    }
    // One evaluation window for both comparisons: from just before the obstacle to the
    // end of the recording, inside both simulations' spans (with room for the shift).
    let t_obs = obstacle_time(&desc.trigger, foil.speed_mps);
    let t_obs_nominal = obstacle_time(&desc.trigger, desc.nominal_speed_mps);
    let mut lo = (t_obs.min(t_obs_nominal) - opts.pre_s).max(meas.time_s[0]);
    let mut hi = *meas.time_s.last().unwrap_or(&lo);
    for (acq, t_ev, margin) in [
        (Some(&plain), t_obs_nominal, 0.0),
        (fitted.as_ref(), t_obs, opts.max_shift_s),
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
        return Err(ValidateError::Signal(format!(
            "{}: the recording and the simulation overlap on only {} samples ({lo:.3} .. {hi:.3} s)",
            desc.path.display(),
            idx.len()
        )));
    }
    let names: Vec<String> = desc.channels.iter().map(|c| c.simulated.clone()).collect();
    let uncorrected = compare(
        "uncorrected",
        &meas,
        &idx,
        &names,
        &plain,
        desc.nominal_speed_mps,
        t_obs_nominal,
        None,
        opts,
    );
    let corrected = fitted.as_ref().map(|acq| {
        compare(
            "corrected",
            &meas,
            &idx,
            &names,
            acq,
            foil.speed_mps,
            t_obs,
            Some(opts.max_shift_s),
            opts,
        )
    });
    Ok(RunValidation {
        name: desc.name(),
        descriptor: desc.path.display().to_string(),
        synthetic: desc.synthetic,
        obstacle: desc.obstacle.clone(),
        load_case: desc.load_case.clone(),
        nominal_speed_mps: desc.nominal_speed_mps,
        foil_speed: foil,
        sample_rate_hz: meas.rate_hz,
        notes: meas.notes.clone(),
        corrected,
        uncorrected,
        wall_s: wall.elapsed().as_secs_f64(),
    })
}

/// Compares on the samples `idx`; with `search = Some(bound)` the time shift is found
/// by the cross-correlation first.
#[allow(clippy::too_many_arguments)]
fn compare(
    label: &'static str,
    meas: &Measurement,
    idx: &[usize],
    names: &[String],
    acq: &Acquired,
    speed_mps: f64,
    t_obs: f64,
    search: Option<f64>,
    opts: &Options,
) -> Comparison {
    let t: Vec<f64> = idx.iter().map(|&k| meas.time_s[k]).collect();
    let measured: BTreeMap<String, Vec<f64>> = names
        .iter()
        .map(|n| {
            (
                n.clone(),
                idx.iter().map(|&k| meas.channels[n][k]).collect(),
            )
        })
        .collect();
    let offset = t_obs - acq.obstacle_time_s;
    let sim_at = |c: usize, ti: f64, shift: f64| acq.at(&names[c], ti - offset + shift);
    let dt = 1.0 / meas.rate_hz;
    let (shift, at_bound, correlation) = match search {
        Some(bound) => {
            let m: Vec<&[f64]> = names.iter().map(|n| measured[n].as_slice()).collect();
            let a = best_shift(&t, &m, &sim_at, dt, bound);
            (a.shift_s, a.at_bound, Some(a.correlation))
        }
        None => (0.0, false, None),
    };
    let simulated: BTreeMap<String, Vec<f64>> = names
        .iter()
        .enumerate()
        .map(|(c, n)| {
            (
                n.clone(),
                t.iter().map(|&ti| sim_at(c, ti, shift)).collect(),
            )
        })
        .collect();
    let channels: Vec<ChannelFigures> = names
        .iter()
        .map(|n| {
            let (a, b) = active(
                &measured[n],
                &simulated[n],
                opts.active_threshold,
                (opts.active_pad_s / dt) as usize,
            );
            let (m, s, t) = (&measured[n][a..b], &simulated[n][a..b], &t[a..b]);
            let (pm, tpm) = peak(t, m);
            let (ps, tps) = peak(t, s);
            ChannelFigures {
                channel: n.clone(),
                peak_measured_mps2: pm,
                t_peak_measured_s: tpm,
                peak_simulated_mps2: ps,
                t_peak_simulated_s: tps,
                rms_diff_mps2: rms_diff(m, s),
                correlation: pearson(m, s),
                gain_ratio: gain_ratio(m, s),
                rating: iso_rating(m, s, dt),
                interval_s: [t[0], t[t.len() - 1]],
            }
        })
        .collect();
    let mean_rating =
        channels.iter().map(|c| c.rating.overall).sum::<f64>() / channels.len().max(1) as f64;
    Comparison {
        label,
        speed_mps,
        shift_s: shift,
        shift_at_bound: at_bound,
        shift_correlation: correlation,
        obstacle_time_s: t_obs - shift,
        mean_rating,
        channels,
        time_s: t,
        measured,
        simulated,
    }
}

/// The zeroing mean is taken up to this long before the obstacle [s].
const ZERO_MARGIN_S: f64 = 0.1;

/// Subtracts from `y` its mean over t < `t_end` (needs 10 samples there).
fn zero(t: &[f64], y: Option<&mut Vec<f64>>, t_end: f64) {
    let Some(y) = y else { return };
    let n = t.iter().take_while(|&&ti| ti < t_end).count().min(y.len());
    if n >= 10 {
        let mean = y[..n].iter().sum::<f64>() / n as f64;
        y.iter_mut().for_each(|v| *v -= mean);
    }
}

/// Index range where |m| or |s| exceeds `share` of its own largest magnitude, widened by
/// `pad` samples each side.
fn active(m: &[f64], s: &[f64], share: f64, pad: usize) -> (usize, usize) {
    let n = m.len();
    let mut range: Option<(usize, usize)> = None;
    for y in [m, s] {
        let top = y.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let first = y.iter().position(|v| v.abs() >= share * top && top > 0.0);
        let last = y.iter().rposition(|v| v.abs() >= share * top && top > 0.0);
        if let (Some(f), Some(l)) = (first, last) {
            range = Some(range.map_or((f, l), |(a, b)| (a.min(f), b.max(l))));
        }
    }
    match range {
        Some((a, b)) if b + 1 - a >= 10 => (a.saturating_sub(pad), (b + 1 + pad).min(n)),
        _ => (0, n),
    }
}
