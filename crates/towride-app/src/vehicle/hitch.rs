//! The towing hitch: the crossbeam with brackets and hook as one modal body (the
//! Craig-Bampton data of `flex/hitch_crossbeam.toml`, variant 1..10, modes selected by
//! the file's rule), held on the car body by bushings at its two bracket interface nodes
//! (the thesis: bushings, not fixed joints, so the few kept modes do not over-constrain
//! it), and the ball coupling to the trailer drawbar at the ball interface node:
//! a spherical joint, a stiff bushing, or a coupling head (a bushing whose translations
//! have a smoothly regularised play and whose rotations a regularised friction torque:
//! `LawSpec::DeadBand`, `LawSpec::Friction`; docs/hitch_mounts.md).

use std::path::Path;

use serde::Deserialize;

use super::build::{Builder, Link};
use super::geom::{IDENTITY, V};
use super::modal_body;
use super::props::{at, joint_bushing, point, BushingLaws, BushingProps};
use towride_mbs::input::{InputError, Source};
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::model::desc::JointKind;
use towride_mbs::model::elements::{JointBushing, LawSpec};
use towride_mbs::model::math::add;
use towride_mbs::path;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    hitch: Hitch,
    mounting: Mounting,
    ball_coupling: BallCouplingSec,
    /// The coupling's UN R55 rating (optional).
    rating: Option<crate::durability::coupling::RatingIn>,
}

/// How each bracket is held on the body: the bolted joint in series with the body-side
/// compliance of the side-member end at the bolts (docs/hitch_mounts.md), per axis of
/// the mount (x, y, z; rotations about them), and the path's damping as a loss factor.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Mounting {
    /// Mount z axis (the bolt axis) and x axis, vehicle coordinates.
    z_axis: [f64; 3],
    x_axis: [f64; 3],
    /// Body side (side-member end and panel at the bolts) [N/m], [N m/rad].
    body_stiffness_n_m: [f64; 3],
    body_stiffness_n_m_rad: [f64; 3],
    /// The bracket's bolts together [N/m], [N m/rad].
    bolt_stiffness_n_m: [f64; 3],
    bolt_stiffness_n_m_rad: [f64; 3],
    /// Loss factor of the path (material and joint damping) [-].
    loss_factor: f64,
    /// Frequency at which the viscous damping equals the loss factor's [Hz].
    damping_reference_hz: f64,
}

impl Mounting {
    /// Series stiffness per axis and the viscous damping c = eta k / omega_ref.
    fn laws(&self, src: &Source) -> Result<BushingLaws, InputError> {
        let p = path!["mounting"];
        let eta = src.non_negative(&at(&p, "loss_factor"), self.loss_factor)?;
        let f = src.positive(&at(&p, "damping_reference_hz"), self.damping_reference_hz)?;
        let omega = 2.0 * std::f64::consts::PI * f;
        let series = |body: &[f64; 3], bolt: &[f64; 3], bk: &str, ok: &str| {
            let mut k = [0.0; 3];
            for i in 0..3 {
                let a = src.positive(&at(&at(&p, bk), i), body[i])?;
                let b = src.positive(&at(&at(&p, ok), i), bolt[i])?;
                k[i] = a * b / (a + b);
            }
            Ok::<_, InputError>(k)
        };
        let kt = series(
            &self.body_stiffness_n_m,
            &self.bolt_stiffness_n_m,
            "body_stiffness_n_m",
            "bolt_stiffness_n_m",
        )?;
        let kr = series(
            &self.body_stiffness_n_m_rad,
            &self.bolt_stiffness_n_m_rad,
            "body_stiffness_n_m_rad",
            "bolt_stiffness_n_m_rad",
        )?;
        let lin = |k: [f64; 3], scale: f64| k.map(|x| LawSpec::Linear(x * scale));
        BushingProps {
            z_axis: Some(self.z_axis),
            x_axis: Some(self.x_axis),
            stiffness_n_m: lin(kt, 1.0),
            damping_n_s_m: lin(kt, eta / omega),
            stiffness_n_m_rad: lin(kr, 1.0),
            damping_n_m_s_rad: lin(kr, eta / omega),
        }
        .check(src, &p, [0.0, 1.0, 0.0])
    }
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Hitch {
    /// The FE model (relative to this file).
    fe_file: String,
    /// Crossbeam variant 1..10.
    variant: u32,
    /// Where the FE file's origin lies in vehicle coordinates [m] (its axes are the
    /// vehicle's).
    fe_origin_m: [f64; 3],
    /// Inertia coupling of the modal body: constant, partial or full.
    inertia_coupling: String,
    bracket_nodes: [String; 2],
    ball_node: String,
    sensor_node: String,
    /// How the brackets are held.
    #[serde(default)]
    bracket_mount: BracketMount,
}

/// How the hitch's brackets are held on the body.
#[derive(Deserialize, Clone, Copy, Debug, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
enum BracketMount {
    /// Bushings of the `[mounting]` table.
    #[default]
    Bushing,
    /// Ideal fixed joints: the thesis's over-constrained variant, for stress tests.
    Fixed,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct BallCouplingSec {
    kind: BallCoupling,
    /// The bushing used for kind = "bushing" (translations only: a ball passes no
    /// moments).
    bushing: Option<JointBushing>,
    /// The bushing used for kind = "coupling_head" (axes in vehicle coordinates).
    coupling_head: Option<BushingProps>,
}

/// How the drawbar is to be coupled to the ball: the hitch file's `ball_coupling.kind`,
/// a scene's `ball_coupling`.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BallCoupling {
    /// An ideal spherical joint.
    Spherical,
    /// The hitch file's stiff bushing.
    Bushing,
    /// The hitch file's coupling head: play, compliance and friction torque.
    CouplingHead,
}

impl std::fmt::Display for BallCoupling {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(match self {
            BallCoupling::Spherical => "spherical",
            BallCoupling::Bushing => "bushing",
            BallCoupling::CouplingHead => "coupling_head",
        })
    }
}

