//! Vehicle templates: property files (TOML in `vehicles/`) turned into bodies, markers,
//! joints or bushings and force elements of a [`Model`], knowing nothing about the
//! solver. `docs/vehicle.md` documents the templates, coordinates and every field.
//!
//! Two kinds of vehicle file, one assembly path: an assembly file (`vehicles/*.toml`,
//! [`assembly_file`]) names the templates and property files that make a vehicle; a
//! compact `simple` file ([`simple`]) gives a few numbers from which the same slots'
//! data are derived. Either becomes a [`description::Description`], which
//! [`assembly::assemble`] turns into builder calls, with the design statics, once.
//! [`load`] returns the [`Vehicle`]: the model (bodies, tyres, the speed controller; no
//! road and no outputs yet, a scene adds those) plus named [`Handles`] and what the
//! design statics found ([`Design`]).
//!
//! Coordinates: x forward, y left, z up. The car's origin is on the ground under the
//! centre of the front axle at the design ride height (car with driver, no trailer);
//! the trailer's is on the ground under its coupling's ball centre. Hardpoints are given
//! at the design position; left-side values are mirrored for the right side.
//!
//! Templates (the registry: `templates!` below): axles ([`axle`]) [`mcpherson`],
//! [`twist_beam`] (its cross member rigid or flexible: [`twist_flex`]),
//! [`trailing_arm_axle`]; trailers ([`trailer`]) [`box_trailer`], [`lumped_trailer`];
//! one template per other slot: [`body`] (lumped body), [`engine`], [`driveline`] (speed
//! control), [`hitch`] (modal crossbeam and ball coupling). Shared pieces in [`wheel`],
//! [`swing`], [`design`] (spring preloads by virtual work), [`air`] (levelled air
//! springs), [`build`], [`props`], [`geom`], [`sensors`], [`strut`] (McPherson
//! kinematics), [`modal_body`] (modal bodies of the hitch and the cross member).

pub(crate) mod air;
pub(crate) mod assembly;
pub(crate) mod assembly_file;
pub mod axle;
pub(crate) mod body;
pub(crate) mod build;
pub(crate) mod description;
pub(crate) mod design;
pub(crate) mod drawbar;
pub(crate) mod driveline;
pub(crate) mod engine;
pub(crate) mod geom;
pub(crate) mod hitch;
pub(crate) mod modal_body;
pub(crate) mod props;
pub(crate) mod sensors;
pub mod simple;
pub(crate) mod strut;
pub(crate) mod swing;
pub mod trailer;
pub(crate) mod twist_flex;
pub(crate) mod wheel;

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::Serialize;

/// The registry: declares the templates' modules and lists them in [`axle::TEMPLATES`]
/// and [`trailer::TEMPLATES`], `file::Type` per template.
macro_rules! templates {
    (axle: $($am:ident::$at:ident),* ; trailer: $($tm:ident::$tt:ident),* $(;)?) => {
        $(pub(crate) mod $am;)*
        $(pub(crate) mod $tm;)*

        /// The registered axle templates.
        pub(crate) static AXLE_TEMPLATES: &[&dyn axle::AxleTemplate] = &[$(&$am::$at),*];
        /// The registered trailer templates.
        pub(crate) static TRAILER_TEMPLATES: &[&dyn trailer::TrailerTemplate] =
            &[$(&$tm::$tt),*];
    };
}

// The registered templates. A new one is its file in this folder and one line here.
templates! {
    axle:
        mcpherson::McPherson,
        trailing_arm_axle::TrailingArmAxle,
        twist_beam::TwistBeam;
    trailer:
        box_trailer::BoxTrailer,
        lumped_trailer::LumpedTrailer;
}

pub use build::Link;
pub use design::CornerDesign;
pub use geom::Placement;
pub use hitch::{BallCoupling, BallKind, HitchHandle};
pub use sensors::Sensor;
pub use twist_flex::CrossMember;
pub use wheel::WheelHandle;

use towride_mbs::flex::feedback::RunModes;
use towride_mbs::model::builder::{BodyHandle, MarkerHandle};
use towride_mbs::model::elements::JointBushing;
use towride_mbs::model::Model;
use towride_mbs::tyre::TyreKind;

/// Choices that override the files'.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Set speed of the driveline and initial forward speed of every body [m/s]; the
    /// wheels spin at the free-rolling rate.
    pub speed: f64,
    /// World x of the car's origin [m] (the road's x = 0 is where the front wheels
    /// touch it at the start).
    pub x_offset: f64,
    /// Trailer load case (assembly file: `trailer.load_case`).
    pub load_case: Option<String>,
    /// Hitch crossbeam variant 1..10 (hitch file: `hitch.variant`).
    pub hitch_variant: Option<u32>,
    /// Tyre model (assembly file: `vehicle.tyre_model`).
    pub tyre_kind: Option<TyreKind>,
    /// Every ideal joint becomes a bushing of these properties.
    pub joints_as_bushings: Option<JointBushing>,
    /// Ball coupling (hitch file: `ball_coupling.kind`; the bushing's properties always
    /// come from the hitch file).
    pub ball_coupling: Option<BallCoupling>,
    /// Rear axle cross member (rear axle file: `cross_member.kind`).
    pub rear_cross_member: Option<CrossMember>,
    /// Modes of the modal bodies selected from an earlier run's strain-energy shares,
    /// replacing the files' selection rules (`--modes-from`, a scene's `modes_from`).
    pub run_modes: Option<Arc<RunModes>>,
    /// The speed the driveline follows (a scene's `[run.manoeuvre]`); `None` holds
    /// `speed`.
    pub speed_target: Option<towride_mbs::model::function::TimeFunction>,
    /// The steering rack's travel to the left over time [m] (a scene's
    /// `[run.steering]`); `None`: no rack is built and the tie rods sit on the body.
    pub steering: Option<towride_mbs::model::function::TimeFunction>,
}

