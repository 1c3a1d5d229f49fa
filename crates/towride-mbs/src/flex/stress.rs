//! Nominal stress recovery at named points of a beam model (`[[stress_point]]` in a flex
//! file): section forces from the element end forces, nominal normal and shear stresses
//! at the section's extreme fibres, and the modal "stress modes" that make a run's stress
//! a linear map of the modal coordinates.
//!
//! Section forces. An element's end forces in its local axes are f = K_l T u_e (the
//! element's own stiffness, Przemieniecki 1968 eq. 5.116, on its nodal displacements).
//! With no load along the element, equilibrium of the part [0, x] gives the resultant on
//! the positive cut face: N = -F_x,A, V_y = -F_y,A, V_z = -F_z,A, T = -M_x,A,
//! M_y(x) = -M_y,A - x F_z,A, M_z(x) = -M_z,A + x F_y,A.
//!
//! Nominal stresses (beam theory, e.g. Gere & Goodno, Mechanics of Materials, ch. 5-6):
//! sigma_x(y, z) = N / A + M_y z / I_y - M_z y / I_z; over a rectangle's four corners the
//! extremes are N / A +- |M_y| / W_y +- |M_z| / W_z (W_y = I_y / (h/2), W_z = I_z / (b/2));
//! over a circle N / A +- sqrt(M_y^2 + M_z^2) / W. Torsion: closed thin-walled section,
//! Bredt: tau = T / (2 A_m t), A_m the area inside the wall's mid-line (Roark's Formulas
//! for Stress and Strain, 7th ed., table 10.7 case 16, the same A_m as the section's J);
//! round sections tau = T r / J. Transverse-shear stresses (zero at the extreme fibres of
//! a solid section, small in a box wall) are left out. The combined value is von Mises's
//! sqrt(sigma^2 + 3 tau^2) at the fibre of largest |sigma|.
//!
//! These are NOMINAL stresses, the quantity of the IIW's nominal-stress approach with its
//! FAT classes (Hobbacher, IIW recommendations, doc. IIW-1823-07 / IIW-2259-15, ch. 2-3):
//! a beam model carries no weld geometry, so it gives no structural hot-spot stress and no
//! notch stress. `docs/flex.md`, "Crossbeam stress".

use nalgebra::SVector;

use super::assemble::Assembly;
use super::beam::Beam;
use super::craig_bampton::{CraigBampton, ModeKind};
use super::section::Section;

/// A named stress point: a section of one beam element.
#[derive(Clone, Debug)]
pub struct StressPoint {
    /// Name from the flex file (channel names use it).
    pub name: String,
    /// Index of the element in the mesh.
    pub element: usize,
    /// Position along the element, 0 at its first node, 1 at its second.
    pub xi: f64,
    /// How the section's extreme fibres and torsional stress are found.
    pub fibres: Fibres,
    /// IIW fatigue class FAT of the weld detail there [Pa], if the file gives one.
    pub fat_pa: Option<f64>,
}

/// Section moduli of the shapes stress recovery knows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fibres {
    /// Four corners of a rectangle (hollow): extremes add |M_y|/W_y and |M_z|/W_z.
    Corners {
        /// Area [m^2].
        area_m2: f64,
        /// I_y / (h/2) [m^3].
        wy_m3: f64,
        /// I_z / (b/2) [m^3].
        wz_m3: f64,
        /// Torsional section modulus 2 A_m t [m^3].
        wt_m3: f64,
    },
    /// A circle: extremes add the resultant moment over W.
    Circle {
        /// Area [m^2].
        area_m2: f64,
        /// I / r [m^3].
        w_m3: f64,
        /// J / r [m^3].
        wt_m3: f64,
    },
}

impl Fibres {
    /// The fibres of `section`, or why it has none here (a solid rectangle's torsional
    /// stress peaks mid-side, not at a corner; a `general` section has no outline).
    pub fn of(section: &Section, poissons_ratio: f64) -> Result<Fibres, String> {
        let p = section.properties(poissons_ratio);
        match *section {
            Section::RectangularHollow {
                width_m: b,
                height_m: h,
                wall_m: t,
            } => Ok(Fibres::Corners {
                area_m2: p.area_m2,
                wy_m3: p.iy_m4 / (0.5 * h),
                wz_m3: p.iz_m4 / (0.5 * b),
                wt_m3: 2.0 * (b - t) * (h - t) * t,
            }),
            Section::RoundSolid { diameter_m: d }
            | Section::RoundHollow {
                outer_diameter_m: d,
                ..
            } => Ok(Fibres::Circle {
                area_m2: p.area_m2,
                w_m3: p.iy_m4 / (0.5 * d),
                wt_m3: p.torsion_constant_m4 / (0.5 * d),
            }),
            _ => Err(format!(
                "stress recovery supports rectangular_hollow, round_solid and round_hollow \
                 sections, not {}",
                section.shape_name()
            )),
        }
    }

