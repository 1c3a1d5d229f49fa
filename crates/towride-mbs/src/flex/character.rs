//! What an elastic mode does, in words: bending, torsion or axial stretch, from the
//! share of its strain energy in each family of the beam elements' local DOFs, with the
//! body-frame direction it moves in. The linear analysis names a vehicle mode dominated
//! by a modal body's elastic motion this way ("hitch vertical bending").

use nalgebra::SVector;

use super::mesh::Mesh;

/// Local DOF families of a beam element (`Beam::stiffness_local` has no coupling
/// between them): axial stretch, torsion, bending with displacement along local y, and
/// along local z.
const FAMILIES: [&[usize]; 4] = [&[0, 6], &[3, 9], &[1, 5, 7, 11], &[2, 4, 8, 10]];

/// Body-frame axes as a vehicle engineer names them.
const AXES: [&str; 3] = ["fore-aft", "lateral", "vertical"];

/// The character of mode shape `shape` (six DOFs per mesh node, body frame) and the
/// share of the strain energy behind it: "vertical bending, bracket", "torsion about y,
/// crossbeam", "axial along y, crossbeam". Bending is named by the axis its translations
/// are largest along, torsion and stretch by the axis of the rotations or translations
/// carrying them; the section named is the one holding the most strain energy.
pub fn character(mesh: &Mesh, shape: &[[f64; 6]]) -> (String, f64) {
    let mut energy = [0.0; 4];
    let mut by_section: Vec<(&str, f64)> = Vec::new();
    for el in &mesh.elements {
        let q = SVector::<f64, 12>::from_fn(|i, _| shape[el.nodes[i / 6]][i % 6]);
        let ql = el.beam.transform() * q;
        let k = el.beam.stiffness_local();
        let mut element = 0.0;
        for (f, dofs) in FAMILIES.iter().enumerate() {
            for &i in dofs.iter() {
                for &j in dofs.iter() {
                    let e = 0.5 * ql[i] * k[(i, j)] * ql[j];
                    energy[f] += e;
                    element += e;
                }
            }
        }
        match by_section.iter_mut().find(|(n, _)| *n == el.section) {
            Some(s) => s.1 += element,
            None => by_section.push((&el.section, element)),
        }
    }
    let part = by_section
        .iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or("", |s| s.0);
    let total: f64 = energy.iter().sum();
    let (bending, rest) = (energy[2] + energy[3], [energy[0], energy[1]]);
    // Largest sum of squares over the nodes of the translations (from 0) or rotations
    // (from 3), as an axis index.
    let axis = |from: usize| -> usize {
        let mut s = [0.0; 3];
        for d in shape {
            for a in 0..3 {
                s[a] += d[from + a] * d[from + a];
            }
        }
        (0..3).max_by(|&a, &b| s[a].total_cmp(&s[b])).unwrap_or(0)
    };
    let xyz = ["x", "y", "z"];
    if total <= 0.0 {
        return ("elastic".into(), 0.0);
    }
    let (what, share) = if bending >= rest[0] && bending >= rest[1] {
        (format!("{} bending", AXES[axis(0)]), bending / total)
    } else if rest[1] >= rest[0] {
        (format!("torsion about {}", xyz[axis(3)]), rest[1] / total)
    } else {
        (format!("axial along {}", xyz[axis(0)]), rest[0] / total)
    };
    (format!("{what}, {part}"), share)
}
