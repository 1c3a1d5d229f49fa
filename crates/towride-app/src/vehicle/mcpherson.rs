//! McPherson strut front axle. One property set describes the left side; the right side
//! is its mirror image (y -> -y).
//!
//! Parts per side: lower control arm (`lca_<w>`) on two body bushings; knuckle with the
//! strut tube (`knuckle_<w>`) on the arm's ball joint; piston rod with the top mount's
//! inner part (`strut_rod_<w>`) sliding in the tube (cylindrical joint along the strut
//! axis) and held by the top-mount bushing; tie rod (`tie_rod_<w>`) from the steering
//! rack, fixed on the body (universal joint), to the steering arm (ball joint); the
//! wheel on its bearing. The coil spring bears on the knuckle's spring seat and on the
//! body at the top mount (the spring path of a decoupled top mount); the damper and its
//! bump and rebound stops act between tube and rod.

use serde::Deserialize;

use std::path::Path;

use super::axle::{Axle, AxleData, AxleSlot, AxleTemplate};
use super::build::Builder;
use super::design::{Corner, CornerRates, Preloaded};
use super::geom::{frame, norm, unit, V};
use super::props::{
    joints, point, stop, BushingLaws, BushingProps, DamperProps, JointsProps, Mass, MassProps,
    WheelProps,
};
use super::strut::{rates, StrutPoints};
use super::wheel::{self, WheelHandle};
use towride_mbs::input::{InputError, Source};
use towride_mbs::model::builder::{BodyHandle, Link, SpringLine};
use towride_mbs::model::desc::{JointKind, Law, MotionDof, Stop};
use towride_mbs::model::elements::{JointBushing, StopSpec};
use towride_mbs::model::math::{cross, scale, sub};
use towride_mbs::path;
use towride_mbs::tyre::Tyre;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    hardpoints: Hardpoints,
    knuckle: MassProps,
    lower_arm: MassProps,
    strut_rod: MassProps,
    tie_rod: MassProps,
    /// The steering rack between the tie rods' inner joints, built only when a scene
    /// steers; without steering the tie rods sit on the body.
    steering_rack: Option<MassProps>,
    wheel: WheelProps,
    spring: Spring,
    damper: DamperProps,
    bump_stop: Option<StopSpec>,
    rebound_stop: Option<StopSpec>,
    lower_arm_front_bushing: BushingProps,
    lower_arm_rear_bushing: BushingProps,
    top_mount: BushingProps,
    joints: JointsProps,
}

/// Left-side hardpoints, vehicle coordinates at the design position [m].
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Hardpoints {
    wheel_centre_m: [f64; 3],
    lower_arm_front_m: [f64; 3],
    lower_arm_rear_m: [f64; 3],
    ball_joint_m: [f64; 3],
    strut_lower_m: [f64; 3],
    strut_top_m: [f64; 3],
    spring_seat_m: [f64; 3],
    tie_rod_inner_m: [f64; 3],
    tie_rod_outer_m: [f64; 3],
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Spring {
    stiffness_n_m: f64,
}

/// The McPherson strut axle template.
pub struct McPherson;

impl AxleTemplate for McPherson {
    fn name(&self) -> &'static str {
        "mcpherson"
    }

    fn read(
        &self,
        b: &mut Builder,
        file: &Path,
        slot: &AxleSlot,
    ) -> Result<Box<dyn AxleData>, InputError> {
        let src = b.read(file)?;
        if slot.cross_member.is_some() {
            return Err(b.refused(towride_mbs::model::ModelError::Unsupported(
                "the McPherson axle has no variants".into(),
            )));
        }
        Ok(Box::new(read(src, slot.tyre)?))
    }
}

