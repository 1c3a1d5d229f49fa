//! A vehicle description: the vehicle's slots, each naming a template with its property
//! data, as either kind of vehicle file gives them. An assembly file names templates and
//! property files ([`super::assembly_file`]); a compact `simple` file's few numbers are
//! translated into the same slots with derived data ([`super::simple`]). The one
//! assembly path, [`super::assembly::assemble`], turns a description into builder calls
//! and runs the design statics.

use std::path::PathBuf;

use serde::Serialize;

use super::axle::AxleSpec;
use super::driveline::Gains;
use super::geom::V;
use super::props::Mass;
use super::sensors::SensorSpec;
use super::trailer::TrailerSpec;
use towride_mbs::input::{InputError, Loader, Seg, Source};
use towride_mbs::tyre::{Tyre, TyreKind};

/// What a vehicle is made of.
pub struct Description {
    /// The vehicle file: errors about the vehicle as a whole and its sensors are
    /// located in it.
    pub src: Source,
    /// The model's name.
    pub name: String,
    /// Gravity, world axes [m/s^2] (it also sets the design loads).
    pub gravity: V,
    /// The model of the tyres read from `.tir` files.
    pub tyre_kind: TyreKind,
    /// The car body (`lumped_body`).
    pub body: BodySpec,
    /// The engine on its mounts (`engine_on_mounts`): its property file.
    pub engine: Option<PathBuf>,
    /// The front axle, then the rear.
    pub axles: [AxleDesc; 2],
    /// The speed controller (`speed_control`).
    pub driveline: DrivelineSpec,
    /// The towing hitch, when the car has one.
    pub hitch: Option<HitchSpec>,
    /// The trailer, when there is one.
    pub trailer: Option<TrailerDesc>,
    /// Sensor lists, each at its place in `src`, added in this order.
    pub sensors: Vec<(Vec<Seg>, Vec<SensorSpec>)>,
    /// Values the vehicle file left to defaults or derived from its numbers: the car's
    /// (the trailer's and the driveline's are with those parts).
    pub assumed: Vec<Assumed>,
}

/// The car body's mass properties.
pub enum BodySpec {
    /// The `lumped_body` property file.
    File(PathBuf),
    /// Derived in code.
    Given(Mass),
}

/// An axle slot: template with data, and tyre.
pub struct AxleDesc {
    pub spec: AxleSpec,
    pub tyre: TyreSpec,
}

/// A tyre.
pub enum TyreSpec {
    /// A `.tir` file, read with the description's tyre model when the axle is built.
    File(PathBuf),
    /// Made in code (a compact file's size and stiffness on the defaults' base `.tir`).
    Given(Box<Tyre>),
}

impl TyreSpec {
    /// The tyre, of model `kind` when read from a file.
    pub fn tyre(self, kind: TyreKind, loader: &Loader) -> Result<Tyre, InputError> {
        match self {
            TyreSpec::File(f) => Tyre::from_file(&f, kind, loader),
            TyreSpec::Given(t) => Ok(*t),
        }
    }
}

/// The speed controller.
pub enum DrivelineSpec {
    /// The `speed_control` property file.
    File(PathBuf),
    /// Gains derived in code, and what was assumed or derived for them.
    Given { gains: Gains, assumed: Vec<Assumed> },
}

/// The towing hitch.
pub enum HitchSpec {
    /// The `modal_hitch` property file (crossbeam as a modal body, ball coupling).
    Modal(PathBuf),
    /// A ball fixed on the car body at this point, car coordinates [m].
    Ball(V),
}

/// The trailer slot.
pub struct TrailerDesc {
    pub spec: TrailerSpec,
    pub tyre: TyreSpec,
    /// Where the vehicle file gives the trailer (errors of its placement).
    pub at: Vec<Seg>,
    /// What was assumed or derived for the trailer.
    pub assumed: Vec<Assumed>,
}

/// A value a compact vehicle file did not give or that follows from its numbers.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Assumed {
    /// What it stands for, as a field of the compact file (`front.wheel_mass_kg`).
    pub field: String,
    /// The value (NaN for a choice without a number, such as a file).
    pub value: f64,
    /// Its unit.
    pub unit: String,
    /// `assumed` (from the defaults file) or `derived` (from the file's numbers).
    pub kind: Kind,
    /// Where it comes from.
    pub source: String,
}

/// Whether a value was assumed or derived.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Taken from the defaults file.
    Assumed,
    /// Computed from the vehicle file's own numbers (or by the design statics).
    Derived,
}
