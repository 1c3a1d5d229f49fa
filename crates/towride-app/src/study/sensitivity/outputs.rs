//! The outputs a sensitivity study ranks its parameters by: `CHANNEL.abs_peak` (largest
//! magnitude, max(|max|, |min|)), `CHANNEL.max`, `CHANNEL.min`, `CHANNEL.rms` and
//! `CHANNEL.freq` (peak of the amplitude spectrum, as the summary's hitch-force ringing,
//! [`crate::job::ringing`]). CHANNEL may be a band-limited twin, the channel through the
//! scene's acquisition chain (`acc_hitch_z_lp100`, [`crate::job::band`]). The names
//! `peak` (the largest magnitude) and `peak100` (the same after a 100 Hz low-pass) of
//! earlier versions are refused with the name to use instead.

use crate::error::Result;
use crate::job::{Job, RunResult};
use crate::scene::channels::{acc, band, ACC_PREFIX, HITCH_FX};
use towride_mbs::input::InputError;

/// What is taken of a channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// Largest magnitude, max(|max|, |min|).
    AbsPeak,
    /// Largest value.
    Max,
    /// Smallest value.
    Min,
    /// Root mean square over the run.
    Rms,
    /// Dominant frequency [Hz].
    Freq,
}

impl Measure {
    fn name(self) -> &'static str {
        match self {
            Measure::AbsPeak => "abs_peak",
            Measure::Max => "max",
            Measure::Min => "min",
            Measure::Rms => "rms",
            Measure::Freq => "freq",
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

/// The default outputs of a scene (`channels`: raw channels, then band-limited twins
/// named with `suffix`): the hitch force's |peak|, RMS and dominant frequency (with a
/// hitch), the trailer box's raw acceleration |peak| (its drawbar sensor) and every
/// accelerometer's |peak| as the instrument saw it (its band-limited twin; raw without
/// an acquisition chain). `None` for a model with neither a hitch nor an accelerometer
/// (name them).
pub fn defaults(channels: &[(String, String)], suffix: Option<&str>) -> Option<Vec<String>> {
    let has = |n: &str| channels.iter().any(|c| c.0 == n);
    let mut v: Vec<String> = Vec::new();
    if has(HITCH_FX) {
        v.extend(["abs_peak", "rms", "freq"].map(|m| format!("{HITCH_FX}.{m}")));
    }
    // The trailer's drawbar sensor.
    let drawbar = acc("trailer_drawbar", "z");
    if has(&drawbar) {
        v.push(format!("{drawbar}.abs_peak"));
    }
    let sensors = channels
        .iter()
        .filter(|c| c.0.starts_with(ACC_PREFIX) && band(&c.0).is_some());
    for (c, _) in sensors {
        let shown = suffix
            .map(|s| format!("{c}{s}"))
            .filter(|t| has(t))
            .unwrap_or_else(|| c.clone());
        v.push(format!("{shown}.abs_peak"));
    }
    (!v.is_empty()).then_some(v)
}

/// The outputs named in `names` (empty: [`defaults`]) against the channels of `job`
/// (raw and band-limited).
pub fn resolve(names: &[String], job: &Job) -> Result<Vec<OutputSpec>> {
    let mut channels: Vec<(String, String)> = towride_mbs::model::output::channels(&job.system)
        .into_iter()
        .map(|c| (c.name, c.unit.to_string()))
        .collect();
    channels.extend(job.band_channels());
    let suffix = job.acquisition().map(|f| f.suffix());
    let bad = |n: &str, m: String| InputError {
        file: "command line".into(),
        line: None,
        column: None,
        field: format!("--outputs {n}"),
        message: m,
        kind: Default::default(),
    };
    let names = if names.is_empty() {
        defaults(&channels, suffix.as_deref()).ok_or_else(|| {
            // The example is a channel of this model, so that it is accepted as given.
            let first = channels.first().map_or("CHANNEL", |c| c.0.as_str());
            bad(
                "",
                format!(
                    "this model has no hitch and no accelerometer: name the outputs, e.g. \
                     --outputs {first}.abs_peak (its channels: {})",
                    channels
                        .iter()
                        .map(|c| c.0.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )
        })?
    } else {
        names.to_vec()
    };
    names
        .iter()
        .map(|n| {
            let (ch, m) = n.rsplit_once('.').ok_or_else(|| {
                bad(
                    n,
                    "write CHANNEL.abs_peak, .max, .min, .rms or .freq".into(),
                )
            })?;
            let measure = match m {
                "abs_peak" => Measure::AbsPeak,
                "max" => Measure::Max,
                "min" => Measure::Min,
                "rms" => Measure::Rms,
                "freq" => Measure::Freq,
                // The names of earlier versions: say what they are now.
                "peak" => {
                    return Err(bad(
                        n,
                        format!(
                            "`peak` is now `abs_peak` (the largest magnitude, max(|max|, |min|)): write {ch}.abs_peak, or {ch}.max / {ch}.min for one side"
                        ),
                    ))
                }
                "peak100" => {
                    let twin = format!("{ch}{}", suffix.as_deref().unwrap_or("_lp100"));
                    return Err(bad(
                        n,
                        format!(
                            "`peak100` is gone: the channel through the scene's acquisition chain ([acquisition], default 100 Hz) is `{twin}`; write {twin}.abs_peak"
                        ),
                    ));
                }
                _ => {
                    return Err(bad(
                        n,
                        format!("`{m}`: use abs_peak, max, min, rms or freq"),
                    ))
                }
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
            Ok(match o.measure {
                Measure::AbsPeak => y.iter().fold(0.0f64, |m, v| m.max(v.abs())),
                Measure::Max => y.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                Measure::Min => y.iter().copied().fold(f64::INFINITY, f64::min),
                Measure::Rms => {
                    (y.iter().map(|v| v * v).sum::<f64>() / y.len().max(1) as f64).sqrt()
                }
                Measure::Freq => {
                    crate::signal::spectrum::peak_in(&y, 1.0 / rate, [1.0, 0.45 * rate])
                        .unwrap_or(f64::NAN)
                }
            })
        })
        .collect()
}

/// Per output, an `.abs_peak`'s signed sample at its largest magnitude (the first such
/// sample); `None` for the other measures, whose values carry their sign already.
pub fn signed_peaks(specs: &[OutputSpec], r: &RunResult) -> Vec<Option<f64>> {
    specs
        .iter()
        .map(|o| {
            if o.measure != Measure::AbsPeak {
                return None;
            }
            let y = r.channel(&o.channel).unwrap_or_default();
            y.iter().copied().filter(|v| v.is_finite()).reduce(|m, v| {
                if v.abs() > m.abs() {
                    v
                } else {
                    m
                }
            })
        })
        .collect()
}
