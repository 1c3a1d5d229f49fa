//! One run pipeline for everything that integrates a model: a [`Job`] is an assembled
//! model with its solver options, run settings and start policy, built from a mechanism
//! file, a scene or a plan case; [`Job::run`] starts it, integrates it and returns a
//! [`RunResult`]: the sampled channels (with the band-limited twins of the sensor, force
//! and deflection channels, [`band`]) plus a typed [`RunSummary`]. `run`, `linear`,
//! `doctor`, `bench`, `stress`, `sweep` and `validate` all build their runs here, so the
//! model checks (a motion on a locked direction, redundant constraints) run on every
//! path.
//!
//! ```no_run
//! use std::path::Path;
//! use towride_app::prelude::*;
//! use towride_app::scene::channels::HITCH_FX;
//!
//! # fn main() -> Result<(), towride_app::Error> {
//! let job = Job::from_file(Path::new("scenes/default.toml"), &Loader::new())?;
//! let run = job.run(&Silent)?;
//! let fx = run.extremes(HITCH_FX).expect("a scene has the hitch_fx channel");
//! println!("hitch_fx max {:.1} N, min {:.1} N, |peak| {:.1} N", fx.max, fx.min, fx.abs_peak);
//! # Ok(())
//! # }
//! ```

pub mod band;
pub mod convergence;
mod produced;
pub mod ringing;
mod summary;

use std::path::{Path, PathBuf};
use std::time::Instant;

pub use produced::ProducedBy;
pub use summary::{
    Acquisition, ChannelSummary, Extremes, LiftOff, RunStatus, RunSummary, SceneInfo, Signal,
    SolverSummary, StepLimiter, Unknowns, SCHEMA_VERSION,
};

use crate::error::Result;
use crate::scene::{self, Changes, Scene};
use crate::signal::acquisition::AcqFilter;
use towride_mbs::input::Loader;
use towride_mbs::model::run::{simulate_with_poses, Samples};
use towride_mbs::model::spec::{self, Mechanism};
use towride_mbs::model::start::StartReport;
use towride_mbs::model::statics::StaticsReport;
use towride_mbs::model::system::Owner;
use towride_mbs::model::{ModelError, System};
use towride_mbs::progress::Progress;
use towride_solver::SolverOptions;

/// Where a run starts from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StartPolicy {
    /// The given positions and velocities, assembled onto the constraints.
    Assembly,
    /// Static equilibrium found from the given positions.
    Statics,
    /// Static equilibrium, then the set speed [m/s], then `settle` seconds on flat road
    /// (`model::start::at_speed`).
    EquilibriumAtSpeed {
        /// Set speed [m/s].
        speed: f64,
        /// Settling time before t = 0 [s].
        settle: f64,
    },
}

/// What a run covers: end time and output sample rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSettings {
    /// End time [s] (runs start at 0).
    pub t_end: f64,
    /// Output sample rate [Hz].
    pub sample_rate: f64,
    /// Rate of the body poses recorded for the report's 3D view [Hz] (0: none; at most
    /// `sample_rate`).
    pub animation_rate: f64,
}

/// An assembled model ready to run.
pub struct Job {
    /// The model's or the scene's name.
    pub name: String,
    /// The file it came from.
    pub file: PathBuf,
    /// The assembled equations.
    pub system: System,
    /// Integrator settings (a scene's absolute tolerances come from the model).
    pub solver: SolverOptions,
    /// End time and sample rate.
    pub settings: RunSettings,
    /// How the run starts.
    pub start: StartPolicy,
    /// The scene, for a vehicle run (handles, design statics, channels).
    pub scene: Option<Box<Scene>>,
    /// One line per redundant constraint row the assembly dropped.
    pub warnings: Vec<String>,
    /// What produced the run (overrides from the files; version and command line from
    /// the caller, [`ProducedBy::stamped`]).
    pub produced_by: ProducedBy,
}

