//! Work-precision comparison of towride's variable-coefficient BDF against the BDF (NDF)
//! solver of the `diffsol` crate on the stiff ODEs of the IVP test set (hires, vdpol,
//! rober).
//!
//! Both solvers get the same right-hand side and the same analytic Jacobian (from
//! [`StiffOde::rhs_jacobian`]), the same rtol/atol, and are scored by the same
//! [`towride_solver::testset::scd`] over all components at `t_end`. Wall times are the fastest of
//! repeated runs. Because equal tolerances do not give equal accuracy, the cost ratio is
//! taken at equal SCD: for each towride point, diffsol's log10(wall) is interpolated
//! piecewise linearly in SCD between diffsol's own points (no extrapolation).
//!
//! Usage: `cargo run --release -- [--json] [--out DIR] [--min-wall S] [--max-repeats N]
//! [--kmin K] [--kmax K] [--problems hires,vdpol,rober] [--linalg nalgebra|faer]
//! [--rober-atol-factor F] [--towride-cap]`.

use std::cell::{Cell, RefCell};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Instant;

use diffsol::matrix::MatrixRef;
use diffsol::{
    FaerLU, FaerMat, LinearSolver, Matrix, NalgebraLU, NalgebraMat, OdeBuilder,
    OdeEquationsImplicit, OdeSolverMethod, OdeSolverProblem, OdeSolverStopReason, Vector,
    VectorRef,
};
use serde_json::{json, Value};
use towride_solver::{Method, SolverOptions};
use towride_solver::testset::runner::{run_with, Formulation};
use towride_solver::testset::{self as verify, StiffOde, StiffOdeCase};

/// diffsol version this crate is built against (checked against Cargo.lock by hand).
const DIFFSOL_VERSION: &str = "0.18.0";
/// diffsol features enabled in Cargo.toml.
const DIFFSOL_FEATURES: &str = "default-features = false, features = [\"nalgebra\", \"faer\"]";

/// Default ratio atol / rtol for rober (see [`atol_for`]).
const ROBER_ATOL_FACTOR: f64 = 1e-4;

/// Absolute tolerance used with rtol = 10^-k for a problem (the same for both solvers).
///
/// hires and vdpol use rtol = atol. rober's y1 (2e-8) and y2 (8e-14) at t = 1e11 lie far
/// below atol = rtol, so with rtol = atol both are uncontrolled and the SCD is negative
/// at loose tolerances; rober therefore gets atol = `rober_factor` * rtol, by default
/// 1e-4 * rtol, the setting of the SUNDIALS ARKode driver for the test set's `rober.f`
/// (D. R. Reynolds: `rtol = 1.d-4; atols = 1.d-4*rtol`). The test-set file itself sets no
/// special tolerances (`settolerances` leaves `tolvec = .false.`).
fn atol_for(problem: &str, rtol: f64, rober_factor: f64) -> f64 {
    if problem == "rober" {
        rober_factor * rtol
    } else {
        rtol
    }
}

/// Which diffsol dense matrix / LU pair to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Linalg {
    Nalgebra,
    Faer,
}

impl Linalg {
    fn name(self) -> &'static str {
        match self {
            Linalg::Nalgebra => "nalgebra (NalgebraMat<f64> + NalgebraLU<f64>, dense)",
            Linalg::Faer => "faer (FaerMat<f64> + FaerLU<f64>, dense)",
        }
    }
}

/// Command-line settings.
#[derive(clap::Parser, Debug)]
#[command(
    about = "towride BDF vs diffsol BDF on the IVP test set's stiff ODEs, compared at equal scd"
)]
struct Args {
    /// Print the JSON summary to stdout.
    #[arg(long)]
    json: bool,
    /// Output folder for diffsol_compare.csv and diffsol_compare.json.
    #[arg(long, default_value_os_t = Path::new(env!("CARGO_MANIFEST_DIR")).join("out"))]
    out: PathBuf,
    /// Repeat each run until this many seconds have passed [s].
    #[arg(long, default_value_t = 0.2)]
    min_wall: f64,
    /// At most this many repeats per run (at least 1).
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u32).range(1..))]
    max_repeats: u32,
    /// Loosest tolerance exponent: rtol = 10^-kmin.
    #[arg(long, default_value_t = 4)]
    kmin: i32,
    /// Tightest tolerance exponent: rtol = 10^-kmax.
    #[arg(long, default_value_t = 10)]
    kmax: i32,
    /// Problems to run.
    #[arg(long, value_delimiter = ',', default_values_t = ["hires".to_string(), "vdpol".to_string(), "rober".to_string()])]
    problems: Vec<String>,
    /// diffsol's dense matrix and LU.
    #[arg(long, value_enum, default_value = "nalgebra")]
    linalg: Linalg,
    /// Robertson's atol as a multiple of rtol.
    #[arg(long, default_value_t = ROBER_ATOL_FACTOR)]
    rober_atol_factor: f64,
    /// Run towride with `newton_tol_growth_cap` (Newton tolerance capped at the error level
    /// the step controller acts on) instead of IDA's constant 0.33.
    #[arg(long)]
    towride_cap: bool,
}

