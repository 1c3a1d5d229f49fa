//! The scaling study: how the set-up, the start, the integration and the outputs grow
//! with the model. Three families, described in a study file (`scenes/scaling.toml`):
//! chains of N links on revolute joints, ladders of N parallelogram loops (three
//! redundant rows each), and a vehicle scene with its modal hitch at 2, 20 or 100 modes
//! (the FE file's mode selection overridden through the [`Loader`]). Each run is timed by
//! phase; a log-log fit of time per step and set-up time against the number of equations
//! gives the growth exponent. Written as `scaling.csv`, `scaling.json` and `scaling.png`.

pub mod models;

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::job::{Job, RunResult};
use crate::report::plot::{loglog_panels, Panel, Series};
use crate::scene::Changes;
use towride_mbs::input::{InputError, Loader, Override, Source};
use towride_mbs::model::desc::Accelerations;
use towride_mbs::model::spec::{Mechanism, RunSpec, Start};
use towride_mbs::model::Model;
use towride_mbs::progress::{Progress, Silent};
use towride_solver::SolverOptions;

use models::Link;

/// Version of `scaling.json`'s layout.
pub const SCHEMA_VERSION: u32 = 1;

/// A family of generated models (chain or ladder) in the study file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Generated {
    /// Sizes run: links of a chain, loops of a ladder.
    pub sizes: Vec<usize>,
    /// The fits start at this size (below it fixed costs dominate).
    pub fit_from: usize,
    /// Every link of the model.
    pub link: Link,
    /// Ladder only: the posts' lean from the vertical at the start [deg].
    pub post_angle_deg: Option<f64>,
    /// Gravity [m/s^2].
    pub gravity_m_s2: [f64; 3],
    /// Simulated time [s].
    pub end_time_s: f64,
    /// Output sample rate [Hz].
    pub sample_rate_hz: f64,
    /// Integrator settings.
    pub solver: SolverOptions,
}

/// One vehicle case: the hitch's elastic modes.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HitchCase {
    /// Elastic modes kept (the lowest ones: mode-table numbers 7 and up).
    pub hitch_modes: usize,
    /// Fixed-interface modes of the Craig-Bampton reduction (enough to have that many).
    pub fixed_interface_modes: usize,
}

/// The vehicle family in the study file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Vehicle {
    /// The scene, relative to the study file.
    pub scene: PathBuf,
    /// The hitch's FE file, as an override names it (the end of its path).
    pub fe_file: String,
    /// Simulated time [s] (the scene's own when absent).
    pub duration_s: Option<f64>,
    /// The cases.
    pub case: Vec<HitchCase>,
}

/// The study file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spec {
    /// Chains of links on revolute joints.
    pub chain: Generated,
    /// Ladders of parallelogram loops.
    pub ladder: Generated,
    /// A vehicle scene with more or fewer hitch modes.
    pub vehicle: Vehicle,
}

impl Spec {
    /// Reads and checks a study file.
    pub fn load(path: &Path) -> std::result::Result<Spec, InputError> {
        let src = Source::read(path)?;
        let mut s: Spec = src.parse()?;
        for (key, g) in [("chain", &s.chain), ("ladder", &s.ladder)] {
            for (k, v) in [
                ("mass_kg", g.link.mass_kg),
                ("length_m", g.link.length_m),
                ("radius_m", g.link.radius_m),
            ] {
                src.positive(&towride_mbs::path![key, "link", k], v)?;
            }
            src.positive(&towride_mbs::path![key, "end_time_s"], g.end_time_s)?;
            src.positive(&towride_mbs::path![key, "sample_rate_hz"], g.sample_rate_hz)?;
            for (c, x) in g.gravity_m_s2.iter().enumerate() {
                src.finite(&towride_mbs::path![key, "gravity_m_s2", c], *x)?;
            }
            if let Some(k) = g.sizes.iter().position(|&n| n == 0) {
                return Err(src.error(&towride_mbs::path![key, "sizes", k], "must be at least 1"));
            }
            g.solver
                .validate(1)
                .map_err(|e| src.error(&towride_mbs::path![key, "solver"], e.to_string()))?;
        }
        let angle = s
            .ladder
            .post_angle_deg
            .ok_or_else(|| src.error(&towride_mbs::path!["ladder"], "post_angle_deg is missing"))?;
        if !(angle > 0.0 && angle < 60.0) {
            return Err(src.error(
                &towride_mbs::path!["ladder", "post_angle_deg"],
                format!("must be between 0 and 60 deg (away from the loops' folded position), got {angle}"),
            ));
        }
        for (k, c) in s.vehicle.case.iter().enumerate() {
            if c.hitch_modes == 0 {
                return Err(src.error(
                    &towride_mbs::path!["vehicle", "case", k, "hitch_modes"],
                    "must be at least 1",
                ));
            }
        }
        if let Some(d) = s.vehicle.duration_s {
            src.positive(&towride_mbs::path!["vehicle", "duration_s"], d)?;
        }
        let dir = path.parent().unwrap_or(Path::new("."));
        s.vehicle.scene = dir.join(&s.vehicle.scene);
        Ok(s)
    }
}