    /// Nominal stresses from section forces [N, V_y, V_z, T, M_y, M_z].
    pub fn stresses(&self, f: &[f64; 6]) -> NominalStress {
        let [n, _, _, t, my, mz] = *f;
        let (a, bend, wt) = match *self {
            Fibres::Corners {
                area_m2,
                wy_m3,
                wz_m3,
                wt_m3,
            } => (area_m2, my.abs() / wy_m3 + mz.abs() / wz_m3, wt_m3),
            Fibres::Circle {
                area_m2,
                w_m3,
                wt_m3,
            } => (area_m2, my.hypot(mz) / w_m3, wt_m3),
        };
        let (sx_max, sx_min) = (n / a + bend, n / a - bend);
        let tau = t / wt;
        let s = if sx_max.abs() >= sx_min.abs() {
            sx_max
        } else {
            sx_min
        };
        NominalStress {
            sx_max,
            sx_min,
            tau,
            eq: (s * s + 3.0 * tau * tau).sqrt(),
        }
    }

    /// Signed normal stress at four fixed fibres [Pa], for rainflow counting (the
    /// envelope `sx_max` jumps between fibres, so its ranges are no fibre's ranges).
    /// Rectangle: the corners (y, z) = (+,+), (+,-), (-,+), (-,-), where
    /// sigma = N/A + M_y z/I_y - M_z y/I_z. Circle: the fibres on +z, -z, +y, -y (they read
    /// down to 1/sqrt(2) = 71 % of an inclined moment's bending at the fibre between).
    pub fn fibre_stresses(&self, f: &[f64; 6]) -> [f64; 4] {
        let [n, _, _, _, my, mz] = *f;
        match *self {
            Fibres::Corners {
                area_m2,
                wy_m3,
                wz_m3,
                ..
            } => {
                let (a, b, c) = (n / area_m2, my / wy_m3, mz / wz_m3);
                [a + b - c, a - b - c, a + b + c, a - b + c]
            }
            Fibres::Circle { area_m2, w_m3, .. } => {
                let (a, b, c) = (n / area_m2, my / w_m3, mz / w_m3);
                [a + b, a - b, a - c, a + c]
            }
        }
    }
}

/// Nominal stresses at a section [Pa].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NominalStress {
    /// Largest normal stress over the extreme fibres (most tensile).
    pub sx_max: f64,
    /// Smallest normal stress over the extreme fibres (most compressive).
    pub sx_min: f64,
    /// Torsional shear stress (signed as T).
    pub tau: f64,
    /// von Mises combination at the fibre of largest |sigma|.
    pub eq: f64,
}

/// Section forces [N, V_y, V_z, T, M_y, M_z] (local axes; N, N m) at `xi` of `beam` from
/// its nodes' global displacements and rotations.
pub fn section_forces(beam: &Beam, ua: &[f64; 6], ub: &[f64; 6], xi: f64) -> [f64; 6] {
    let u = SVector::<f64, 12>::from_fn(|i, _| if i < 6 { ua[i] } else { ub[i - 6] });
    let f = beam.stiffness_local() * beam.transform() * u;
    let x = xi * beam.length_m;
    [
        -f[0],
        -f[1],
        -f[2],
        -f[3],
        -f[4] - x * f[2],
        -f[5] + x * f[1],
    ]
}

/// Section forces at every stress point from the motion of every mesh node.
pub fn point_forces(
    elements: &[super::mesh::Element],
    points: &[StressPoint],
    nodes: &[[f64; 6]],
) -> Vec<[f64; 6]> {
    points
        .iter()
        .map(|p| {
            let e = &elements[p.element];
            section_forces(&e.beam, &nodes[e.nodes[0]], &nodes[e.nodes[1]], p.xi)
        })
        .collect()
}

/// Stress modes: the section forces at each stress point per unit modal coordinate of
/// each elastic mode (the modes of [`super::ModalData`], same order). A run's section
/// forces are sum_j S_j q_j: a matrix built once.
#[derive(Clone, Debug, Default)]
pub struct StressModes {
    /// The points, in file order.
    pub points: Vec<StressPoint>,
    /// forces[point][mode]: [N, V_y, V_z, T, M_y, M_z] per unit modal coordinate.
    pub forces: Vec<Vec<[f64; 6]>>,
}

