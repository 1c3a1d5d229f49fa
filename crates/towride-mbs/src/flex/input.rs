//! The `flex/*.toml` schema: what a beam finite-element model file may contain.
//!
//! Serde does the typing (unknown keys are refused); the semantic checks and the
//! meshing live in `mesh.rs`. Units are in the field names; positions are in the body's
//! frame (for vehicle parts the vehicle frame: x forward, y left, z up).

use std::collections::BTreeMap;

use serde::Deserialize;

fn yes() -> bool {
    true
}

fn one() -> usize {
    1
}

/// A whole flexible-body file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlexFile {
    pub name: String,
    #[serde(default)]
    pub description: String,
    /// Timoshenko shear flexibility where sections have shear areas (default true);
    /// false gives Euler-Bernoulli beams.
    #[serde(default = "yes")]
    pub shear_deformation: bool,
    /// Fixed-interface normal modes kept by the Craig-Bampton reduction.
    pub fixed_interface_modes: Option<usize>,
    #[serde(default)]
    pub material: Vec<MaterialIn>,
    #[serde(default)]
    pub section: Vec<SectionIn>,
    #[serde(default)]
    pub node: Vec<NodeIn>,
    #[serde(default)]
    pub element: Vec<ElementIn>,
    #[serde(default)]
    pub point_mass: Vec<PointMassIn>,
    #[serde(default)]
    pub interface: Vec<InterfaceIn>,
    #[serde(default)]
    pub marker: Vec<MarkerIn>,
    #[serde(default)]
    pub stress_point: Vec<StressPointIn>,
    pub selection: Option<SelectionIn>,
    pub damping: Option<DampingIn>,
    #[serde(default)]
    pub variant: Vec<VariantIn>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialIn {
    pub name: String,
    pub youngs_modulus_pa: f64,
    pub poissons_ratio: f64,
    /// Optional; default E / (2 (1 + nu)).
    pub shear_modulus_pa: Option<f64>,
    pub density_kg_m3: f64,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ShapeIn {
    RectangularHollow,
    RectangularSolid,
    RoundSolid,
    RoundHollow,
    General,
}

/// Dimensions of a section; which ones are required depends on `shape`.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionDims {
    pub width_m: Option<f64>,
    pub height_m: Option<f64>,
    pub wall_m: Option<f64>,
    pub diameter_m: Option<f64>,
    pub outer_diameter_m: Option<f64>,
    pub area_m2: Option<f64>,
    pub iy_m4: Option<f64>,
    pub iz_m4: Option<f64>,
    pub torsion_constant_m4: Option<f64>,
    pub shear_area_y_m2: Option<f64>,
    pub shear_area_z_m2: Option<f64>,
}

impl SectionDims {
    /// (field name, value) of every dimension given.
    pub fn given(&self) -> Vec<(&'static str, f64)> {
        [
            ("width_m", self.width_m),
            ("height_m", self.height_m),
            ("wall_m", self.wall_m),
            ("diameter_m", self.diameter_m),
            ("outer_diameter_m", self.outer_diameter_m),
            ("area_m2", self.area_m2),
            ("iy_m4", self.iy_m4),
            ("iz_m4", self.iz_m4),
            ("torsion_constant_m4", self.torsion_constant_m4),
            ("shear_area_y_m2", self.shear_area_y_m2),
            ("shear_area_z_m2", self.shear_area_z_m2),
        ]
        .into_iter()
        .filter_map(|(k, v)| v.map(|v| (k, v)))
        .collect()
    }
}

/// A named section. The dimensions are repeated from [`SectionDims`] rather than
/// flattened because serde cannot refuse unknown keys through `flatten`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionIn {
    pub name: String,
    pub shape: ShapeIn,
    pub width_m: Option<f64>,
    pub height_m: Option<f64>,
    pub wall_m: Option<f64>,
    pub diameter_m: Option<f64>,
    pub outer_diameter_m: Option<f64>,
    pub area_m2: Option<f64>,
    pub iy_m4: Option<f64>,
    pub iz_m4: Option<f64>,
    pub torsion_constant_m4: Option<f64>,
    pub shear_area_y_m2: Option<f64>,
    pub shear_area_z_m2: Option<f64>,
}

