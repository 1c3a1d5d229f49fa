//! The rigid-ring tyre (MF-Swift class): belt ring on sidewall springs, residual springs in
//! series with a transient-slip contact patch, tandem-cam enveloping.
//!
//! References: Zegelaar, "The dynamic response of tyres to brake torque variations and road
//! unevennesses" (PhD thesis, TU Delft 1998), the rigid ring; Pacejka, "Tire and Vehicle
//! Dynamics" (3rd ed. 2012) ch. 9 (rigid ring, residual stiffness, contact patch slip) and
//! ch. 10 (effective road inputs, rolling over obstacles); Schmeitz (PhD thesis, TU Delft
//! 2004), tandem cams. Equations and state layout: `docs/road_tyre.md` and the module
//! docs of [`crate::tyre`].

use nalgebra::Vector3;

use crate::road::Road;
use towride_solver::VarKind;

use super::envelope::{EffectiveRoad, TandemCams};
use super::params::TyreParams;
use super::{
    contact_velocity, ramp, smooth_step, ContactOutputs, HubLoad, WheelFrame, WheelKinematics,
};

/// State indices of the rigid-ring tyre.
pub mod idx {
    /// Ring centre displacement from the wheel centre along e_x and e_z [m].
    pub const XB: usize = 0;
    pub const ZB: usize = 1;
    /// Wind-up angle, ring rotation minus rim rotation [rad].
    pub const THETA: usize = 2;
    /// Ring centre absolute velocity along e_x and e_z [m/s].
    pub const VBX: usize = 3;
    pub const VBZ: usize = 4;
    /// Ring absolute spin rate about the spin axis [rad/s].
    pub const OMEGA_B: usize = 5;
    /// Residual longitudinal spring deflection [m].
    pub const UR: usize = 6;
    /// Tread deflection of the contact patch, kappa' = u_t / a0 [m].
    pub const UT: usize = 7;
    /// Lateral deflection (carcass and tread), tan(alpha') = v / sigma_alpha [m].
    pub const VT: usize = 8;
    pub const N: usize = 9;
}

const NAMES: [&str; idx::N] = [
    "ring_x_m",
    "ring_z_m",
    "windup_rad",
    "ring_vx_m_s",
    "ring_vz_m_s",
    "ring_omega_rad_s",
    "residual_u_m",
    "tread_u_m",
    "tread_v_m",
];

/// The rigid-ring tyre.
#[derive(Clone, Debug)]
pub struct RigidRing {
    /// The checked `.tir` data.
    pub p: TyreParams,
    /// The enveloping model's cam geometry.
    pub cams: TandemCams,
    /// Gravity vector [m/s^2] (from the file's GRAVITY along z unless overridden).
    pub gravity: Vector3<f64>,
}

/// Everything one evaluation computes.
struct Eval {
    hub: HubLoad,
    out: ContactOutputs,
    /// Residual parts that do not involve x'.
    f_ring: [f64; 2],
    m_spin: f64,
    v_slip: f64,
    v_roll: f64,
    f_x: f64,
    /// Contact point velocity along e_x and the lateral direction [m/s].
    v_cx: f64,
    v_cy: f64,
}

impl RigidRing {
    /// The rigid ring with parameters `p`; gravity from the file's GRAVITY along z.
    pub fn new(p: TyreParams) -> RigidRing {
        let cams = TandemCams::new(&p);
        let gravity = Vector3::new(0.0, 0.0, p.gravity);
        RigidRing { p, cams, gravity }
    }

    /// Number of states (ring motion, residual spring and tread).
    pub fn n_states(&self) -> usize {
        idx::N
    }

    /// Names of the states.
    pub fn state_names(&self) -> Vec<String> {
        NAMES.iter().map(|s| s.to_string()).collect()
    }

    /// Differential or algebraic, per state.
    pub fn var_kinds(&self) -> Vec<VarKind> {
        vec![VarKind::Differential; idx::N]
    }

