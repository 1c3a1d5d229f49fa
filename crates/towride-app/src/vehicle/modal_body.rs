//! Modal (Craig-Bampton) bodies in the vehicle templates: the beam FE model read,
//! reduced and its modes selected, nodes found by name, the body added, and joints or
//! bushings pinned to its nodes. The towing hitch and the flexible twist-beam cross
//! member share these.

use std::path::Path;

use super::build::{Builder, Link};
use super::geom::V;
use super::props::{at, Mass};
use towride_mbs::flex::SelectionIn;
use towride_mbs::flex::{FlexBody, FlexError, Mesh, ModalData, Options, Rule};
use towride_mbs::input::{InputError, Seg, Source};
use towride_mbs::model::builder::BodyHandle;
use towride_mbs::model::desc::{Coupling, Modal, TwoMarkers};
use towride_mbs::model::math::add;

/// The selected modes of the FE model `fe` (`variant`, None for the base sections); its
/// file's `[selection]` unless `selection` (a table of `src` at the given path) replaces
/// it, and an earlier run's strain-energy selection ([`Builder::run_modes`]) replaces
/// both (its modes of `body`); the files are read through `b`'s loader. Errors of the FE file name that file; a model the reduction refuses is reported at
/// `fe_at`, the property file's field naming it.
pub fn load(
    src: &Source,
    fe_at: &[Seg],
    fe: &Path,
    variant: Option<u32>,
    selection: Option<(&[Seg], &SelectionIn)>,
    b: &Builder,
    body: &str,
) -> Result<ModalData, InputError> {
    let (loader, run_modes) = (&b.loader, b.run_modes.as_deref());
    if !fe.is_file() {
        return Err(src.error(fe_at, towride_mbs::input::no_file(fe)));
    }
    let mesh = Mesh::read(fe, variant, loader)?;
    let rule = match selection {
        // Modes chosen from an earlier run's strain-energy shares replace any rule.
        _ if run_modes.is_some() => {
            let rm = run_modes.map(|r| (r, r.body(body)));
            match rm {
                Some((_, Some(b))) => Some(Rule::List { modes: b.kept() }),
                Some((r, None)) => {
                    return Err(src.error(
                        fe_at,
                        format!(
                        "modes_from: the run in {} has no strain-energy shares of body `{body}`",
                        r.run_dir.display()
                    ),
                    ))
                }
                None => None,
            }
        }
        Some((p, s)) => {
            let names: Vec<String> = mesh.interfaces.iter().map(|i| i.name.clone()).collect();
            Some(Rule::from_input(src, p, s, &names)?)
        }
        None => None,
    };
    let opts = Options {
        fixed_interface_modes: None,
        rule,
    };
    match FlexBody::from_mesh(mesh, &opts) {
        Ok(body) => Ok(body.modal.selected()),
        Err(FlexError::Input(e)) => Err(e),
        Err(FlexError::Model { file, message }) => {
            Err(src.error(fe_at, format!("{file}: {message}")))
        }
        Err(e @ (FlexError::Selection(_) | FlexError::Numerics(_))) => {
            Err(src.error(fe_at, e.to_string()))
        }
    }
}

/// The inertia coupling named at `p`.
pub fn coupling(src: &Source, p: &[Seg], s: &str) -> Result<Coupling, InputError> {
    Coupling::parse(s).ok_or_else(|| src.error(p, format!("'{s}': use {}", Coupling::NAMES)))
}

/// Index of the interface or marker node `name` of `data` (read from `fe`), or an error
/// at `p` listing the nodes there are.
pub fn node(
    src: &Source,
    p: &[Seg],
    data: &ModalData,
    fe: &Path,
    name: &str,
) -> Result<usize, InputError> {
    data.nodes
        .iter()
        .position(|n| n.name == name)
        .ok_or_else(|| {
            let names: Vec<&str> = data.nodes.iter().map(|n| n.name.as_str()).collect();
            src.error(
                p,
                format!(
                    "no node '{name}' in {} (nodes: {})",
                    fe.display(),
                    names.join(", ")
                ),
            )
        })
}

/// Node names at `p` (an array), looked up in `data`.
pub fn nodes<const N: usize>(
    src: &Source,
    p: &[Seg],
    data: &ModalData,
    fe: &Path,
    names: &[String; N],
) -> Result<[usize; N], InputError> {
    let mut out = [0; N];
    for (k, name) in names.iter().enumerate() {
        out[k] = node(src, &at(p, k), data, fe, name)?;
    }
    Ok(out)
}

/// Adds the modal body `name` whose FE frame has its origin at `origin` (subsystem
/// coordinates, axes the subsystem's).
pub fn add_body(
    b: &mut Builder,
    name: &str,
    data: ModalData,
    origin: V,
    coupling: Coupling,
) -> Result<BodyHandle, InputError> {
    let mass = Mass {
        mass: data.mass_kg,
        cm: add(&origin, &data.com_m),
        inertia: data.inertia_com_kg_m2,
    };
    let k = b.body(name, &mass)?;
    b.model_mut().bodies[k].modal = Some(Box::new(Modal { data, coupling }));
    Ok(k)
}

/// Position of node `n` of the modal body `body` in subsystem coordinates.
pub fn node_position(b: &Builder, body: BodyHandle, origin: V, n: usize) -> V {
    let data = &b.model().bodies[body]
        .modal
        .as_ref()
        .expect("a modal body")
        .data;
    add(&origin, &data.nodes[n].position_m)
}

/// Moves the modal body's marker of `link` (its I marker when `on_i`, else its J marker)
/// onto node `n`, so the joint or bushing acts there and follows the node's deformation.
pub fn pin(b: &mut Builder, link: Link, on_i: bool, n: usize) {
    let TwoMarkers { i, j } = link.markers(b.model());
    b.mb.pin_to_node(if on_i { i } else { j }, n);
}
