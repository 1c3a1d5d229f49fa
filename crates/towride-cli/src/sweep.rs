//! `towride sweep SWEEP.toml [--jobs N] [--shard I/N]` and `towride sweep merge`.

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use serde_json::json;

use towride::model::{self, spec};
use towride::sweep::exec::{merge, run_cases, write_summary, Figures};
use towride::sweep::{parse_shard, Sweep};

#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepArgs {
    #[command(subcommand)]
    cmd: Option<SweepCmd>,
    /// The sweep file (TOML).
    #[arg(required = true)]
    file: Option<PathBuf>,
    /// Parallel cases (default: all cores).
    #[arg(long)]
    jobs: Option<usize>,
    /// Run only the cases with index mod N = I (0 <= I < N), for job arrays.
    #[arg(long)]
    shard: Option<String>,
    /// Output folder for summary.csv and summary.json.
    #[arg(long, default_value = "out/sweep")]
    out: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Subcommand, Debug)]
enum SweepCmd {
    /// Join shard summaries into one table ordered by case.
    Merge {
        /// Shard summary CSV files.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// The merged table.
        #[arg(long, default_value = "out/sweep/summary.csv")]
        out: PathBuf,
    },
}

pub fn run(a: &SweepArgs) -> Result<i32, String> {
    if let Some(SweepCmd::Merge { inputs, out }) = &a.cmd {
        let n = merge(inputs, out)?;
        println!("{n} cases merged into {}", out.display());
        return Ok(0);
    }
    let file = a.file.as_ref().ok_or("a sweep file is required")?;
    let sweep = Sweep::load(file).map_err(|e| e.to_string())?;
    let (i, n) = match &a.shard {
        Some(s) => parse_shard(s)?,
        None => (0, 1),
    };
    let cases = sweep.shard(i, n);
    let jobs = a
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pb = crate::progress(cases.len() as u64, a.json);
    let wall = std::time::Instant::now();
    let rows = run_cases(&sweep, &cases, jobs, &run_file, &pb)?;
    pb.finish_and_clear();
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let name = if n > 1 {
        format!("summary_shard{i}of{n}.csv")
    } else {
        "summary.csv".into()
    };
    let csv_path = a.out.join(name);
    write_summary(&csv_path, &sweep, &rows)?;
    let failed = rows.iter().filter(|r| r.status != "completed").count();
    let summary = json!({
        "sweep": sweep.name,
        "cases": rows.len(),
        "cases_total": sweep.len(),
        "shard": [i, n],
        "jobs": jobs,
        "failed": failed,
        "wall_s": wall.elapsed().as_secs_f64(),
        "summary_csv": csv_path.display().to_string(),
        "rows": rows,
    });
    let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
    std::fs::write(csv_path.with_extension("json"), &text).map_err(|e| e.to_string())?;
    if a.json {
        println!("{text}");
    } else {
        println!(
            "{}: {} cases ({} failed) on {jobs} threads in {:.2} s; summary in {}",
            sweep.name,
            rows.len(),
            failed,
            wall.elapsed().as_secs_f64(),
            csv_path.display()
        );
        for r in rows.iter().filter(|r| r.status != "completed") {
            eprintln!(
                "  case {} {:?}: {}",
                r.index,
                r.values,
                r.error.as_deref().unwrap_or("")
            );
        }
    }
    Ok(if failed == 0 { 0 } else { 1 })
}

/// Runs one case file (read with the case's overrides active) and returns its figures.
fn run_file(path: &Path) -> Result<Figures, String> {
    if towride::scene::is_scene(path) {
        return run_scene(path);
    }
    let mech = spec::load(path).map_err(|e| e.to_string())?;
    let sys = model::System::new(mech.model);
    let start = match mech.run.start {
        spec::Start::Assembly => None,
        spec::Start::Statics => {
            let st = model::statics::equilibrium(&sys, 0.0, &mech.solver)?;
            Some((st.y, st.yp))
        }
    };
    let res = model::run::simulate(
        &sys,
        0.0,
        mech.run.end_time_s,
        mech.run.sample_rate_hz,
        &mech.solver,
        start,
        &towride::progress::Silent,
    );
    if let Some((e, t)) = res.error {
        return Err(format!("failed at t = {t:.6} s: {e}"));
    }
    let mut out = Figures::new();
    for p in res.peaks() {
        let name = p["name"].as_str().unwrap_or("");
        let unit = p["unit"].as_str().unwrap_or("");
        out.push((
            format!("{name} max [{unit}]"),
            p["max"].as_f64().unwrap_or(f64::NAN),
        ));
        out.push((
            format!("{name} min [{unit}]"),
            p["min"].as_f64().unwrap_or(f64::NAN),
        ));
    }
    out.push(("steps".into(), res.stats.steps as f64));
    Ok(out)
}

/// A vehicle scene: peak hitch force components, peak acceleration per sensor, the
/// crossbeam's peak deflection and strain energy, solver effort.
fn run_scene(path: &Path) -> Result<Figures, String> {
    use towride::scene::exec::run;
    use towride::scene::Overrides;
    let r = run(path, &[], &Overrides::default(), &|_| {})?;
    if let Some((e, t)) = &r.result.error {
        return Err(format!("failed at t = {t:.4} s: {e}"));
    }
    let mut out = Figures::new();
    let abs_peak = |n: &str| {
        r.channel(n)
            .map(|v| v.iter().fold(0.0f64, |m, x| m.max(x.abs())))
    };
    for n in ["hitch_fx", "hitch_fy", "hitch_fz"] {
        if let Some(p) = r.peak(n) {
            out.push((format!("{n} peak [N]"), p));
        }
    }
    for c in &r.result.channels {
        if c.name.starts_with("acc_") || c.name == "trailer_ax" {
            out.push((
                format!("{} peak [m/s^2]", c.name),
                abs_peak(&c.name).unwrap_or(f64::NAN),
            ));
        }
    }
    if let (Some(x), Some(y), Some(z)) = (
        r.channel("hitch_deflection_x"),
        r.channel("hitch_deflection_y"),
        r.channel("hitch_deflection_z"),
    ) {
        let d = (0..x.len()).fold(0.0f64, |m, k| {
            m.max((x[k] * x[k] + y[k] * y[k] + z[k] * z[k]).sqrt())
        });
        out.push(("crossbeam peak deflection [m]".into(), d));
    }
    if let Some(e) = abs_peak("hitch_strain_energy") {
        out.push(("crossbeam peak strain energy [J]".into(), e));
    }
    out.push(("steps".into(), r.result.stats.steps as f64));
    out.push(("run wall time [s]".into(), r.wall_s));
    Ok(out)
}