    /// Absolute tolerances that suit each state (1 um, 1 urad, 1 mm/s, 1 N scaled).
    pub fn atol(&self, scale: f64) -> Vec<f64> {
        let mut a = vec![1e-6 * scale; idx::N];
        a[idx::VBX] = 1e-4 * scale;
        a[idx::VBZ] = 1e-4 * scale;
        a[idx::OMEGA_B] = 1e-3 * scale;
        a
    }

    fn eval(&self, kin: &WheelKinematics, road: &Road, x: &[f64], xdot_ur: f64) -> Eval {
        let p = &self.p;
        let d = &p.d;
        let fr = WheelFrame::new(kin);
        let (xb, zb) = (x[idx::XB], x[idx::ZB]);
        let (vbx, vbz) = (x[idx::VBX], x[idx::VBZ]);
        let omega_b = x[idx::OMEGA_B];
        let offset = fr.ex * xb + fr.ez * zb;
        let pb = kin.position + offset;
        let v_lat = kin.velocity.dot(&fr.ey);
        let vb = fr.ex * vbx + fr.ez * vbz + fr.ey * v_lat;

        // Effective road plane under the ring centre.
        let env: EffectiveRoad = self
            .cams
            .effective(road, [pb.x, pb.y], fr.heading, fr.lateral);
        let tan = env.tan_slope;
        let cosb = 1.0 / (1.0 + tan * tan).sqrt();
        let sinb = tan * cosb;
        let n = fr.ex * (-sinb) + Vector3::z() * cosb;
        let t = fr.ex * cosb + Vector3::z() * sinb;
        // Distance of the ring centre from the effective plane through (pb.x, pb.y, w).
        let dz = pb.z - env.height;
        let h = dz * cosb;
        let s_dot = vb.dot(&fr.ex);
        let beta_ds = env.dtan_ds * cosb * cosb;
        let beta_dot = beta_ds * s_dot;
        let h_dot = (vb.z - env.dheight_ds * s_dot) * cosb - dz * sinb * beta_dot;
        let rho = p.r0 - h;
        let rho_dot = -h_dot;

        // Normal force: residual spring and damper, C1 blend at touch-down, never tensile.
        let eps = p.contact_blend;
        let f_raw = d.c_rz * ramp(rho, eps) + d.k_rz * rho_dot * smooth_step(rho, eps);
        let f_n = ramp(f_raw, eps * d.c_rz);

        // Total deflection (residual plus ring) for the rolling radius and contact length.
        let rho_tot = ramp(rho, eps) + offset.dot(&n);
        let r_e = p.rolling_radius(rho_tot, omega_b);
        // Slip of the contact patch: material velocity of the ring at the contact point.
        // Written as in Swift, V_s = V_c - V_r with the contact point's velocity
        // V_c = V_b.t + h beta' and the rolling speed V_r = r_e Omega_b + h beta', the slope
        // rate cancels: an obstacle turns the effective plane without creating slip.
        let v_c = vb.dot(&t) + h * beta_dot;
        let v_roll = r_e * omega_b + h * beta_dot;
        let v_slip = v_c - v_roll;
        let cp = pb - n * h;
        let (v_cx, v_cy) = contact_velocity(kin, &fr, &cp);
        // The tread's slips, damped below VXLOW where the relaxation stops damping them.
        let (kappa, alpha) = p.damped_slips(
            x[idx::UT] / d.a0,
            x[idx::VT] / d.sigma_alpha,
            v_slip,
            v_cx,
            v_cy,
            f_n,
        );
        let mf = p.mf.forces(kappa, alpha, f_n, v_cx >= 0.0);
        let f_x = mf.fx;

        // In-plane contact force on the ring.
        let fc = n * f_n + t * f_x;
        let m_b = (cp - pb).cross(&fc);
        let m_spin = m_b.dot(&fr.ey);
        let f_out = fr.ey * fc.dot(&fr.ey);

        // Sidewall force on the ring, damping in the rim-fixed (rotating) frame: the rates
        // of the deflection seen from the rim carry the Omega x deflection terms (Zegelaar
        // 1998; Pacejka 2012 sec. 9.2).
        let omega_w = kin.omega.dot(&fr.ey);
        let vrel_x = vbx - kin.velocity.dot(&fr.ex);
        let vrel_z = vbz - kin.velocity.dot(&fr.ez);
        let fsw_x = -d.c_b * xb - d.k_b * (vrel_x - omega_w * zb);
        let fsw_z = -d.c_b * zb - d.k_b * (vrel_z + omega_w * xb);
        let g = self.gravity * p.belt_mass;
        let f_ring = [
            fsw_x + fc.dot(&fr.ex) + g.dot(&fr.ex),
            fsw_z + fc.dot(&fr.ez) + g.dot(&fr.ez),
        ];
        let windup = d.c_theta * x[idx::THETA] + d.k_theta * (omega_b - omega_w);
        // The lateral force and the aligning moment act on the rim at the contact point
        // (the ring has no lateral or yaw freedom of its own).
        let f_lat = Vector3::new(fr.lateral[0], fr.lateral[1], 0.0) * mf.fy;
        let f_hub = -(fr.ex * fsw_x + fr.ez * fsw_z) + f_out + fr.ey * g.dot(&fr.ey) + f_lat;
        let m_hub = fr.ey * windup
            + (m_b - fr.ey * m_spin)
            + offset.cross(&f_out)
            + (cp - kin.position).cross(&f_lat)
            + n * mf.mz;
        let _ = xdot_ur;
        Eval {
            hub: HubLoad {
                force: f_hub,
                torque: m_hub,
            },
            out: ContactOutputs {
                normal_force: f_n,
                longitudinal_force: f_x,
                contact_force: fc,
                contact_point: cp,
                effective: env,
                slip: kappa,
                rolling_radius: r_e,
                loaded_radius: h,
                deflection: rho_tot,
                slip_velocity: v_slip,
                rolling_speed: v_roll,
                lateral_force: mf.fy,
                aligning_moment: mf.mz,
                slip_angle: alpha,
                lateral_velocity: v_cy,
            },
            f_ring,
            m_spin,
            v_slip,
            v_roll,
            f_x,
            v_cx,
            v_cy,
        }
    }

