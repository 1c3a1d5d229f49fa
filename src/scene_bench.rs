//! `towride bench SCENE`: the work-precision study of a scene (`towride_app::study::bench`),
//! printed as a table.

use std::path::PathBuf;

use clap::Args;

use towride_app::study::bench::{self, Settings};

use crate::CliResult;

#[derive(Args, Debug)]
pub struct BenchSceneArgs {
    /// The scene file.
    #[arg(required_unless_present = "replot")]
    pub scene: Option<PathBuf>,
    /// Only redraw the plot of an earlier study from its table (`bench.csv`) into
    /// `--out` (nothing is run or timed).
    #[arg(long, value_name = "BENCH_CSV")]
    pub replot: Option<PathBuf>,
    /// Relative tolerances of the study.
    #[arg(long, value_delimiter = ',', default_values_t = vec![1e-2, 3e-3, 1e-3, 3e-4, 1e-4], value_parser = crate::bounded::tolerance)]
    pub tol: Vec<f64>,
    /// Relative tolerance of the reference run.
    #[arg(long, default_value_t = 1e-6, value_parser = crate::bounded::tolerance)]
    pub reference_tol: f64,
    /// Methods compared.
    #[arg(long, value_enum, value_delimiter = ',', default_values = ["variable", "fixed", "radau"])]
    pub methods: Vec<crate::MethodArg>,
    /// Hitch |peak| errors at which the methods' cost is compared (the fastest run of
    /// each method whose error is at most this).
    #[arg(long, value_delimiter = ',', default_values_t = vec![1e-2, 2e-3])]
    pub equal_error: Vec<f64>,
    /// The same for the sensors' in-band error.
    #[arg(long, value_delimiter = ',', default_values_t = vec![2e-2, 1e-2])]
    pub equal_band_error: Vec<f64>,
    /// Band of the in-band sensor error [Hz]: the acquisition low-pass of the
    /// measurements (`cutoff_hz` in `measurements/`), a 4th-order Butterworth.
    #[arg(long, default_value_t = 100.0, value_parser = crate::bounded::hz)]
    pub band_hz: f64,
    /// Parallel runs (1 keeps the timings undisturbed).
    #[arg(long, default_value_t = 1, value_parser = crate::bounded::jobs)]
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
    #[command(flatten)]
    pub inputs: crate::inputs::InputArgs,
}

pub fn run_bench(a: &BenchSceneArgs) -> CliResult {
    if let Some(csv) = &a.replot {
        std::fs::create_dir_all(&a.out)?;
        let png = a.out.join("bench.png");
        bench::replot(csv, &png)?;
        if a.json {
            let doc = serde_json::json!({"schema_version": 1, "table": csv, "plot": png});
            println!("{}", serde_json::to_string_pretty(&doc)?);
        } else {
            println!("wrote {}", png.display());
        }
        return Ok(0);
    }
    let scene = a.scene.as_ref().ok_or("a scene file is required")?;
    towride_app::atomic::claim(
        &a.out,
        "bench",
        &[
            "bench.csv",
            "bench.png",
            "bench.json",
            "steps.csv",
            "steps.png",
        ],
        std::slice::from_ref(scene),
    )?;
    let settings = Settings {
        tol: a.tol.clone(),
        reference_tol: a.reference_tol,
        band_hz: a.band_hz,
        jobs: a.jobs,
        repeat: a.repeat,
        methods: a.methods.iter().map(|&m| m.into()).collect(),
        equal_error: a.equal_error.clone(),
        equal_band_error: a.equal_band_error.clone(),
        loader: a.inputs.loader()?,
    };
    crate::interrupt::install();
    let pb = crate::progress(0, a.json);
    let mut b = match bench::run(scene, &settings, &pb) {
        Err(_) if crate::interrupt::requested() => {
            eprintln!("interrupted during the reference run: no run timed, nothing written");
            return Ok(crate::interrupt::EXIT);
        }
        other => other?,
    };
    let json = b.write(&a.out)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&b)?);
    } else {
        println!(
            "{}: reference (rtol {:.0e}) hitch_fx |peak| {:.1} N, {:.2} s wall",
            scene.display(),
            a.reference_tol,
            b.reference.hitch_abs_peak_n,
            b.reference.wall_s
        );
        println!("method    rtol     wall [s]  x real time  steps  Jac |peak| err  hitch RMS err  sensor RMS err  in band");
        for p in &b.runs {
            println!(
                "{:<8} {:>7.0e} {:>9.3} {:>11.2} {:>6} {:>4} {:>9.2e} {:>14.2e} {:>15.2e} {:>8.2e}  {}",
                p.method,
                p.rtol,
                p.wall_s,
                p.realtime_factor,
                p.steps,
                p.jacobian_evals,
                p.hitch_abs_peak_error,
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
        for e in &b.at_equal_error {
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
        for h in &b.step_histories {
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
            "wrote {}, bench.csv, bench.png{}",
            json.display(),
            if b.step_histories.is_empty() {
                ""
            } else {
                ", steps.csv and steps.png"
            }
        );
    }
    if b.status == "interrupted" {
        eprintln!(
            "interrupted: {} of {} runs not begun or stopped (labelled in {}); run the study again for them",
            b.interrupted,
            b.runs.len(),
            json.display()
        );
        return Ok(crate::interrupt::EXIT);
    }
    Ok(if b.all_completed() { 0 } else { 1 })
}
