//! The work-precision study of a scene: a tight reference run, then each method (the BDF
//! variants and Radau IIA) over a tolerance range, with wall time, steps, Jacobians and
//! the errors of the key outputs against the reference; the methods' cost at equal
//! accuracy; their step-size and order histories at the scene's own tolerance. Written as
//! `bench.csv`, `bench.json`, a log-log `bench.png`, `steps.csv` and `steps.png`.

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::Serialize;

use super::{pool, total_wall, Reference};
use crate::error::{Error, Result};
use crate::job::{Job, RunResult};
use crate::report::plot::{loglog_panels, Panel, Series};
use crate::report::steps::{step_history_plot, StepHistory};
use crate::scene::Changes;
use towride_mbs::input::Loader;
use towride_mbs::progress::{Progress, StopOnly};
use towride_solver::{Method, SolverOptions};

/// Version of `bench.json`'s layout. 2: the signed hitch peak is gone for its
/// magnitude (`hitch_abs_peak_n`, `hitch_abs_peak_error`). 3: `status` and
/// `interrupted` (a study stopped by Ctrl-C).
pub const SCHEMA_VERSION: u32 = 3;

/// What to measure.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Relative tolerances of the study.
    pub tol: Vec<f64>,
    /// Relative tolerance of the reference run.
    pub reference_tol: f64,
    /// Band of the in-band sensor error [Hz] (the measurements' acquisition low-pass).
    pub band_hz: f64,
    /// Parallel runs (1 keeps the timings undisturbed).
    pub jobs: usize,
    /// Runs of each setting; the fastest wall time is kept.
    pub repeat: usize,
    /// The integrator variants compared.
    pub methods: Vec<Method>,
    /// Hitch |peak| errors at which the methods' cost is compared (the fastest run of
    /// each method whose error is at most this).
    pub equal_error: Vec<f64>,
    /// The same for the sensors' in-band error.
    pub equal_band_error: Vec<f64>,
    /// Reads the scene's files (the command line's overrides).
    pub loader: Loader,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            tol: vec![1e-2, 3e-3, 1e-3, 3e-4, 1e-4],
            reference_tol: 1e-6,
            band_hz: 100.0,
            jobs: 1,
            repeat: 3,
            methods: vec![Method::Variable, Method::FixedCoefficient, Method::Radau5],
            equal_error: vec![1e-2, 2e-3],
            equal_band_error: vec![2e-2, 1e-2],
            loader: Loader::new(),
        }
    }
}

/// One run of the study and its errors against the reference.
#[derive(Clone, Debug, Serialize)]
pub struct Point {
    /// Integrator variant.
    pub method: &'static str,
    /// Relative tolerance.
    pub rtol: f64,
    /// "completed" or "failed: ...".
    pub status: String,
    /// Fastest wall time, start included [s].
    pub wall_s: f64,
    /// Simulated time over wall time.
    pub realtime_factor: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Jacobian evaluations.
    pub jacobian_evals: usize,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// The hitch force's |peak|, max(|max|, |min|) [N].
    pub hitch_abs_peak_n: f64,
    /// ||peak| - |reference peak|| / |reference peak|.
    pub hitch_abs_peak_error: f64,
    /// RMS of the hitch-force difference over the reference's RMS.
    pub hitch_rms_error: f64,
    /// Mean over the acceleration sensors of their relative RMS errors.
    pub sensor_rms_error: f64,
    /// The same after the measurements' low-pass: the error a comparison with recorded
    /// data sees.
    pub sensor_band_error: f64,
}

/// The reference run.
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceRun {
    /// Its relative tolerance.
    pub rtol: f64,
    /// Wall time, start included [s].
    pub wall_s: f64,
    /// Accepted steps.
    pub steps: usize,
    /// The hitch force's |peak| [N].
    pub hitch_abs_peak_n: f64,
}

/// The study's result.
#[derive(Clone, Debug, Serialize)]
pub struct Bench {
    /// Layout version.
    pub schema_version: u32,
    /// "completed", or "interrupted" (Ctrl-C): runs not begun or stopped say so, and
    /// the step histories end where it came.
    pub status: &'static str,
    /// Runs not begun or stopped by the interruption.
    pub interrupted: usize,
    /// The scene file.
    pub scene: String,
    /// Simulated time [s].
    pub duration_s: f64,
    /// Unknowns of the model.
    pub equations: usize,
    /// Modal coordinates among them.
    pub modal_coordinates: usize,
    /// The reference run.
    pub reference: ReferenceRun,
    /// Every run of the study.
    pub runs: Vec<Point>,
    /// Each method's cheapest run at or below each error target.
    pub at_equal_error: Vec<AtError>,
    /// Each method's run at the scene's own settings, its steps recorded.
    pub step_histories: Vec<HistorySummary>,
    /// Files written, once written.
    pub csv: Option<String>,
    /// The plot, once written.
    pub plot: Option<String>,
    /// The step-history plot, once written.
    pub step_plot: Option<String>,
    /// The recorded steps: (method, [(end time [s], step [s], order)]).
    #[serde(skip)]
    pub histories: Histories,
}

