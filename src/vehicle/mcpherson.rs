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

use super::build::{Builder, Line};
use super::design::{Corner, CornerRates, Preloaded};
use super::geom::{frame, length_rate, mirror, mirror_axes, turning, unit, Axes, V};
use super::props::{
    joints, point, stop, BushingProps, DamperProps, JointsProps, MassProps, WheelProps,
};
use super::wheel::{self, WheelHandle};
use crate::input::{InputError, Source};
use crate::model::desc::{JointKind, Law};
use crate::model::math::{add, cross, dot, scale, sub};
use crate::model::spec::StopSpec;
use crate::path;
use crate::tyre::Tyre;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    hardpoints: Hardpoints,
    knuckle: MassProps,
    lower_arm: MassProps,
    strut_rod: MassProps,
    tie_rod: MassProps,
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

/// Named points of one side.
struct Pts {
    w: V,
    af: V,
    ar: V,
    b: V,
    l: V,
    t: V,
    q: V,
    s: V,
    r: V,
}

/// The built front axle: wheels (left, right) and the corners awaiting their loads.
pub struct Front {
    pub wheels: Vec<WheelHandle>,
    pub corners: Vec<Corner>,
    /// Top-mount centres (left, right), vehicle coordinates.
    pub top_mounts: Vec<V>,
}

