//! Many runs at once: every descriptor under a folder, one summary table (CSV + JSON).
//! A run that fails is reported with its error and does not stop the others.

use super::ValidateError;
use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use super::pipeline::{validate_run, ChannelFigures, Comparison, Options, RunValidation};
use super::Simulator;

/// The outcome of a batch.
#[derive(Debug, Default)]
pub struct FolderResult {
    /// The runs validated, in descriptor order.
    pub runs: Vec<RunValidation>,
    /// (descriptor, error) of each run that could not be validated.
    pub failures: Vec<(PathBuf, String)>,
    /// Descriptors an interruption (Ctrl-C) kept from being validated.
    pub not_run: Vec<PathBuf>,
    /// Wall-clock time of the batch [s].
    pub wall_s: f64,
    /// The simulator's name (so a stand-in is never mistaken for the vehicle model).
    pub simulator: String,
}

/// `path` itself if it is a file, else every `*.toml` below it (recursively, sorted).
pub fn find_descriptors(path: &Path) -> Result<Vec<PathBuf>, ValidateError> {
    if path.is_file() {
        return Ok(vec![path.to_path_buf()]);
    }
    let mut out = Vec::new();
    let mut stack = vec![path.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let entries = std::fs::read_dir(&dir).map_err(|e| ValidateError::Io {
            path: dir.clone(),
            source: e,
        })?;
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "toml") {
                out.push(p);
            }
        }
    }
    out.sort();
    if out.is_empty() {
        return Err(ValidateError::Signal(format!(
            "{}: no *.toml descriptors found",
            path.display()
        )));
    }
    Ok(out)
}

/// Validates every descriptor in `files`; `progress(i, file)` is called before each.
pub fn validate_folder(
    files: &[PathBuf],
    sim: &dyn Simulator,
    opts: &Options,
    progress: &dyn Fn(usize, &Path),
) -> FolderResult {
    validate_folder_until(files, sim, opts, progress, &|| false)
}

/// [`validate_folder`], starting no further run once `stop()` holds (Ctrl-C): the
/// runs not validated are listed in [`FolderResult::not_run`].
pub fn validate_folder_until(
    files: &[PathBuf],
    sim: &dyn Simulator,
    opts: &Options,
    progress: &dyn Fn(usize, &Path),
    stop: &dyn Fn() -> bool,
) -> FolderResult {
    let wall = std::time::Instant::now();
    let mut res = FolderResult {
        simulator: sim.name(),
        ..FolderResult::default()
    };
    for (i, f) in files.iter().enumerate() {
        if stop() {
            res.not_run = files[i..].to_vec();
            break;
        }
        progress(i, f);
        match validate_run(f, sim, opts) {
            Ok(r) => res.runs.push(r),
            Err(e) => res.failures.push((f.clone(), e.to_string())),
        }
    }
    res.wall_s = wall.elapsed().as_secs_f64();
    res
}

fn figures(c: &Comparison, f: &ChannelFigures) -> Value {
    json!({
        "peak_measured_mps2": f.peak_measured_mps2,
        "t_peak_measured_s": f.t_peak_measured_s,
        "peak_simulated_mps2": f.peak_simulated_mps2,
        "t_peak_simulated_s": f.t_peak_simulated_s,
        "rms_diff_mps2": f.rms_diff_mps2,
        "correlation": f.correlation,
        "gain_ratio": f.gain_ratio,
        "rating": f.rating.overall,
        "scores": f.rating,
        "shift_s": c.shift_s,
        "speed_mps": c.speed_mps,
        "clipped_samples": f.clipped_samples,
        "simulated_clipped_samples": f.simulated_clipped_samples,
        "signal_to_noise": f.signal_to_noise,
        "has_signal": f.has_signal,
    })
}

/// Layout version of the `validate --json` document and `summary.json`. 2: `status`
/// and `not_run` (a batch stopped by Ctrl-C). 3: each run's `obstacle_geometry` (the
/// road file's obstacle values, their source classes and which are assumed).
pub const SCHEMA_VERSION: u32 = 3;

