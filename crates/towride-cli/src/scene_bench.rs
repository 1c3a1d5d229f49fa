//! `towride bench SCENE`: work-precision study of a scene (a tight-tolerance reference,
//! then a tolerance range for each method, the BDF variants and Radau IIA: wall time,
//! steps, Jacobians and the errors of the key outputs against the reference), CSV and a
//! log-log plot; the methods' cost at equal hitch-peak error; their step-size and order
//! histories at the scene's own tolerance.

use std::path::{Path, PathBuf};

use clap::Args;
use rayon::prelude::*;
use serde::Serialize;
use serde_json::json;

use crate::MethodArg;
use towride::report::plot::{loglog_panels, Panel, Series};
use towride::report::steps::{step_history_plot, StepHistory};
use towride::scene::exec::{rel_rms, run, SceneRun};
use towride::scene::Overrides;
use towride::validate::filter::Butterworth;
use towride_solver::Method;

#[derive(Args, Debug)]
pub struct BenchSceneArgs {
    /// The scene file.
    #[arg(required = true)]
    pub scene: Option<PathBuf>,
    /// Relative tolerances of the study.
    #[arg(long, value_delimiter = ',', default_values_t = vec![1e-2, 3e-3, 1e-3, 3e-4, 1e-4])]
    pub tol: Vec<f64>,
    /// Relative tolerance of the reference run.
    #[arg(long, default_value_t = 1e-6)]
    pub reference_tol: f64,
    /// Methods compared.
    #[arg(long, value_enum, value_delimiter = ',', default_values = ["variable", "fixed", "radau"])]
    pub methods: Vec<MethodArg>,
    /// Hitch-peak errors at which the methods' cost is compared (the fastest run of each
    /// method whose error is at most this).
    #[arg(long, value_delimiter = ',', default_values_t = vec![1e-2, 2e-3])]
    pub equal_error: Vec<f64>,
    /// The same for the sensors' in-band error.
    #[arg(long, value_delimiter = ',', default_values_t = vec![2e-2, 1e-2])]
    pub equal_band_error: Vec<f64>,
    /// Band of the in-band sensor error [Hz]: the acquisition low-pass of the
    /// measurements (`cutoff_hz` in `measurements/`), a 4th-order Butterworth.
    #[arg(long, default_value_t = 100.0)]
    pub band_hz: f64,
    /// Parallel runs (1 keeps the timings undisturbed).
    #[arg(long, default_value_t = 1)]
    pub jobs: usize,
    /// Runs of each setting; the fastest wall time is reported (the results of repeated
    /// runs are identical, their wall times are not on a shared machine).
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
    /// Output folder.
    #[arg(long, default_value = "out/bench")]
    pub out: PathBuf,
    #[arg(long)]
    pub json: bool,
}

/// One run of the study and its errors against the reference.
#[derive(Clone, Debug, Serialize)]
pub struct Point {
    pub method: &'static str,
    pub rtol: f64,
    pub status: String,
    pub wall_s: f64,
    /// Simulated time over wall time.
    pub realtime_factor: f64,
    pub steps: usize,
    pub jacobian_evals: usize,
    pub newton_iterations: usize,
    pub hitch_peak_n: f64,
    /// |peak - reference peak| / |reference peak|.
    pub hitch_peak_error: f64,
    /// RMS of the hitch-force difference over the reference's RMS.
    pub hitch_rms_error: f64,
    /// Mean over the acceleration sensors of their relative RMS errors.
    pub sensor_rms_error: f64,
    /// The same after the measurements' low-pass (`--band-hz`): the error a comparison
    /// with recorded data sees.
    pub sensor_band_error: f64,
}

/// The reference run's key outputs (plain data, shared by the parallel runs).
pub struct Reference {
    pub peak: f64,
    pub hitch: Vec<f64>,
    pub sensors: Vec<(String, Vec<f64>)>,
    /// The low-pass of the in-band error and the sensors through it.
    pub band: Option<Butterworth>,
    pub sensors_band: Vec<Vec<f64>>,
}

