//! Scenes: a vehicle on a road at a set speed, with what to run and what to record.
//!
//! ```toml
//! [scene]
//! name = "thesis ramp, empty trailer, 50 km/h"
//! vehicle = "../vehicles/fabia_trailer.toml"
//! load_case = "empty"          # optional overrides of the vehicle's files
//! hitch_variant = 5
//! tyre_model = "rigid-ring"
//! ball_coupling = "spherical"
//! rear_cross_member = "rigid"  # or "flexible" (the twist beam's modal cross member)
//!
//! [road]
//! file = "../roads/ramp_thesis.toml"
//! obstacle_ahead_m = 1.0       # front tyres' contact to the road's first edge
//!
//! [run]
//! speed_km_h = 50.0
//! duration_s = 3.0
//! sample_rate_hz = 1000.0
//! start = "equilibrium_at_speed"
//! settle_s = 0.5
//!
//! [run.manoeuvre]              # optional: a speed change instead of the held speed
//! start_s = 0.5                # ([`manoeuvre`]: braking to rest here)
//! to_speed_km_h = 0.0
//! acceleration_m_s2 = 5.0
//! jerk_m_s3 = 25.0
//!
//! [solver]                     # any SolverOptions field
//! rtol = 1e-4
//!
//! [acquisition]                # the instrument's low-pass the sensor channels are
//! filter = "butterworth"       # reported through (default as here, the thesis's);
//! order = 4                    # "none": raw channels only
//! cutoff_hz = 100.0
//!
//! [[sensor]]                   # extra sensors, as in the vehicle file
//!
//! [[override]]                 # a value of any file the scene reads, replaced
//! file = "fabia/hitch.toml"    # matched by the end of the file's path
//! path = "ball_coupling.kind"  # TOML `table.key`, .tir `SECTION.KEY`, CSV `column[row]`
//! value = "bushing"
//!
//! [[output]]                   # more channels: a named vehicle quantity or a
//! quantity = "susp_fl_travel"  # marker, joint or element ([`outputs`])
//! ```
//!
//! [`load`] gives the [`Scene`]: the vehicle's model with its road and the standard
//! outputs ([`channels`]), and the run settings. A plan file ([`plan`]) expands one
//! template scene over obstacles, speeds and load cases.

pub mod channels;
pub mod manoeuvre;
pub mod outputs;
pub mod plan;

pub use crate::error::SceneError;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::Deserialize;

pub use channels::Channel;

use crate::signal::acquisition::AcqFilter;
use crate::vehicle::sensors::{self, SensorSpec};
use crate::vehicle::{self, build::Builder, BallCoupling, CrossMember, Options, Vehicle};
use towride_mbs::flex::feedback::RunModes;
use towride_mbs::input::Origin;
use towride_mbs::input::{InputError, InputErrorKind, Layer, Loader, Override, Source};
use towride_mbs::model::builder::ModelBuilder;
use towride_mbs::model::elements::JointBushing;
use towride_mbs::model::{Model, System};
use towride_mbs::path;
use towride_mbs::road::Road;
use towride_mbs::tyre::TyreKind;
use towride_solver::SolverOptions;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    scene: SceneSec,
    road: RoadSec,
    run: RunSec,
    #[serde(default)]
    solver: SolverOptions,
    #[serde(default)]
    sensor: Vec<SensorSpec>,
    #[serde(default, rename = "override")]
    overrides: Vec<OverrideSec>,
    /// Outputs beyond the fixed channels ([`outputs`]).
    #[serde(default)]
    output: Vec<towride_mbs::model::spec::OutputSpec>,
    #[serde(default)]
    report: ReportSec,
    acquisition: Option<AcquisitionSec>,
}

/// `[acquisition]`: the instrument's low-pass ([`crate::signal::acquisition`]).
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct AcquisitionSec {
    /// "butterworth" or "none".
    filter: String,
    order: Option<i64>,
    cutoff_hz: Option<f64>,
}

/// `[report]`: what the run's HTML report shows.
#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
struct ReportSec {
    /// Rate of the body poses for the 3D view [Hz]; 0 switches the view off.
    animation_rate_hz: Option<f64>,
}

