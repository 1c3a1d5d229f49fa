//! `towride tyre-rig FILE.toml`: runs a tyre test rig (cleat, quarter or lateral rig) and
//! reports peaks, contact losses and solver effort; optionally writes the history (CSV)
//! and a plot. A lateral rig also runs its steady slip-angle sweep and compares it with
//! the Magic Formula and the file's reference table (`<name>_sweep.csv`,
//! `<name>_lateral.png`).

use crate::CliResult;
use std::path::PathBuf;

use clap::Args;
use towride_app::report::tyre_lateral::LateralSummary;
use towride_app::report::tyre_rig::RigSummary;
use towride_mbs::tyre::rig::{RigCase, RigSetup};
use towride_mbs::tyre::rig_lateral::read_reference;

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
    #[command(flatten)]
    inputs: crate::inputs::InputArgs,
}

pub fn run(a: &TyreRigArgs) -> CliResult {
    let loader = a.inputs.loader()?;
    let case = RigCase::from_file(&a.file, &loader)?;
    // An override that reached no file the rig read would otherwise change nothing.
    loader.check_used()?;
    if let Some(dir) = &a.out {
        claim_out(dir, a, &case, &loader)?;
    }
    let rtol = a.rtol.unwrap_or(case.rtol);
    let run = case
        .run(Some(rtol))
        .map_err(|e| format!("{}: {e}", a.file.display()))?;
    let mut sum = RigSummary::of(&case, &a.file, rtol, &run)?;
    let name = stem(&a.file);
    if let Some(dir) = &a.out {
        sum.write(&run, dir, &name)?;
    }
    let mut lateral = None;
    if let (Some(points), RigSetup::Lateral { rig, sweep, .. }) =
        (case.lateral_sweep(Some(rtol)), &case.setup)
    {
        let points = points.map_err(|e| format!("{}: sweep: {e}", a.file.display()))?;
        let reference = match &sweep.reference {
            Some(p) => read_reference(p)?,
            None => Vec::new(),
        };
        let sigma = rig.tyre.params().d.sigma_alpha;
        let mut lat = LateralSummary::of(points, &reference, sigma, &run, rig.speed, rig.alpha);
        if let Some(dir) = &a.out {
            let label = sweep
                .reference
                .as_ref()
                .and_then(|p| p.file_stem())
                .map_or("reference".into(), |s| s.to_string_lossy().to_string());
            let mf = &rig.tyre.params().mf;
            let formula = |load: f64, alpha: f64| {
                let f = mf.forces(0.0, alpha, load, true);
                (f.fy, f.mz)
            };
            lat.write(
                dir, &name, &formula, &reference, &label, &run, rig.speed, rig.alpha,
            )?;
        }
        lateral = Some(lat);
    }
    if a.json {
        let mut v = serde_json::to_value(&sum)?;
        if let Some(l) = &lateral {
            v["lateral"] = serde_json::to_value(l)?;
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
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
        if let Some(l) = &lateral {
            println!(
                "steady sweep: {} points; rig vs formula: |dFy| <= {:.3e} N, |dMz| <= {:.3e} N m",
                l.points.len(),
                l.max_dev_formula_fy_n,
                l.max_dev_formula_mz_n_m
            );
            if let (Some(f), Some(m)) = (l.max_dev_reference_fy_n, l.max_dev_reference_mz_n_m) {
                println!(
                    "rig vs reference ({} points): |dFy| <= {f:.3e} N, |dMz| <= {m:.3e} N m",
                    l.reference_points
                );
            }
            println!(
                "step response: 63 % reached after {} m rolled (sigma_alpha = {:.4} m)",
                l.step_distance_63_m
                    .map_or("(not reached)".into(), |d| format!("{d:.4}")),
                l.sigma_alpha_m
            );
            if let (Some(c), Some(p)) = (&l.csv, &l.png) {
                println!("wrote {c} and {p}");
            }
        }
    }
    Ok(0)
}

/// Refuses an `--out` holding another command's results, or one of whose files the rig
/// would write is a file it reads (the rig file, its tyre, road or reference table).
fn claim_out(
    dir: &std::path::Path,
    a: &TyreRigArgs,
    case: &RigCase,
    loader: &towride_mbs::input::Loader,
) -> Result<(), String> {
    let name = stem(&a.file);
    let mut read = loader.files_read();
    read.push(a.file.clone());
    read.extend(a.inputs.overrides.clone());
    if let RigSetup::Lateral { sweep, .. } = &case.setup {
        read.extend(sweep.reference.clone());
    }
    let writes: Vec<String> = ["{}.csv", "{}.png", "{}_sweep.csv", "{}_lateral.png"]
        .iter()
        .map(|p| p.replace("{}", &name))
        .collect();
    let writes: Vec<&str> = writes.iter().map(String::as_str).collect();
    towride_app::atomic::claim(dir, "tyre-rig", &writes, &read)
}

/// The rig's name: its file's stem.
fn stem(file: &std::path::Path) -> String {
    file.file_stem()
        .map_or("rig".into(), |s| s.to_string_lossy().to_string())
}