/// One run of one solver at one tolerance.
#[derive(Clone, Debug)]
struct Point {
    problem: String,
    solver: &'static str,
    k: i32,
    rtol: f64,
    atol: f64,
    ok: bool,
    error: Option<String>,
    /// Solution at t_end (empty if the run failed).
    y: Vec<f64>,
    /// Time the solution was taken at (must equal t_end).
    t_out: f64,
    scd: Option<f64>,
    /// Fastest wall time of one run [s].
    wall_s: f64,
    repeats: usize,
    steps: Option<usize>,
    rejected_steps: Option<usize>,
    newton_iterations: Option<usize>,
    jacobian_evals: Option<usize>,
    lu_factorizations: Option<usize>,
    rhs_evals: Option<usize>,
}

impl Point {
    fn failed(
        problem: &str,
        solver: &'static str,
        k: i32,
        rtol: f64,
        atol: f64,
        wall_s: f64,
        error: String,
    ) -> Self {
        Point {
            problem: problem.to_string(),
            solver,
            k,
            rtol,
            atol,
            ok: false,
            error: Some(error),
            y: Vec::new(),
            t_out: f64::NAN,
            scd: None,
            wall_s,
            repeats: 1,
            steps: None,
            rejected_steps: None,
            newton_iterations: None,
            jacobian_evals: None,
            lu_factorizations: None,
            rhs_evals: None,
        }
    }

    fn to_json(&self) -> Value {
        json!({
            "problem": self.problem,
            "solver": self.solver,
            "k": self.k,
            "rtol": self.rtol,
            "atol": self.atol,
            "status": if self.ok { "ok" } else { "failed" },
            "error": self.error,
            "t_out": finite_or_null(self.t_out),
            "y": self.y,
            "scd": self.scd.and_then(finite_or_null),
            "wall_s": self.wall_s,
            "repeats": self.repeats,
            "steps": self.steps,
            "rejected_steps": self.rejected_steps,
            "newton_iterations": self.newton_iterations,
            "jacobian_evals": self.jacobian_evals,
            "lu_factorizations": self.lu_factorizations,
            "rhs_evals": self.rhs_evals,
        })
    }
}

fn finite_or_null(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        format!("panic: {s}")
    } else if let Some(s) = p.downcast_ref::<String>() {
        format!("panic: {s}")
    } else {
        "panic".to_string()
    }
}

/// towride's BDF through the verification runner (DAE form F = y' - f(t, y), analytic
/// iteration matrix, variable-coefficient BDF).
fn run_towride(
    b: &verify::Benchmark,
    k: i32,
    rtol: f64,
    atol: f64,
    comps: &[usize],
    min_wall: f64,
    cap: bool,
) -> Point {
    let clock = Instant::now();
    let opts = SolverOptions {
        method: Method::Variable,
        newton_tol_growth_cap: cap,
        ..SolverOptions::with_tol(rtol, atol)
    };
    let r = match catch_unwind(AssertUnwindSafe(|| {
        run_with(b, &opts, Formulation::Ggl, min_wall)
    })) {
        Ok(r) => r,
        Err(p) => {
            return Point::failed(
                b.name,
                "towride",
                k,
                rtol,
                atol,
                clock.elapsed().as_secs_f64(),
                panic_message(p),
            )
        }
    };
    if r.status != "ok" {
        let mut p = Point::failed(
            b.name,
            "towride",
            k,
            rtol,
            atol,
            r.wall_s,
            r.error.unwrap_or_default(),
        );
        p.repeats = r.repeats;
        return p;
    }
    let scd = verify::scd(&r.y, &b.reference, comps);
    Point {
        problem: b.name.to_string(),
        solver: "towride",
        k,
        rtol,
        atol,
        ok: true,
        error: None,
        t_out: r.t_end,
        scd: Some(scd),
        y: r.y,
        wall_s: r.wall_s,
        repeats: r.repeats,
        steps: Some(r.steps),
        rejected_steps: Some(r.rejected_steps),
        newton_iterations: Some(r.newton_iterations),
        jacobian_evals: Some(r.jacobian_evals),
        lu_factorizations: Some(r.lu_factorizations),
        rhs_evals: Some(r.residual_evals),
    }
}