/// A finished (or stopped) run: the sampled channels and the summary.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// Channels, samples, solver statistics, the final state.
    pub samples: Samples,
    /// Status, solver effort, per-channel extremes and, for scenes, the vehicle figures.
    pub summary: RunSummary,
}

impl Job {
    /// A mechanism file or a scene, told apart by the scene's `[scene]` table (a plan
    /// holds several jobs: [`crate::scene::plan`]).
    pub fn from_file(path: &Path, loader: &Loader) -> Result<Job> {
        if scene::plan::is_plan(path) {
            return Err(scene::SceneError::Plan {
                file: path.to_path_buf(),
                message: "a plan holds several runs: load it with scene::plan::load".into(),
            }
            .into());
        }
        if scene::is_scene(path) {
            Job::from_scene_file(path, &Changes::default(), loader)
        } else {
            Job::from_mechanism_file(path, loader)
        }
    }

    /// A mechanism file (see `docs/mechanism.md`).
    pub fn from_mechanism_file(path: &Path, loader: &Loader) -> Result<Job> {
        let mech = spec::load(path, loader)?;
        Job::from_mechanism(path, mech)
    }

    /// A mechanism already read.
    pub fn from_mechanism(path: &Path, mech: Mechanism) -> Result<Job> {
        let start = match mech.run.start {
            spec::Start::Assembly => StartPolicy::Assembly,
            spec::Start::Statics => StartPolicy::Statics,
        };
        let settings = RunSettings {
            t_end: mech.run.end_time_s,
            sample_rate: mech.run.sample_rate_hz,
            animation_rate: scene::DEFAULT_ANIMATION_RATE_HZ,
        };
        let name = mech.model.name.clone();
        let overrides = mech.overrides;
        let mut job = Job::assemble(path, name, mech.model, mech.solver, settings, start, None)?;
        job.set_overrides(overrides);
        Ok(job)
    }

    /// A scene file with some settings changed (`Changes::default()` for none).
    pub fn from_scene_file(path: &Path, changes: &Changes, loader: &Loader) -> Result<Job> {
        Job::from_scene(scene::load_with(path, changes, loader)?)
    }

    /// A scene already read (a plan's case).
    pub fn from_scene(s: Scene) -> Result<Job> {
        let start = match s.start {
            scene::Start::EquilibriumAtSpeed => StartPolicy::EquilibriumAtSpeed {
                speed: s.speed,
                settle: s.settle,
            },
            scene::Start::Assembly => StartPolicy::Assembly,
        };
        let settings = RunSettings {
            t_end: s.duration,
            sample_rate: s.sample_rate,
            animation_rate: s.animation_rate,
        };
        let model = s.model().clone();
        let mut job = Job::assemble(
            &s.file.clone(),
            s.name.clone(),
            model,
            s.solver.clone(),
            settings,
            start,
            Some(Box::new(s)),
        )?;
        if let Some(sc) = &job.scene {
            job.solver = sc.solver_for(&job.system);
            let o = sc.overrides.clone();
            job.set_overrides(o);
        }
        Ok(job)
    }

    /// Records the overrides that took effect; the caller's change the run's name, so
    /// that a title written for 50 km/h does not stand over a run at 40.
    fn set_overrides(&mut self, overrides: Vec<towride_mbs::input::Applied>) {
        if let Some(said) = produced::caller_changes(&overrides) {
            self.name = format!("{} ({said})", self.name);
        }
        self.produced_by.overrides = overrides;
    }

    fn assemble(
        file: &Path,
        name: String,
        model: towride_mbs::model::Model,
        solver: SolverOptions,
        settings: RunSettings,
        start: StartPolicy,
        scene: Option<Box<Scene>>,
    ) -> Result<Job> {
        let system = System::new(model);
        check(&system)?;
        let warnings = redundancy_warnings(&system);
        Ok(Job {
            name,
            file: file.to_path_buf(),
            system,
            solver,
            settings,
            start,
            scene,
            warnings,
            produced_by: ProducedBy::default(),
        })
    }

