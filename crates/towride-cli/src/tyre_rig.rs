//! `towride tyre-rig FILE.toml`: runs a tyre test rig (cleat or quarter rig) and reports
//! peaks, contact losses and solver effort; optionally writes the history (CSV) and a plot.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use towride::tyre::rig::{RigCase, RigRun, RigSetup};

use towride::report::lineplot::{line_panels, Line, LinePanel};

#[derive(Args, Debug)]
pub struct TyreRigArgs {
    /// Rig file (TOML with [tyre], [road], [rig], [solver], [output]).
    file: PathBuf,
    /// Print a JSON summary instead of text.
    #[arg(long)]
    json: bool,
    /// Relative tolerance (overrides the file's [solver] rtol).
    #[arg(long)]
    rtol: Option<f64>,
    /// Directory for `<name>.csv` (history) and `<name>.png` (plot).
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(Serialize)]
struct Summary {
    file: String,
    rig: &'static str,
    tyre: String,
    road: String,
    rtol: f64,
    t_end_s: f64,
    steps: usize,
    rejected_steps: usize,
    residual_evals: usize,
    wall_s: f64,
    hub_fz_max_n: f64,
    hub_fz_min_n: f64,
    hub_fx_max_n: f64,
    hub_fx_min_n: f64,
    normal_force_min_n: f64,
    airborne_s: f64,
    final_rolling_radius_m: f64,
    final_deflection_m: f64,
    csv: Option<String>,
    png: Option<String>,
}

pub fn run(a: &TyreRigArgs) -> Result<i32, String> {
    let case = RigCase::from_file(&a.file).map_err(|e| e.to_string())?;
    let rtol = a.rtol.unwrap_or(case.rtol);
    let run = case
        .run(Some(rtol))
        .map_err(|e| format!("{}: {e}", a.file.display()))?;
    let (rig, tyre, road) = match &case.setup {
        RigSetup::Cleat { rig, .. } => ("cleat", &rig.tyre, &rig.road),
        RigSetup::Quarter { rig, .. } => ("quarter", &rig.tyre, &rig.road),
    };
    let name = a
        .file
        .file_stem()
        .map_or("rig".into(), |s| s.to_string_lossy().to_string());
    let (mut csv, mut png) = (None, None);
    if let Some(dir) = &a.out {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let c = dir.join(format!("{name}.csv"));
        write_csv(&c, &run)?;
        csv = Some(c.display().to_string());
        let p = dir.join(format!("{name}.png"));
        plot(&p, &run, &name)?;
        png = Some(p.display().to_string());
    }
    let s = &run.samples;
    let fold = |f: &dyn Fn(&towride::tyre::rig::RigSample) -> f64, max: bool| {
        s.iter()
            .map(f)
            .fold(if max { f64::MIN } else { f64::MAX }, |a, b| {
                if max {
                    a.max(b)
                } else {
                    a.min(b)
                }
            })
    };
    let dt = if s.len() > 1 {
        s[1].t_s - s[0].t_s
    } else {
        0.0
    };
    let last = s.last().ok_or("no output")?;
    let sum = Summary {
        file: a.file.display().to_string(),
        rig,
        tyre: format!("{} ({:?})", tyre.params().file.display(), tyre.kind()),
        road: road.describe(),
        rtol,
        t_end_s: last.t_s,
        steps: run.stats.steps,
        rejected_steps: run.stats.rejected_steps,
        residual_evals: run.stats.residual_evals,
        wall_s: run.wall_s,
        hub_fz_max_n: fold(&|x| x.hub_fz_n, true),
        hub_fz_min_n: fold(&|x| x.hub_fz_n, false),
        hub_fx_max_n: fold(&|x| x.hub_fx_n, true),
        hub_fx_min_n: fold(&|x| x.hub_fx_n, false),
        normal_force_min_n: fold(&|x| x.normal_force_n, false),
        airborne_s: s.iter().filter(|x| x.normal_force_n == 0.0).count() as f64 * dt,
        final_rolling_radius_m: last.rolling_radius_m,
        final_deflection_m: last.deflection_m,
        csv,
        png,
    };
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&sum).map_err(|e| e.to_string())?
        );
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

fn write_csv(path: &std::path::Path, run: &RigRun) -> Result<(), String> {
    let mut w = csv::Writer::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    // Field names carry their units (serde names of RigSample).
    for s in &run.samples {
        w.serialize(s).map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())
}

fn plot(path: &std::path::Path, run: &RigRun, name: &str) -> Result<(), String> {
    let s = &run.samples;
    let series = |label: &str, f: &dyn Fn(&towride::tyre::rig::RigSample) -> f64| Line {
        label: label.into(),
        points: s.iter().map(|x| (x.t_s, f(x))).collect(),
    };
    line_panels(
        path,
        &[
            LinePanel {
                title: format!("{name}: load on the rim"),
                x_label: "time [s]".into(),
                y_label: "force [N]".into(),
                lines: vec![
                    series("Fz", &|x| x.hub_fz_n),
                    series("Fx", &|x| x.hub_fx_n),
                    series("normal contact force", &|x| x.normal_force_n),
                ],
            },
            LinePanel {
                title: format!("{name}: wheel centre and effective road"),
                x_label: "time [s]".into(),
                y_label: "height [mm]".into(),
                lines: vec![
                    series("wheel centre z", &|x| x.z_m * 1e3),
                    series("effective road height", &|x| x.effective_height_m * 1e3),
                ],
            },
        ],
        1,
    )
}
