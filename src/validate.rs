//! `towride validate RUN.toml|FOLDER`: compares recorded runs with the simulation;
//! `towride validate synth`: writes synthetic runs (one, or the 72-run plan);
//! `towride validate init DATA --scene SCENE`: drafts a descriptor from a recording.

use crate::CliResult;
use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};

use towride_mbs::input::regular::same_file;

use towride_app::validate::descriptor::{AcqFilter, Unit};
use towride_app::validate::folder::{find_descriptors, summary_json, validate_folder_until};
use towride_app::validate::synth::{make_synthetic, SensorModel, SynthRun, TriggerLayout};
use towride_app::validate::{init, plan, report, simulator_with, write_summary, Options};

#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true)]
pub struct ValidateArgs {
    #[command(subcommand)]
    cmd: Option<ValidateCommand>,
    /// A run descriptor (RUN.toml) or a folder searched recursively for them.
    path: Option<PathBuf>,
    /// Directory for summary.csv, summary.json, index.html and per-run plots.
    #[arg(long, default_value = "out/validate")]
    out: PathBuf,
    /// Print per run and channel figures as JSON.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    inputs: crate::inputs::InputArgs,
    /// Skip the corrections (speed from the foils, cross-correlation shift).
    #[arg(long)]
    no_correct: bool,
    /// Skip the PNG overlays and report pages.
    #[arg(long)]
    no_plots: bool,
    /// Bound of the time-shift search [ms].
    #[arg(long, default_value_t = 100.0, value_parser = crate::bounded::time_ms)]
    max_shift_ms: f64,
}

#[derive(Subcommand, Debug)]
enum ValidateCommand {
    /// Write synthetic runs (CSV + descriptor, labelled synthetic) made by the simulator.
    Synth(Box<SynthArgs>),
    /// Sniff a recording (separator, header, units, time base, channels) and draft a
    /// commented descriptor mapping its columns onto the scene's sensors.
    Init(InitArgs),
}