/// Counters kept by the closures handed to diffsol, reset before each run.
#[derive(Default)]
struct Counters {
    rhs: Cell<usize>,
    jac_mul: Cell<usize>,
}

/// Statistics of one diffsol run.
struct DiffsolRun {
    y: Vec<f64>,
    t_out: f64,
    wall_s: f64,
    steps: usize,
    rejected_steps: usize,
    newton_iterations: usize,
    lu_factorizations: usize,
}

/// One diffsol BDF run from t0 to t_end on an already built problem: a fresh solver
/// (consistent initial state, initial step), the stop time set to t_end so that the last
/// step is shortened to land on it, stepping until `TstopReached`, and the state taken at
/// t_end (interpolated back should the last step overshoot by round-off).
fn diffsol_once<Eqn, LS>(problem: &OdeSolverProblem<Eqn>, t_end: f64) -> Result<DiffsolRun, String>
where
    Eqn: OdeEquationsImplicit<T = f64>,
    Eqn::V: diffsol::DefaultDenseMatrix,
    LS: LinearSolver<Eqn::M>,
    for<'b> &'b Eqn::V: VectorRef<Eqn::V>,
    for<'b> &'b Eqn::M: MatrixRef<Eqn::M>,
{
    let start = Instant::now();
    let mut solver = problem.bdf::<LS>().map_err(|e| e.to_string())?;
    solver.set_stop_time(t_end).map_err(|e| e.to_string())?;
    loop {
        match solver.step().map_err(|e| e.to_string())? {
            OdeSolverStopReason::TstopReached => break,
            OdeSolverStopReason::InternalTimestep => {}
            OdeSolverStopReason::RootFound(t, _) => {
                return Err(format!("unexpected root at t = {t}"))
            }
        }
    }
    let state = solver.state();
    let (y, t_out) = if state.t == t_end {
        (state.y.clone_as_vec(), state.t)
    } else if state.t > t_end {
        let y = solver.interpolate(t_end).map_err(|e| e.to_string())?;
        (y.clone_as_vec(), t_end)
    } else {
        // Within diffsol's round-off window below t_end (100 eps (|t| + |h|)); it cannot
        // interpolate forward, so the state is taken as is and t_out records where.
        (state.y.clone_as_vec(), state.t)
    };
    let wall_s = start.elapsed().as_secs_f64();
    let s = solver.get_statistics();
    Ok(DiffsolRun {
        y,
        t_out,
        wall_s,
        steps: s.number_of_steps,
        rejected_steps: s.number_of_error_test_failures + s.number_of_nonlinear_solver_fails,
        newton_iterations: s.number_of_nonlinear_solver_iterations,
        lu_factorizations: s.number_of_linear_solver_setups,
    })
}

