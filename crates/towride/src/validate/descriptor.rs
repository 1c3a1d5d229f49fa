//! The TOML descriptor of a measured run: which scene, obstacle, speed and load it
//! belongs to, how its CSV columns map onto simulated channels, the acquisition filter and
//! the trigger. Read through [`Source`], so every error names file, line and field. The
//! format is documented in `docs/validation.md`.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::input::{InputError, Source};
use crate::path;

use super::G_MPS2;

/// Physical unit of a recorded channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unit {
    /// Metres per second squared.
    Mps2,
    /// Multiples of standard gravity.
    G,
}

impl Unit {
    /// Parses `m/s^2` (also `m/s2`, `m/s²`) or `g`.
    pub fn parse(s: &str) -> Option<Unit> {
        match s.trim() {
            "m/s^2" | "m/s2" | "m/s²" | "m s^-2" => Some(Unit::Mps2),
            "g" | "G" => Some(Unit::G),
            _ => None,
        }
    }

    /// Factor to m/s^2.
    pub fn to_si(self) -> f64 {
        match self {
            Unit::Mps2 => 1.0,
            Unit::G => G_MPS2,
        }
    }

    /// The unit as written in reports: "m/s^2" or "g".
    pub fn label(self) -> &'static str {
        match self {
            Unit::Mps2 => "m/s^2",
            Unit::G => "g",
        }
    }
}

/// One recorded channel and the simulated channel it is compared with.
#[derive(Clone, Debug)]
pub struct ChannelSpec {
    /// Column name in the CSV header (without the `[unit]`).
    pub column: String,
    /// Simulated channel name, e.g. `acc_trailer_drawbar_z`.
    pub simulated: String,
    /// Sensor axis recorded (x, y or z of the vehicle frame).
    pub axis: char,
    /// +1, or -1 for a sensor mounted against the vehicle axis.
    pub sign: f64,
    /// Unit of the recorded numbers; `None`: take it from the CSV header.
    pub unit: Option<Unit>,
    /// Calibration gain: physical value = gain * sign * recorded value (in `unit`).
    pub gain: f64,
    /// Subtract each curve's mean before the obstacle (a DC accelerometer's gravity or
    /// offset); applied to the simulated channel alike.
    pub zero_before_obstacle: bool,
}

/// The acquisition low-pass (Butterworth, see [`super::filter`]).
#[derive(Clone, Copy, Debug)]
pub struct AcqFilter {
    /// Filter order.
    pub order: usize,
    /// -3 dB cut-off frequency [Hz].
    pub cutoff_hz: f64,
}

/// Trigger information on the recording's clock.
#[derive(Clone, Debug)]
pub struct Trigger {
    /// Front-wheel contact point relative to the obstacle start [m] when the photocell
    /// fires (negative: before the obstacle).
    pub photocell_position_m: f64,
    /// When the photocell pulse was recorded [s].
    pub photocell_time_s: f64,
    /// Foils: (front-wheel position relative to the obstacle start [m], pulse time [s]).
    pub foils: Vec<(f64, f64)>,
}

/// What a synthetic run was made with (informational; validation does not use it).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Injected {
    /// Name of the simulator that made the run.
    pub simulator: String,
    /// Trigger delay put in [s].
    pub trigger_delay_s: f64,
    /// Speedometer error put in [%].
    pub speed_error_pct: f64,
    /// Channel gain error put in [%].
    pub gain_error_pct: f64,
    /// RMS of the white noise added [m/s^2].
    pub noise_rms_mps2: f64,
    /// RMS jitter of the foil pulses [s].
    pub foil_jitter_s: f64,
    /// Sample rate of the synthetic recording [Hz].
    pub sample_rate_hz: f64,
    /// Seed of the noise generator.
    pub seed: u64,
}

/// A checked descriptor with paths resolved against its directory.
#[derive(Clone, Debug)]
pub struct Descriptor {
    /// The descriptor file.
    pub path: PathBuf,
    /// Labelled synthetic (made by `validate synth`, not measured).
    pub synthetic: bool,
    /// The scene the run is simulated with.
    pub scene: PathBuf,
    /// Name of the obstacle driven over (as in the measurement plan).
    pub obstacle: String,
    /// Nominal (speedometer) speed [m/s].
    pub nominal_speed_mps: f64,
    /// Trailer load case.
    pub load_case: String,
    /// The CSV file with the recording.
    pub data: PathBuf,
    /// Name of the time column in the CSV header.
    pub time_column: String,
    /// The acquisition low-pass.
    pub filter: AcqFilter,
    /// Photocell and foil pulses.
    pub trigger: Trigger,
    /// The recorded channels and their simulated counterparts.
    pub channels: Vec<ChannelSpec>,
    /// What a synthetic run was made with; `None` for measurements.
    pub injected: Option<Injected>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    #[serde(default)]
    synthetic: bool,
    scene: String,
    obstacle: String,
    nominal_speed_kmh: f64,
    load_case: String,
    data: String,
    #[serde(default = "default_time")]
    time_column: String,
    acquisition: AcqToml,
    trigger: TriggerToml,
    channel: Vec<ChannelToml>,
    injected: Option<Injected>,
}

