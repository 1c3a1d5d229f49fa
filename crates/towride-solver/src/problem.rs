//! The problem side of the solver: a DAE in residual form F(t, y, y') = 0.
//!
//! The solver knows nothing about what the equations mean. A problem supplies the
//! residual, optionally its sparsity pattern and an analytic iteration matrix
//! dF/dy + cj dF/dy', and tells which unknowns are algebraic (and of which index) so the
//! error and convergence tests can treat them as index-3 BDF codes do.

/// How an unknown enters the DAE, used by the error test and the Newton scaling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarKind {
    /// A differential unknown (its derivative appears) or an index-1 algebraic unknown.
    Differential,
    /// An algebraic unknown of index 1 (e.g. a force that follows from a smooth equation).
    Algebraic1,
    /// An index-2 unknown (velocities of a constrained mechanism, GGL multipliers).
    Index2,
    /// An index-3 unknown (Lagrange multipliers of position-level constraints).
    Index3,
}

impl VarKind {
    /// The differentiation index level used for h-scaling: 1 for differential and index-1
    /// unknowns, 2 and 3 for the higher-index ones (Hairer & Wanner, Solving ODEs II, VII.3).
    pub fn level(self) -> i32 {
        match self {
            VarKind::Differential | VarKind::Algebraic1 => 1,
            VarKind::Index2 => 2,
            VarKind::Index3 => 3,
        }
    }

    /// True for every unknown whose derivative does not appear in the residual.
    pub fn is_algebraic(self) -> bool {
        !matches!(self, VarKind::Differential)
    }
}

/// Collects the non-zero entries of the iteration matrix dF/dy + cj dF/dy'.
///
/// Entries may be added more than once for the same position; they are summed. A problem
/// that adds its cj terms with [`JacobianSink::add_scaled`] lets the solver keep dF/dy'
/// apart and rebuild the matrix for another cj without evaluating it again (it must then
/// add all of them that way).
pub struct JacobianSink<'a> {
    pub(crate) entries: &'a mut Vec<(usize, usize, f64)>,
    /// The dF/dy' coefficients added with `add_scaled`, when the caller keeps them.
    pub(crate) yp: Option<&'a mut Vec<(usize, usize, f64)>>,
}

impl<'a> JacobianSink<'a> {
    /// A sink appending to `entries` (for callers outside the solver, e.g. analyses).
    pub fn new(entries: &'a mut Vec<(usize, usize, f64)>) -> Self {
        JacobianSink { entries, yp: None }
    }

    /// A sink that also keeps the dF/dy' coefficients reported by `add_scaled`.
    pub fn with_yp(
        entries: &'a mut Vec<(usize, usize, f64)>,
        yp: &'a mut Vec<(usize, usize, f64)>,
    ) -> Self {
        JacobianSink {
            entries,
            yp: Some(yp),
        }
    }

    /// Adds `value` at (`row`, `col`).
    #[inline]
    pub fn add(&mut self, row: usize, col: usize, value: f64) {
        self.entries.push((row, col, value));
    }

    /// Adds `cj * coeff` at (`row`, `col`), `coeff` being an entry of dF/dy'.
    #[inline]
    pub fn add_scaled(&mut self, row: usize, col: usize, cj: f64, coeff: f64) {
        self.entries.push((row, col, cj * coeff));
        if let Some(yp) = self.yp.as_mut() {
            yp.push((row, col, coeff));
        }
    }
}

/// Which side of the iteration matrix a [`DaeProblem::transport`] acts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Transport {
    /// D_r^T applied to a residual before the solve with the old matrix.
    Rows,
    /// D_c applied to the solution of that solve.
    Columns,
}

/// A differential-algebraic system F(t, y, y') = 0.
pub trait DaeProblem {
    /// Number of unknowns (and of equations).
    fn size(&self) -> usize;

    /// Evaluates the residual F(t, y, y') into `res`.
    fn residual(&self, t: f64, y: &[f64], yp: &[f64], res: &mut [f64]);