impl Reference {
    pub fn of(r: &SceneRun) -> Reference {
        Reference {
            peak: r.peak("hitch_fx").unwrap_or(f64::NAN),
            hitch: r.channel("hitch_fx").unwrap_or_default(),
            sensors: r
                .result
                .channels
                .iter()
                .filter(|c| c.name.starts_with("acc_"))
                .map(|c| (c.name.clone(), r.channel(&c.name).unwrap_or_default()))
                .collect(),
            band: None,
            sensors_band: Vec::new(),
        }
        .without_silent_sensors()
    }

    /// Also measures the sensors' errors after a low-pass at `band_hz`.
    pub fn with_band(mut self, band_hz: f64, rate_hz: f64) -> Result<Self, String> {
        let f = Butterworth::low_pass(4, band_hz, rate_hz)?;
        self.sensors_band = self.sensors.iter().map(|(_, v)| f.apply(v)).collect();
        self.band = Some(f);
        Ok(self)
    }

    /// Mean relative RMS error of the sensors after the band's low-pass (NaN without one).
    pub fn band_error(&self, r: &SceneRun) -> f64 {
        let Some(f) = &self.band else {
            return f64::NAN;
        };
        let e: Vec<f64> = self
            .sensors
            .iter()
            .zip(&self.sensors_band)
            .map(|((n, _), v)| rel_rms(&f.apply(&r.channel(n).unwrap_or_default()), v))
            .collect();
        e.iter().sum::<f64>() / e.len().max(1) as f64
    }

    /// Drops sensors whose reference RMS is below 1 % of the loudest one's (the lateral
    /// axes of a straight, symmetric crossing): their relative error measures rounding
    /// noise, not the integration.
    fn without_silent_sensors(mut self) -> Self {
        let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
        let loudest = self.sensors.iter().map(|(_, v)| rms(v)).fold(0.0, f64::max);
        self.sensors.retain(|(_, v)| rms(v) >= 0.01 * loudest);
        self
    }

    /// Peak, peak error, hitch RMS error and mean sensor RMS error of run `r`.
    pub fn errors(&self, r: &SceneRun) -> (f64, f64, f64, f64) {
        let peak = r.peak("hitch_fx").unwrap_or(f64::NAN);
        let hitch = rel_rms(&r.channel("hitch_fx").unwrap_or_default(), &self.hitch);
        let sensors: Vec<f64> = self
            .sensors
            .iter()
            .map(|(n, v)| rel_rms(&r.channel(n).unwrap_or_default(), v))
            .collect();
        let sensor = sensors.iter().sum::<f64>() / sensors.len().max(1) as f64;
        (peak, ((peak - self.peak) / self.peak).abs(), hitch, sensor)
    }
}

fn method_name(method: Method) -> &'static str {
    match method {
        Method::Variable => "variable",
        Method::FixedCoefficient => "fixed",
        Method::Radau5 => "radau",
    }
}

fn point(method: Method, rtol: f64, r: &Result<SceneRun, String>, reference: &Reference) -> Point {
    let name = method_name(method);
    match r {
        Ok(r) if r.result.error.is_none() => {
            let (peak, pe, he, se) = reference.errors(r);
            let st = &r.result.stats;
            Point {
                method: name,
                rtol,
                status: "completed".into(),
                wall_s: r.wall_s,
                realtime_factor: r.scene.duration / r.wall_s,
                steps: st.steps,
                jacobian_evals: st.jacobian_evals,
                newton_iterations: st.newton_iterations,
                hitch_peak_n: peak,
                hitch_peak_error: pe,
                hitch_rms_error: he,
                sensor_rms_error: se,
                sensor_band_error: reference.band_error(r),
            }
        }
        other => Point {
            method: name,
            rtol,
            status: match other {
                Ok(r) => format!("failed: {}", r.result.error.as_ref().map_or("", |e| &e.0)),
                Err(e) => format!("failed: {e}"),
            },
            wall_s: f64::NAN,
            realtime_factor: f64::NAN,
            steps: 0,
            jacobian_evals: 0,
            newton_iterations: 0,
            hitch_peak_n: f64::NAN,
            hitch_peak_error: f64::NAN,
            hitch_rms_error: f64::NAN,
            sensor_rms_error: f64::NAN,
            sensor_band_error: f64::NAN,
        },
    }
}

