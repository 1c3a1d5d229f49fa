//! Two swinging halves on a common pivot axis, joined on the centreline by a torsion
//! element: the rigid twist-beam rear axle and the trailer's rubber torsion axle share
//! this layout.
//!
//! Each half (arm, half the beam or inner bar, stub axle) hangs on the carrier by a
//! bushing at its pivot; the halves meet on the centreline in a revolute joint about the
//! pivot axis with a torsion spring-damper: heave turns both halves together, roll twists
//! the torsion element. The torsion axis is the pivot axis (the line through both pivot
//! bushings), so the rigid variant's roll stiffness is the torsion element's and not the
//! bushings'.

use super::build::Builder;
use super::design::CornerRates;
use super::geom::{mirror, turning, Axes, V, Z_ALONG_Y};
use super::props::{BushingLaws, Mass};
use super::wheel::{self, WheelHandle};
use towride_mbs::input::InputError;
use towride_mbs::model::builder::{BodyHandle, ElementHandle};
use towride_mbs::model::desc::{JointKind, Law};
use towride_mbs::model::elements::JointBushing;
use towride_mbs::model::math::dot;
use towride_mbs::tyre::Tyre;

/// A swinging-half axle described by its left side.
pub struct Spec<'a> {
    /// Body name prefix of the halves (`<prefix>_<wheel>`).
    pub prefix: &'a str,
    /// Short wheel names, left then right.
    pub wheels: [&'a str; 2],
    /// Name of the centre joint and torsion element.
    pub centre: &'a str,
    /// The body the axle hangs on.
    pub carrier: BodyHandle,
    pub pivot: V,
    pub half: Mass,
    pub rim: Mass,
    pub bushing: BushingLaws,
    pub torsion: (Law, Law),
    pub joints_as_bushings: Option<JointBushing>,
}

pub struct Built {
    pub halves: [BodyHandle; 2],
    pub wheels: Vec<WheelHandle>,
    /// Pivot bushings.
    pub bushings: [ElementHandle; 2],
    /// Per side: velocities per unit rotation of the half about +y (`element_rate` 0:
    /// the caller names the load-carrying element).
    pub rates: Vec<CornerRates>,
    /// Per side: rate of rotation about the pivot bushing's own z axis.
    pub bushing_rates: [f64; 2],
}

/// The halves on their bushings with their wheels; [`join`] adds the centre joint (a
/// flexible cross member joins them otherwise).
pub fn build(b: &mut Builder, s: &Spec, tyre: &Tyre) -> Result<Built, InputError> {
    let y = [0.0, 1.0, 0.0];
    let belt = wheel::tyre_own_mass(tyre);
    let mut halves = Vec::new();
    let mut bushings = Vec::new();
    let mut wheels = Vec::new();
    let mut rates = Vec::new();
    let mut bushing_rates = [0.0; 2];
    for (k, side) in [false, true].into_iter().enumerate() {
        let name = s.wheels[k];
        let (half, rim) = (s.half.side(side), s.rim.side(side));
        let pivot = if side { mirror(s.pivot) } else { s.pivot };
        let h = b.body(&format!("{}_{name}", s.prefix), &half)?;
        let laws = s.bushing.side(side);
        let bu = b.bushing(
            &format!("{}_bushing_{name}", s.prefix),
            Some(h),
            Some(s.carrier),
            pivot,
            &laws.axes,
            &laws,
            [0.0; 6],
        )?;
        let wh = wheel::add(b, name, h, &rim, tyre)?;
        let vw = turning(&pivot, &y, &rim.cm);
        rates.push(CornerRates {
            masses: vec![
                (half.mass, turning(&pivot, &y, &half.cm)),
                (rim.mass, vw),
                (belt, vw),
            ],
            wheel_centre: vw,
            element_rate: 0.0,
        });
        bushing_rates[k] = dot(&col(&laws.axes, 2), &y);
        halves.push(h);
        bushings.push(bu);
        wheels.push(wh);
    }
    Ok(Built {
        halves: [halves[0], halves[1]],
        wheels,
        bushings: [bushings[0], bushings[1]],
        rates,
        bushing_rates,
    })
}

/// Joins the halves on the centreline: a revolute joint about y with the torsion element.
pub fn join(b: &mut Builder, s: &Spec, halves: [BodyHandle; 2]) -> Result<(), InputError> {
    let axes = Z_ALONG_Y;
    let centre = [s.pivot[0], 0.0, s.pivot[2]];
    b.add(|m| {
        m.joint(
            s.centre,
            JointKind::Revolute,
            Some(halves[0]),
            Some(halves[1]),
            centre,
            &axes,
            s.joints_as_bushings.as_ref(),
        )
    })?;
    b.torsion(
        &format!("{}_torsion", s.centre),
        Some(halves[0]),
        Some(halves[1]),
        centre,
        &axes,
        s.torsion.0.clone(),
        s.torsion.1.clone(),
    )?;
    Ok(())
}

fn col(a: &Axes, k: usize) -> V {
    [a[0][k], a[1][k], a[2][k]]
}
