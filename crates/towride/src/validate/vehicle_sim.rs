//! The vehicle model as the validation's simulator: a scene file driven at the measured
//! speed with the measured load case, started from equilibrium at speed far enough before
//! the obstacle (half a second of travel, at least the scene's own distance) and run until
//! the trailer's wheels have passed it and the response has died out.

use std::path::Path;

use super::{SimChannels, Simulator};
use crate::input::overrides::Override;
use crate::scene::Overrides;

/// Quiet travel before the obstacle [s] (the alignment needs a lead-in).
const LEAD_IN_S: f64 = 0.5;
/// Travel after the front wheels reach the obstacle until the trailer's wheels are past
/// it [m] (the plan's `travel_m`), and the ring-down after that [s].
const TRAVEL_M: f64 = 7.5;
const RING_DOWN_S: f64 = 1.0;

#[derive(Clone, Copy, Debug, Default)]
pub struct VehicleSimulator;

impl Simulator for VehicleSimulator {
    fn simulate(
        &self,
        scene: &Path,
        speed_mps: f64,
        load_case: &str,
    ) -> Result<SimChannels, String> {
        if speed_mps.is_nan() || speed_mps <= 0.0 {
            return Err(format!("speed must be positive, got {speed_mps} m/s"));
        }
        let ahead = (LEAD_IN_S * speed_mps).max(1.0);
        let ov = [Override {
            file: scene.display().to_string(),
            path: "road.obstacle_ahead_m".into(),
            value: format!("{ahead:?}"),
        }];
        let o = Overrides {
            speed_km_h: Some(speed_mps * 3.6),
            duration_s: Some((ahead + TRAVEL_M) / speed_mps + RING_DOWN_S),
            load_case: Some(load_case.to_string()),
            ..Default::default()
        };
        let r = crate::scene::exec::run(scene, &ov, &o, &|_| {})?;
        let res = r.result;
        if let Some((e, t)) = res.error {
            return Err(format!(
                "{}: simulation failed at t = {t:.4} s: {e}",
                scene.display()
            ));
        }
        // The accelerometer channels: what a measurement can be compared with.
        let channels = res
            .channels
            .iter()
            .enumerate()
            .filter(|(_, ch)| ch.name.starts_with("acc_"))
            .map(|(c, ch)| (ch.name.clone(), res.rows.iter().map(|r| r[c]).collect()))
            .collect();
        Ok(SimChannels {
            time_s: res.times.clone(),
            channels,
            obstacle_time_s: ahead / speed_mps,
        })
    }

    fn name(&self) -> String {
        "towride vehicle model".into()
    }
}