pub fn run_bench(a: &BenchSceneArgs) -> Result<i32, String> {
    let scene = a.scene.as_ref().ok_or("a scene file is required")?;
    let tuned = |m: Method, rtol: f64| {
        move |o: &mut towride_solver::SolverOptions| {
            o.rtol = rtol;
            o.method = m;
        }
    };
    // The reference tightens the absolute tolerances with the relative one: with the
    // scene's atol the crossbeam's modal coordinates (micrometres) would be held only to
    // atol, and their 200-300 Hz modes ring at that level in the raw accelerations.
    let reference = run(scene, &[], &Overrides::default(), &|o| {
        let f = a.reference_tol / o.rtol;
        if f < 1.0 {
            o.atol.iter_mut().for_each(|x| *x *= f);
        }
        tuned(Method::Variable, a.reference_tol)(o)
    })?;
    if let Some((e, t)) = &reference.result.error {
        return Err(format!("reference run failed at t = {t:.4} s: {e}"));
    }
    let refdata = Reference::of(&reference).with_band(a.band_hz, reference.scene.sample_rate)?;
    let methods: Vec<Method> = a.methods.iter().map(|&m| m.into()).collect();
    let cases: Vec<(Method, f64)> = methods
        .iter()
        .flat_map(|&m| a.tol.iter().map(move |&t| (m, t)))
        .collect();
    let pb = crate::progress(cases.len() as u64, a.json);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.jobs.max(1))
        .build()
        .map_err(|e| e.to_string())?;
    let points: Vec<Point> = pool.install(|| {
        cases
            .par_iter()
            .map(|&(m, t)| {
                let mut r = run(scene, &[], &Overrides::default(), &tuned(m, t));
                for _ in 1..a.repeat.max(1) {
                    let again = run(scene, &[], &Overrides::default(), &tuned(m, t));
                    if let (Ok(best), Ok(x)) = (&mut r, again) {
                        best.wall_s = best.wall_s.min(x.wall_s);
                    }
                }
                pb.inc(1);
                point(m, t, &r, &refdata)
            })
            .collect()
    });
    pb.finish_and_clear();
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    write_csv(&a.out.join("bench.csv"), &points)?;
    plot(&a.out.join("bench.png"), &points, &methods)?;
    let mut equal = at_equal_error(&points, &methods, &a.equal_error, Measure::HitchPeak);
    equal.extend(at_equal_error(
        &points,
        &methods,
        &a.equal_band_error,
        Measure::SensorBand,
    ));
    let histories = step_histories(scene, &methods, &a.out)?;
    let summary = json!({
        "scene": scene.display().to_string(),
        "duration_s": reference.scene.duration,
        "equations": reference.equations,
        "modal_coordinates": reference.modes,
        "reference": {
            "rtol": a.reference_tol,
            "wall_s": reference.wall_s,
            "steps": reference.result.stats.steps,
            "hitch_peak_n": reference.peak("hitch_fx"),
        },
        "runs": points,
        "at_equal_error": equal,
        "step_histories": histories,
        "csv": a.out.join("bench.csv").display().to_string(),
        "plot": a.out.join("bench.png").display().to_string(),
        "step_plot": a.out.join("steps.png").display().to_string(),
    });
    let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
    std::fs::write(a.out.join("bench.json"), &text).map_err(|e| e.to_string())?;
    if a.json {
        println!("{text}");
    } else {
        println!(
            "{}: reference (rtol {:.0e}) hitch_fx peak {:.1} N, {:.2} s wall",
            scene.display(),
            a.reference_tol,
            reference.peak("hitch_fx").unwrap_or(f64::NAN),
            reference.wall_s
        );
        println!("method    rtol     wall [s]  x real time  steps  Jac  peak err  hitch RMS err  sensor RMS err  in band");
        for p in &points {
            println!(
                "{:<8} {:>7.0e} {:>9.3} {:>11.2} {:>6} {:>4} {:>9.2e} {:>14.2e} {:>15.2e} {:>8.2e}  {}",
                p.method,
                p.rtol,
                p.wall_s,
                p.realtime_factor,
                p.steps,
                p.jacobian_evals,
                p.hitch_peak_error,
                p.hitch_rms_error,
                p.sensor_rms_error,
                p.sensor_band_error,
                if p.status == "completed" {
                    ""
                } else {
                    &p.status
                }
            );
        }
        println!("at equal error (the fastest run of each method within it):");
        for e in &equal {
            println!(
                "  {:<8} {} <= {:>7.1e}: {}",
                e.method,
                e.measure,
                e.target,
                match e.rtol {
                    Some(rtol) => format!(
                        "rtol {rtol:.0e}, {:.3} s, {:.1} x real time, {} steps, error {:.2e}",
                        e.wall_s, e.realtime_factor, e.steps, e.error
                    ),
                    None => "no run of the study".into(),
                }
            );
        }
        println!("step histories at the scene's tolerance:");
        for h in &histories {
            println!(
                "  {:<8} {:>6} steps, mean {:.3} ms, {:.3} s wall, step limiters: {}",
                h.method,
                h.steps,
                1e3 * h.mean_step_s,
                h.wall_s,
                h.limiters.join(", ")
            );
        }
        println!(
            "wrote {}, bench.csv, bench.png, steps.csv and steps.png",
            a.out.join("bench.json").display()
        );
    }
    Ok(if points.iter().all(|p| p.status == "completed") {
        0
    } else {
        1
    })
}