/// A method's cheapest run at or below an error.
#[derive(Clone, Debug, Serialize)]
pub struct AtError {
    /// The method.
    pub method: &'static str,
    /// The error measure.
    pub measure: &'static str,
    /// The error target.
    pub target: f64,
    /// The run's rtol (`None`: no run of the study reached the target).
    pub rtol: Option<f64>,
    /// Its wall time [s].
    pub wall_s: f64,
    /// Simulated over wall time.
    pub realtime_factor: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Its error.
    pub error: f64,
}

/// One method's run at the scene's tolerance with its steps recorded.
#[derive(Clone, Debug, Serialize)]
pub struct HistorySummary {
    /// The method.
    pub method: &'static str,
    /// Accepted steps.
    pub steps: usize,
    /// Mean step [s].
    pub mean_step_s: f64,
    /// Wall time, start included [s].
    pub wall_s: f64,
    /// The unknowns that limited the most steps.
    pub limiters: Vec<String>,
}

/// A name for a method, as `bench.csv` writes it.
pub fn method_name(m: Method) -> &'static str {
    match m {
        Method::Variable => "variable",
        Method::FixedCoefficient => "fixed",
        Method::Radau5 => "radau",
    }
}

/// A method's name in legends.
fn method_label(m: Method) -> String {
    match m {
        Method::Radau5 => "Radau IIA (order 5)".into(),
        _ => format!("BDF {}-coefficient", method_name(m)),
    }
}

fn run_at(
    scene: &Path,
    loader: &Loader,
    stop: &dyn Progress,
    f: impl FnOnce(&mut SolverOptions),
) -> Result<RunResult> {
    Job::from_scene_file(scene, &Changes::default(), loader)?
        .without_view()
        .tune(f)?
        .run(stop)
}

/// A point before anything is known of it.
fn blank(method: Method, rtol: f64) -> Point {
    Point {
        method: method_name(method),
        rtol,
        status: String::new(),
        wall_s: f64::NAN,
        realtime_factor: f64::NAN,
        steps: 0,
        jacobian_evals: 0,
        newton_iterations: 0,
        hitch_abs_peak_n: f64::NAN,
        hitch_abs_peak_error: f64::NAN,
        hitch_rms_error: f64::NAN,
        sensor_rms_error: f64::NAN,
        sensor_band_error: f64::NAN,
    }
}

fn point(method: Method, rtol: f64, r: &Result<RunResult>, reference: &Reference) -> Point {
    let mut p = blank(method, rtol);
    match r {
        Ok(r) if r.completed() => {
            let e = reference.errors(r);
            let s = &r.summary;
            p.status = "completed".into();
            p.wall_s = total_wall(r);
            p.realtime_factor = s.t_end_s / p.wall_s;
            p.steps = s.solver.steps;
            p.jacobian_evals = s.solver.jacobian_evals;
            p.newton_iterations = s.solver.newton_iterations;
            p.hitch_abs_peak_n = e.extremes.abs_peak;
            p.hitch_abs_peak_error = e.abs_peak_error;
            p.hitch_rms_error = e.hitch_rms;
            p.sensor_rms_error = e.sensor_rms;
            p.sensor_band_error = reference.band_error(r);
        }
        Ok(r) => match r.samples.interrupted {
            Some(t) => p.status = super::interrupted_at(t),
            None => p.status = format!("failed: {}", r.failure().map_or("", |f| f.0)),
        },
        Err(e) => p.status = format!("failed: {e}"),
    }
    p
}

