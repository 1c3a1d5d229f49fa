//! The thesis's measurement plan (5.5.3.4): 3 obstacles x 6 speeds x 4 trailer loads =
//! 72 runs, synthesised with any [`Simulator`].

use super::ValidateError;
use std::path::{Path, PathBuf};

use super::synth::{make_synthetic, SensorModel, SynthRun, TriggerLayout};
use super::{Simulator, LOAD_CASES};

/// Nominal speeds of the plan [km/h].
pub const SPEEDS_KMH: [f64; 6] = [10.0, 20.0, 30.0, 40.0, 50.0, 60.0];

/// The plan's obstacles and the vehicle scenes that drive over them (`--plan-scene
/// NAME=FILE` replaces one).
pub fn default_obstacles() -> Vec<(String, PathBuf)> {
    [
        ("bump_25mm", "scenes/bump_25mm.toml"),
        ("bump_50mm", "scenes/bump_50mm.toml"),
        ("ramp_50mm", "scenes/default.toml"),
    ]
    .iter()
    .map(|(n, p)| (n.to_string(), PathBuf::from(p)))
    .collect()
}

/// Every run of the plan, obstacle-major.
pub fn plan(obstacles: &[(String, PathBuf)]) -> Vec<SynthRun> {
    let mut runs = Vec::new();
    for (name, scene) in obstacles {
        for v in SPEEDS_KMH {
            for load in LOAD_CASES {
                runs.push(SynthRun {
                    name: format!("{name}_{v:02.0}kmh_{load}"),
                    scene: scene.clone(),
                    obstacle: name.clone(),
                    nominal_speed_kmh: v,
                    load_case: load.to_string(),
                });
            }
        }
    }
    runs
}

/// Writes the plan's runs into `out` (seed + run index as each run's noise seed);
/// `progress` is called after each run.
pub fn write_plan(
    sim: &dyn Simulator,
    runs: &[SynthRun],
    sensor: &SensorModel,
    out: &Path,
    progress: &dyn Fn(usize),
) -> Result<Vec<PathBuf>, ValidateError> {
    let mut files = Vec::with_capacity(runs.len());
    for (i, run) in runs.iter().enumerate() {
        let s = SensorModel {
            seed: sensor.seed.wrapping_add(i as u64),
            ..sensor.clone()
        };
        files.push(make_synthetic(
            sim,
            run,
            &s,
            &TriggerLayout::default(),
            out,
        )?);
        progress(i + 1);
    }
    Ok(files)
}
