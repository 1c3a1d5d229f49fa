//! Craig-Bampton reduction, orthonormalised as modal files present it.
//!
//! Craig & Bampton, AIAA J. 6 (1968) 1313-1319. With the interface DOFs b (six per
//! interface node) and the rest i:
//! - static constraint modes Psi = -K_ii^-1 K_ib (unit motion of one interface DOF, the
//!   others held, interior in static equilibrium);
//! - N fixed-interface normal modes Phi_i of (K_ii, M_ii);
//! - T = [[I, 0], [Psi, Phi_i]], K^ = T^T K T, M^ = T^T M T.
//!
//! The reduced basis is then orthonormalised: K^ N = M^ N Lambda with N^T M^ N = I, and
//! Y = T N, so the modal mass is the identity and the modal stiffness diagonal
//! (omega^2). Its six lowest modes are the rigid-body modes (the constraint modes
//! contain rigid motion exactly), dropped by a floating-frame body; the rest is the
//! free-free-like mode table of the body (the procedure of MSC Adams/Flex and Altair's
//! "Craig-Bampton modes" for multibody use; Exudyn's ComputeHurtyCraigBamptonModes).

use super::FlexError;
use faer::{Mat, Side};
use nalgebra::Vector3;

use super::assemble::Assembly;
use super::mesh::Mesh;
use super::modes::{count_rigid, frequency_hz, generalized_eigen, submatrix, symmetrize};

/// Kind of a mode of the orthonormalised basis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeKind {
    /// A rigid-body mode (zero frequency up to rounding).
    Rigid,
    /// An elastic (deformation) mode.
    Elastic,
}

impl ModeKind {
    /// Lower-case name for reports: "rigid" or "elastic".
    pub fn as_str(self) -> &'static str {
        match self {
            ModeKind::Rigid => "rigid",
            ModeKind::Elastic => "elastic",
        }
    }
}

/// The reduced model.
#[derive(Clone, Debug)]
pub struct CraigBampton {
    /// Interface DOFs (six per interface node, in interface order).
    pub boundary: Vec<usize>,
    /// omega^2 of the kept fixed-interface modes.
    pub fixed_interface_omega2: Vec<f64>,
    /// Fixed-interface modes, full size (zero on the interface), M-orthonormal.
    pub fixed_interface_modes: Mat<f64>,
    /// The Craig-Bampton transformation T (n_dof x (n_b + N)).
    pub transformation: Mat<f64>,
    /// Y = T N: orthonormalised modes, ascending, rigid-body modes first.
    pub modes: Mat<f64>,
    /// omega^2 of `modes`, ascending [1/s^2].
    pub omega2: Vec<f64>,
    /// Rigid or elastic, per column of `modes`.
    pub kinds: Vec<ModeKind>,
}

/// One row of the mode table.
#[derive(Clone, Debug)]
pub struct ModeRow {
    /// 1-based, rigid-body modes included (as modal files number them).
    pub number: usize,
    /// Natural frequency [Hz], signed like omega^2 (tiny negative values for rigid-body
    /// modes).
    pub frequency_hz: f64,
    /// Rigid-body or elastic.
    pub kind: ModeKind,
    /// y^T M y with the full FE mass matrix (1 after orthonormalisation).
    pub generalised_mass: f64,
    /// Gamma_d^2 / m_gen for rigid-body directions x, y, z [kg] and rotations about
    /// x, y, z through the centre of mass [kg m^2].
    pub effective_mass: [f64; 6],
    /// Share of the mode's kinetic energy per section name (lumped bodies under
    /// "point_mass"), largest first: tells which part moves.
    pub kinetic_energy_by_section: Vec<(String, f64)>,
}