    /// The scene's acquisition chain, through which the run also reports its sensor,
    /// force and deflection channels (`None`: a mechanism, or `filter = "none"`).
    pub fn acquisition(&self) -> Option<AcqFilter> {
        self.scene.as_ref().and_then(|s| s.acquisition)
    }

    /// The band-limited twins a run of this job appends to its channels: (name, unit)
    /// ([`band`]).
    pub fn band_channels(&self) -> Vec<(String, String)> {
        let Some(f) = self.acquisition() else {
            return Vec::new();
        };
        let chans = towride_mbs::model::output::channels(&self.system);
        band::twins(chans.iter().map(|c| c.name.as_str()), &f)
            .into_iter()
            .map(|(k, n)| (n, chans[k].unit.to_string()))
            .collect()
    }

    /// The job without the 3D view's pose samples, for runs whose report nobody writes
    /// (studies, sweeps without kept histories): about 7 ms a default run.
    pub fn without_view(mut self) -> Job {
        self.settings.animation_rate = 0.0;
        self
    }

    /// Changes the solver settings (a bench's tolerance, a stress case's step limit);
    /// the result is checked.
    pub fn tune(mut self, f: impl FnOnce(&mut SolverOptions)) -> Result<Job> {
        f(&mut self.solver);
        self.solver.validate(self.system.size())?;
        Ok(self)
    }

    /// The consistent state at t = 0 by the start policy (`None`: assembled from the
    /// model's initial values by the run itself), and what the start did.
    pub fn start_state(&self) -> Result<StartState> {
        let mut out = StartState::default();
        match self.start {
            StartPolicy::Assembly => {}
            StartPolicy::Statics => {
                let st = towride_mbs::model::statics::equilibrium(&self.system, 0.0, &self.solver)?;
                out.statics = Some(st.report.clone());
                out.state = Some((st.y, st.yp));
            }
            StartPolicy::EquilibriumAtSpeed { speed, settle } => {
                let (y, yp, rep) = towride_mbs::model::start::at_speed(
                    &self.system.model,
                    speed,
                    settle,
                    &self.solver,
                )?;
                out.state = Some((y, yp));
                out.start = Some(rep);
            }
        }
        Ok(out)
    }

    /// The same job at tolerances `factor` times tighter (rtol and every atol divided by
    /// it): the companion of a convergence check ([`convergence`]).
    pub fn tightened(mut self, factor: f64) -> Job {
        self.solver.rtol /= factor;
        self.solver.atol.iter_mut().for_each(|a| *a /= factor);
        self
    }

    /// Starts and integrates the job, sampling every 1/rate seconds. A solver failure
    /// keeps everything computed up to it (status `failed` in the summary); an error is
    /// returned only when the run cannot start.
    pub fn run(&self, progress: &dyn Progress) -> Result<RunResult> {
        self.check_budget()?;
        let wall = Instant::now();
        let start = self.start_state()?;
        let start_wall_s = wall.elapsed().as_secs_f64();
        // The report shows step size and order over time; recording does not change
        // the steps.
        let mut solver = self.solver.clone();
        solver.record_steps = true;
        let mut samples = simulate_with_poses(
            &self.system,
            0.0,
            self.settings.t_end,
            self.settings.sample_rate,
            self.settings.animation_rate,
            &solver,
            start.state.clone(),
            progress,
        );
        progress.finish();
        if let Some(f) = self.acquisition() {
            band::append(&mut samples, &f, self.settings.sample_rate)?;
        }
        let summary = RunSummary::of(self, &samples, start, start_wall_s);
        Ok(RunResult { samples, summary })
    }
}