    /// The DAE residual of the tyre's states and the load on the rim.
    pub fn residual(
        &self,
        _t: f64,
        kin: &WheelKinematics,
        road: &Road,
        x: &[f64],
        xdot: &[f64],
        res: &mut [f64],
    ) -> HubLoad {
        let p = &self.p;
        let d = &p.d;
        let e = self.eval(kin, road, x, xdot[idx::UR]);
        let fr = WheelFrame::new(kin);
        let omega_w = kin.omega.dot(&fr.ey);
        res[idx::XB] = xdot[idx::XB] - (x[idx::VBX] - kin.velocity.dot(&fr.ex));
        res[idx::ZB] = xdot[idx::ZB] - (x[idx::VBZ] - kin.velocity.dot(&fr.ez));
        res[idx::THETA] = xdot[idx::THETA] - (x[idx::OMEGA_B] - omega_w);
        res[idx::VBX] = p.belt_mass * xdot[idx::VBX] - e.f_ring[0];
        res[idx::VBZ] = p.belt_mass * xdot[idx::VBZ] - e.f_ring[1];
        res[idx::OMEGA_B] = p.belt_iyy * xdot[idx::OMEGA_B]
            - (-d.c_theta * x[idx::THETA] - d.k_theta * (x[idx::OMEGA_B] - omega_w) + e.m_spin);
        // Massless patch: residual spring-damper force equals the tread force.
        res[idx::UR] = (d.k_rx * xdot[idx::UR] + d.c_rx * x[idx::UR] - e.f_x) / d.c_rx;
        // Tread transient slip (first-order relaxation, Pacejka 2012 sec. 7.2; the brush's
        // relaxation length is the half contact length a0): the patch slides at the ring's
        // slip plus the residual spring's rate.
        res[idx::UT] =
            xdot[idx::UT] + e.v_slip + xdot[idx::UR] + e.v_roll.abs() / d.a0 * x[idx::UT];
        // Lateral transient slip (Pacejka 2012 sec. 7.2, ISO signs), the same law as the
        // point follower's: v' = V_cy - |V_cx| v / sigma_alpha, sigma_alpha = |K_ya| / C_y.
        res[idx::VT] = xdot[idx::VT] - e.v_cy + e.v_cx.abs() / d.sigma_alpha * x[idx::VT];
        e.hub
    }

