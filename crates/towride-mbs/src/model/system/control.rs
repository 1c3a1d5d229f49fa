//! The speed controller as an extension element: its states (the speed error's
//! integral, the driveline shaft's spin, the stick-slip bristles of the brakes and the
//! engine's drag), its residuals and the torques it puts on the driven and braked wheels
//! and their carriers. docs/manoeuvres.md describes the controller; the friction law is
//! in [`crate::model::stick`].

use super::System;
use crate::model::desc::{MarkerHandle, SpeedControl};

/// Where controller `c`'s states sit in its block: the speed error's integral at 0, the
/// shaft's spin at 1 if it has a driveline, then one bristle per braked wheel and one per
/// drag contact (the shaft, or each driven wheel without one). Brakeless controllers have
/// no bristles: their engine is a torque source.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ControlStates {
    /// Offset of the first brake bristle.
    pub brakes: usize,
    /// Offset of the first drag bristle.
    pub drag: usize,
    /// Number of drag contacts.
    pub n_drag: usize,
    /// Number of states in all.
    pub n: usize,
}

impl ControlStates {
    /// The layout of `c`'s states.
    pub fn of(c: &SpeedControl) -> ControlStates {
        let brakes = 1 + usize::from(c.driveline.is_some());
        let (nb, n_drag) = match &c.brakes {
            None => (0, 0),
            Some(b) if c.driveline.is_some() => (b.wheels.len(), 1),
            Some(b) => (b.wheels.len(), c.wheels.len()),
        };
        ControlStates {
            brakes,
            drag: brakes + nb,
            n_drag,
            n: brakes + nb + n_drag,
        }
    }
}

impl System {
    /// Forward speed of a controller's sensor marker [m/s].
    pub fn control_speed(&self, k: usize, q: &[f64], v: &[f64]) -> f64 {
        let c = &self.model.controls[k];
        let ff = self.flex_frame(q, c.sensor);
        let b = self.body_of(c.sensor).expect("sensor on a body");
        let (vo, _) = ff.rates(&v[self.vo[b]..self.vo[b] + 6 + self.nm[b]]);
        let x = [ff.axes[0][0], ff.axes[1][0], ff.axes[2][0]];
        vo[0] * x[0] + vo[1] * x[1] + vo[2] * x[2]
    }

    /// Total torque controller `k` asks at `speed` with speed-error integral `z` [N m]:
    /// feed-forward on the target's rate plus PI on the speed error.
    pub fn control_demand(&self, k: usize, t: f64, speed: f64, z: f64) -> f64 {
        let c = &self.model.controls[k];
        if !self.controls_active.get() {
            return 0.0;
        }
        let (target, rate, _) = c.target.eval(t);
        c.feedforward_kg_m * rate + c.kp * (target - speed) + c.ki * z
    }

    /// How controller `k` meets a `demand` at time `t` [N m]: (engine, brake) totals.
    /// Without brakes the engine takes it all, either sign (the thesis's engine). With
    /// brakes the engine takes down to its drag and the brakes the rest (brake <= 0), plus
    /// the driver's hold at a stopped target. Saturations and the hand-over are smooth so
    /// the residual stays differentiable.
    pub fn control_split(&self, k: usize, t: f64, demand: f64) -> (f64, f64) {
        let c = &self.model.controls[k];
        let saturate = |x: f64, limit: f64| limit * (x / limit).tanh();
        match &c.brakes {
            None => (saturate(demand, c.max_torque), 0.0),
            // Exact below 80 % of the limits, so a manoeuvre gets the torque it asks
            // (tanh alone gives 90 % of a demand at half the limit).
            Some(b) => {
                // A stopped target: the driver takes the foot off the throttle and keeps
                // the brakes on (the hold, in full at zero target speed).
                let h = self.hold_weight(k, t);
                let demand = demand * (1.0 - h);
                let brake = smooth_min0(demand + b.engine_drag, b.blend);
                let held = soft_clip(brake - b.hold_torque * h, b.max_torque);
                (soft_clip(demand - brake, c.max_torque), held)
            }
        }
    }

