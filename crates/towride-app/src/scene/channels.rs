//! The fixed output channels of a vehicle scene, the same names as CSV headers
//! (`name [unit]`) and JSON keys:
//!
//! | channel | request |
//! |---|---|
//! | `speed` [m/s] | car body centre of mass: velocity along the body's x |
//! | `hitch_fx`, `hitch_fy`, `hitch_fz` [N] | the drawbar's force on the car at the ball, car body axes (x forward, z up): the ball joint's reaction on the hitch, or minus the ball bushing's force on the drawbar |
//! | `trailer_ax` [m/s^2] | trailer box centre of mass: acceleration along the box's x |
//! | `acc_<sensor>_<axis>` [m/s^2] | sensor marker: acceleration along its measuring axes (kinematic, gravity not included) |
//!
//! | `tyre_<wheel>_fz` [N], `tyre_<wheel>_contact` [-] | contact normal force, 1 in contact / 0 in flight |
//! | `hitch_eta_<k>` [-] | crossbeam modal coordinates (k = 1.. over the selected modes, unit modal mass) |
//! | `hitch_strain_energy` [J] | crossbeam strain energy |
//! | `hitch_deflection_<x,y,z>` [m] | elastic displacement of the ball relative to the brackets, hitch axes |

use serde::Serialize;

use crate::vehicle::{Link, Vehicle};
use towride_mbs::flex::NodeKind;
use towride_mbs::model::desc::{
    Axes, ElementQuantity, JointQuantity, MarkerQuantity, ModalQuantity, Output, Request,
    TyreQuantity,
};
use towride_mbs::model::output::{channels_of, component_count};

/// One channel: its fixed name and unit.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Channel {
    /// Channel name, e.g. `hitch_fx` (the CSV column header).
    pub name: String,
    /// Unit, e.g. "m/s^2".
    pub unit: String,
}

/// An output keeping only the named components (empty names are dropped).
fn named(name: &str, request: Request, components: &[&str], scale: f64) -> Output {
    let mut o = Output::new(name, request);
    o.components = Some(components.iter().map(|s| s.to_string()).collect());
    o.scale = scale;
    o
}

/// The standard outputs of a vehicle and the channels they produce.
pub fn standard(v: &Vehicle) -> (Vec<Output>, Vec<Channel>) {
    let h = &v.handles;
    let mut out = Vec::new();
    out.push(named(
        "speed",
        Request::Marker {
            marker: h.car_ref,
            quantity: MarkerQuantity::Velocity,
            axes: Axes::Marker(h.car_ref),
        },
        &["speed", "", ""],
        1.0,
    ));
    let hitch = ["hitch_fx", "hitch_fy", "hitch_fz"];
    match h.ball {
        Some((Link::Joint(joint), _)) => out.push(named(
            "hitch_f",
            Request::Joint {
                joint,
                quantity: JointQuantity::Force,
                axes: Axes::Marker(h.car_ref),
            },
            &hitch,
            1.0,
        )),
        Some((Link::Bushing(element, _), _)) => out.push(named(
            "hitch_f",
            Request::Element {
                element,
                quantity: ElementQuantity::Force,
            },
            &[hitch[0], hitch[1], hitch[2], "", "", ""],
            -1.0,
        )),
        None => {}
    }
    if let Some(t) = h.trailer_ref {
        out.push(named(
            "trailer_a",
            Request::Marker {
                marker: t,
                quantity: MarkerQuantity::Acceleration,
                axes: Axes::Marker(t),
            },
            &["trailer_ax", "", ""],
            1.0,
        ));
    }
    for s in &h.sensors {
        let names: Vec<String> = ["x", "y", "z"]
            .iter()
            .zip(s.axes)
            .map(|(a, on)| {
                if on {
                    format!("acc_{}_{a}", s.name)
                } else {
                    String::new()
                }
            })
            .collect();
        let refs: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
        out.push(named(
            &format!("acc_{}", s.name),
            Request::Marker {
                marker: s.marker,
                quantity: MarkerQuantity::Acceleration,
                axes: Axes::Marker(s.marker),
            },
            &refs,
            1.0,
        ));
    }
    for w in &h.wheels {
        for (q, suffix) in [
            (TyreQuantity::NormalForce, "fz"),
            (TyreQuantity::Contact, "contact"),
        ] {
            let name = format!("tyre_{}_{suffix}", w.name);
            out.push(named(
                &name,
                Request::Tyre {
                    tyre: w.tyre,
                    quantity: q,
                },
                &[name.as_str()],
                1.0,
            ));
        }
    }
    if let Some(hh) = &h.hitch {
        let names: Vec<String> = (1..=hh.modes).map(|k| format!("hitch_eta_{k}")).collect();
        let refs: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
        out.push(named(
            "hitch_eta",
            Request::Modal {
                body: hh.body,
                quantity: ModalQuantity::Coordinates,
            },
            &refs,
            1.0,
        ));
        out.push(named(
            "hitch_strain_energy",
            Request::Modal {
                body: hh.body,
                quantity: ModalQuantity::StrainEnergy,
            },
            &["hitch_strain_energy"],
            1.0,
        ));
        // The ball's elastic displacement relative to the brackets.
        if let Some(md) = &v.model.bodies[hh.body].modal {
            let reference: Vec<usize> = md
                .data
                .nodes
                .iter()
                .enumerate()
                .filter(|(k, n)| n.kind == NodeKind::Interface && *k != hh.ball_node)
                .map(|(k, _)| k)
                .collect();
            out.push(named(
                "hitch_deflection",
                Request::Modal {
                    body: hh.body,
                    quantity: ModalQuantity::Deflection {
                        node: hh.ball_node,
                        reference,
                    },
                },
                &[
                    "hitch_deflection_x",
                    "hitch_deflection_y",
                    "hitch_deflection_z",
                ],
                1.0,
            ));
        }
    }
    let mut m = v.model.clone();
    for o in &out {
        debug_assert_eq!(
            component_count(&m, &o.request),
            o.components.as_ref().map_or(0, |c| c.len())
        );
    }
    m.outputs = out.clone();
    let channels = channels_of(&m)
        .into_iter()
        .map(|c| Channel {
            name: c.name,
            unit: c.unit.to_string(),
        })
        .collect();
    (out, channels)
}
