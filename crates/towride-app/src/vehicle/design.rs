//! Design statics without a solver: static wheel loads from the centre of mass, and the
//! preload of each suspension spring that holds its corner at the design position.
//!
//! Each corner is a one-degree-of-freedom mechanism when the body is held and its
//! bushings are taken rigid. The principle of virtual work over one unit of its
//! coordinate s gives the preload P of its spring (or torsion element):
//!
//! ```text
//! sum_i m_i g . v_i  +  F_road . v_wheel  +  P dl/ds  =  0
//! ```
//!
//! with v_i the velocities of the masses (unsprung parts, the tyre belt) per unit s and
//! F_road the static road load on the wheel, vertical through the wheel centre. Every
//! bushing and torsion element is undeflected at the design position, so it does no work
//! there.

use serde::Serialize;

use super::air::{AirSpec, AirSpring};
use super::build::Builder;
use super::geom::{distance, norm, V};
use towride_mbs::input::InputError;
use towride_mbs::model::builder::{ElementHandle, SpringLine};
use towride_mbs::model::desc::{Force, Law};
use towride_mbs::model::math::{add, dot, scale};

/// The element of a corner that carries the static load, before its preload is known.
pub enum Preloaded {
    /// A coil spring (rate [N/m]) along `line`; its free length follows from the preload.
    Coil { line: Box<SpringLine>, rate: f64 },
    /// A bushing (index in `Model::forces`) whose torque about its z axis carries the
    /// load (a rubber torsion spring); rate of the torsion [N m/rad].
    Torsion { force: ElementHandle, rate: f64 },
    /// A levelled air spring along `line`: its pressure follows from the preload, its
    /// law from the gas ([`super::air`]).
    Air {
        line: Box<SpringLine>,
        spring: AirSpec,
    },
}

/// One corner of an axle: its mechanism rates and its load-carrying element.
pub struct Corner {
    pub wheel: String,
    pub rates: CornerRates,
    pub element: Preloaded,
    /// Where to complain if the element cannot hold the corner (located at its rate).
    pub complaint: InputError,
}

/// Sets the corner's element so it holds the design position under `load` [N]; returns
/// what was found, and the air spring when the element is one (its pressure and volume
/// are derived values).
pub fn finish(
    b: &mut Builder,
    c: Corner,
    load: f64,
) -> Result<(CornerDesign, Option<AirSpring>), InputError> {
    let g = b.model().gravity;
    let p = preload(&c.rates, g, load);
    let mr = motion_ratio(&c.rates, g);
    let unsprung_kg = reduced_mass(&c.rates, g);
    let (bump_steer_deg_m, camber_gain_deg_m) = toe_and_camber_rates(&c.rates, g);
    let complain = |message: String| InputError {
        message,
        ..c.complaint.clone()
    };
    let (element_rate, free_length_m, air) = match c.element {
        Preloaded::Coil { mut line, rate } => {
            let l = distance(&line.point_i, &line.point_j);
            // Linear coil: force = rate (free length - length), so the free length is
            // the design length plus the static compression.
            line.free_length = l + p / rate;
            if line.free_length <= 0.0 || p <= 0.0 {
                return Err(complain(format!("the spring would need {p:.1} N at its design length {l:.4} m (free length {:.4} m): check the hardpoints and loads", line.free_length)));
            }
            line.preload = 0.0;
            line.spring = Law::Linear(rate);
            let free = line.free_length;
            b.add(|m| m.spring(*line))?;
            (rate, Some(free), None)
        }
        Preloaded::Torsion { force, rate } => {
            if let Force::Bushing(bu) = &mut b.model_mut().forces[force] {
                bu.preload[5] = p;
            }
            (rate, None, None)
        }
        Preloaded::Air { mut line, spring } => {
            let air = spring
                .levelled(p, mr)
                .map_err(|e| complain(e.to_string()))?;
            // The table holds the force less the preload, zero at the design length.
            line.free_length = distance(&line.point_i, &line.point_j);
            line.preload = p;
            line.spring = spring.law(&air)?;
            b.add(|m| m.spring(*line))?;
            (air.rate(), None, Some(air))
        }
    };
    let design = CornerDesign {
        wheel: c.wheel,
        load_n: load,
        preload: p,
        motion_ratio: mr,
        wheel_rate_n_m: element_rate * mr * mr,
        free_length_m,
        unsprung_kg,
        bump_steer_deg_m,
        camber_gain_deg_m,
    };
    Ok((design, air))
}

/// Rates of one corner's mechanism per unit of its coordinate (body held).
#[derive(Clone, Debug)]
pub struct CornerRates {
    /// (mass [kg], velocity of its centre of mass [m/s]).
    pub masses: Vec<(f64, V)>,
    /// Velocity of the wheel centre [m/s].
    pub wheel_centre: V,
    /// Rate of the preloaded element's length [m] or angle [rad].
    pub element_rate: f64,
    /// Where the wheel centre is [m] (its side, for the sign of toe and camber).
    pub wheel_centre_at: V,
    /// Angular velocity of the wheel carrier per unit of the coordinate [rad]: its toe
    /// and camber rates.
    pub carrier_turn: V,
}