/// How the drawbar is coupled to the ball, as built.
#[derive(Clone, Debug)]
pub enum BallKind {
    /// An ideal spherical joint.
    Spherical,
    /// A bushing with these properties (translations only).
    Bushing(JointBushing),
    /// A coupling head: a bushing with these six laws.
    Head(Box<BushingLaws>),
}

/// What the rest of the vehicle needs of the hitch.
#[derive(Clone, Debug)]
pub struct HitchHandle {
    /// The crossbeam's modal body.
    pub body: BodyHandle,
    /// Ball centre, vehicle coordinates [m].
    pub ball: V,
    /// Index of the ball interface node in the modal data.
    pub ball_node: usize,
    /// Index of the crossbeam sensor node.
    pub sensor_node: usize,
    /// Sensor node position, vehicle coordinates [m].
    pub sensor: V,
    /// How the drawbar is coupled to the ball.
    pub ball_kind: BallKind,
    /// FE origin in vehicle coordinates (checked against the rear axle).
    pub fe_origin: V,
    /// Crossbeam variant in use (1..10).
    pub variant: u32,
    /// Number of selected modes.
    pub modes: usize,
    /// The bracket mounts, left then right (I: the hitch, J: the car body, at the
    /// bracket interface nodes' design positions, the bolt-pattern centres).
    pub brackets: [Link; 2],
    /// Where to complain about `fe_origin_m`.
    pub origin_complaint: InputError,
    /// The coupling's UN R55 rating, when the file gives one.
    pub rating: Option<crate::durability::coupling::Rating>,
}

/// Reads `file` and adds the hitch to the car body `body`; `variant` overrides the file.
pub fn build(
    b: &mut Builder,
    file: &Path,
    body: BodyHandle,
    variant: Option<u32>,
    ball: Option<BallCoupling>,
) -> Result<HitchHandle, InputError> {
    let src = b.read(file)?;
    let f: File = src.parse()?;
    let h = &f.hitch;
    let origin = point(&src, &path!["hitch", "fe_origin_m"], &h.fe_origin_m)?;
    let variant = variant.unwrap_or(h.variant);
    let coupling = modal_body::coupling(
        &src,
        &path!["hitch", "inertia_coupling"],
        &h.inertia_coupling,
    )?;
    let fe = file.parent().unwrap_or(Path::new(".")).join(&h.fe_file);
    let data = modal_body::load(
        &src,
        &path!["hitch", "fe_file"],
        &fe,
        Some(variant),
        None,
        b,
        "hitch",
    )?;
    let brackets = modal_body::nodes(
        &src,
        &path!["hitch", "bracket_nodes"],
        &data,
        &fe,
        &h.bracket_nodes,
    )?;
    let ball_node = modal_body::node(&src, &path!["hitch", "ball_node"], &data, &fe, &h.ball_node)?;
    let sensor_node = modal_body::node(
        &src,
        &path!["hitch", "sensor_node"],
        &data,
        &fe,
        &h.sensor_node,
    )?;
    let bushing = f.mounting.laws(&src)?;
    let ball_kind = match ball.unwrap_or(f.ball_coupling.kind) {
        BallCoupling::Spherical => BallKind::Spherical,
        BallCoupling::Bushing => {
            let jb = joint_bushing(
                &src,
                &path!["ball_coupling", "bushing"],
                &f.ball_coupling.bushing,
            )?;
            BallKind::Bushing(jb.ok_or_else(|| {
                src.error(
                    &path!["ball_coupling"],
                    "the bushing coupling needs a bushing table",
                )
            })?)
        }
        BallCoupling::CouplingHead => {
            let p = path!["ball_coupling", "coupling_head"];
            let head = f.ball_coupling.coupling_head.as_ref().ok_or_else(|| {
                src.error(
                    &path!["ball_coupling"],
                    "the coupling_head coupling needs a coupling_head table",
                )
            })?;
            BallKind::Head(Box::new(head.check(&src, &p, [0.0, 0.0, 1.0])?))
        }
    };
    let at = |p: &[f64; 3]| add(&origin, p);
    let fixed = h.bracket_mount == BracketMount::Fixed;
    let (ball, sensor) = (
        at(&data.nodes[ball_node].position_m),
        at(&data.nodes[sensor_node].position_m),
    );
    let modes = data.modes.len();
    let hb = modal_body::add_body(b, "hitch", data, origin, coupling)?;
    let mut mounts = Vec::with_capacity(2);
    for (k, &n) in brackets.iter().enumerate() {
        let p = modal_body::node_position(b, hb, origin, n);
        let name = format!("hitch_bracket_{}", ["left", "right"][k]);
        let link = if fixed {
            b.add(|m| {
                m.ideal_joint(
                    &name,
                    JointKind::Fixed,
                    Some(hb),
                    Some(body),
                    p,
                    &bushing.axes,
                )
            })?
        } else {
            b.bushing_link(&name, Some(hb), Some(body), p, &bushing.axes, &bushing)?
        };
        modal_body::pin(b, link, true, n);
        mounts.push(link);
    }
    Ok(HitchHandle {
        body: hb,
        ball,
        ball_node,
        sensor_node,
        sensor,
        ball_kind,
        fe_origin: origin,
        variant,
        modes,
        brackets: [mounts[0], mounts[1]],
        origin_complaint: src.error(&path!["hitch", "fe_origin_m"], ""),
        rating: f.rating.as_ref().map(|r| r.check(&src)).transpose()?,
    })
}