#[derive(Args, Debug)]
struct InitArgs {
    /// The recording (CSV or any delimited text export).
    data: PathBuf,
    /// The scene the run is simulated with.
    #[arg(long)]
    scene: PathBuf,
    /// Where to write the descriptor (default: beside DATA, same stem, .toml).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Sample rate [Hz] when the file has no time column and no comment declaring it
    /// (an error for a file with a time column).
    #[arg(long, value_parser = crate::bounded::rate_hz)]
    rate_hz: Option<f64>,
    /// Overwrite an existing descriptor.
    #[arg(long)]
    force: bool,
    /// Print what was found as JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Args, Debug)]
struct SynthArgs {
    /// Output folder.
    #[arg(long)]
    out: PathBuf,
    /// Every run of a plan file (default: the 72-run measurement plan,
    /// scenes/measurement_plan.toml: 3 obstacles x 6 speeds x 4 loads).
    #[arg(long, num_args = 0..=1, default_missing_value = "scenes/measurement_plan.toml")]
    plan: Option<PathBuf>,
    /// Single run: the scene file.
    #[arg(long, required_unless_present = "plan")]
    scene: Option<PathBuf>,
    /// Single run: obstacle name (default: the scene's file stem).
    #[arg(long)]
    obstacle: Option<String>,
    /// Single run: nominal (speedometer) speed [km/h].
    #[arg(long, required_unless_present = "plan", value_parser = crate::bounded::speed_kmh)]
    speed_kmh: Option<f64>,
    /// Single run: trailer load case.
    #[arg(long, default_value = "empty")]
    load: String,
    /// Single run: file name stem (default OBSTACLE_SPEEDkmh_LOAD).
    #[arg(long)]
    name: Option<String>,
    #[arg(long, default_value_t = 0.05, value_parser = crate::bounded::mps2)]
    noise_rms_mps2: f64,
    #[arg(long, default_value_t = 37.0, value_parser = crate::bounded::time_ms)]
    trigger_delay_ms: f64,
    #[arg(long, default_value_t = 3.0, value_parser = crate::bounded::pct)]
    speed_error_pct: f64,
    #[arg(long, default_value_t = 5.0, value_parser = crate::bounded::pct)]
    gain_error_pct: f64,
    #[arg(long, default_value_t = 1000.0, value_parser = crate::bounded::rate_hz)]
    rate_hz: f64,
    #[arg(long, default_value_t = 4, value_parser = crate::bounded::count)]
    filter_order: usize,
    #[arg(long, default_value_t = 100.0, value_parser = crate::bounded::rate_hz)]
    cutoff_hz: f64,
    #[arg(long, default_value_t = 0.1, value_parser = crate::bounded::time_ms)]
    foil_jitter_ms: f64,
    /// Write the channels in g instead of m/s^2.
    #[arg(long)]
    in_g: bool,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// RMS of a constant offset drawn per channel [m/s^2] (the descriptor then zeroes
    /// each channel before the obstacle).
    #[arg(long, default_value_t = 0.0, value_parser = crate::bounded::mps2)]
    offset_rms_mps2: f64,
    /// RMS of the run-to-run scatter of the trigger delay [ms].
    #[arg(long, default_value_t = 0.0, value_parser = crate::bounded::time_ms)]
    trigger_jitter_ms: f64,
    /// Decimals of the written time column (a logger's time-stamp resolution).
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u8).range(1..=9))]
    time_decimals: u8,
    /// The "true" vehicle: overrides the simulating model is made with (recorded in the
    /// descriptor's `[injected] truth`; the descriptor's scene stays the files' model).
    #[command(flatten)]
    inputs: crate::inputs::InputArgs,
    /// Print what was written as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &ValidateArgs) -> CliResult {
    match &a.cmd {
        Some(ValidateCommand::Synth(s)) => return synth(s),
        Some(ValidateCommand::Init(i)) => return init(i),
        None => {}
    }
    let path = a
        .path
        .as_ref()
        .ok_or("give a run descriptor (RUN.toml) or a folder")?;
    let files = find_descriptors(path)?;
    // Nothing read is written over, and no other command's results are replaced.
    let mut inputs: Vec<std::path::PathBuf> = files.clone();
    inputs.push(path.clone());
    towride_app::atomic::claim(
        &a.out,
        "validate",
        &[
            "summary.csv",
            "summary.json",
            "index.html",
            "trends.csv",
            "trends.html",
        ],
        &inputs,
    )?;
    let sim = simulator_with(a.inputs.loader()?);
    let opts = Options {
        correct: !a.no_correct,
        max_shift_s: a.max_shift_ms * 1e-3,
        ..Options::default()
    };
    let pb = crate::progress(files.len() as u64, a.json);
    let show = |i: usize, f: &Path| {
        pb.set_position(i as u64);
        pb.set_message(
            f.file_stem()
                .map_or(String::new(), |s| s.to_string_lossy().to_string()),
        );
    };
    crate::interrupt::install();
    let res = validate_folder_until(&files, sim.as_ref(), &opts, &show, &|| {
        crate::interrupt::requested()
    });
    pb.finish_and_clear();
    let (csv, json) = write_summary(&res, &a.out)?;
    let mut pages = Vec::new();
    if !a.no_plots {
        for r in &res.runs {
            let dir = a.out.join(&r.name);
            report::overlays(r, &dir, report::Format::Png)?;
            let page = dir.join("report.png");
            report::page(r, &page)?;
            towride_app::validate::html::write(r, &dir)?;
            pages.push((r.clone(), page));
        }
        report::index(
            &pages,
            &res.failures,
            &res.not_run,
            &a.out.join("index.html"),
        )?;
    }
    for (f, e) in &res.failures {
        eprintln!("error: {}: {e}", f.display());
    }
    if a.json {
        let text = serde_json::to_string_pretty(&summary_json(&res)).map_err(|e| e.to_string())?;
        println!("{text}");
    } else {
        println!("simulator: {}", sim.name());
        for r in &res.runs {
            let u = r.uncorrected.mean_rating;
            match &r.corrected {
                Some(c) => println!(
                    "{}{}: rating {u:.3} uncorrected -> {:.3} corrected; speed {:.2} km/h (nominal {:.2}); shift {:+.1} ms{}",
                    r.name, if r.synthetic { " [synthetic]" } else { "" }, c.mean_rating,
                    c.speed_mps * 3.6, r.nominal_speed_mps * 3.6, c.shift_s * 1e3,
                    if c.shift_at_bound { " (at the search bound)" } else { "" }
                ),
                None => println!("{}: rating {u:.3} uncorrected", r.name),
            }
            let quiet = &r
                .corrected
                .as_ref()
                .unwrap_or(&r.uncorrected)
                .without_signal;
            if !quiet.is_empty() {
                println!(
                    "  left out of the mean rating (no signal above the sensor noise): {}",
                    quiet.join(", ")
                );
            }
            let low = |x: &dyn std::fmt::Debug| format!("{x:?}").to_lowercase();
            let mut more = format!(
                "  speed from the {}, {} Hz ({} time base)",
                low(&r.speed.source),
                hz(r.sample_rate_hz),
                low(&r.time_base.kind)
            );
            if let Some(p) = &r.passage {
                more.push_str(&format!(
                    "; passage found in the signals at {:.4} s",
                    r.obstacle_time_s
                ));
                if let (Some(w), Some(m)) = (p.implied_wheelbase_m, r.wheelbase_m) {
                    more.push_str(&format!(", implied wheelbase {w:.3} m (model {m:.3} m)"));
                }
            }
            let clipped: usize = r.channels.iter().map(|c| c.clipped_samples).sum();
            if clipped > 0 {
                more.push_str(&format!("; {clipped} clipped samples left out"));
            }
            println!("{more}");
            if let Some(g) = &r.obstacle_geometry {
                for l in g.lines() {
                    println!("  {l}");
                }
            }
            for d in &r.speed.channel_dropouts_s {
                eprintln!(
                    "warning: {}: the speed channel drops out from {:.3} to {:.3} s (a step no car makes); left out of the speed",
                    r.name, d[0], d[1]
                );
            }
        }
        println!(
            "{} run(s) validated, {} failed, {:.2} s; wrote {} and {}{}",
            res.runs.len(),
            res.failures.len(),
            res.wall_s,
            csv.display(),
            json.display(),
            if a.no_plots {
                String::new()
            } else {
                format!(" and plots under {}", a.out.display())
            }
        );
    }
    if !res.not_run.is_empty() {
        eprintln!(
            "interrupted: {} of {} run(s) not validated (listed in summary.json as not_run); validate again for them",
            res.not_run.len(),
            files.len()
        );
        return Ok(crate::interrupt::EXIT);
    }
    Ok(if res.failures.is_empty() { 0 } else { 1 })
}