/// A scene's `[[override]]`: one value of a file the scene reads.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct OverrideSec {
    file: String,
    path: String,
    value: toml::Value,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SceneSec {
    name: String,
    vehicle: String,
    load_case: Option<String>,
    hitch_variant: Option<u32>,
    tyre_model: Option<TyreKind>,
    ball_coupling: Option<BallCoupling>,
    joints_as_bushings: Option<JointBushing>,
    rear_cross_member: Option<CrossMember>,
    /// A run folder whose strain-energy shares select the modal bodies' modes.
    modes_from: Option<String>,
    /// The share a mode needs there (fraction; default 0.01).
    modes_min_energy_share: Option<f64>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct RoadSec {
    file: String,
    obstacle_ahead_m: Option<f64>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct RunSec {
    speed_km_h: f64,
    duration_s: f64,
    sample_rate_hz: f64,
    start: Start,
    #[serde(default)]
    settle_s: f64,
    /// Absolute tolerances per kind of unknown from the model (`System::atol`) times
    /// this, unless `[solver]` gives `atol`.
    #[serde(default = "one")]
    atol_scale: f64,
    /// Sampled accelerations and hitch forces: "interpolant" (default, the integrator's
    /// own solution) or "solve" (the acceleration-level equations at every sample).
    #[serde(default)]
    accelerations: towride_mbs::model::desc::Accelerations,
    /// A speed change instead of the held speed ([`manoeuvre`]).
    manoeuvre: Option<manoeuvre::ManoeuvreSec>,
    /// The steering rack's travel over time ([`manoeuvre`]).
    steering: Option<manoeuvre::SteeringSec>,
}

fn one() -> f64 {
    1.0
}

/// Where a run starts from.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Start {
    /// Static equilibrium, then the set speed and free-rolling spin, then `settle_s` of
    /// driving on flat road (`model::start::at_speed`).
    EquilibriumAtSpeed,
    /// The design position with the set speed, assembled onto the constraints.
    Assembly,
}

/// The report's 3D-view pose rate when a file does not set one (`[report]
/// animation_rate_hz` of a scene; mechanism files always use it) [Hz].
pub const DEFAULT_ANIMATION_RATE_HZ: f64 = 200.0;

/// A scene ready to run.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The overrides that took effect (the scene's `[[override]]` tables and the
    /// caller's), as `overrides.toml` records them.
    pub overrides: Vec<towride_mbs::input::Applied>,
    /// Scene name (the file's, or the plan case's).
    pub name: String,
    /// The scene file.
    pub file: PathBuf,
    /// The vehicle, its model carrying the road and the outputs.
    pub vehicle: Vehicle,
    /// Set speed [m/s].
    pub speed: f64,
    /// Run length [s] and output sample rate [Hz].
    pub duration: f64,
    /// Output sample rate [Hz].
    pub sample_rate: f64,
    /// Pose rate of the report's 3D view [Hz] (`[report] animation_rate_hz`; 0: none).
    pub animation_rate: f64,
    /// How the state at t = 0 is found.
    pub start: Start,
    /// Settling time on flat road before t = 0 [s] (equilibrium_at_speed).
    pub settle: f64,
    /// Solver settings from the file's `[solver]` (see [`Scene::solver_for`]).
    pub solver: SolverOptions,
    /// Scale of the model's per-unknown absolute tolerances; `None` when the scene's
    /// `[solver]` gives `atol` itself.
    pub atol_scale: Option<f64>,
    /// The output channels, in CSV order: the fixed ones, then the `[[output]]` tables'.
    pub channels: Vec<Channel>,
    /// The channels the `[[output]]` tables asked for (the last of `channels`).
    pub requested: Vec<String>,
    /// What `[[output]]` tables can name (`run SCENE --list-names`).
    pub names: outputs::Names,
    /// The road file in use.
    pub road_file: PathBuf,
    /// The instrument's low-pass the sensor, force and deflection channels are also
    /// reported through (`[acquisition]`; `None`: `filter = "none"`, raw channels only).
    pub acquisition: Option<AcqFilter>,
}

impl Scene {
    /// The vehicle's model.
    pub fn model(&self) -> &Model {
        &self.vehicle.model
    }