impl StressModes {
    /// The stress modes of all elastic modes of `cb`.
    pub fn build(mesh: &super::Mesh, asm: &Assembly, cb: &CraigBampton) -> StressModes {
        let per_mode: Vec<Vec<[f64; 6]>> = (0..cb.kinds.len())
            .filter(|&k| cb.kinds[k] == ModeKind::Elastic)
            .map(|k| {
                let shape = asm.expand(|d| cb.modes[(d, k)]);
                point_forces(&mesh.elements, &mesh.stress_points, &shape)
            })
            .collect();
        let forces = (0..mesh.stress_points.len())
            .map(|p| per_mode.iter().map(|m| m[p]).collect())
            .collect();
        StressModes {
            points: mesh.stress_points.clone(),
            forces,
        }
    }

    /// Keeps the modes `keep` (indices into the elastic modes), as
    /// [`super::ModalData::restrict`] does.
    pub fn restrict(&self, keep: &[usize]) -> StressModes {
        StressModes {
            points: self.points.clone(),
            forces: self
                .forces
                .iter()
                .map(|f| keep.iter().map(|&k| f[k]).collect())
                .collect(),
        }
    }

    /// Section forces at point `p` for modal coordinates `q` (one per kept mode).
    pub fn forces_at(&self, p: usize, q: &[f64]) -> [f64; 6] {
        let mut out = [0.0; 6];
        for (s, &qj) in self.forces[p].iter().zip(q) {
            for c in 0..6 {
                out[c] += s[c] * qj;
            }
        }
        out
    }

    /// Signed normal stresses at point `p`'s four fibres for modal coordinates `q`.
    pub fn fibres_at(&self, p: usize, q: &[f64]) -> [f64; 4] {
        self.points[p].fibres.fibre_stresses(&self.forces_at(p, q))
    }

    /// Nominal stresses at point `p` for modal coordinates `q`.
    pub fn stress_at(&self, p: usize, q: &[f64]) -> NominalStress {
        self.points[p].fibres.stresses(&self.forces_at(p, q))
    }
}

/// The file's `[[stress_point]]` entries located on the meshed elements.
pub(crate) fn resolve(
    src: &crate::input::Source,
    f: &super::input::FlexFile,
    sections: &[(String, Section)],
    elements: &[super::mesh::Element],
) -> Result<Vec<StressPoint>, crate::input::InputError> {
    use crate::path;
    let mut out: Vec<StressPoint> = Vec::new();
    for (i, s) in f.stress_point.iter().enumerate() {
        if out.iter().any(|o| o.name == s.name) {
            return Err(src.error(&path!["stress_point", i, "name"], "duplicate name"));
        }
        let frac = src.finite(&path!["stress_point", i, "at_fraction"], s.at_fraction)?;
        if !(0.0..=1.0).contains(&frac) {
            return Err(src.error(
                &path!["stress_point", i, "at_fraction"],
                format!("must lie in 0..1, got {frac}"),
            ));
        }
        let member = f.element.iter().enumerate().find_map(|(m, e)| {
            if e.node_a == s.node_a && e.node_b == s.node_b {
                Some((m, frac))
            } else if e.node_a == s.node_b && e.node_b == s.node_a {
                Some((m, 1.0 - frac))
            } else {
                None
            }
        });
        let Some((m, along)) = member else {
            return Err(src.error(
                &path!["stress_point", i, "node_b"],
                format!(
                    "no [[element]] runs between `{}` and `{}`",
                    s.node_a, s.node_b
                ),
            ));
        };
        let subs: Vec<usize> = (0..elements.len())
            .filter(|&e| elements[e].member == m)
            .collect();
        let x = along * subs.len() as f64;
        let k = (x.floor() as usize).min(subs.len() - 1);
        let spec = &f.element[m];
        let section = &sections
            .iter()
            .find(|(n, _)| n == &spec.section)
            .expect("a checked member's section exists")
            .1;
        let nu = f
            .material
            .iter()
            .find(|x| x.name == spec.material)
            .expect("a checked member's material exists")
            .poissons_ratio;
        let fibres = Fibres::of(section, nu)
            .map_err(|e| src.error(&path!["stress_point", i, "node_a"], e))?;
        let fat_pa = match s.fat_class_mpa {
            Some(v) => {
                let v = src.finite(&path!["stress_point", i, "fat_class_mpa"], v)?;
                if v <= 0.0 {
                    return Err(src.error(
                        &path!["stress_point", i, "fat_class_mpa"],
                        format!("must be > 0, got {v}"),
                    ));
                }
                Some(v * 1e6)
            }
            None => None,
        };
        out.push(StressPoint {
            name: s.name.clone(),
            element: subs[k],
            xi: x - k as f64,
            fibres,
            fat_pa,
        });
    }
    Ok(out)
}
