//! `towride bench SCENE`: work-precision study of a scene (a tight-tolerance reference,
//! then a tolerance range for each BDF variant: wall time, steps, Jacobians and the errors
//! of the key outputs against the reference), CSV and a log-log plot.

use std::path::{Path, PathBuf};

use clap::Args;
use rayon::prelude::*;
use serde::Serialize;
use serde_json::json;

use towride::report::plot::{loglog_panels, Panel, Series};
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

fn point(method: Method, rtol: f64, r: &Result<SceneRun, String>, reference: &Reference) -> Point {
    let name = match method {
        Method::Variable => "variable",
        Method::FixedCoefficient => "fixed",
    };
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
    let cases: Vec<(Method, f64)> = [Method::Variable, Method::FixedCoefficient]
        .into_iter()
        .flat_map(|m| a.tol.iter().map(move |&t| (m, t)))
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
    plot(&a.out.join("bench.png"), &points)?;
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
        "csv": a.out.join("bench.csv").display().to_string(),
        "plot": a.out.join("bench.png").display().to_string(),
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
        println!(
            "wrote {}, bench.csv and bench.png",
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

/// Wall time against each error measure, one curve per method.
fn plot(path: &Path, points: &[Point]) -> Result<(), String> {
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
            series: ["variable", "fixed"]
                .iter()
                .map(|m| Series {
                    label: format!("BDF {m}-coefficient"),
                    points: points
                        .iter()
                        .filter(|p| p.method == *m && p.status == "completed")
                        .map(|p| (f(p).max(1e-12), p.wall_s))
                        .collect(),
                })
                .collect(),
        })
        .collect();
    loglog_panels(path, &panels, 2)
}
