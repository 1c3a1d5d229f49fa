//! A plan: scenes (one per obstacle) run over speeds x trailer load cases, like the
//! thesis's measurement plan (5.5.3.4: 3 obstacles x 6 speeds x 4 loads = 72 passes).
//! `scenes/measurement_plan.toml` is the plan's one definition: runs and the synthetic
//! measurement set (`validate::plan`) both expand it.
//!
//! ```toml
//! [plan]
//! name = "measurement_plan"
//! speeds_km_h = [10.0, 20.0, 30.0, 40.0, 50.0, 60.0]
//! load_cases = ["empty", "200kg_over_axle", "200kg_ahead_of_axle", "200kg_behind_axle"]
//! # Each run lasts travel_m / speed + after_s: long enough for the trailer's wheels to
//! # cross the obstacle, then a little more.
//! travel_m = 7.5
//! after_s = 1.0
//!
//! [[obstacle]]
//! name = "ramp_50mm"
//! scene = "default.toml"       # the scene that drives over it
//! ```
//!
//! Case names are `<obstacle>_<speed>kmh_<load case>`, e.g. `ramp_50mm_50kmh_empty` (the
//! names `validate::plan` gives its synthetic runs).

use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::{load_with, Changes, Scene};
use towride_mbs::input::{InputError, Loader, Source};
use towride_mbs::path;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    plan: PlanSec,
    obstacle: Vec<ObstacleSec>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct PlanSec {
    name: String,
    speeds_km_h: Vec<f64>,
    load_cases: Vec<String>,
    travel_m: f64,
    after_s: f64,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ObstacleSec {
    name: String,
    scene: String,
}

/// One run of a plan.
#[derive(Clone, Debug)]
pub struct Case {
    /// `<obstacle>_<speed>kmh_<load case>`.
    pub name: String,
    /// The obstacle's name.
    pub obstacle: String,
    /// The scene that drives over it.
    pub scene: PathBuf,
    /// Nominal speed [km/h].
    pub speed_km_h: f64,
    /// Trailer load case.
    pub load_case: String,
    /// The scene settings the case changes.
    pub changes: Changes,
}

/// A plan read and expanded (scenes are built on demand: [`Plan::scene`]).
#[derive(Clone, Debug)]
pub struct Plan {
    /// The plan's name.
    pub name: String,
    /// Every case, obstacle-major, then speed, then load case.
    pub cases: Vec<Case>,
}

impl Plan {
    /// The scene of one case, its files read through `loader`.
    pub fn scene(&self, case: &Case, loader: &Loader) -> Result<Scene, InputError> {
        load_with(&case.scene, &case.changes, loader)
    }

    /// The case called `name`.
    pub fn case(&self, name: &str) -> Option<&Case> {
        self.cases.iter().find(|c| c.name == name)
    }
}

/// True when `path` is a plan file (it has a `[plan]` table).
pub fn is_plan(path: &Path) -> bool {
    super::has_table(path, "plan")
}

/// Reads a plan file and lists its cases (obstacle-major, then speed, then load).
pub fn load(path: &Path) -> Result<Plan, InputError> {
    let src = Source::read(path)?;
    let f: File = src.parse()?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let p = &f.plan;
    let travel = src.positive(&path!["plan", "travel_m"], p.travel_m)?;
    let after = src.non_negative(&path!["plan", "after_s"], p.after_s)?;
    if f.obstacle.is_empty() || p.speeds_km_h.is_empty() || p.load_cases.is_empty() {
        return Err(src.error(
            &path!["plan"],
            "give at least one obstacle, speed and load case",
        ));
    }
    // Case names are keys (output folders, `--case`): no speed or load case twice.
    for (j, l) in p.load_cases.iter().enumerate() {
        if p.load_cases[..j].contains(l) {
            return Err(src.error(
                &path!["plan", "load_cases", j],
                format!("load case '{l}' is listed twice"),
            ));
        }
    }
    for (j, &v) in p.speeds_km_h.iter().enumerate() {
        src.positive(&path!["plan", "speeds_km_h", j], v)?;
        if p.speeds_km_h[..j]
            .iter()
            .any(|&w| fmt_speed(w) == fmt_speed(v))
        {
            return Err(src.error(
                &path!["plan", "speeds_km_h", j],
                format!("speed {v} km/h is listed twice"),
            ));
        }
        let duration = travel / (v / 3.6) + after;
        let time = towride_mbs::input::bounds::for_key("duration_s");
        if !time.accepts(duration) {
            return Err(src.error(
                &path!["plan", "speeds_km_h", j],
                format!(
                    "a run of travel_m / speed + after_s = {duration:e} s: {}",
                    time.message(duration)
                ),
            ));
        }
    }
    let mut cases = Vec::new();
    for (i, o) in f.obstacle.iter().enumerate() {
        let scene = dir.join(&o.scene);
        if !scene.is_file() {
            return Err(src.error(
                &path!["obstacle", i, "scene"],
                towride_mbs::input::no_file(&scene),
            ));
        }
        if f.obstacle[..i].iter().any(|q| q.name == o.name) {
            return Err(src.error(
                &path!["obstacle", i, "name"],
                format!("obstacle '{}' defined twice", o.name),
            ));
        }
        for &v in &p.speeds_km_h {
            for load in &p.load_cases {
                let name = format!("{}_{}kmh_{load}", o.name, fmt_speed(v));
                cases.push(Case {
                    name: name.clone(),
                    obstacle: o.name.clone(),
                    scene: scene.clone(),
                    speed_km_h: v,
                    load_case: load.clone(),
                    changes: Changes {
                        name: Some(name),
                        road: None,
                        speed_km_h: Some(v),
                        duration_s: Some(travel / (v / 3.6) + after),
                        load_case: Some(load.clone()),
                        hitch_variant: None,
                        obstacle_ahead_m: None,
                        animation_rate_hz: None,
                        run_modes: None,
                    },
                });
            }
        }
    }
    Ok(Plan {
        name: p.name.clone(),
        cases,
    })
}

/// 50 -> "50", 5 -> "05" (as `validate::plan` names its runs), 12.5 -> "12.5".
fn fmt_speed(v: f64) -> String {
    if v.fract() == 0.0 {
        format!("{v:02.0}")
    } else {
        format!("{v}")
    }
}
