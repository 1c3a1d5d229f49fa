//! Two swinging halves on a common pivot axis, joined on the centreline by a torsion
//! element: the rigid twist-beam rear axle and the trailer's rubber torsion axle share
//! this layout.
//!
//! Each half (arm, half the beam or inner bar, stub axle) hangs on the carrier by a
//! bushing at its pivot; the halves meet on the centreline in a revolute joint about the
//! pivot axis with a torsion spring-damper: heave turns both halves together, roll twists
//! the torsion element. The torsion axis is the pivot axis (the line through both pivot
//! bushings), so the rigid variant's roll stiffness is the torsion element's and not the
//! bushings'. The trailing-arm axle has the same layout with its springs and dampers
//! standing on the arms; both name their points with [`ArmPoints`].

use serde::Deserialize;

use super::build::Builder;
use super::design::CornerRates;
use super::geom::{distance, mirror, turning, Axes, V, Z_ALONG_Y};
use super::props::{at, point, BushingLaws, Mass};
use super::wheel::{self, WheelHandle};
use towride_mbs::input::{InputError, Seg, Source};
use towride_mbs::model::builder::{BodyHandle, ElementHandle};
use towride_mbs::model::desc::{JointKind, Law};
use towride_mbs::model::elements::JointBushing;
use towride_mbs::model::math::dot;
use towride_mbs::tyre::Tyre;

/// `[hardpoints]` of a trailing arm with its spring and damper: left side, at the design
/// position [m].
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct ArmHardpoints {
    wheel_centre_m: [f64; 3],
    pivot_m: [f64; 3],
    spring_lower_m: [f64; 3],
    spring_upper_m: [f64; 3],
    damper_lower_m: [f64; 3],
    damper_upper_m: [f64; 3],
}

/// The points of a trailing arm with its spring and damper, one side [m].
#[derive(Clone, Debug)]
pub struct ArmPoints {
    pub wheel_centre: V,
    /// Centre of the arm's body bushing, on the pivot axis (along y).
    pub pivot: V,
    /// Spring seats on the arm and on the carrier.
    pub spring_lower: V,
    pub spring_upper: V,
    /// Damper mounts on the arm and on the carrier.
    pub damper_lower: V,
    pub damper_upper: V,
}

impl ArmHardpoints {
    /// The points, checked (at `p` of `src`): finite, on the left, no two that set a
    /// line coincident.
    pub fn check(&self, src: &Source, p: &[Seg]) -> Result<ArmPoints, InputError> {
        let hp = |k: &str, v: &[f64; 3]| point(src, &at(p, k), v);
        let pts = ArmPoints {
            wheel_centre: hp("wheel_centre_m", &self.wheel_centre_m)?,
            pivot: hp("pivot_m", &self.pivot_m)?,
            spring_lower: hp("spring_lower_m", &self.spring_lower_m)?,
            spring_upper: hp("spring_upper_m", &self.spring_upper_m)?,
            damper_lower: hp("damper_lower_m", &self.damper_lower_m)?,
            damper_upper: hp("damper_upper_m", &self.damper_upper_m)?,
        };
        for (k, v) in [("wheel_centre_m", pts.wheel_centre), ("pivot_m", pts.pivot)] {
            if v[1] <= 0.0 {
                return Err(src.error(
                    &at(&at(p, k), 1),
                    "give the left side (y > 0); the right side is mirrored",
                ));
            }
        }
        // Coincident ends are the hardpoints' fault, not the element's line that the
        // builder would otherwise blame (named in no file).
        for (k, a, other, b, what) in [
            (
                "wheel_centre_m",
                pts.wheel_centre,
                "pivot_m",
                pts.pivot,
                "the trailing arm",
            ),
            (
                "spring_upper_m",
                pts.spring_upper,
                "spring_lower_m",
                pts.spring_lower,
                "the spring's line",
            ),
            (
                "damper_upper_m",
                pts.damper_upper,
                "damper_lower_m",
                pts.damper_lower,
                "the damper's line",
            ),
        ] {
            if distance(&a, &b) < 1e-6 {
                return Err(src.error(
                    &at(p, k),
                    format!("coincides with `{other}`; the two set {what}"),
                ));
            }
        }
        Ok(pts)
    }
}

impl ArmPoints {
    /// The right side's points (itself when `right` is false).
    pub fn side(&self, right: bool) -> ArmPoints {
        let m = |p: V| if right { mirror(p) } else { p };
        ArmPoints {
            wheel_centre: m(self.wheel_centre),
            pivot: m(self.pivot),
            spring_lower: m(self.spring_lower),
            spring_upper: m(self.spring_upper),
            damper_lower: m(self.damper_lower),
            damper_upper: m(self.damper_upper),
        }
    }
}

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
            wheel_centre_at: rim.cm,
            carrier_turn: y,
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
