//! The fixed output channels of a vehicle scene, the same names as CSV headers
//! (`name [unit]`) and JSON keys:
//!
//! | channel | request |
//! |---|---|
//! | `speed` [m/s] | car body centre of mass: velocity along the body's x |
//! | `hitch_fx`, `hitch_fy`, `hitch_fz` [N] | the drawbar's force on the car at the ball, car body axes (x forward, z up): the ball joint's reaction on the hitch, or minus the ball bushing's force on the drawbar |
//! | `hitch_bracket_<left,right>_<fx,fy,fz>` [N], `_<mx,my,mz>` [N m] | the load each hitch bracket passes into the car body, car body axes, moment about the bracket's bolt point (the bracket interface node's design position, the centre of its bolt pattern): minus the mount bushing's load on the hitch, moved from where it acts (the deflected node) to the bolt point, or minus the fixed joint's reaction |
//! | `trailer_ax` [m/s^2] | trailer box centre of mass: acceleration along the box's x |
//! | `acc_<sensor>_<axis>` [m/s^2] | sensor marker: acceleration along its measuring axes (kinematic, gravity not included) |
//!
//! | `tyre_<wheel>_fz` [N], `tyre_<wheel>_contact` [-] | contact normal force, 1 in contact / 0 in flight |
//! | `hitch_eta_<k>` [-] | crossbeam modal coordinates (k = 1.. over the selected modes, unit modal mass) |
//! | `hitch_strain_energy` [J] | crossbeam strain energy |
//! | `hitch_deflection_<x,y,z>` [m] | elastic displacement of the ball relative to the brackets, hitch axes |
//!
//! Each accelerometer (`acc_*`, `trailer_ax`), force (`hitch_f*`, `hitch_bracket_*`) and deflection
//! (`hitch_deflection_*`) channel has a band-limited twin, the channel through the
//! scene's acquisition chain (`[acquisition]`, default the thesis's fourth-order 100 Hz
//! Butterworth, causal): its name plus the filter's suffix, `acc_hitch_z_lp100`
//! ([`band`], [`crate::signal::acquisition::AcqFilter::suffix`]).

use serde::Serialize;

use crate::vehicle::{Link, Vehicle};
use towride_mbs::flex::NodeKind;
use towride_mbs::model::desc::{
    Axes, ElementQuantity, JointQuantity, MarkerQuantity, ModalQuantity, Output, Request,
    TyreQuantity,
};
use towride_mbs::model::output::{channels_of, component_count, TRANSMITTED_PARTS};

// The fixed channels' names, defined once: the library and the command line read the
// channels by these.

/// The car body's speed along its x [m/s].
pub const SPEED: &str = "speed";
/// The drawbar's force on the car along the car body's x [N].
pub const HITCH_FX: &str = "hitch_fx";
/// The drawbar's force on the car along the car body's y [N].
pub const HITCH_FY: &str = "hitch_fy";
/// The drawbar's force on the car along the car body's z [N].
pub const HITCH_FZ: &str = "hitch_fz";
/// Start of the hitch brackets' load channels, `hitch_bracket_<side>_<component>`.
pub const HITCH_BRACKET_PREFIX: &str = "hitch_bracket_";
/// The hitch brackets, in the order of the hitch file's `bracket_nodes`.
pub const HITCH_BRACKETS: [&str; 2] = ["left", "right"];

/// A hitch bracket's load channel: `side` left or right, `component` one of
/// [`towride_mbs::model::output::TRANSMITTED_PARTS`] (`hitch_bracket_left_fz`).
pub fn hitch_bracket(side: &str, component: &str) -> String {
    format!("{HITCH_BRACKET_PREFIX}{side}_{component}")
}

