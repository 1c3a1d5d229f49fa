//! Solver settings and run statistics.

use super::error::SolverError;

/// The integration method: the BDF with its two ways of following step changes, or the
/// 3-stage Radau IIA method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Method {
    /// Variable-coefficient BDF in fixed-leading-coefficient form (IDA, DASSL): the
    /// formula is built on the actual, unequally spaced history.
    #[default]
    Variable,
    /// Fixed-coefficient BDF (the GSTIFF family): constant-step formulas; on a step change
    /// the history is interpolated onto an equally spaced grid first.
    FixedCoefficient,
    /// The 3-stage Radau IIA method (order 5, L-stable, stiffly accurate) as Hairer and
    /// Wanner's RADAU5 (`crate::radau`); `max_order` and the BDF-only settings do not
    /// apply, [`RadauOptions`] does.
    #[cfg_attr(feature = "serde", serde(alias = "radau"))]
    Radau5,
}

impl Method {
    /// `[solver]` keys this method does not read: a file that sets one under it would
    /// change nothing, so readers refuse it.
    pub fn unused_keys(self) -> &'static [&'static str] {
        match self {
            Method::Variable => &["radau"],
            Method::FixedCoefficient => &["radau", "vector_error_weights"],
            Method::Radau5 => &["max_order", "stability_limit_detection"],
        }
    }
}

/// Settings of the Radau IIA integrator (RADAU5's WORK and IWORK entries of the same
/// meaning; defaults are RADAU5's).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct RadauOptions {
    /// The Jacobian is kept for the next step when the Newton contraction rate of this
    /// one was at most this (RADAU5's THET, WORK(3): 0.001; "increase to 0.1 when
    /// Jacobian evaluations are costly"). A kept Jacobian is still refactorised for a new
    /// step size; a negative value re-evaluates it at every step.
    pub jacobian_theta: f64,
    /// Newton iterations per step attempt (RADAU5's NIT, IWORK(3): 7).
    pub newton_iters: usize,
    /// The step size is kept (and with it the factorisations) when the controller's new
    /// step lies within [1, this] of it and the Jacobian is kept (RADAU5's QUOT2, WORK(6):
    /// 1.2; QUOT1 is 1).
    pub keep_step_ratio: f64,
}

impl Default for RadauOptions {
    fn default() -> Self {
        Self {
            jacobian_theta: 0.001,
            newton_iters: 7,
            keep_step_ratio: 1.2,
        }
    }
}

impl RadauOptions {
    /// For problems whose Jacobian costs many residuals and whose factorisations cost
    /// several Newton iterations (the vehicle: an evaluation about 30 residuals, a real
    /// and a complex refactorisation together about 1 ms, a Newton iteration 0.11 ms):
    /// keep the Jacobian unless Newton contracted slower than 0.3, and keep the step, and
    /// so the factorisations, unless the controller asks for more than 3 times it.
    /// Measured on the default scene at rtol 1e-2 (docs/performance.md): RADAU5's
    /// defaults 621 steps, 396 Jacobians, 509 factorisation pairs, 1.27 s; these 820
    /// steps, 63, 191, 0.59 s.
    pub fn costly_jacobian() -> Self {
        Self {
            jacobian_theta: 0.3,
            keep_step_ratio: 3.0,
            ..Self::default()
        }
    }
}

/// How unknowns of index 2 and 3 enter the error and Newton convergence tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum AlgebraicControl {
    /// By the problem's highest index. Index <= 2 (GGL forms, the multibody System):
    /// index-2 unknowns are left out of the error test, as the IDA user guide recommends
    /// for systems of index 2 or more (IDASetSuppressAlg), while differential and index-1
    /// unknowns are controlled in full. With index-3 unknowns (a published index-3 form,
    /// whose velocities are index 2): `Scaled`, as MEBDFI and RADAU5 do.
    #[default]
    Auto,
    /// Weight index-k unknowns by h^(k-1) (Hairer & Wanner II, VII.3; RADAU5, MEBDFI):
    /// they are controlled, at the accuracy their index allows.
    Scaled,
    /// Leave every algebraic unknown out of the error test (IDASetSuppressAlg,
    /// DASPK INFO(16)); Newton convergence still uses the h-scaled weights.
    Exclude,
    /// Treat every unknown alike (correct for index-1 problems only).
    Full,
}

/// Which linear-algebra path the Newton iteration uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum LinearSolver {
    /// Dense below `dense_limit` unknowns or when the problem gives no pattern, else sparse.
    #[default]
    Auto,
    /// Always dense LU (nalgebra).
    Dense,
    /// Always sparse LU (AMD order, refactorising).
    Sparse,
}

