//! The mode table of a flexible body as a report: modes with frequencies, effective
//! masses and selection, fixed-interface modes, nodes, mass properties and an inertia-
//! invariant summary (what `towride modes` prints).

use std::path::Path;

use serde::Serialize;

use super::modes::frequency_hz;
use super::selection::{LoadPath, DEFAULT_MIN_ENERGY_SHARE};
use super::{FlexBody, FlexError, ModeKind, Rule};

/// Version of the report's layout.
pub const SCHEMA_VERSION: u32 = 1;

/// One row of the mode table in the report.
#[derive(Clone, Debug, Serialize)]
pub struct ModeRecord {
    /// Mode-table number (1-based, rigid-body modes included).
    pub index: usize,
    /// Natural frequency [Hz] (signed; rigid-body modes may be slightly negative).
    pub frequency_hz: f64,
    /// "rigid" or "elastic".
    pub kind: &'static str,
    /// y^T M y with the full FE mass matrix (1 after orthonormalisation).
    pub generalised_mass: f64,
    /// x, y, z [kg], rx, ry, rz about the centre of mass [kg m^2].
    pub effective_mass: [f64; 6],
    /// Kept by the selection rule (never for rigid-body modes).
    pub selected: bool,
    /// Fraction of critical damping; `None` for rigid-body modes.
    pub damping_ratio: Option<f64>,
    /// Load-path rule: largest weighted strain-energy share over the load cases.
    pub energy_share: Option<f64>,
    /// Share of the mode's kinetic energy per section, largest first.
    pub kinetic_energy_by_section: Vec<(String, f64)>,
    /// What an elastic mode does ("vertical bending, crossbeam") and the share of its
    /// strain energy behind the word ([`super::character`]); `None` for rigid-body modes.
    pub character: Option<(String, f64)>,
}

/// A fixed-interface normal mode with its effective mass relative to the held
/// interface (rigid-body directions about the centre of mass).
#[derive(Clone, Debug, Serialize)]
pub struct FixedModeRecord {
    /// Natural frequency with the interface held [Hz].
    pub frequency_hz: f64,
    /// x, y, z [kg], rx, ry, rz about the centre of mass [kg m^2].
    pub effective_mass: [f64; 6],
}

/// A named node of the body (interface or marker).
#[derive(Clone, Debug, Serialize)]
pub struct NodeRecord {
    /// Node name from the flex file.
    pub name: String,
    /// "interface" or "marker".
    pub kind: &'static str,
    /// Undeformed position in the body frame [m].
    pub position_m: [f64; 3],
}

/// Largest magnitudes of the inertia invariants, as a check on the modal data.
#[derive(Clone, Debug, Serialize)]
pub struct InvariantSummary {
    /// max |I3|, max |I4|: first-order coupling, zero for modes orthogonal to rigid motion.
    pub i3_max_abs: f64,
    /// max |I4| (see `i3_max_abs`).
    pub i4_max_abs: f64,
    /// max |I6 - identity|: modal mass.
    pub i6_identity_error: f64,
    /// max |I5|: coupling of mode pairs through the angular velocity.
    pub i5_max_abs: f64,
    /// max |I8|: first-order change of the inertia tensor with the modal coordinates.
    pub i8_max_abs: f64,
    /// max |I9|: second-order change of the inertia tensor with the modal coordinates.
    pub i9_max_abs: f64,
}