/// The trailer box's acceleration along its x [m/s^2].
pub const TRAILER_AX: &str = "trailer_ax";
/// The crossbeam's strain energy [J].
pub const HITCH_STRAIN_ENERGY: &str = "hitch_strain_energy";
/// The ball's elastic displacement relative to the brackets along the hitch's x, y, z
/// [m].
pub const HITCH_DEFLECTION: [&str; 3] = [
    "hitch_deflection_x",
    "hitch_deflection_y",
    "hitch_deflection_z",
];
/// Start of the crossbeam's modal coordinates, `hitch_eta_<k>`.
pub const HITCH_ETA_PREFIX: &str = "hitch_eta_";
/// Start of the acceleration sensors' channels, `acc_<sensor>_<axis>`.
pub const ACC_PREFIX: &str = "acc_";
/// Start of the tyres' channels, `tyre_<wheel>_<quantity>`.
pub const TYRE_PREFIX: &str = "tyre_";
/// The tyre quantity of the contact normal force [N].
pub const TYRE_FZ: &str = "fz";
/// The tyre quantity of contact: 1 in contact, 0 in flight.
pub const TYRE_CONTACT: &str = "contact";

/// The crossbeam's modal coordinate `k` (1..): `hitch_eta_<k>`.
pub fn hitch_eta(k: usize) -> String {
    format!("{HITCH_ETA_PREFIX}{k}")
}

/// An acceleration sensor's channel along `axis` (x, y or z): `acc_<sensor>_<axis>`.
pub fn acc(sensor: &str, axis: &str) -> String {
    format!("{ACC_PREFIX}{sensor}_{axis}")
}

/// A tyre's channel of `quantity` ([`TYRE_FZ`], [`TYRE_CONTACT`], ...):
/// `tyre_<wheel>_<quantity>`.
pub fn tyre(wheel: &str, quantity: &str) -> String {
    format!("{TYRE_PREFIX}{wheel}_{quantity}")
}

/// True for a channel named like a tyre's channel of `quantity`.
pub fn is_tyre(channel: &str, quantity: &str) -> bool {
    channel.starts_with(TYRE_PREFIX)
        && channel
            .strip_suffix(quantity)
            .is_some_and(|c| c.ends_with('_'))
}

/// The wheel of a tyre's channel of `quantity` (`tyre_<wheel>_<quantity>`).
pub fn tyre_wheel<'a>(channel: &'a str, quantity: &str) -> Option<&'a str> {
    channel
        .strip_prefix(TYRE_PREFIX)?
        .strip_suffix(quantity)?
        .strip_suffix('_')
}

/// How the scene's acquisition chain (`[acquisition]`,
/// [`crate::signal::acquisition`]) treats a channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Band {
    /// An accelerometer (`acc_*`, `trailer_ax`): reported band-limited, as the instrument
    /// saw it, with the raw channel beside it.
    Sensor,
    /// A force, deflection or crossbeam stress (`hitch_f*`, `hitch_deflection_*`,
    /// `hitch_stress_*`): reported raw, with the band-limited channel beside it.
    Load,
}

/// What the acquisition chain does with the raw channel `name` (`None`: nothing, it is
/// reported raw only; also for a band-limited twin itself, [`is_band_limited`]).
pub fn band(name: &str) -> Option<Band> {
    if is_band_limited(name) {
        None
    } else if name.starts_with(ACC_PREFIX) || name == TRAILER_AX {
        Some(Band::Sensor)
    } else if [HITCH_FX, HITCH_FY, HITCH_FZ].contains(&name)
        || name.starts_with(HITCH_BRACKET_PREFIX)
        || HITCH_DEFLECTION.contains(&name)
        || is_stress_fibre(name)
    {
        Some(Band::Load)
    } else {
        None
    }
}

/// Prefix of the crossbeam's stress channels (`hitch_stress_<point>_<quantity>`).
pub const HITCH_STRESS_PREFIX: &str = "hitch_stress_";

