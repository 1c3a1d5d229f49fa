//! Tyres: a Swift-like rigid-ring tyre with tandem-cam enveloping, and a point follower,
//! both with the Magic Formula 6.1 longitudinal and lateral forces, aligning moment and
//! combined slip (`magic.rs`, `magic_lateral.rs`, `combined.rs`) behind first-order
//! relaxation states.
//!
//! # Interface for a multibody model
//!
//! A tyre is a self-contained force element with internal states. The model that owns the
//! wheel (a rim body) hands it the wheel's motion and gets back the load on the rim:
//!
//! ```text
//! let tyre = Tyre::from_file(Path::new("vehicles/tyres/car_185_60r14.tir"), TyreKind::RigidRing)?;
//! let road = Road::from_file(Path::new("roads/ramp_thesis.toml"))?;
//! tyre.n_states(); tyre.state_names(); tyre.var_kinds();      // layout of its unknowns
//! let x0 = tyre.initial_state(&kin, &road);                   // steady state, x' = 0
//! let hub = tyre.residual(t, &kin, &road, x, xdot, res);      // res: n_states equations
//! // hub.force, hub.torque: load on the rim at the wheel centre, world axes
//! ```
//!
//! - [`WheelKinematics`]: wheel centre position and velocity (world), rotation matrix
//!   wheel -> world (the spin axis is the wheel's local y, pointing left on a car), angular
//!   velocity (world). The spin rate is omega . spin axis.
//! - The tyre appends `n_states()` unknowns and as many equations to the model's DAE; their
//!   kinds ([`VarKind::Differential`] or [`VarKind::Algebraic1`]) come from `var_kinds()`,
//!   suggested absolute tolerances from `atol()`.
//! - `residual` writes the tyre's equations and returns the [`HubLoad`] at the state; the
//!   load depends on x (and the wheel motion), never on x', so it can enter the rim's
//!   equations of motion directly. The tyre needs no wheel acceleration.
//! - `initial_state` gives a statically consistent state for a wheel resting or rolling
//!   steadily with `kin` (ring in equilibrium, steady slip at the current spin, forces
//!   consistent); x' = 0 is consistent with it for steady motion.
//! - The rigid-ring tyre carries the belt's mass and spin inertia itself: give the rim
//!   body the rest ([`TyreParams::rim_share`]). The point follower has no mass of its own.
//! - Everything physical comes from the `.tir` file ([`TyreParams`]); the gravity vector
//!   is the file's GRAVITY along world z unless set with [`Tyre::set_gravity`].
//!
//! # Frames and sign conventions
//!
//! e_y = spin axis (world), e_x = e_y x z / |e_y x z| (horizontal heading), e_z = e_x x e_y
//! (up in the wheel plane). A wheel rolling forward has a positive spin rate. The effective
//! road plane has slope angle beta (positive uphill along e_x), normal
//! n = -sin(beta) e_x + cos(beta) z and tangent t = cos(beta) e_x + sin(beta) z.
//!
//! # Rigid-ring states (`ring::idx`), all differential
//!
//! | # | name | meaning |
//! |---|---|---|
//! | 0, 1 | ring_x_m, ring_z_m | ring centre minus wheel centre along e_x, e_z [m] |
//! | 2 | windup_rad | ring rotation minus rim rotation [rad] |
//! | 3, 4 | ring_vx_m_s, ring_vz_m_s | ring centre velocity along e_x, e_z [m/s] |
//! | 5 | ring_omega_rad_s | ring spin rate [rad/s] |
//! | 6 | residual_u_m | residual longitudinal spring deflection [m] |
//! | 7 | tread_u_m | tread deflection, transient slip kappa' = u / a0 [m] |
//! | 8 | tread_v_m | lateral deflection, transient slip angle alpha' = atan(v / sigma_alpha) [m] |
//!
//! Point follower (`point::idx`): tread_u_m, kappa' = u / sigma; tread_v_m, alpha' =
//! atan(v / sigma_alpha) (differential).
//!
//! # Lateral force and aligning moment
//!
//! The ring is in-plane (x, z, wind-up): it has no lateral or yaw freedom. The lateral
//! force F_y (along the horizontal lateral direction z x e_x, ISO: positive to the left)
//! and the aligning moment M_z (about the road normal) act on the rim at the contact point,
//! with the moment arm from the contact point to the wheel centre. The slip angle is that
//! of the contact point's velocity (wheel centre velocity plus the carrier's rotation, spin
//! excluded, times the arm) in the wheel's heading frame (e_x, z x e_x): at steady state
//! tan(alpha) = V_cy / |V_cx|. The lateral deflection v obeys v' = V_cy - |V_cx| v /
//! sigma_alpha, sigma_alpha = |K_ya(FNOMIN)| / LATERAL_STIFFNESS: no division by the speed,
//! so the state is defined at rest (then a lateral spring of stiffness ~ C_y), exactly as
//! the longitudinal tread state u' = -V_s - |V_r| u / sigma is.
//!
//! The contact forces are not unknowns: they follow from the states and the road in every
//! residual evaluation (see [`Tyre::outputs`]). On a road with kinks (obstacle edges) the
//! effective road's rate jumps and so does the damper part of the normal force; kept
//! inside the differential equations such a jump is only a kink of the states, which the
//! BDF error control passes with a few step cuts, whereas an algebraic force unknown
//! would jump and stall the step size (the error test cannot pass a jump).
//!
//! # Integration hints
//!
//! The integrator learns of the road only through the residual: limit the step so it cannot
//! jump over an obstacle (the rigs use h_max = 0.1 / FREQ_LONG), or check
//! [`crate::road::Road::is_flat`] over [`Tyre::reach`] ahead of the wheel.
//!
//! The equations are written out in `docs/road_tyre.md`.