/// Reads `file` and adds both sides, attached to the car body `body`.
pub fn build(
    b: &mut Builder,
    file: &std::path::Path,
    body: usize,
    tyre: &Tyre,
) -> Result<Front, InputError> {
    let src = Source::read(file)?;
    let f: File = src.parse()?;
    let h = &f.hardpoints;
    let hp = |k: &str, v: &[f64; 3]| point(&src, &path!["hardpoints", k], v);
    let left = Pts {
        w: hp("wheel_centre_m", &h.wheel_centre_m)?,
        af: hp("lower_arm_front_m", &h.lower_arm_front_m)?,
        ar: hp("lower_arm_rear_m", &h.lower_arm_rear_m)?,
        b: hp("ball_joint_m", &h.ball_joint_m)?,
        l: hp("strut_lower_m", &h.strut_lower_m)?,
        t: hp("strut_top_m", &h.strut_top_m)?,
        q: hp("spring_seat_m", &h.spring_seat_m)?,
        s: hp("tie_rod_inner_m", &h.tie_rod_inner_m)?,
        r: hp("tie_rod_outer_m", &h.tie_rod_outer_m)?,
    };
    if left.w[1] <= 0.0 {
        return Err(src.error(
            &path!["hardpoints", "wheel_centre_m", 1],
            "give the left side (y > 0); the right side is mirrored",
        ));
    }
    let knuckle = f.knuckle.check(&src, &path!["knuckle"])?;
    let lca = f.lower_arm.check(&src, &path!["lower_arm"])?;
    let rod = f.strut_rod.check(&src, &path!["strut_rod"])?;
    let tie = f.tie_rod.check(&src, &path!["tie_rod"])?;
    let rim = wheel::rim_mass(&src, &path!["wheel"], &f.wheel, tyre, left.w)?;
    let k_spring = src.positive(&path!["spring", "stiffness_n_m"], f.spring.stiffness_n_m)?;
    let damper = f.damper.check(&src, &path!["damper"])?;
    let bump = stop(&src, &path!["bump_stop"], &f.bump_stop)?;
    let rebound = stop(&src, &path!["rebound_stop"], &f.rebound_stop)?;
    let pivot = unit(&sub(&left.af, &left.ar));
    let strut = unit(&sub(&left.t, &left.l));
    let bf = f
        .lower_arm_front_bushing
        .check(&src, &path!["lower_arm_front_bushing"], pivot)?;
    let br = f
        .lower_arm_rear_bushing
        .check(&src, &path!["lower_arm_rear_bushing"], pivot)?;
    let tm = f.top_mount.check(&src, &path!["top_mount"], strut)?;
    let jb = joints(&src, &path!["joints"], &f.joints)?;
    let belt = wheel::tyre_own_mass(tyre);
    let mut out = Front {
        wheels: Vec::new(),
        corners: Vec::new(),
        top_mounts: Vec::new(),
    };
    for (side, name) in [(false, "fl"), (true, "fr")] {
        let m = |p: V| if side { mirror(p) } else { p };
        let ma = |a: &Axes| if side { mirror_axes(a) } else { *a };
        let pt = Pts {
            w: m(left.w),
            af: m(left.af),
            ar: m(left.ar),
            b: m(left.b),
            l: m(left.l),
            t: m(left.t),
            q: m(left.q),
            s: m(left.s),
            r: m(left.r),
        };
        let mirrored = |x: &super::props::Mass| super::props::Mass {
            cm: m(x.cm),
            inertia: if side {
                mirror_inertia(&x.inertia)
            } else {
                x.inertia
            },
            mass: x.mass,
        };
        let lca_id = b.body(&format!("lca_{name}"), &mirrored(&lca));
        let kn = b.body(&format!("knuckle_{name}"), &mirrored(&knuckle));
        let rd = b.body(&format!("strut_rod_{name}"), &mirrored(&rod));
        let tr = b.body(&format!("tie_rod_{name}"), &mirrored(&tie));
        let mut bf_s = bf.clone();
        bf_s.axes = ma(&bf.axes);
        let mut br_s = br.clone();
        br_s.axes = ma(&br.axes);
        let mut tm_s = tm.clone();
        tm_s.axes = ma(&tm.axes);
        let z = [0.0; 6];
        b.bushing(
            &format!("lca_front_bushing_{name}"),
            Some(lca_id),
            Some(body),
            pt.af,
            &bf_s.axes,
            &bf_s,
            z,
        );
        b.bushing(
            &format!("lca_rear_bushing_{name}"),
            Some(lca_id),
            Some(body),
            pt.ar,
            &br_s.axes,
            &br_s,
            z,
        );
        b.bushing(
            &format!("top_mount_{name}"),
            Some(rd),
            Some(body),
            pt.t,
            &tm_s.axes,
            &tm_s,
            z,
        );
        let axis = unit(&sub(&pt.t, &pt.l));
        let strut_axes = frame(axis, Some([1.0, 0.0, 0.0])).expect("strut axis not along x");
        let ball_axes = frame([0.0, 0.0, 1.0], None).expect("vertical");
        let jbr = jb.as_ref();
        b.joint(
            &format!("ball_joint_{name}"),
            JointKind::Spherical,
            Some(kn),
            Some(lca_id),
            pt.b,
            &ball_axes,
            jbr,
        );
        b.joint(
            &format!("strut_{name}"),
            JointKind::Cylindrical,
            Some(rd),
            Some(kn),
            pt.l,
            &strut_axes,
            jbr,
        );
        // Tie rod: universal at the rack (pins across the rod, so its spin is held),
        // ball joint at the steering arm.
        let d = unit(&sub(&pt.r, &pt.s));
        let pin_j = unit(&sub(&[0.0, 0.0, 1.0], &scale(&d, d[2])));
        let pin_i = cross(&d, &pin_j);
        let u_axes = frame(pin_j, Some(pin_i)).expect("tie rod not vertical");
        b.joint(
            &format!("tie_rod_inner_{name}"),
            JointKind::Universal,
            Some(tr),
            Some(body),
            pt.s,
            &u_axes,
            jbr,
        );
        b.joint(
            &format!("tie_rod_outer_{name}"),
            JointKind::Spherical,
            Some(tr),
            Some(kn),
            pt.r,
            &ball_axes,
            jbr,
        );
        b.line(Line {
            name: format!("damper_{name}"),
            body_i: Some(kn),
            point_i: pt.l,
            body_j: Some(rd),
            point_j: pt.t,
            free_length: super::geom::distance(&pt.l, &pt.t),
            preload: 0.0,
            spring: Law::Linear(0.0),
            damper: damper.clone(),
            bump_stop: bump.clone(),
            rebound_stop: rebound.clone(),
        });
        let wh = wheel::add(b, name, kn, &mirrored(&rim), tyre);
        let cms = [
            mirrored(&knuckle).cm,
            mirrored(&lca).cm,
            mirrored(&rod).cm,
            mirrored(&tie).cm,
        ];
        let v = rates(&pt, &src, &cms)?;
        let r = CornerRates {
            masses: vec![
                (knuckle.mass, v.parts[0]),
                (lca.mass, v.parts[1]),
                (rod.mass, v.parts[2]),
                (tie.mass, v.parts[3]),
                (rim.mass, v.wheel_centre),
                (belt, v.wheel_centre),
            ],
            wheel_centre: v.wheel_centre,
            element_rate: v.element_rate,
        };
        out.corners.push(Corner {
            wheel: name.to_string(),
            rates: r,
            element: Preloaded::Coil {
                line: Box::new(Line {
                    name: format!("spring_{name}"),
                    body_i: Some(kn),
                    point_i: pt.q,
                    body_j: Some(body),
                    point_j: pt.t,
                    free_length: 0.0,
                    preload: 0.0,
                    spring: Law::Linear(k_spring),
                    damper: Law::Linear(0.0),
                    bump_stop: None,
                    rebound_stop: None,
                }),
                rate: k_spring,
            },
            complaint: src.error(&path!["spring", "stiffness_n_m"], ""),
        });
        out.wheels.push(wh);
        out.top_mounts.push(pt.t);
    }
    Ok(out)
}