/// A stress channel linear in the body's state: a fibre's signed normal stress
/// (`_sx_f1`..`_sx_f4`) or the torsional shear (`_tau`). Raw they carry every kept mode up
/// to 1.6 kHz, which the scenes' steps (tuned to the 100 Hz acquisition band) do not
/// resolve, so they get band-limited twins, which a convergence verdict judges. The
/// envelopes (`_eq`, `_sx_max`, `_sx_min`: maxima over fibres, von Mises) are not judged:
/// their kinks make their extremes ill-posed (the band-limited minimum of the ball
/// mount's `_eq` moves by 25 kPa, 3 % of its 1 %-of-peak floor, from rtol 1e-4 to 1e-5 on
/// the default scene, where its maximum moves 0.03 %); the fibres they are made of are
/// judged. Fatigue figures (rainflow, DEL) take the raw channels.
pub fn is_stress_fibre(name: &str) -> bool {
    name.strip_prefix(HITCH_STRESS_PREFIX).is_some_and(|rest| {
        !is_band_limited(name)
            && (rest.ends_with("_tau")
                || rest
                    .rsplit_once("_sx_f")
                    .is_some_and(|(_, k)| !k.is_empty() && k.chars().all(|c| c.is_ascii_digit())))
    })
}

/// A stress envelope channel (see [`is_stress_fibre`]): not judged for convergence.
pub fn is_stress_envelope(name: &str) -> bool {
    name.starts_with(HITCH_STRESS_PREFIX) && !is_stress_fibre(name) && !is_band_limited(name)
}

/// True for a name ending in a band-limited twin's suffix, `_lp<cutoff>`
/// (`acc_hitch_z_lp100`).
pub fn is_band_limited(name: &str) -> bool {
    name.rsplit_once("_lp").is_some_and(|(_, f)| {
        !f.is_empty()
            && f.parse::<f64>().is_ok()
            && f.chars().all(|c| c.is_ascii_digit() || c == '.')
    })
}

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
        SPEED,
        Request::Marker {
            marker: h.car_ref,
            quantity: MarkerQuantity::Velocity,
            axes: Axes::Marker(h.car_ref),
        },
        &[SPEED, "", ""],
        1.0,
    ));
    let hitch = [HITCH_FX, HITCH_FY, HITCH_FZ];
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
    // The brackets' loads into the body, beside the ball force.
    if let Some(hh) = &h.hitch {
        for (side, link) in HITCH_BRACKETS.iter().zip(hh.brackets) {
            let names = TRANSMITTED_PARTS.map(|c| hitch_bracket(side, c));
            let refs = names.each_ref().map(|s| s.as_str());
            out.push(named(
                &format!("{HITCH_BRACKET_PREFIX}{side}"),
                Request::Transmitted {
                    by: link.carrier(),
                    axes: Axes::Marker(h.car_ref),
                },
                &refs,
                1.0,
            ));
        }
    }
    if let Some(t) = h.trailer_ref {
        out.push(named(
            "trailer_a",
            Request::Marker {
                marker: t,
                quantity: MarkerQuantity::Acceleration,
                axes: Axes::Marker(t),
            },
            &[TRAILER_AX, "", ""],
            1.0,
        ));
    }
    for s in &h.sensors {
        let names: Vec<String> = ["x", "y", "z"]
            .iter()
            .zip(s.axes)
            .map(|(a, on)| if on { acc(&s.name, a) } else { String::new() })
            .collect();
        let refs: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
        out.push(named(
            &format!("{ACC_PREFIX}{}", s.name),
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
            (TyreQuantity::NormalForce, TYRE_FZ),
            (TyreQuantity::Contact, TYRE_CONTACT),
        ] {
            let name = tyre(&w.name, suffix);
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
        let names: Vec<String> = (1..=hh.modes).map(hitch_eta).collect();
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
            HITCH_STRAIN_ENERGY,
            Request::Modal {
                body: hh.body,
                quantity: ModalQuantity::StrainEnergy,
            },
            &[HITCH_STRAIN_ENERGY],
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
                &HITCH_DEFLECTION,
                1.0,
            ));
            // Nominal stresses at the flex file's stress points (flex::stress).
            for (point, sp) in md.data.stress.points.iter().enumerate() {
                let names: Vec<String> = towride_mbs::model::output::STRESS_PARTS
                    .iter()
                    .map(|c| format!("hitch_stress_{}_{c}", sp.name))
                    .collect();
                let refs: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
                out.push(named(
                    &format!("hitch_stress_{}", sp.name),
                    Request::Modal {
                        body: hh.body,
                        quantity: ModalQuantity::Stress { point },
                    },
                    &refs,
                    1.0,
                ));
            }
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
