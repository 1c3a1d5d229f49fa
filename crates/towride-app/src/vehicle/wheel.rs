//! A wheel: the rim body on a revolute bearing to its carrier (knuckle, trailing arm or
//! swing arm), the wheel-centre markers and the tyre.
//!
//! The rim body carries the wheel's own mass plus the part of the tyre that turns with
//! the rim: for the rigid-ring tyre everything but the belt (which the tyre integrates
//! itself, `TyreParams::rim_share`), for the point follower (massless) the whole tyre. So
//! the vehicle's mass does not depend on the tyre model.

use nalgebra::Vector3;

use super::build::{Builder, Link};
use super::geom::{IDENTITY, V, Z_ALONG_Y};
use super::props::{at, Mass, WheelProps};
use towride_mbs::input::{InputError, Seg, Source};
use towride_mbs::model::builder::{BodyHandle, MarkerHandle, TyreHandle};
use towride_mbs::model::desc::{JointKind, Model};
use towride_mbs::tyre::Tyre;

/// What the scene and the outputs need of a wheel.
#[derive(Clone, Debug)]
pub struct WheelHandle {
    /// Short name: fl, fr, rl, rr, tl, tr.
    pub name: String,
    /// The rim body.
    pub body: BodyHandle,
    /// The body the bearing sits on.
    pub carrier: BodyHandle,
    /// Marker on the rim at the wheel centre, axes of the subsystem (y = spin axis, left).
    pub centre: MarkerHandle,
    /// Marker on the carrier at the wheel centre, same axes (takes the drive reaction).
    pub carrier_centre: MarkerHandle,
    /// The bearing.
    pub bearing: Link,
    /// The tyre.
    pub tyre: TyreHandle,
    /// Wheel centre at the design position, subsystem coordinates [m].
    pub design_centre: V,
}

/// Rim mass properties (wheel plus the tyre's share that turns with it).
pub fn rim_mass(
    src: &Source,
    p: &[Seg],
    w: &WheelProps,
    tyre: &Tyre,
    centre: V,
) -> Result<Mass, InputError> {
    let m = src.positive(&at(p, "mass_kg"), w.mass_kg)?;
    let spin = src.positive(&at(p, "spin_inertia_kg_m2"), w.spin_inertia_kg_m2)?;
    let tilt = src.positive(&at(p, "tilt_inertia_kg_m2"), w.tilt_inertia_kg_m2)?;
    if 2.0 * tilt < spin {
        return Err(src.error(
            &at(p, "tilt_inertia_kg_m2"),
            format!("must be at least half the spin inertia ({spin} kg m^2): a wheel is a disc or a ring at most"),
        ));
    }
    let (tm, ti) = tyre_on_rim(tyre);
    // A tyre is close to a thin ring: its inertia about a diameter is half the spin one.
    Ok(Mass {
        mass: m + tm,
        cm: centre,
        inertia: [
            [tilt + 0.5 * ti, 0.0, 0.0],
            [0.0, spin + ti, 0.0],
            [0.0, 0.0, tilt + 0.5 * ti],
        ],
    })
}

/// Mass [kg] and spin inertia [kg m^2] of the tyre that move with the rim.
pub fn tyre_on_rim(tyre: &Tyre) -> (f64, f64) {
    match tyre {
        Tyre::RigidRing(r) => r.p.rim_share(),
        Tyre::PointFollower(r) => (r.p.mass, r.p.iyy),
    }
}

/// Mass the tyre integrates itself (the rigid ring's belt) [kg].
pub fn tyre_own_mass(tyre: &Tyre) -> f64 {
    match tyre {
        Tyre::RigidRing(r) => r.p.belt_mass,
        Tyre::PointFollower(_) => 0.0,
    }
}

/// Adds the rim body `wheel_<name>`, its bearing on `carrier` and the tyre `tyre_<name>`.
pub fn add(
    b: &mut Builder,
    name: &str,
    carrier: BodyHandle,
    rim: &Mass,
    tyre: &Tyre,
) -> Result<WheelHandle, InputError> {
    let centre = rim.cm;
    let body = b.body(&format!("wheel_{name}"), rim)?;
    // The bearing stays an ideal revolute joint even when the other joints become
    // bushings: a bushing's rotation-vector deflection cannot follow the wheel's spin.
    let link = b.add(|m| {
        m.ideal_joint(
            &format!("bearing_{name}"),
            JointKind::Revolute,
            Some(body),
            Some(carrier),
            centre,
            &Z_ALONG_Y,
        )
    })?;
    let centre_marker = b.add(|m| {
        m.marker(
            &format!("wheel_{name}.centre"),
            Some(body),
            centre,
            &IDENTITY,
        )
    })?;
    let carrier_centre =
        b.add(|m| m.marker(&format!("hub_{name}"), Some(carrier), centre, &IDENTITY))?;
    let mut tyre = tyre.clone();
    let g = b.model().gravity;
    tyre.set_gravity(Vector3::new(g[0], g[1], g[2]));
    let tyre = b.mb.tyre(&format!("tyre_{name}"), centre_marker, tyre);
    Ok(WheelHandle {
        name: name.to_string(),
        body,
        carrier,
        centre: centre_marker,
        carrier_centre,
        bearing: link,
        tyre,
        design_centre: centre,
    })
}

/// Every body moves forward at `speed`; wheels spin at the free-rolling rate of their
/// tyre at the design deflection.
pub fn set_speed(model: &mut Model, wheels: &[WheelHandle], speed: f64) {
    for body in &mut model.bodies {
        body.velocity = [speed, 0.0, 0.0];
        body.angular_velocity = [0.0; 3];
    }
    for w in wheels {
        let p = model.tyres[w.tyre].tyre.params().clone();
        let rho = p.r0 - w.design_centre[2];
        let mut omega = speed / p.r0;
        for _ in 0..50 {
            omega = speed / p.rolling_radius(rho, omega);
        }
        model.bodies[w.body].angular_velocity = [0.0, omega, 0.0];
    }
}
