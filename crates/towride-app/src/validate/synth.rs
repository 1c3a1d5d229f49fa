//! Synthetic measurements: a simulation passed through a documented sensor model and
//! written as CSV + descriptor, both labelled synthetic (`synthetic = true`, a header
//! comment, and an `[injected]` table recording what was put in).
//!
//! Sensor model (docs/validation.md): the run is simulated at the true speed, the
//! speedometer (the descriptor's nominal speed) reads `speed_error_pct` high; the
//! acquisition low-pass is applied; samples are taken at `sample_rate_hz` on a clock whose
//! zero is the recorded photocell pulse, which fires `trigger_delay_s` after the car
//! passes the photocell (every foil pulse carries the same latency plus white jitter of
//! RMS `foil_jitter_s`); each channel reads (1 + gain error) times the true value (the
//! descriptor keeps gain 1, as if the calibration were unaware); white noise of RMS
//! `noise_rms_mps2` is added to every sample.

use super::ValidateError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::descriptor::{AcqFilter, Unit};
use super::filter::acquire;
use super::Simulator;
use crate::scene::channels::ACC_PREFIX;

/// The documented sensor model; the defaults are docs/validation.md's values (37 ms
/// trigger delay, speedometer +3 %, gain +5 %, 0.05 m/s^2 noise).
#[derive(Clone, Debug)]
pub struct SensorModel {
    /// RMS of the white noise added to every sample [m/s^2].
    pub noise_rms_mps2: f64,
    /// The acquisition low-pass.
    pub filter: AcqFilter,
    /// Delay of the photocell pulse after the car passes the photocell [s].
    pub trigger_delay_s: f64,
    /// The nominal (speedometer) speed reads this much above the true speed [%].
    pub speed_error_pct: f64,
    /// Every channel reads this much high [%] unless listed in `channel_gain_error_pct`.
    pub gain_error_pct: f64,
    /// Per-channel gain errors [%], overriding `gain_error_pct` for the channels listed.
    pub channel_gain_error_pct: Vec<(String, f64)>,
    /// Sample rate of the recording [Hz].
    pub sample_rate_hz: f64,
    /// RMS jitter of the foil pulses [s].
    pub foil_jitter_s: f64,
    /// Unit written to the CSV.
    pub unit: Unit,
    /// Seed of the noise generator.
    pub seed: u64,
    /// RMS of a constant offset drawn once per channel and added to every sample [m/s^2]
    /// (a sensor's zero error; the descriptor then zeroes each channel before the
    /// obstacle, as a recording with offsets needs).
    pub offset_rms_mps2: f64,
    /// RMS of the run-to-run scatter of the photocell's delay [s] (drawn once per run and
    /// added to `trigger_delay_s`: the timing error the cross-correlation must find).
    pub trigger_jitter_s: f64,
    /// Decimals of the time column (a logger's quantised time stamps; 6 by default).
    pub time_decimals: usize,
}

impl Default for SensorModel {
    fn default() -> Self {
        SensorModel {
            noise_rms_mps2: 0.05,
            filter: AcqFilter {
                order: 4,
                cutoff_hz: 100.0,
            },
            trigger_delay_s: 0.037,
            speed_error_pct: 3.0,
            gain_error_pct: 5.0,
            channel_gain_error_pct: Vec::new(),
            sample_rate_hz: 1000.0,
            foil_jitter_s: 1e-4,
            unit: Unit::Mps2,
            seed: 1,
            offset_rms_mps2: 0.0,
            trigger_jitter_s: 0.0,
            time_decimals: 6,
        }
    }
}

/// Where the photocell and the foils are, relative to the obstacle start [m] (front-wheel
/// contact point when each pulse fires).
#[derive(Clone, Debug)]
pub struct TriggerLayout {
    /// Photocell position [m].
    pub photocell_m: f64,
    /// Foil positions [m].
    pub foils_m: Vec<f64>,
}

impl Default for TriggerLayout {
    fn default() -> Self {
        // As in the thesis: the trigger foil before the obstacle, two more at known spacing.
        TriggerLayout {
            photocell_m: -10.0,
            foils_m: vec![-10.0, -6.0, -2.0],
        }
    }
}

/// One run to synthesise.
#[derive(Clone, Debug)]
pub struct SynthRun {
    /// Run name (file stem of the CSV and descriptor written).
    pub name: String,
    /// The scene simulated.
    pub scene: PathBuf,
    /// Name of the obstacle driven over.
    pub obstacle: String,
    /// Nominal (speedometer) speed [km/h].
    pub nominal_speed_kmh: f64,
    /// Trailer load case.
    pub load_case: String,
    /// The overrides (`FILE:PATH=VALUE`) the simulating model was made with: a "true"
    /// vehicle that differs from the files (recorded in the descriptor's `[injected]`).
    pub truth: Vec<String>,
}

