//! The twist-beam axle's flexible variant: the cross member as a modal body (the
//! Craig-Bampton data of a beam FE model, modes selected by its file's rule or the
//! property file's), fixed to the two rigid trailing arms at its interface nodes by
//! fixed joints or stiff bushings. The arms carry their own parts only; the cross
//! member's mass is the FE model's.

use std::path::Path;

use serde::Deserialize;

use super::build::Builder;
use super::geom::{mirror, norm, V, Z_ALONG_Y};
use super::modal_body;
use super::props::{at, point, BushingLaws, BushingProps, Mass, MassProps};
use towride_mbs::flex::ModalData;
use towride_mbs::flex::SelectionIn;
use towride_mbs::input::{InputError, Seg, Source};
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::model::desc::{Coupling, JointKind};
use towride_mbs::model::elements::JointBushing;
use towride_mbs::model::math::{add, sub};

/// The two interface nodes must be mirror images within this [m]: the design statics
/// treat the right side as the left one's image.
const MIRROR_TOLERANCE_M: f64 = 1e-3;

/// The twist beam's cross member: the rear axle file's `cross_member.kind`, a scene's
/// `rear_cross_member`.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum CrossMember {
    /// Two rigid halves joined by a revolute joint and a torsion element (`[half]`,
    /// `[torsion]`).
    Rigid,
    /// A modal body fixed to the arms (`[cross_member]`).
    Flexible,
}

impl std::fmt::Display for CrossMember {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(match self {
            CrossMember::Rigid => "rigid",
            CrossMember::Flexible => "flexible",
        })
    }
}

/// How the cross member's interface nodes hold the arms.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum MountKind {
    /// Fixed joints (they follow the axle's `[joints]` switch).
    Fixed,
    /// Bushings (`mount_bushing`).
    Bushing,
}

/// `[cross_member]` of the rear axle's file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct CrossMemberProps {
    /// Which cross member the axle has.
    pub kind: CrossMember,
    /// The FE model (relative to the property file).
    pub fe_file: String,
    /// Where the FE file's origin lies in vehicle coordinates [m] (axes the vehicle's).
    pub fe_origin_m: [f64; 3],
    /// Inertia coupling of the modal body: constant or partial.
    pub inertia_coupling: String,
    /// Interface nodes welded to the left and the right arm.
    pub interface_nodes: [String; 2],
    /// How the interface nodes hold the arms.
    pub mount: MountKind,
    /// Replaces the FE file's `[selection]` (same fields).
    pub selection: Option<SelectionIn>,
    /// A trailing arm without the cross member: arm, stub axle, brake back plate.
    pub arm: MassProps,
    /// The bushing of mount = "bushing" (z along the pivot axis, y by default).
    pub mount_bushing: BushingProps,
}

enum Mount {
    Fixed,
    Bushing(Box<BushingLaws>),
}

/// The flexible cross member, checked and reduced.
pub struct Flexible {
    /// A trailing arm (left side).
    pub arm: Mass,
    data: ModalData,
    origin: V,
    coupling: Coupling,
    nodes: [usize; 2],
    mount: Mount,
}

/// Reads and checks `c` (the table at `p` of `src`, the property file `file`).
pub fn read(
    src: &Source,
    p: &[Seg],
    file: &Path,
    c: &CrossMemberProps,
    b: &Builder,
) -> Result<Flexible, InputError> {
    let origin = point(src, &at(p, "fe_origin_m"), &c.fe_origin_m)?;
    let coupling = modal_body::coupling(src, &at(p, "inertia_coupling"), &c.inertia_coupling)?;
    let fe = file.parent().unwrap_or(Path::new(".")).join(&c.fe_file);
    if !fe.is_file() {
        return Err(src.error(&at(p, "fe_file"), towride_mbs::input::no_file(&fe)));
    }
    let sel_at = at(p, "selection");
    let selection = c.selection.as_ref().map(|s| (sel_at.as_slice(), s));
    let data = modal_body::load(
        src,
        &at(p, "fe_file"),
        &fe,
        None,
        selection,
        b,
        "cross_member",
    )?;
    let np = at(p, "interface_nodes");
    let nodes = modal_body::nodes(src, &np, &data, &fe, &c.interface_nodes)?;
    let pos = nodes.map(|n| add(&origin, &data.nodes[n].position_m));
    if pos[0][1] <= 0.0 {
        return Err(src.error(
            &at(&np, 0),
            format!(
                "the left arm's node lies at y = {:.4} m: give the left node first",
                pos[0][1]
            ),
        ));
    }
    let off = norm(&sub(&pos[1], &mirror(pos[0])));
    if off > MIRROR_TOLERANCE_M {
        return Err(src.error(
            &at(&np, 1),
            format!(
                "the right node lies {:.1} mm from the left node's mirror image (at most {} mm: the right side is the left one's image)",
                1e3 * off,
                1e3 * MIRROR_TOLERANCE_M
            ),
        ));
    }
    let mount = match c.mount {
        MountKind::Fixed => Mount::Fixed,
        MountKind::Bushing => Mount::Bushing(Box::new(c.mount_bushing.check(
            src,
            &at(p, "mount_bushing"),
            [0.0, 1.0, 0.0],
        )?)),
    };
    Ok(Flexible {
        arm: c.arm.check(src, &at(p, "arm"))?,
        data,
        origin,
        coupling,
        nodes,
        mount,
    })
}

/// What the cross member added.
pub struct Joined {
    pub body: BodyHandle,
    /// Its mass [kg] and undeformed centre of mass (vehicle coordinates).
    pub mass: f64,
    pub cm: V,
    /// Selected modes.
    pub modes: usize,
}

/// Adds the cross member and fixes it to the arms `arms` (left, right). Fixed joints
/// follow the axle's `[joints]` switch (`jb`) like the rigid variant's centre joint.
pub fn join(
    b: &mut Builder,
    f: Flexible,
    arms: [BodyHandle; 2],
    jb: Option<&JointBushing>,
) -> Result<Joined, InputError> {
    let (mass, cm) = (f.data.mass_kg, add(&f.origin, &f.data.com_m));
    let modes = f.data.modes.len();
    let body = modal_body::add_body(b, "cross_member", f.data, f.origin, f.coupling)?;
    for (k, side) in ["left", "right"].into_iter().enumerate() {
        let n = f.nodes[k];
        let p = modal_body::node_position(b, body, f.origin, n);
        let name = format!("cross_member_{side}");
        let link = match &f.mount {
            Mount::Fixed => {
                let axes = if k == 0 {
                    Z_ALONG_Y
                } else {
                    super::geom::mirror_axes(&Z_ALONG_Y)
                };
                b.add(|m| {
                    m.joint(
                        &name,
                        JointKind::Fixed,
                        Some(body),
                        Some(arms[k]),
                        p,
                        &axes,
                        jb,
                    )
                })?
            }
            Mount::Bushing(laws) => {
                let laws = laws.side(k == 1);
                b.bushing_link(&name, Some(body), Some(arms[k]), p, &laws.axes, &laws)?
            }
        };
        modal_body::pin(b, link, true, n);
    }
    Ok(Joined {
        body,
        mass,
        cm,
        modes,
    })
}