/// The inertia tensor of the mirror image (products with y change sign).
pub fn mirror_inertia(i: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut o = *i;
    o[0][1] = -i[0][1];
    o[1][0] = -i[1][0];
    o[1][2] = -i[1][2];
    o[2][1] = -i[2][1];
    o
}

/// Velocities per unit rotation rate of the lower arm about its body pivot axis.
struct Rates {
    /// Centres of mass of knuckle, lower arm, rod, tie rod.
    parts: [V; 4],
    wheel_centre: V,
    /// Spring length rate.
    element_rate: f64,
}

/// The body held and the bushings rigid, the arm turns about its pivot axis and the
/// knuckle follows the ball joint with its strut axis through the top mount and its
/// steering arm on the tie rod.
fn rates(p: &Pts, src: &Source, cms: &[V; 4]) -> Result<Rates, InputError> {
    let u = unit(&sub(&p.af, &p.ar));
    let vb = turning(&p.ar, &u, &p.b);
    let a = unit(&sub(&p.t, &p.l));
    let guess = if a[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = unit(&cross(&a, &guess));
    let e2 = cross(&a, &e1);
    // Knuckle angular velocity w: the knuckle point at the top mount moves along the
    // strut axis only (two rows: e.(vb + w x (T - B)) = 0), and the tie rod keeps its
    // length (one row); e.(w x r) = w.(r x e).
    let tb = sub(&p.t, &p.b);
    let rs = sub(&p.r, &p.s);
    let rows = [
        cross(&tb, &e1),
        cross(&tb, &e2),
        cross(&sub(&p.r, &p.b), &rs),
    ];
    let rhs = [-dot(&e1, &vb), -dot(&e2, &vb), -dot(&rs, &vb)];
    let m = nalgebra::Matrix3::from_fn(|i, j| rows[i][j]);
    let w = m
        .lu()
        .solve(&nalgebra::Vector3::from_fn(|i, _| rhs[i]))
        .ok_or_else(|| {
            src.error(
                &path!["hardpoints"],
                "the strut, ball joint and tie rod lock the knuckle (singular geometry)",
            )
        })?;
    let w = [w[0], w[1], w[2]];
    let on_knuckle = |x: &V| add(&vb, &cross(&w, &sub(x, &p.b)));
    // The rod tilts with the knuckle about the top mount but does not spin with it.
    let w_rod = sub(&w, &scale(&a, dot(&w, &a)));
    // The tie rod turns about its inner joint: its points move in proportion.
    let along = dot(&sub(&cms[3], &p.s), &rs) / dot(&rs, &rs);
    Ok(Rates {
        parts: [
            on_knuckle(&cms[0]),
            turning(&p.ar, &u, &cms[1]),
            cross(&w_rod, &sub(&cms[2], &p.t)),
            scale(&on_knuckle(&p.r), along),
        ],
        wheel_centre: on_knuckle(&p.w),
        element_rate: length_rate(&p.q, &on_knuckle(&p.q), &p.t),
    })
}
