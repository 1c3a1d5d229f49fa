//! Tyre test rigs as DAE problems for the crate's BDF solver.
//!
//! - [`CleatRig`]: the wheel centre moves at constant speed and constant height over the
//!   road (a drum or flat-plank cleat test); the rim spins freely on its bearing with the
//!   rim's inertia, or is driven at a constant spin. Unknowns: the tyre's states, then the
//!   rim spin rate.
//! - [`QuarterRig`]: the wheel centre has a vertical degree of freedom carrying a mass
//!   under gravity (wheel plus the load on it), optionally a guide damper to ground; it
//!   moves forward at constant speed and spins freely. Unknowns: the tyre's states, then
//!   the wheel centre height, its vertical velocity and the rim spin rate.
//!
//! - [`crate::tyre::rig_lateral::LateralRig`]: side slip at a set slip angle (its own
//!   module).
//!
//! The solver builds the iteration matrix by finite differences (the systems have 3 to
//! 12 unknowns, below the dense limit). A rig file (TOML, `rig_file.rs`, read with
//! [`crate::input::Source`]) names the tyre, the road and the rig; see
//! `docs/road_tyre.md` and `scenes/tyre_rigs/`.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::road::Road;
use towride_solver::consistent_index1;
use towride_solver::DaeMethod;
use towride_solver::{Advance, Bdf, DaeProblem, SolverError, SolverOptions, Stats, VarKind};

use super::{Tyre, WheelKinematics};

/// How the rim of the cleat rig turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Spin {
    /// Free on its bearing, with the rim's inertia.
    Free,
    /// Held at the free-rolling spin rate of the flat road.
    Driven,
}

/// Wheel centre at constant speed and height; rim free or driven.
pub struct CleatRig {
    /// The tyre under test.
    pub tyre: Tyre,
    /// The road it rolls on.
    pub road: Road,
    /// Forward speed of the wheel centre [m/s].
    pub speed: f64,
    /// Wheel-centre x at t = 0 [m].
    pub x0: f64,
    /// Wheel-centre height [m], set so that the tyre carries the rig's load at `x0`.
    pub z_axle: f64,
    /// Free or driven rim.
    pub spin: Spin,
    /// Spin inertia of everything that turns with the rim [kg m^2].
    pub rim_iyy: f64,
    /// Initial spin as a multiple of the free-rolling spin (1 = steady free rolling; other
    /// values start the rim slipping, to watch it settle).
    pub initial_spin_factor: f64,
    n: usize,
}

impl CleatRig {
    /// Sets the axle height so that the tyre carries `load` [N] on the road at `x0`.
    pub fn new(
        tyre: Tyre,
        road: Road,
        speed: f64,
        x0: f64,
        load: f64,
        spin: Spin,
        rim_iyy: f64,
    ) -> CleatRig {
        let n = tyre.n_states();
        let mut rig = CleatRig {
            tyre,
            road,
            speed,
            x0,
            z_axle: 0.0,
            spin,
            rim_iyy,
            initial_spin_factor: 1.0,
            n,
        };
        rig.z_axle = height_for_load(&rig.tyre, &rig.road, x0, speed, load);
        rig
    }

    fn kin(&self, t: f64, omega: f64) -> WheelKinematics {
        WheelKinematics::upright(
            Vector3::new(self.x0 + self.speed * t, 0.0, self.z_axle),
            Vector3::new(self.speed, 0.0, 0.0),
            omega,
        )
    }

    /// Consistent initial values: the tyre rolling freely on the road at `x0`.
    pub fn initial(&self) -> (Vec<f64>, Vec<f64>) {
        let omega = self.initial_spin_factor
            * free_rolling_spin(
                &self.tyre,
                &self.road,
                self.x0,
                self.z_axle,
                self.speed,
                0.0,
            );
        let mut y = self.tyre.initial_state(&self.kin(0.0, omega), &self.road);
        y.push(omega);
        let yp = vec![0.0; y.len()];
        (y, yp)
    }
}