fn write_csv(path: &Path, points: &[Point]) -> Result<(), String> {
    let mut w = csv::Writer::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    w.write_record([
        "method",
        "rtol [-]",
        "status",
        "wall [s]",
        "realtime_factor [-]",
        "steps",
        "jacobian_evals",
        "newton_iterations",
        "hitch_peak [N]",
        "hitch_peak_error [-]",
        "hitch_rms_error [-]",
        "sensor_rms_error [-]",
        "sensor_band_error [-]",
    ])
    .map_err(|e| e.to_string())?;
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
            format!("{:.3}", p.hitch_peak_n),
            format!("{:.3e}", p.hitch_peak_error),
            format!("{:.3e}", p.hitch_rms_error),
            format!("{:.3e}", p.sensor_rms_error),
            format!("{:.3e}", p.sensor_band_error),
        ])
        .map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())
}

/// The error measure a cost comparison is made at.
#[derive(Clone, Copy, Debug)]
enum Measure {
    HitchPeak,
    SensorBand,
}

impl Measure {
    fn name(self) -> &'static str {
        match self {
            Measure::HitchPeak => "hitch-peak error",
            Measure::SensorBand => "sensor in-band error",
        }
    }

    fn of(self, p: &Point) -> f64 {
        match self {
            Measure::HitchPeak => p.hitch_peak_error,
            Measure::SensorBand => p.sensor_band_error,
        }
    }
}

/// A method's cheapest run at or below an error.
#[derive(Clone, Debug, Serialize)]
pub struct AtError {
    pub method: &'static str,
    pub measure: &'static str,
    pub target: f64,
    /// The run's rtol (None: no run of the study reached the target).
    pub rtol: Option<f64>,
    pub wall_s: f64,
    pub realtime_factor: f64,
    pub steps: usize,
    pub error: f64,
}