fn init(a: &InitArgs) -> CliResult {
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| a.data.with_extension("toml"));
    // Whatever --force says: `validate init run.toml` would put the draft over the
    // recording itself (the default --out is DATA with .toml).
    for (what, input) in [("the recording", &a.data), ("the scene", &a.scene)] {
        if same_file(&out, input) {
            return Err(format!(
                "--out {} is {what} {} (the same file): a draft never overwrites its input; give another --out",
                out.display(),
                input.display()
            )
            .into());
        }
    }
    if out.exists() && !a.force {
        return Err(format!("{} exists; give --force to overwrite it", out.display()).into());
    }
    let mut s = init::sniff(&a.data, a.rate_hz)?;
    init::map_columns(&mut s, &init::scene_sensors(&a.scene)?);
    std::fs::write(&out, init::draft(&s, &a.scene, &out))
        .map_err(|e| format!("{}: cannot write: {e}", out.display()))?;
    if a.json {
        let doc = serde_json::json!({
            "schema_version": towride_app::validate::folder::SCHEMA_VERSION,
            "descriptor": out.display().to_string(),
            "sniff": s,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&doc).map_err(|e| e.to_string())?
        );
    } else {
        // The speed channel is mapped too (the draft's [speed] column).
        let mapped = s
            .columns
            .iter()
            .filter(|c| c.simulated.is_some() || c.speed_channel)
            .count();
        println!(
            "{}: {} rows at {} Hz ({:?} time base), {mapped} of {} columns mapped; wrote {}",
            a.data.display(),
            s.rows,
            hz(s.time_base.rate_hz),
            s.time_base.kind,
            s.columns.len(),
            out.display()
        );
    }
    Ok(0)
}

