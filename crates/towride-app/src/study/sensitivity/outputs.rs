//! The outputs a sensitivity study ranks its parameters by: `CHANNEL.peak` (largest
//! magnitude), `CHANNEL.rms`, `CHANNEL.freq` (peak of the amplitude spectrum, as the
//! summary's hitch-force ringing, [`crate::job::ringing`]) and `CHANNEL.peak100`
//! (largest magnitude after the measurements' 100 Hz low-pass: a fourth-order
//! Butterworth, [`crate::signal::butterworth`]).

use crate::error::Result;
use crate::job::{Job, RunResult};
use crate::scene::channels::{acc, ACC_PREFIX, HITCH_FX};
use crate::signal::butterworth::Butterworth;
use towride_mbs::input::InputError;

/// What is taken of a channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// Largest magnitude.
    Peak,
    /// Root mean square over the run.
    Rms,
    /// Dominant frequency [Hz].
    Freq,
    /// Largest magnitude after the 100 Hz low-pass.
    Peak100,
}

impl Measure {
    fn name(self) -> &'static str {
        match self {
            Measure::Peak => "peak",
            Measure::Rms => "rms",
            Measure::Freq => "freq",
            Measure::Peak100 => "peak100",
        }
    }
}

/// One output.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputSpec {
    /// The channel.
    pub channel: String,
    /// What is taken of it.
    pub measure: Measure,
    /// Unit of the value.
    pub unit: String,
}

impl OutputSpec {
    /// `CHANNEL.measure`.
    pub fn name(&self) -> String {
        format!("{}.{}", self.channel, self.measure.name())
    }
}

/// The default outputs of a scene: the hitch force's peak, RMS and dominant frequency,
/// the trailer box's acceleration peak (its drawbar sensor) and every accelerometer's
/// peak in the 100 Hz band. `None` for a model without a hitch (name them).
pub fn defaults(channels: &[(String, String)]) -> Option<Vec<String>> {
    let has = |n: &str| channels.iter().any(|c| c.0 == n);
    if !has(HITCH_FX) {
        return None;
    }
    let mut v: Vec<String> = ["peak", "rms", "freq"]
        .map(|m| format!("{HITCH_FX}.{m}"))
        .to_vec();
    // The trailer's drawbar sensor.
    let drawbar = acc("trailer_drawbar", "z");
    if has(&drawbar) {
        v.push(format!("{drawbar}.peak"));
    }
    v.extend(
        channels
            .iter()
            .filter(|c| c.0.starts_with(ACC_PREFIX))
            .map(|c| format!("{}.peak100", c.0)),
    );
    Some(v)
}

/// The outputs named in `names` (empty: [`defaults`]) against the channels of `job`.
pub fn resolve(names: &[String], job: &Job) -> Result<Vec<OutputSpec>> {
    let channels: Vec<(String, String)> = towride_mbs::model::output::channels(&job.system)
        .into_iter()
        .map(|c| (c.name, c.unit.to_string()))
        .collect();
    let bad = |n: &str, m: String| InputError {
        file: "command line".into(),
        line: None,
        column: None,
        field: format!("--outputs {n}"),
        message: m,
        kind: Default::default(),
    };
    let names = if names.is_empty() {
        defaults(&channels).ok_or_else(|| {
            bad(
                "",
                "this model has no hitch: name the outputs, e.g. --outputs body.z.peak".into(),
            )
        })?
    } else {
        names.to_vec()
    };
    names
        .iter()
        .map(|n| {
            let (ch, m) = n
                .rsplit_once('.')
                .ok_or_else(|| bad(n, "write CHANNEL.peak, .rms, .freq or .peak100".into()))?;
            let measure = match m {
                "peak" => Measure::Peak,
                "rms" => Measure::Rms,
                "freq" => Measure::Freq,
                "peak100" => Measure::Peak100,
                _ => return Err(bad(n, format!("`{m}`: use peak, rms, freq or peak100"))),
            };
            let unit = channels
                .iter()
                .find(|c| c.0 == ch)
                .map(|c| c.1.clone())
                .ok_or_else(|| {
                    let names: Vec<&str> = channels.iter().map(|c| c.0.as_str()).collect();
                    bad(
                        n,
                        format!("no channel `{ch}` (channels: {})", names.join(", ")),
                    )
                })?;
            Ok(OutputSpec {
                channel: ch.into(),
                measure,
                unit: if measure == Measure::Freq {
                    "Hz".into()
                } else {
                    unit
                },
            })
        })
        .collect::<std::result::Result<Vec<_>, InputError>>()
        .map_err(Into::into)
}

/// The outputs' values of a run.
pub fn evaluate(specs: &[OutputSpec], r: &RunResult) -> Result<Vec<f64>> {
    let t = &r.samples.times;
    let n = t.len();
    let rate = if n > 1 {
        (n - 1) as f64 / (t[n - 1] - t[0])
    } else {
        0.0
    };
    specs
        .iter()
        .map(|o| {
            let y = r.channel(&o.channel).unwrap_or_default();
            let peak = |y: &[f64]| y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            Ok(match o.measure {
                Measure::Peak => peak(&y),
                Measure::Rms => {
                    (y.iter().map(|v| v * v).sum::<f64>() / y.len().max(1) as f64).sqrt()
                }
                Measure::Freq => {
                    crate::signal::spectrum::peak_in(&y, 1.0 / rate, [1.0, 0.45 * rate])
                        .unwrap_or(f64::NAN)
                }
                Measure::Peak100 => peak(&Butterworth::low_pass(4, 100.0, rate)?.apply(&y)),
            })
        })
        .collect()
}
