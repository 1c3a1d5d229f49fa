//! A STAND-IN for the vehicle simulation, so `towride validate` runs end to end before
//! the vehicle model exists. It is not the vehicle model: each axle is a point follower
//! over the road (height averaged over a 0.2 m contact length) driving a wheel-hop
//! oscillator that drives a body oscillator; the hitch and the drawbar follow from rigid
//! car and trailer bodies. Geometry roughly that of the thesis's car and trailer;
//! frequencies and damping ratios are plausible round numbers, not identified values.
//! The scene it takes is a road file (`roads/*.toml`).

use std::collections::BTreeMap;
use std::path::Path;

use crate::road::Road;

use super::{SimChannels, Simulator};

/// Output rate [Hz] and integration steps per output sample.
const RATE_HZ: f64 = 2000.0;
const SUBSTEPS: usize = 5;
/// Contact length over which the road height is averaged [m].
const CONTACT_M: f64 = 0.2;
/// Lateral position of the left track [m].
const TRACK_Y_M: f64 = 0.7;

/// The analytic stand-in (see the module text).
#[derive(Clone, Debug)]
pub struct StandInSimulator {
    pub wheelbase_m: f64,
    /// Rear axle to hitch ball [m].
    pub rear_overhang_m: f64,
    /// Hitch ball to trailer axle [m].
    pub drawbar_to_axle_m: f64,
    /// Hitch ball to the drawbar sensor [m].
    pub drawbar_sensor_m: f64,
}

impl Default for StandInSimulator {
    fn default() -> Self {
        StandInSimulator {
            wheelbase_m: 2.46,
            rear_overhang_m: 0.85,
            drawbar_to_axle_m: 2.2,
            drawbar_sensor_m: 1.0,
        }
    }
}

/// (natural frequency [Hz], damping ratio) of a stage.
type Stage = (f64, f64);

const WHEEL_FRONT: Stage = (12.0, 0.25);
const WHEEL_REAR: Stage = (13.0, 0.25);
const BODY_FRONT: Stage = (1.4, 0.30);
const BODY_REAR: Stage = (1.6, 0.30);
const WHEEL_TRAILER: Stage = (14.0, 0.20);

/// The trailer body stage per load case: a heavier trailer rides lower in frequency.
fn trailer_body(load: &str) -> Result<Stage, String> {
    match load {
        "empty" => Ok((2.4, 0.20)),
        "200kg_over_axle" => Ok((1.7, 0.14)),
        "200kg_ahead_of_axle" => Ok((1.8, 0.15)),
        "200kg_behind_axle" => Ok((1.6, 0.13)),
        _ => Err(format!("stand-in: unknown load case `{load}`")),
    }
}

/// Base-excited oscillator: acceleration of the mass for base (u, u') and state (z, z').
fn accel(s: Stage, u: f64, du: f64, z: f64, dz: f64) -> f64 {
    let w = 2.0 * std::f64::consts::PI * s.0;
    w * w * (u - z) + 2.0 * s.1 * w * (du - dz)
}

impl StandInSimulator {
    /// Road height averaged over the contact length, and its rate of change along x.
    fn contact(road: &Road, x: f64) -> (f64, f64) {
        let n = 10;
        let h = CONTACT_M / n as f64;
        let mut sum = 0.0;
        for i in 0..=n {
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            sum += w * road.height(x - 0.5 * CONTACT_M + i as f64 * h, TRACK_Y_M);
        }
        let slope = (road.height(x + 0.5 * CONTACT_M, TRACK_Y_M)
            - road.height(x - 0.5 * CONTACT_M, TRACK_Y_M))
            / CONTACT_M;
        (sum * h / 3.0 / CONTACT_M, slope)
    }
}

impl Simulator for StandInSimulator {
    fn name(&self) -> String {
        "analytic stand-in (not the vehicle model)".into()
    }