    /// The solver settings for the assembled scene: the file's, with the absolute
    /// tolerances of `sys` (`System::atol`) unless the file gave them.
    pub fn solver_for(&self, sys: &System) -> SolverOptions {
        let mut o = self.solver.clone();
        if let Some(s) = self.atol_scale {
            o.atol = sys.atol(s);
        }
        o
    }
}

/// Changes to a scene file's settings (a plan's cases, a validation run).
#[derive(Clone, Debug, Default)]
pub struct Changes {
    /// Replaces the scene's name.
    pub name: Option<String>,
    /// Replaces the road file.
    pub road: Option<PathBuf>,
    /// Replaces the set speed [km/h].
    pub speed_km_h: Option<f64>,
    /// Replaces the run length [s].
    pub duration_s: Option<f64>,
    /// Replaces the trailer load case.
    pub load_case: Option<String>,
    /// Replaces the hitch variant.
    pub hitch_variant: Option<u32>,
    /// Distance from the front tyres' contact to the road's first obstacle edge [m].
    pub obstacle_ahead_m: Option<f64>,
    /// Replaces `[report] animation_rate_hz` (0: no 3D view).
    pub animation_rate_hz: Option<f64>,
    /// Modes of the modal bodies from an earlier run's strain-energy shares (the command
    /// line's `--modes-from`), replacing the scene's `modes_from` and the files' rules.
    pub run_modes: Option<Arc<RunModes>>,
}

/// True when `path` is a scene file (it has a `[scene]` table).
pub fn is_scene(path: &Path) -> bool {
    has_table(path, "scene")
}

/// True when the TOML file at `path` has the top-level table `key`.
pub fn has_table(path: &Path, key: &str) -> bool {
    // Through the bounded reader: a named pipe given as the file must not block here.
    towride_mbs::input::read_text(path)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .is_some_and(|t| t.contains_key(key))
}

/// The scene file's `[[override]]` tables, each located where it was written.
fn overrides_in(src: &Source, f: &File) -> Vec<Override> {
    f.overrides
        .iter()
        .enumerate()
        .map(|(k, x)| Override {
            file: x.file.clone(),
            path: x.path.clone(),
            value: towride_mbs::input::value_text(&x.value),
            origin: Origin::File {
                file: Box::new(src.error(&path!["override", k, "file"], "")),
                path: Box::new(src.error(&path!["override", k, "path"], "")),
            },
        })
        .collect()
}

/// The hitch variant the scene asks the builder for: the caller's (a sweep's, a plan's)
/// or the scene's own `hitch_variant`, unless an override of the hitch file's
/// `hitch.variant` of a higher layer decides (the command line beats the scene file);
/// two of one layer setting it is an error, as for any value set twice.
fn hitch_variant(
    loader: &Loader,
    caller: Option<u32>,
    scene: Option<u32>,
) -> Result<Option<u32>, InputError> {
    let twice = |ov: &Override, by: &str| {
        Err(ov.origin.at_path(format!(
            "the hitch variant is set twice: also by {by}; keep one"
        )))
    };
    match (loader.override_at("hitch.variant"), caller, scene) {
        (Some((ov, Layer::Caller)), Some(n), _) => twice(
            ov,
            &format!("the case being run (a sweep or plan value, {n})"),
        ),
        (Some((_, Layer::Caller)), None, _) => Ok(None),
        (Some((ov, Layer::Scene)), None, Some(n)) => {
            twice(ov, &format!("the scene's hitch_variant = {n}"))
        }
        (Some((_, Layer::Scene)), None, None) => Ok(None),
        (_, c, s) => Ok(c.or(s)),
    }
}

/// The `[[override]]` tables of the scene file at `path` (as `load` applies them).
pub fn file_overrides(path: &Path) -> Result<Vec<Override>, InputError> {
    let src = Source::read(path)?;
    let f: File = src.parse()?;
    Ok(overrides_in(&src, &f))
}

/// Reads a scene file.
pub fn load(path: &Path) -> Result<Scene, InputError> {
    load_with(path, &Changes::default(), &Loader::new())
}

