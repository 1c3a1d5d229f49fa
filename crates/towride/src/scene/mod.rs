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
//! [solver]                     # any SolverOptions field
//! rtol = 1e-4
//!
//! [[sensor]]                   # extra sensors, as in the vehicle file
//! ```
//!
//! [`load`] gives the [`Scene`]: the vehicle's model with its road and the standard
//! outputs ([`channels`]), and the run settings. A plan file ([`plan`]) expands one
//! template scene over obstacles, speeds and load cases.

pub mod channels;
pub mod exec;
pub mod plan;

use std::path::{Path, PathBuf};

use serde::Deserialize;

pub use channels::Channel;

use crate::input::{InputError, Source};
use crate::model::spec::JointBushing;
use crate::model::{Model, System};
use crate::path;
use crate::road::Road;
use crate::tyre::TyreKind;
use crate::vehicle::sensors::{self, SensorSpec};
use crate::vehicle::{self, build::Builder, Options, Vehicle};
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
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SceneSec {
    name: String,
    vehicle: String,
    load_case: Option<String>,
    hitch_variant: Option<u32>,
    tyre_model: Option<TyreKind>,
    ball_coupling: Option<String>,
    joints_as_bushings: Option<JointBushing>,
    rear_cross_member: Option<String>,
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
    accelerations: crate::model::desc::Accelerations,
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

/// A scene ready to run.
#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    pub file: PathBuf,
    /// The vehicle, its model carrying the road and the outputs.
    pub vehicle: Vehicle,
    /// Set speed [m/s].
    pub speed: f64,
    /// Run length [s] and output sample rate [Hz].
    pub duration: f64,
    pub sample_rate: f64,
    pub start: Start,
    /// Settling time on flat road before t = 0 [s] (equilibrium_at_speed).
    pub settle: f64,
    pub solver: SolverOptions,
    /// Scale of the model's per-unknown absolute tolerances; `None` when the scene's
    /// `[solver]` gives `atol` itself.
    pub atol_scale: Option<f64>,
    /// The output channels, in CSV order.
    pub channels: Vec<Channel>,
    pub road_file: PathBuf,
}

impl Scene {
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

/// Changes to a scene file's settings (a plan's cases).
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    pub name: Option<String>,
    pub road: Option<PathBuf>,
    pub speed_km_h: Option<f64>,
    pub duration_s: Option<f64>,
    pub load_case: Option<String>,
    pub hitch_variant: Option<u32>,
}

/// True when `path` is a scene file (it has a `[scene]` table).
pub fn is_scene(path: &Path) -> bool {
    has_table(path, "scene")
}

/// True when the TOML file at `path` has the top-level table `key`.
pub fn has_table(path: &Path, key: &str) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .is_some_and(|t| t.contains_key(key))
}

/// Reads a scene file.
pub fn load(path: &Path) -> Result<Scene, InputError> {
    load_with(path, &Overrides::default())
}

/// Reads a scene file with some settings replaced.
pub fn load_with(path: &Path, o: &Overrides) -> Result<Scene, InputError> {
    let src = Source::read(path)?;
    let f: File = src.parse()?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let existing = |p: &[crate::input::Seg], rel: &str| -> Result<PathBuf, InputError> {
        let full = dir.join(rel);
        if full.is_file() {
            Ok(full)
        } else {
            Err(src.error(p, format!("no file {}", full.display())))
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
    // Which [solver] keys the file itself sets (the parsed options carry defaults).
    let raw: Option<toml::Table> = src.text().parse().ok();
    let solver_sets = |key: &str| {
        raw.as_ref()
            .and_then(|t| t.get("solver"))
            .is_some_and(|s| s.get(key).is_some())
    };
    let atol_given = solver_sets("atol");
    let mut solver = f.solver;
    // A vehicle's Jacobian costs about 25 Newton iterations: rebuild the iteration matrix
    // for a new step size from the kept parts unless the file says otherwise.
    if !solver_sets("jacobian_recombine") {
        solver.jacobian_recombine = true;
    }
    // For Radau IIA the same cost ratio: keep Jacobians and factorisations longer.
    if !solver_sets("radau") {
        solver.radau = towride_solver::RadauOptions::costly_jacobian();
    }
    let atol_scale = if atol_given {
        None
    } else {
        Some(src.positive(&path!["run", "atol_scale"], f.run.atol_scale)?)
    };
    solver
        .validate(1)
        .map_err(|e| src.error(&path!["solver"], e.to_string()))?;
    if let Some(b) = &f.scene.ball_coupling {
        if b != "spherical" && b != "bushing" {
            return Err(src.error(
                &path!["scene", "ball_coupling"],
                format!("'{b}': use spherical or bushing"),
            ));
        }
    }
    if let Some(k) = &f.scene.rear_cross_member {
        if k != "rigid" && k != "flexible" {
            return Err(src.error(
                &path!["scene", "rear_cross_member"],
                format!("'{k}': use rigid or flexible"),
            ));
        }
    }
    if let Some(jb) = &f.scene.joints_as_bushings {
        vehicle::props::joint_bushing(
            &src,
            &path!["scene", "joints_as_bushings"],
            &Some(jb.clone()),
        )?;
    }
    let road = Road::from_file(&road_file)?;
    let x_offset = match f.road.obstacle_ahead_m {
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
        hitch_variant: o.hitch_variant.or(f.scene.hitch_variant),
        tyre_kind: f.scene.tyre_model,
        joints_as_bushings: f.scene.joints_as_bushings.clone(),
        ball_coupling: f.scene.ball_coupling.clone(),
        rear_cross_member: f.scene.rear_cross_member.clone(),
    };
    let mut v = vehicle::load(&vehicle_file, &opts)?;
    let extra = {
        let mut b = Builder::new(&mut v.model, None);
        sensors::add(&mut b, &v.handles, &src, &path!["sensor"], &f.sensor)?
    };
    v.handles.sensors.extend(extra);
    let (outputs, channels) = channels::standard(&v);
    for (k, c) in channels.iter().enumerate() {
        if channels[..k].iter().any(|d| d.name == c.name) {
            return Err(src.error(&path!["sensor"], format!("channel '{}' is defined twice (sensor names must differ from the vehicle's channels)", c.name)));
        }
    }
    v.model.outputs = outputs;
    v.model.road = Some(road);
    v.model.accelerations = f.run.accelerations;
    Ok(Scene {
        name: o.name.clone().unwrap_or(f.scene.name.clone()),
        file: path.to_path_buf(),
        vehicle: v,
        speed,
        duration,
        sample_rate,
        start: f.run.start,
        settle,
        solver,
        atol_scale,
        channels,
        road_file,
    })
}