/// Where the iteration matrix comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum JacobianSource {
    /// The problem's analytic Jacobian when it offers one, else finite differences.
    #[default]
    Auto,
    /// Column-coloured finite differences even when an analytic Jacobian exists.
    FiniteDifference,
}

/// Integrator settings. Every field has a sensible default (`SolverOptions::default()`).
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct SolverOptions {
    /// Relative tolerance (dimensionless).
    pub rtol: f64,
    /// Absolute tolerance, in the units of each unknown; one value or one per unknown.
    pub atol: Vec<f64>,
    /// Highest BDF order, 1..=5.
    pub max_order: usize,
    /// First step [s]; `None` lets the solver choose from ||y'0||.
    pub h_init: Option<f64>,
    /// Largest step [s].
    pub h_max: f64,
    /// Smallest step [s] before the solver gives up.
    pub h_min: f64,
    /// Step budget for one call.
    pub max_steps: usize,
    /// How the BDF coefficients follow step-size changes.
    pub method: Method,
    /// How index-2 and index-3 unknowns enter the error and Newton tests.
    pub algebraic: AlgebraicControl,
    /// Dense or sparse LU for the Newton iteration matrix.
    pub linear_solver: LinearSolver,
    /// Problems with fewer unknowns use dense LU under `LinearSolver::Auto`.
    pub dense_limit: usize,
    /// Analytic or finite-difference iteration matrix.
    pub jacobian: JacobianSource,
    /// Newton iterations per step attempt (IDA: 4).
    pub max_newton_iters: usize,
    /// Newton convergence failures allowed in one step (IDA: 10). Radau IIA, as RADAU5,
    /// counts only non-finite residuals: a diverging or slow iteration just cuts the step.
    pub max_convergence_failures: usize,
    /// Error-test failures allowed in one step (IDA: 10); the BDF only. Radau IIA, as
    /// RADAU5, has no such limit: its step-size guard ends a step that keeps failing.
    pub max_error_failures: usize,
    /// Newton convergence constant: converged when rate/(1-rate)*||delta|| < this (IDA: 0.33).
    pub newton_tol: f64,
    /// Cap the Newton tolerance at the error level at which the step controller grows the
    /// step, eta_fixed_max^-(k+1) / (2 sigma_k) in the norm of the correction (order 5:
    /// 0.047 instead of 0.33). IDA's constant lets iteration noise, not the truncation
    /// error, decide order and step growth; the cap removes that: 25-40 % fewer steps at
    /// equal accuracy, but at a given tolerance the result is less accurate (car axis at
    /// 1e-9: scd 4.8 instead of 5.1). Off by default (IDA's behaviour).
    pub newton_tol_growth_cap: bool,
    /// Rebuild the iteration matrix at least every this many steps (IDA rebuilds only on
    /// need; 0 disables the age limit).
    pub max_jacobian_age: usize,
    /// The step grows only when the error estimate allows at least this factor (IDA's
    /// upper fixed-step bound, 2 in classic IDA and DASSL); growth is capped at 2.
    /// Lower values change the step more often: fewer steps, more factorisations.
    pub eta_fixed_max: f64,
    /// Row equilibration and h^(k-1) column scaling of the Newton matrix for index-k
    /// unknowns (keeps its condition number bounded as h -> 0 on index-3 problems).
    pub scale_newton_matrix: bool,
    /// Error weights of the problem's vector-valued unknowns (`magnitude_groups`: a
    /// rotation quaternion, an angular velocity in body axes) take their relative part from
    /// the vector's length, not from each component: the accuracy asked of a vector then
    /// does not depend on the frame it is resolved in, and does not tighten a thousandfold
    /// each time a component of a spinning wheel's quaternion passes through zero.
    /// Variable-coefficient method only.
    pub vector_error_weights: bool,
    /// Carry a re-used iteration matrix to the current state by the problem's frame
    /// transport (`DaeProblem::transport`: a spinning wheel's body axes), instead of
    /// solving with the matrix as it was built.
    pub matrix_transport: bool,
    /// When only the step size has changed (the leading coefficient cj left
    /// [0.6, 5/3] of the matrix's), rebuild J = dF/dy + cj dF/dy' from the parts of the
    /// last evaluation, dF/dy' kept separately, and refactorise, instead of evaluating
    /// the problem's Jacobian again (CVODE keeps dF/dy for the same purpose; IDA, whose
    /// linear-solver interface only receives J, re-evaluates). A Newton failure on such
    /// a matrix still triggers a full evaluation. Pays where an evaluation costs many
    /// Newton iterations (the vehicle: 25; vehicle scenes turn it on); on the small test-set
    /// problems it costs 5-20 % more steps, so it is off by default.
    pub jacobian_recombine: bool,
    /// A recombination uses a matrix evaluated at most this many steps ago; an older one
    /// is evaluated anew (CVODE's MSBJ, 50 steps). Without the limit a matrix evaluated
    /// before the trailer's impact was still recombined 112 steps later and the
    /// fixed-coefficient run at rtol 3e-3 failed there.
    pub recombine_max_age: usize,
    /// BDF stability limit detection (STALD, CVODE's `CVodeSetStabLimDet`; TOML key
    /// `stability_limit_detection`): from the scaled derivatives of the last steps at
    /// orders 3..5, detect a lightly damped mode that the step size holds inside the
    /// order's instability region and lower the order (`bdf/stald.rs`). BDF only (both
    /// variants); Radau IIA is L-stable and ignores it.
    pub stability_limit_detection: bool,
    /// Settings of the Radau IIA method (`method = "radau5"`).
    pub radau: RadauOptions,
    /// Record (time, step, order) of every accepted step in `Stats::step_history`.
    pub record_steps: bool,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            rtol: 1e-6,
            atol: vec![1e-6],
            max_order: 5,
            h_init: None,
            h_max: f64::INFINITY,
            h_min: 0.0,
            max_steps: 500_000,
            method: Method::Variable,
            algebraic: AlgebraicControl::Auto,
            linear_solver: LinearSolver::Auto,
            dense_limit: 40,
            jacobian: JacobianSource::Auto,
            max_newton_iters: 4,
            max_convergence_failures: crate::method::MXNCF,
            max_error_failures: crate::method::MXNEF,
            newton_tol: crate::bdf::EPCON,
            newton_tol_growth_cap: false,
            max_jacobian_age: 0,
            eta_fixed_max: crate::bdf::ETA_MAX_FX,
            scale_newton_matrix: true,
            vector_error_weights: true,
            matrix_transport: true,
            jacobian_recombine: false,
            recombine_max_age: 50,
            stability_limit_detection: false,
            radau: RadauOptions::default(),
            record_steps: false,
        }
    }
}