/// diffsol's BDF on the explicit ODE y' = f(t, y) with the analytic Jacobian given as its
/// action J v (assembled from `rhs_jacobian`), repeated until `min_wall` seconds have
/// passed (at most `max_repeats` runs), fastest kept.
#[allow(clippy::too_many_arguments)]
fn run_diffsol_with<M, LS>(
    case: &StiffOdeCase,
    name: &str,
    k: i32,
    rtol: f64,
    atol: f64,
    comps: &[usize],
    min_wall: f64,
    max_repeats: usize,
) -> Point
where
    M: Matrix<T = f64>,
    LS: LinearSolver<M>,
    M::V: diffsol::DefaultDenseMatrix,
    for<'b> &'b M::V: VectorRef<M::V>,
    for<'b> &'b M: MatrixRef<M>,
{
    let ode: &dyn StiffOde = case.ode.as_ref();
    let n = ode.dim();
    let y0 = case.y0.clone();
    let counters = Counters::default();
    let scratch: RefCell<Vec<(usize, usize, f64)>> = RefCell::new(Vec::with_capacity(4 * n));
    let problem = OdeBuilder::<M>::new()
        .t0(case.t0)
        .rtol(rtol)
        .atol([atol])
        .rhs_implicit(
            |x: &[f64], _p: &[f64], t: f64, f: &mut [f64]| {
                counters.rhs.set(counters.rhs.get() + 1);
                ode.rhs(t, x, f);
            },
            |x: &[f64], _p: &[f64], t: f64, v: &[f64], jv: &mut [f64]| {
                counters.jac_mul.set(counters.jac_mul.get() + 1);
                let mut entries = scratch.borrow_mut();
                entries.clear();
                ode.rhs_jacobian(t, x, &mut entries);
                jv.fill(0.0);
                for &(r, c, val) in entries.iter() {
                    jv[r] += val * v[c];
                }
            },
        )
        .init(
            move |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&y0),
            n,
        )
        .build();
    let problem = match problem {
        Ok(p) => p,
        Err(e) => return Point::failed(name, "diffsol", k, rtol, atol, 0.0, format!("build: {e}")),
    };
    let clock = Instant::now();
    let mut best: Option<DiffsolRun> = None;
    let mut repeats = 0;
    let mut last_counts;
    loop {
        counters.rhs.set(0);
        counters.jac_mul.set(0);
        let r = match catch_unwind(AssertUnwindSafe(|| {
            diffsol_once::<_, LS>(&problem, case.t_end)
        })) {
            Ok(r) => r,
            Err(p) => Err(panic_message(p)),
        };
        repeats += 1;
        match r {
            Ok(run) => {
                last_counts = (counters.rhs.get(), counters.jac_mul.get());
                if best.as_ref().is_none_or(|b| run.wall_s < b.wall_s) {
                    best = Some(run);
                }
            }
            Err(e) => {
                let mut p = Point::failed(
                    name,
                    "diffsol",
                    k,
                    rtol,
                    atol,
                    clock.elapsed().as_secs_f64(),
                    e,
                );
                p.repeats = repeats;
                return p;
            }
        }
        if clock.elapsed().as_secs_f64() >= min_wall || repeats >= max_repeats {
            break;
        }
    }
    let run = best.expect("at least one successful run");
    let scd = verify::scd(&run.y, &case.reference, comps);
    Point {
        problem: name.to_string(),
        solver: "diffsol",
        k,
        rtol,
        atol,
        ok: true,
        error: None,
        scd: Some(scd),
        t_out: run.t_out,
        y: run.y,
        wall_s: run.wall_s,
        repeats,
        steps: Some(run.steps),
        rejected_steps: Some(run.rejected_steps),
        newton_iterations: Some(run.newton_iterations),
        // The dense Jacobian is assembled column by column from n products J e_j.
        jacobian_evals: Some(last_counts.1 / n),
        lu_factorizations: Some(run.lu_factorizations),
        rhs_evals: Some(last_counts.0),
    }
}

#[allow(clippy::too_many_arguments)]
fn run_diffsol(
    case: &StiffOdeCase,
    name: &str,
    k: i32,
    rtol: f64,
    atol: f64,
    comps: &[usize],
    min_wall: f64,
    max_repeats: usize,
    linalg: Linalg,
) -> Point {
    match linalg {
        Linalg::Nalgebra => run_diffsol_with::<NalgebraMat<f64>, NalgebraLU<f64>>(
            case,
            name,
            k,
            rtol,
            atol,
            comps,
            min_wall,
            max_repeats,
        ),
        Linalg::Faer => run_diffsol_with::<FaerMat<f64>, FaerLU<f64>>(
            case,
            name,
            k,
            rtol,
            atol,
            comps,
            min_wall,
            max_repeats,
        ),
    }
}

/// A towride point compared with diffsol at the same SCD.
#[derive(Clone, Debug)]
struct Ratio {
    problem: String,
    k: i32,
    scd: f64,
    towride_wall_s: f64,
    /// diffsol's wall time interpolated at towride's SCD [s]; `None` outside its range.
    diffsol_wall_s: Option<f64>,
    /// towride wall / diffsol wall at equal SCD.
    ratio: Option<f64>,
}