    /// How far controller `k`'s hold is in at `t`: 0 while the target speed is above its
    /// brakes' `hold_speed`, rising smoothly to 1 at a zero target; 0 without brakes or
    /// without a hold.
    pub fn hold_weight(&self, k: usize, t: f64) -> f64 {
        let c = &self.model.controls[k];
        match &c.brakes {
            Some(b) if self.controls_active.get() && b.hold_torque > 0.0 => {
                let target = c.target.eval(t).0.max(0.0);
                1.0 - smooth_step01(target / b.hold_speed)
            }
            _ => 0.0,
        }
    }

    /// Spin rate of wheel marker `wheel` relative to marker `carrier`, about the wheel
    /// marker's y axis [rad/s].
    pub(super) fn relative_spin(
        &self,
        q: &[f64],
        v: &[f64],
        wheel: MarkerHandle,
        carrier: MarkerHandle,
    ) -> f64 {
        let omega = |mk: MarkerHandle| -> [f64; 3] {
            match self.body_of(mk) {
                Some(b) => {
                    let ff = self.flex_frame(q, mk);
                    ff.rates(&v[self.vo[b]..self.vo[b] + 6 + self.nm[b]]).1
                }
                None => [0.0; 3],
            }
        };
        let (w, c) = (omega(wheel), omega(carrier));
        let a = self.marker_frame(q, wheel).axes;
        (0..3).map(|r| (w[r] - c[r]) * a[r][1]).sum()
    }

    /// Mean spin of controller `k`'s driven wheels on their carriers: what an open
    /// differential gears to the engine [rad/s].
    pub fn driven_mean_spin(&self, k: usize, q: &[f64], v: &[f64]) -> f64 {
        let c = &self.model.controls[k];
        let n = c.wheels.len().max(1) as f64;
        c.wheels
            .iter()
            .map(|&(wm, cm)| self.relative_spin(q, v, wm, cm))
            .sum::<f64>()
            / n
    }

