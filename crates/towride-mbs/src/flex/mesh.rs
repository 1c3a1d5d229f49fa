//! From a `flex/*.toml` file to a checked beam mesh: variants applied, members split
//! into elements, spiders and interfaces resolved. Every refusal names the file, the
//! line and the field (through [`Source`]).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use nalgebra::{Matrix3, Vector3};

use super::beam::{default_local_y, Beam, BeamError, MassPoint, Mat3x12};
use super::damping::Damping;
use super::input::{FlexFile, SectionDims, SectionIn, ShapeIn};
use super::material::Material;
use super::section::Section;
use super::selection::Rule;
use crate::input::{InputError, InputErrorKind, Seg, Source};
use crate::path;

/// Fixed-interface modes kept when the file does not say.
pub const DEFAULT_FIXED_INTERFACE_MODES: usize = 8;

#[derive(Clone, Debug)]
pub struct Node {
    /// The file's name, or `a~b#k` for the k-th node generated on member a-b.
    pub name: String,
    pub position: Vector3<f64>,
}

#[derive(Clone, Debug)]
pub struct Element {
    pub nodes: [usize; 2],
    pub beam: Beam,
    /// Index of the member (`[[element]]` entry) it was cut from.
    pub member: usize,
    pub section: String,
}

#[derive(Clone, Debug)]
pub struct PointMass {
    pub node: usize,
    pub mass_kg: f64,
    pub inertia_kg_m2: [f64; 3],
}

#[derive(Clone, Debug)]
pub struct Interface {
    pub name: String,
    pub node: usize,
    /// FE nodes tied rigidly to `node`.
    pub spider: Vec<usize>,
}

#[derive(Clone, Debug)]
pub struct Marker {
    pub name: String,
    pub node: usize,
}

/// The chosen variant of a file.
#[derive(Clone, Debug, PartialEq)]
pub struct VariantInfo {
    pub number: u32,
    pub description: String,
}

/// A checked beam model, ready to assemble.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Body name from the file's `name`.
    pub name: String,
    /// The file's free-text `description` (empty when absent).
    pub description: String,
    /// The file the mesh was read from.
    pub path: PathBuf,
    /// The variant applied, `None` for the base sections.
    pub variant: Option<VariantInfo>,
    /// Variant numbers the file defines.
    pub variants: Vec<u32>,
    /// Sections as used (after the variant's changes), by name.
    pub sections: Vec<(String, Section)>,
    /// FE nodes: the file's nodes and those generated along members.
    pub nodes: Vec<Node>,
    /// Beam elements, members split as the file asks.
    pub elements: Vec<Element>,
    /// Lumped masses at nodes.
    pub point_masses: Vec<PointMass>,
    /// Interface nodes, where joints, bushings and forces attach.
    pub interfaces: Vec<Interface>,
    /// Marker nodes, reported only (sensors).
    pub markers: Vec<Marker>,
    /// Sections where nominal stresses are recovered (`[[stress_point]]`).
    pub stress_points: Vec<super::stress::StressPoint>,
    /// Fixed-interface modes of the Craig-Bampton reduction (file's value or
    /// `DEFAULT_FIXED_INTERFACE_MODES`).
    pub fixed_interface_modes: usize,
    /// Mode-selection rule from the file's `[selection]` ([`Rule::All`] when absent).
    pub selection: Rule,
    /// Modal damping from the file's `[damping]` (defaults when absent).
    pub damping: Damping,
}

impl Mesh {
    /// Reads `path` and builds variant `variant` (None: the base sections).
    pub fn read(
        path: &Path,
        variant: Option<u32>,
        loader: &crate::input::Loader,
    ) -> Result<Mesh, InputError> {
        Mesh::from_source(&loader.toml(path)?, variant)
    }

    /// Builds the mesh (variant `variant`, None for the base sections) from an already
    /// loaded TOML source.
    pub fn from_source(src: &Source, variant: Option<u32>) -> Result<Mesh, InputError> {
        let f: FlexFile = src.parse()?;
        build(src, &f, variant)
    }

    /// Index of the node called `name`.
    pub fn node_index(&self, name: &str) -> Option<usize> {
        self.nodes.iter().position(|n| n.name == name)
    }