/// Reduces the assembled model with `n_fixed` fixed-interface modes.
pub fn reduce(mesh: &Mesh, asm: &Assembly, n_fixed: usize) -> Result<CraigBampton, FlexError> {
    if mesh.interfaces.is_empty() {
        return Err(FlexError::Numerics(
            "Craig-Bampton reduction needs at least one interface node".into(),
        ));
    }
    let boundary: Vec<usize> = mesh
        .interfaces
        .iter()
        .flat_map(|it| asm.dofs(it.node))
        .collect();
    let interior: Vec<usize> = (0..asm.n_dof).filter(|d| !boundary.contains(d)).collect();
    let (nb, ni) = (boundary.len(), interior.len());
    if n_fixed > ni {
        return Err(FlexError::Numerics(format!(
            "{n_fixed} fixed-interface modes asked, the model has only {ni} interior DOFs"
        )));
    }
    let kii = submatrix(asm.k.as_ref(), &interior, &interior);
    let kib = submatrix(asm.k.as_ref(), &interior, &boundary);
    let mii = submatrix(asm.m.as_ref(), &interior, &interior);

    // Constraint modes: Psi = -K_ii^-1 K_ib.
    let llt = kii.llt(Side::Lower).map_err(|_| {
        FlexError::Numerics(
            "the model held at its interface nodes is a mechanism: some part is not \
             connected to any interface"
                .to_string(),
        )
    })?;
    let mut psi = -&kib;
    faer::linalg::solvers::Solve::solve_in_place(&llt, psi.as_mut());

    // Fixed-interface modes.
    let fim = generalized_eigen(kii.as_ref(), mii.as_ref())?;

    let nr = nb + n_fixed;
    let mut t = Mat::zeros(asm.n_dof, nr);
    for (c, &b) in boundary.iter().enumerate() {
        t[(b, c)] = 1.0;
    }
    let mut phi_full = Mat::zeros(asm.n_dof, n_fixed);
    for (r, &i) in interior.iter().enumerate() {
        for c in 0..nb {
            t[(i, c)] = psi[(r, c)];
        }
        for c in 0..n_fixed {
            t[(i, nb + c)] = fim.vectors[(r, c)];
            phi_full[(i, c)] = fim.vectors[(r, c)];
        }
    }
    let mut kr = t.transpose() * &asm.k * &t;
    let mut mr = t.transpose() * &asm.m * &t;
    symmetrize(&mut kr);
    symmetrize(&mut mr);
    let red = generalized_eigen(kr.as_ref(), mr.as_ref())?;
    let n_rigid = count_rigid(&red.omega2)?;
    let y = &t * &red.vectors;
    let kinds = (0..nr)
        .map(|i| {
            if i < n_rigid {
                ModeKind::Rigid
            } else {
                ModeKind::Elastic
            }
        })
        .collect();
    Ok(CraigBampton {
        boundary,
        fixed_interface_omega2: fim.omega2[..n_fixed].to_vec(),
        fixed_interface_modes: phi_full,
        transformation: t,
        modes: y,
        omega2: red.omega2,
        kinds,
    })
}

/// Total mass and centre of mass from the FE mass matrix and rigid-body vectors.
pub fn mass_and_centre(asm: &Assembly) -> (f64, Vector3<f64>) {
    let r = asm.rigid_body_vectors(&Vector3::zeros());
    let g = r.transpose() * &asm.m * &r;
    let m = g[(0, 0)];
    // R_t^T M R_r = -[m c]x: read m c from the skew part.
    let mc = Vector3::new(g[(1, 5)], g[(2, 3)], g[(0, 4)]);
    (m, mc / m)
}

/// Effective masses of the columns of `modes` (n_dof x k) for rigid-body motions about
/// the centre of mass: Gamma = y^T M r, m_eff = Gamma^2 / (y^T M y).
pub fn effective_masses(asm: &Assembly, modes: &Mat<f64>) -> Vec<(f64, [f64; 6])> {
    let (_, c) = mass_and_centre(asm);
    let r = asm.rigid_body_vectors(&c);
    let my = &asm.m * modes;
    let gamma = modes.transpose() * &asm.m * &r;
    (0..modes.ncols())
        .map(|k| {
            let gm: f64 = (0..modes.nrows()).map(|i| modes[(i, k)] * my[(i, k)]).sum();
            let mut e = [0.0; 6];
            for d in 0..6 {
                e[d] = gamma[(k, d)].powi(2) / gm;
            }
            (gm, e)
        })
        .collect()
}

/// Kinetic-energy share of each section (and of the lumped bodies) in mode column `k`.
pub fn kinetic_energy_by_section(
    mesh: &Mesh,
    asm: &Assembly,
    modes: &Mat<f64>,
    k: usize,
) -> Vec<(String, f64)> {
    let shape = asm.expand(|d| modes[(d, k)]);
    let mut parts: Vec<(String, f64)> = Vec::new();
    let mut add = |name: &str, e: f64| match parts.iter_mut().find(|(n, _)| n == name) {
        Some(p) => p.1 += e,
        None => parts.push((name.to_string(), e)),
    };
    for el in &mesh.elements {
        let q = nalgebra::SMatrix::<f64, 12, 1>::from_fn(|i, _| shape[el.nodes[i / 6]][i % 6]);
        add(&el.section, (q.transpose() * el.beam.mass() * q)[0]);
    }
    for pm in &mesh.point_masses {
        let u = Vector3::from_fn(|i, _| shape[pm.node][i]);
        let w = Vector3::from_fn(|i, _| shape[pm.node][3 + i]);
        let j: f64 = (0..3).map(|i| pm.inertia_kg_m2[i] * w[i] * w[i]).sum();
        add("point_mass", pm.mass_kg * u.dot(&u) + j);
    }
    let total: f64 = parts.iter().map(|p| p.1).sum();
    for p in &mut parts {
        p.1 /= total;
    }
    parts.sort_by(|a, b| b.1.total_cmp(&a.1));
    parts
}

/// The free-free-like mode table of the orthonormalised basis.
pub fn mode_table(mesh: &Mesh, asm: &Assembly, cb: &CraigBampton) -> Vec<ModeRow> {
    effective_masses(asm, &cb.modes)
        .into_iter()
        .enumerate()
        .map(|(k, (gm, eff))| ModeRow {
            number: k + 1,
            frequency_hz: frequency_hz(cb.omega2[k]),
            kind: cb.kinds[k],
            generalised_mass: gm,
            effective_mass: eff,
            kinetic_energy_by_section: kinetic_energy_by_section(mesh, asm, &cb.modes, k),
        })
        .collect()
}
