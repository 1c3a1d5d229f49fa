//! `towride bench scaling`: the scaling study (`towride_app::study::scaling`), printed as a
//! table.

use std::path::PathBuf;

use clap::Args;

use towride_app::study::scaling::{self, Settings};

use crate::CliResult;

#[derive(Args, Debug)]
pub struct ScalingArgs {
    /// The study file.
    #[arg(long, default_value = "scenes/scaling.toml")]
    file: PathBuf,
    /// Chain sizes (links); default the file's.
    #[arg(long, value_delimiter = ',')]
    chain: Option<Vec<usize>>,
    /// Ladder sizes (loops); default the file's.
    #[arg(long, value_delimiter = ',')]
    ladder: Option<Vec<usize>>,
    /// Vehicle cases by hitch modes; default the file's.
    #[arg(long, value_delimiter = ',')]
    hitch_modes: Option<Vec<usize>>,
    /// Runs of each case; the fastest is reported.
    #[arg(long, default_value_t = 1)]
    repeat: usize,
    /// Output folder.
    #[arg(long, default_value = "out/bench-scaling")]
    out: PathBuf,
    /// Print the study as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &ScalingArgs) -> CliResult {
    let settings = Settings {
        chain: a.chain.clone(),
        ladder: a.ladder.clone(),
        hitch_modes: a.hitch_modes.clone(),
        repeat: a.repeat,
    };
    let pb = crate::progress(0, a.json);
    let mut study = scaling::run(&a.file, &settings, &a.out, &pb)?;
    let json = study.write(&a.out)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&study)?);
        return Ok(0);
    }
    println!("family   size  equations  rows  redundant  steps  set-up [s]  start [s]  integration [s]  outputs [s]  total [s]  per step [ms]  set-up share");
    for p in &study.points {
        println!(
            "{:<8} {:>4} {:>10} {:>5} {:>10} {:>6} {:>11.4} {:>10.4} {:>16.4} {:>12.4} {:>10.4} {:>14.4} {:>13.3}  {}",
            p.family,
            p.size,
            p.equations,
            p.constraint_rows,
            p.redundant_rows,
            p.steps,
            p.setup_s,
            p.start_s,
            p.integration_s,
            p.outputs_s,
            p.total_s,
            1e3 * p.per_step_s,
            p.setup_share,
            if p.status == "completed" { "" } else { &p.status }
        );
    }
    println!("fits against equations, y = c n^p:");
    for f in &study.fits {
        println!(
            "  {:<8} {:<14} p = {:.3} over {}..{} equations; growth over linear {:.2}",
            f.family, f.quantity, f.exponent, f.from_equations, f.to_equations, f.over_linear
        );
    }
    println!("written: {}", json.display());
    Ok(0)
}