/// A vehicle ready for a scene.
#[derive(Clone, Debug)]
pub struct Vehicle {
    /// The multibody model: bodies, joints, elements and tyres.
    pub model: Model,
    /// Named parts a scene needs.
    pub handles: Handles,
    /// What the design statics found.
    pub design: Design,
    /// Values a compact (`simple`) vehicle file left to the defaults or derived from its
    /// numbers, and values the design statics derived (air springs' pressures); empty
    /// for an assembly file of coil springs and rubber, which gives everything.
    pub assumed: Vec<simple::Assumed>,
    /// The driver's seat (`[seat]` of the body file), for the comfort at the seat
    /// surface; `None` when the body file gives none.
    pub seat: Option<crate::comfort::Seat>,
}

/// Reads a vehicle file, an assembly file ([`assembly_file`]) or a compact `simple` file
/// ([`simple`]), and builds the vehicle by the one assembly path, every file read
/// through `loader`.
pub fn load(
    path: &std::path::Path,
    opts: &Options,
    loader: &towride_mbs::input::Loader,
) -> Result<Vehicle, towride_mbs::input::InputError> {
    let description = if simple::is_simple(path) {
        simple::describe(path, opts, loader)?
    } else {
        assembly_file::describe(path, opts, loader)?
    };
    assembly::assemble(description, opts, loader)
}

/// Named parts a scene needs.
#[derive(Clone, Debug)]
pub struct Handles {
    /// The car body.
    pub car_body: BodyHandle,
    /// Marker at the car body's centre of mass with the vehicle's axes (speed sensor,
    /// axes of the hitch force).
    pub car_ref: MarkerHandle,
    /// Wheels fl, fr, rl, rr, then the trailer's tl, tr.
    pub wheels: Vec<WheelHandle>,
    /// The towbar crossbeam, when the car has one.
    pub hitch: Option<HitchHandle>,
    /// The ball coupling (joint or bushing) and what it became.
    pub ball: Option<(Link, BallKind)>,
    /// The trailer box, when there is a trailer.
    pub trailer_body: Option<BodyHandle>,
    /// Marker at the trailer box's centre of mass with its axes.
    pub trailer_ref: Option<MarkerHandle>,
    /// Markers on the car body above each car wheel (top mounts, upper spring seats),
    /// by wheel name: ride heights are measured between them and the wheel centres.
    pub ride: Vec<(String, MarkerHandle)>,
    /// Acceleration sensors, the vehicle's and the scene's (channels `acc_<name>_<axis>`).
    pub sensors: Vec<Sensor>,
    /// Every body by name.
    pub bodies: BTreeMap<String, BodyHandle>,
    /// Placement of the car's coordinates in the world.
    pub car_place: Placement,
    /// Placement of the trailer's coordinates in the world, when there is a trailer.
    pub trailer_place: Option<Placement>,
    /// The placement of each body's subsystem (indexed like `Model::bodies`): sensor
    /// positions are given in these coordinates.
    pub body_place: Vec<Placement>,
    /// The car's levelled air springs by wheel (element `spring_<w>`): their effective
    /// areas turn the spring force into a pressure.
    pub air_springs: Vec<(String, air::AirSpring)>,
}

impl Handles {
    /// The placement of body `b`'s subsystem.
    pub fn place_of(&self, b: BodyHandle) -> Option<Placement> {
        // `body_place` is a table in the model's body order.
        self.body_place.get(b.index()).copied()
    }
}

/// What the design statics found (no solver involved).
#[derive(Clone, Debug, Serialize)]
pub struct Design {
    /// Car with driver, hitch and the tyres' belts [kg], centre of mass in vehicle
    /// coordinates [m].
    pub car_mass_kg: f64,
    /// Centre of mass of the car, vehicle coordinates [m].
    pub car_cm_m: [f64; 3],
    /// Car corners fl, fr, rl, rr at the design position.
    pub car_corners: Vec<CornerDesign>,
    /// The trailer's design statics, when there is a trailer.
    pub trailer: Option<TrailerDesign>,
    /// Everything, belts included [kg].
    pub total_mass_kg: f64,
}

/// What the design statics found for the trailer.
#[derive(Clone, Debug, Serialize)]
pub struct TrailerDesign {
    /// The trailer load case.
    pub load_case: String,
    /// With the payload [kg]; centre of mass in trailer coordinates [m].
    pub mass_kg: f64,
    /// Centre of mass with the payload, trailer coordinates [m].
    pub cm_m: [f64; 3],
    /// Empty trailer: ball load [N] and corners (the rubber's preload).
    pub empty_ball_load_n: f64,
    /// Trailer corners tl, tr of the empty trailer (the rubber's preload).
    pub corners: Vec<CornerDesign>,
    /// Pitch of the trailer placed on the ball [rad] (positive: nose down).
    pub pitch_rad: f64,
}