impl SectionIn {
    pub fn dims(&self) -> SectionDims {
        SectionDims {
            width_m: self.width_m,
            height_m: self.height_m,
            wall_m: self.wall_m,
            diameter_m: self.diameter_m,
            outer_diameter_m: self.outer_diameter_m,
            area_m2: self.area_m2,
            iy_m4: self.iy_m4,
            iz_m4: self.iz_m4,
            torsion_constant_m4: self.torsion_constant_m4,
            shear_area_y_m2: self.shear_area_y_m2,
            shear_area_z_m2: self.shear_area_z_m2,
        }
    }
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NodeIn {
    pub name: String,
    pub position_m: [f64; 3],
}

/// A straight member between two nodes, meshed into `divisions` beam elements.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElementIn {
    pub node_a: String,
    pub node_b: String,
    pub section: String,
    pub material: String,
    /// Direction of the section's local y (width) axis; only its part perpendicular to
    /// the member counts. Default: local y horizontal (local z as close to up as possible).
    pub local_y: Option<[f64; 3]>,
    #[serde(default = "one")]
    pub divisions: usize,
}

/// A rigid lumped body at a node (a ball, a bolt head): mass and principal moments of
/// inertia about global axes through the node.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointMassIn {
    pub node: String,
    pub mass_kg: f64,
    #[serde(default)]
    pub inertia_kg_m2: [f64; 3],
}

/// An interface node: where joints, bushings and forces attach. `spider` ties the listed
/// FE nodes rigidly to it (RBE2-like multipoint constraint).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InterfaceIn {
    pub name: String,
    pub node: String,
    #[serde(default)]
    pub spider: Vec<String>,
}

/// A node whose motion is reported (a sensor position) but which is not an interface.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MarkerIn {
    pub name: String,
    pub node: String,
}

/// A section where nominal stresses are recovered: on the member `node_a`-`node_b` (as
/// an `[[element]]` names it, either order), at `at_fraction` of the way from `node_a`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StressPointIn {
    pub name: String,
    pub node_a: String,
    pub node_b: String,
    pub at_fraction: f64,
    /// IIW fatigue class of the weld detail at the point [MPa] (optional).
    pub fat_class_mpa: Option<f64>,
}

/// How a flex file's default selection picks modes (`selection.rule`).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum RuleIn {
    /// Every elastic mode.
    All,
    /// Modes up to `cutoff_hz`.
    Cutoff,
    /// The modes listed in `modes`.
    List,
    /// The a-priori load-path rule: strain-energy shares of the interface load paths,
    /// weighted by the excitation band `band_hz`, kept from `min_energy_share` up.
    LoadPath,
}

/// The default mode selection of this body (the command line may override it).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SelectionIn {
    /// The rule.
    pub rule: RuleIn,
    /// Highest kept frequency for `cutoff` [Hz].
    pub cutoff_hz: Option<f64>,
    /// Mode numbers as in the mode table (1-based, rigid-body modes 1..6 included).
    pub modes: Option<Vec<usize>>,
    /// Excitation band of the load-path rule [Hz].
    pub band_hz: Option<[f64; 2]>,
    /// Smallest kept strain-energy share of the load-path rule (a fraction).
    pub min_energy_share: Option<f64>,
    /// Interfaces where the scene's loads enter (default: all).
    pub load_interfaces: Option<Vec<String>>,
    /// Load the interfaces with moments too (default true; false for ball joints).
    pub load_moments: Option<bool>,
    /// The scene's expected load at the loaded interfaces, body axes [N]: one combined
    /// load case in this direction mix instead of one per direction.
    pub load_n: Option<[f64; 3]>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingBandIn {
    pub up_to_hz: f64,
    pub ratio: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModeDampingIn {
    pub index: usize,
    pub ratio: f64,
}

/// Modal damping ratios: by frequency bands, then per-mode overrides.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingIn {
    pub band: Option<Vec<DampingBandIn>>,
    pub above_ratio: Option<f64>,
    #[serde(default)]
    pub mode: Vec<ModeDampingIn>,
}

/// A stiffness variant: section dimensions that replace the base ones.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VariantIn {
    pub number: u32,
    #[serde(default)]
    pub description: String,
    #[serde(default)]
    pub section: BTreeMap<String, SectionDims>,
}
