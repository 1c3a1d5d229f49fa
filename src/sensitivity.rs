//! `towride sensitivity SCENE`: OAT elasticities or Morris screening of a scene's
//! outputs over its property-file values (the library's `study::sensitivity`).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use towride_app::study::sensitivity::{self, params, Method, Settings};

use crate::CliResult;

#[derive(Clone, Copy, Debug, ValueEnum)]
enum MethodArg {
    Oat,
    Morris,
}

#[derive(Args, Debug)]
pub struct SensitivityArgs {
    /// Scene (or mechanism) file.
    file: PathBuf,
    /// Parameters FILE:PATH (TOML path, `.tir` SECTION.KEY; `[i]` for one component of a
    /// vector); default: every stiffness, damping and mass of the groups.
    #[arg(long, value_delimiter = ',', conflicts_with = "group")]
    params: Vec<String>,
    /// Groups searched for parameters (default hitch, trailer, tyres).
    #[arg(long, value_delimiter = ',')]
    group: Vec<String>,
    /// Outputs CHANNEL.abs_peak|max|min|rms|freq, CHANNEL raw or band-limited
    /// (`acc_hitch_z_lp100`) (default: hitch force |peak|, RMS and frequency, trailer-box
    /// acceleration |peak|, every accelerometer's band-limited |peak|).
    #[arg(long, value_delimiter = ',')]
    outputs: Vec<String>,
    /// oat (central differences at +-10 %) or morris (elementary effects).
    #[arg(long, value_enum, default_value = "oat")]
    method: MethodArg,
    /// Morris trajectories.
    #[arg(long, default_value_t = 10, value_parser = crate::bounded::count)]
    trajectories: usize,
    /// Morris range: each value times 1 -+ this fraction.
    #[arg(long, default_value_t = 0.3)]
    range: f64,
    /// Morris seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Parallel runs (default: all cores).
    #[arg(long, value_parser = crate::bounded::jobs)]
    jobs: Option<usize>,
    /// Output folder (default out/sensitivity/<scene>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// List the parameters found (with their groups) and stop.
    #[arg(long)]
    list: bool,
    /// Print the study as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &SensitivityArgs) -> CliResult {
    if !(a.range > 0.0 && a.range < 1.0) {
        return Err(format!("--range {}: a fraction between 0 and 1", a.range).into());
    }
    let jobs = a
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let s = Settings {
        file: a.file.clone(),
        params: a.params.clone(),
        groups: a.group.clone(),
        outputs: a.outputs.clone(),
        method: match a.method {
            MethodArg::Oat => Method::Oat,
            MethodArg::Morris => Method::Morris,
        },
        trajectories: a.trajectories,
        levels: 4,
        range: a.range,
        seed: a.seed,
        jobs,
    };
    if a.list {
        let all = params::candidates(&a.file, &[])?;
        if a.json {
            let doc = serde_json::json!({"schema_version": sensitivity::SCHEMA_VERSION, "parameters": all});
            println!("{}", serde_json::to_string_pretty(&doc)?);
        } else {
            for p in &all {
                println!(
                    "{:<8} {:<9} {:<70} {:.4e}",
                    p.group,
                    p.kind,
                    p.name,
                    p.base_value()
                );
            }
        }
        return Ok(0);
    }
    let pb = crate::progress(0, a.json);
    crate::interrupt::install();
    let mut study = sensitivity::run(&s, &pb)?;
    let dir = a
        .out
        .clone()
        .unwrap_or_else(|| sensitivity::default_dir(&a.file));
    sensitivity::write::write(&mut study, &dir)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&study)?);
        return Ok(0);
    }
    println!(
        "{:?} study of {}: {} parameters, {} runs on {} threads in {:.1} s ({} failed)",
        study.method,
        study.file,
        study.params.len(),
        study.runs,
        study.jobs,
        study.runs_wall_s,
        study.failed.len()
    );
    for f in &study.failed {
        println!("  failed: {}: {}", f.changes, f.error);
    }
    if let Some(o) = study.outputs.first() {
        println!("ranking by {} (base {:.5e} {}):", o.name, o.base, o.unit);
        for p in study.ranking(0).iter().take(10) {
            match study.method {
                Method::Oat => println!(
                    "  {:<70} elasticity {}",
                    p.param.name,
                    p.elasticity[0].map_or("-".into(), |v| format!("{v:+.4}"))
                ),
                Method::Morris => println!(
                    "  {:<70} mu*/base {:.4}  sigma/base {:.4}",
                    p.param.name,
                    p.mu_star_rel[0],
                    p.morris[0].sigma / o.base.abs()
                ),
            }
        }
    }
    if !study.inactive.is_empty() {
        println!(
            "not studied (the model does not depend on them): {}",
            study.inactive.join(", ")
        );
    }
    for w in &study.written {
        println!("wrote {w}");
    }
    Ok(if study.failed.is_empty() { 0 } else { 1 })
}
