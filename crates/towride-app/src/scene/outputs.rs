//! Outputs a scene asks for beyond the fixed channels: `[[output]]` tables with the
//! mechanism files' keys (`marker`, `joint` or `element` with `quantity` and `axes`,
//! resolved by [`towride_mbs::model::spec`]'s reader), or a named vehicle quantity alone:
//!
//! ```toml
//! [[output]]
//! quantity = "susp_fl_travel"      # a named vehicle quantity (run SCENE --list-names)
//!
//! [[output]]
//! element = "damper_rl"            # any element, marker or joint of the vehicle
//! quantity = "force"
//! name = "rl_strut_force"          # optional channel name
//! ```
//!
//! | quantity | unit | what |
//! |---|---|---|
//! | `susp_<w>_travel` | m | wheel centre relative to the body above it, along the body's z, from the design position; positive in bump |
//! | `susp_<w>_velocity` | m/s | its rate |
//! | `spring_<w>_force`, `damper_<w>_force`, `bump_stop_<w>_force`, `rebound_stop_<w>_force` | N | one law of the corner's spring or strut, positive pushing its ends apart |
//! | `air_spring_<w>_pressure` | Pa | gauge pressure of a levelled air spring (`simple` template): its force over its effective area |
//! | `tyre_<w>_fx` | N | longitudinal contact force |
//! | `tyre_<w>_road_height` | m | height of the effective road plane (the enveloped obstacle) |
//! | `body_heave`, `trailer_heave` | m | centre of mass height above its design height |
//! | `body_pitch`, `trailer_pitch` | rad | pitch (ISO 8855 yaw-pitch-roll; positive nose down) |
//! | `body_roll`, `trailer_roll` | rad | roll (positive right side down) |
//! | `drive_torque` | N m | the engine's total torque at the driven wheels (its share of the speed controller's demand) |
//! | `hitch_ball_deflection` | m, rad | the ball coupling bushing's deflection (bushing couplings only) |
//!
//! Tyre Fz and contact, and the crossbeam's modal coordinates (`hitch_eta_<k>`), are
//! fixed channels.
//!
//! An unknown name is an error at its file, line and field with the closest names
//! suggested.

use serde::Serialize;

use super::Channel;
use crate::vehicle::Vehicle;
use towride_mbs::input::{InputError, Source};
use towride_mbs::model::builder::{
    BodyHandle, ElementHandle, Link, MarkerHandle, ModelBuilder, TyreHandle,
};
use towride_mbs::model::desc::{
    BodyQuantity, ElementQuantity, LinePart, Output, RelativeQuantity, Request, TyreQuantity,
};
use towride_mbs::model::elements::Force;
use towride_mbs::model::math::{mm, mtv, mv, rot, sub};
use towride_mbs::model::output::channels_of;
use towride_mbs::model::spec::{output_of, OutputSpec};
use towride_mbs::model::suggest::did_you_mean;
use towride_mbs::model::Model;
use towride_mbs::path;

/// Version of the `--list-names` document.
pub const NAMES_SCHEMA_VERSION: u32 = 1;

/// A named vehicle quantity.
#[derive(Clone, Debug, Serialize)]
pub struct Quantity {
    /// Name (also the channel's).
    pub name: String,
    /// Unit.
    pub unit: &'static str,
    /// What it measures.
    pub what: String,
    #[serde(skip)]
    kind: Kind,
}

#[derive(Clone, Debug)]
enum Kind {
    /// Wheel (index into the handles' wheels) against the body above it.
    Travel { wheel: usize, velocity: bool },
    Line {
        element: ElementHandle,
        part: LinePart,
    },
    Tyre {
        tyre: TyreHandle,
        quantity: TyreQuantity,
    },
    Body {
        body: BodyHandle,
        quantity: BodyQuantity,
    },
    Element {
        element: ElementHandle,
        quantity: ElementQuantity,
    },
    /// A speed controller's engine torque (index into the model's controllers).
    Drive { control: usize },
    /// A speed controller's brake torque (index into the model's controllers).
    Brake { control: usize },
    Pressure {
        element: ElementHandle,
        area_m2: f64,
    },
}

