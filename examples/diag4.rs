use towride::solver::*;
use towride::verify::{
    self,
    runner::{run_with, Formulation},
};
fn main() {
    for name in ["caraxis", "andrews", "hires", "vdpol"] {
        let b = verify::by_name(name).unwrap();
        for alg in [AlgebraicControl::Scaled, AlgebraicControl::Exclude] {
            for ntol in [0.33, 0.1, 0.03] {
                let mut line = format!("{name:8} {alg:?} ntol {ntol}:");
                for tol in [1e-6, 1e-9, 1e-10] {
                    let o = SolverOptions {
                        newton_tol: ntol,
                        algebraic: alg,
                        ..SolverOptions::with_tol(tol, tol)
                    };
                    let r = run_with(&b, &o, Formulation::Ggl, 0.0);
                    line += &format!(
                        " | {tol:e}: scd {:.2} st {} nre {} t {:.4}",
                        r.scd.unwrap_or(-1.0),
                        r.steps,
                        r.residual_evals,
                        r.wall_s
                    );
                }
                println!("{line}");
            }
        }
    }
}
