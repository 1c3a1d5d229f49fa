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
    /// Groups searched for parameters (default hitch, trailer, tyres and a `simple`
    /// vehicle's own file, `vehicle`; `--list` shows every value's group).
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
    /// Morris trajectories (2 to 1000).
    #[arg(long, default_value_t = 10, value_parser = crate::bounded::trajectories)]
    trajectories: usize,
    /// Morris range: each value times 1 -+ this fraction (default 0.3); OAT varies each
    /// value by +-10 % and refuses it.
    #[arg(long)]
    range: Option<f64>,
    /// Morris seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Parallel runs (default: all cores).
    #[arg(long, value_parser = crate::bounded::jobs)]
    jobs: Option<usize>,
    /// Output folder (default out/sensitivity/<scene's path, `/` as `_`, no extension>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// List the parameters found (with their groups) and stop.
    #[arg(long)]
    list: bool,
    /// Print the study as JSON.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    inputs: crate::inputs::InputArgs,
}

pub fn run(a: &SensitivityArgs) -> CliResult {
    let range = match (a.method, a.range) {
        (MethodArg::Oat, Some(r)) => {
            return Err(format!(
                "--range {r} applies to --method morris; OAT varies each value by +-10 %"
            )
            .into())
        }
        (_, r) => r.unwrap_or(0.3),
    };
    if !(range > 0.0 && range < 1.0) {
        return Err(format!("--range {range}: a fraction between 0 and 1").into());
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
        range,
        seed: a.seed,
        jobs,
        base: a.inputs.loader()?,
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
    let dir = a
        .out
        .clone()
        .unwrap_or_else(|| sensitivity::default_dir(&a.file));
    // Before any run: the folder must not hold another command's results or an input.
    towride_app::atomic::claim(
        &dir,
        "sensitivity",
        &[
            "sensitivity.csv",
            "tornado.png",
            "sensitivity.html",
            "sensitivity.json",
        ],
        std::slice::from_ref(&a.file),
    )?;
    let pb = crate::progress(0, a.json);
    crate::interrupt::install();
    let mut study = match sensitivity::run(&s, &pb) {
        Err(towride_app::Error::Scene(towride_app::scene::SceneError::Interrupted { .. })) => {
            eprintln!("interrupted before the study's base run finished: nothing to write");
            return Ok(crate::interrupt::EXIT);
        }
        r => r?,
    };
    study.produced_by = crate::inputs::stamp(&study.produced_by);
    sensitivity::write::write(&mut study, &dir)?;
    // Interrupted: what ran is written, labelled, with the interrupted exit code.
    let code = if study.not_run > 0 {
        crate::interrupt::EXIT
    } else if study.failed.is_empty() {
        0
    } else {
        1
    };
    if a.json {
        println!("{}", serde_json::to_string_pretty(&study)?);
        return Ok(code);
    }
    // First line: the figures below are partial.
    if let Some(note) = &study.note {
        println!("{note}");
    }
    println!(
        "{} of {}: {} parameters, {} runs on {} threads in {:.1} s ({} failed, {} not run)",
        study.method,
        study.file,
        study.params.len(),
        study.runs,
        study.jobs,
        study.runs_wall_s,
        study.failed.len(),
        study.not_run
    );
    for f in &study.failed {
        println!("  failed: {}: {}", f.changes, f.error);
    }
    // A figure that could not be computed is said so, never printed as 0 or NaN.
    let shown = |v: Option<f64>, p: &sensitivity::ParamResult| match v.filter(|x| x.is_finite()) {
        Some(x) => format!("{x:+.4}"),
        None if p.note.is_some() => format!("undefined ({})", p.note.as_deref().unwrap_or("")),
        None => "- (a run failed or was not run)".into(),
    };
    if let Some(o) = study.outputs.first() {
        println!("ranking by {} (base {:+.5e} {}):", o.name, o.base, o.unit);
        for p in study.ranking(0).iter().take(10) {
            match study.method {
                Method::Oat => println!(
                    "  {:<70} elasticity {}",
                    p.param.name,
                    shown(p.elasticity[0], p)
                ),
                Method::Morris => println!(
                    "  {:<70} mu*/base {}  sigma/base {}",
                    p.param.name,
                    shown(p.mu_star_rel.first().copied(), p),
                    shown(
                        p.morris
                            .first()
                            .map(|e| e.sigma / o.base.abs())
                            .filter(|_| p.param.base_value() != 0.0),
                        p
                    )
                ),
            }
        }
    }
    if !study.inactive.is_empty() {
        println!(
            "not studied (the model does not depend on them, or they cannot be varied): {}",
            study.inactive.join(", ")
        );
    }
    for w in &study.written {
        println!("wrote {w}");
    }
    Ok(code)
}
