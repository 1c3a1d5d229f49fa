//! A steady-state side-slip rig (a flat-track or drum test at a set slip angle): the
//! wheel centre moves at constant height with the forward speed V_x along the wheel's
//! heading (world x) and the side speed V_x tan(alpha) (world y), so the contact point's
//! slip angle is alpha = atan(V_cy / V_cx) (ISO); the rim is driven at the free-rolling
//! spin (longitudinal slip 0) or turns freely. Unknowns: the tyre's states, then the rim
//! spin rate.
//!
//! Started in the steady state of its slip angle (`step = false`) the rig checks the
//! steady F_y(alpha), M_z(alpha); started with the lateral deflection at zero (`step =
//! true`) it is a step in slip angle at t = 0, whose response is first order in the
//! distance rolled with the relaxation length sigma_alpha.

use std::path::Path;

use nalgebra::Vector3;

use crate::input::InputError;
use crate::road::Road;
use towride_solver::{SolverError, SolverOptions};

use super::rig::{free_rolling_spin, height_for_load, integrate, sample_of, RigRun, Spin};
use super::{Tyre, WheelKinematics};

/// Wheel centre at constant height and velocity (V_x, V_x tan alpha); rim driven or free.
pub struct LateralRig {
    /// The tyre under test.
    pub tyre: Tyre,
    /// The road it rolls on.
    pub road: Road,
    /// Forward speed along the wheel's heading V_x [m/s].
    pub speed: f64,
    /// Slip angle alpha [rad] (the side speed is V_x tan alpha).
    pub alpha: f64,
    /// Wheel-centre x at t = 0 [m].
    pub x0: f64,
    /// Wheel-centre height [m], set so that the tyre carries the rig's load.
    pub z_axle: f64,
    /// Driven at the free-rolling spin, or free.
    pub spin: Spin,
    /// Spin inertia of everything that turns with the rim [kg m^2].
    pub rim_iyy: f64,
    /// Start with no lateral deflection (a step in slip angle at t = 0) instead of the
    /// steady state.
    pub step: bool,
    n: usize,
}

impl LateralRig {
    /// A rig at slip angle `alpha` [rad] carrying `load` [N] at forward speed `speed`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        tyre: Tyre,
        road: Road,
        speed: f64,
        alpha: f64,
        x0: f64,
        load: f64,
        spin: Spin,
        rim_iyy: f64,
    ) -> LateralRig {
        let n = tyre.n_states();
        let z_axle = height_for_load(&tyre, &road, x0, speed, load);
        LateralRig {
            tyre,
            road,
            speed,
            alpha,
            x0,
            z_axle,
            spin,
            rim_iyy,
            step: false,
            n,
        }
    }

    /// The wheel's motion at time `t` with rim spin `omega`.
    pub fn kin(&self, t: f64, omega: f64) -> WheelKinematics {
        let vy = self.speed * self.alpha.tan();
        WheelKinematics::upright(
            Vector3::new(self.x0 + self.speed * t, vy * t, self.z_axle),
            Vector3::new(self.speed, vy, 0.0),
            omega,
        )
    }

    /// Index of the tyre's lateral deflection state.
    pub fn lateral_state(&self) -> usize {
        self.tyre
            .state_names()
            .iter()
            .position(|s| s == "tread_v_m")
            .expect("every tyre has a lateral tread state")
    }

    /// Initial values: steady at the slip angle, or (`step`) with no lateral deflection.
    pub fn initial(&self) -> (Vec<f64>, Vec<f64>) {
        let omega = free_rolling_spin(
            &self.tyre,
            &self.road,
            self.x0,
            self.z_axle,
            self.speed,
            0.0,
        );
        let mut y = self.tyre.initial_state(&self.kin(0.0, omega), &self.road);
        if self.step {
            y[self.lateral_state()] = 0.0;
        }
        y.push(omega);
        let yp = vec![0.0; y.len()];
        (y, yp)
    }

    /// Runs the rig to `t_end` with output every `dt`.
    pub fn run(&self, t_end: f64, dt: f64, opts: &SolverOptions) -> Result<RigRun, SolverError> {
        let (y, yp) = self.initial();
        let n = self.n;
        integrate(self, y, yp, t_end, dt, opts, |t, y| {
            sample_of(&self.tyre, &self.road, t, &self.kin(t, y[n]), &y[..n])
        })
    }
}

super::rig::spinning_rig_dae!(LateralRig);