impl SolverOptions {
    /// Options with the same relative and absolute tolerance.
    pub fn with_tol(rtol: f64, atol: f64) -> Self {
        Self {
            rtol,
            atol: vec![atol],
            ..Self::default()
        }
    }

    /// Checks every setting; `n` is the problem size.
    pub fn validate(&self, n: usize) -> Result<(), SolverError> {
        let bad = |field: &str, why: String| {
            Err(SolverError::InvalidSettings {
                field: field.to_string(),
                why,
            })
        };
        if !self.rtol.is_finite() || self.rtol < 0.0 {
            return bad(
                "rtol",
                format!("must be finite and >= 0, got {}", self.rtol),
            );
        }
        if self.atol.len() != 1 && self.atol.len() != n {
            return bad(
                "atol",
                format!("needs 1 or {n} values, got {}", self.atol.len()),
            );
        }
        if let Some(a) = self.atol.iter().find(|a| !a.is_finite() || **a < 0.0) {
            return bad("atol", format!("must be finite and >= 0, got {a}"));
        }
        if self.rtol == 0.0 && self.atol.contains(&0.0) {
            return bad(
                "atol",
                "rtol and atol are both zero for some unknown: no error weight".into(),
            );
        }
        if !(1..=5).contains(&self.max_order) {
            return bad(
                "max_order",
                format!("must be 1..=5, got {}", self.max_order),
            );
        }
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return bad("h_max", format!("must be > 0, got {}", self.h_max));
        }
        if !self.h_min.is_finite() || self.h_min < 0.0 || self.h_min >= self.h_max {
            return bad(
                "h_min",
                format!("must be >= 0 and below h_max, got {}", self.h_min),
            );
        }
        if let Some(h) = self.h_init {
            if !h.is_finite() || h <= 0.0 {
                return bad("h_init", format!("must be finite and > 0, got {h}"));
            }
        }
        if self.max_newton_iters == 0 {
            return bad("max_newton_iters", "must be >= 1".into());
        }
        if !(self.newton_tol > 0.0 && self.newton_tol.is_finite()) {
            return bad(
                "newton_tol",
                format!("must be > 0, got {}", self.newton_tol),
            );
        }
        if !(1.0..=2.0).contains(&self.eta_fixed_max) {
            return bad(
                "eta_fixed_max",
                format!("must be in [1, 2], got {}", self.eta_fixed_max),
            );
        }
        if self.max_steps == 0 {
            return bad("max_steps", "must be >= 1".into());
        }
        let r = &self.radau;
        if r.jacobian_theta.is_nan() || r.jacobian_theta >= 1.0 {
            return bad(
                "radau.jacobian_theta",
                format!("must be below 1, got {}", r.jacobian_theta),
            );
        }
        if r.newton_iters == 0 {
            return bad("radau.newton_iters", "must be >= 1".into());
        }
        if !(r.keep_step_ratio >= 1.0 && r.keep_step_ratio.is_finite()) {
            return bad(
                "radau.keep_step_ratio",
                format!("must be finite and >= 1, got {}", r.keep_step_ratio),
            );
        }
        Ok(())
    }

    pub(crate) fn atol_of(&self, i: usize) -> f64 {
        if self.atol.len() == 1 {
            self.atol[0]
        } else {
            self.atol[i]
        }
    }
}

