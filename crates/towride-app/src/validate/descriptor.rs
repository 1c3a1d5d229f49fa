//! The TOML descriptor of a measured run: which scene it belongs to, how its CSV's time
//! base and columns map onto simulated channels, where its speed comes from (foils, a
//! speed channel or the nominal speed), the acquisition filter, the sensor ranges, and
//! optionally the trigger. Read through [`Source`], so every error names file, line and
//! field. The format is documented in `docs/validation.md`.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use towride_mbs::input::{InputError, Source};
use towride_mbs::path;

pub use super::units::{SpeedUnit, Unit};

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
    /// Unit of the recorded numbers; `None`: take it from the CSV header or units row.
    pub unit: Option<Unit>,
    /// Calibration gain: physical value = gain * sign * recorded value (in `unit`).
    pub gain: f64,
    /// Subtract each curve's mean before the obstacle (a DC accelerometer's gravity or
    /// offset); applied to the simulated channel alike.
    pub zero_before_obstacle: bool,
    /// Subtract standard gravity after gain and sign: a DC accelerometer on z reads
    /// +1 g at rest, the simulation's kinematic acceleration 0.
    pub remove_gravity: bool,
    /// The sensor's range [g]: recorded samples at it are clipped and left out of the
    /// rating; the simulation is flagged where such a sensor would clip.
    pub range_g: Option<f64>,
    /// A fixed offset [g] subtracted after gain, sign and gravity: the sensor's own bias,
    /// as `validate init` measures it before the passage.
    pub offset_g: f64,
}

/// The acquisition low-pass (Butterworth, see [`super::filter`]): the same type a scene
/// declares its instrument chain with.
pub use crate::signal::acquisition::AcqFilter;

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

/// A recorded vehicle-speed channel.
#[derive(Clone, Debug)]
pub struct SpeedChannel {
    /// Column name in the CSV header.
    pub column: String,
    /// Unit; `None`: from the header or units row.
    pub unit: Option<SpeedUnit>,
}