    /// The interface called `name`.
    pub fn interface(&self, name: &str) -> Option<&Interface> {
        self.interfaces.iter().find(|i| i.name == name)
    }

    /// The mass distribution: beam quadrature points and lumped bodies, each with the
    /// two mesh nodes whose 12 DOFs its interpolation reads.
    pub fn mass_points(&self) -> Vec<([usize; 2], MassPoint)> {
        let mut out = Vec::new();
        for e in &self.elements {
            for p in e.beam.mass_points() {
                out.push((e.nodes, p));
            }
        }
        for pm in &self.point_masses {
            let mut nu = Mat3x12::zeros();
            let mut nt = Mat3x12::zeros();
            for i in 0..3 {
                nu[(i, i)] = 1.0;
                nt[(i, 3 + i)] = 1.0;
            }
            let j = Matrix3::from_diagonal(&Vector3::from(pm.inertia_kg_m2));
            out.push((
                [pm.node, pm.node],
                MassPoint {
                    position: self.nodes[pm.node].position,
                    mass_kg: pm.mass_kg,
                    // D = tr(J)/2 I - J, so that tr(D) I - D = J.
                    second_moment: Matrix3::identity() * (0.5 * j.trace()) - j,
                    nu,
                    nt,
                },
            ));
        }
        out
    }
}

fn lookup(names: &HashMap<String, usize>, name: &str) -> Option<usize> {
    names.get(name).copied()
}

/// Builds the section of entry `si` with the variant's changes; errors point at the
/// field where the offending value was written.
fn section_of(
    src: &Source,
    si: usize,
    s: &SectionIn,
    change: Option<(usize, &SectionDims)>,
) -> Result<Section, InputError> {
    let base = s.dims();
    let mut dims: HashMap<&'static str, (f64, Vec<Seg>)> = base
        .given()
        .into_iter()
        .map(|(k, v)| (k, (v, path!["section", si, k].to_vec())))
        .collect();
    if let Some((vi, c)) = change {
        for (k, v) in c.given() {
            let p = path!["variant", vi, "section", s.name.as_str(), k].to_vec();
            dims.insert(k, (v, p));
        }
    }
    let (required, optional): (&[&str], &[&str]) = match s.shape {
        ShapeIn::RectangularHollow => (&["width_m", "height_m", "wall_m"], &[]),
        ShapeIn::RectangularSolid => (&["width_m", "height_m"], &[]),
        ShapeIn::RoundSolid => (&["diameter_m"], &[]),
        ShapeIn::RoundHollow => (&["outer_diameter_m", "wall_m"], &[]),
        ShapeIn::General => (
            &["area_m2", "iy_m4", "iz_m4", "torsion_constant_m4"],
            &["shear_area_y_m2", "shear_area_z_m2"],
        ),
    };
    let shape = format!("{:?}", s.shape);
    for (k, (_, p)) in &dims {
        if !required.contains(k) && !optional.contains(k) {
            return Err(src.error(p, format!("is not a dimension of a {shape} section")));
        }
    }
    for k in required {
        if !dims.contains_key(k) {
            return Err(src.error(
                &path!["section", si, *k],
                format!("missing: a {shape} section needs {}", required.join(", ")),
            ));
        }
    }
    let v = |k: &str| dims.get(k).map(|d| d.0);
    let sec = match s.shape {
        ShapeIn::RectangularHollow => Section::RectangularHollow {
            width_m: v("width_m").unwrap(),
            height_m: v("height_m").unwrap(),
            wall_m: v("wall_m").unwrap(),
        },
        ShapeIn::RectangularSolid => Section::RectangularSolid {
            width_m: v("width_m").unwrap(),
            height_m: v("height_m").unwrap(),
        },
        ShapeIn::RoundSolid => Section::RoundSolid {
            diameter_m: v("diameter_m").unwrap(),
        },
        ShapeIn::RoundHollow => Section::RoundHollow {
            outer_diameter_m: v("outer_diameter_m").unwrap(),
            wall_m: v("wall_m").unwrap(),
        },
        ShapeIn::General => Section::General {
            area_m2: v("area_m2").unwrap(),
            iy_m4: v("iy_m4").unwrap(),
            iz_m4: v("iz_m4").unwrap(),
            torsion_constant_m4: v("torsion_constant_m4").unwrap(),
            shear_area_y_m2: v("shear_area_y_m2"),
            shear_area_z_m2: v("shear_area_z_m2"),
        },
    };
    sec.validate()
        .map_err(|e| src.error(&dims[e.field].1, e.message))?;
    Ok(sec)
}