    fn simulate(
        &self,
        scene: &Path,
        speed_mps: f64,
        load_case: &str,
    ) -> Result<SimChannels, String> {
        if speed_mps.is_nan() || speed_mps <= 0.0 {
            return Err(format!("speed must be positive, got {speed_mps}"));
        }
        let road = Road::from_file(scene)
            .map_err(|e| format!("stand-in needs a road file as scene: {e}"))?;
        let base = road.height(-1e3, TRACK_Y_M);
        let mut kinks = Vec::new();
        road.kinks_along([0.0, TRACK_Y_M], [1.0, 0.0], -1e3, 1e3, &mut kinks);
        let (Some(&start), Some(&end)) = (kinks.first(), kinks.last()) else {
            return Err(format!("stand-in: no obstacle on {}", road.describe()));
        };
        let trailer = trailer_body(load_case)?;
        let rear = self.wheelbase_m;
        let axle_t = rear + self.rear_overhang_m + self.drawbar_to_axle_m;
        let x0 = start - (0.6 * speed_mps).max(1.0);
        let t_end = (end + axle_t + CONTACT_M - x0) / speed_mps + 2.0;
        // Stages: 0 front wheel, 1 front body, 2 rear wheel, 3 rear body, 4 trailer
        // wheel, 5 trailer body; state [z, z'] each, relative to the flat road height.
        let stages = [
            WHEEL_FRONT,
            BODY_FRONT,
            WHEEL_REAR,
            BODY_REAR,
            WHEEL_TRAILER,
            trailer,
        ];
        let offsets = [0.0, rear, axle_t];
        let rhs = |t: f64, y: &[f64; 12]| -> [f64; 12] {
            let mut d = [0.0; 12];
            for a in 0..3 {
                let (u, slope) = Self::contact(&road, x0 + speed_mps * t - offsets[a]);
                let (w, b) = (2 * a, 2 * a + 1);
                let aw = accel(
                    stages[w],
                    u - base,
                    slope * speed_mps,
                    y[2 * w],
                    y[2 * w + 1],
                );
                let ab = accel(stages[b], y[2 * w], y[2 * w + 1], y[2 * b], y[2 * b + 1]);
                d[2 * w] = y[2 * w + 1];
                d[2 * w + 1] = aw;
                d[2 * b] = y[2 * b + 1];
                d[2 * b + 1] = ab;
            }
            d
        };
        let h = 1.0 / (RATE_HZ * SUBSTEPS as f64);
        let n_out = (t_end * RATE_HZ).ceil() as usize + 1;
        let mut y = [0.0; 12];
        let names = [
            "acc_wheel_front_left_z",
            "acc_body_front_left_z",
            "acc_wheel_rear_left_z",
            "acc_body_rear_left_z",
            "acc_hitch_z",
            "acc_trailer_drawbar_z",
        ];
        let mut out: Vec<Vec<f64>> = vec![Vec::with_capacity(n_out); names.len()];
        let mut time = Vec::with_capacity(n_out);
        let lever_h = self.rear_overhang_m / self.wheelbase_m;
        let lever_d = self.drawbar_sensor_m / self.drawbar_to_axle_m;
        for k in 0..n_out {
            let t = k as f64 / RATE_HZ;
            let d = rhs(t, &y);
            // Rigid car: the hitch extrapolates the two body points; rigid trailer: the
            // drawbar sensor interpolates between the hitch and the trailer body.
            let hitch = d[7] + (d[7] - d[3]) * lever_h;
            let drawbar = hitch + (d[11] - hitch) * lever_d;
            for (o, v) in out.iter_mut().zip([d[1], d[3], d[5], d[7], hitch, drawbar]) {
                o.push(v);
            }
            time.push(t);
            for s in 0..SUBSTEPS {
                let ts = t + s as f64 * h;
                let k1 = rhs(ts, &y);
                let k2 = rhs(
                    ts + 0.5 * h,
                    &std::array::from_fn(|i| y[i] + 0.5 * h * k1[i]),
                );
                let k3 = rhs(
                    ts + 0.5 * h,
                    &std::array::from_fn(|i| y[i] + 0.5 * h * k2[i]),
                );
                let k4 = rhs(ts + h, &std::array::from_fn(|i| y[i] + h * k3[i]));
                y = std::array::from_fn(|i| {
                    y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
                });
            }
        }
        Ok(SimChannels {
            time_s: time,
            channels: names
                .iter()
                .map(|n| n.to_string())
                .zip(out)
                .collect::<BTreeMap<_, _>>(),
            obstacle_time_s: (start - x0) / speed_mps,
        })
    }
}