/// One run as JSON: the run's speed, time base, passage and per channel the clipping,
/// the dominant frequencies and the corrected and uncorrected figures.
pub fn run_json(r: &RunValidation) -> Value {
    let channels: Vec<Value> = r
        .uncorrected
        .channels
        .iter()
        .enumerate()
        .map(|(i, u)| {
            let mut v = json!({ "channel": u.channel, "uncorrected": figures(&r.uncorrected, u) });
            if let Some(c) = &r.corrected {
                v["corrected"] = figures(c, &c.channels[i]);
            }
            if let Some(x) = r.channels.get(i) {
                v["range_g"] = json!(x.range_g);
                v["clipped_samples"] = json!(x.clipped_samples);
                v["simulated_clipped_samples"] = json!(x.simulated_clipped_samples);
                v["measured_hz"] = json!(x.measured_hz);
                v["simulated_hz"] = json!(x.simulated_hz);
            }
            v
        })
        .collect();
    json!({
        "run": r.name,
        "descriptor": r.descriptor,
        "synthetic": r.synthetic,
        "obstacle": r.obstacle,
        "obstacle_geometry": r.obstacle_geometry,
        "load_case": r.load_case,
        "nominal_speed_mps": r.nominal_speed_mps,
        "speed_mps": r.speed.speed_mps,
        "speed_kmh": r.speed.speed_mps * 3.6,
        "speed_source": r.speed.source,
        "speed": r.speed,
        "foil_fit_residual_s": r.speed.foils.map(|f| f.residual_rms_s),
        "obstacle_time_s": r.obstacle_time_s,
        "rear_axle_time_s": r.rear_axle_time_s,
        "implied_wheelbase_m": r.implied_wheelbase_m,
        "wheelbase_m": r.wheelbase_m,
        "passage": r.passage,
        "sample_rate_hz": r.sample_rate_hz,
        "time_base": r.time_base.kind,
        "time_base_detail": r.time_base,
        "shift_s": r.corrected.as_ref().map(|c| c.shift_s),
        "shift_at_bound": r.corrected.as_ref().map(|c| c.shift_at_bound),
        "shift_correlation": r.corrected.as_ref().and_then(|c| c.shift_correlation),
        "mean_rating_corrected": r.corrected.as_ref().map(|c| c.mean_rating),
        "mean_rating_uncorrected": r.uncorrected.mean_rating,
        // Channels of sensor noise alone: rated, but left out of the means.
        "without_signal": r.corrected.as_ref().unwrap_or(&r.uncorrected).without_signal,
        "notes": r.notes,
        "wall_s": r.wall_s,
        "channels": channels,
    })
}

/// The whole batch as JSON.
pub fn summary_json(res: &FolderResult) -> Value {
    json!({
        "schema_version": SCHEMA_VERSION,
        "simulator": res.simulator,
        "runs": res.runs.iter().map(run_json).collect::<Vec<_>>(),
        "failures": res.failures.iter().map(|(f, e)| json!({"descriptor": f.display().to_string(), "error": e})).collect::<Vec<_>>(),
        "status": if res.not_run.is_empty() { "completed" } else { "interrupted" },
        "not_run": res.not_run.iter().map(|f| f.display().to_string()).collect::<Vec<_>>(),
        "wall_s": res.wall_s,
    })
}

/// Writes `dir/summary.csv` (one row per run and channel, failures last with their
/// error), `dir/summary.json` and the trends (`trends.csv`, `trends.html`, [`super::trends`]).
pub fn write_summary(res: &FolderResult, dir: &Path) -> Result<(PathBuf, PathBuf), ValidateError> {
    let e = |x: &dyn std::fmt::Display| ValidateError::Io {
        path: dir.to_path_buf(),
        source: std::io::Error::other(x.to_string()),
    };
    std::fs::create_dir_all(dir).map_err(|x| e(&x))?;
    let csv_path = dir.join("summary.csv");
    let mut w = csv::Writer::from_path(&csv_path).map_err(|x| e(&x))?;
    w.write_record([
        "run",
        "synthetic",
        "obstacle",
        "load_case",
        "nominal_speed [m/s]",
        "speed [m/s]",
        "shift [s]",
        "channel",
        "rating_corrected [-]",
        "rating_uncorrected [-]",
        "corridor [-]",
        "phase [-]",
        "magnitude [-]",
        "slope [-]",
        "peak_measured [m/s^2]",
        "t_peak_measured [s]",
        "peak_simulated [m/s^2]",
        "t_peak_simulated [s]",
        "rms_diff [m/s^2]",
        "correlation [-]",
        "gain_ratio [-]",
        "error",
    ])
    .map_err(|x| e(&x))?;
    let f = |x: f64| format!("{x:.6}");
    for r in &res.runs {
        let p = r.primary();
        for (i, c) in p.channels.iter().enumerate() {
            let rc = r
                .corrected
                .as_ref()
                .map_or(String::new(), |k| f(k.channels[i].rating.overall));
            w.write_record([
                r.name.clone(),
                r.synthetic.to_string(),
                r.obstacle.clone(),
                r.load_case.clone(),
                f(r.nominal_speed_mps),
                f(p.speed_mps),
                f(p.shift_s),
                c.channel.clone(),
                rc,
                f(r.uncorrected.channels[i].rating.overall),
                f(c.rating.corridor),
                f(c.rating.phase),
                f(c.rating.magnitude),
                f(c.rating.slope),
                f(c.peak_measured_mps2),
                f(c.t_peak_measured_s),
                f(c.peak_simulated_mps2),
                f(c.t_peak_simulated_s),
                f(c.rms_diff_mps2),
                f(c.correlation),
                f(c.gain_ratio),
                String::new(),
            ])
            .map_err(|x| e(&x))?;
        }
    }
    for (file, err) in &res.failures {
        let mut row = vec![String::new(); 22];
        row[0] = file.display().to_string();
        row[21] = err.clone();
        w.write_record(&row).map_err(|x| e(&x))?;
    }
    w.flush().map_err(|x| e(&x))?;
    let json_path = dir.join("summary.json");
    let text = serde_json::to_string_pretty(&summary_json(res)).map_err(|x| e(&x))?;
    std::fs::write(&json_path, text).map_err(|x| e(&x))?;
    super::trends::write(res, dir)?;
    Ok((csv_path, json_path))
}