    /// Largest step the problem allows from (t, y), for events the solver cannot see
    /// coming through the residual (a road obstacle ahead of a tyre). `None`: no limit
    /// beyond the options' `h_max`.
    fn max_step(&self, _t: f64, _y: &[f64]) -> Option<f64> {
        None
    }

    /// Unknowns that are the components of one vector whose resolution in components is a
    /// matter of frame (see `SolverOptions::vector_error_weights`). Default: none.
    fn magnitude_groups(&self) -> Vec<std::ops::Range<usize>> {
        Vec::new()
    }

    /// Carries an iteration matrix built at `built` to the state `now` by orthogonal
    /// changes of variables, J(now) ~ D_r J(built) D_c^T, so that a re-used matrix stays
    /// accurate for unknowns expressed in frames that turn fast (a spinning wheel's body
    /// axes turn half a radian over a matrix's life). `Rows` applies D_r^T to `v` in place,
    /// `Columns` applies D_c. Default: the identity (see `has_transport`).
    fn transport(&self, _built: &[f64], _now: &[f64], _v: &mut [f64], _side: Transport) {}

    /// Whether [`DaeProblem::transport`] does anything (lets the solver skip it).
    fn has_transport(&self) -> bool {
        false
    }

    /// The kind of each unknown. Defaults to all differential (an implicit ODE).
    fn var_kinds(&self) -> Vec<VarKind> {
        vec![VarKind::Differential; self.size()]
    }

    /// Structural non-zeros (row, col) of dF/dy + cj dF/dy'. `None` means dense.
    fn jacobian_pattern(&self) -> Option<Vec<(usize, usize)>> {
        None
    }

    /// Writes the analytic iteration matrix dF/dy + cj dF/dy' into `jac` and returns true,
    /// or returns false to let the solver build it by (coloured) finite differences.
    fn jacobian(
        &self,
        _t: f64,
        _y: &[f64],
        _yp: &[f64],
        _cj: f64,
        _jac: &mut JacobianSink,
    ) -> bool {
        false
    }

    /// Number of event functions g(t, y, y') whose sign changes the solver locates.
    fn n_roots(&self) -> usize {
        0
    }

    /// Evaluates the event functions into `g` (length `n_roots()`).
    fn roots(&self, _t: f64, _y: &[f64], _yp: &[f64], _g: &mut [f64]) {}

    /// A human-readable name of unknown `i`, used in error messages.
    fn var_name(&self, i: usize) -> String {
        format!("y[{i}]")
    }

    /// A human-readable name of equation `i`, used in error messages.
    fn eq_name(&self, i: usize) -> String {
        format!("F[{i}]")
    }
}

/// Checks an integrator's start (t0, y0, y'0) against the problem: sizes, finite values,
/// one kind per unknown; returns the kinds.
pub(crate) fn check_start<P: DaeProblem + ?Sized>(
    prob: &P,
    t0: f64,
    y0: &[f64],
    yp0: &[f64],
) -> Result<Vec<VarKind>, crate::SolverError> {
    use crate::SolverError;
    let n = prob.size();
    if y0.len() != n || yp0.len() != n {
        return Err(SolverError::SizeMismatch {
            what: format!(
                "problem has {n} unknowns, y0 {} and yp0 {}",
                y0.len(),
                yp0.len()
            ),
        });
    }
    if !t0.is_finite() {
        return Err(SolverError::NonFiniteInitial {
            name: "t0".into(),
            value: t0,
        });
    }
    for (i, v) in y0.iter().chain(yp0.iter()).enumerate() {
        if !v.is_finite() {
            let name = if i < n {
                prob.var_name(i)
            } else {
                format!("d/dt {}", prob.var_name(i - n))
            };
            return Err(SolverError::NonFiniteInitial { name, value: *v });
        }
    }
    let kinds = prob.var_kinds();
    if kinds.len() != n {
        return Err(SolverError::SizeMismatch {
            what: format!("var_kinds has {} entries for {n} unknowns", kinds.len()),
        });
    }
    Ok(kinds)
}