/// Runs the study on `scene`; `progress` counts the runs after the reference.
pub fn run(scene: &Path, s: &Settings, progress: &dyn Progress) -> Result<Bench> {
    // The reference tightens the absolute tolerances with the relative one: with the
    // scene's atol the crossbeam's modal coordinates (micrometres) would be held only to
    // atol, and their 200-300 Hz modes ring at that level in the raw accelerations.
    let stop = StopOnly(progress);
    let reference = run_at(scene, &s.loader, &stop, |o| {
        let f = s.reference_tol / o.rtol;
        if f < 1.0 {
            o.atol.iter_mut().for_each(|x| *x *= f);
        }
        o.rtol = s.reference_tol;
        o.method = Method::Variable;
    })?;
    reference.require_completed()?;
    let refdata =
        Reference::of(&reference).with_band(s.band_hz, reference.summary.sample_rate_hz)?;
    let cases: Vec<(Method, f64)> = s
        .methods
        .iter()
        .flat_map(|&m| s.tol.iter().map(move |&t| (m, t)))
        .collect();
    progress.begin(cases.len() as u64);
    let tuned = |m: Method, rtol: f64| {
        move |o: &mut SolverOptions| {
            o.rtol = rtol;
            o.method = m;
        }
    };
    let points: Vec<Point> = pool(s.jobs)?.install(|| {
        cases
            .par_iter()
            .map(|&(m, t)| {
                // Stopped: runs not begun say so (their timings would mean nothing).
                if progress.cancelled() {
                    return Point {
                        status: super::NOT_RUN.into(),
                        ..blank(m, t)
                    };
                }
                let mut r = run_at(scene, &s.loader, &stop, tuned(m, t));
                for _ in 1..s.repeat.max(1) {
                    let again = run_at(scene, &s.loader, &stop, tuned(m, t));
                    if let (Ok(best), Ok(x)) = (&mut r, again) {
                        if total_wall(&x) < total_wall(best) {
                            best.summary.wall_s = x.summary.wall_s;
                            best.summary.start_wall_s = x.summary.start_wall_s;
                        }
                    }
                }
                progress.inc(1);
                point(m, t, &r, &refdata)
            })
            .collect()
    });
    progress.finish();
    let mut at_equal_error = at_equal(&points, &s.methods, &s.equal_error, ErrorMeasure::HitchPeak);
    at_equal_error.extend(at_equal(
        &points,
        &s.methods,
        &s.equal_band_error,
        ErrorMeasure::SensorBand,
    ));
    let (step_histories, histories) = step_histories(scene, &s.methods, &s.loader, &stop)?;
    let interrupted = points.iter().filter(|p| super::stopped(&p.status)).count();
    let job = &reference.summary;
    Ok(Bench {
        schema_version: SCHEMA_VERSION,
        status: if interrupted > 0 || progress.cancelled() {
            "interrupted"
        } else {
            "completed"
        },
        interrupted,
        scene: scene.display().to_string(),
        duration_s: job.t_end_s,
        equations: job.equations,
        modal_coordinates: job.modal_energy.iter().map(|b| b.shares.modes.len()).sum(),
        reference: ReferenceRun {
            rtol: s.reference_tol,
            wall_s: total_wall(&reference),
            steps: job.solver.steps,
            hitch_abs_peak_n: refdata.extremes.abs_peak,
        },
        runs: points,
        at_equal_error,
        step_histories,
        csv: None,
        plot: None,
        step_plot: None,
        histories,
    })
}

/// The error measure a cost comparison is made at.
#[derive(Clone, Copy, Debug)]
enum ErrorMeasure {
    HitchPeak,
    SensorBand,
}

impl ErrorMeasure {
    fn name(self) -> &'static str {
        match self {
            ErrorMeasure::HitchPeak => "hitch |peak| error",
            ErrorMeasure::SensorBand => "sensor in-band error",
        }
    }

    fn of(self, p: &Point) -> f64 {
        match self {
            ErrorMeasure::HitchPeak => p.hitch_abs_peak_error,
            ErrorMeasure::SensorBand => p.sensor_band_error,
        }
    }
}

/// For each method and target, the fastest completed run whose error is at most the
/// target: cost at equal accuracy, without interpolating between tolerances (the errors
/// are not monotone in rtol).
fn at_equal(
    points: &[Point],
    methods: &[Method],
    targets: &[f64],
    measure: ErrorMeasure,
) -> Vec<AtError> {
    let mut out = Vec::new();
    for &target in targets {
        for &m in methods {
            let name = method_name(m);
            let best = points
                .iter()
                .filter(|p| p.method == name && p.status == "completed")
                .filter(|p| measure.of(p) <= target)
                .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
            out.push(AtError {
                method: name,
                measure: measure.name(),
                target,
                rtol: best.map(|p| p.rtol),
                wall_s: best.map_or(f64::NAN, |p| p.wall_s),
                realtime_factor: best.map_or(f64::NAN, |p| p.realtime_factor),
                steps: best.map_or(0, |p| p.steps),
                error: best.map_or(f64::NAN, |p| measure.of(p)),
            });
        }
    }
    out
}

