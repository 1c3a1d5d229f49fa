//! What a vehicle needs from any trailer template, and the registry's trailer templates
//! (the same three tiers as [`super::axle`]): [`TrailerData`] places the trailer on the
//! ball and adds it with its design statics; a template fixes its topology
//! (`box_trailer.rs`: a box on a rubber torsion axle; `lumped_trailer.rs`: a lumped body
//! on an axle of any registered axle template); its data come from a property file
//! ([`TrailerTemplate::read`]) or from code ([`TrailerSpec::Given`]). Adding a template is
//! its own file plus one line in the `templates!` list of `vehicle/mod.rs`.
//!
//! Trailer coordinates: x forward (towards the car), y left, z up, origin on the ground
//! under the coupling's ball centre, the empty trailer at its design attitude.

use crate::error::DesignError;
use std::path::{Path, PathBuf};

use super::build::Builder;
use super::design::CornerDesign;
use super::geom::{Placement, V};
use super::wheel::WheelHandle;
use towride_mbs::input::InputError;
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::tyre::Tyre;

/// What a trailer gets.
pub struct TrailerSlot<'a> {
    /// The tyre of its wheels.
    pub tyre: &'a Tyre,
}

/// A built trailer.
pub struct Trailer {
    /// The trailer's main body (box, chassis and, unless flexible, the drawbar).
    pub body: BodyHandle,
    /// The body the ball coupling holds: the main body, or a flexible drawbar.
    pub coupling_body: BodyHandle,
    /// The modal node the coupling acts at, when `coupling_body` is a modal body.
    pub coupling_node: Option<usize>,
    /// Wheels, left then right (`tl`, `tr`).
    pub wheels: Vec<WheelHandle>,
    /// Design statics of the empty trailer (the springs' preloads).
    pub corners: Vec<CornerDesign>,
    /// Static load on the ball of the empty trailer [N].
    pub design_ball_load_n: f64,
    /// Mass with the payload [kg].
    pub mass: f64,
    /// Centre of mass with the payload, trailer coordinates [m].
    pub cm: V,
    /// The load case built.
    pub load_case: String,
}

/// A trailer template with its data, checked: ready to be placed and added.
pub trait TrailerData {
    /// Where the trailer goes with its coupling on the ball at `ball` (world), and its
    /// pitch [rad] (positive: nose down); or why it cannot sit there.
    fn place(&self, ball: V) -> Result<(Placement, f64), DesignError>;
    /// Adds the trailer and its design statics, the builder placed in trailer
    /// coordinates.
    fn build(self: Box<Self>, b: &mut Builder, slot: &TrailerSlot) -> Result<Trailer, InputError>;
}

/// A trailer template of the registry: its name and its property-file reader.
pub trait TrailerTemplate: Sync {
    /// The name the assembly file uses.
    fn name(&self) -> &'static str;
    /// Reads and checks the property file `file` with the load case `load_case` (the
    /// file's first when `None`), through `b`'s loader.
    fn read(
        &self,
        b: &mut Builder,
        file: &Path,
        load_case: Option<&str>,
    ) -> Result<Box<dyn TrailerData>, InputError>;
}

/// A trailer's template and data, as a vehicle description holds them.
pub enum TrailerSpec {
    /// A registered template, its property file and the load case asked for.
    File {
        /// The template.
        template: &'static dyn TrailerTemplate,
        /// Its property file.
        file: PathBuf,
        /// The load case the vehicle file names, if any.
        load_case: Option<String>,
    },
    /// A template's data made in code (a compact file's derived values).
    Given(Box<dyn TrailerData>),
}

impl TrailerSpec {
    /// The data: read from the property file (the scene's load case `load_case` before
    /// the assembly file's), or as given.
    pub fn data(
        self,
        b: &mut Builder,
        load_case: Option<&str>,
    ) -> Result<Box<dyn TrailerData>, InputError> {
        match self {
            TrailerSpec::File {
                template,
                file,
                load_case: own,
            } => template.read(b, &file, load_case.or(own.as_deref())),
            TrailerSpec::Given(data) => Ok(data),
        }
    }
}

/// The registered trailer templates (listed in `vehicle/mod.rs`).
pub static TEMPLATES: &[&dyn TrailerTemplate] = super::TRAILER_TEMPLATES;

/// The template named `name`.
pub fn template(name: &str) -> Option<&'static dyn TrailerTemplate> {
    TEMPLATES.iter().copied().find(|t| t.name() == name)
}

/// The registered names, for messages.
pub fn names() -> Vec<&'static str> {
    TEMPLATES.iter().map(|t| t.name()).collect()
}

/// A trailer with its coupling `coupling` (trailer coordinates) on the ball at `ball`
/// (world), pitched about the ground line of its axle at x = `axle_x` so its wheels
/// stay on the ground: the placement and the pitch [rad], or why it cannot sit there
/// (`origin`: the trailer's file, for the message).
pub fn pitched_on_ball(
    origin: &str,
    coupling: V,
    axle_x: f64,
    ball: V,
) -> Result<(Placement, f64), DesignError> {
    let (a, h) = (coupling[0] - axle_x, coupling[2]);
    let rho = a.hypot(h);
    let pitch = (ball[2] / rho).clamp(-1.0, 1.0).acos() - a.atan2(h);
    // More than about 6 deg means the files disagree on the ball height.
    if pitch.is_nan() || pitch.abs() > 0.1 || coupling[1] != 0.0 {
        return Err(DesignError::CouplingCannotPitch {
            origin: origin.to_string(),
            coupling_height_m: h,
            coupling_y_m: coupling[1],
            ball_height_m: ball[2],
            pitch_rad: pitch,
        });
    }
    let x_rot = axle_x + pitch.cos() * a + pitch.sin() * h;
    let place = Placement::pitched([axle_x, 0.0, 0.0], pitch, [ball[0] - x_rot, ball[1], 0.0]);
    Ok((place, pitch))
}