/// What a scene's outputs can address: the named quantities, the fixed channels, and
/// the vehicle's bodies, markers, joints and elements by name.
#[derive(Clone, Debug, Serialize)]
pub struct Names {
    /// Layout version ([`NAMES_SCHEMA_VERSION`]).
    pub schema_version: u32,
    /// Channels every scene run writes.
    pub fixed_channels: Vec<Channel>,
    /// Named vehicle quantities (`[[output]] quantity = "..."`).
    pub quantities: Vec<Quantity>,
    /// Bodies (their centre-of-mass markers are `<body>.cm`).
    pub bodies: Vec<String>,
    /// Markers (`marker = ...`; quantities position, velocity, acceleration,
    /// angular_velocity, angular_acceleration).
    pub markers: Vec<String>,
    /// Ideal joints (`joint = ...`; force, torque, displacement).
    pub joints: Vec<String>,
    /// Force elements and their kind (`element = ...`; force, deflection, velocity).
    pub elements: Vec<(String, &'static str)>,
}

/// The names a scene's vehicle offers, with the fixed channels `fixed`.
pub fn names(v: &Vehicle, fixed: &[Channel]) -> Names {
    let m = &v.model;
    Names {
        schema_version: NAMES_SCHEMA_VERSION,
        fixed_channels: fixed.to_vec(),
        quantities: quantities(v),
        bodies: m.bodies.iter().map(|b| b.name.clone()).collect(),
        markers: m.markers.iter().map(|k| k.name.clone()).collect(),
        joints: m.joints.iter().map(|j| j.name.clone()).collect(),
        elements: m
            .forces
            .iter()
            .map(|f| (f.name().to_string(), f.kind()))
            .collect(),
    }
}

/// The named quantities of a vehicle.
pub fn quantities(v: &Vehicle) -> Vec<Quantity> {
    let m = &v.model;
    let h = &v.handles;
    let mut out = Vec::new();
    let mut add = |name: String, unit, what: String, kind| {
        out.push(Quantity {
            name,
            unit,
            what,
            kind,
        })
    };
    for (k, w) in h.wheels.iter().enumerate() {
        let n = &w.name;
        if reference_body(v, k).is_some() {
            add(
                format!("susp_{n}_travel"),
                "m",
                format!("wheel {n}: suspension travel (bump positive) from the design position"),
                Kind::Travel {
                    wheel: k,
                    velocity: false,
                },
            );
            add(
                format!("susp_{n}_velocity"),
                "m/s",
                format!("wheel {n}: suspension velocity (bump positive)"),
                Kind::Travel {
                    wheel: k,
                    velocity: true,
                },
            );
        }
        for (part, label, key) in [
            (LinePart::Spring, "spring", "spring"),
            (LinePart::Damper, "damper", "damper"),
            (LinePart::BumpStop, "bump stop", "bump_stop"),
            (LinePart::ReboundStop, "rebound stop", "rebound_stop"),
        ] {
            if let Some((element, el)) = line_with(m, n, part) {
                add(
                    format!("{key}_{n}_force"),
                    "N",
                    format!("wheel {n}: {label} force in '{el}' (positive pushing apart)"),
                    Kind::Line { element, part },
                );
            }
        }
        let air = h.air_springs.iter().find(|(w, _)| w == n);
        if let (Some((_, a)), Some((element, el))) = (air, line_with(m, n, LinePart::Spring)) {
            add(
                format!("air_spring_{n}_pressure"),
                "Pa",
                format!("wheel {n}: gauge pressure of the air spring '{el}' (force over its {} m^2 effective area)", a.area_m2),
                Kind::Pressure {
                    element,
                    area_m2: a.area_m2,
                },
            );
        }
        for (q, key, unit, what) in [
            (
                TyreQuantity::LongitudinalForce,
                "fx",
                "N",
                "longitudinal contact force",
            ),
            (
                TyreQuantity::EffectiveRoadHeight,
                "road_height",
                "m",
                "height of the effective road plane",
            ),
        ] {
            add(
                super::channels::tyre(n, key),
                unit,
                format!("wheel {n}: {what}"),
                Kind::Tyre {
                    tyre: w.tyre,
                    quantity: q,
                },
            );
        }
    }
    if let Some((Link::Bushing(e, _), _)) = h.ball {
        add(
            "hitch_ball_deflection".into(),
            "m, rad",
            "ball coupling bushing: deflection per direction (one channel each)".into(),
            Kind::Element {
                element: e,
                quantity: ElementQuantity::Deflection,
            },
        );
    }
    for (k, c) in m.controls.iter().enumerate() {
        let name = if k == 0 {
            "drive_torque".to_string()
        } else {
            format!("drive_torque_{k}")
        };
        add(
            name,
            "N m",
            format!(
                "{}: the engine's total torque at the driven wheels (its share of the controller's demand)",
                c.name
            ),
            Kind::Drive { control: k },
        );
        if c.brakes.is_some() {
            add(
                format!("brake_torque{}", if k == 0 { String::new() } else { format!("_{k}") }),
                "N m",
                format!(
                    "{}: the friction brakes' total torque capacity asked (negative: opposing forward spin)",
                    c.name
                ),
                Kind::Brake { control: k },
            );
        }
    }
    let bodies = [("body", Some(h.car_body)), ("trailer", h.trailer_body)];
    for (prefix, b) in bodies {
        let Some(b) = b else { continue };
        let who = if prefix == "body" {
            "car body"
        } else {
            "trailer box"
        };
        for (q, key, unit, what) in [
            (
                BodyQuantity::Heave,
                "heave",
                "m",
                "heave of the centre of mass from design",
            ),
            (
                BodyQuantity::Pitch,
                "pitch",
                "rad",
                "pitch (positive nose down)",
            ),
            (
                BodyQuantity::Roll,
                "roll",
                "rad",
                "roll (positive right side down)",
            ),
        ] {
            add(
                format!("{prefix}_{key}"),
                unit,
                format!("{who}: {what}"),
                Kind::Body {
                    body: b,
                    quantity: q,
                },
            );
        }
    }
    out
}

/// The spring-damper line element of wheel `w` that holds `part`: `spring_<w>` for the
/// spring, `damper_<w>` for the damper, whichever has it for a stop.
fn line_with<'a>(m: &'a Model, w: &str, part: LinePart) -> Option<(ElementHandle, &'a str)> {
    let cands: &[&str] = match part {
        LinePart::Spring => &["spring"],
        LinePart::Damper => &["damper"],
        _ => &["damper", "spring"],
    };
    for c in cands {
        let name = format!("{c}_{w}");
        let Some(k) = m.element_by_name(&name) else {
            continue;
        };
        let Force::Spring(s) = &m.forces[k] else {
            continue;
        };
        let has = match part {
            LinePart::Spring | LinePart::Damper => true,
            LinePart::BumpStop => s.bump_stop.is_some(),
            LinePart::ReboundStop => s.rebound_stop.is_some(),
        };
        if has {
            return Some((k, m.forces[k].name()));
        }
    }
    None
}