/// diffsol's wall time at `scd`: log10(wall) interpolated piecewise linearly in SCD over
/// diffsol's points sorted by SCD, `None` outside [min SCD, max SCD]. Points of equal SCD
/// are merged into the geometric mean of their walls.
fn interpolate_wall(points: &[(f64, f64)], scd: f64) -> Option<f64> {
    let mut pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(s, w)| s.is_finite() && *w > 0.0)
        .map(|&(s, w)| (s, w.log10()))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut merged: Vec<(f64, f64, usize)> = Vec::new();
    for (s, lw) in pts {
        match merged.last_mut() {
            Some(last) if last.0 == s => {
                last.1 += lw;
                last.2 += 1;
            }
            _ => merged.push((s, lw, 1)),
        }
    }
    let merged: Vec<(f64, f64)> = merged
        .into_iter()
        .map(|(s, lw, c)| (s, lw / c as f64))
        .collect();
    let (first, last) = (merged.first()?, merged.last()?);
    if scd < first.0 || scd > last.0 {
        return None;
    }
    if merged.len() == 1 {
        return Some(10f64.powf(first.1));
    }
    for w in merged.windows(2) {
        let ((s0, l0), (s1, l1)) = (w[0], w[1]);
        if scd >= s0 && scd <= s1 {
            let lw = l0 + (l1 - l0) * (scd - s0) / (s1 - s0);
            return Some(10f64.powf(lw));
        }
    }
    None
}

fn ratios(points: &[Point], problem: &str) -> Vec<Ratio> {
    let diffsol: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.problem == problem && p.solver == "diffsol" && p.ok)
        .filter_map(|p| p.scd.map(|s| (s, p.wall_s)))
        .collect();
    points
        .iter()
        .filter(|p| p.problem == problem && p.solver == "towride" && p.ok)
        .filter_map(|p| {
            let scd = p.scd.filter(|s| s.is_finite())?;
            let dw = interpolate_wall(&diffsol, scd);
            Some(Ratio {
                problem: problem.to_string(),
                k: p.k,
                scd,
                towride_wall_s: p.wall_s,
                diffsol_wall_s: dw,
                ratio: dw.map(|d| p.wall_s / d),
            })
        })
        .collect()
}

