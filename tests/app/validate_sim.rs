//! A closed-form test simulator for the validation tests, independent of the crate's
//! stand-in: every channel is a point at a fixed distance behind the front axle whose
//! response is a damped sine starting when the point reaches the obstacle start, minus
//! the same sine starting when it leaves the obstacle end. Timing therefore scales with
//! 1/speed and the amplitude with the speed.

#![allow(dead_code)]

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::Path;

use towride_app::validate::{SimChannels, Simulator};

/// (name, distance behind the front axle [m], frequency [Hz], damping ratio, amplitude
/// per m/s [m/s^2 / (m/s)]).
pub type Channel = (&'static str, f64, f64, f64, f64);

pub const CHANNELS: [Channel; 4] = [
    ("acc_wheel_front_left_z", 0.0, 12.0, 0.30, 3.0),
    ("acc_wheel_rear_left_z", 2.46, 13.0, 0.30, 3.0),
    ("acc_body_rear_left_z", 2.46, 1.6, 0.30, 0.4),
    ("acc_trailer_drawbar_z", 5.5, 2.5, 0.20, 0.5),
];

pub struct Analytic {
    pub channels: Vec<Channel>,
    pub rate_hz: f64,
    /// Obstacle length along the road [m].
    pub length_m: f64,
}

impl Default for Analytic {
    fn default() -> Self {
        Analytic {
            channels: CHANNELS.to_vec(),
            rate_hz: 2000.0,
            length_m: 0.5,
        }
    }
}

fn damped_sine(tau: f64, f: f64, zeta: f64) -> f64 {
    if tau <= 0.0 {
        return 0.0;
    }
    let w = 2.0 * PI * f;
    (-zeta * w * tau).exp() * (w * (1.0 - zeta * zeta).sqrt() * tau).sin()
}

impl Simulator for Analytic {
    fn name(&self) -> String {
        "closed-form test simulator".into()
    }

    fn simulate(
        &self,
        _scene: &Path,
        v: f64,
        load: &str,
    ) -> Result<SimChannels, towride_app::Error> {
        // A heavier trailer rides lower in frequency.
        let trailer = match load {
            "empty" => 1.0,
            "200kg_over_axle" => 0.8,
            "200kg_ahead_of_axle" => 0.85,
            "200kg_behind_axle" => 0.75,
            _ => {
                return Err(towride_app::validate::ValidateError::Mismatch(format!(
                    "unknown load {load}"
                ))
                .into())
            }
        };
        let t_obs = 1.0 / v + 0.6; // front wheels 0.6 s + 1 m before the obstacle
        let last = self.channels.iter().map(|c| c.1).fold(0.0, f64::max);
        let t_end = t_obs + (last + self.length_m) / v + 1.5;
        let n = (t_end * self.rate_hz) as usize;
        let time: Vec<f64> = (0..n).map(|k| k as f64 / self.rate_hz).collect();
        let mut channels = BTreeMap::new();
        for &(name, lag, f, zeta, amp) in &self.channels {
            let f = if name.contains("trailer") {
                f * trailer
            } else {
                f
            };
            let (t_in, t_out) = (t_obs + lag / v, t_obs + (lag + self.length_m) / v);
            let y = time
                .iter()
                .map(|&t| {
                    amp * v * (damped_sine(t - t_in, f, zeta) - damped_sine(t - t_out, f, zeta))
                })
                .collect();
            channels.insert(name.to_string(), y);
        }
        Ok(SimChannels {
            time_s: time,
            channels,
            obstacle_time_s: t_obs,
        })
    }
}