/// Per method, its accepted steps: (end time [s], step [s], order).
pub type Histories = Vec<(Method, Vec<(f64, f64, usize)>)>;

/// Runs each method at the scene's own settings with the step history recorded.
fn step_histories(
    scene: &Path,
    methods: &[Method],
    loader: &Loader,
    stop: &dyn Progress,
) -> Result<(Vec<HistorySummary>, Histories)> {
    let mut hist = Vec::new();
    let mut summary = Vec::new();
    for &m in methods {
        let r = run_at(scene, loader, stop, |o| {
            o.method = m;
            o.record_steps = true;
        })?;
        // Interrupted: the histories so far, the study's points are kept.
        if stop.cancelled() || r.samples.interrupted.is_some() {
            break;
        }
        r.require_completed()?;
        let st = &r.samples.stats;
        summary.push(HistorySummary {
            method: method_name(m),
            steps: st.steps,
            mean_step_s: r.summary.t_end_s / st.steps.max(1) as f64,
            wall_s: total_wall(&r),
            limiters: st
                .step_limiters
                .iter()
                .map(|(n, k)| format!("{n} ({k})"))
                .collect(),
        });
        hist.push((m, st.step_history.clone()));
    }
    Ok((summary, hist))
}

impl Bench {
    /// True when every run of the study completed.
    pub fn all_completed(&self) -> bool {
        self.runs.iter().all(|p| p.status == "completed")
    }

    /// Writes `bench.csv`, `bench.png` and `bench.json` into `dir`.
    pub fn write(&mut self, dir: &Path) -> Result<PathBuf> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let csv = dir.join("bench.csv");
        write_csv(&csv, &self.runs)?;
        let png = dir.join("bench.png");
        plot(&png, &self.runs)?;
        self.csv = Some(csv.display().to_string());
        self.plot = Some(png.display().to_string());
        if !self.histories.is_empty() {
            let steps_csv = dir.join("steps.csv");
            let io = |e: csv::Error| Error::io(&steps_csv, e.into());
            let mut w = csv::Writer::from_path(&steps_csv).map_err(io)?;
            w.write_record(["method", "t [s]", "h [s]", "order"])
                .map_err(io)?;
            for (m, steps) in &self.histories {
                for &(t, dt, k) in steps {
                    w.write_record([
                        method_name(*m).to_string(),
                        format!("{t:.9e}"),
                        format!("{dt:.6e}"),
                        k.to_string(),
                    ])
                    .map_err(io)?;
                }
            }
            w.flush().map_err(|e| Error::io(&steps_csv, e))?;
            let steps_png = dir.join("steps.png");
            let hist: Vec<StepHistory> = self
                .histories
                .iter()
                .map(|(m, steps)| StepHistory {
                    label: method_label(*m),
                    steps: steps.clone(),
                })
                .collect();
            step_history_plot(&steps_png, &hist)?;
            self.step_plot = Some(steps_png.display().to_string());
        }
        let json = dir.join("bench.json");
        let text = serde_json::to_string_pretty(self).unwrap_or_default();
        std::fs::write(&json, text).map_err(|e| Error::io(&json, e))?;
        Ok(json)
    }
}

/// The columns of `bench.csv`, in [`Point`]'s order.
const COLUMNS: [&str; 13] = [
    "method",
    "rtol [-]",
    "status",
    "wall [s]",
    "realtime_factor [-]",
    "steps",
    "jacobian_evals",
    "newton_iterations",
    "hitch_abs_peak [N]",
    "hitch_abs_peak_error [-]",
    "hitch_rms_error [-]",
    "sensor_rms_error [-]",
    "sensor_band_error [-]",
];

fn write_csv(path: &Path, points: &[Point]) -> Result<()> {
    let io = |e: csv::Error| Error::io(path, e.into());
    let mut w = csv::Writer::from_path(path).map_err(io)?;
    w.write_record(COLUMNS).map_err(io)?;
    for p in points {
        w.write_record([
            p.method.to_string(),
            format!("{:e}", p.rtol),
            p.status.clone(),
            format!("{:.4}", p.wall_s),
            format!("{:.3}", p.realtime_factor),
            p.steps.to_string(),
            p.jacobian_evals.to_string(),
            p.newton_iterations.to_string(),
            format!("{:.3}", p.hitch_abs_peak_n),
            format!("{:.3e}", p.hitch_abs_peak_error),
            format!("{:.3e}", p.hitch_rms_error),
            format!("{:.3e}", p.sensor_rms_error),
            format!("{:.3e}", p.sensor_band_error),
        ])
        .map_err(io)?;
    }
    w.flush().map_err(|e| Error::io(path, e))
}