/// How the obstacle passage is found in the signals when no trigger is given.
#[derive(Clone, Debug, Default)]
pub struct PassageSpec {
    /// Front to rear axle [m]; default: the scene's vehicle.
    pub wheelbase_m: Option<f64>,
    /// Front axle to the trailer's axle [m]; default: the scene's vehicle.
    pub trailer_axle_m: Option<f64>,
    /// Simulated channel names of the front axle's unsprung accelerations; default:
    /// the channels named `wheel` and `front`.
    pub front: Option<Vec<String>>,
    /// The rear axle's (default: `wheel` and `rear`).
    pub rear: Option<Vec<String>>,
    /// The trailer axle's (default: `wheel` and `trailer`).
    pub trailer: Option<Vec<String>>,
    /// Look for the front axle's passage only inside this interval [s].
    pub search_s: Option<[f64; 2]>,
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
    /// RMS of the constant per-channel offsets added [m/s^2].
    #[serde(default)]
    pub offset_rms_mps2: f64,
    /// RMS of the run-to-run scatter of the trigger delay [s].
    #[serde(default)]
    pub trigger_jitter_s: f64,
    /// The overrides the simulating ("true") model was made with.
    #[serde(default)]
    pub truth: Vec<String>,
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
    /// Name of the obstacle driven over (default: the scene's road file stem).
    pub obstacle: String,
    /// Nominal (speedometer) speed [m/s], if given.
    pub nominal_speed_mps: Option<f64>,
    /// Trailer load case; `None`: the scene's own.
    pub load_case: Option<String>,
    /// The CSV file with the recording.
    pub data: PathBuf,
    /// Name of the time column in the CSV header.
    pub time_column: String,
    /// The time column was named in the descriptor (not the default `time`).
    pub time_column_given: bool,
    /// Declared sample rate [Hz]: the time base when the file has no time column, a
    /// check of the time column's rate otherwise.
    pub sample_rate_hz: Option<f64>,
    /// The acquisition low-pass.
    pub filter: AcqFilter,
    /// Pass the recording through the same low-pass too (a logger sampling far above
    /// the band of interest, whose own anti-alias filter is unknown).
    pub filter_measurement: bool,
    /// Photocell and foil pulses, if recorded.
    pub trigger: Option<Trigger>,
    /// The vehicle-speed channel, if recorded.
    pub speed: Option<SpeedChannel>,
    /// How the passage is found in the signals.
    pub passage: PassageSpec,
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
    obstacle: Option<String>,
    nominal_speed_kmh: Option<f64>,
    load_case: Option<String>,
    data: String,
    time_column: Option<String>,
    sample_rate_hz: Option<f64>,
    acquisition: AcqToml,
    trigger: Option<TriggerToml>,
    speed: Option<SpeedToml>,
    passage: Option<PassageToml>,
    channel: Vec<ChannelToml>,
    injected: Option<Injected>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AcqToml {
    filter: String,
    order: i64,
    cutoff_hz: f64,
    /// "as_recorded" (default) or "filtered".
    measurement: Option<String>,
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
struct SpeedToml {
    column: String,
    unit: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PassageToml {
    wheelbase_m: Option<f64>,
    trailer_axle_m: Option<f64>,
    front: Option<Vec<String>>,
    rear: Option<Vec<String>>,
    trailer: Option<Vec<String>>,
    search_s: Option<[f64; 2]>,
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
    #[serde(default)]
    remove_gravity: bool,
    range_g: Option<f64>,
    #[serde(default)]
    offset_g: f64,
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
        nonempty("data", &f.data)?;
        // Read later, by the validation (a descriptor is also read for its data alone).
        let scene = src.path.parent().unwrap_or(Path::new(".")).join(&f.scene);
        let obstacle = match &f.obstacle {
            Some(o) => {
                nonempty("obstacle", o)?;
                o.clone()
            }
            None => super::scene_info::road_name(&scene).unwrap_or_else(|| "obstacle".into()),
        };
        let nominal = match f.nominal_speed_kmh {
            Some(v) => Some(src.positive(&path!["nominal_speed_kmh"], v)? / 3.6),
            None => None,
        };
        if let Some(case) = &f.load_case {
            let (known, whose) = super::scene_info::load_cases(&scene);
            if let Some(known) = known.filter(|k| !k.contains(case)) {
                return Err(src.error(
                    &path!["load_case"],
                    format!("unknown load case `{case}` ({whose}: {})", known.join(", ")),
                ));
            }
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
        let filter_measurement = match f.acquisition.measurement.as_deref() {
            None | Some("as_recorded") => false,
            Some("filtered") => true,
            Some(x) => {
                return Err(src.error(
                    &path!["acquisition", "measurement"],
                    format!("`{x}`: use as_recorded or filtered"),
                ))
            }
        };
        let rate = match f.sample_rate_hz {
            Some(r) => Some(src.positive(&path!["sample_rate_hz"], r)?),
            None => None,
        };
        if let Some(t) = &f.time_column {
            nonempty("time_column", t)?;
        }
        let trigger = f.trigger.as_ref().map(|t| trigger(src, t)).transpose()?;
        let speed = match &f.speed {
            None => None,
            Some(s) => {
                nonempty("speed", &s.column)?;
                let unit = match &s.unit {
                    None => None,
                    Some(u) => Some(SpeedUnit::parse(u).ok_or_else(|| {
                        src.error(
                            &path!["speed", "unit"],
                            format!("unknown unit `{u}` (km/h, m/s or mph)"),
                        )
                    })?),
                };
                Some(SpeedChannel {
                    column: s.column.trim().to_string(),
                    unit,
                })
            }
        };
        if trigger.is_none() && speed.is_none() && nominal.is_none() {
            return Err(src.error(
                &path!["nominal_speed_kmh"],
                "no speed: give [trigger] foils, a [speed] channel or nominal_speed_kmh",
            ));
        }
        let passage = match &f.passage {
            None => PassageSpec::default(),
            Some(p) => passage(src, p)?,
        };
        let channels = channels(src, &f.channel)?;
        if f.injected.is_some() && !f.synthetic {
            return Err(src.error(&path!["injected"], "only synthetic runs have [injected]"));
        }
        Ok(Descriptor {
            path: src.path.clone(),
            synthetic: f.synthetic,
            scene,
            obstacle,
            nominal_speed_mps: nominal,
            load_case: f.load_case,
            data: src.existing_file(&path!["data"], &f.data)?,
            time_column_given: f.time_column.is_some(),
            time_column: f.time_column.unwrap_or_else(|| "time".into()),
            sample_rate_hz: rate,
            filter: AcqFilter {
                order: f.acquisition.order as usize,
                cutoff_hz: cutoff,
            },
            filter_measurement,
            trigger,
            speed,
            passage,
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

fn trigger(src: &Source, t: &TriggerToml) -> Result<Trigger, InputError> {
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
    Ok(Trigger {
        photocell_position_m: t.photocell_position_m,
        photocell_time_s: t.photocell_time_s,
        foils,
    })
}

fn passage(src: &Source, p: &PassageToml) -> Result<PassageSpec, InputError> {
    let pos = |k: &str, v: Option<f64>| -> Result<Option<f64>, InputError> {
        v.map(|x| src.positive(&path!["passage", k], x)).transpose()
    };
    if let Some([a, b]) = p.search_s {
        src.finite(&path!["passage", "search_s", 0], a)?;
        src.finite(&path!["passage", "search_s", 1], b)?;
        if b <= a {
            return Err(src.error(
                &path!["passage", "search_s"],
                "must be [start, end] with end > start",
            ));
        }
    }
    for (k, l) in [
        ("front", &p.front),
        ("rear", &p.rear),
        ("trailer", &p.trailer),
    ] {
        if l.as_ref().is_some_and(|l| l.is_empty()) {
            return Err(src.error(
                &path!["passage", k],
                "name at least one channel or leave it out",
            ));
        }
    }
    Ok(PassageSpec {
        wheelbase_m: pos("wheelbase_m", p.wheelbase_m)?,
        trailer_axle_m: pos("trailer_axle_m", p.trailer_axle_m)?,
        front: p.front.clone(),
        rear: p.rear.clone(),
        trailer: p.trailer.clone(),
        search_s: p.search_s,
    })
}

fn channels(src: &Source, list: &[ChannelToml]) -> Result<Vec<ChannelSpec>, InputError> {
    let mut channels: Vec<ChannelSpec> = Vec::new();
    if list.is_empty() {
        return Err(src.error(&path!["channel"], "no channels"));
    }
    for (i, c) in list.iter().enumerate() {
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
                src.error(&at("unit"), format!("unknown unit `{u}` (m/s^2, g or gn)"))
            })?),
        };
        let gain = src.positive(&at("gain"), c.gain)?;
        if c.remove_gravity && axis != 'z' {
            return Err(src.error(
                &at("remove_gravity"),
                "only a z (vertical) sensor reads gravity at rest",
            ));
        }
        if c.remove_gravity && c.zero_before_obstacle {
            return Err(src.error(
                &at("remove_gravity"),
                "give remove_gravity or zero_before_obstacle, not both",
            ));
        }
        let range_g = c
            .range_g
            .map(|r| src.positive(&at("range_g"), r))
            .transpose()?;
        channels.push(ChannelSpec {
            column: c.column.trim().to_string(),
            simulated: c.simulated.clone(),
            axis,
            sign: c.sign as f64,
            unit,
            gain,
            zero_before_obstacle: c.zero_before_obstacle,
            remove_gravity: c.remove_gravity,
            range_g,
            offset_g: src.finite(&at("offset_g"), c.offset_g)?,
        });
    }
    Ok(channels)
}
