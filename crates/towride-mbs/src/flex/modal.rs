//! What a floating-frame modal body needs from the FE model: mass properties, interface
//! and marker nodes with their mode shapes, modal stiffness and damping, inertia
//! invariants.
//!
//! The modes are the elastic modes of the orthonormalised Craig-Bampton basis: modal
//! mass = identity, modal stiffness = diag(omega^2). Rigid-body modes are dropped (the
//! floating frame carries rigid motion). Because the kept modes are mass-orthogonal to
//! the rigid-body modes, the first-order coupling invariants I3 and I4 vanish (the
//! body frame is a linearised mean axis frame): computed, not assumed.

use serde::Serialize;

use super::assemble::Assembly;
use super::craig_bampton::{CraigBampton, ModeKind};
use super::damping::Damping;
use super::invariants::Invariants;
use super::mesh::Mesh;
use super::modes::frequency_hz;
use super::stress::StressModes;

/// Role of a named node of a modal body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NodeKind {
    /// Joints, bushings and forces attach here.
    Interface,
    /// Reported only (sensors).
    Marker,
}

/// A node of the body with its motion in every mode.
#[derive(Clone, Debug, Serialize)]
pub struct ModalNode {
    /// Node name from the flex file.
    pub name: String,
    /// Interface or marker.
    pub kind: NodeKind,
    /// Undeformed position in the body frame [m].
    pub position_m: [f64; 3],
    /// Per mode: translations [m] and rotations [rad] per unit modal coordinate
    /// (u_x, u_y, u_z, theta_x, theta_y, theta_z), body-frame components.
    pub shapes: Vec<[f64; 6]>,
}

/// One elastic mode.
#[derive(Clone, Debug, Serialize)]
pub struct ModalMode {
    /// Number in the mode table (1-based, rigid-body modes 1..6 included).
    pub number: usize,
    /// Natural frequency [Hz].
    pub frequency_hz: f64,
    /// Modal stiffness omega^2 [1/s^2] (modal mass 1).
    pub stiffness: f64,
    /// Fraction of critical damping.
    pub damping_ratio: f64,
    /// Kept by the selection rule (only selected modes become modal coordinates).
    pub selected: bool,
    /// What the mode does ("vertical bending", "torsion about y"; [`super::character`])
    /// and the share of its strain energy behind that word.
    pub character: (String, f64),
}

/// The data of a modal body (SI units, body frame = the FE file's frame).
#[derive(Clone, Debug)]
pub struct ModalData {
    /// Body name from the flex file.
    pub name: String,
    /// The variant applied, `None` for the base sections.
    pub variant: Option<u32>,
    /// Mass [kg].
    pub mass_kg: f64,
    /// Centre of mass in the body frame [m].
    pub com_m: [f64; 3],
    /// Inertia tensor about the centre of mass [kg m^2].
    pub inertia_com_kg_m2: [[f64; 3]; 3],
    /// Interface and marker nodes with their mode shapes.
    pub nodes: Vec<ModalNode>,
    /// All elastic modes, ascending, with their selection flags.
    pub modes: Vec<ModalMode>,
    /// Over `modes`, in the same order.
    pub invariants: Invariants,
    /// The whole mesh, for drawing the body deformed.
    pub skeleton: Skeleton,
    /// Section forces per unit modal coordinate at the file's stress points, over `modes`.
    pub stress: StressModes,
}

/// Every FE node and beam element of a modal body with the nodes' translations in each
/// mode: what the report's 3D view draws.
#[derive(Clone, Debug, Default)]
pub struct Skeleton {
    /// Undeformed node positions in the body frame [m].
    pub positions_m: Vec<[f64; 3]>,
    /// Beam elements as pairs of node indices.
    pub edges: Vec<[usize; 2]>,
    /// shapes[mode][node]: translation per unit modal coordinate [m], over `modes`.
    pub shapes: Vec<Vec<[f64; 3]>>,
}

