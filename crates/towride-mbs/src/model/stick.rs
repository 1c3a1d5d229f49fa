//! Friction that sticks: the brakes' and the engine drag's torque on a spinning part,
//! with static friction at rest. One state per contact, written for an implicit DAE
//! integrator with error control: no events, no switching of equations, a right-hand
//! side that is continuous everywhere (C1 in the deflection, a kink in the spin at rest,
//! as LuGre's |v| has).
//!
//! # The law
//!
//! The single-state elasto-plastic model of Dupont, Hayward, Armstrong and Altpeter
//! ("Single state elastoplastic friction models", IEEE Trans. Automatic Control 47(5),
//! 2002, pp. 787-792), in its dwell-free Coulomb form (no Stribeck curve: the steady
//! deflection `z_ss` is constant), a LuGre bristle (Canudas de Wit, Olsson, Astrom,
//! Lischinsky, IEEE TAC 40(3), 1995) that does not drift under loads below breakaway:
//!
//! ```text
//! dz/dt = w (1 - alpha(z, w) z / z_ss)
//! alpha = 0                                                  |z| <= z_ba, or sgn z != sgn w
//!       = 1/2 sin(pi (|z| - (z_ss + z_ba)/2) / (z_ss - z_ba)) + 1/2    z_ba < |z| < z_ss
//!       = 1                                                  |z| >= z_ss
//! T     = -C (sigma_0' z + sigma_1' dz/dt)
//! ```
//!
//! w the part's spin relative to its carrier, z the bristle's angular deflection, C >= 0
//! the contact's torque capacity now (the brake's share of the controller's demand, the
//! engine's drag). Below `z_ba` the bristle is a spring-damper (no creep: stiction);
//! between `z_ba` and `z_ss` it yields smoothly; at `z_ss` it slips with T = -C sgn w.
//! The alpha function was checked against two public implementations of the model (the
//! paper's text was not read); LuGre with g(v) = F_c / sigma_0 is the alpha = 1 case.
//!
//! **A capacity that changes in time.** The torque is written per unit capacity, as the
//! LuGre tyre model writes its force per unit normal load, F = F_n (sigma_0 z + sigma_1
//! dz/dt + sigma_2 v) (Canudas de Wit, Tsiotras, Velenis, Basset, Gissinger, "Dynamic
//! friction models for road/tire longitudinal interaction", Vehicle System Dynamics
//! 39(3), 2003): sigma_0' = 1 / z_ss, so the deflection at breakaway is the same at any
//! capacity and the stiffness C / z_ss scales with it (a brake clamped harder is stiffer).
//! The state is that normalised deflection s = z / z_ss, dimensionless within [-1, 1].
//! Released brakes (C = 0) give exactly no torque, whatever s holds; a wheel held while
//! the demand grows keeps its torque (the part moves back until the torque balances
//! again), so a stopped wheel is driven backwards by at most the bristle's `z_ss`, not
//! on and on as plain Coulomb friction with a sign function would. sigma_1' = tau / z_ss:
//! the damping is a time constant `tau` of the spring, the damping ratio of the part's
//! spin mode on it tau / 2 sqrt(C / (z_ss J)) (J the part's spin inertia).
//!
//! dz/dt enters the torque as its formula, not as the state's derivative unknown, so
//! the load depends on the states and never on their rates (as the tyres' loads).

/// The bristle of a stick-slip friction contact (the brakes', the engine drag's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StickFriction {
    /// Angular deflection at which the contact slips, z_ss [rad].
    pub deflection_rad: f64,
    /// Share of that deflection that stays elastic, z_ba / z_ss, in [0, 1) [-].
    pub elastic_share: f64,
    /// Damping time constant of the bristle, sigma_1' / sigma_0' [s].
    pub damping_s: f64,
}

impl StickFriction {
    /// The yield weight alpha of the normalised deflection `s` at spin `w`.
    fn alpha(&self, s: f64, w: f64) -> f64 {
        let a = s.abs();
        let b = self.elastic_share;
        if s * w <= 0.0 || a <= b {
            0.0
        } else if a >= 1.0 {
            1.0
        } else {
            0.5 * (std::f64::consts::PI * (a - 0.5 * (1.0 + b)) / (1.0 - b)).sin() + 0.5
        }
    }

    /// Rate of the normalised deflection s = z / z_ss at relative spin `w` [1/s].
    pub fn rate(&self, s: f64, w: f64) -> f64 {
        w / self.deflection_rad * (1.0 - self.alpha(s, w) * s)
    }

    /// Friction torque per unit capacity, positive opposing a positive spin: the torque
    /// on the part is -C times this [-].
    pub fn per_capacity(&self, s: f64, w: f64) -> f64 {
        s + self.damping_s * self.rate(s, w)
    }

    /// The state of a contact in steady motion at spin `w`: slipping (s = sgn w, where
    /// the rate vanishes) when the part turns, unloaded at rest. "Turning" is a spin that
    /// would carry the bristle through its deflection within a millisecond.
    pub fn initial(&self, w: f64) -> f64 {
        if w.abs() * 1e-3 > self.deflection_rad {
            w.signum()
        } else {
            0.0
        }
    }
}