/// The property file, checked (left side).
struct Props {
    points: StrutPoints,
    knuckle: Mass,
    lca: Mass,
    rod: Mass,
    tie: Mass,
    rack: Option<Mass>,
    /// Where a scene that steers is told the file has no rack.
    rack_at: InputError,
    rim: Mass,
    belt: f64,
    spring: f64,
    damper: Law,
    bump: Option<Stop>,
    rebound: Option<Stop>,
    lca_front: BushingLaws,
    lca_rear: BushingLaws,
    top_mount: BushingLaws,
    joints: Option<JointBushing>,
    /// Where the design statics complain about the spring.
    spring_at: InputError,
    /// The file (the kinematics locate a singular geometry in it).
    src: Source,
}

fn read(file: Source, tyre: &Tyre) -> Result<Props, InputError> {
    let src = &file;
    let f: File = src.parse()?;
    let h = &f.hardpoints;
    let hp = |k: &str, v: &[f64; 3]| point(src, &path!["hardpoints", k], v);
    let pts = StrutPoints {
        wheel_centre: hp("wheel_centre_m", &h.wheel_centre_m)?,
        lower_arm_front: hp("lower_arm_front_m", &h.lower_arm_front_m)?,
        lower_arm_rear: hp("lower_arm_rear_m", &h.lower_arm_rear_m)?,
        ball_joint: hp("ball_joint_m", &h.ball_joint_m)?,
        strut_lower: hp("strut_lower_m", &h.strut_lower_m)?,
        strut_top: hp("strut_top_m", &h.strut_top_m)?,
        spring_seat: hp("spring_seat_m", &h.spring_seat_m)?,
        tie_rod_inner: hp("tie_rod_inner_m", &h.tie_rod_inner_m)?,
        tie_rod_outer: hp("tie_rod_outer_m", &h.tie_rod_outer_m)?,
    };
    if pts.wheel_centre[1] <= 0.0 {
        return Err(src.error(
            &path!["hardpoints", "wheel_centre_m", 1],
            "give the left side (y > 0); the right side is mirrored",
        ));
    }
    // Pairs of hardpoints that set an axis: coincident ones are the hardpoints' fault,
    // not the axis's (which no file names).
    for (k, a, other, b, what) in [
        ("lower_arm_rear_m", &pts.lower_arm_rear, "lower_arm_front_m", &pts.lower_arm_front, "the lower arm's pivot axis"),
        ("strut_top_m", &pts.strut_top, "strut_lower_m", &pts.strut_lower, "the strut axis"),
        ("tie_rod_outer_m", &pts.tie_rod_outer, "tie_rod_inner_m", &pts.tie_rod_inner, "the tie rod"),
    ] {
        if norm(&sub(a, b)) < 1e-6 {
            return Err(src.error(
                &path!["hardpoints", k],
                format!("coincides with `{other}`; the two set {what}"),
            ));
        }
    }
    // The strut's frame takes x across it, the tie rod's universal joint pins across it.
    let along = |a: &V, b: &V, e: &V| norm(&cross(&unit(&sub(a, b)), e)) < 1e-6;
    if along(&pts.strut_top, &pts.strut_lower, &[1.0, 0.0, 0.0]) {
        return Err(src.error(
            &path!["hardpoints", "strut_top_m"],
            "the strut (strut_lower_m to strut_top_m) must not lie along x",
        ));
    }
    if along(&pts.tie_rod_outer, &pts.tie_rod_inner, &[0.0, 0.0, 1.0]) {
        return Err(src.error(
            &path!["hardpoints", "tie_rod_outer_m"],
            "the tie rod (tie_rod_inner_m to tie_rod_outer_m) must not be vertical",
        ));
    }
    let pivot = unit(&sub(&pts.lower_arm_front, &pts.lower_arm_rear));
    let strut = unit(&sub(&pts.strut_top, &pts.strut_lower));
    Ok(Props {
        knuckle: f.knuckle.check(src, &path!["knuckle"])?,
        lca: f.lower_arm.check(src, &path!["lower_arm"])?,
        rod: f.strut_rod.check(src, &path!["strut_rod"])?,
        tie: f.tie_rod.check(src, &path!["tie_rod"])?,
        rack: f
            .steering_rack
            .as_ref()
            .map(|r| r.check(src, &path!["steering_rack"]))
            .transpose()?,
        rack_at: src.error(
            &path!["steering_rack"],
            "the scene steers, but this axle has no [steering_rack]",
        ),
        rim: wheel::rim_mass(src, &path!["wheel"], &f.wheel, tyre, pts.wheel_centre)?,
        belt: wheel::tyre_own_mass(tyre),
        spring: src.positive(&path!["spring", "stiffness_n_m"], f.spring.stiffness_n_m)?,
        damper: f.damper.check(src, &path!["damper"])?,
        bump: stop(src, &path!["bump_stop"], &f.bump_stop)?,
        rebound: stop(src, &path!["rebound_stop"], &f.rebound_stop)?,
        lca_front: f.lower_arm_front_bushing.check(
            src,
            &path!["lower_arm_front_bushing"],
            pivot,
        )?,
        lca_rear: f
            .lower_arm_rear_bushing
            .check(src, &path!["lower_arm_rear_bushing"], pivot)?,
        top_mount: f.top_mount.check(src, &path!["top_mount"], strut)?,
        joints: joints(src, &path!["joints"], &f.joints)?,
        spring_at: src.error(&path!["spring", "stiffness_n_m"], ""),
        points: pts,
        src: file,
    })
}