/// Reads a scene file with some settings replaced (`o`) and the files it reads through
/// `loader` (its property overrides, plus the scene's own `[[override]]` tables). An
/// override that matches no file or value read is an error.
pub fn load_with(path: &Path, o: &Changes, loader: &Loader) -> Result<Scene, InputError> {
    let loader = loader.fresh();
    let src = loader.toml(path)?;
    let f: File = src.parse()?;
    // The file's overrides first, so that the caller's (`run --set`, a sweep case, a
    // sensitivity study) win where both set a value.
    let own = overrides_in(&src, &f);
    // The scene is read before its own overrides exist: one of the scene would change
    // nothing.
    let me = towride_mbs::input::normalized(path);
    if let Some(o) = own
        .iter()
        .find(|o| me.ends_with(towride_mbs::input::normalized(Path::new(&o.file))))
    {
        return Err(o.origin.at_file(format!(
            "a scene's [[override]] cannot change the scene itself ({}): write the value in the scene",
            path.display()
        )));
    }
    let loader = loader.under(own);
    let dir = path.parent().unwrap_or(Path::new("."));
    // Modes from an earlier run: the command line's choice wins over the file's.
    let run_modes = match (&f.scene.modes_from, &o.run_modes) {
        (Some(run), None) => {
            let share = f
                .scene
                .modes_min_energy_share
                .unwrap_or(towride_mbs::flex::selection::DEFAULT_MIN_ENERGY_SHARE);
            let at = if f.scene.modes_min_energy_share.is_some() {
                src.error(&path!["scene", "modes_min_energy_share"], "")
            } else {
                src.error(&path!["scene", "modes_from"], "")
            };
            let rm = towride_mbs::flex::feedback::from_run(&dir.join(run), share, &at)?;
            Some(Arc::new(rm))
        }
        (_, given) => given.clone(),
    };
    let existing = |p: &[towride_mbs::input::Seg], rel: &str| -> Result<PathBuf, InputError> {
        let full = dir.join(rel);
        if full.is_file() {
            Ok(full)
        } else {
            Err(src.error(p, towride_mbs::input::no_file(&full)))
        }
    };
    let vehicle_file = existing(&path!["scene", "vehicle"], &f.scene.vehicle)?;
    let road_file = match &o.road {
        Some(r) => r.clone(),
        None => existing(&path!["road", "file"], &f.road.file)?,
    };
    let speed_km_h = o.speed_km_h.unwrap_or(f.run.speed_km_h);
    let speed = src.non_negative(&path!["run", "speed_km_h"], speed_km_h)? / 3.6;
    let duration = src.positive(
        &path!["run", "duration_s"],
        o.duration_s.unwrap_or(f.run.duration_s),
    )?;
    let sample_rate = src.positive(&path!["run", "sample_rate_hz"], f.run.sample_rate_hz)?;
    let settle = src.non_negative(&path!["run", "settle_s"], f.run.settle_s)?;
    let speed_target = match &f.run.manoeuvre {
        Some(m) => Some(manoeuvre::target(&src, m, speed, duration)?),
        None => None,
    };
    let steering = match &f.run.steering {
        Some(s) => Some(manoeuvre::steering(&src, s)?),
        None => None,
    };
    let animation_rate = match o.animation_rate_hz {
        Some(r) if r.is_finite() && r >= 0.0 => r,
        Some(r) => {
            return Err(src.error(
                &path!["report", "animation_rate_hz"],
                format!("{r}: the animation rate (command line) must be 0 or positive"),
            ))
        }
        None => src.non_negative(
            &path!["report", "animation_rate_hz"],
            f.report
                .animation_rate_hz
                .unwrap_or(DEFAULT_ANIMATION_RATE_HZ),
        )?,
    };
    towride_mbs::input::bounds::budget::check(duration, sample_rate, 0)
        .map_err(|e| src.error(&path!["run", "sample_rate_hz"], e.to_string()))?;
    // Which [solver] keys the file itself sets (the parsed options carry defaults).
    let raw: Option<toml::Table> = src.text().parse().ok();
    let solver_sets = |key: &str| {
        raw.as_ref()
            .and_then(|t| t.get("solver"))
            .is_some_and(|s| s.get(key).is_some())
    };
    let atol_given = solver_sets("atol");
    let mut solver = f.solver;
    // Radau IIA unless the file names a method: BDF orders 3-5 are not A-stable, and the
    // vehicle's lightly damped hitch and trailer modes (183 Hz at zeta 0.07, 212 Hz) fall
    // inside their unstable band at the steps taken, so BDF runs carry a late oscillation
    // at the tolerance level that tightening the tolerance does not remove; Radau IIA is
    // L-stable and its answer converges (docs/solver.md, "BDF stability limit detection").
    if !solver_sets("method") {
        solver.method = towride_solver::Method::Radau5;
    }
    // A vehicle's Jacobian costs about 25 Newton iterations: rebuild the iteration matrix
    // for a new step size from the kept parts unless the file says otherwise.
    if !solver_sets("jacobian_recombine") {
        solver.jacobian_recombine = true;
    }
    // For Radau IIA the same cost ratio: keep Jacobians and factorisations longer.
    if !solver_sets("radau") {
        solver.radau = towride_solver::RadauOptions::costly_jacobian();
    }
    towride_mbs::model::spec::solver_keys_used(&src, solver.method)?;
    let atol_scale = if atol_given {
        None
    } else {
        Some(src.positive(&path!["run", "atol_scale"], f.run.atol_scale)?)
    };
    solver
        .validate(1)
        .map_err(|e| src.error(&path!["solver"], e.to_string()))?;
    if let Some(jb) = &f.scene.joints_as_bushings {
        vehicle::props::joint_bushing(
            &src,
            &path!["scene", "joints_as_bushings"],
            &Some(jb.clone()),
        )?;
    }
    let road = Road::from_file(&road_file, &loader)?;
    let x_offset = match o.obstacle_ahead_m.or(f.road.obstacle_ahead_m) {
        None => 0.0,
        Some(d) => {
            let d = src.finite(&path!["road", "obstacle_ahead_m"], d)?;
            let (x0, span) = (-1.0e3, 2.0e3);
            let mut kinks = Vec::new();
            road.kinks_along([x0, 0.0], [1.0, 0.0], 0.0, span, &mut kinks);
            let first = kinks.first().ok_or_else(|| {
                src.error(
                    &path!["road", "obstacle_ahead_m"],
                    format!("{} has no obstacle to place", road_file.display()),
                )
            })?;
            x0 + first - d
        }
    };
    let opts = Options {
        speed,
        x_offset,
        load_case: o.load_case.clone().or(f.scene.load_case.clone()),
        hitch_variant: hitch_variant(&loader, o.hitch_variant, f.scene.hitch_variant)?,
        tyre_kind: f.scene.tyre_model,
        joints_as_bushings: f.scene.joints_as_bushings.clone(),
        ball_coupling: f.scene.ball_coupling,
        rear_cross_member: f.scene.rear_cross_member,
        run_modes,
        speed_target: speed_target.clone(),
        steering: steering.clone(),
    };
    let mut v = vehicle::load(&vehicle_file, &opts, &loader).map_err(|e| {
        // A variant the hitch's flexible body lacks is the scene's mistake when the scene
        // chose it: blame `scene.hitch_variant`, not the flexible-body file.
        match (o.hitch_variant, f.scene.hitch_variant, &e.kind) {
            (None, Some(n), InputErrorKind::NoVariant { number, .. }) if *number == n => src
                .error(
                    &path!["scene", "hitch_variant"],
                    format!("{} ({})", e.message, e.file.display()),
                )
                .with_kind(e.kind.clone()),
            // The same for a load case the scene names.
            _ => match (&o.load_case, &f.scene.load_case, &e.kind) {
                (None, Some(_), InputErrorKind::NoLoadCase) => src
                    .error(
                        &path!["scene", "load_case"],
                        format!("{} ({})", e.message, e.file.display()),
                    )
                    .with_kind(e.kind.clone()),
                _ => e,
            },
        }
    })?;
    if speed_target.as_ref().is_some_and(manoeuvre::slows)
        && v.model.controls.iter().any(|c| c.brakes.is_none())
    {
        return Err(src.error(
            &path!["run", "manoeuvre", "to_speed_km_h"],
            format!(
                "slows the vehicle, but {} has no brakes (its driveline file needs [brakes])",
                vehicle_file.display()
            ),
        ));
    }
    if steering.is_some() && !v.model.motions.iter().any(|m| m.name == "steering_rack") {
        return Err(src.error(
            &path!["run", "steering"],
            format!(
                "{}'s front axle has no steering rack (only the McPherson template builds one)",
                vehicle_file.display()
            ),
        ));
    }
    let extra = {
        let model = std::mem::take(&mut v.model);
        let mut b = Builder::new(ModelBuilder::from_model(model), &loader, None);
        let extra = sensors::add(&mut b, &v.handles, &src, &path!["sensor"], &f.sensor);
        v.model = b.mb.finish();
        extra?
    };
    v.handles.sensors.extend(extra);
    let (mut outputs, mut channels) = channels::standard(&v);
    for (k, c) in channels.iter().enumerate() {
        if channels[..k].iter().any(|d| d.name == c.name) {
            return Err(src.error(&path!["sensor"], format!("channel '{}' is defined twice (sensor names must differ from the vehicle's channels)", c.name)));
        }
    }
    let names = outputs::names(&v, &channels);
    let (more, more_channels) = outputs::requested(&src, &mut v, &f.output, &channels)?;
    outputs.extend(more);
    let requested = more_channels.iter().map(|c| c.name.clone()).collect();
    channels.extend(more_channels);
    let acquisition = acquisition(&src, f.acquisition.as_ref())?;
    // Steps no longer than half the period of the band's upper edge unless the file sets
    // h_max: the channels are reported up to the cutoff, so the integrator, not only its
    // interpolant, must resolve what lies there. On flat road Radau IIA grows its steps to
    // 14-20 ms, where the 46 Hz lateral hitch mode (zeta 0.045) is not resolved and its
    // tolerance-level content changes with the step sequence (hitch_fy 0.22 N, 0.004 N at
    // a 5 ms limit; docs/performance.md).
    if let (Some(a), false) = (&acquisition, solver_sets("h_max")) {
        solver.h_max = solver.h_max.min(0.5 / a.cutoff_hz);
    }
    if let Some(a) = &acquisition {
        // A band-limited twin is named by suffix: no channel may already carry its name.
        let suffix = a.suffix();
        for c in channels
            .iter()
            .filter(|c| channels::band(&c.name).is_some())
        {
            let twin = format!("{}{suffix}", c.name);
            if channels.iter().any(|d| d.name == twin) {
                return Err(src.error(
                    &path!["output"],
                    format!("channel '{twin}' has the name of the band-limited twin of '{}' ([acquisition]): rename it", c.name),
                ));
            }
        }
    }
    v.model.outputs = outputs;
    v.model.road = Some(road);
    v.model.accelerations = f.run.accelerations;
    loader.check_used()?;
    Ok(Scene {
        overrides: loader.applied(),
        name: o.name.clone().unwrap_or(f.scene.name.clone()),
        file: path.to_path_buf(),
        vehicle: v,
        speed,
        duration,
        sample_rate,
        animation_rate,
        start: f.run.start,
        settle,
        solver,
        atol_scale,
        channels,
        requested,
        names,
        road_file,
        acquisition,
    })
}

