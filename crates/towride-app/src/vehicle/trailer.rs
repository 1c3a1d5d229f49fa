//! The trailer: box, chassis and drawbar as one rigid body (plus the payload of the load
//! case, merged into it), a rubber torsion axle of two swinging halves, wheels and tyres.
//!
//! The axle follows the thesis (5.5.3.1): two rigid halves joined on the centreline by a
//! torsion element (the inner bar) and carried by two bushings (the rubber packs), whose
//! rotation about the axle axis springs and damps the box. The rubber's preload holds
//! the empty trailer at its design position; a payload makes it sit lower.
//!
//! Trailer coordinates: x forward (towards the car), y left, z up, origin on the ground
//! under the coupling's ball centre, the empty trailer at its design attitude.

use std::path::Path;

use serde::Deserialize;

use super::build::Builder;
use super::design::{self, centre_of_mass, Corner, CornerDesign, Preloaded};
use super::geom::{mirror, Placement, V};
use super::props::{
    joints, point, BushingProps, JointsProps, Mass, MassProps, TorsionProps, WheelProps,
};
use super::swing::{self, Spec};
use super::wheel::{self, WheelHandle};
use towride_mbs::input::{InputError, Source};
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::model::elements::JointBushing;
use towride_mbs::model::math::{add, scale, sub};
use towride_mbs::path;
use towride_mbs::tyre::Tyre;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    trailer: Coupling,
    body: MassProps,
    hardpoints: Hardpoints,
    half: MassProps,
    wheel: WheelProps,
    pivot_bushing: BushingProps,
    torsion: TorsionProps,
    joints: JointsProps,
    load_case: Vec<LoadCase>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Coupling {
    /// Ball-socket centre on the drawbar [m].
    coupling_m: [f64; 3],
}

/// Left-side hardpoints [m].
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Hardpoints {
    pivot_m: [f64; 3],
    wheel_centre_m: [f64; 3],
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct LoadCase {
    name: String,
    /// Added mass (none: the empty trailer).
    payload: Option<MassProps>,
}

/// A trailer read and checked, before it is placed.
pub struct TrailerFile {
    pub src_path: std::path::PathBuf,
    pub coupling: V,
    /// Wheel centre (left), trailer coordinates.
    pub wheel_centre: V,
    /// Payload of the chosen load case.
    pub payload: Option<Mass>,
    pub load_case: String,
    box_mass: Mass,
    half: Mass,
    pivot: V,
    wheel: WheelProps,
    bushing: super::props::BushingLaws,
    torsion: (towride_mbs::model::desc::Law, towride_mbs::model::desc::Law),
    joints_as_bushings: Option<JointBushing>,
    src: Source,
}

/// Reads `file`, choosing the load case `case` (the first one when `None`).
pub fn read(
    file: &Path,
    case: Option<&str>,
    loader: &towride_mbs::input::Loader,
) -> Result<TrailerFile, InputError> {
    let src = loader.toml(file)?;
    let f: File = src.parse()?;
    let coupling = point(&src, &path!["trailer", "coupling_m"], &f.trailer.coupling_m)?;
    let pivot = point(&src, &path!["hardpoints", "pivot_m"], &f.hardpoints.pivot_m)?;
    let wc = point(
        &src,
        &path!["hardpoints", "wheel_centre_m"],
        &f.hardpoints.wheel_centre_m,
    )?;
    if wc[1] <= 0.0 || pivot[1] <= 0.0 {
        return Err(src.error(
            &path!["hardpoints"],
            "give the left side (y > 0); the right side is mirrored",
        ));
    }
    if f.load_case.is_empty() {
        return Err(src.error(&path!["load_case"], "define at least one load case"));
    }
    let k = match case {
        None => 0,
        Some(name) => f
            .load_case
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| {
                let names: Vec<&str> = f.load_case.iter().map(|c| c.name.as_str()).collect();
                src.error(
                    &path!["load_case"],
                    format!("no load case '{name}' (cases: {})", names.join(", ")),
                )
            })?,
    };
    let mut payload = None;
    for (i, c) in f.load_case.iter().enumerate() {
        // Every case is checked, not only the chosen one.
        let m = match &c.payload {
            Some(p) => Some(p.check(&src, &path!["load_case", i, "payload"])?),
            None => None,
        };
        if i == k {
            payload = m;
        }
    }
    Ok(TrailerFile {
        coupling,
        wheel_centre: wc,
        payload,
        load_case: f.load_case[k].name.clone(),
        box_mass: f.body.check(&src, &path!["body"])?,
        half: f.half.check(&src, &path!["half"])?,
        pivot,
        bushing: f
            .pivot_bushing
            .check(&src, &path!["pivot_bushing"], [0.0, 1.0, 0.0])?,
        torsion: f.torsion.laws(&src, &path!["torsion"])?,
        joints_as_bushings: joints(&src, &path!["joints"], &f.joints)?,
        wheel: f.wheel.clone(),
        src_path: file.to_path_buf(),
        src,
    })
}

