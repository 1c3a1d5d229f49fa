//! What a vehicle needs from any axle (suspension) template, and the registry of axle
//! templates. The assembly file names a template per axle slot
//! (`front = { template = "mcpherson", ... }`); any registered axle template fits any
//! axle slot. Adding a template is its own file plus one line in the `axle_templates!`
//! list of `vehicle/mod.rs`.

use std::path::Path;

use super::build::Builder;
use super::design::Corner;
use super::geom::V;
use super::wheel::WheelHandle;
use towride_mbs::input::InputError;
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::tyre::Tyre;

/// Where an axle goes and what it gets.
pub struct AxleSlot<'a> {
    /// The body it hangs on (the car body).
    pub carrier: BodyHandle,
    /// The tyre of its wheels.
    pub tyre: &'a Tyre,
    /// Short names of its wheels, left then right (`fl`, `fr` or `rl`, `rr`).
    pub wheels: [&'a str; 2],
    /// A template variant asked for by the scene (the twist beam's "rigid" or
    /// "flexible" cross member), if any.
    pub variant: Option<&'a str>,
}

/// A built axle: what the design statics, the ride heights and the scene need.
pub struct Axle {
    /// Wheels, left then right.
    pub wheels: Vec<WheelHandle>,
    /// The corners awaiting their static loads (springs get their preloads then).
    pub corners: Vec<Corner>,
    /// Per wheel, the point on the carrier above it (top mount, upper spring seat),
    /// vehicle coordinates: ride heights are measured to it.
    pub body_mounts: Vec<V>,
    /// A flexible member of the axle: its body and number of selected modes.
    pub flexible: Option<(BodyHandle, usize)>,
}

/// An axle template: reads its property file and adds both sides.
pub trait AxleTemplate: Sync {
    /// The name the assembly file uses.
    fn name(&self) -> &'static str;
    /// Reads `file` and adds the axle at `slot`.
    fn build(&self, b: &mut Builder, file: &Path, slot: &AxleSlot) -> Result<Axle, InputError>;
}

/// The registered axle templates (listed in `vehicle/mod.rs`).
pub static TEMPLATES: &[&dyn AxleTemplate] = super::AXLE_TEMPLATES;

/// The template named `name`.
pub fn template(name: &str) -> Option<&'static dyn AxleTemplate> {
    TEMPLATES.iter().copied().find(|t| t.name() == name)
}

/// The registered names, for messages.
pub fn names() -> Vec<&'static str> {
    TEMPLATES.iter().map(|t| t.name()).collect()
}
