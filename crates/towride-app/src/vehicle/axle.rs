//! What a vehicle needs from any axle (suspension) template, and the registry's axle
//! templates. Three tiers, as in Chrono's vehicle module: [`AxleData`] is what the
//! assembly asks of an axle (add both sides, hand back the wheels and the corners
//! awaiting their static loads); a template fixes the topology and names its hardpoints
//! (`mcpherson.rs`, `twist_beam.rs`, `trailing_arm_axle.rs`); its data come from a
//! property file ([`AxleTemplate::read`]) or from code (a compact `simple` file's derived
//! values, [`AxleSpec::Given`]). Any registered axle template fits any axle slot, the car's
//! and a trailer's. Adding a template is its own file plus one line in the `templates!`
//! list of `vehicle/mod.rs`.

use std::path::{Path, PathBuf};

use super::build::Builder;
use super::design::Corner;
use super::geom::V;
use super::props::at;
use super::twist_flex::CrossMember;
use super::wheel::WheelHandle;
use towride_mbs::input::{InputError, Seg, Source};
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::tyre::Tyre;

/// Where an axle goes and what it gets.
pub struct AxleSlot<'a> {
    /// The body it hangs on (the car body or the trailer's).
    pub carrier: BodyHandle,
    /// The tyre of its wheels.
    pub tyre: &'a Tyre,
    /// Short names of its wheels, left then right (`fl`, `fr`; `rl`, `rr`; `tl`, `tr`).
    pub wheels: [&'a str; 2],
    /// The slot (`front`, `rear`, `trailer`): names the parts an axle has once, such as
    /// the joint on its centreline.
    pub name: &'a str,
    /// Prefix of the names of its bodies: empty on the car, `trailer_` on a trailer.
    pub prefix: &'a str,
    /// The cross member asked for by the scene (the twist beam's rigid or flexible one),
    /// if any; a template without that choice refuses it.
    pub cross_member: Option<CrossMember>,
    /// The steering rack's travel to the left over time [m], when the scene steers
    /// (`[run.steering]`); only a steerable template (McPherson) builds a rack for it.
    pub steering: Option<&'a towride_mbs::model::function::TimeFunction>,
}

/// A built axle: what the design statics, the ride heights and the scene need.
pub struct Axle {
    /// Wheels, left then right.
    pub wheels: Vec<WheelHandle>,
    /// The corners awaiting their static loads (springs get their preloads then).
    pub corners: Vec<Corner>,
    /// Per wheel, the point on the carrier above it (top mount, upper spring seat),
    /// carrier coordinates: ride heights are measured to it.
    pub body_mounts: Vec<V>,
    /// A flexible member of the axle: its body and number of selected modes.
    pub flexible: Option<(BodyHandle, usize)>,
}

/// An axle template with its data, checked: ready to add both sides.
pub trait AxleData {
    /// Adds the axle at `slot`.
    fn build(self: Box<Self>, b: &mut Builder, slot: &AxleSlot) -> Result<Axle, InputError>;
}

/// An axle template of the registry: its name and its property-file reader.
pub trait AxleTemplate: Sync {
    /// The name the assembly file uses.
    fn name(&self) -> &'static str;
    /// Reads and checks the property file `file` for `slot` (through `b`'s loader).
    fn read(
        &self,
        b: &mut Builder,
        file: &Path,
        slot: &AxleSlot,
    ) -> Result<Box<dyn AxleData>, InputError>;
}

/// An axle slot's template and data, as a vehicle description holds them.
pub enum AxleSpec {
    /// A registered template and its property file, read when the axle is built.
    File {
        /// The template.
        template: &'static dyn AxleTemplate,
        /// Its property file.
        file: PathBuf,
    },
    /// A template's data made in code (a compact file's derived values).
    Given(Box<dyn AxleData>),
}

impl AxleSpec {
    /// Reads the property file if there is one, then adds the axle at `slot`.
    pub fn build(self, b: &mut Builder, slot: &AxleSlot) -> Result<Axle, InputError> {
        match self {
            AxleSpec::File { template, file } => template.read(b, &file, slot)?.build(b, slot),
            AxleSpec::Given(data) => data.build(b, slot),
        }
    }
}

/// The axle a file names at `p` (`{ template = "...", file = "..." }`, the file relative
/// to `dir`): a registered template and an existing file, or an error at the field.
pub fn spec(
    src: &Source,
    p: &[Seg],
    template: &str,
    dir: &Path,
    file: &str,
) -> Result<AxleSpec, InputError> {
    let t = self::template(template).ok_or_else(|| {
        src.error(
            &at(p, "template"),
            format!(
                "'{template}': an axle slot takes one of the axle templates ({})",
                names().join(", ")
            ),
        )
    })?;
    let f = dir.join(file);
    if !f.is_file() {
        return Err(src.error(&at(p, "file"), format!("no file {}", f.display())));
    }
    Ok(AxleSpec::File {
        template: t,
        file: f,
    })
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