/// What to run.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Chain sizes (the file's when `None`).
    pub chain: Option<Vec<usize>>,
    /// Ladder sizes (the file's when `None`).
    pub ladder: Option<Vec<usize>>,
    /// Hitch modes of the vehicle cases (the file's when `None`); a count the file has
    /// no case for is an error.
    pub hitch_modes: Option<Vec<usize>>,
    /// Runs of each case; the fastest is kept.
    pub repeat: usize,
}

/// One run, timed by phase.
#[derive(Clone, Debug, Serialize)]
pub struct Point {
    /// "chain", "ladder" or "vehicle".
    pub family: &'static str,
    /// Links, loops or hitch modes.
    pub size: usize,
    /// Unknowns (and equations) of the DAE.
    pub equations: usize,
    /// Constraint rows kept.
    pub constraint_rows: usize,
    /// Constraint rows found redundant and dropped.
    pub redundant_rows: usize,
    /// Accepted steps of the run.
    pub steps: usize,
    /// Building the model and the equations (redundancy sweep included) and the
    /// integrator's set-up [s].
    pub setup_s: f64,
    /// The integrator's part of `setup_s` (iteration matrix structure, fill-reducing
    /// order, column colouring, first evaluation) [s].
    pub integrator_setup_s: f64,
    /// The consistent start (assembly, statics and settling run where the scene asks)
    /// [s].
    pub start_s: f64,
    /// Stepping [s].
    pub integration_s: f64,
    /// Output channels at the samples, the run summary and the CSV file [s].
    pub outputs_s: f64,
    /// All of it [s].
    pub total_s: f64,
    /// integration_s / steps [s].
    pub per_step_s: f64,
    /// setup_s / total_s.
    pub setup_share: f64,
    /// "completed" or "failed: ...".
    pub status: String,
}

/// A power-law fit y = c x^p of a quantity against the number of equations.
#[derive(Clone, Debug, Serialize)]
pub struct Fit {
    /// The family.
    pub family: &'static str,
    /// "time per step" or "set-up".
    pub quantity: &'static str,
    /// The exponent p (1: linear growth).
    pub exponent: f64,
    /// Equations at the smallest and largest point fitted.
    pub from_equations: usize,
    /// Equations at the largest point fitted.
    pub to_equations: usize,
    /// (y_last / y_first) / (x_last / x_first): 1 for linear growth.
    pub over_linear: f64,
}

/// The study's result.
#[derive(Clone, Debug, Serialize)]
pub struct Study {
    /// Layout version of this document.
    pub schema_version: u32,
    /// The study file.
    pub file: String,
    /// Every run.
    pub points: Vec<Point>,
    /// The fits per family.
    pub fits: Vec<Fit>,
    /// The files written.
    pub csv: Option<String>,
    /// The log-log plot.
    pub plot: Option<String>,
}