/// For each method and target, the fastest completed run whose error is at most the
/// target: cost at equal accuracy, without interpolating between tolerances (the errors
/// are not monotone in rtol).
fn at_equal_error(
    points: &[Point],
    methods: &[Method],
    targets: &[f64],
    measure: Measure,
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

/// One method's run at the scene's tolerance with its steps recorded.
#[derive(Clone, Debug, Serialize)]
pub struct HistorySummary {
    pub method: &'static str,
    pub steps: usize,
    pub mean_step_s: f64,
    pub wall_s: f64,
    pub limiters: Vec<String>,
}

/// Runs each method at the scene's own settings with the step history recorded; writes
/// steps.csv (method, t, h, order) and steps.png (step size and order against time).
fn step_histories(
    scene: &Path,
    methods: &[Method],
    out: &Path,
) -> Result<Vec<HistorySummary>, String> {
    let mut hist = Vec::new();
    let mut summary = Vec::new();
    for &m in methods {
        let r = run(scene, &[], &Overrides::default(), &|o| {
            o.method = m;
            o.record_steps = true;
        })?;
        if let Some((e, t)) = &r.result.error {
            return Err(format!(
                "{} run failed at t = {t:.4} s: {e}",
                method_name(m)
            ));
        }
        let st = &r.result.stats;
        summary.push(HistorySummary {
            method: method_name(m),
            steps: st.steps,
            mean_step_s: r.scene.duration / st.steps.max(1) as f64,
            wall_s: r.wall_s,
            limiters: st
                .step_limiters
                .iter()
                .map(|(n, k)| format!("{n} ({k})"))
                .collect(),
        });
        hist.push(StepHistory {
            label: match m {
                Method::Radau5 => "Radau IIA (order 5)".into(),
                _ => format!("BDF {}-coefficient", method_name(m)),
            },
            steps: st.step_history.clone(),
        });
    }
    let path = out.join("steps.csv");
    let mut w = csv::Writer::from_path(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    w.write_record(["method", "t [s]", "h [s]", "order"])
        .map_err(|e| e.to_string())?;
    for (s, h) in summary.iter().zip(&hist) {
        for &(t, dt, k) in &h.steps {
            w.write_record([
                s.method.to_string(),
                format!("{t:.9e}"),
                format!("{dt:.6e}"),
                k.to_string(),
            ])
            .map_err(|e| e.to_string())?;
        }
    }
    w.flush().map_err(|e| e.to_string())?;
    step_history_plot(&out.join("steps.png"), &hist)?;
    Ok(summary)
}

/// Wall time against each error measure, one curve per method.
fn plot(path: &Path, points: &[Point], methods: &[Method]) -> Result<(), String> {
    type Measure = (&'static str, fn(&Point) -> f64);
    let measures: [Measure; 4] = [
        ("hitch-force peak error", |p| p.hitch_peak_error),
        ("hitch-force RMS error", |p| p.hitch_rms_error),
        ("sensor RMS error (mean)", |p| p.sensor_rms_error),
        ("sensor RMS error in band (mean)", |p| p.sensor_band_error),
    ];
    let panels: Vec<Panel> = measures
        .iter()
        .map(|(title, f)| Panel {
            title: (*title).into(),
            x_label: "relative error".into(),
            y_label: "wall time [s]".into(),
            series: methods
                .iter()
                .map(|&m| Series {
                    label: match m {
                        Method::Radau5 => "Radau IIA".into(),
                        _ => format!("BDF {}-coefficient", method_name(m)),
                    },
                    points: points
                        .iter()
                        .filter(|p| p.method == method_name(m) && p.status == "completed")
                        .map(|p| (f(p).max(1e-12), p.wall_s))
                        .collect(),
                })
                .collect(),
        })
        .collect();
    loglog_panels(path, &panels, 2)
}
