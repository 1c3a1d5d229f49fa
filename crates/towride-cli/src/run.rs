//! `towride run FILE`: integrate a mechanism file, a scene or a plan's cases and write
//! the outputs (scenes and plans: `scene_run.rs`).

use std::path::PathBuf;

use clap::Args;
use serde_json::json;

use towride::model::{self, spec};

#[derive(Args, Debug)]
pub struct RunArgs {
    /// A mechanism file, a scene (`[scene]`) or a plan (`[plan]`), TOML.
    pub(crate) file: PathBuf,
    /// Output folder for outputs.csv and summary.json (a plan: one folder per case).
    #[arg(long, default_value = "out")]
    pub(crate) out: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    pub(crate) json: bool,
    /// Plans: run only these cases (comma-separated names; `--list` shows them).
    #[arg(long, value_delimiter = ',')]
    pub(crate) case: Vec<String>,
    /// Plans: list the cases and stop.
    #[arg(long)]
    pub(crate) list: bool,
}

pub fn run(a: &RunArgs) -> Result<i32, String> {
    if towride::scene::plan::is_plan(&a.file) || towride::scene::is_scene(&a.file) {
        return crate::scene_run::run(a);
    }
    let mech = spec::load(&a.file).map_err(|e| e.to_string())?;
    let sys = model::System::new(mech.model);
    crate::model_check(&sys)?;
    let warnings = crate::redundancy_warnings(&sys);
    if !a.json {
        for w in &warnings {
            eprintln!("warning: {w}");
        }
    }
    let t_end = mech.run.end_time_s;
    let pb = crate::progress((t_end * mech.run.sample_rate_hz).round() as u64, a.json);
    let (start, statics) = match mech.run.start {
        spec::Start::Assembly => (None, None),
        spec::Start::Statics => {
            let st =
                model::statics::equilibrium(&sys, 0.0, &mech.solver).map_err(|e| e.to_string())?;
            (Some((st.y.clone(), st.yp.clone())), Some(st.report))
        }
    };
    let res = model::run::simulate(
        &sys,
        0.0,
        t_end,
        mech.run.sample_rate_hz,
        &mech.solver,
        start,
        &pb,
    );
    pb.finish_and_clear();
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let csv_path = a.out.join("outputs.csv");
    res.write_csv(&csv_path)
        .map_err(|e| format!("{}: {e}", csv_path.display()))?;
    let s = &res.stats;
    let summary = json!({
        "file": a.file.display().to_string(),
        "model": sys.model.name,
        "status": if res.error.is_none() { "completed" } else { "failed" },
        "error": res.error.as_ref().map(|e| e.0.clone()),
        "failed_at_s": res.error.as_ref().map(|e| e.1),
        "t_end_s": t_end,
        "samples": res.times.len(),
        "equations": sys.size(),
        "constraint_rows": sys.m,
        "redundant_rows": sys.redundant.len(),
        "warnings": warnings,
        "assembly": res.assembly,
        "statics": statics,
        "steps": s.steps,
        "rejected_steps": s.rejected_steps,
        "residual_evals": s.residual_evals,
        "jacobian_evals": s.jacobian_evals,
        "lu_factorizations": s.lu_factorizations,
        "newton_iterations": s.newton_iterations,
        "wall_s": res.wall_s,
        "outputs_csv": csv_path.display().to_string(),
        "channels": res.peaks(),
    });
    let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
    std::fs::write(a.out.join("summary.json"), &text).map_err(|e| e.to_string())?;
    if a.json {
        println!("{text}");
    } else {
        println!(
            "{}: {}",
            sys.model.name,
            if res.error.is_none() {
                "completed"
            } else {
                "FAILED"
            }
        );
        println!(
            "  {} steps, {} Newton iterations, {} Jacobians, {:.3} s wall; outputs in {}",
            s.steps,
            s.newton_iterations,
            s.jacobian_evals,
            res.wall_s,
            csv_path.display()
        );
        for p in res.peaks() {
            println!(
                "  {:<32} min {:>12.5e} max {:>12.5e} {:<7} peak at {:.4} s",
                p["name"].as_str().unwrap_or(""),
                p["min"].as_f64().unwrap_or(f64::NAN),
                p["max"].as_f64().unwrap_or(f64::NAN),
                p["unit"].as_str().unwrap_or(""),
                p["time_of_peak_s"].as_f64().unwrap_or(f64::NAN)
            );
        }
    }
    if let Some((e, t)) = &res.error {
        eprintln!(
            "error: run stopped at t = {t:.6} s: {e}\n  results up to that time are in {}",
            csv_path.display()
        );
        return Ok(1);
    }
    Ok(0)
}