/// Runs the study described in `file`; each run's outputs go to `out/runs/`.
pub fn run(file: &Path, s: &Settings, out: &Path, progress: &dyn Progress) -> Result<Study> {
    let spec = Spec::load(file)?;
    let runs = out.join("runs");
    std::fs::create_dir_all(&runs).map_err(|e| Error::io(&runs, e))?;
    let chain = s.chain.clone().unwrap_or(spec.chain.sizes.clone());
    let ladder = s.ladder.clone().unwrap_or(spec.ladder.sizes.clone());
    let cases: Vec<HitchCase> = match &s.hitch_modes {
        None => spec.vehicle.case.clone(),
        Some(want) => want
            .iter()
            .map(|&k| {
                spec.vehicle
                    .case
                    .iter()
                    .find(|c| c.hitch_modes == k)
                    .cloned()
                    .ok_or_else(|| {
                        Error::from(InputError {
                            file: file.to_path_buf(),
                            line: None,
                            column: None,
                            field: "vehicle.case".into(),
                            message: format!("no case with hitch_modes = {k}"),
                            kind: Default::default(),
                        })
                    })
            })
            .collect::<Result<_>>()?,
    };
    progress.begin((chain.len() + ladder.len() + cases.len()) as u64);
    let mut points = Vec::new();
    let angle = spec.ladder.post_angle_deg.unwrap_or(0.0).to_radians();
    for (family, sizes, g) in [
        ("chain", &chain, &spec.chain),
        ("ladder", &ladder, &spec.ladder),
    ] {
        for &n in sizes {
            let build = || match family {
                "chain" => models::chain(&g.link, n, g.gravity_m_s2),
                _ => models::ladder(&g.link, n, angle, g.gravity_m_s2),
            };
            let csv = runs.join(format!("{family}_{n}.csv"));
            points.push(best_of(s.repeat, || {
                measure(family, n, &csv, || generated_job(file, build()?, g))
            })?);
            progress.inc(1);
        }
    }
    for c in &cases {
        let csv = runs.join(format!("vehicle_{}.csv", c.hitch_modes));
        points.push(best_of(s.repeat, || {
            measure("vehicle", c.hitch_modes, &csv, || {
                vehicle_job(&spec.vehicle, c)
            })
        })?);
        progress.inc(1);
    }
    progress.finish();
    let mut fits = Vec::new();
    for (family, from) in [
        ("chain", spec.chain.fit_from),
        ("ladder", spec.ladder.fit_from),
        ("vehicle", 0),
    ] {
        let pts: Vec<&Point> = points
            .iter()
            .filter(|p| p.family == family && p.size >= from && p.status == "completed")
            .collect();
        for (quantity, y) in [
            (
                "time per step",
                (|p: &Point| p.per_step_s) as fn(&Point) -> f64,
            ),
            ("set-up", |p: &Point| p.setup_s),
        ] {
            if let Some(f) = fit(family, quantity, &pts, y) {
                fits.push(f);
            }
        }
    }
    Ok(Study {
        schema_version: SCHEMA_VERSION,
        file: file.display().to_string(),
        points,
        fits,
        csv: None,
        plot: None,
    })
}

/// A generated model as a job with the family's run and solver settings.
fn generated_job(file: &Path, model: Model, g: &Generated) -> Result<Job> {
    let mech = Mechanism {
        model,
        run: RunSpec {
            end_time_s: g.end_time_s,
            sample_rate_hz: g.sample_rate_hz,
            start: Start::Assembly,
            accelerations: Accelerations::Interpolant,
        },
        solver: g.solver.clone(),
        overrides: Vec::new(),
    };
    Job::from_mechanism(file, mech)
}

/// The vehicle scene with the hitch's mode selection overridden.
fn vehicle_job(v: &Vehicle, c: &HitchCase) -> Result<Job> {
    let modes: Vec<String> = (7..7 + c.hitch_modes).map(|k| k.to_string()).collect();
    let what = "bench scaling";
    let loader = Loader::with_overrides(vec![
        Override::program(&v.fe_file, "selection.rule", "\"list\"", what),
        Override::program(
            &v.fe_file,
            "selection.modes",
            format!("[{}]", modes.join(", ")),
            what,
        ),
        Override::program(
            &v.fe_file,
            "fixed_interface_modes",
            c.fixed_interface_modes.to_string(),
            what,
        ),
    ]);
    let changes = Changes {
        duration_s: v.duration_s,
        ..Changes::default()
    };
    // The scene's reader refuses an override that reached no file or value.
    Job::from_scene_file(&v.scene, &changes, &loader)
}

