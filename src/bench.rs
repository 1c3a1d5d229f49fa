//! `towride bench solver`: work-precision data for the built-in problems.

use crate::CliResult;
use clap::Args;
use std::path::PathBuf;

use towride_app::report::plot::{loglog_panels, Panel, Series};
use towride_solver::testset::runner::{self, CaseResult, Formulation};
use towride_solver::Method;

#[derive(Args, Debug)]
pub struct BenchSolverArgs {
    /// Print the records as JSON.
    #[arg(long)]
    json: bool,
    /// Output folder for work_precision.csv and work_precision.png.
    #[arg(long, default_value = "out/bench-solver")]
    out: PathBuf,
    /// Only these problems; default all.
    #[arg(long, value_delimiter = ',')]
    problems: Vec<String>,
    /// Tightest tolerance exponent: tolerances run 10^-3 ... 10^-N.
    #[arg(long, default_value_t = 11)]
    tightest: u32,
    /// Repeat each run until this many seconds have passed and keep the fastest.
    #[arg(long, default_value_t = 0.05)]
    min_wall: f64,
}

pub fn run_solver(a: &BenchSolverArgs) -> CliResult {
    let benches = crate::verify::select(&a.problems)?;
    let tols: Vec<f64> = (3..=a.tightest.max(3))
        .map(|k| 10f64.powi(-(k as i32)))
        .collect();
    let methods = [Method::Variable, Method::FixedCoefficient];
    let pb = crate::progress((benches.len() * tols.len() * methods.len()) as u64, a.json);
    let mut records: Vec<CaseResult> = Vec::new();
    for b in &benches {
        for &m in &methods {
            for &tol in &tols {
                pb.set_message(format!("{} {m:?} {tol:e}", b.name));
                records.push(runner::run_case(
                    b,
                    tol,
                    tol * b.atol_scale,
                    m,
                    Formulation::Ggl,
                    a.min_wall,
                ));
                pb.inc(1);
            }
        }
    }
    pb.finish_and_clear();
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let csv_path = a.out.join("work_precision.csv");
    write_csv(&csv_path, &records)?;
    let png_path = a.out.join("work_precision.png");
    let panels: Vec<Panel> = benches
        .iter()
        .map(|b| Panel {
            title: b.name.to_string(),
            x_label: "error 10^-scd [-]".into(),
            // Milliseconds: the test problems run in 0.1 to 100 ms, plain numbers on
            // the axis where seconds would need powers of ten.
            y_label: "wall time [ms]".into(),
            series: methods
                .iter()
                .map(|m| Series {
                    label: format!("{m:?}"),
                    points: records
                        .iter()
                        .filter(|r| r.problem == b.name && r.method == *m)
                        .filter_map(|r| r.scd.map(|s| (10f64.powf(-s), 1e3 * r.wall_s)))
                        .collect(),
                })
                .collect(),
        })
        .collect();
    loglog_panels(&png_path, &panels, 3)?;
    if a.json {
        let doc = serde_json::json!({
            "csv": csv_path, "png": png_path, "records": records,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&doc).map_err(|e| e.to_string())?
        );
    } else {
        println!(
            "{:<8} {:<16} {:>7} {:>6} {:>6} {:>6} {:>10}",
            "problem", "method", "tol", "scd", "steps", "J-evl", "wall [s]"
        );
        for r in &records {
            println!(
                "{:<8} {:<16} {:>7.0e} {:>6} {:>6} {:>6} {:>10.2e}",
                r.problem,
                format!("{:?}", r.method),
                r.rtol,
                r.scd
                    .map(|s| format!("{s:.2}"))
                    .unwrap_or_else(|| "FAIL".into()),
                r.steps,
                r.jacobian_evals,
                r.wall_s
            );
        }
        println!("wrote {} and {}", csv_path.display(), png_path.display());
    }
    Ok(0)
}

fn write_csv(path: &std::path::Path, records: &[CaseResult]) -> Result<(), String> {
    let mut w = csv::Writer::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let err = |e: csv::Error| format!("{}: {e}", path.display());
    w.write_record([
        "problem",
        "method",
        "rtol [-]",
        "atol [-]",
        "status",
        "scd [-]",
        "mescd [-]",
        "steps [-]",
        "rejected_steps [-]",
        "residual_evals [-]",
        "jacobian_evals [-]",
        "lu_factorizations [-]",
        "newton_iterations [-]",
        "wall [s]",
    ])
    .map_err(err)?;
    for r in records {
        let opt = |v: Option<f64>| v.map(|x| format!("{x:.4}")).unwrap_or_default();
        w.write_record([
            r.problem.clone(),
            format!("{:?}", r.method),
            format!("{:e}", r.rtol),
            format!("{:e}", r.atol),
            r.status.clone(),
            opt(r.scd),
            opt(r.mescd),
            r.steps.to_string(),
            r.rejected_steps.to_string(),
            r.residual_evals.to_string(),
            r.jacobian_evals.to_string(),
            r.lu_factorizations.to_string(),
            r.newton_iterations.to_string(),
            format!("{:.6e}", r.wall_s),
        ])
        .map_err(err)?;
    }
    w.flush().map_err(|e| format!("{}: {e}", path.display()))
}