impl AxleData for Props {
    fn build(self: Box<Self>, b: &mut Builder, slot: &AxleSlot) -> Result<Axle, InputError> {
        let mut out = Axle {
            wheels: Vec::new(),
            corners: Vec::new(),
            body_mounts: Vec::new(),
            flexible: None,
        };
        let rack = match slot.steering {
            Some(travel) => Some(rack(b, &self, slot, travel)?),
            None => None,
        };
        for (right, name) in [(false, slot.wheels[0]), (true, slot.wheels[1])] {
            let (wheel, corner, top) = side(b, &self, slot, rack, right, name)?;
            out.wheels.push(wheel);
            out.corners.push(corner);
            out.body_mounts.push(top);
        }
        Ok(out)
    }
}

/// The steering rack: a body sliding across the car on a translational joint at the tie
/// rods' inner joints' height, its travel prescribed (`travel`, to the left [m]).
fn rack(
    b: &mut Builder,
    c: &Props,
    slot: &AxleSlot,
    travel: &towride_mbs::model::function::TimeFunction,
) -> Result<BodyHandle, InputError> {
    let m = c.rack.as_ref().ok_or_else(|| c.rack_at.clone())?;
    let rack = b.body(&format!("{}steering_rack", slot.prefix), m)?;
    let at = [c.points.tie_rod_inner[0], 0.0, c.points.tie_rod_inner[2]];
    let axes = frame([0.0, 1.0, 0.0], Some([1.0, 0.0, 0.0])).expect("y is not along x");
    // Ideal whatever `joints_as_bushings` says: the motion prescribes it.
    let link = b.add(|mb| {
        mb.ideal_joint(
            "steering_rack",
            JointKind::Translational,
            Some(rack),
            Some(slot.carrier),
            at,
            &axes,
        )
    })?;
    let Link::Joint(joint) = link else {
        unreachable!("an ideal joint is a joint")
    };
    b.add(|mb| {
        mb.motion(
            "steering_rack",
            joint,
            Some(MotionDof::Translation),
            travel.clone(),
            false,
        )
    })?;
    Ok(rack)
}