/// Builds the job, runs it and writes its outputs, timing each phase.
fn measure(
    family: &'static str,
    size: usize,
    csv: &Path,
    job: impl FnOnce() -> Result<Job>,
) -> Result<Point> {
    let wall = Instant::now();
    let job = job()?.without_view();
    let built = wall.elapsed().as_secs_f64();
    let run = Instant::now();
    let r: RunResult = job.run(&Silent)?;
    let run_s = run.elapsed().as_secs_f64();
    let write = Instant::now();
    crate::report::samples_csv(&r.samples, csv).map_err(|e| Error::io(csv, e))?;
    let write_s = write.elapsed().as_secs_f64();
    let ph = &r.samples.phases;
    let setup_s = built + ph.solver_setup_s;
    let start_s = r.summary.start_wall_s + ph.start_s;
    let outputs_s =
        run_s - r.summary.start_wall_s - ph.start_s - ph.solver_setup_s - ph.integration_s
            + write_s;
    let total_s = built + run_s + write_s;
    let steps = r.samples.stats.steps;
    Ok(Point {
        family,
        size,
        equations: job.system.size(),
        constraint_rows: job.system.m,
        redundant_rows: job.system.redundant.len(),
        steps,
        setup_s,
        integrator_setup_s: ph.solver_setup_s,
        start_s,
        integration_s: ph.integration_s,
        outputs_s,
        total_s,
        per_step_s: ph.integration_s / steps.max(1) as f64,
        setup_share: setup_s / total_s,
        status: match r.failure() {
            None => "completed".into(),
            Some((m, t)) => format!("failed at {t:.4} s: {m}"),
        },
    })
}

/// The fastest of `repeat` runs.
fn best_of(repeat: usize, mut f: impl FnMut() -> Result<Point>) -> Result<Point> {
    let mut best = f()?;
    for _ in 1..repeat.max(1) {
        let p = f()?;
        if p.total_s < best.total_s {
            best = p;
        }
    }
    Ok(best)
}

/// A quantity read from a point.
type Quantity = fn(&Point) -> f64;

/// Least-squares slope of log y against log x.
fn fit(
    family: &'static str,
    quantity: &'static str,
    pts: &[&Point],
    y: fn(&Point) -> f64,
) -> Option<Fit> {
    let xy: Vec<(f64, f64)> = pts
        .iter()
        .map(|p| (p.equations as f64, y(p)))
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .collect();
    if xy.len() < 2 {
        return None;
    }
    let n = xy.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = xy.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx) * (a - mx)).sum();
    let first = xy.iter().min_by(|a, b| a.0.total_cmp(&b.0))?;
    let last = xy.iter().max_by(|a, b| a.0.total_cmp(&b.0))?;
    Some(Fit {
        family,
        quantity,
        exponent: sxy / sxx,
        from_equations: first.0 as usize,
        to_equations: last.0 as usize,
        over_linear: (last.1 / first.1) / (last.0 / first.0),
    })
}