/// The sprung body wheel `k` is measured against: the car body for the car's wheels
/// (their `ride_<w>` markers), the trailer box for the trailer's.
fn reference_body(v: &Vehicle, k: usize) -> Option<BodyHandle> {
    let w = &v.handles.wheels[k];
    if v.handles.ride.iter().any(|(n, _)| *n == w.name) {
        return Some(v.handles.car_body);
    }
    let tb = v.handles.trailer_body?;
    // A trailer wheel: built in the trailer's subsystem (placed where the trailer is),
    // whatever it is called.
    let place = v.handles.place_of(w.body)?;
    (Some(place) == v.handles.trailer_place).then_some(tb)
}

/// Initial world position of marker `k` and its world axes.
fn initial_frame(m: &Model, k: MarkerHandle) -> ([f64; 3], [[f64; 3]; 3]) {
    let mk = &m.markers[k];
    match mk.body {
        None => (mk.position, mk.axes),
        Some(b) => {
            let body = &m.bodies[b];
            let a = rot(&body.orientation);
            let s = mv(&a, &mk.position);
            let axes = mm(&a, &mk.axes);
            (std::array::from_fn(|i| body.position[i] + s[i]), axes)
        }
    }
}

/// The marker above wheel `k` on its sprung body: the `ride_<w>` marker, or one added at
/// the wheel centre's design position on the trailer box (body axes).
fn reference_marker(v: &mut Vehicle, k: usize) -> Option<MarkerHandle> {
    let w = v.handles.wheels[k].clone();
    if let Some((_, mk)) = v.handles.ride.iter().find(|(n, _)| *n == w.name) {
        return Some(*mk);
    }
    let body = reference_body(v, k)?;
    let name = format!("ride_{}", w.name);
    if let Some(i) = v.model.marker_by_name(&name) {
        return Some(i);
    }
    let (p, _) = initial_frame(&v.model, w.centre);
    let axes = rot(&v.model.bodies[body].orientation);
    let mut b = ModelBuilder::from_model(std::mem::take(&mut v.model));
    let body_handle = v.handles.trailer_body?;
    let made = b.world_marker(&name, Some(body_handle), p, axes).ok();
    v.model = b.finish();
    made
}