impl ModalData {
    /// All elastic modes of `cb`, selected, damped by the mesh's damping rule.
    pub fn build(mesh: &Mesh, asm: &Assembly, cb: &CraigBampton) -> ModalData {
        let elastic: Vec<usize> = (0..cb.kinds.len())
            .filter(|&k| cb.kinds[k] == ModeKind::Elastic)
            .collect();
        let shapes: Vec<Vec<[f64; 6]>> = elastic
            .iter()
            .map(|&k| asm.expand(|d| cb.modes[(d, k)]))
            .collect();
        let invariants = Invariants::compute(mesh, &shapes);
        let mut nodes: Vec<ModalNode> = Vec::new();
        let named = mesh
            .interfaces
            .iter()
            .map(|i| (i.name.clone(), NodeKind::Interface, i.node))
            .chain(
                mesh.markers
                    .iter()
                    .map(|m| (m.name.clone(), NodeKind::Marker, m.node)),
            );
        for (name, kind, node) in named {
            let x = mesh.nodes[node].position;
            nodes.push(ModalNode {
                name,
                kind,
                position_m: [x[0], x[1], x[2]],
                shapes: shapes.iter().map(|s| s[node]).collect(),
            });
        }
        let modes = elastic
            .iter()
            .zip(&shapes)
            .map(|(&k, shape)| {
                let f = frequency_hz(cb.omega2[k]);
                ModalMode {
                    character: super::character::character(mesh, shape),
                    number: k + 1,
                    frequency_hz: f,
                    stiffness: cb.omega2[k],
                    damping_ratio: mesh.damping.ratio(k + 1, f),
                    selected: true,
                }
            })
            .collect();
        let skeleton = Skeleton {
            positions_m: mesh
                .nodes
                .iter()
                .map(|n| [n.position[0], n.position[1], n.position[2]])
                .collect(),
            edges: mesh.elements.iter().map(|e| e.nodes).collect(),
            shapes: shapes
                .iter()
                .map(|s| s.iter().map(|d| [d[0], d[1], d[2]]).collect())
                .collect(),
        };
        ModalData {
            name: mesh.name.clone(),
            variant: mesh.variant.as_ref().map(|v| v.number),
            mass_kg: invariants.i1,
            com_m: invariants.centre_of_mass(),
            inertia_com_kg_m2: invariants.inertia_about_centre(),
            nodes,
            modes,
            invariants,
            skeleton,
            stress: StressModes::build(mesh, asm, cb),
        }
    }

    /// The node called `name`.
    pub fn node(&self, name: &str) -> Option<&ModalNode> {
        self.nodes.iter().find(|n| n.name == name)
    }

    /// Replaces the damping ratios by `damping`'s rule.
    pub fn set_damping(&mut self, damping: &Damping) {
        for m in &mut self.modes {
            m.damping_ratio = damping.ratio(m.number, m.frequency_hz);
        }
    }

    /// Marks the modes to keep (one flag per mode).
    pub fn set_selection(&mut self, selected: &[bool]) {
        for (m, &s) in self.modes.iter_mut().zip(selected) {
            m.selected = s;
        }
    }

    /// Modal damping coefficients c_k = 2 zeta_k omega_k (unit modal mass) [1/s].
    pub fn damping_coefficients(&self) -> Vec<f64> {
        self.modes
            .iter()
            .map(|m| 2.0 * m.damping_ratio * m.stiffness.max(0.0).sqrt())
            .collect()
    }

    /// The body with the modes `keep` only (indices into `modes`).
    pub fn restrict(&self, keep: &[usize]) -> ModalData {
        ModalData {
            name: self.name.clone(),
            variant: self.variant,
            mass_kg: self.mass_kg,
            com_m: self.com_m,
            inertia_com_kg_m2: self.inertia_com_kg_m2,
            nodes: self
                .nodes
                .iter()
                .map(|n| ModalNode {
                    shapes: keep.iter().map(|&k| n.shapes[k]).collect(),
                    ..n.clone()
                })
                .collect(),
            modes: keep.iter().map(|&k| self.modes[k].clone()).collect(),
            invariants: self.invariants.restrict(keep),
            skeleton: Skeleton {
                shapes: keep
                    .iter()
                    .filter_map(|&k| self.skeleton.shapes.get(k).cloned())
                    .collect(),
                ..self.skeleton.clone()
            },
            stress: self.stress.restrict(keep),
        }
    }

    /// The body with its selected modes only: what a simulation integrates.
    pub fn selected(&self) -> ModalData {
        let keep: Vec<usize> = (0..self.modes.len())
            .filter(|&k| self.modes[k].selected)
            .collect();
        self.restrict(&keep)
    }
}