pub(crate) mod combined;
pub(crate) mod envelope;
mod envelope_pieces;
pub use crate::input::tyre_factors as factors;
pub(crate) mod magic;
pub(crate) mod magic_lateral;
pub mod params;
pub(crate) mod point;
pub mod rig;
mod rig_file;
pub mod rig_lateral;
pub(crate) mod ring;

use std::path::Path;

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use crate::input::InputError;
use crate::road::Road;
use towride_solver::VarKind;

pub use combined::{MagicFormula, MfForces};
pub use envelope::{EffectiveRoad, TandemCams};
pub use params::TyreParams;
pub use point::PointFollower;
pub use ring::RigidRing;

/// The motion of a wheel (rim) as the multibody model knows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelKinematics {
    /// Wheel centre, world [m].
    pub position: Vector3<f64>,
    /// Rotation wheel -> world; the spin axis is the wheel's local y.
    pub rotation: Matrix3<f64>,
    /// Wheel centre velocity, world [m/s].
    pub velocity: Vector3<f64>,
    /// Angular velocity, world [rad/s].
    pub omega: Vector3<f64>,
}

impl WheelKinematics {
    /// A wheel upright with its spin axis along world y, moving with `velocity` and
    /// spinning at `spin` [rad/s] (positive rolling forward along +x).
    pub fn upright(position: Vector3<f64>, velocity: Vector3<f64>, spin: f64) -> WheelKinematics {
        WheelKinematics {
            position,
            rotation: Matrix3::identity(),
            velocity,
            omega: Vector3::new(0.0, spin, 0.0),
        }
    }
}

/// The load a tyre puts on its rim, at the wheel centre, world axes.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct HubLoad {
    /// Force on the rim, world axes [N].
    pub force: Vector3<f64>,
    /// Torque on the rim about the wheel centre, world axes [N m].
    pub torque: Vector3<f64>,
}

/// Contact quantities at a state, for output and checks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOutputs {
    /// Normal and longitudinal contact force (the states) [N].
    pub normal_force: f64,
    /// Longitudinal contact force [N].
    pub longitudinal_force: f64,
    /// Road force on the tyre, world [N], and where it acts [m].
    pub contact_force: Vector3<f64>,
    /// Point of application of `contact_force`, world [m].
    pub contact_point: Vector3<f64>,
    /// The effective road plane (for the point follower: the road itself under the centre).
    pub effective: EffectiveRoad,
    /// Transient longitudinal slip kappa' [-].
    pub slip: f64,
    /// Effective rolling radius and loaded radius (ring or wheel centre to road) [m].
    pub rolling_radius: f64,
    /// Loaded radius: ring or wheel centre to the road [m].
    pub loaded_radius: f64,
    /// Total tyre deflection [m].
    pub deflection: f64,
    /// Slip velocity and rolling speed at the contact [m/s].
    pub slip_velocity: f64,
    /// Rolling speed at the contact [m/s].
    pub rolling_speed: f64,
    /// Lateral contact force F_y [N], along the horizontal lateral direction z x e_x
    /// (ISO: positive to the wheel's left).
    pub lateral_force: f64,
    /// Aligning moment M_z [N m] about the road normal at the contact point.
    pub aligning_moment: f64,
    /// Transient slip angle alpha' = atan(v / sigma_alpha) [rad] (ISO: positive when the
    /// contact point moves to the left).
    pub slip_angle: f64,
    /// Velocity of the contact point along the lateral direction [m/s] and along e_x.
    pub lateral_velocity: f64,
}

