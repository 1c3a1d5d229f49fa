//! `towride tyre-rig FILE.toml`: runs a tyre test rig (cleat or quarter rig) and reports
//! peaks, contact losses and solver effort; optionally writes the history (CSV) and a plot.

use crate::CliResult;
use std::path::PathBuf;

use clap::Args;
use towride_app::report::tyre_rig::RigSummary;
use towride_mbs::input::Loader;
use towride_mbs::tyre::rig::RigCase;

#[derive(Args, Debug)]
pub struct TyreRigArgs {
    /// Rig file (TOML with [tyre], [road], [rig], [solver], [output]).
    file: PathBuf,
    /// Print a JSON summary instead of text.
    #[arg(long)]
    json: bool,
    /// Relative tolerance (overrides the file's [solver] rtol).
    #[arg(long, value_parser = crate::bounded::tolerance)]
    rtol: Option<f64>,
    /// Directory for `<name>.csv` (history) and `<name>.png` (plot).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(a: &TyreRigArgs) -> CliResult {
    let case = RigCase::from_file(&a.file, &Loader::new())?;
    let rtol = a.rtol.unwrap_or(case.rtol);
    let run = case
        .run(Some(rtol))
        .map_err(|e| format!("{}: {e}", a.file.display()))?;
    let mut sum = RigSummary::of(&case, &a.file, rtol, &run)?;
    if let Some(dir) = &a.out {
        let name = a
            .file
            .file_stem()
            .map_or("rig".into(), |s| s.to_string_lossy().to_string());
        sum.write(&run, dir, &name)?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&sum)?);
    } else {
        println!("{} ({} rig), tyre {}", sum.file, sum.rig, sum.tyre);
        println!("road: {}", sum.road);
        println!(
            "rtol {:.0e}: {} steps ({} rejected), {} residuals, {:.3} s wall",
            sum.rtol, sum.steps, sum.rejected_steps, sum.residual_evals, sum.wall_s
        );
        println!(
            "rim load Fz {:.1} .. {:.1} N, Fx {:.1} .. {:.1} N; normal force min {:.1} N; airborne {:.3} s",
            sum.hub_fz_min_n, sum.hub_fz_max_n, sum.hub_fx_min_n, sum.hub_fx_max_n, sum.normal_force_min_n, sum.airborne_s
        );
        println!(
            "at {:.3} s: rolling radius {:.5} m, deflection {:.5} m",
            sum.t_end_s, sum.final_rolling_radius_m, sum.final_deflection_m
        );
        if let (Some(c), Some(p)) = (&sum.csv, &sum.png) {
            println!("wrote {c} and {p}");
        }
    }
    Ok(0)
}