/// Two bodies merged: mass, centre of mass and inertia about it (parallel axes).
pub fn merge(a: &Mass, b: &Mass) -> Mass {
    let m = a.mass + b.mass;
    let cm = scale(&add(&scale(&a.cm, a.mass), &scale(&b.cm, b.mass)), 1.0 / m);
    let mut inertia = [[0.0; 3]; 3];
    for part in [a, b] {
        let d = sub(&part.cm, &cm);
        let d2: f64 = d.iter().map(|x| x * x).sum();
        for r in 0..3 {
            for c in 0..3 {
                let delta = if r == c { 1.0 } else { 0.0 };
                inertia[r][c] += part.inertia[r][c] + part.mass * (d2 * delta - d[r] * d[c]);
            }
        }
    }
    Mass {
        mass: m,
        cm,
        inertia,
    }
}

/// The built trailer.
pub struct Trailer {
    pub body: BodyHandle,
    pub wheels: Vec<WheelHandle>,
    /// Design statics of the empty trailer (the rubber's preload).
    pub corners: Vec<CornerDesign>,
    /// Static load on the ball of the empty trailer [N].
    pub design_ball_load_n: f64,
    /// Mass and centre of mass (trailer coordinates) with the payload.
    pub mass: f64,
    pub cm: V,
}

/// Adds the trailer (the builder placed in trailer coordinates).
pub fn build(b: &mut Builder, t: &TrailerFile, tyre: &Tyre) -> Result<Trailer, InputError> {
    let src = &t.src;
    let rim = wheel::rim_mass(src, &path!["wheel"], &t.wheel, tyre, t.wheel_centre)?;
    let loaded = match &t.payload {
        Some(p) => merge(&t.box_mass, p),
        None => t.box_mass.clone(),
    };
    let body = b.body("trailer_box", &loaded)?;
    let spec = Spec {
        prefix: "trailer_arm",
        wheels: ["tl", "tr"],
        centre: "trailer_axle",
        carrier: body,
        pivot: t.pivot,
        half: t.half.clone(),
        rim: rim.clone(),
        bushing: t.bushing.clone(),
        torsion: t.torsion.clone(),
        joints_as_bushings: t.joints_as_bushings.clone(),
    };
    let built = swing::build(b, &spec, tyre)?;
    swing::join(b, &spec, built.halves)?;
    // Design statics of the empty trailer: ball and axle share its weight.
    let belt = wheel::tyre_own_mass(tyre);
    let mut parts = vec![(t.box_mass.mass, t.box_mass.cm)];
    for side in [false, true] {
        let m = |p: V| if side { mirror(p) } else { p };
        parts.push((t.half.mass, m(t.half.cm)));
        parts.push((rim.mass + belt, m(t.wheel_centre)));
    }
    let (m_empty, cm_empty) = centre_of_mass(&parts);
    let g = b.model().gravity;
    let w = m_empty * super::geom::norm(&g);
    let (ball, axle) = design::lever(w, cm_empty[0], t.coupling[0], t.wheel_centre[0]);
    let mut corners = Vec::new();
    for k in 0..2 {
        let mut rates = built.rates[k].clone();
        rates.element_rate = built.bushing_rates[k];
        let rate = match &t.bushing.stiffness[5] {
            towride_mbs::model::desc::Law::Linear(r) => *r,
            l => l.stiffness(),
        };
        let c = Corner {
            wheel: built.wheels[k].name.clone(),
            rates,
            element: Preloaded::Torsion {
                force: built.bushings[k],
                rate,
            },
            complaint: src.error(&path!["pivot_bushing", "stiffness_n_m_rad", 2], ""),
        };
        corners.push(design::finish(b, c, 0.5 * axle)?);
    }
    let mut all = parts.clone();
    if let Some(p) = &t.payload {
        all.push((p.mass, p.cm));
    }
    let (mass, cm) = centre_of_mass(&all);
    Ok(Trailer {
        body,
        wheels: built.wheels,
        corners,
        design_ball_load_n: ball,
        mass,
        cm,
    })
}

/// The trailer's placement: its coupling on the ball `ball` (world), pitched about the
/// axle's ground line so its wheels stay on the ground. Returns it and the pitch [rad].
pub fn place(src: &Source, t: &TrailerFile, ball: V) -> Result<(Placement, f64), InputError> {
    let (xa, c) = (t.wheel_centre[0], t.coupling);
    let (a, h) = (c[0] - xa, c[2]);
    let rho = a.hypot(h);
    let pitch = (ball[2] / rho).clamp(-1.0, 1.0).acos() - a.atan2(h);
    // More than about 6 deg means the files disagree on the ball height.
    if pitch.is_nan() || pitch.abs() > 0.1 || c[1] != 0.0 {
        return Err(src.error(&path!["trailer", "file"], format!("{}: the coupling at height {h} m (y {}) cannot sit on a ball {} m high on the centreline without pitching the trailer by {pitch:.3} rad", t.src_path.display(), c[1], ball[2])));
    }
    let x_rot = xa + pitch.cos() * a + pitch.sin() * h;
    let place = Placement::pitched([xa, 0.0, 0.0], pitch, [ball[0] - x_rot, ball[1], 0.0]);
    Ok((place, pitch))
}