fn geometric_mean(xs: &[f64]) -> Option<f64> {
    if xs.is_empty() {
        return None;
    }
    Some((xs.iter().map(|x| x.ln()).sum::<f64>() / xs.len() as f64).exp())
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

fn opt_usize(x: Option<usize>) -> String {
    x.map(|v| v.to_string()).unwrap_or_default()
}

fn opt_f64(x: Option<f64>, prec: usize) -> String {
    match x {
        Some(v) if v.is_finite() => format!("{v:.prec$e}"),
        Some(v) => format!("{v}"),
        None => String::new(),
    }
}

fn write_csv(path: &Path, points: &[Point], all_ratios: &[Ratio]) -> Result<(), String> {
    let mut w = csv::Writer::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    w.write_record([
        "problem",
        "solver",
        "k",
        "rtol [-]",
        "atol [-]",
        "status",
        "t_out [problem time]",
        "scd [digits]",
        "wall [s]",
        "repeats",
        "steps",
        "rejected steps",
        "newton iterations",
        "jacobian evals",
        "lu factorizations",
        "rhs evals",
        "diffsol wall at equal scd [s]",
        "ratio towride/diffsol at equal scd [-]",
        "error",
    ])
    .map_err(|e| e.to_string())?;
    for p in points {
        let r = all_ratios
            .iter()
            .find(|r| p.solver == "towride" && r.problem == p.problem && r.k == p.k);
        w.write_record([
            p.problem.clone(),
            p.solver.to_string(),
            p.k.to_string(),
            format!("{:e}", p.rtol),
            format!("{:e}", p.atol),
            if p.ok { "ok" } else { "failed" }.to_string(),
            if p.t_out.is_finite() {
                format!("{:e}", p.t_out)
            } else {
                String::new()
            },
            p.scd.map(|s| format!("{s:.4}")).unwrap_or_default(),
            format!("{:.6e}", p.wall_s),
            p.repeats.to_string(),
            opt_usize(p.steps),
            opt_usize(p.rejected_steps),
            opt_usize(p.newton_iterations),
            opt_usize(p.jacobian_evals),
            opt_usize(p.lu_factorizations),
            opt_usize(p.rhs_evals),
            opt_f64(r.and_then(|r| r.diffsol_wall_s), 6),
            r.and_then(|r| r.ratio)
                .map(|x| format!("{x:.4}"))
                .unwrap_or_default(),
            p.error.clone().unwrap_or_default(),
        ])
        .map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())
}

fn print_tables(points: &[Point], all_ratios: &[Ratio], geo: &[(String, Option<f64>, usize)]) {
    println!("Raw points (rtol = 10^-k, wall = fastest of repeats):");
    println!(
        "{:<6} {:<8} {:>3} {:>8} {:>8} {:>7} {:>11} {:>5} {:>6} {:>5} {:>7} {:>5} {:>5}  status",
        "prob",
        "solver",
        "k",
        "rtol",
        "atol",
        "scd",
        "wall [s]",
        "reps",
        "steps",
        "rej",
        "newton",
        "jac",
        "LU"
    );
    for p in points {
        println!(
            "{:<6} {:<8} {:>3} {:>8.0e} {:>8.0e} {:>7} {:>11.4e} {:>5} {:>6} {:>5} {:>7} {:>5} {:>5}  {}",
            p.problem,
            p.solver,
            p.k,
            p.rtol,
            p.atol,
            p.scd.map(|s| format!("{s:.2}")).unwrap_or_else(|| "-".into()),
            p.wall_s,
            p.repeats,
            opt_usize(p.steps),
            opt_usize(p.rejected_steps),
            opt_usize(p.newton_iterations),
            opt_usize(p.jacobian_evals),
            opt_usize(p.lu_factorizations),
            if p.ok { "ok".to_string() } else { format!("FAILED: {}", p.error.as_deref().unwrap_or("")) }
        );
    }
    println!();
    println!(
        "towride wall / diffsol wall at equal SCD (diffsol interpolated in SCD, no extrapolation):"
    );
    println!(
        "{:<6} {:>3} {:>8} {:>14} {:>20} {:>8}",
        "prob", "k", "scd", "towride [s]", "diffsol@scd [s]", "ratio"
    );
    for r in all_ratios {
        println!(
            "{:<6} {:>3} {:>8.2} {:>14.4e} {:>20} {:>8}",
            r.problem,
            r.k,
            r.scd,
            r.towride_wall_s,
            r.diffsol_wall_s
                .map(|w| format!("{w:.4e}"))
                .unwrap_or_else(|| "out of range".into()),
            r.ratio
                .map(|x| format!("{x:.3}"))
                .unwrap_or_else(|| "-".into())
        );
    }
    println!();
    for (problem, g, n) in geo {
        println!(
            "{problem:<6} geometric mean ratio towride/diffsol = {} over {n} points",
            g.map(|g| format!("{g:.3}")).unwrap_or_else(|| "-".into())
        );
    }
}

fn main() {
    let args = <Args as clap::Parser>::parse();
    if args.kmin > args.kmax {
        eprintln!("--kmin must not exceed --kmax");
        std::process::exit(2);
    }
    let cases = verify::stiff_odes();
    let mut points: Vec<Point> = Vec::new();
    let mut all_ratios: Vec<Ratio> = Vec::new();
    let mut geo: Vec<(String, Option<f64>, usize)> = Vec::new();
    for name in &args.problems {
        let Some(case) = cases.iter().find(|c| c.ode.name() == name) else {
            eprintln!("unknown problem `{name}` (hires, vdpol, rober)");
            std::process::exit(2);
        };
        let bench = verify::by_name(name).expect("every stiff ODE is a benchmark");
        assert_eq!(
            bench.t0, case.t0,
            "{name}: t0 differs between the DAE and ODE forms"
        );
        assert_eq!(bench.t_end, case.t_end, "{name}: t_end differs");
        assert_eq!(bench.y0, case.y0, "{name}: y0 differs");
        assert_eq!(bench.reference, case.reference, "{name}: reference differs");
        // SCD over all components, the same for both solvers.
        let comps: Vec<usize> = (0..case.ode.dim()).collect();
        for k in args.kmin..=args.kmax {
            let rtol = 10f64.powi(-k);
            let atol = atol_for(name, rtol, args.rober_atol_factor);
            eprintln!("{name} k={k}: towride ...");
            points.push(run_towride(
                &bench,
                k,
                rtol,
                atol,
                &comps,
                args.min_wall,
                args.towride_cap,
            ));
            eprintln!("{name} k={k}: diffsol ...");
            points.push(run_diffsol(
                case,
                name,
                k,
                rtol,
                atol,
                &comps,
                args.min_wall,
                args.max_repeats as usize,
                args.linalg,
            ));
        }
        let rs = ratios(&points, name);
        let valid: Vec<f64> = rs.iter().filter_map(|r| r.ratio).collect();
        geo.push((name.clone(), geometric_mean(&valid), valid.len()));
        all_ratios.extend(rs);
    }

    let failures: Vec<Value> = points
        .iter()
        .filter(|p| !p.ok)
        .map(|p| json!({"problem": p.problem, "solver": p.solver, "k": p.k, "error": p.error}))
        .collect();
    let summary = json!({
        "description": "towride BDF vs diffsol BDF, work-precision on the test-set stiff ODEs; \
                        ratio = towride wall / diffsol wall at equal SCD",
        "machine": {
            "cpu": cpu_model(),
            "threads": std::thread::available_parallelism().map(|n| n.get()).unwrap_or(0),
        },
        "diffsol": {
            "version": DIFFSOL_VERSION,
            "cargo": DIFFSOL_FEATURES,
            "linear_algebra": args.linalg.name(),
            "jacobian": "analytic, as closure J*v assembled from StiffOde::rhs_jacobian; \
                         diffsol builds the dense matrix from n products J e_j",
        },
        "towride": {
            "method": "Variable (variable-coefficient BDF, fixed-leading-coefficient form)",
            "entry": "towride_solver::testset::runner::run_with on the DAE form F = y' - f(t, y)",
            "newton_tol_growth_cap": args.towride_cap,
        },
        "settings": {
            "tolerances": "rtol = 10^-k; atol = rtol for hires and vdpol, atol = rober_atol_factor * rtol for rober",
            "rober_atol_factor": args.rober_atol_factor,
            "k": [args.kmin, args.kmax],
            "min_wall_s": args.min_wall,
            "max_repeats": args.max_repeats,
            "scd": "towride_solver::testset::scd over all components at t_end",
        },
        "points": points.iter().map(Point::to_json).collect::<Vec<_>>(),
        "ratios": all_ratios.iter().map(|r| json!({
            "problem": r.problem,
            "k": r.k,
            "scd": r.scd,
            "towride_wall_s": r.towride_wall_s,
            "diffsol_wall_at_scd_s": r.diffsol_wall_s,
            "ratio": r.ratio,
        })).collect::<Vec<_>>(),
        "geometric_mean_ratio": geo.iter().map(|(p, g, n)| json!({
            "problem": p, "ratio": g, "points": n,
        })).collect::<Vec<_>>(),
        "failures": failures,
    });

    if let Err(e) = std::fs::create_dir_all(&args.out) {
        eprintln!("{}: {e}", args.out.display());
        std::process::exit(1);
    }
    let csv_path = args.out.join("diffsol_compare.csv");
    if let Err(e) = write_csv(&csv_path, &points, &all_ratios) {
        eprintln!("{e}");
        std::process::exit(1);
    }
    let json_path = args.out.join("diffsol_compare.json");
    let text = serde_json::to_string_pretty(&summary).expect("JSON serialises");
    if let Err(e) = std::fs::write(&json_path, &text) {
        eprintln!("{}: {e}", json_path.display());
        std::process::exit(1);
    }
    if args.json {
        println!("{text}");
    } else {
        print_tables(&points, &all_ratios, &geo);
        println!();
        println!("wrote {} and {}", csv_path.display(), json_path.display());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_is_linear_in_log_wall_and_does_not_extrapolate() {
        let pts = [(4.0, 1e-3), (6.0, 1e-1), (5.0, 1e-2)];
        assert!((interpolate_wall(&pts, 5.5).unwrap() - 10f64.powf(-1.5)).abs() < 1e-15);
        assert!((interpolate_wall(&pts, 4.0).unwrap() - 1e-3).abs() < 1e-15);
        assert!(interpolate_wall(&pts, 3.99).is_none());
        assert!(interpolate_wall(&pts, 6.01).is_none());
        assert!(interpolate_wall(&[], 5.0).is_none());
    }

    #[test]
    fn geometric_mean_of_ratios() {
        assert!((geometric_mean(&[2.0, 8.0]).unwrap() - 4.0).abs() < 1e-12);
        assert!(geometric_mean(&[]).is_none());
    }
}