/// One side: parts, joints, bushings, damper, wheel; the spring awaits its load.
fn side(
    b: &mut Builder,
    c: &Props,
    slot: &AxleSlot,
    rack: Option<BodyHandle>,
    right: bool,
    name: &str,
) -> Result<(WheelHandle, Corner, V), InputError> {
    let (body, tyre, prefix) = (slot.carrier, slot.tyre, slot.prefix);
    let p = c.points.side(right);
    let (kn_m, lca_m, rod_m, tie_m) = (
        c.knuckle.side(right),
        c.lca.side(right),
        c.rod.side(right),
        c.tie.side(right),
    );
    let lca = b.body(&format!("{prefix}lca_{name}"), &lca_m)?;
    let kn = b.body(&format!("{prefix}knuckle_{name}"), &kn_m)?;
    let rod = b.body(&format!("{prefix}strut_rod_{name}"), &rod_m)?;
    let tie = b.body(&format!("{prefix}tie_rod_{name}"), &tie_m)?;
    for (what, laws, bi, at) in [
        ("lca_front_bushing", &c.lca_front, lca, p.lower_arm_front),
        ("lca_rear_bushing", &c.lca_rear, lca, p.lower_arm_rear),
        ("top_mount", &c.top_mount, rod, p.strut_top),
    ] {
        let l = laws.side(right);
        b.bushing(
            &format!("{what}_{name}"),
            Some(bi),
            Some(body),
            at,
            &l.axes,
            &l,
            [0.0; 6],
        )?;
    }
    let strut_axes =
        frame(unit(&sub(&p.strut_top, &p.strut_lower)), Some([1.0, 0.0, 0.0])).expect("strut axis not along x");
    let ball_axes = frame([0.0, 0.0, 1.0], None).expect("vertical");
    // Tie rod: universal at the rack (pins across the rod, so its spin is held), ball
    // joint at the steering arm.
    let d = unit(&sub(&p.tie_rod_outer, &p.tie_rod_inner));
    let pin_j = unit(&sub(&[0.0, 0.0, 1.0], &scale(&d, d[2])));
    let u_axes = frame(pin_j, Some(cross(&d, &pin_j))).expect("tie rod not vertical");
    let jb = c.joints.as_ref();
    for (what, kind, bi, bj, at, axes) in [
        ("ball_joint", JointKind::Spherical, kn, lca, p.ball_joint, &ball_axes),
        ("strut", JointKind::Cylindrical, rod, kn, p.strut_lower, &strut_axes),
        (
            "tie_rod_inner",
            JointKind::Universal,
            tie,
            rack.unwrap_or(body),
            p.tie_rod_inner,
            &u_axes,
        ),
        (
            "tie_rod_outer",
            JointKind::Spherical,
            tie,
            kn,
            p.tie_rod_outer,
            &ball_axes,
        ),
    ] {
        b.add(|m| m.joint(
            &format!("{what}_{name}"),
            kind,
            Some(bi),
            Some(bj),
            at,
            axes,
            jb,
        ))?;
    }
    let mut damper = SpringLine::new(&format!("damper_{name}"), Some(kn), p.strut_lower, Some(rod), p.strut_top);
    damper.damper = c.damper.clone();
    damper.bump_stop = c.bump.clone();
    damper.rebound_stop = c.rebound.clone();
    b.add(|m| m.spring(damper))?;
    let rim = c.rim.side(right);
    let wheel = wheel::add(b, name, kn, &rim, tyre)?;
    let v = rates(&p, &c.src, &[kn_m.cm, lca_m.cm, rod_m.cm, tie_m.cm])?;
    let rates = CornerRates {
        masses: vec![
            (kn_m.mass, v.parts[0]),
            (lca_m.mass, v.parts[1]),
            (rod_m.mass, v.parts[2]),
            (tie_m.mass, v.parts[3]),
            (rim.mass, v.wheel_centre),
            (c.belt, v.wheel_centre),
        ],
        wheel_centre: v.wheel_centre,
        element_rate: v.spring,
        wheel_centre_at: p.wheel_centre,
        carrier_turn: v.knuckle,
    };
    let corner = Corner {
        wheel: name.to_string(),
        rates,
        element: Preloaded::Coil {
            line: Box::new(SpringLine::new(
                &format!("spring_{name}"),
                Some(kn),
                p.spring_seat,
                Some(body),
                p.strut_top,
            )),
            rate: c.spring,
        },
        complaint: c.spring_at.clone(),
    };
    Ok((wheel, corner, p.strut_top))
}