/// The DAE of a rig whose rim moves on a prescribed path and spins free or driven: the
/// tyre's equations and, last, the rim's spin (its moment balance, or a held speed). The
/// rig type needs fields `n`, `tyre`, `road`, `spin`, `rim_iyy` and a method
/// `kin(t, omega) -> WheelKinematics`.
macro_rules! spinning_rig_dae {
    ($rig:ty) => {
        impl towride_solver::DaeProblem for $rig {
            fn size(&self) -> usize {
                self.n + 1
            }

            fn residual(&self, t: f64, y: &[f64], yp: &[f64], res: &mut [f64]) {
                let n = self.n;
                let kin = self.kin(t, y[n]);
                let hub = self
                    .tyre
                    .residual(t, &kin, &self.road, &y[..n], &yp[..n], &mut res[..n]);
                res[n] = match self.spin {
                    $crate::tyre::rig::Spin::Free => {
                        (self.rim_iyy * yp[n] - hub.torque.y) / self.rim_iyy
                    }
                    $crate::tyre::rig::Spin::Driven => yp[n],
                };
            }

            fn var_kinds(&self) -> Vec<towride_solver::VarKind> {
                let mut k = self.tyre.var_kinds();
                k.push(towride_solver::VarKind::Differential);
                k
            }

            fn var_name(&self, i: usize) -> String {
                if i < self.n {
                    self.tyre.state_names()[i].clone()
                } else {
                    "rim_omega_rad_s".into()
                }
            }
        }
    };
}
pub(crate) use spinning_rig_dae;

spinning_rig_dae!(CleatRig);

/// Wheel with a vertical degree of freedom, constant forward speed, free spin.
pub struct QuarterRig {
    /// The tyre under test.
    pub tyre: Tyre,
    /// The road it rolls on.
    pub road: Road,
    /// Forward speed of the wheel centre [m/s].
    pub speed: f64,
    /// Wheel-centre x at t = 0 [m].
    pub x0: f64,
    /// Mass on the wheel centre (rim and load; the rigid ring's belt is in the tyre) [kg].
    pub mass: f64,
    /// Spin inertia of everything that turns with the rim [kg m^2].
    pub rim_iyy: f64,
    /// Guide damper to ground [N s/m] (a drop-test carriage's friction; 0 for none).
    pub damper: f64,
    /// Gravity along z [m/s^2] (the tyre file's GRAVITY).
    pub gravity: f64,
    n: usize,
}

impl QuarterRig {
    /// A quarter rig; gravity comes from the tyre file's GRAVITY.
    pub fn new(
        tyre: Tyre,
        road: Road,
        speed: f64,
        x0: f64,
        mass: f64,
        rim_iyy: f64,
        damper: f64,
    ) -> QuarterRig {
        let n = tyre.n_states();
        let gravity = tyre.params().gravity;
        QuarterRig {
            tyre,
            road,
            speed,
            x0,
            mass,
            rim_iyy,
            damper,
            gravity,
            n,
        }
    }

    fn kin(&self, t: f64, z: f64, vz: f64, omega: f64) -> WheelKinematics {
        WheelKinematics::upright(
            Vector3::new(self.x0 + self.speed * t, 0.0, z),
            Vector3::new(self.speed, 0.0, vz),
            omega,
        )
    }

    /// The weight the tyre carries at rest: the mass plus, for the rigid ring, the belt.
    pub fn total_weight(&self) -> f64 {
        let belt = match &self.tyre {
            Tyre::RigidRing(r) => r.p.belt_mass,
            Tyre::PointFollower(_) => 0.0,
        };
        -(self.mass + belt) * self.gravity
    }

    /// Initial values: resting in equilibrium (`drop = None`) or released at rest with the
    /// wheel centre `drop` metres above the height where the tyre first touches the road.
    pub fn initial(&self, drop: Option<f64>) -> (Vec<f64>, Vec<f64>) {
        let road_z = self.road.height(self.x0, 0.0);
        let z = match drop {
            Some(d) => road_z + self.tyre.params().r0 + d,
            None => height_for_load(
                &self.tyre,
                &self.road,
                self.x0,
                self.speed,
                self.total_weight(),
            ),
        };
        let omega = free_rolling_spin(&self.tyre, &self.road, self.x0, z, self.speed, 0.0);
        let mut y = self
            .tyre
            .initial_state(&self.kin(0.0, z, 0.0, omega), &self.road);
        y.extend([z, 0.0, omega]);
        let mut yp = vec![0.0; y.len()];
        // A dropped wheel starts in free fall.
        if drop.is_some() {
            yp[self.n] = 0.0;
            yp[self.n + 1] = self.gravity;
        }
        (y, yp)
    }
}

impl DaeProblem for QuarterRig {
    fn size(&self) -> usize {
        self.n + 3
    }

    fn residual(&self, t: f64, y: &[f64], yp: &[f64], res: &mut [f64]) {
        let n = self.n;
        let (z, vz, omega) = (y[n], y[n + 1], y[n + 2]);
        let kin = self.kin(t, z, vz, omega);
        let hub = self
            .tyre
            .residual(t, &kin, &self.road, &y[..n], &yp[..n], &mut res[..n]);
        res[n] = yp[n] - vz;
        res[n + 1] = (self.mass * yp[n + 1] - self.mass * self.gravity - hub.force.z
            + self.damper * vz)
            / self.mass;
        res[n + 2] = (self.rim_iyy * yp[n + 2] - hub.torque.y) / self.rim_iyy;
    }

