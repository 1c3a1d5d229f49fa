//! The measurement plan's runs synthesised with any [`Simulator`]: the plan is the one
//! of `scenes/measurement_plan.toml` (3 obstacles x 6 speeds x 4 trailer loads = 72
//! runs, thesis 5.5.3.4), read by [`crate::scene::plan::load`].

use super::ValidateError;
use std::path::{Path, PathBuf};

use super::synth::{make_synthetic, SensorModel, SynthRun, TriggerLayout};
use super::Simulator;
use crate::scene::plan::Plan;

/// The shipped measurement plan's text, its one definition.
const SHIPPED_PLAN: &str = include_str!("../../../../scenes/measurement_plan.toml");

/// The trailer load cases of the shipped measurement plan (thesis 5.5.3.4), read from
/// `scenes/measurement_plan.toml`: the load cases a recorded run may name.
pub fn load_cases() -> Vec<String> {
    #[derive(serde::Deserialize)]
    struct File {
        plan: Head,
    }
    #[derive(serde::Deserialize)]
    struct Head {
        load_cases: Vec<String>,
    }
    // The file is part of the source tree and its test reads it: it parses.
    toml::from_str::<File>(SHIPPED_PLAN)
        .map(|f| f.plan.load_cases)
        .unwrap_or_default()
}

/// Every run of the plan, in the plan's order (obstacle-major).
pub fn plan(p: &Plan) -> Vec<SynthRun> {
    p.cases
        .iter()
        .map(|c| SynthRun {
            name: c.name.clone(),
            scene: c.scene.clone(),
            obstacle: c.obstacle.clone(),
            nominal_speed_kmh: c.speed_km_h,
            load_case: c.load_case.clone(),
            truth: Vec::new(),
        })
        .collect()
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
    // A recording in the way stops the plan before the first simulation, not midway.
    super::synth::targets_free(runs, out)?;
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

#[cfg(test)]
mod tests {
    #[test]
    fn the_shipped_plan_has_its_four_load_cases() {
        assert_eq!(
            super::load_cases(),
            [
                "empty",
                "200kg_over_axle",
                "200kg_ahead_of_axle",
                "200kg_behind_axle"
            ]
        );
    }
}