/// One steady point of a slip-angle sweep.
#[derive(Clone, Debug, serde::Serialize)]
pub struct LateralPoint {
    /// Vertical load set [N] and the normal force reached [N].
    pub load_n: f64,
    /// Normal contact force at the end of the run [N].
    pub normal_force_n: f64,
    /// Slip angle set [rad].
    pub alpha_rad: f64,
    /// Transient slip angle reached alpha' [rad].
    pub slip_angle_rad: f64,
    /// Lateral force F_y [N] and aligning moment M_z [N m] at the end of the run.
    pub fy_n: f64,
    /// Aligning moment M_z [N m].
    pub mz_n_m: f64,
    /// Longitudinal contact force F_x [N].
    pub fx_n: f64,
    /// The Magic Formula evaluated directly at (kappa 0, alpha, load) [N], [N m].
    pub fy_formula_n: f64,
    /// M_z of the formula at (kappa 0, alpha, load) [N m].
    pub mz_formula_n_m: f64,
    /// Solver steps of this point's run.
    pub steps: usize,
}

/// Runs one rig per (load, slip angle) for `settle` seconds from its steady state and
/// takes the last sample (the rig is steady if the tyre's own equations are).
#[allow(clippy::too_many_arguments)]
pub fn sweep(
    tyre: &Tyre,
    road: &Road,
    speed: f64,
    loads: &[f64],
    alphas: &[f64],
    settle: f64,
    spin: Spin,
    rim_iyy: f64,
    rtol: f64,
) -> Result<Vec<LateralPoint>, SolverError> {
    let mut out = Vec::new();
    for &load in loads {
        for &alpha in alphas {
            let rig = LateralRig::new(
                tyre.clone(),
                road.clone(),
                speed,
                alpha,
                0.0,
                load,
                spin,
                rim_iyy,
            );
            let opts = super::rig::rig_options(&rig.tyre, rtol, &[1e-3]);
            let run = rig.run(settle, settle, &opts)?;
            let s = run.samples.last().expect("a run has samples");
            let f = tyre.params().mf.forces(0.0, alpha, load, true);
            out.push(LateralPoint {
                load_n: load,
                normal_force_n: s.normal_force_n,
                alpha_rad: alpha,
                slip_angle_rad: s.slip_angle_rad,
                fy_n: s.lateral_force_n,
                mz_n_m: s.aligning_moment_n_m,
                fx_n: s.long_force_n,
                fy_formula_n: f.fy,
                mz_formula_n_m: f.mz,
                steps: run.stats.steps,
            });
        }
    }
    Ok(out)
}

/// One row of a reference table of steady forces (load, slips, F_x, F_y, M_z).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ReferencePoint {
    /// Vertical load [N].
    pub fz_n: f64,
    /// Longitudinal slip [-].
    pub kappa: f64,
    /// Slip angle [rad].
    pub alpha_rad: f64,
    /// Forces [N] and aligning moment [N m].
    pub fx_n: f64,
    /// Lateral force [N].
    pub fy_n: f64,
    /// Aligning moment [N m].
    pub mz_n_m: f64,
}

/// Reads a reference table: `#` comment lines, a header line naming the columns
/// `fz_n,kappa,alpha_rad,fx_n,fy_n,mz_n_m` (any order), then rows of numbers.
pub fn read_reference(path: &Path) -> Result<Vec<ReferencePoint>, InputError> {
    let text = crate::input::loader::read_text(path)?;
    let err = |line: usize, m: String| InputError {
        file: path.to_path_buf(),
        line: Some(line),
        column: None,
        field: String::new(),
        message: m,
        kind: Default::default(),
    };
    let mut cols: Option<Vec<String>> = None;
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let Some(c) = &cols else {
            cols = Some(cells.iter().map(|s| s.to_string()).collect());
            continue;
        };
        let get = |name: &str| -> Result<f64, InputError> {
            let k = c
                .iter()
                .position(|x| x == name)
                .ok_or_else(|| err(i + 1, format!("no column {name}")))?;
            cells
                .get(k)
                .and_then(|v| v.parse::<f64>().ok())
                .ok_or_else(|| err(i + 1, format!("column {name}: not a number")))
        };
        out.push(ReferencePoint {
            fz_n: get("fz_n")?,
            kappa: get("kappa")?,
            alpha_rad: get("alpha_rad")?,
            fx_n: get("fx_n")?,
            fy_n: get("fy_n")?,
            mz_n_m: get("mz_n_m")?,
        });
    }
    Ok(out)
}
