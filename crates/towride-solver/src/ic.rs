//! Consistent initial values for the index-1 part (IDA's IDACalcIC, option
//! IDA_YA_YDP_INIT): with the differential unknowns y_d fixed, find the algebraic unknowns
//! y_a and the derivatives y'_d so that F(t0, y, y') = 0.
//!
//! Index-2 and index-3 unknowns (velocities under constraints, Lagrange multipliers) are
//! not handled here: a mechanical model supplies them from its own position and velocity
//! analyses, where the constraint structure is known.

use super::error::SolverError;
use super::linear::NewtonMatrix;
use super::options::SolverOptions;
use super::problem::{DaeProblem, VarKind};

/// Solves for the consistent y_a and y'_d in place; returns the Newton iterations used.
pub fn consistent_index1<P: DaeProblem + ?Sized>(
    prob: &P,
    t0: f64,
    y: &mut [f64],
    yp: &mut [f64],
    opts: &SolverOptions,
) -> Result<usize, SolverError> {
    let n = prob.size();
    opts.validate(n)?;
    let kinds = prob.var_kinds();
    if let Some(i) = kinds
        .iter()
        .position(|k| matches!(k, VarKind::Index2 | VarKind::Index3))
    {
        return Err(SolverError::InitialConditions {
            why: format!(
                "{} is of index {}; only index-1 unknowns can be made consistent here",
                prob.var_name(i),
                kinds[i].level()
            ),
        });
    }
    let dense = prob.jacobian_pattern().is_none() || n < opts.dense_limit;
    let mut m = NewtonMatrix::new(n, prob.jacobian_pattern(), dense)
        .map_err(|e| SolverError::InitialConditions { why: e.to_string() })?;
    let colours = m.take_colours();
    let w: Vec<f64> = (0..n)
        .map(|i| 1.0 / (opts.rtol * y[i].abs() + opts.atol_of(i)))
        .collect();
    let mut f0 = vec![0.0; n];
    let mut f1 = vec![0.0; n];
    let mut col = vec![0.0; n];
    for iter in 1..=20 {
        prob.residual(t0, y, yp, &mut f0);
        if let Some(i) = f0.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::InitialConditions {
                why: format!("residual {} is not finite", prob.eq_name(i)),
            });
        }
        // Iteration matrix over the unknowns being solved for, by coloured differences.
        m.clear();
        for group in &colours {
            let mut incs = Vec::with_capacity(group.len());
            for &j in group {
                // IDA's difference increment: sqrt(eps) relative, never below 1/w.
                let inc = (f64::EPSILON.sqrt() * y[j].abs().max(yp[j].abs())).max(1.0 / w[j]);
                if kinds[j] == VarKind::Differential {
                    yp[j] += inc;
                } else {
                    y[j] += inc;
                }
                incs.push(inc);
            }
            prob.residual(t0, y, yp, &mut f1);
            for (&j, &inc) in group.iter().zip(&incs) {
                if kinds[j] == VarKind::Differential {
                    yp[j] -= inc;
                } else {
                    y[j] -= inc;
                }
                for &r in m.column_rows(j) {
                    col[r] = (f1[r] - f0[r]) / inc;
                }
                m.set_column_from(j, &col);
            }
        }
        m.factor(&vec![1.0; n], true)
            .map_err(|s| SolverError::InitialConditions {
                why: format!("singular initial-value matrix: {}", s.detail),
            })?;
        let mut d: Vec<f64> = f0.iter().map(|v| -v).collect();
        m.solve(&mut d)
            .map_err(|s| SolverError::InitialConditions { why: s.detail })?;
        let mut norm = 0.0;
        for j in 0..n {
            if kinds[j] == VarKind::Differential {
                yp[j] += d[j];
                // Derivatives are measured against the state's scale per unit time.
                norm += (d[j] * w[j] * 1e-3).powi(2);
            } else {
                y[j] += d[j];
                norm += (d[j] * w[j]).powi(2);
            }
        }
        if (norm / n as f64).sqrt() < 1e-3 {
            return Ok(iter);
        }
    }
    Err(SolverError::InitialConditions {
        why: "Newton iteration did not converge in 20 iterations".into(),
    })
}
