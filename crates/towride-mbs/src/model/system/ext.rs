//! Extension elements: force elements with states of their own, appended after the
//! multipliers. Tyres (rigid ring or point follower, see [`crate::tyre`]) load the rim at
//! the wheel centre; a speed controller integrates the speed error and drives the wheels
//! against their carriers.
//!
//! Their iteration-matrix entries come from finite differences over the few unknowns
//! each touches (`jacobian.rs`): the tyre's contact geometry (tandem cams on the road) is
//! not worth differentiating by hand, and the blocks are small.

use nalgebra::{Matrix3, Vector3};

use super::System;
use crate::model::desc::{MarkerHandle, Model, TyreHandle};
use crate::tyre::WheelKinematics;
use towride_solver::problem::VarKind;

/// What an extension element is: its states follow their own equations beside the
/// bodies'.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExtKind {
    /// A tyre.
    Tyre(TyreHandle),
    /// Index into `Model::controls`.
    Control(usize),
}

/// An extension element and the place of its states in the extension block.
#[derive(Clone, Debug)]
pub struct Ext {
    /// Tyre or controller, with its index.
    pub kind: ExtKind,
    /// Offset of its first state in the extension block.
    pub off: usize,
    /// Number of its states.
    pub n: usize,
}

/// Extension elements of a model and their total number of states.
pub fn layout(model: &Model) -> (Vec<Ext>, usize) {
    let mut out = Vec::new();
    let mut off = 0;
    for (k, t) in model.each_tyre() {
        let n = t.tyre.n_states();
        out.push(Ext {
            kind: ExtKind::Tyre(k),
            off,
            n,
        });
        off += n;
    }
    for (k, c) in model.controls.iter().enumerate() {
        // The speed error's integral, and the driveline shaft's spin if it has inertia.
        let n = 1 + usize::from(c.driveline.is_some());
        out.push(Ext {
            kind: ExtKind::Control(k),
            off,
            n,
        });
        off += n;
    }
    (out, off)
}

impl System {
    /// Motion of the wheel marker `k` as a tyre sees it.
    pub fn wheel_kinematics(&self, q: &[f64], v: &[f64], k: MarkerHandle) -> WheelKinematics {
        let ff = self.flex_frame(q, k);
        let b = self.body_of(k).expect("wheel marker on a body");
        let (vo, w) = ff.rates(&v[self.vo[b]..self.vo[b] + 6 + self.nm[b]]);
        let a = ff.axes;
        WheelKinematics {
            position: Vector3::from(ff.origin),
            rotation: Matrix3::from_fn(|r, c| a[r][c]),
            velocity: Vector3::from(vo),
            omega: Vector3::from(w),
        }
    }

    /// Bodies whose unknowns extension element `e` reads or loads.
    pub fn ext_bodies(&self, e: &Ext) -> Vec<usize> {
        let mut out: Vec<usize> = match e.kind {
            ExtKind::Tyre(k) => self
                .body_of(self.model.tyres[k].marker)
                .into_iter()
                .collect(),
            ExtKind::Control(k) => {
                let c = &self.model.controls[k];
                let braked = c.brakes.iter().flat_map(|b| &b.wheels);
                std::iter::once(c.sensor)
                    .chain(c.wheels.iter().flat_map(|&(a, b)| [a, b]))
                    .chain(braked.flat_map(|&(a, b, _)| [a, b]))
                    .filter_map(|mk| self.body_of(mk))
                    .collect()
            }
        };
        out.sort_unstable();
        out.dedup();
        out
    }

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

    /// How controller `k` meets a `demand` [N m]: (engine, brake) totals. Without brakes
    /// the engine takes it all, either sign (the thesis's engine). With brakes the engine
    /// takes down to its drag and the brakes the rest (brake <= 0). Saturations and the
    /// hand-over are smooth so the residual stays differentiable.
    pub fn control_split(&self, k: usize, demand: f64) -> (f64, f64) {
        let c = &self.model.controls[k];
        let saturate = |x: f64, limit: f64| limit * (x / limit).tanh();
        match &c.brakes {
            None => (saturate(demand, c.max_torque), 0.0),
            // Exact below 80 % of the limits, so a manoeuvre gets the torque it asks
            // (tanh alone gives 90 % of a demand at half the limit).
            Some(b) => {
                let brake = smooth_min0(demand + b.engine_drag, b.blend);
                (
                    soft_clip(demand - brake, c.max_torque),
                    soft_clip(brake, b.max_torque),
                )
            }
        }
    }