impl Study {
    /// Writes `scaling.csv`, `scaling.json` and `scaling.png` into `dir`; returns the
    /// JSON file.
    pub fn write(&mut self, dir: &Path) -> Result<PathBuf> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let csv = dir.join("scaling.csv");
        self.write_csv(&csv)?;
        let png = dir.join("scaling.png");
        self.plot(&png)?;
        self.csv = Some(csv.display().to_string());
        self.plot = Some(png.display().to_string());
        let json = dir.join("scaling.json");
        let text = serde_json::to_string_pretty(self)
            .map_err(|e| Error::io(&json, std::io::Error::other(e.to_string())))?;
        std::fs::write(&json, text).map_err(|e| Error::io(&json, e))?;
        Ok(json)
    }

    fn write_csv(&self, path: &Path) -> Result<()> {
        let io = |e: csv::Error| Error::io(path, e.into());
        let mut w = csv::Writer::from_path(path).map_err(io)?;
        w.write_record([
            "family",
            "size [-]",
            "equations [-]",
            "constraint rows [-]",
            "redundant rows [-]",
            "steps [-]",
            "set-up [s]",
            "integrator set-up [s]",
            "start [s]",
            "integration [s]",
            "outputs [s]",
            "total [s]",
            "time per step [s]",
            "set-up share [-]",
            "status",
        ])
        .map_err(io)?;
        for p in &self.points {
            w.write_record([
                p.family.to_string(),
                p.size.to_string(),
                p.equations.to_string(),
                p.constraint_rows.to_string(),
                p.redundant_rows.to_string(),
                p.steps.to_string(),
                format!("{:.6}", p.setup_s),
                format!("{:.6}", p.integrator_setup_s),
                format!("{:.6}", p.start_s),
                format!("{:.6}", p.integration_s),
                format!("{:.6}", p.outputs_s),
                format!("{:.6}", p.total_s),
                format!("{:.4e}", p.per_step_s),
                format!("{:.4}", p.setup_share),
                p.status.clone(),
            ])
            .map_err(io)?;
        }
        w.flush().map_err(|e| Error::io(path, e))
    }

    /// Time per step, set-up, the whole run and the set-up's share of it against the
    /// equations, per family, with the fitted exponents in the legend, a line of slope 1
    /// through each family's first fitted point, and the share's 10 % goal.
    fn plot(&self, path: &Path) -> Result<()> {
        let quantities: [(&str, &str, Quantity); 4] = [
            ("time per step", "time per step [s]", |p| p.per_step_s),
            ("set-up", "set-up [s]", |p| p.setup_s),
            ("whole run", "total [s]", |p| p.total_s),
            ("set-up share", "set-up / whole run [-]", |p| p.setup_share),
        ];
        let mut panels: Vec<Panel> = quantities
            .iter()
            .map(|(name, unit, y)| {
                let mut series = Vec::new();
                for family in ["chain", "ladder", "vehicle"] {
                    let pts: Vec<(f64, f64)> = self
                        .points
                        .iter()
                        .filter(|p| p.family == family && p.status == "completed")
                        .map(|p| (p.equations as f64, y(p)))
                        .collect();
                    if pts.is_empty() {
                        continue;
                    }
                    let exp = self
                        .fits
                        .iter()
                        .find(|f| f.family == family && f.quantity == *name)
                        .map_or(String::new(), |f| format!(" (exponent {:.2})", f.exponent));
                    series.push(Series {
                        label: format!("{family}{exp}"),
                        points: pts,
                    });
                }
                if let Some(f) = self.fits.iter().find(|f| f.quantity == *name) {
                    let p0 = self
                        .points
                        .iter()
                        .find(|p| p.family == f.family && p.equations == f.from_equations);
                    if let Some(p0) = p0 {
                        let (x0, y0) = (p0.equations as f64, y(p0));
                        let x1 = f.to_equations as f64;
                        series.push(Series {
                            label: format!("linear from {} {}", f.family, p0.size),
                            points: vec![(x0, y0), (x1, y0 * x1 / x0)],
                        });
                    }
                }
                Panel {
                    title: format!("{name} against model size"),
                    x_label: "equations [-]".into(),
                    y_label: unit.to_string(),
                    series,
                }
            })
            .collect();
        let sizes = self.points.iter().map(|p| p.equations as f64);
        let (lo, hi) = sizes.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
        if let Some(share) = panels.last_mut().filter(|_| hi >= lo) {
            share.series.push(Series {
                label: "goal: 10 %".into(),
                points: vec![(lo, 0.1), (hi, 0.1)],
            });
        }
        loglog_panels(path, &panels, 2).map_err(Error::from)
    }
}