    /// Forces, slip and effective road at a state (for output and tests).
    pub fn outputs(&self, kin: &WheelKinematics, road: &Road, x: &[f64]) -> ContactOutputs {
        self.eval(kin, road, x, 0.0).out
    }

    /// The load on the rim at a state (no derivatives needed: the hub load depends on the
    /// states only).
    pub fn hub_load(&self, kin: &WheelKinematics, road: &Road, x: &[f64]) -> HubLoad {
        self.eval(kin, road, x, 0.0).hub
    }

    /// Steady state for a wheel moving steadily with `kin` (resting or rolling at its
    /// current spin): ring force and moment balance, steady slip, forces consistent.
    /// x' = 0 is then consistent with the residual for steady wheel motion.
    pub fn initial_state(&self, kin: &WheelKinematics, road: &Road) -> Vec<f64> {
        let p = &self.p;
        let d = &p.d;
        let fr = WheelFrame::new(kin);
        let omega_w = kin.omega.dot(&fr.ey);
        let mut x = vec![0.0; idx::N];
        x[idx::VBX] = kin.velocity.dot(&fr.ex);
        x[idx::VBZ] = kin.velocity.dot(&fr.ez);
        x[idx::OMEGA_B] = omega_w;
        // Steady side slip tan(alpha) = V_cy / |V_cx| (the contact point's velocity does
        // not depend on the ring's in-plane offset, whose rate is zero at steady state).
        {
            let e = self.eval(kin, road, &x, 0.0);
            if e.v_cx.abs() > 1e-9 {
                x[idx::VT] = e.v_cy / e.v_cx.abs() * d.sigma_alpha;
            }
        }
        // Given the ring offset, close the slip and the wind-up at steady state.
        let settle = |x: &mut Vec<f64>| {
            for _ in 0..50 {
                let e = self.eval(kin, road, x, 0.0);
                let kappa = if e.v_roll.abs() > 1e-9 {
                    -e.v_slip / e.v_roll.abs()
                } else {
                    0.0
                };
                let ut = kappa * d.a0;
                let change = (ut - x[idx::UT]).abs();
                x[idx::UT] = ut;
                let e = self.eval(kin, road, x, 0.0);
                x[idx::UR] = e.f_x / d.c_rx;
                x[idx::THETA] = e.m_spin / d.c_theta;
                if change < 1e-15 {
                    break;
                }
            }
        };
        // Newton on the ring's in-plane force balance (x_b, z_b).
        for _ in 0..60 {
            settle(&mut x);
            let f0 = self.eval(kin, road, &x, 0.0).f_ring;
            if f0[0].abs() + f0[1].abs() < 1e-9 * p.fnomin {
                break;
            }
            let mut jac = [[0.0; 2]; 2];
            for (j, k) in [idx::XB, idx::ZB].into_iter().enumerate() {
                let mut xp = x.clone();
                let hstep = 1e-8;
                xp[k] += hstep;
                settle(&mut xp);
                let f1 = self.eval(kin, road, &xp, 0.0).f_ring;
                jac[0][j] = (f1[0] - f0[0]) / hstep;
                jac[1][j] = (f1[1] - f0[1]) / hstep;
            }
            let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
            if det.abs() < 1e-300 {
                break;
            }
            let dxb = (-f0[0] * jac[1][1] + f0[1] * jac[0][1]) / det;
            let dzb = (-f0[1] * jac[0][0] + f0[0] * jac[1][0]) / det;
            x[idx::XB] += dxb;
            x[idx::ZB] += dzb;
            if dxb.abs() + dzb.abs() < 1e-13 {
                settle(&mut x);
                break;
            }
        }
        x
    }
}