    fn var_kinds(&self) -> Vec<VarKind> {
        let mut k = self.tyre.var_kinds();
        k.extend([VarKind::Differential; 3]);
        k
    }

    fn var_name(&self, i: usize) -> String {
        if i < self.n {
            self.tyre.state_names()[i].clone()
        } else {
            ["wheel_z_m", "wheel_vz_m_s", "rim_omega_rad_s"][i - self.n].into()
        }
    }
}

/// Spin rate at which the tyre rolls freely at `speed` on the road under `x0` with the
/// wheel centre at `z` (fixed point of Omega = V / R_e).
pub fn free_rolling_spin(tyre: &Tyre, road: &Road, x0: f64, z: f64, speed: f64, vz: f64) -> f64 {
    let mut omega = speed / tyre.params().r0;
    for _ in 0..30 {
        let kin = WheelKinematics::upright(
            Vector3::new(x0, 0.0, z),
            Vector3::new(speed, 0.0, vz),
            omega,
        );
        let x = tyre.initial_state(&kin, road);
        let re = tyre.outputs(&kin, road, &x).rolling_radius;
        let next = speed / re;
        if (next - omega).abs() <= 1e-13 * omega.abs().max(1.0) {
            return next;
        }
        omega = next;
    }
    omega
}

/// Wheel centre height at which the steady tyre carries the normal load `load` [N].
pub fn height_for_load(tyre: &Tyre, road: &Road, x0: f64, speed: f64, load: f64) -> f64 {
    let p = tyre.params();
    let fz = |z: f64| {
        let omega = free_rolling_spin(tyre, road, x0, z, speed, 0.0);
        let kin = WheelKinematics::upright(
            Vector3::new(x0, 0.0, z),
            Vector3::new(speed, 0.0, 0.0),
            omega,
        );
        let x = tyre.initial_state(&kin, road);
        tyre.outputs(&kin, road, &x).normal_force
    };
    // Start from the linear estimate, then secant steps.
    let mut z1 = road.height(x0, 0.0) + p.r0 - load / p.cz;
    let mut z0 = z1 + 1e-4;
    let (mut f0, mut f1) = (fz(z0) - load, fz(z1) - load);
    for _ in 0..50 {
        if f1.abs() < 1e-9 * load.abs().max(1.0) || f1 == f0 {
            break;
        }
        let z2 = z1 - f1 * (z1 - z0) / (f1 - f0);
        z0 = z1;
        f0 = f1;
        z1 = z2;
        f1 = fz(z1) - load;
    }
    z1
}

/// One output sample of a rig run.
#[derive(Clone, Debug, Serialize)]
pub struct RigSample {
    /// Time [s].
    pub t_s: f64,
    /// Wheel centre x and z [m], rim spin [rad/s].
    pub x_m: f64,
    /// Wheel-centre height [m].
    pub z_m: f64,
    /// Rim spin rate [rad/s].
    pub omega_rad_s: f64,
    /// Load on the rim (world x, z) [N] and spin torque [N m].
    pub hub_fx_n: f64,
    /// Vertical load on the rim [N].
    pub hub_fz_n: f64,
    /// Spin torque on the rim [N m].
    pub hub_my_n_m: f64,
    /// Contact forces [N], slip, radii [m], effective road [m, -].
    pub normal_force_n: f64,
    /// Longitudinal contact force [N].
    pub long_force_n: f64,
    /// Transient longitudinal slip [-].
    pub slip: f64,
    /// Effective rolling radius [m].
    pub rolling_radius_m: f64,
    /// Total tyre deflection [m].
    pub deflection_m: f64,
    /// Effective road height [m].
    pub effective_height_m: f64,
    /// Effective forward slope tan(beta) [-].
    pub effective_slope: f64,
    /// Lateral load on the rim (world y) [N] and its moment about world z [N m].
    pub hub_fy_n: f64,
    /// Moment of the load on the rim about world z [N m].
    pub hub_mz_n_m: f64,
    /// Lateral contact force F_y [N] and aligning moment M_z [N m].
    pub lateral_force_n: f64,
    /// Aligning moment M_z [N m].
    pub aligning_moment_n_m: f64,
    /// Transient slip angle alpha' [rad].
    pub slip_angle_rad: f64,
}

