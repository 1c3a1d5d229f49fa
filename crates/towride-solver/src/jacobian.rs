//! Evaluation of the iteration matrix dF/dy + cj dF/dy' into a [`NewtonMatrix`]: the
//! problem's analytic matrix when it offers one, else coloured finite differences with
//! IDA's increments (Curtis, Powell & Reid 1974; IDA's IDADenseDQJac). Shared by the
//! integrators.

use crate::linear::NewtonMatrix;
use crate::options::Stats;
use crate::problem::{DaeProblem, JacobianSink};

const UROUND: f64 = f64::EPSILON;

/// The entry buffers of the analytic path and whether that path is available.
pub(crate) struct JacobianEval {
    entries: Vec<(usize, usize, f64)>,
    /// The dF/dy' part of the last analytic evaluation, when the problem reports it with
    /// [`JacobianSink::add_scaled`] and it was asked for.
    pub yp_entries: Vec<(usize, usize, f64)>,
    /// The analytic matrix is used (cleared when the problem declines to give one).
    pub analytic: bool,
}

impl JacobianEval {
    pub fn new(analytic: bool) -> Self {
        JacobianEval {
            entries: Vec::new(),
            yp_entries: Vec::new(),
            analytic,
        }
    }

    /// Writes dF/dy + cj dF/dy' at (t, y, y') into `jac`. `keep_yp`: collect the dF/dy'
    /// part the problem reports (`yp_entries`). `h` and the error weights `ewt` set the
    /// finite-difference increments. An entry outside the declared pattern is an error
    /// of the problem, returned as a message.
    #[allow(clippy::too_many_arguments)]
    pub fn eval<P: DaeProblem + ?Sized>(
        &mut self,
        prob: &P,
        jac: &mut NewtonMatrix,
        t: f64,
        y: &[f64],
        yp: &[f64],
        cj: f64,
        h: f64,
        ewt: &[f64],
        keep_yp: bool,
        stats: &mut Stats,
    ) -> Result<(), String> {
        stats.jacobian_evals += 1;
        jac.clear();
        if self.analytic {
            self.entries.clear();
            self.yp_entries.clear();
            let provided = {
                let mut sink = if keep_yp {
                    JacobianSink::with_yp(&mut self.entries, &mut self.yp_entries)
                } else {
                    JacobianSink::new(&mut self.entries)
                };
                prob.jacobian(t, y, yp, cj, &mut sink)
            };
            if provided {
                for &(r, c, v) in &self.entries {
                    if jac.add(r, c, v).is_err() {
                        return Err(format!(
                            "Jacobian entry ({}, {}) = d {} / d {} lies outside the declared pattern",
                            r,
                            c,
                            prob.eq_name(r),
                            prob.var_name(c)
                        ));
                    }
                }
                return Ok(());
            }
            self.analytic = false;
        }
        let n = prob.size();
        let mut f0 = vec![0.0; n];
        prob.residual(t, y, yp, &mut f0);
        stats.residual_evals += 1;
        let mut yw = y.to_vec();
        let mut ypw = yp.to_vec();
        let mut f1 = vec![0.0; n];
        let mut col = vec![0.0; n];
        let srur = UROUND.sqrt();
        let colours = jac.take_colours();
        let mut incs = vec![0.0; n];
        for group in &colours {
            for &j in group {
                let mut inc = (srur * y[j].abs().max((h * yp[j]).abs())).max(1.0 / ewt[j]);
                if h * yp[j] < 0.0 {
                    inc = -inc;
                }
                inc = (y[j] + inc) - y[j];
                incs[j] = inc;
                yw[j] += inc;
                ypw[j] += cj * inc;
            }
            prob.residual(t, &yw, &ypw, &mut f1);
            stats.residual_evals += 1;
            for &j in group {
                for &r in jac.column_rows(j) {
                    col[r] = (f1[r] - f0[r]) / incs[j];
                }
                jac.set_column_from(j, &col);
                yw[j] = y[j];
                ypw[j] = yp[j];
            }
        }
        jac.keep_colours(colours);
        Ok(())
    }
}