fn synth(a: &SynthArgs) -> CliResult {
    let sensor = SensorModel {
        noise_rms_mps2: a.noise_rms_mps2,
        filter: AcqFilter {
            order: a.filter_order,
            cutoff_hz: a.cutoff_hz,
        },
        trigger_delay_s: a.trigger_delay_ms * 1e-3,
        speed_error_pct: a.speed_error_pct,
        gain_error_pct: a.gain_error_pct,
        channel_gain_error_pct: Vec::new(),
        sample_rate_hz: a.rate_hz,
        foil_jitter_s: a.foil_jitter_ms * 1e-3,
        unit: if a.in_g { Unit::G } else { Unit::Mps2 },
        seed: a.seed,
        offset_rms_mps2: a.offset_rms_mps2,
        trigger_jitter_s: a.trigger_jitter_ms * 1e-3,
        time_decimals: a.time_decimals as usize,
    };
    let truth: Vec<String> = a
        .inputs
        .overrides()?
        .iter()
        .map(|o| format!("{}:{}={}", o.file, o.path, o.value))
        .collect();
    let sim = simulator_with(a.inputs.loader()?);
    let files = if let Some(file) = &a.plan {
        let mut runs = plan::plan(&towride_app::scene::plan::load(file)?);
        runs.iter_mut().for_each(|r| r.truth = truth.clone());
        let pb = crate::progress(runs.len() as u64, a.json);
        let files = plan::write_plan(sim.as_ref(), &runs, &sensor, &a.out, &|i| {
            pb.set_position(i as u64)
        })?;
        pb.finish_and_clear();
        files
    } else {
        let scene = a.scene.clone().ok_or("--scene is required")?;
        let speed = a.speed_kmh.ok_or("--speed-kmh is required")?;
        let obstacle = a.obstacle.clone().unwrap_or_else(|| {
            scene
                .file_stem()
                .map_or("obstacle".into(), |s| s.to_string_lossy().to_string())
        });
        let run = SynthRun {
            name: a
                .name
                .clone()
                .unwrap_or(format!("{obstacle}_{speed:02.0}kmh_{}", a.load)),
            scene,
            obstacle,
            nominal_speed_kmh: speed,
            load_case: a.load.clone(),
            truth: truth.clone(),
        };
        vec![make_synthetic(
            sim.as_ref(),
            &run,
            &sensor,
            &TriggerLayout::default(),
            &a.out,
        )?]
    };
    if a.json {
        let v = serde_json::json!({
            "schema_version": 1,
            "simulator": sim.name(),
            "out": a.out.display().to_string(),
            "synthetic": true,
            "descriptors": files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>(),
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        println!(
            "wrote {} synthetic run(s) made by the {} into {}",
            files.len(),
            sim.name(),
            a.out.display()
        );
    }
    Ok(0)
}

/// A sample rate for the terminal: at most three decimals, no trailing zeros (a rate
/// rebuilt from a time column reads 500, not 499.99999999999994).
fn hz(rate: f64) -> String {
    let s = format!("{rate:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
