//! `towride verify`: the published benchmarks at a few tolerances.

use crate::CliResult;
use clap::Args;

use crate::MethodArg;
use towride_solver::testset::{self, radau5_runs, runner};

/// `--formulation` values on the command line.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub(crate) enum FormulationArg {
    Ggl,
    Index3,
}

impl From<FormulationArg> for runner::Formulation {
    fn from(f: FormulationArg) -> Self {
        match f {
            FormulationArg::Ggl => runner::Formulation::Ggl,
            FormulationArg::Index3 => runner::Formulation::Index3,
        }
    }
}

#[derive(Args, Debug)]
pub struct VerifyArgs {
    /// Print machine-readable JSON (an array of records) instead of a table.
    #[arg(long)]
    json: bool,
    /// Only these problems (caraxis, andrews, hires, vdpol, rober); default all.
    #[arg(long, value_delimiter = ',')]
    problems: Vec<String>,
    /// Tolerances (rtol = atol) to run.
    #[arg(long, value_delimiter = ',', default_values_t = [1e-6, 1e-8, 1e-9, 1e-10], value_parser = crate::bounded::tolerance)]
    tol: Vec<f64>,
    /// Integration method: a BDF variant or Radau IIA (`radau`: the first step is then
    /// the tolerance, as in the test set's RADAU5 runs, and the Fortran RADAU5's own
    /// figures at the same tolerance are printed beside ours).
    #[arg(long, value_enum, default_value = "variable")]
    method: MethodArg,
    /// How index-3 problems are integrated: ggl (stabilised index 2) or index3.
    #[arg(long, value_enum, default_value = "ggl")]
    formulation: FormulationArg,
    /// Cap the Newton tolerance at the error level the step controller acts on
    /// (`newton_tol_growth_cap`, see docs/solver.md).
    #[arg(long)]
    newton_tol_cap: bool,
    /// BDF stability limit detection (`stability_limit_detection`, see docs/solver.md).
    #[arg(long)]
    stability_limit_detection: bool,
}

pub fn run(a: &VerifyArgs) -> CliResult {
    let benches = select(&a.problems)?;
    let pb = crate::progress((benches.len() * a.tol.len()) as u64, a.json);
    let mut records = Vec::new();
    for b in &benches {
        for &tol in &a.tol {
            pb.set_message(format!("{} {tol:e}", b.name));
            let radau = matches!(a.method, MethodArg::Radau);
            let opts = towride_solver::SolverOptions {
                method: a.method.into(),
                newton_tol_growth_cap: a.newton_tol_cap,
                stability_limit_detection: a.stability_limit_detection,
                // rtol = atol = h0 for RADAU5 in the test set (`docs/data/radau5_testset.csv`).
                h_init: radau.then_some(tol),
                ..towride_solver::SolverOptions::with_tol(tol, tol * b.atol_scale)
            };
            records.push(runner::run_with(b, &opts, a.formulation.into(), 0.0));
            pb.inc(1);
        }
    }
    pb.finish_and_clear();
    let failed = records.iter().filter(|r| r.status != "ok").count();
    // The Fortran RADAU5's run of the same problem at the same tolerance (Radau only),
    // with its scd on the same components as ours.
    let fortran = |r: &runner::CaseResult| {
        let f = radau5_runs::find(&r.problem, r.rtol)
            .filter(|_| matches!(a.method, MethodArg::Radau))?;
        let b = testset::by_name(&r.problem)?;
        // The mechanisms are run by RADAU5 as published (index 3).
        let form = if b.ggl.is_some() {
            " (index-3 form)"
        } else {
            ""
        };
        let scd = f.scd(&b);
        Some((f, scd, form))
    };
    if a.json {
        let mut out = Vec::new();
        for r in &records {
            let mut v = serde_json::to_value(r).map_err(|e| e.to_string())?;
            if let (Some((f, scd, _)), Some(obj)) = (fortran(r), v.as_object_mut()) {
                obj.insert(
                    "radau5_fortran".into(),
                    serde_json::json!({
                        "steps": f.steps, "accepted": f.accepted, "rejected": f.rejected,
                        "f_evals": f.f_evals, "jac_evals": f.jac_evals,
                        "lu_decompositions": f.lu_decompositions, "cpu_s": f.cpu_s,
                        "scd": scd,
                    }),
                );
            }
            out.push(v);
        }
        println!(
            "{}",
            serde_json::to_string_pretty(&out).map_err(|e| e.to_string())?
        );
    } else {
        println!(
            "{:<8} {:>7} {:>6} {:>6} {:>6} {:>5} {:>6} {:>5} {:>5} {:>6} {:>9}  published",
            "problem",
            "tol",
            "scd",
            "mescd",
            "steps",
            "rej",
            "F-evl",
            "J-evl",
            "LU",
            "Newton",
            "wall [s]"
        );
        for r in &records {
            let publ = match (&r.published_code, r.published_tol, r.published_steps) {
                (Some(c), Some(t), Some(s)) if t == r.rtol => format!("{c}: {s} steps"),
                _ => String::new(),
            };
            // RADAU5: accepted steps, rejected attempts, f and Jacobian evaluations, LU
            // pairs, scd and CPU time of one run, beside ours.
            let publ = match fortran(r) {
                Some((f, scd, form)) => format!(
                    "RADAU5{form}: {} steps, {} rej, {} F, {} J, {} LU, scd {:.2}, {:.4} s",
                    f.accepted,
                    f.steps - f.accepted,
                    f.f_evals,
                    f.jac_evals,
                    f.lu_decompositions,
                    scd,
                    f.cpu_s
                ),
                None => publ,
            };
            match r.scd {
                Some(scd) => println!(
                    "{:<8} {:>7.0e} {:>6.2} {:>6.2} {:>6} {:>5} {:>6} {:>5} {:>5} {:>6} {:>9.4}  {}",
                    r.problem,
                    r.rtol,
                    scd,
                    r.mescd.unwrap_or(f64::NAN),
                    r.steps,
                    r.rejected_steps,
                    r.residual_evals,
                    r.jacobian_evals,
                    r.lu_factorizations,
                    r.newton_iterations,
                    r.wall_s,
                    publ
                ),
                None => println!(
                    "{:<8} {:>7.0e} FAILED: {}",
                    r.problem,
                    r.rtol,
                    r.error.as_deref().unwrap_or("")
                ),
            }
        }
        println!("scd: significant correct digits, -log10 of the largest relative error (test set's getscd)");
    }
    Ok(if failed > 0 { 1 } else { 0 })
}

pub(crate) fn select(names: &[String]) -> Result<Vec<testset::Benchmark>, String> {
    if names.is_empty() {
        return Ok(testset::all());
    }
    names
        .iter()
        .map(|n| {
            testset::by_name(n).ok_or_else(|| {
                format!("unknown problem `{n}` (caraxis, andrews, hires, vdpol, rober)")
            })
        })
        .collect()
}
