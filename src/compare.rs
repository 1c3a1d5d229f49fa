//! `towride compare DIR DIR... [--out DIR]`: overlays the channels of two or more runs'
//! `outputs.csv` in `compare.png` and `compare.html`, with the differences of max, min
//! and |peak| (like with like) and the RMS difference against the first run.

use std::path::PathBuf;

use clap::Args;
use towride_app::report::compare::{compare, load, write};

use crate::CliResult;

#[derive(Args, Debug)]
pub struct CompareArgs {
    /// Run folders (each with outputs.csv); the first is the reference.
    #[arg(num_args = 2.., required = true)]
    dirs: Vec<PathBuf>,
    /// Folder for compare.png (or .svg) and compare.html.
    #[arg(long, default_value = "compare")]
    out: PathBuf,
    /// Figure format.
    #[arg(long, default_value = "png", value_parser = ["png", "svg"])]
    format: String,
    /// Print the comparison as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &CompareArgs) -> CliResult {
    let runs = a
        .dirs
        .iter()
        .map(|d| load(d))
        .collect::<Result<Vec<_>, _>>()?;
    let mut c = compare(&runs)?;
    if c.channels.is_empty() {
        return Err("the runs have no channel in common".into());
    }
    write(&runs, &mut c, &a.out, &a.format)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&c)?);
        return Ok(0);
    }
    println!(
        "{} channels in common; differences against {}:",
        c.channels.len(),
        c.runs[0]
    );
    for d in &c.differences {
        println!(
            "  {:<26} {:<12} max {:>11.4e} vs {:>11.4e} ({:>+10.3e})  min {:>11.4e} vs {:>11.4e} ({:>+10.3e})  |peak| {:>10.4e} vs {:>10.4e} ({:>+10.3e})  RMS diff {:>10.3e} [{}]{}",
            d.channel,
            d.run,
            d.max,
            d.reference_max,
            d.max_difference,
            d.min,
            d.reference_min,
            d.min_difference,
            d.abs_peak,
            d.reference_abs_peak,
            d.abs_peak_difference,
            d.rms_difference,
            d.unit,
            // A channel a run's convergence check failed: its numbers depend on the
            // tolerance, and so does this difference.
            if d.converged == Some(false) {
                "  NOT CONVERGED (run --check)"
            } else {
                ""
            }
        );
    }
    for n in &c.not_comparable {
        println!(
            "  {:<26} {:<12} {}: {}",
            span(&n.channels),
            n.run,
            n.reason,
            n.detail
        );
    }
    for v in &c.conversions {
        println!(
            "  {:<26} {:<12} read in {} and compared in {} (x {:e})",
            v.channel, v.run, v.from, v.to, v.factor
        );
    }
    for f in &c.files {
        println!("wrote {}", f.display());
    }
    Ok(0)
}

/// `first .. last` of a list of channels (`hitch_eta_1 .. hitch_eta_16`).
fn span(names: &[String]) -> String {
    match names {
        [] => String::new(),
        [one] => one.clone(),
        [a, .., b] => format!("{a} .. {b}"),
    }
}