/// The mode table of a flexible body as `towride modes` reports it.
#[derive(Clone, Debug, Serialize)]
pub struct ModesReport {
    /// Report layout version ([`SCHEMA_VERSION`]).
    pub schema_version: u32,
    /// The flex file read.
    pub file: String,
    /// Body name.
    pub name: String,
    /// The variant applied, `None` for the base sections.
    pub variant: Option<u32>,
    /// The variant's description.
    pub variant_description: Option<String>,
    /// FE nodes of the mesh (spider slaves included).
    pub fe_nodes: usize,
    /// Beam elements.
    pub elements: usize,
    /// Independent DOFs after eliminating the spider slaves.
    pub dof: usize,
    /// Fixed-interface modes kept in the reduction.
    pub fixed_interface_modes: usize,
    /// Their natural frequencies with the interfaces held [Hz].
    pub fixed_interface_frequencies_hz: Vec<f64>,
    /// Their effective masses.
    pub fixed_interface_table: Vec<FixedModeRecord>,
    /// Mass [kg].
    pub mass_kg: f64,
    /// Centre of mass in the body frame [m].
    pub com_m: [f64; 3],
    /// About the centre of mass.
    pub inertia_kg_m2: [[f64; 3]; 3],
    /// Interface and marker nodes.
    pub nodes: Vec<NodeRecord>,
    /// The mode table, rigid-body modes included.
    pub modes: Vec<ModeRecord>,
    /// The selection rule in words.
    pub selection_rule: String,
    /// Mode-table numbers of the selected modes.
    pub selected_modes: Vec<usize>,
    /// Summary of the inertia invariants of the elastic modes.
    pub invariants: InvariantSummary,
}

fn max_abs<'a>(it: impl Iterator<Item = &'a f64>) -> f64 {
    it.fold(0.0, |m, x| m.max(x.abs()))
}

fn summary(body: &FlexBody) -> InvariantSummary {
    let inv = &body.modal.invariants;
    let n = inv.i6.len();
    let mut i6e: f64 = 0.0;
    for j in 0..n {
        for k in 0..n {
            let want = if j == k { 1.0 } else { 0.0 };
            i6e = i6e.max((inv.i6[j][k] - want).abs());
        }
    }
    InvariantSummary {
        i3_max_abs: max_abs(inv.i3.iter().flatten()),
        i4_max_abs: max_abs(inv.i4.iter().flatten()),
        i6_identity_error: i6e,
        i5_max_abs: max_abs(inv.i5.iter().flatten().flatten()),
        i8_max_abs: max_abs(inv.i8.iter().flatten().flatten()),
        i9_max_abs: max_abs(inv.i9.iter().flatten().flatten().flatten()),
    }
}

/// A selection asked for instead of the file's: modes up to `cutoff` Hz, a list of
/// mode numbers, or the load-path rule with a band and a share (missing parts from
/// the file's own load-path rule).
#[derive(Clone, Debug, Default)]
pub struct SelectionChoice {
    /// Elastic modes up to this frequency [Hz].
    pub cutoff: Option<f64>,
    /// Mode-table numbers.
    pub modes: Vec<usize>,
    /// Load-path band [Hz]: LOW, HIGH.
    pub band: Option<Vec<f64>>,
    /// Load-path minimum share [%].
    pub share: Option<f64>,
}

/// The rule a [`SelectionChoice`] asks for, completed from the file's rule; `None`
/// keeps the file's.
pub fn rule_from(a: &SelectionChoice, file_rule: &Rule) -> Result<Option<Rule>, FlexError> {
    let bad = |m: String| FlexError::Selection(m);
    if let Some(c) = a.cutoff {
        if c.is_nan() || c <= 0.0 {
            return Err(bad(format!("cutoff must be positive, got {c}")));
        }
        return Ok(Some(Rule::Cutoff { max_hz: c }));
    }
    if !a.modes.is_empty() {
        return Ok(Some(Rule::List {
            modes: a.modes.clone(),
        }));
    }
    if a.band.is_some() || a.share.is_some() {
        let band = match &a.band {
            Some(b) if b.len() == 2 && b[0] >= 0.0 && b[1] > b[0] => [b[0], b[1]],
            Some(b) => {
                return Err(bad(format!(
                    "the band needs LOW,HIGH with 0 <= LOW < HIGH, got {b:?}"
                )))
            }
            None => match file_rule {
                Rule::LoadPath(l) => l.band_hz,
                _ => {
                    return Err(bad(
                        "a share needs a band (the file's rule is not load_path)".into(),
                    ))
                }
            },
        };
        let share = match a.share {
            Some(s) if s > 0.0 && s < 100.0 => s / 100.0,
            Some(s) => {
                return Err(bad(format!(
                    "the share is a percentage in (0, 100), got {s}"
                )))
            }
            None => match file_rule {
                Rule::LoadPath(l) => l.min_energy_share,
                _ => DEFAULT_MIN_ENERGY_SHARE,
            },
        };
        let (load_interfaces, load_moments, load_n) = match file_rule {
            Rule::LoadPath(l) => (l.load_interfaces.clone(), l.load_moments, l.load_n),
            _ => (vec![], true, None),
        };
        return Ok(Some(Rule::LoadPath(LoadPath {
            band_hz: band,
            min_energy_share: share,
            load_interfaces,
            load_moments,
            load_n,
        })));
    }
    Ok(None)
}