/// A finished rig run.
#[derive(Clone, Debug, Serialize)]
pub struct RigRun {
    /// The output samples, every `dt` from t = 0.
    pub samples: Vec<RigSample>,
    /// Solver counters.
    pub stats: Stats,
    /// Wall-clock time of the integration [s].
    pub wall_s: f64,
}

/// Integrates a rig from consistent initial values to `t_end`, sampling every `dt`.
pub(crate) fn integrate<P: DaeProblem>(
    prob: &P,
    y0: Vec<f64>,
    yp0: Vec<f64>,
    t_end: f64,
    dt: f64,
    opts: &SolverOptions,
    sample: impl Fn(f64, &[f64]) -> RigSample,
) -> Result<RigRun, SolverError> {
    let start = std::time::Instant::now();
    let (mut y, mut yp) = (y0, yp0);
    consistent_index1(prob, 0.0, &mut y, &mut yp, opts)?;
    let mut bdf = Bdf::new(prob, 0.0, &y, &yp, opts.clone())?;
    bdf.set_stop_time(t_end);
    let steps = (t_end / dt).round() as usize;
    let mut samples = Vec::with_capacity(steps + 1);
    samples.push(sample(0.0, &y));
    for k in 1..=steps {
        let tout = (k as f64 * dt).min(t_end);
        while let Advance::Root { .. } = bdf.advance(tout)? {}
        bdf.interpolate(tout, &mut y, &mut yp);
        samples.push(sample(tout, &y));
    }
    Ok(RigRun {
        samples,
        stats: bdf.stats().clone(),
        wall_s: start.elapsed().as_secs_f64(),
    })
}

pub(crate) fn sample_of(
    tyre: &Tyre,
    road: &Road,
    t: f64,
    kin: &WheelKinematics,
    x: &[f64],
) -> RigSample {
    let o = tyre.outputs(kin, road, x);
    let hub = tyre.hub_load(kin, road, x);
    RigSample {
        t_s: t,
        x_m: kin.position.x,
        z_m: kin.position.z,
        omega_rad_s: kin.omega.y,
        hub_fx_n: hub.force.x,
        hub_fz_n: hub.force.z,
        hub_my_n_m: hub.torque.y,
        normal_force_n: o.normal_force,
        long_force_n: o.longitudinal_force,
        slip: o.slip,
        rolling_radius_m: o.rolling_radius,
        deflection_m: o.deflection,
        effective_height_m: o.effective.height,
        effective_slope: o.effective.tan_slope,
        hub_fy_n: hub.force.y,
        hub_mz_n_m: hub.torque.z,
        lateral_force_n: o.lateral_force,
        aligning_moment_n_m: o.aligning_moment,
        slip_angle_rad: o.slip_angle,
    }
}

impl CleatRig {
    /// Runs the rig to `t_end` with output every `dt`.
    pub fn run(&self, t_end: f64, dt: f64, opts: &SolverOptions) -> Result<RigRun, SolverError> {
        let (y, yp) = self.initial();
        let n = self.n;
        integrate(self, y, yp, t_end, dt, opts, |t, y| {
            sample_of(&self.tyre, &self.road, t, &self.kin(t, y[n]), &y[..n])
        })
    }
}

impl QuarterRig {
    /// Runs the rig (dropped from `drop` m above first contact, or from rest in
    /// equilibrium) to `t_end` with output every `dt`.
    pub fn run(
        &self,
        drop: Option<f64>,
        t_end: f64,
        dt: f64,
        opts: &SolverOptions,
    ) -> Result<RigRun, SolverError> {
        let (y, yp) = self.initial(drop);
        let n = self.n;
        integrate(self, y, yp, t_end, dt, opts, |t, y| {
            sample_of(
                &self.tyre,
                &self.road,
                t,
                &self.kin(t, y[n], y[n + 1], y[n + 2]),
                &y[..n],
            )
        })
    }
}

/// Solver options suited to a rig: per-unknown absolute tolerances from the tyre (fixed
/// physical resolutions, so rtol alone sets the accuracy), and a largest step of a tenth
/// of the ring's period so that the step never jumps over a short obstacle unseen (the
/// integrator only learns of the road through the residual).
pub fn rig_options(tyre: &Tyre, rtol: f64, extra_atol: &[f64]) -> SolverOptions {
    let mut atol = tyre.atol(1.0);
    atol.extend_from_slice(extra_atol);
    SolverOptions {
        rtol,
        atol,
        h_max: 0.1 / tyre.params().freq_long,
        ..SolverOptions::default()
    }
}

pub use super::rig_file::{LateralSweep, RigCase, RigSetup};
