//! The vehicle model as the validation's simulator: a scene file driven at the measured
//! speed with the measured load case, started from equilibrium at speed far enough before
//! the obstacle (half a second of travel, at least the scene's own distance) and run until
//! the trailer's wheels have passed it and the response has died out.

use std::path::Path;

use super::ValidateError;
use super::{SimChannels, Simulator};
use crate::job::Job;
use crate::scene::channels::ACC_PREFIX;
use crate::scene::Changes;
use towride_mbs::input::Loader;
use towride_mbs::progress::Silent;

/// Quiet travel before the obstacle [s] (the alignment needs a lead-in).
const LEAD_IN_S: f64 = 0.5;
/// Travel after the front wheels reach the obstacle until the trailer's wheels are past
/// it [m] (the plan's `travel_m`), and the ring-down after that [s].
const TRAVEL_M: f64 = 7.5;
const RING_DOWN_S: f64 = 1.0;

#[derive(Clone, Debug, Default)]
pub struct VehicleSimulator {
    /// Reads the scene's files (with the caller's overrides).
    pub loader: Loader,
}

impl Simulator for VehicleSimulator {
    fn obstacle_geometry(&self, scene: &Path) -> Option<super::geometry::ObstacleGeometry> {
        super::geometry::of_scene(scene, &self.loader.fresh())
    }

    fn simulate(
        &self,
        scene: &Path,
        speed_mps: f64,
        load_case: &str,
    ) -> Result<SimChannels, crate::Error> {
        if speed_mps.is_nan() || speed_mps <= 0.0 {
            return Err(ValidateError::Signal(format!(
                "speed must be positive, got {speed_mps} m/s"
            ))
            .into());
        }
        let ahead = (LEAD_IN_S * speed_mps).max(1.0);
        let changes = Changes {
            speed_km_h: Some(speed_mps * 3.6),
            duration_s: Some((ahead + TRAVEL_M) / speed_mps + RING_DOWN_S),
            load_case: (!load_case.is_empty()).then(|| load_case.to_string()),
            obstacle_ahead_m: Some(ahead),
            ..Default::default()
        };
        let r = Job::from_scene_file(scene, &changes, &self.loader)?
            .without_view()
            .run(&Silent)?;
        r.require_completed()?;
        // The raw accelerometer channels: what a measurement can be compared with once
        // through the descriptor's own acquisition chain (not the scene's twins).
        let raw: Vec<bool> = r
            .samples
            .channels
            .iter()
            .map(|c| r.is_raw(&c.name))
            .collect();
        let res = r.samples;
        let channels = res
            .channels
            .iter()
            .enumerate()
            .filter(|(c, ch)| ch.name.starts_with(ACC_PREFIX) && raw[*c])
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

    fn axles(&self, scene: &Path) -> (Option<f64>, Option<f64>) {
        let Ok(s) = crate::scene::load(scene) else {
            return (None, None);
        };
        let m = &s.vehicle.model;
        // Mean x of a pair of wheels at the design position (world).
        let x = |pair: [&str; 2]| -> Option<f64> {
            let xs: Vec<f64> = s
                .vehicle
                .handles
                .wheels
                .iter()
                .filter(|w| pair.contains(&w.name.as_str()))
                .map(|w| m.bodies[w.body].position[0])
                .collect();
            (xs.len() == 2).then(|| 0.5 * (xs[0] + xs[1]))
        };
        let Some(front) = x(["fl", "fr"]) else {
            return (None, None);
        };
        (
            x(["rl", "rr"]).map(|r| front - r),
            x(["tl", "tr"]).map(|t| front - t),
        )
    }
}