fn materials(src: &Source, f: &FlexFile) -> Result<Vec<Material>, InputError> {
    let mut out: Vec<Material> = Vec::new();
    for (i, m) in f.material.iter().enumerate() {
        if out.iter().any(|o| o.name == m.name) {
            return Err(src.error(&path!["material", i, "name"], "duplicate material name"));
        }
        let e = src.positive(
            &path!["material", i, "youngs_modulus_pa"],
            m.youngs_modulus_pa,
        )?;
        let rho = src.positive(&path!["material", i, "density_kg_m3"], m.density_kg_m3)?;
        let nu = src.finite(&path!["material", i, "poissons_ratio"], m.poissons_ratio)?;
        if !(nu > -1.0 && nu < 0.5) {
            return Err(src.error(
                &path!["material", i, "poissons_ratio"],
                format!("must lie in (-1, 0.5), got {nu}"),
            ));
        }
        let g = match m.shear_modulus_pa {
            Some(g) => Some(src.positive(&path!["material", i, "shear_modulus_pa"], g)?),
            None => None,
        };
        out.push(Material::new(&m.name, e, nu, g, rho));
    }
    Ok(out)
}

fn build(src: &Source, f: &FlexFile, variant: Option<u32>) -> Result<Mesh, InputError> {
    // Variant.
    let mut numbers: Vec<u32> = Vec::new();
    for (vi, v) in f.variant.iter().enumerate() {
        if numbers.contains(&v.number) {
            return Err(src.error(&path!["variant", vi, "number"], "duplicate variant number"));
        }
        numbers.push(v.number);
        for name in v.section.keys() {
            if !f.section.iter().any(|s| &s.name == name) {
                return Err(src.error(
                    &path!["variant", vi, "section", name.as_str()],
                    format!("names a missing section `{name}`"),
                ));
            }
        }
    }
    let chosen = match variant {
        None => None,
        Some(n) => match f.variant.iter().position(|v| v.number == n) {
            Some(vi) => Some(vi),
            None => {
                let have = if numbers.is_empty() {
                    "the file defines no variants".to_string()
                } else {
                    let mut s = numbers.clone();
                    s.sort_unstable();
                    format!("the file defines {s:?}")
                };
                return Err(src
                    .error(&path!["variant"], format!("no variant {n}: {have}"))
                    .with_kind(InputErrorKind::NoVariant { number: n }));
            }
        },
    };

    let mats = materials(src, f)?;
    let mut sections: Vec<(String, Section)> = Vec::new();
    for (si, s) in f.section.iter().enumerate() {
        if sections.iter().any(|(n, _)| n == &s.name) {
            return Err(src.error(&path!["section", si, "name"], "duplicate section name"));
        }
        let change = chosen.and_then(|vi| f.variant[vi].section.get(&s.name).map(|c| (vi, c)));
        sections.push((s.name.clone(), section_of(src, si, s, change)?));
    }

    // Declared nodes.
    let mut nodes: Vec<Node> = Vec::new();
    let mut names: HashMap<String, usize> = HashMap::new();
    for (i, n) in f.node.iter().enumerate() {
        if names.contains_key(&n.name) {
            return Err(src.error(&path!["node", i, "name"], "duplicate node name"));
        }
        for c in n.position_m {
            src.finite(&path!["node", i, "position_m"], c)?;
        }
        names.insert(n.name.clone(), nodes.len());
        nodes.push(Node {
            name: n.name.clone(),
            position: Vector3::from(n.position_m),
        });
    }
    let declared = nodes.len();

    // Members -> elements.
    let mut elements: Vec<Element> = Vec::new();
    for (i, m) in f.element.iter().enumerate() {
        let a = lookup(&names, &m.node_a).ok_or_else(|| {
            src.error(
                &path!["element", i, "node_a"],
                format!("names a missing node `{}`", m.node_a),
            )
        })?;
        let b = lookup(&names, &m.node_b).ok_or_else(|| {
            src.error(
                &path!["element", i, "node_b"],
                format!("names a missing node `{}`", m.node_b),
            )
        })?;
        let mat = mats.iter().find(|x| x.name == m.material).ok_or_else(|| {
            src.error(
                &path!["element", i, "material"],
                format!("names a missing material `{}`", m.material),
            )
        })?;
        let sec = sections
            .iter()
            .find(|(n, _)| n == &m.section)
            .ok_or_else(|| {
                src.error(
                    &path!["element", i, "section"],
                    format!("names a missing section `{}`", m.section),
                )
            })?;
        if m.divisions == 0 {
            return Err(src.error(&path!["element", i, "divisions"], "must be at least 1"));
        }
        let (xa, xb) = (nodes[a].position, nodes[b].position);
        let local_y = match m.local_y {
            Some(v) => {
                for c in v {
                    src.finite(&path!["element", i, "local_y"], c)?;
                }
                Vector3::from(v)
            }
            None if (xb - xa).norm() > 0.0 => default_local_y(&xa, &xb),
            None => Vector3::y(),
        };
        let props = sec.1.properties(mat.poissons_ratio);
        // Check the whole member once, so the error names the member's fields.
        Beam::new(xa, xb, local_y, mat, props, f.shear_deformation).map_err(|e| match e {
            BeamError::ZeroLength => src.error(
                &path!["element", i, "node_b"],
                format!(
                    "zero-length element: `{}` and `{}` are at the same position",
                    m.node_a, m.node_b
                ),
            ),
            BeamError::OrientationParallel => src.error(
                &path!["element", i, "local_y"],
                "is parallel to the element axis",
            ),
        })?;
        let mut prev = a;
        for k in 1..=m.divisions {
            let next = if k == m.divisions {
                b
            } else {
                nodes.push(Node {
                    name: format!("{}~{}#{k}", m.node_a, m.node_b),
                    position: xa + (xb - xa) * (k as f64 / m.divisions as f64),
                });
                nodes.len() - 1
            };
            let beam = Beam::new(
                nodes[prev].position,
                nodes[next].position,
                local_y,
                mat,
                props,
                f.shear_deformation,
            )
            .expect("a sub-element of a valid member is valid");
            elements.push(Element {
                nodes: [prev, next],
                beam,
                member: i,
                section: m.section.clone(),
            });
            prev = next;
        }
    }

    // Point masses.
    let mut point_masses = Vec::new();
    for (i, p) in f.point_mass.iter().enumerate() {
        let node = lookup(&names, &p.node).ok_or_else(|| {
            src.error(
                &path!["point_mass", i, "node"],
                format!("names a missing node `{}`", p.node),
            )
        })?;
        let mass_kg = src.positive(&path!["point_mass", i, "mass_kg"], p.mass_kg)?;
        let j = p.inertia_kg_m2;
        for c in j {
            src.non_negative(&path!["point_mass", i, "inertia_kg_m2"], c)?;
        }
        // Principal moments of a real body obey the triangle inequality.
        if j[0] > j[1] + j[2] || j[1] > j[0] + j[2] || j[2] > j[0] + j[1] {
            return Err(src.error(
                &path!["point_mass", i, "inertia_kg_m2"],
                "each principal moment must not exceed the sum of the other two",
            ));
        }
        point_masses.push(PointMass {
            node,
            mass_kg,
            inertia_kg_m2: j,
        });
    }

    // Interfaces and spiders.
    let mut degree = vec![0usize; nodes.len()];
    for e in &elements {
        degree[e.nodes[0]] += 1;
        degree[e.nodes[1]] += 1;
    }
    let mut interfaces: Vec<Interface> = Vec::new();
    let mut tied = vec![false; nodes.len()];
    for (i, it) in f.interface.iter().enumerate() {
        if interfaces.iter().any(|o| o.name == it.name) {
            return Err(src.error(&path!["interface", i, "name"], "duplicate interface name"));
        }
        let node = lookup(&names, &it.node).ok_or_else(|| {
            src.error(
                &path!["interface", i, "node"],
                format!("names a node not in the mesh: `{}`", it.node),
            )
        })?;
        if interfaces.iter().any(|o| o.node == node) || tied[node] {
            return Err(src.error(
                &path!["interface", i, "node"],
                format!("node `{}` already belongs to another interface", it.node),
            ));
        }
        let mut spider = Vec::new();
        for (j, s) in it.spider.iter().enumerate() {
            let n = lookup(&names, s).ok_or_else(|| {
                src.error(
                    &path!["interface", i, "spider", j],
                    format!("names a node not in the mesh: `{s}`"),
                )
            })?;
            if n == node || tied[n] || interfaces.iter().any(|o| o.node == n) || spider.contains(&n)
            {
                return Err(src.error(
                    &path!["interface", i, "spider", j],
                    format!("node `{s}` is already an interface node or tied to one"),
                ));
            }
            tied[n] = true;
            spider.push(n);
        }
        if degree[node] == 0 && spider.is_empty() {
            return Err(src.error(
                &path!["interface", i, "node"],
                format!(
                    "node `{}` is not connected to the mesh (no element, no spider)",
                    it.node
                ),
            ));
        }
        interfaces.push(Interface {
            name: it.name.clone(),
            node,
            spider,
        });
    }

    let mut markers: Vec<Marker> = Vec::new();
    for (i, m) in f.marker.iter().enumerate() {
        if markers.iter().any(|o| o.name == m.name) || interfaces.iter().any(|o| o.name == m.name) {
            return Err(src.error(
                &path!["marker", i, "name"],
                "duplicate name (markers and interfaces share one namespace)",
            ));
        }
        let node = lookup(&names, &m.node).ok_or_else(|| {
            src.error(
                &path!["marker", i, "node"],
                format!("names a node not in the mesh: `{}`", m.node),
            )
        })?;
        markers.push(Marker {
            name: m.name.clone(),
            node,
        });
    }

    // Every declared node must carry stiffness, and the mesh must hold together
    // (otherwise the free body has more than six zero-frequency modes).
    for i in 0..declared {
        let is_master = interfaces
            .iter()
            .any(|it| it.node == i && !it.spider.is_empty());
        if degree[i] == 0 && !tied[i] && !is_master {
            return Err(src.error(
                &path!["node", i, "name"],
                "node is not connected to any element or spider",
            ));
        }
    }
    if nodes.is_empty() || elements.is_empty() {
        return Err(src.error(&path!["element"], "the model has no elements"));
    }
    let mut parent: Vec<usize> = (0..nodes.len()).collect();
    fn root(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let join = |a: usize, b: usize, p: &mut [usize]| {
        let (ra, rb) = (root(p, a), root(p, b));
        p[ra] = rb;
    };
    for e in &elements {
        join(e.nodes[0], e.nodes[1], &mut parent);
    }
    for it in &interfaces {
        for &s in &it.spider {
            join(it.node, s, &mut parent);
        }
    }
    let r0 = root(&mut parent, 0);
    if let Some(i) = (0..nodes.len()).find(|&i| root(&mut parent, i) != r0) {
        let at = if i < declared {
            path!["node", i, "name"].to_vec()
        } else {
            path!["element"].to_vec()
        };
        return Err(src.error(
            &at,
            format!(
                "the mesh is not connected: `{}` is not linked to `{}` by elements or spiders",
                nodes[i].name, nodes[0].name
            ),
        ));
    }

    let stress_points = super::stress::resolve(src, f, &sections, &elements)?;
    let interface_names: Vec<String> = interfaces.iter().map(|i| i.name.clone()).collect();
    let selection = match &f.selection {
        Some(s) => Rule::from_input(src, &path!["selection"], s, &interface_names)?,
        None => Rule::All,
    };
    let damping = match &f.damping {
        Some(d) => Damping::from_input(src, d)?,
        None => Damping::default(),
    };
    Ok(Mesh {
        name: f.name.clone(),
        description: f.description.clone(),
        path: src.path.clone(),
        variant: chosen.map(|vi| VariantInfo {
            number: f.variant[vi].number,
            description: f.variant[vi].description.clone(),
        }),
        variants: numbers,
        sections,
        nodes,
        elements,
        point_masses,
        interfaces,
        markers,
        stress_points,
        fixed_interface_modes: f
            .fixed_interface_modes
            .unwrap_or(DEFAULT_FIXED_INTERFACE_MODES),
        selection,
        damping,
    })
}
