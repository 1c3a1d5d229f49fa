use towride::solver::*;
use towride::verify;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let b = verify::by_name(&args[1]).unwrap();
    for ntol in [0.33, 0.03, 1e-3] {
        for m in [Method::Variable, Method::FixedCoefficient] {
            for tol in [1e-6, 1e-9, 1e-10] {
                let o = SolverOptions {
                    newton_tol: ntol,
                    method: m,
                    ..SolverOptions::with_tol(tol, tol)
                };
                match solve_to(b.problem.as_ref(), b.t0, &b.y0, &b.yp0, b.t_end, &o) {
                    Ok(e) => {
                        println!("I3 ntol {ntol} {m:?} {tol:e}: scd {:.2} steps {} rej {}/{} orders {:?} nre {} nje {} nni {}", verify::scd(&e.y, &b.reference, &b.scd_components), e.stats.steps, e.stats.error_test_failures, e.stats.convergence_failures, e.stats.order_counts, e.stats.residual_evals, e.stats.jacobian_evals, e.stats.newton_iterations);
                    }
                    Err(err) => println!("{tol:e}: {err}"),
                }
                if let Some(g) = b.ggl.as_ref() {
                    match solve_to(g.problem.as_ref(), b.t0, &g.y0, &g.yp0, b.t_end, &o) {
                        Ok(e) => {
                            let y = (g.to_testset)(&e.y, &e.yp);
                            println!("GGL ntol {ntol} {m:?} {tol:e}: scd {:.2} steps {} rej {}/{} orders {:?} nre {} nje {} nni {}", verify::scd(&y, &b.reference, &b.scd_components), e.stats.steps, e.stats.error_test_failures, e.stats.convergence_failures, e.stats.order_counts, e.stats.residual_evals, e.stats.jacobian_evals, e.stats.newton_iterations);
                        }
                        Err(err) => println!("{tol:e}: {err}"),
                    }
                }
            }
        }
    }
}