/// The scene's `[acquisition]` (default [`AcqFilter::THESIS`]; `None` for `filter =
/// "none"`).
fn acquisition(src: &Source, a: Option<&AcquisitionSec>) -> Result<Option<AcqFilter>, InputError> {
    let Some(a) = a else {
        return Ok(Some(AcqFilter::THESIS));
    };
    match a.filter.as_str() {
        "none" => {
            if a.order.is_some() || a.cutoff_hz.is_some() {
                return Err(src.error(
                    &path!["acquisition", "filter"],
                    "`none` takes no order or cutoff_hz",
                ));
            }
            Ok(None)
        }
        "butterworth" => {
            let order = a.order.unwrap_or(AcqFilter::THESIS.order as i64);
            if !(1..=10).contains(&order) {
                return Err(src.error(&path!["acquisition", "order"], "must be 1 ..= 10"));
            }
            let cutoff_hz = src.positive(
                &path!["acquisition", "cutoff_hz"],
                a.cutoff_hz.unwrap_or(AcqFilter::THESIS.cutoff_hz),
            )?;
            Ok(Some(AcqFilter {
                order: order as usize,
                cutoff_hz,
            }))
        }
        other => Err(src.error(
            &path!["acquisition", "filter"],
            format!("`{other}`: use butterworth or none"),
        )),
    }
}