    /// Spin rate of wheel marker `wheel` relative to marker `carrier`, about the wheel
    /// marker's y axis [rad/s].
    fn relative_spin(
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

    /// Adds one extension element's loads to `f` and writes its residual `res` (its own
    /// states `x`, rates `xd`).
    #[allow(clippy::too_many_arguments)]
    pub fn ext_eval(
        &self,
        e: &Ext,
        t: f64,
        q: &[f64],
        v: &[f64],
        x: &[f64],
        xd: &[f64],
        res: &mut [f64],
        f: &mut [f64],
    ) {
        let mut add = |mk: MarkerHandle, force: [f64; 3], torque: [f64; 3]| {
            let Some(b) = self.body_of(mk) else {
                return;
            };
            let ff = self.flex_frame(q, mk);
            for (c, g) in ff.generalised(&force, &torque).into_iter().enumerate() {
                f[self.vo[b] + c] += g;
            }
        };
        match e.kind {
            ExtKind::Tyre(k) => {
                let te = &self.model.tyres[k];
                let road = self
                    .model
                    .road
                    .as_ref()
                    .expect("validated: tyres need a road");
                let kin = self.wheel_kinematics(q, v, te.marker);
                let hub = te.tyre.residual(t, &kin, road, x, xd, res);
                add(te.marker, hub.force.into(), hub.torque.into());
            }
            ExtKind::Control(k) => {
                let c = &self.model.controls[k];
                let speed = self.control_speed(k, q, v);
                let err = if self.controls_active.get() {
                    c.target.eval(t).0 - speed
                } else {
                    0.0
                };
                res[0] = xd[0] - err;
                let demand = self.control_demand(k, t, speed, x[0]);
                let (engine, brake) = self.control_split(k, demand);
                let mut spin_torque = |wm: MarkerHandle, cm: MarkerHandle, tq: f64| {
                    let a = self.marker_frame(q, wm).axes;
                    let spin = [a[0][1] * tq, a[1][1] * tq, a[2][1] * tq];
                    add(wm, [0.0; 3], spin);
                    add(cm, [0.0; 3], spin.map(|s| -s));
                };
                let n = c.wheels.len().max(1) as f64;
                // Friction (the engine's drag, the brakes) opposes each wheel's spin on its
                // carrier, whichever way it turns, and vanishes with it (tanh over
                // `release_rad_s`): a stopped car is not driven backwards by its brakes.
                // The engine pushes; a pull beyond `blend` is drag (weight w: 1 -> 0).
                let engine_share = |spin: &dyn Fn() -> f64| match &c.brakes {
                    None => 1.0,
                    Some(b) => {
                        let w = smooth_step01((engine + b.blend) / b.blend);
                        if w == 1.0 {
                            1.0
                        } else {
                            w + (1.0 - w) * (spin() / b.release_rad_s).tanh()
                        }
                    }
                };
                match &c.driveline {
                    None => {
                        for &(wm, cm) in &c.wheels {
                            let slip = engine_share(&|| self.relative_spin(q, v, wm, cm));
                            spin_torque(wm, cm, engine / n * slip);
                        }
                    }
                    Some(d) => {
                        // The engine turns the shaft (spin x[1]); the stiff coupling gears
                        // it to the wheels' mean spin and splits its torque equally.
                        let shaft = x[1];
                        let coupled = d.coupling * (shaft - self.driven_mean_spin(k, q, v));
                        let drive = engine * engine_share(&|| shaft);
                        res[1] = d.inertia * xd[1] - (drive - coupled);
                        for &(wm, cm) in &c.wheels {
                            spin_torque(wm, cm, coupled / n);
                        }
                    }
                }
                if let Some(b) = &c.brakes {
                    for &(wm, cm, share) in &b.wheels {
                        let slip = (self.relative_spin(q, v, wm, cm) / b.release_rad_s).tanh();
                        spin_torque(wm, cm, brake * share * slip);
                    }
                }
            }
        }
    }

    /// Loads and residuals of all extension elements.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn ext_loads(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        x: &[f64],
        xd: &[f64],
        res: &mut [f64],
        f: &mut [f64],
    ) {
        for e in &self.ext {
            let r = e.off..e.off + e.n;
            self.ext_eval(e, t, q, v, &x[r.clone()], &xd[r.clone()], &mut res[r], f);
        }
    }