/// Deterministic normal deviates (SplitMix64 + Box-Muller): the same seed gives the same
/// file on every machine.
pub struct Noise(u64);

impl Noise {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Noise {
        Noise(seed)
    }

    /// A uniform deviate in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A standard normal deviate.
    pub fn normal(&mut self) -> f64 {
        let u1 = self.uniform().max(1e-300);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}

/// `target` relative to directory `base` (both made absolute), with `/` separators.
pub fn relative_path(target: &Path, base: &Path) -> String {
    let abs = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
    let (t, b) = (abs(target), abs(base));
    let (tc, bc): (Vec<_>, Vec<_>) = (t.components().collect(), b.components().collect());
    let common = tc.iter().zip(&bc).take_while(|(a, b)| a == b).count();
    let mut parts: Vec<String> = vec!["..".into(); bc.len() - common];
    parts.extend(
        tc[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().to_string()),
    );
    parts.join("/")
}

/// First line of every synthetic CSV, by which a rewrite knows its own file.
const CSV_MARK: &str = "# SYNTHETIC DATA, not a measurement";

/// Refuses when a file `runs` would write into `out` exists and is not a synthetic run
/// (a recording, or anything else: it would be lost), or is the run's scene. Checked
/// for every run before the first is simulated.
pub fn targets_free(runs: &[SynthRun], out: &Path) -> Result<(), ValidateError> {
    for run in runs {
        for ext in ["csv", "toml"] {
            let path = out.join(format!("{}.{ext}", run.name));
            if towride_mbs::input::regular::same_file(&path, &run.scene) {
                return Err(ValidateError::WouldOverwrite {
                    path,
                    why: "is the scene this synthetic run simulates".into(),
                });
            }
            if !path.exists() {
                continue;
            }
            // Read only the head: a recording may be large.
            let head = read_head(&path);
            let ours = if ext == "csv" {
                head.starts_with(CSV_MARK)
            } else {
                head.lines().any(|l| l.trim() == "synthetic = true")
            };
            if !ours {
                return Err(ValidateError::WouldOverwrite {
                    path,
                    why: "exists and is not a synthetic run made by `validate synth` (a \
                          recording?)"
                        .into(),
                });
            }
        }
    }
    Ok(())
}

/// The first 4 KiB of `path` as text (lossy); empty when unreadable.
fn read_head(path: &Path) -> String {
    use std::io::Read as _;
    let mut buf = Vec::new();
    if let Ok(f) = std::fs::File::open(path) {
        let _ = f.take(4096).read_to_end(&mut buf);
    }
    String::from_utf8_lossy(&buf).into_owned()
}

/// Simulates `run` with `sim`, applies `sensor`, and writes `<out>/<name>.csv` and
/// `<out>/<name>.toml`; returns the descriptor's path.
pub fn make_synthetic(
    sim: &dyn Simulator,
    run: &SynthRun,
    sensor: &SensorModel,
    layout: &TriggerLayout,
    out: &Path,
) -> Result<PathBuf, ValidateError> {
    let s = sensor;
    targets_free(std::slice::from_ref(run), out)?;
    // The folder must exist before paths can be made relative to it.
    std::fs::create_dir_all(out).map_err(|e| ValidateError::Io {
        path: out.to_path_buf(),
        source: e,
    })?;
    let v_true = run.nominal_speed_kmh / 3.6 / (1.0 + s.speed_error_pct / 100.0);
    let simulated = sim
        .simulate(&run.scene, v_true, &run.load_case)
        .map_err(|e| ValidateError::Simulation(Box::new(e)))?;
    let acq = acquire(&simulated, s.filter)?;
    let mut noise = Noise::new(s.seed);
    // This run's photocell delay: the nominal one plus its run-to-run scatter.
    // (No deviate is drawn without scatter: the default files stay as they were.)
    let delay = match s.trigger_jitter_s {
        j if j > 0.0 => s.trigger_delay_s + j * noise.normal(),
        _ => s.trigger_delay_s,
    };
    // Recording clock: the photocell pulse is stamped 0, `delay` after the passage.
    let t_obs = -delay - layout.photocell_m / v_true;
    let to_sim = |t_rec: f64| t_rec - t_obs + acq.obstacle_time_s;
    let (s0, s1) = acq.span();
    let fs = s.sample_rate_hz;
    let k0 = ((s0 + t_obs - acq.obstacle_time_s) * fs).ceil() as i64;
    let k1 = ((s1 - 0.1 + t_obs - acq.obstacle_time_s) * fs).floor() as i64;
    if k1 - k0 < 20 {
        return Err(ValidateError::Signal(format!(
            "{}: the simulation is too short to record",
            run.name
        )));
    }
    let names: Vec<&String> = acq.channels.keys().collect();
    let offsets: Vec<f64> = names
        .iter()
        .map(|_| match s.offset_rms_mps2 {
            o if o > 0.0 => o * noise.normal(),
            _ => 0.0,
        })
        .collect();
    let unit = s.unit.to_si();
    let gain = |n: &str| {
        let pct = s
            .channel_gain_error_pct
            .iter()
            .find(|(c, _)| c == n)
            .map_or(s.gain_error_pct, |c| c.1);
        1.0 + pct / 100.0
    };
    let column = |n: &str| n.strip_prefix(ACC_PREFIX).unwrap_or(n).to_string();
    let injected = format!(
        "trigger delay {} ms (this run {:.3} ms), speedometer +{} %, gain error +{} %, noise {} m/s^2 RMS, offsets {} m/s^2 RMS, foil jitter {} ms RMS, {}th-order {} Hz Butterworth, {} Hz, time to {} decimals, seed {}",
        s.trigger_delay_s * 1e3, delay * 1e3, s.speed_error_pct, s.gain_error_pct, s.noise_rms_mps2,
        s.offset_rms_mps2, s.foil_jitter_s * 1e3, s.filter.order, s.filter.cutoff_hz, fs,
        s.time_decimals, s.seed
    );
    let mut csv = format!(
        "{CSV_MARK}: made by `towride validate synth` with the {}\n# sensor model: {injected}\ntime [s]",
        sim.name()
    );
    for n in &names {
        let _ = write!(csv, ",{} [{}]", column(n), s.unit.label());
    }
    csv.push('\n');
    for k in k0..=k1 {
        let t = k as f64 / fs;
        // Sampled at t, stamped with the logger's resolution.
        let _ = write!(csv, "{t:.*}", s.time_decimals);
        for (n, off) in names.iter().zip(&offsets) {
            let v = gain(n) * acq.at(n, to_sim(t)) + off + s.noise_rms_mps2 * noise.normal();
            let _ = write!(csv, ",{:.6}", v / unit);
        }
        csv.push('\n');
    }
    let csv_path = out.join(format!("{}.csv", run.name));
    crate::atomic::write(&csv_path, csv).map_err(|e| ValidateError::Io {
        path: csv_path.clone(),
        source: e,
    })?;
    let mut toml = format!(
        "# SYNTHETIC run, not a measurement: {} simulated by the {} and passed through the\n# sensor model of docs/validation.md ({injected}).\nsynthetic = true\nscene = \"{}\"\nobstacle = \"{}\"\nnominal_speed_kmh = {:?}\nload_case = \"{}\"\ndata = \"{}.csv\"\n\n[acquisition]\nfilter = \"butterworth\"\norder = {}\ncutoff_hz = {:?}\n\n[trigger]\nphotocell_position_m = {:?}\nphotocell_time_s = 0.0\n",
        run.name, sim.name(), relative_path(&run.scene, out), run.obstacle, run.nominal_speed_kmh,
        run.load_case, run.name, s.filter.order, s.filter.cutoff_hz, layout.photocell_m
    );
    for &x in &layout.foils_m {
        let t = t_obs + x / v_true + delay + s.foil_jitter_s * noise.normal();
        let _ = write!(
            toml,
            "\n[[trigger.foil]]\nposition_m = {x:?}\ntime_s = {t:.7}\n"
        );
    }
    for n in &names {
        let axis = n
            .rsplit('_')
            .next()
            .filter(|a| matches!(*a, "x" | "y" | "z"))
            .unwrap_or("z");
        let _ = write!(toml, "\n[[channel]]\ncolumn = \"{}\"\nsimulated = \"{n}\"\naxis = \"{axis}\"\nsign = 1\ngain = 1.0\n", column(n));
        if s.offset_rms_mps2 > 0.0 {
            toml.push_str("zero_before_obstacle = true\n");
        }
    }
    let _ = write!(
        toml,
        "\n[injected]\nsimulator = \"{}\"\ntrigger_delay_s = {:?}\nspeed_error_pct = {:?}\ngain_error_pct = {:?}\nnoise_rms_mps2 = {:?}\noffset_rms_mps2 = {:?}\nfoil_jitter_s = {:?}\ntrigger_jitter_s = {:?}\nsample_rate_hz = {:?}\nseed = {}\ntruth = {:?}\n",
        sim.name(), delay, s.speed_error_pct, s.gain_error_pct, s.noise_rms_mps2, s.offset_rms_mps2, s.foil_jitter_s, s.trigger_jitter_s, fs, s.seed, run.truth
    );
    let desc = out.join(format!("{}.toml", run.name));
    crate::atomic::write(&desc, toml).map_err(|e| ValidateError::Io {
        path: desc.clone(),
        source: e,
    })?;
    Ok(desc)
}