/// The output of named quantity `q` (adds a reference marker when one is needed).
fn output_for(v: &mut Vehicle, q: &Quantity, name: &str) -> Option<Output> {
    let request = match q.kind {
        Kind::Travel { wheel, velocity } => {
            let j = reference_marker(v, wheel)?;
            let i = v.handles.wheels[wheel].centre;
            let (pi, _) = initial_frame(&v.model, i);
            let (pj, aj) = initial_frame(&v.model, j);
            Request::Relative {
                i,
                j,
                axis: 2,
                quantity: if velocity {
                    RelativeQuantity::Velocity
                } else {
                    RelativeQuantity::Position
                },
                offset: mtv(&aj, &sub(&pi, &pj))[2],
            }
        }
        Kind::Line { element, part } => Request::LinePart { element, part },
        Kind::Pressure { element, area_m2 } => Request::LinePressure { element, area_m2 },
        Kind::Tyre { tyre, quantity } => Request::Tyre { tyre, quantity },
        Kind::Element { element, quantity } => Request::Element { element, quantity },
        Kind::Drive { control } => Request::DriveTorque { control },
        Kind::Brake { control } => Request::BrakeTorque { control },
        Kind::Body { body, quantity } => Request::Body {
            body,
            quantity,
            z_ref: v.model.bodies[body].position[2],
        },
    };
    Some(Output::new(name, request))
}

/// Adds the outputs of the scene's `[[output]]` tables to the vehicle's model after the
/// fixed channels `channels`; returns them and their channels. Every error is located
/// at its table's field.
pub fn requested(
    src: &Source,
    v: &mut Vehicle,
    specs: &[OutputSpec],
    channels: &[Channel],
) -> Result<(Vec<Output>, Vec<Channel>), InputError> {
    let mut outs = Vec::new();
    let mut chans: Vec<Channel> = Vec::new();
    let known = quantities(v);
    for (k, o) in specs.iter().enumerate() {
        let out = if o.marker.is_none() && o.joint.is_none() && o.element.is_none() {
            if o.axes.is_some() {
                return Err(src.error(
                    &path!["output", k, "axes"],
                    "a named vehicle quantity has its own axes: give axes only with marker or joint",
                ));
            }
            let Some(q) = known.iter().find(|q| q.name == o.quantity) else {
                let fixed = channels.iter().any(|c| c.name == o.quantity);
                let message = if fixed {
                    format!(
                        "'{}' is a fixed channel: every scene run writes it",
                        o.quantity
                    )
                } else {
                    format!(
                        "'{}' is not a vehicle quantity{}; `towride run SCENE --list-names` lists the quantities, or give marker, joint or element",
                        o.quantity,
                        did_you_mean(&o.quantity, known.iter().map(|q| q.name.as_str()))
                    )
                };
                return Err(src.error(&path!["output", k, "quantity"], message));
            };
            let name = o.name.clone().unwrap_or_else(|| q.name.clone());
            output_for(v, q, &name).ok_or_else(|| {
                src.error(
                    &path!["output", k, "quantity"],
                    format!("'{}' has no reference body in this vehicle", q.name),
                )
            })?
        } else {
            let joints = v
                .model
                .each_joint()
                .map(|(i, j)| (j.name.clone(), i))
                .collect();
            output_of(src, &v.model, k, o, &joints)?
        };
        let mut m = v.model.clone();
        m.outputs = vec![out.clone()];
        for c in channels_of(&m) {
            if channels.iter().chain(&chans).any(|d| d.name == c.name) {
                return Err(src.error(
                    &path!["output", k],
                    format!(
                        "channel '{}' is written already: give this output another name",
                        c.name
                    ),
                ));
            }
            chans.push(Channel {
                name: c.name,
                unit: c.unit.to_string(),
            });
        }
        outs.push(out);
    }
    Ok((outs, chans))
}