/// Wall time against each error measure, one curve per method.
/// Redraws the work-precision plot (`bench.png`, or SVG by extension) from a table
/// [`Bench::write`] wrote (`bench.csv`): an earlier study's figures through today's
/// renderer, without running or timing anything.
pub fn replot(csv: &Path, png: &Path) -> Result<()> {
    let bad = |line: Option<usize>, field: &str, message: String| -> Error {
        towride_mbs::input::csv_table::error(csv, line, field, message).into()
    };
    let mut r = csv::Reader::from_path(csv).map_err(|e| bad(None, "", e.to_string()))?;
    let h = r
        .headers()
        .map_err(|e| bad(Some(1), "", e.to_string()))?
        .clone();
    // A table of bench.json version 1 names the signed peak `hitch_peak [N]` and its
    // error `hitch_peak_error [-]`: read as |peak| and its error, which they are where
    // a run's peak has the reference's sign (every run of the tables in docs/data).
    let legacy = |name: &str| match name {
        "hitch_abs_peak [N]" => Some("hitch_peak [N]"),
        "hitch_abs_peak_error [-]" => Some("hitch_peak_error [-]"),
        _ => None,
    };
    let col = |name: &str| {
        h.iter()
            .position(|c| c == name)
            .or_else(|| legacy(name).and_then(|old| h.iter().position(|c| c == old)))
            .ok_or_else(|| bad(Some(1), name, "no such column (not a bench.csv?)".into()))
    };
    let names = COLUMNS;
    let c: Vec<usize> = names.iter().map(|n| col(n)).collect::<Result<_>>()?;
    let mut points = Vec::new();
    for (k, rec) in r.records().enumerate() {
        let line = Some(k + 2);
        let rec = rec.map_err(|e| bad(line, "", e.to_string()))?;
        let get = |i: usize| rec.get(c[i]).unwrap_or("");
        let num = |i: usize| -> Result<f64> {
            get(i)
                .parse()
                .map_err(|_| bad(line, names[i], format!("'{}' is not a number", get(i))))
        };
        let method = [Method::Variable, Method::FixedCoefficient, Method::Radau5]
            .into_iter()
            .map(method_name)
            .find(|m| *m == get(0))
            .ok_or_else(|| bad(line, "method", format!("unknown method '{}'", get(0))))?;
        points.push(Point {
            method,
            rtol: num(1)?,
            status: get(2).to_string(),
            wall_s: num(3)?,
            realtime_factor: num(4)?,
            steps: num(5)? as usize,
            jacobian_evals: num(6)? as usize,
            newton_iterations: num(7)? as usize,
            hitch_abs_peak_n: num(8)?.abs(),
            hitch_abs_peak_error: num(9)?,
            hitch_rms_error: num(10)?,
            sensor_rms_error: num(11)?,
            sensor_band_error: num(12)?,
        });
    }
    plot(png, &points)
}

fn plot(path: &Path, points: &[Point]) -> Result<()> {
    type Measure = (&'static str, fn(&Point) -> f64);
    let measures: [Measure; 4] = [
        ("hitch-force |peak| error", |p| p.hitch_abs_peak_error),
        ("hitch-force RMS error", |p| p.hitch_rms_error),
        ("sensor RMS error (mean)", |p| p.sensor_rms_error),
        ("sensor RMS error in band (mean)", |p| p.sensor_band_error),
    ];
    let mut methods: Vec<&str> = points.iter().map(|p| p.method).collect();
    methods.dedup();
    let label = |m: &str| match m {
        "radau" => "Radau IIA".to_string(),
        _ => format!("BDF {m}-coefficient"),
    };
    let panels: Vec<Panel> = measures
        .iter()
        .map(|(title, f)| Panel {
            title: (*title).into(),
            x_label: "relative error".into(),
            y_label: "wall time [s]".into(),
            series: methods
                .iter()
                .map(|m| Series {
                    label: label(m),
                    points: points
                        .iter()
                        .filter(|p| p.method == *m && p.status == "completed")
                        .map(|p| (f(p).max(1e-12), p.wall_s))
                        .collect(),
                })
                .collect(),
        })
        .collect();
    loglog_panels(path, &panels, 2)?;
    Ok(())
}