/// Counters of one integration, as IDA reports them.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Step attempts rejected by the error test or by Newton failure.
    pub rejected_steps: usize,
    /// Step attempts rejected by the local error test.
    pub error_test_failures: usize,
    /// Step attempts rejected because Newton did not converge (or the matrix was singular).
    pub convergence_failures: usize,
    /// Residual evaluations, including those spent on finite-difference Jacobians.
    pub residual_evals: usize,
    /// Iteration-matrix evaluations (analytic or finite-difference), counting the
    /// evaluation of dF/dy' that a first recombination needs.
    pub jacobian_evals: usize,
    /// Iteration matrices rebuilt for a new step size from the kept parts of the last
    /// evaluation (`jacobian_recombine`), without evaluating the problem's Jacobian.
    pub matrix_recombinations: usize,
    /// LU factorisations of the (real) iteration matrix.
    pub lu_factorizations: usize,
    /// Factorisations of Radau IIA's complex iteration matrix (one per real one).
    pub complex_lu_factorizations: usize,
    /// Non-zeros of the real iteration matrix's sparse LU factors (L + U) after the last
    /// factorisation; 0 on the dense path. Grows linearly with a model whose fill-reducing
    /// order works (`docs/performance.md`, "Scaling").
    #[cfg_attr(feature = "serde", serde(default))]
    pub lu_entries: usize,
    /// Newton iterations over all step attempts.
    pub newton_iterations: usize,
    /// Evaluations of the event (root) functions.
    pub root_evals: usize,
    /// Order and step of the last accepted step.
    pub last_order: usize,
    /// Step size of the last accepted step [s].
    pub last_step: f64,
    /// Accepted steps per order 1..=5 (Radau IIA: all at 5, its classical order).
    pub order_counts: [usize; 5],
    /// Order reductions dictated by stability limit detection
    /// (`SolverOptions::stability_limit_detection`; CVODE's nor,
    /// CVodeGetNumStabLimOrderReds).
    #[cfg_attr(feature = "serde", serde(default))]
    pub stability_order_reductions: usize,
    /// Why the iteration matrix was rebuilt.
    pub matrix_rebuilds: MatrixRebuilds,
    /// The unknowns whose error estimate dominated the most accepted steps, with the
    /// number of steps (the five most frequent; filled by [`crate::DaeMethod::step_limiters`]).
    pub step_limiters: Vec<(String, usize)>,
    /// (end time, step, order) of every accepted step, when
    /// `SolverOptions::record_steps` asks for them.
    pub step_history: Vec<(f64, f64, usize)>,
}

/// Reasons for rebuilding (and refactorising) the Newton iteration matrix (IDA's rules);
/// they add up to the LU factorisations. Radau IIA counts its pairs of factorisations the
/// same way: `invalid` the first step and evaluations after a failed error test,
/// `convergence` evaluations after a Newton failure or a contraction above
/// `RadauOptions::jacobian_theta` on a kept Jacobian, `step_change` a kept Jacobian
/// refactorised for a new step (also counted in `matrix_recombinations`).
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MatrixRebuilds {
    /// The first step, or after a failed step or a singular factorisation.
    pub invalid: usize,
    /// The leading coefficient drifted outside [0.6, 5/3] of the matrix's (a step change).
    pub step_change: usize,
    /// Newton did not converge on a matrix kept from earlier steps.
    pub convergence: usize,
    /// `max_jacobian_age` reached.
    pub age: usize,
}