/// Which tyre model to build from a `.tir` file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum TyreKind {
    /// Rigid ring with tandem-cam enveloping (Swift-like).
    #[default]
    RigidRing,
    /// Single contact point, no ring (flat roads, quick runs).
    PointFollower,
}

/// A tyre of either kind, behind one interface.
#[derive(Clone, Debug)]
pub enum Tyre {
    /// Rigid ring with tandem-cam enveloping.
    RigidRing(RigidRing),
    /// Single contact point, no ring.
    PointFollower(PointFollower),
}

impl Tyre {
    /// Reads a `.tir` file and builds the tyre.
    pub fn from_file(
        path: &Path,
        kind: TyreKind,
        loader: &crate::input::Loader,
    ) -> Result<Tyre, InputError> {
        Ok(Tyre::new(TyreParams::from_file(path, loader)?, kind))
    }

    /// The tyre of kind `kind` with parameters `p`.
    pub fn new(p: TyreParams, kind: TyreKind) -> Tyre {
        match kind {
            TyreKind::RigidRing => Tyre::RigidRing(RigidRing::new(p)),
            TyreKind::PointFollower => Tyre::PointFollower(PointFollower::new(p)),
        }
    }

    /// The checked `.tir` data.
    pub fn params(&self) -> &TyreParams {
        match self {
            Tyre::RigidRing(r) => &r.p,
            Tyre::PointFollower(r) => &r.p,
        }
    }

    /// Which model this is.
    pub fn kind(&self) -> TyreKind {
        match self {
            Tyre::RigidRing(_) => TyreKind::RigidRing,
            Tyre::PointFollower(_) => TyreKind::PointFollower,
        }
    }

    /// Overrides the gravity vector the ring feels (the rigid ring has mass).
    pub fn set_gravity(&mut self, g: Vector3<f64>) {
        if let Tyre::RigidRing(r) = self {
            r.gravity = g;
        }
    }

    /// Number of the tyre's own states.
    pub fn n_states(&self) -> usize {
        match self {
            Tyre::RigidRing(r) => r.n_states(),
            Tyre::PointFollower(r) => r.n_states(),
        }
    }

    /// Names of the tyre's states (for messages and outputs).
    pub fn state_names(&self) -> Vec<String> {
        match self {
            Tyre::RigidRing(r) => r.state_names(),
            Tyre::PointFollower(r) => r.state_names(),
        }
    }

    /// Differential or algebraic, per state.
    pub fn var_kinds(&self) -> Vec<VarKind> {
        match self {
            Tyre::RigidRing(r) => r.var_kinds(),
            Tyre::PointFollower(r) => r.var_kinds(),
        }
    }

    /// Suggested absolute tolerances of the states, times `scale`.
    pub fn atol(&self, scale: f64) -> Vec<f64> {
        match self {
            Tyre::RigidRing(r) => r.atol(scale),
            Tyre::PointFollower(r) => r.atol(scale),
        }
    }

    /// Steady state for a wheel moving steadily with `kin` on `road`.
    pub fn initial_state(&self, kin: &WheelKinematics, road: &Road) -> Vec<f64> {
        match self {
            Tyre::RigidRing(r) => r.initial_state(kin, road),
            Tyre::PointFollower(r) => r.initial_state(kin, road),
        }
    }

    /// The DAE residual of the tyre's states (into `res`) and the load on the rim.
    pub fn residual(
        &self,
        t: f64,
        kin: &WheelKinematics,
        road: &Road,
        x: &[f64],
        xdot: &[f64],
        res: &mut [f64],
    ) -> HubLoad {
        match self {
            Tyre::RigidRing(r) => r.residual(t, kin, road, x, xdot, res),
            Tyre::PointFollower(r) => r.residual(t, kin, road, x, xdot, res),
        }
    }

    /// The load on the rim at a state.
    pub fn hub_load(&self, kin: &WheelKinematics, road: &Road, x: &[f64]) -> HubLoad {
        match self {
            Tyre::RigidRing(r) => r.hub_load(kin, road, x),
            Tyre::PointFollower(r) => r.hub_load(kin, road, x),
        }
    }