    pub(super) fn ext_var_kinds(&self) -> Vec<VarKind> {
        let mut out = Vec::with_capacity(self.ne);
        for e in &self.ext {
            match e.kind {
                ExtKind::Tyre(k) => out.extend(self.model.tyres[k].tyre.var_kinds()),
                ExtKind::Control(_) => out.extend(std::iter::repeat_n(VarKind::Differential, e.n)),
            }
        }
        out
    }

    /// Initial extension states for a state (q, v): tyres in steady state for their
    /// wheel's motion, controller integrators at `z0` [m], driveline shafts turning with
    /// their wheels.
    pub fn ext_initial(&self, q: &[f64], v: &[f64], z0: f64) -> Vec<f64> {
        let mut x = vec![0.0; self.ne];
        for e in &self.ext {
            match e.kind {
                ExtKind::Tyre(k) => {
                    let te = &self.model.tyres[k];
                    let road = self.model.road.as_ref().expect("tyres need a road");
                    let kin = self.wheel_kinematics(q, v, te.marker);
                    x[e.off..e.off + e.n].copy_from_slice(&te.tyre.initial_state(&kin, road));
                }
                ExtKind::Control(k) => {
                    x[e.off] = z0;
                    if e.n > 1 {
                        x[e.off + 1] = self.driven_mean_spin(k, q, v);
                    }
                }
            }
        }
        x
    }

    /// Name of extension element `e` and of its state `i`.
    pub fn ext_state_name(&self, e: &Ext, i: usize) -> String {
        match e.kind {
            ExtKind::Tyre(k) => {
                let te = &self.model.tyres[k];
                format!("tyre '{}' {}", te.name, te.tyre.state_names()[i])
            }
            ExtKind::Control(k) if i == 0 => format!(
                "speed control '{}' integral of the speed error [m]",
                self.model.controls[k].name
            ),
            ExtKind::Control(k) => format!(
                "speed control '{}' driveline spin at the wheels [rad/s]",
                self.model.controls[k].name
            ),
        }
    }

    /// The extension element owning state `i` of the extension block.
    pub fn ext_of(&self, i: usize) -> Option<(&Ext, usize)> {
        self.ext
            .iter()
            .find(|e| (e.off..e.off + e.n).contains(&i))
            .map(|e| (e, i - e.off))
    }

    /// Suggested absolute tolerances of the extension states (tyres' own hints, 1e-4 m
    /// for controller integrators, 1e-4 rad/s for driveline spins as for the bodies'
    /// velocities).
    pub fn ext_atol(&self, scale: f64) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.ne);
        for e in &self.ext {
            match e.kind {
                ExtKind::Tyre(k) => out.extend(self.model.tyres[k].tyre.atol(scale)),
                ExtKind::Control(_) => out.extend(std::iter::repeat_n(1e-4 * scale, e.n)),
            }
        }
        out
    }

    /// Step limit from the road: where a tyre has an obstacle within its reach or within
    /// `look_s` seconds of travel ahead, a tenth of the tyre's ring period (so no step
    /// jumps over an edge unseen); on flat road `look_s` itself, so the next check comes
    /// before the wheel can reach anything.
    pub fn road_step_limit(&self, q: &[f64], v: &[f64], look_s: f64) -> Option<f64> {
        let road = self.model.road.as_ref()?;
        let mut lim: Option<f64> = None;
        for te in &self.model.tyres {
            let kin = self.wheel_kinematics(q, v, te.marker);
            let (x, y) = (kin.position.x, kin.position.y);
            let travel = kin.velocity.x.abs() * look_s;
            let (a, b) = te.tyre.reach(x);
            let near = 0.1 / te.tyre.params().freq_long;
            let h = match road.flat_height(a - travel, b + travel, y - 0.2, y + 0.2) {
                Some(_) => look_s.max(near),
                None => near,
            };
            lim = Some(lim.map_or(h, |l: f64| l.min(h)));
        }
        lim
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
