//! The point-follower tyre: one contact point under the wheel centre, vertical spring and
//! damper (VERTICAL_STIFFNESS, VERTICAL_DAMPING), first-order transient slip with the
//! relaxation lengths sigma = C_Fkappa / C_x and sigma_alpha = C_Falpha / C_y (Pacejka 2012
//! sec. 7.2), and the Magic Formula with combined slip (F_x, F_y, M_z). No ring, no
//! enveloping: it sees the road's own slope (45 deg on the thesis ramp's flank), which is
//! why it suits flat roads and quick runs only.

use nalgebra::Vector3;

use crate::road::Road;
use towride_solver::VarKind;

use super::envelope::EffectiveRoad;
use super::params::TyreParams;
use super::{
    contact_velocity, ramp, smooth_step, ContactOutputs, HubLoad, WheelFrame, WheelKinematics,
};

/// State indices of the point follower.
pub mod idx {
    /// Tread (carcass) deflection, kappa' = u / sigma [m].
    pub const U: usize = 0;
    /// Lateral tread (carcass) deflection, tan(alpha') = v / sigma_alpha [m].
    pub const V: usize = 1;
    pub const N: usize = 2;
}

/// The point-follower tyre.
#[derive(Clone, Debug)]
pub struct PointFollower {
    /// The checked `.tir` data.
    pub p: TyreParams,
}

struct Eval {
    hub: HubLoad,
    out: ContactOutputs,
    v_slip: f64,
    v_roll: f64,
    /// Contact point velocity along e_x and the lateral direction [m/s].
    v_cx: f64,
    v_cy: f64,
}

impl PointFollower {
    /// The point follower with parameters `p`.
    pub fn new(p: TyreParams) -> PointFollower {
        PointFollower { p }
    }

    /// Number of states (two: the longitudinal and lateral tread deflections).
    pub fn n_states(&self) -> usize {
        idx::N
    }

    /// Names of the states.
    pub fn state_names(&self) -> Vec<String> {
        vec!["tread_u_m".to_string(), "tread_v_m".to_string()]
    }

    /// Differential or algebraic, per state.
    pub fn var_kinds(&self) -> Vec<VarKind> {
        vec![VarKind::Differential; idx::N]
    }

    /// Absolute tolerance of the tread deflections (1 um), times `scale`.
    pub fn atol(&self, scale: f64) -> Vec<f64> {
        vec![1e-6 * scale; idx::N]
    }

    fn eval(&self, kin: &WheelKinematics, road: &Road, x: &[f64]) -> Eval {
        let p = &self.p;
        let fr = WheelFrame::new(kin);
        let (px, py) = (kin.position.x, kin.position.y);
        let z_road = road.height(px, py);
        let (gx, gy) = road.slope(px, py);
        let tan = gx * fr.heading[0] + gy * fr.heading[1];
        let cosb = 1.0 / (1.0 + tan * tan).sqrt();
        let sinb = tan * cosb;
        let n = fr.ex * (-sinb) + Vector3::z() * cosb;
        let t = fr.ex * cosb + Vector3::z() * sinb;
        let rho = p.r0 - (kin.position.z - z_road);
        let s_dot = kin.velocity.dot(&fr.ex);
        let rho_dot = -(kin.velocity.z - tan * s_dot);
        let eps = p.contact_blend;
        let f_raw = p.cz * ramp(rho, eps) + p.vertical_damping * rho_dot * smooth_step(rho, eps);
        let f_n = ramp(f_raw, eps * p.cz);
        let omega = kin.omega.dot(&fr.ey);
        let r_e = p.rolling_radius(ramp(rho, eps), omega);
        let v_roll = r_e * omega;
        let v_slip = kin.velocity.dot(&t) - v_roll;
        let cp = Vector3::new(px, py, z_road);
        let (v_cx, v_cy) = contact_velocity(kin, &fr, &cp);
        // Pacejka's single contact point with its low-speed damping (sec. 7.2.2).
        let (kappa, alpha) = p.damped_slips(
            x[idx::U] / p.d.sigma_point,
            x[idx::V] / p.d.sigma_alpha,
            v_slip,
            v_cx,
            v_cy,
            f_n,
        );
        let mf = p.mf.forces(kappa, alpha, f_n, v_cx >= 0.0);
        let f_x = mf.fx;
        let ly = Vector3::new(fr.lateral[0], fr.lateral[1], 0.0);
        let fc = n * f_n + t * f_x + ly * mf.fy;
        let hub = HubLoad {
            force: fc,
            torque: (cp - kin.position).cross(&fc) + n * mf.mz,
        };
        let out = ContactOutputs {
            normal_force: f_n,
            longitudinal_force: f_x,
            contact_force: fc,
            contact_point: cp,
            effective: EffectiveRoad {
                height: z_road,
                tan_slope: tan,
                dheight_ds: tan,
                dtan_ds: 0.0,
                curvature: 0.0,
                flat: tan == 0.0,
            },
            slip: kappa,
            rolling_radius: r_e,
            loaded_radius: kin.position.z - z_road,
            deflection: rho,
            slip_velocity: v_slip,
            rolling_speed: v_roll,
            lateral_force: mf.fy,
            aligning_moment: mf.mz,
            slip_angle: alpha,
            lateral_velocity: v_cy,
        };
        Eval {
            hub,
            out,
            v_slip,
            v_roll,
            v_cx,
            v_cy,
        }
    }

    /// The DAE residual of the tread state (into `res`) and the load on the rim.
    pub fn residual(
        &self,
        _t: f64,
        kin: &WheelKinematics,
        road: &Road,
        x: &[f64],
        xdot: &[f64],
        res: &mut [f64],
    ) -> HubLoad {
        let e = self.eval(kin, road, x);
        let d = &self.p.d;
        res[idx::U] = xdot[idx::U] + e.v_slip + e.v_roll.abs() / d.sigma_point * x[idx::U];
        // Lateral transient slip (Pacejka 2012 sec. 7.2, ISO signs): the contact point
        // slides sideways at V_cy, the deflection relaxes over sigma_alpha of travel. At
        // standstill v' = V_cy: the tyre is a lateral spring of stiffness |K_ya| / sigma_alpha
        // = C_y, so nothing divides by the speed.
        res[idx::V] = xdot[idx::V] - e.v_cy + e.v_cx.abs() / d.sigma_alpha * x[idx::V];
        e.hub
    }

    /// Forces, slip and road at a state (for output and tests).
    pub fn outputs(&self, kin: &WheelKinematics, road: &Road, x: &[f64]) -> ContactOutputs {
        self.eval(kin, road, x).out
    }

    /// The load on the rim at a state.
    pub fn hub_load(&self, kin: &WheelKinematics, road: &Road, x: &[f64]) -> HubLoad {
        self.eval(kin, road, x).hub
    }

    /// Steady state for steady wheel motion (x' = 0 consistent).
    pub fn initial_state(&self, kin: &WheelKinematics, road: &Road) -> Vec<f64> {
        let mut x = vec![0.0; idx::N];
        let e = self.eval(kin, road, &x);
        let kappa = if e.v_roll.abs() > 1e-9 {
            -e.v_slip / e.v_roll.abs()
        } else {
            0.0
        };
        x[idx::U] = kappa * self.p.d.sigma_point;
        // Steady side slip tan(alpha) = V_cy / |V_cx|; at rest no deflection.
        if e.v_cx.abs() > 1e-9 {
            x[idx::V] = e.v_cy / e.v_cx.abs() * self.p.d.sigma_alpha;
        }
        x
    }
}
