//! `towride calibrate RUN.toml...`: fits property values so the simulated runs match
//! the recorded ones, says which values the recordings pin down, and rates held-out
//! runs with the fitted values (docs/calibration.md).

use crate::CliResult;
use std::path::PathBuf;

use clap::Args;
use towride_app::calibrate::{
    self,
    target::{Band, Residual},
    Choice, Settings,
};

#[derive(Args, Debug)]
pub struct CalibrateArgs {
    /// Run descriptors (RUN.toml, as `validate` reads them) fitted together: one set of
    /// values for every run.
    #[arg(required = true)]
    runs: Vec<PathBuf>,
    /// `auto` (the scene's assumed values and obstacle geometry that the recordings can
    /// pin down) or `FILE:PATH[=LO..HI],...` (bounds default to half and twice the file
    /// value; positive values are fitted in log scale).
    #[arg(long, default_value = "auto")]
    params: String,
    /// With `--params auto`: at most this many values fitted.
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u16).range(1..=40))]
    max_params: u16,
    /// Channels fitted, comma-separated (default: every mapped channel above its noise).
    #[arg(long, value_delimiter = ',')]
    channels: Vec<String>,
    /// Band [Hz] both curves are limited to before the residual: LO,HI (zero-phase).
    #[arg(long, value_delimiter = ',', num_args = 2)]
    band: Option<Vec<f64>>,
    /// What the residual is made of: `history` (the band-limited curves), `features`
    /// (each channel's largest maximum, minimum and next extremum with their times) or
    /// `both`.
    #[arg(long, value_enum, default_value = "history")]
    residual: ResidualArg,
    /// Runs rated with the fitted values but not fitted on (prediction).
    #[arg(long, num_args = 1..)]
    holdout: Vec<PathBuf>,
    /// Latin-hypercube points of the global stage.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u16).range(0..=500))]
    starts: u16,
    /// Local (Levenberg-Marquardt) fits from the best points.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u16).range(1..=20))]
    local_fits: u16,
    /// Seed of the hypercube.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Threads (default: every core).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=512))]
    jobs: Option<u16>,
    /// Output folder: overrides.toml, calibration.json, report.png, report.html.
    #[arg(long, default_value = "out/calibrate")]
    out: PathBuf,
    /// Print one JSON document instead of text.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    inputs: crate::inputs::InputArgs,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
enum ResidualArg {
    History,
    Features,
    Both,
}

pub fn run(a: &CalibrateArgs) -> CliResult {
    let band = match a.band.as_deref() {
        Some([lo, hi]) if *lo >= 0.0 && hi > lo && hi.is_finite() => Some(Band {
            lo_hz: *lo,
            hi_hz: *hi,
        }),
        Some(b) => {
            return Err(format!(
                "--band {b:?}: give LO,HI in Hz with 0 <= LO < HI, e.g. --band 0.5,40"
            )
            .into())
        }
        None => None,
    };
    let settings = Settings {
        choice: if a.params.trim() == "auto" {
            Choice::Auto(a.max_params as usize)
        } else {
            Choice::Listed(a.params.clone())
        },
        channels: a.channels.clone(),
        band,
        residual: match a.residual {
            ResidualArg::History => Residual::History,
            ResidualArg::Features => Residual::Features,
            ResidualArg::Both => Residual::Both,
        },
        starts: a.starts as usize,
        local_fits: a.local_fits as usize,
        seed: a.seed,
        ..Settings::default()
    };
    let mut inputs = a.runs.clone();
    inputs.extend(a.holdout.iter().cloned());
    towride_app::atomic::claim(
        &a.out,
        "calibrate",
        &[
            "overrides.toml",
            "calibration.json",
            "report.png",
            "report.html",
        ],
        &inputs,
    )?;
    let base = a.inputs.overrides()?;
    let pb = crate::progress(0, a.json);
    let show = |stage: &str, sims: usize| {
        pb.set_position(sims as u64);
        pb.set_message(stage.to_string());
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.jobs.map_or(0, |j| j as usize))
        .build()
        .map_err(|e| e.to_string())?;
    let cal =
        pool.install(|| calibrate::calibrate(&a.runs, &a.holdout, &base, &settings, &show))?;
    pb.finish_and_clear();
    let produced = crate::inputs::stamp(&Default::default());
    let producer = format!(
        "towride {} ({})",
        produced.towride_version, produced.git_commit
    );
    let files = calibrate::output::write(&cal, &a.out, &producer)?;
    let doc = serde_json::json!({
        "schema_version": calibrate::SCHEMA_VERSION,
        "produced_by": produced,
        "calibration": cal,
        "files": files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>(),
    });
    let json_path = a.out.join("calibration.json");
    towride_app::atomic::write(&json_path, serde_json::to_string_pretty(&doc)?)
        .map_err(|e| format!("{}: {e}", json_path.display()))?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(0);
    }
    println!(
        "fitted {} value(s) on {} run(s): residual RMS {:.2} -> {:.2} x the noise; {} simulations ({} failed), {:.1} s",
        cal.fitted.len(),
        cal.targets.len(),
        cal.rms_start,
        cal.rms_fitted,
        cal.simulations,
        cal.failed_simulations,
        cal.wall_s
    );
    for f in &cal.fitted {
        println!(
            "  {:<48} {:>11.4e} -> {:>11.4e}  95 % {:.4e}..{:.4e}  ({:+.1} %){}",
            f.spec.name,
            f.spec.file_value,
            f.value,
            f.interval[0],
            f.interval[1],
            (f.value / f.spec.file_value - 1.0) * 100.0,
            if f.at_bound { "  AT BOUND" } else { "" }
        );
    }
    for (n, why) in &cal.left {
        println!("  left at the file value: {n}: {why}");
    }
    for r in cal
        .fitted_runs
        .iter()
        .map(|r| ("fitted", r))
        .chain(cal.holdout_runs.iter().map(|r| ("held out", r)))
    {
        println!(
            "  {} ({}): rating {:.3} -> {:.3}",
            r.1.name, r.0, r.1.before, r.1.after
        );
    }
    for w in &cal.warnings {
        eprintln!("warning: {w}");
    }
    println!(
        "wrote {}",
        files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(0)
}