impl ModesReport {
    /// The report of `body`, read from `file`.
    pub fn of(body: &FlexBody, file: &Path) -> ModesReport {
        let md = &body.modal;
        let share_of = |number: usize| -> Option<f64> {
            let k = md.modes.iter().position(|m| m.number == number)?;
            body.selection.max_share.as_ref().map(|s| s[k])
        };
        let modes: Vec<ModeRecord> = body
            .table()
            .iter()
            .map(|r| {
                let m = md.modes.iter().find(|m| m.number == r.number);
                ModeRecord {
                    index: r.number,
                    frequency_hz: r.frequency_hz,
                    kind: r.kind.as_str(),
                    generalised_mass: r.generalised_mass,
                    effective_mass: r.effective_mass,
                    selected: r.kind == ModeKind::Elastic && m.is_some_and(|m| m.selected),
                    damping_ratio: m.map(|m| m.damping_ratio),
                    energy_share: share_of(r.number),
                    kinetic_energy_by_section: r.kinetic_energy_by_section.clone(),
                    character: m.map(|m| m.character.clone()),
                }
            })
            .collect();
        ModesReport {
            schema_version: SCHEMA_VERSION,
            file: file.display().to_string(),
            name: body.mesh.name.clone(),
            variant: body.mesh.variant.as_ref().map(|v| v.number),
            variant_description: body.mesh.variant.as_ref().map(|v| v.description.clone()),
            fe_nodes: body.mesh.nodes.len(),
            elements: body.mesh.elements.len(),
            dof: body.assembly.n_dof,
            fixed_interface_modes: body.cb.fixed_interface_omega2.len(),
            fixed_interface_frequencies_hz: body
                .cb
                .fixed_interface_omega2
                .iter()
                .map(|&w| frequency_hz(w))
                .collect(),
            fixed_interface_table: super::craig_bampton::effective_masses(
                &body.assembly,
                &body.cb.fixed_interface_modes,
            )
            .into_iter()
            .zip(&body.cb.fixed_interface_omega2)
            .map(|((_, e), &w)| FixedModeRecord {
                frequency_hz: frequency_hz(w),
                effective_mass: e,
            })
            .collect(),
            mass_kg: md.mass_kg,
            com_m: md.com_m,
            inertia_kg_m2: md.inertia_com_kg_m2,
            nodes: md
                .nodes
                .iter()
                .map(|n| NodeRecord {
                    name: n.name.clone(),
                    kind: match n.kind {
                        super::NodeKind::Interface => "interface",
                        super::NodeKind::Marker => "marker",
                    },
                    position_m: n.position_m,
                })
                .collect(),
            selected_modes: md
                .modes
                .iter()
                .filter(|m| m.selected)
                .map(|m| m.number)
                .collect(),
            selection_rule: body.rule.describe(),
            invariants: summary(body),
            modes,
        }
    }
}