/// The ball coupling between the hitch ball node and the trailer's drawbar (its body and,
/// for a flexible drawbar, its ball node; the builder placed in the car's coordinates). Joint: I = hitch ball, so its reaction is
/// the drawbar's force on the car. Bushing: I = drawbar, J = hitch ball, so its force in
/// J's axes is minus the force on the car in (nearly) car axes.
/// A model-wide switch of joints to bushings turns the ball joint into that bushing.
pub fn couple(
    b: &mut Builder,
    h: &HitchHandle,
    (drawbar, node): (BodyHandle, Option<usize>),
    joints_as_bushings: Option<&JointBushing>,
) -> Result<(Link, BallKind), InputError> {
    let name = "ball_coupling";
    let kind = match (&h.ball_kind, joints_as_bushings) {
        (BallKind::Spherical, Some(g)) => BallKind::Bushing(g.clone()),
        (k, _) => k.clone(),
    };
    let link = match &kind {
        BallKind::Spherical => {
            let link = b.add(|m| {
                m.joint(
                    name,
                    JointKind::Spherical,
                    Some(h.body),
                    Some(drawbar),
                    h.ball,
                    &IDENTITY,
                    None,
                )
            })?;
            modal_body::pin(b, link, true, h.ball_node);
            pin_drawbar(b, link, false, node);
            link
        }
        BallKind::Bushing(jb) => {
            let link = b.add(|m| {
                m.joint(
                    name,
                    JointKind::Spherical,
                    Some(drawbar),
                    Some(h.body),
                    h.ball,
                    &IDENTITY,
                    Some(jb),
                )
            })?;
            modal_body::pin(b, link, false, h.ball_node);
            pin_drawbar(b, link, true, node);
            link
        }
        BallKind::Head(laws) => {
            let link =
                b.bushing_link(name, Some(drawbar), Some(h.body), h.ball, &laws.axes, laws)?;
            modal_body::pin(b, link, false, h.ball_node);
            pin_drawbar(b, link, true, node);
            link
        }
    };
    Ok((link, kind))
}

/// A ball fixed on the car body at `ball` (car coordinates; no crossbeam: the `simple`
/// vehicle files' hitch) coupled to the trailer body `drawbar` by a spherical joint, the
/// builder placed in the car's coordinates. A model-wide switch of joints to bushings
/// turns it into that bushing, the drawbar then I as in [`couple`].
pub fn couple_on_body(
    b: &mut Builder,
    car_body: BodyHandle,
    ball: V,
    (drawbar, node): (BodyHandle, Option<usize>),
    joints_as_bushings: Option<&JointBushing>,
) -> Result<(Link, BallKind), InputError> {
    let (i, j) = match joints_as_bushings {
        None => (car_body, drawbar),
        Some(_) => (drawbar, car_body),
    };
    let link = b.add(|m| {
        m.joint(
            "ball_coupling",
            JointKind::Spherical,
            Some(i),
            Some(j),
            ball,
            &IDENTITY,
            None,
        )
    })?;
    pin_drawbar(b, link, joints_as_bushings.is_some(), node);
    let kind = match joints_as_bushings {
        None => BallKind::Spherical,
        Some(jb) => BallKind::Bushing(jb.clone()),
    };
    Ok((link, kind))
}

/// Pins the coupling's drawbar marker (I when `on_i`) to the flexible drawbar's ball node.
fn pin_drawbar(b: &mut Builder, link: Link, on_i: bool, node: Option<usize>) {
    if let Some(n) = node {
        modal_body::pin(b, link, on_i, n);
    }
}