impl Job {
    /// Refuses a run whose samples would not fit the limits of
    /// [`towride_mbs::input::bounds::budget`], before anything is computed.
    pub fn check_budget(&self) -> Result<()> {
        let columns = towride_mbs::model::output::channels(&self.system).len()
            + self.band_channels().len()
            + self.system.nm.iter().sum::<usize>();
        towride_mbs::input::bounds::budget::check(
            self.settings.t_end,
            self.settings.sample_rate,
            columns,
        )
        .map(|_| ())
        .map_err(|budget| {
            scene::SceneError::TooLarge {
                file: self.file.clone(),
                field: if self.scene.is_some() {
                    "run.duration_s, run.sample_rate_hz".into()
                } else {
                    "run.end_time_s, run.sample_rate_hz".into()
                },
                budget,
            }
            .into()
        })
    }
}

/// What the start policy produced.
#[derive(Clone, Debug, Default)]
pub struct StartState {
    /// (y, y') at t = 0; `None` when the run assembles the model's initial values.
    pub state: Option<(Vec<f64>, Vec<f64>)>,
    /// The equilibrium search of a statics start.
    pub statics: Option<StaticsReport>,
    /// The start at speed.
    pub start: Option<StartReport>,
}

impl RunResult {
    /// Samples of channel `name`.
    pub fn channel(&self, name: &str) -> Option<Vec<f64>> {
        self.samples.channel(name)
    }

    /// Extremes of channel `name`: max, min, |peak| and their times.
    pub fn extremes(&self, name: &str) -> Option<&Extremes> {
        self.summary.channels.get(name).map(|c| &c.extremes)
    }

    /// True unless channel `name` is a band-limited twin ([`band`]).
    pub fn is_raw(&self, name: &str) -> bool {
        self.summary
            .channels
            .get(name)
            .is_none_or(|c| c.signal == Signal::Raw)
    }

    /// Largest magnitude of channel `name`, max(|max|, |min|).
    pub fn abs_peak(&self, name: &str) -> Option<f64> {
        self.extremes(name).map(|e| e.abs_peak)
    }

    /// True when the run reached its end time.
    pub fn completed(&self) -> bool {
        self.summary.status == RunStatus::Completed
    }

    /// An error when the solver stopped the run early or it was interrupted (for callers
    /// that need the whole run).
    pub fn require_completed(&self) -> Result<()> {
        if let Some(t) = self.samples.interrupted {
            return Err(scene::SceneError::Interrupted {
                name: self.summary.name.clone(),
                t,
            }
            .into());
        }
        match &self.samples.error {
            None => Ok(()),
            Some((message, t)) => Err(scene::SceneError::RunFailed {
                name: self.summary.name.clone(),
                t: *t,
                message: message.clone(),
            }
            .into()),
        }
    }

    /// The solver's message and the time reached, when the run stopped early.
    pub fn failure(&self) -> Option<(&str, f64)> {
        self.samples.error.as_ref().map(|(m, t)| (m.as_str(), *t))
    }
}

/// Refuses models the solver cannot run (a motion on a direction already locked).
pub fn check(sys: &System) -> Result<(), ModelError> {
    for r in &sys.redundant {
        if let Owner::Motion(_) = sys.cons[r.elem].owner {
            return Err(ModelError::Unsupported(format!(
                "{} drives a direction the joints already lock",
                sys.row_name(&sys.cons[r.elem], r.row)
            )));
        }
    }
    Ok(())
}

/// One warning per redundant constraint row, naming what it duplicates.
pub fn redundancy_warnings(sys: &System) -> Vec<String> {
    sys.redundant
        .iter()
        .map(|r| {
            let deps: Vec<String> = r
                .depends_on
                .iter()
                .map(|&(e, row, _)| sys.row_name(&sys.cons[e], row))
                .collect();
            if deps.is_empty() {
                format!(
                    "constraint eliminated: {} is degenerate at the initial position (its Jacobian row vanishes)",
                    sys.row_name(&sys.cons[r.elem], r.row)
                )
            } else {
                format!(
                    "redundant constraint eliminated: {} repeats {}",
                    sys.row_name(&sys.cons[r.elem], r.row),
                    deps.join(", ")
                )
            }
        })
        .collect()
}