/// The force (or torque) the preloaded element must carry, repulsive positive, for the
/// corner to rest under the road load `load` [N] with gravity `g`.
pub fn preload(r: &CornerRates, g: V, load: f64) -> f64 {
    let up = scale(&g, -1.0 / norm(&g));
    let gravity: f64 = r.masses.iter().map(|(m, v)| m * dot(&g, v)).sum();
    let road = load * dot(&up, &r.wheel_centre);
    -(gravity + road) / r.element_rate
}

/// Ratio of the element's rate to the wheel centre's vertical rate.
pub fn motion_ratio(r: &CornerRates, g: V) -> f64 {
    let up = scale(&g, -1.0 / norm(&g));
    r.element_rate / dot(&up, &r.wheel_centre)
}

/// Total mass and centre of mass of point masses.
pub fn centre_of_mass(parts: &[(f64, V)]) -> (f64, V) {
    let m: f64 = parts.iter().map(|p| p.0).sum();
    let s = parts
        .iter()
        .fold([0.0; 3], |acc, (mi, x)| add(&acc, &scale(x, *mi)));
    (m, scale(&s, 1.0 / m))
}

/// Static vertical loads [N] on two lines of support across x (axles at `x_a` and
/// `x_b`) carrying weight `w` with its centre of mass at x = `x_cm`.
pub fn lever(w: f64, x_cm: f64, x_a: f64, x_b: f64) -> (f64, f64) {
    let fa = w * (x_cm - x_b) / (x_a - x_b);
    (fa, w - fa)
}

/// What the design statics found for one corner, for reports and checks.
#[derive(Clone, Debug, Serialize)]
pub struct CornerDesign {
    /// Name of the wheel body at the corner.
    pub wheel: String,
    /// Static road load at the design position [N].
    pub load_n: f64,
    /// Force (N) or torque (N m) in the spring element at the design position.
    pub preload: f64,
    /// Spring or torsion-element rate per unit wheel-centre travel (dimensionless for a
    /// spring, rad/m for a torsion element).
    pub motion_ratio: f64,
    /// Spring rate times the motion ratio squared [N/m].
    pub wheel_rate_n_m: f64,
    /// Coil spring free length (springs only) [m].
    pub free_length_m: Option<f64>,
    /// Mass moving with the wheel, reduced to the wheel centre's vertical motion by its
    /// kinetic energy [kg]: sum m_i (|v_i| / v_wheel.up)^2 (tyre belt included, rotary
    /// inertia left out).
    pub unsprung_kg: f64,
    /// Bump steer: toe angle per wheel-centre rise [deg/m], toe-in positive (SAE J670),
    /// at the design position with the body held and the bushings rigid.
    pub bump_steer_deg_m: f64,
    /// Camber per wheel-centre rise [deg/m], top of the wheel outward positive.
    pub camber_gain_deg_m: f64,
}

/// Bump steer and camber gain [deg/m] of a corner: its carrier's turn about the vertical
/// and the fore-aft axis per unit rise of the wheel centre. A left wheel (y > 0) toes in
/// when it turns clockwise seen from above and leans its top out when it turns about -x.
pub fn toe_and_camber_rates(r: &CornerRates, g: V) -> (f64, f64) {
    let up = scale(&g, -1.0 / norm(&g));
    let rise = dot(&up, &r.wheel_centre);
    let side = if r.wheel_centre_at[1] >= 0.0 {
        1.0
    } else {
        -1.0
    };
    let w = &r.carrier_turn;
    // `+ 0.0` turns a negative zero (a right wheel that does not steer) into zero.
    (
        (-side * dot(w, &up) / rise).to_degrees() + 0.0,
        (-side * w[0] / rise).to_degrees() + 0.0,
    )
}

/// Unsprung mass reduced to the wheel centre's vertical motion.
pub fn reduced_mass(r: &CornerRates, g: V) -> f64 {
    let up = scale(&g, -1.0 / norm(&g));
    let vw = dot(&up, &r.wheel_centre);
    r.masses
        .iter()
        .map(|(m, v)| {
            let k = dot(v, v).sqrt() / vw;
            m * k * k
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lever_rule_and_preload_of_a_lever() {
        let (fa, fb) = lever(1000.0, 1.0, 0.0, 4.0);
        assert!((fa - 750.0).abs() < 1e-12 && (fb - 250.0).abs() < 1e-12);
        // A massless arm pivoting at the origin, wheel at 1 m, spring at 0.5 m acting
        // vertically: the spring carries twice the wheel load.
        let r = CornerRates {
            masses: vec![],
            wheel_centre: [0.0, 0.0, 1.0],
            element_rate: -0.5,
            wheel_centre_at: [1.0, 0.0, 0.0],
            carrier_turn: [0.0, -1.0, 0.0],
        };
        assert!((preload(&r, [0.0, 0.0, -9.81], 100.0) - 200.0).abs() < 1e-12);
    }
}