fn default_time() -> String {
    "time".into()
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AcqToml {
    filter: String,
    order: i64,
    cutoff_hz: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TriggerToml {
    photocell_position_m: f64,
    photocell_time_s: f64,
    foil: Vec<FoilToml>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FoilToml {
    position_m: f64,
    time_s: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ChannelToml {
    column: String,
    simulated: String,
    axis: String,
    #[serde(default = "one")]
    sign: i64,
    unit: Option<String>,
    #[serde(default = "onef")]
    gain: f64,
    #[serde(default)]
    zero_before_obstacle: bool,
}

fn one() -> i64 {
    1
}

fn onef() -> f64 {
    1.0
}

impl Descriptor {
    /// Reads and checks a descriptor.
    pub fn from_file(path: &Path) -> Result<Descriptor, InputError> {
        Descriptor::from_source(&Source::read(path)?)
    }

    /// Checks an already read descriptor.
    pub fn from_source(src: &Source) -> Result<Descriptor, InputError> {
        let f: File = src.parse()?;
        let nonempty = |field: &str, v: &str| {
            if v.trim().is_empty() {
                Err(src.error(&path![field], "must not be empty"))
            } else {
                Ok(())
            }
        };
        nonempty("scene", &f.scene)?;
        nonempty("obstacle", &f.obstacle)?;
        nonempty("data", &f.data)?;
        let speed = src.positive(&path!["nominal_speed_kmh"], f.nominal_speed_kmh)?;
        let known = super::plan::load_cases();
        if !known.contains(&f.load_case) {
            return Err(src.error(
                &path!["load_case"],
                format!(
                    "unknown load case `{}` (the measurement plan's: {})",
                    f.load_case,
                    known.join(", ")
                ),
            ));
        }
        if f.acquisition.filter != "butterworth" {
            return Err(src.error(
                &path!["acquisition", "filter"],
                format!(
                    "only `butterworth` is supported, got `{}`",
                    f.acquisition.filter
                ),
            ));
        }
        if !(1..=10).contains(&f.acquisition.order) {
            return Err(src.error(&path!["acquisition", "order"], "must be 1 ..= 10"));
        }
        let cutoff = src.positive(&path!["acquisition", "cutoff_hz"], f.acquisition.cutoff_hz)?;
        let t = &f.trigger;
        src.finite(
            &path!["trigger", "photocell_position_m"],
            t.photocell_position_m,
        )?;
        src.finite(&path!["trigger", "photocell_time_s"], t.photocell_time_s)?;
        let mut foils = Vec::new();
        for (i, foil) in t.foil.iter().enumerate() {
            src.finite(&path!["trigger", "foil", i, "position_m"], foil.position_m)?;
            src.finite(&path!["trigger", "foil", i, "time_s"], foil.time_s)?;
            if let Some(j) = foils.iter().position(|&(x, _)| x == foil.position_m) {
                return Err(src.error(
                    &path!["trigger", "foil", i, "position_m"],
                    format!("same position as foil {j}"),
                ));
            }
            foils.push((foil.position_m, foil.time_s));
        }
        if foils.len() < 2 {
            return Err(src.error(
                &path!["trigger", "foil"],
                "at least two foils are needed for the speed",
            ));
        }
        if let Err(msg) = super::trigger::speed_from_foils(&foils) {
            return Err(src.error(&path!["trigger", "foil"], msg.to_string()));
        }
        let mut channels: Vec<ChannelSpec> = Vec::new();
        if f.channel.is_empty() {
            return Err(src.error(&path!["channel"], "no channels"));
        }
        for (i, c) in f.channel.iter().enumerate() {
            let at = |k: &str| path!["channel", i, k];
            if c.column.trim().is_empty() {
                return Err(src.error(&at("column"), "must not be empty"));
            }
            if channels.iter().any(|o| o.simulated == c.simulated) {
                return Err(src.error(&at("simulated"), "this simulated channel is listed twice"));
            }
            let axis = match c.axis.as_str() {
                "x" | "y" | "z" => c.axis.chars().next().unwrap_or('z'),
                _ => return Err(src.error(&at("axis"), "must be x, y or z")),
            };
            // A simulated name ending in _x/_y/_z must agree with the axis: a swapped
            // channel would otherwise be compared silently.
            if let Some(suffix) = c.simulated.rsplit('_').next() {
                if matches!(suffix, "x" | "y" | "z") && !suffix.starts_with(axis) {
                    return Err(src.error(
                        &at("axis"),
                        format!("axis {axis} but the simulated channel is `{}`", c.simulated),
                    ));
                }
            }
            if c.sign != 1 && c.sign != -1 {
                return Err(src.error(&at("sign"), "must be 1 or -1"));
            }
            let unit = match &c.unit {
                None => None,
                Some(u) => Some(Unit::parse(u).ok_or_else(|| {
                    src.error(&at("unit"), format!("unknown unit `{u}` (m/s^2 or g)"))
                })?),
            };
            let gain = src.positive(&at("gain"), c.gain)?;
            channels.push(ChannelSpec {
                column: c.column.trim().to_string(),
                simulated: c.simulated.clone(),
                axis,
                sign: c.sign as f64,
                unit,
                gain,
                zero_before_obstacle: c.zero_before_obstacle,
            });
        }
        if f.injected.is_some() && !f.synthetic {
            return Err(src.error(&path!["injected"], "only synthetic runs have [injected]"));
        }
        Ok(Descriptor {
            path: src.path.clone(),
            synthetic: f.synthetic,
            // Read later, by the validation (a descriptor is also read for its data alone).
            scene: src.path.parent().unwrap_or(Path::new(".")).join(&f.scene),
            obstacle: f.obstacle,
            nominal_speed_mps: speed / 3.6,
            load_case: f.load_case,
            data: src.existing_file(&path!["data"], &f.data)?,
            time_column: f.time_column,
            filter: AcqFilter {
                order: f.acquisition.order as usize,
                cutoff_hz: cutoff,
            },
            trigger: Trigger {
                photocell_position_m: t.photocell_position_m,
                photocell_time_s: t.photocell_time_s,
                foils,
            },
            channels,
            injected: f.injected,
        })
    }

    /// The run's name: the descriptor's file stem.
    pub fn name(&self) -> String {
        self.path
            .file_stem()
            .map_or("run".into(), |s| s.to_string_lossy().to_string())
    }
}