    /// Controller `k`'s residuals `res` (its states `x`, rates `xd`) and its torques on
    /// the wheels and carriers, added to `f`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn control_eval(
        &self,
        k: usize,
        t: f64,
        q: &[f64],
        v: &[f64],
        x: &[f64],
        xd: &[f64],
        res: &mut [f64],
        f: &mut [f64],
    ) {
        let c = &self.model.controls[k];
        let lay = ControlStates::of(c);
        let speed = self.control_speed(k, q, v);
        let err = if self.controls_active.get() {
            c.target.eval(t).0 - speed
        } else {
            0.0
        };
        // The integral rests while the brakes hold (no wind-up against them).
        res[0] = xd[0] - err * (1.0 - self.hold_weight(k, t));
        let demand = self.control_demand(k, t, speed, x[0]);
        let (engine, brake) = self.control_split(k, t, demand);
        let spin_torque = |f: &mut [f64], wm: MarkerHandle, cm: MarkerHandle, tq: f64| {
            let a = self.marker_frame(q, wm).axes;
            let spin = [a[0][1] * tq, a[1][1] * tq, a[2][1] * tq];
            self.add_load(q, f, wm, [0.0; 3], spin);
            self.add_load(q, f, cm, [0.0; 3], spin.map(|s| -s));
        };
        let n = c.wheels.len().max(1) as f64;
        // Friction (the engine's drag, the brakes) is a stick-slip bristle on each
        // contact: it holds a part at rest below the capacity and slips at it, and its
        // torque vanishes with the capacity. Each bristle's state follows its law here.
        // The engine pushes; a pull beyond `blend` is drag (weight w: 1 -> 0).
        let engine_share = |res: &mut [f64], i: usize, spin: f64| match &c.brakes {
            None => 1.0,
            Some(b) => {
                let j = lay.drag + i;
                res[j] = xd[j] - b.stick.rate(x[j], spin);
                let w = smooth_step01((engine + b.blend) / b.blend);
                if w == 1.0 {
                    1.0
                } else {
                    w + (1.0 - w) * b.stick.per_capacity(x[j], spin)
                }
            }
        };
        match &c.driveline {
            None => {
                for (i, &(wm, cm)) in c.wheels.iter().enumerate() {
                    let slip = engine_share(res, i, self.relative_spin(q, v, wm, cm));
                    spin_torque(f, wm, cm, engine / n * slip);
                }
            }
            Some(d) => {
                // The engine turns the shaft (spin x[1]); the stiff coupling gears it to
                // the wheels' mean spin and splits its torque equally.
                let shaft = x[1];
                let coupled = d.coupling * (shaft - self.driven_mean_spin(k, q, v));
                let drive = engine * engine_share(res, 0, shaft);
                res[1] = d.inertia * xd[1] - (drive - coupled);
                for &(wm, cm) in &c.wheels {
                    spin_torque(f, wm, cm, coupled / n);
                }
            }
        }
        if let Some(b) = &c.brakes {
            for (i, &(wm, cm, share)) in b.wheels.iter().enumerate() {
                let j = lay.brakes + i;
                let spin = self.relative_spin(q, v, wm, cm);
                res[j] = xd[j] - b.stick.rate(x[j], spin);
                spin_torque(f, wm, cm, brake * share * b.stick.per_capacity(x[j], spin));
            }
        }
    }

    /// Controller `k`'s initial states for (q, v): the integral at `z0` [m], the shaft
    /// turning with its wheels, each bristle slipping if its part turns, else unloaded.
    pub(super) fn control_initial(&self, k: usize, q: &[f64], v: &[f64], z0: f64) -> Vec<f64> {
        let c = &self.model.controls[k];
        let lay = ControlStates::of(c);
        let mut x = vec![0.0; lay.n];
        x[0] = z0;
        if c.driveline.is_some() {
            x[1] = self.driven_mean_spin(k, q, v);
        }
        if let Some(b) = &c.brakes {
            for (i, &(wm, cm, _)) in b.wheels.iter().enumerate() {
                x[lay.brakes + i] = b.stick.initial(self.relative_spin(q, v, wm, cm));
            }
            for i in 0..lay.n_drag {
                let spin = match c.driveline {
                    Some(_) => x[1],
                    None => self.relative_spin(q, v, c.wheels[i].0, c.wheels[i].1),
                };
                x[lay.drag + i] = b.stick.initial(spin);
            }
        }
        x
    }

    /// Name of controller `k`'s state `i`.
    pub(super) fn control_state_name(&self, k: usize, i: usize) -> String {
        let c = &self.model.controls[k];
        let lay = ControlStates::of(c);
        let name = &c.name;
        if i == 0 {
            format!("speed control '{name}' integral of the speed error [m]")
        } else if i < lay.brakes {
            format!("speed control '{name}' driveline spin at the wheels [rad/s]")
        } else if i < lay.drag {
            format!(
                "speed control '{name}' brake {} bristle deflection per breakaway deflection [-]",
                i - lay.brakes + 1
            )
        } else {
            format!(
                "speed control '{name}' engine drag {} bristle deflection per breakaway deflection [-]",
                i - lay.drag + 1
            )
        }
    }
}

/// min(x, 0) with the corner rounded by a parabola over [-w/2, w/2]: C1, and exactly 0
/// from w/2 up, so a controller that never asks for the brakes is not changed by them.
fn smooth_min0(x: f64, w: f64) -> f64 {
    if x >= 0.5 * w {
        0.0
    } else if x <= -0.5 * w {
        x
    } else {
        -(x - 0.5 * w).powi(2) / (2.0 * w)
    }
}

/// 0 below 0, 1 above 1, 3 s^2 - 2 s^3 between (C1).
fn smooth_step01(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// x up to 80 % of `limit` in magnitude, then bending smoothly (C1) towards the limit.
fn soft_clip(x: f64, limit: f64) -> f64 {
    let knee = 0.8 * limit;
    if x.abs() <= knee {
        x
    } else {
        let room = limit - knee;
        x.signum() * (knee + room * ((x.abs() - knee) / room).tanh())
    }
}
