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
        // The speed error's integral, the driveline shaft's spin if it has inertia, the
        // bristles of its brakes and drag.
        let n = super::control::ControlStates::of(c).n;
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

    /// Adds a force and a torque (world axes) at marker `mk` to the generalised forces
    /// `f`; nothing on the ground.
    pub(super) fn add_load(
        &self,
        q: &[f64],
        f: &mut [f64],
        mk: MarkerHandle,
        force: [f64; 3],
        torque: [f64; 3],
    ) {
        let Some(b) = self.body_of(mk) else {
            return;
        };
        let ff = self.flex_frame(q, mk);
        for (c, g) in ff.generalised(&force, &torque).into_iter().enumerate() {
            f[self.vo[b] + c] += g;
        }
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
                self.add_load(q, f, te.marker, hub.force.into(), hub.torque.into());
            }
            ExtKind::Control(k) => self.control_eval(k, t, q, v, x, xd, res, f),
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
                    x[e.off..e.off + e.n].copy_from_slice(&self.control_initial(k, q, v, z0));
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
            ExtKind::Control(k) => self.control_state_name(k, i),
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