    /// Forces, slip and effective road at a state (for output and tests).
    pub fn outputs(&self, kin: &WheelKinematics, road: &Road, x: &[f64]) -> ContactOutputs {
        match self {
            Tyre::RigidRing(r) => r.outputs(kin, road, x),
            Tyre::PointFollower(r) => r.outputs(kin, road, x),
        }
    }

    /// Effective-road queries of the enveloping model: (all, from the memo, flat road
    /// without a search); `None` for the point follower, which has none.
    pub fn query_counts(&self) -> Option<[u64; 3]> {
        match self {
            Tyre::RigidRing(r) => Some(r.cams.query_counts()),
            Tyre::PointFollower(_) => None,
        }
    }

    /// Horizontal extent [x0, x1] of road this tyre can touch when its centre is at `x`:
    /// a scene may skip the tyre's road work where `Road::is_flat` holds over it.
    pub fn reach(&self, x: f64) -> (f64, f64) {
        match self {
            Tyre::RigidRing(r) => {
                let half = 0.5 * r.cams.l_s + r.cams.xi_max;
                (x - half, x + half)
            }
            Tyre::PointFollower(_) => (x, x),
        }
    }
}

/// The wheel's carrier frame (non-spinning).
pub(crate) struct WheelFrame {
    pub ex: Vector3<f64>,
    pub ey: Vector3<f64>,
    pub ez: Vector3<f64>,
    /// Horizontal heading and lateral unit vectors (x, y).
    pub heading: [f64; 2],
    pub lateral: [f64; 2],
}

/// Velocity of the contact point `cp` (a geometric point, not a material one): the wheel
/// centre's velocity plus the carrier's rotation (the angular velocity without the spin)
/// times the arm; returns its components along e_x and along the horizontal lateral
/// direction z x e_x: (V_cx, V_cy).
pub(crate) fn contact_velocity(
    kin: &WheelKinematics,
    fr: &WheelFrame,
    cp: &Vector3<f64>,
) -> (f64, f64) {
    let carrier = kin.omega - fr.ey * kin.omega.dot(&fr.ey);
    let vc = kin.velocity + carrier.cross(&(cp - kin.position));
    let ly = Vector3::new(fr.lateral[0], fr.lateral[1], 0.0);
    (vc.dot(&fr.ex), vc.dot(&ly))
}

impl WheelFrame {
    pub fn new(kin: &WheelKinematics) -> WheelFrame {
        let ey: Vector3<f64> = kin.rotation.column(1).into_owned();
        let mut ex = ey.cross(&Vector3::z());
        if ex.norm() < 1e-9 {
            // Spin axis vertical (a wheel lying flat): fall back to the wheel's own x.
            ex = kin.rotation.column(0).into_owned();
            ex.z = 0.0;
        }
        let ex = ex.normalize();
        let ez = ex.cross(&ey);
        WheelFrame {
            heading: [ex.x, ex.y],
            lateral: [-ex.y, ex.x],
            ex,
            ey,
            ez,
        }
    }
}

/// One-sided C1 ramp for max(v, 0): exactly 0 for v <= 0, exactly v for v >= delta, and
/// v^2 (2 delta - v) / delta^2 in between (value and slope match at both ends). Used for
/// contact forces: no force before contact, the exact linear law once delta deep, and a
/// smooth enough onset for the BDF error control at touch-down and lift-off.
#[inline]
pub fn ramp(v: f64, delta: f64) -> f64 {
    if v <= 0.0 {
        0.0
    } else if v >= delta {
        v
    } else {
        v * v * (2.0 * delta - v) / (delta * delta)
    }
}

/// C1 smooth step from 0 (v <= 0) to 1 (v >= delta): 3 u^2 - 2 u^3 with u = v / delta.
#[inline]
pub fn smooth_step(v: f64, delta: f64) -> f64 {
    if v <= 0.0 {
        0.0
    } else if v >= delta {
        1.0
    } else {
        let u = v / delta;
        u * u * (3.0 - 2.0 * u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_is_c1_and_exact_outside() {
        let d = 1e-3;
        assert_eq!(ramp(-1e-9, d), 0.0);
        assert_eq!(ramp(0.0, d), 0.0);
        assert_eq!(ramp(2e-3, d), 2e-3);
        let h = 1e-9;
        let slope = |v: f64| (ramp(v + h, d) - ramp(v - h, d)) / (2.0 * h);
        assert!(slope(h).abs() < 1e-5);
        assert!((slope(d - 2.0 * h) - 1.0).abs() < 1e-5);
        assert!((ramp(d, d) - d).abs() < 1e-18);
        assert_eq!(smooth_step(0.5 * d, d), 0.5);
    }
}
