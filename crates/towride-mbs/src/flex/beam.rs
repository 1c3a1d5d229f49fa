//! The 3D two-node beam element: 12 DOF (u, v, w, theta_x, theta_y, theta_z per node),
//! Timoshenko shear optional, consistent mass with rotary inertia.
//!
//! Bending uses the interdependent interpolation of the Timoshenko beam (cubic
//! deflection, quadratic rotation, constant shear strain; the static solution of the
//! element, so the stiffness is exact): Przemieniecki, Theory of Matrix Structural
//! Analysis (1968), sec. 5.6 and 11.5; Friedman & Kosmatka, Computers & Structures 47
//! (1993) 473-481. With phi = 0 it reduces to Hermite cubics (Euler-Bernoulli). The mass
//! matrix is the consistent one of the same interpolation, translational and rotary
//! parts, integrated by 4-point Gauss quadrature (exact for these polynomials). The
//! quadrature points are kept ([`MassPoint`]) because the inertia invariants of a modal
//! body are integrals of the same mass distribution (see `invariants.rs`).

use nalgebra::{Matrix3, SMatrix, Vector3};

use super::material::Material;
use super::section::SectionProperties;

/// 12x12 matrix of one beam element's DOFs (stiffness, mass).
pub type Mat12 = SMatrix<f64, 12, 12>;
/// 3x12 map from a beam element's 12 DOFs to a 3-vector (displacement or rotation).
pub type Mat3x12 = SMatrix<f64, 3, 12>;

/// Why a beam cannot be built.
#[derive(Clone, Debug, PartialEq)]
pub enum BeamError {
    /// The two nodes coincide.
    ZeroLength,
    /// The orientation vector is parallel to the element axis.
    OrientationParallel,
}

/// A point of the mass distribution: a slice of a beam (one quadrature point) or a
/// lumped body. The displacement of a material point at offset d from `position` is
/// u + theta x d, with u = `nu` q and theta = `nt` q for the owner's nodal DOFs q.
#[derive(Clone, Debug)]
pub struct MassPoint {
    /// Position of the slice's centroid (or the lumped body's centre of mass) [m].
    pub position: Vector3<f64>,
    /// Mass of the slice or lumped body [kg].
    pub mass_kg: f64,
    /// D = integral of rho d d^T over the slice [kg m^2]; the inertia tensor about the
    /// centroid is tr(D) I - D.
    pub second_moment: Matrix3<f64>,
    /// Axis displacement (global components) from the owner's 12 global DOFs.
    pub nu: Mat3x12,
    /// Section rotation (global components) from the owner's 12 global DOFs.
    pub nt: Mat3x12,
}

impl MassPoint {
    /// This point's share of the consistent mass matrix:
    /// m nu^T nu + nt^T (tr(D) I - D) nt.
    pub fn mass_matrix(&self) -> Mat12 {
        let j = Matrix3::identity() * self.second_moment.trace() - self.second_moment;
        self.nu.transpose() * self.nu * self.mass_kg + self.nt.transpose() * j * self.nt
    }
}

/// A straight beam element between two nodes.
#[derive(Clone, Debug)]
pub struct Beam {
    /// Position of the first node [m].
    pub a: Vector3<f64>,
    /// Position of the second node [m].
    pub b: Vector3<f64>,
    /// Length between the nodes [m].
    pub length_m: f64,
    /// Rows: the local x, y, z axes in global components (v_local = axes v_global).
    pub axes: Matrix3<f64>,
    /// Young's modulus E [Pa].
    pub youngs_modulus_pa: f64,
    /// Shear modulus G [Pa].
    pub shear_modulus_pa: f64,
    /// Density [kg/m^3].
    pub density_kg_m3: f64,
    /// Cross-section properties in the local axes.
    pub section: SectionProperties,
    /// Timoshenko shear flexibility on (where the section has shear areas).
    pub shear: bool,
}

/// 4-point Gauss-Legendre on [0, 1]: abscissae and weights.
const GAUSS4: [(f64, f64); 4] = [
    (
        0.5 - 0.5 * 0.861_136_311_594_052_6,
        0.5 * 0.347_854_845_137_453_9,
    ),
    (
        0.5 - 0.5 * 0.339_981_043_584_856_3,
        0.5 * 0.652_145_154_862_546_1,
    ),
    (
        0.5 + 0.5 * 0.339_981_043_584_856_3,
        0.5 * 0.652_145_154_862_546_1,
    ),
    (
        0.5 + 0.5 * 0.861_136_311_594_052_6,
        0.5 * 0.347_854_845_137_453_9,
    ),
];

/// Bending shape functions of one plane (deflection v, rotation theta = v' in the
/// shear-rigid limit) for DOFs (v1, theta1, v2, theta2) at xi = x / L; Friedman &
/// Kosmatka (1993) eq. (14). Returns (N_v, N_theta).
pub fn bending_shape(xi: f64, l: f64, phi: f64) -> ([f64; 4], [f64; 4]) {
    let c = 1.0 / (1.0 + phi);
    let (x2, x3) = (xi * xi, xi * xi * xi);
    let nv = [
        c * (2.0 * x3 - 3.0 * x2 - phi * xi + 1.0 + phi),
        c * l * (x3 - (2.0 + 0.5 * phi) * x2 + (1.0 + 0.5 * phi) * xi),
        c * (-2.0 * x3 + 3.0 * x2 + phi * xi),
        c * l * (x3 - (1.0 - 0.5 * phi) * x2 - 0.5 * phi * xi),
    ];
    let nt = [
        c * 6.0 / l * (x2 - xi),
        c * (3.0 * x2 - (4.0 + phi) * xi + 1.0 + phi),
        -c * 6.0 / l * (x2 - xi),
        c * (3.0 * x2 - (2.0 - phi) * xi),
    ];
    (nv, nt)
}

/// The orthonormal local axes (rows x, y, z): x along a -> b, y the part of
/// `local_y` perpendicular to x (Nastran CBAR's orientation-vector convention).
pub fn local_axes(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    local_y: &Vector3<f64>,
) -> Result<Matrix3<f64>, BeamError> {
    let d = b - a;
    let l = d.norm();
    if l.is_nan() || l <= 1e-9 {
        return Err(BeamError::ZeroLength);
    }
    let ex = d / l;
    let z = ex.cross(local_y);
    if local_y.norm() == 0.0 || z.norm() < 1e-6 * local_y.norm() {
        return Err(BeamError::OrientationParallel);
    }
    let ez = z.normalize();
    let ey = ez.cross(&ex);
    Ok(Matrix3::from_rows(&[
        ex.transpose(),
        ey.transpose(),
        ez.transpose(),
    ]))
}

/// Default orientation: local z as close to global z as possible (local y horizontal);
/// for an element along global z, local y = global y.
pub fn default_local_y(a: &Vector3<f64>, b: &Vector3<f64>) -> Vector3<f64> {
    let d = (b - a).normalize();
    let y = Vector3::z().cross(&d);
    if y.norm() < 1e-6 {
        Vector3::y()
    } else {
        y
    }
}

impl Beam {
    /// A beam from `a` to `b` with local y from `local_y` (see [`local_axes`]); fails on
    /// coincident nodes or an orientation vector along the axis.
    pub fn new(
        a: Vector3<f64>,
        b: Vector3<f64>,
        local_y: Vector3<f64>,
        material: &Material,
        section: SectionProperties,
        shear: bool,
    ) -> Result<Beam, BeamError> {
        let axes = local_axes(&a, &b, &local_y)?;
        Ok(Beam {
            a,
            b,
            length_m: (b - a).norm(),
            axes,
            youngs_modulus_pa: material.youngs_modulus_pa,
            shear_modulus_pa: material.shear_modulus_pa,
            density_kg_m3: material.density_kg_m3,
            section,
            shear,
        })
    }

    /// Shear-flexibility ratio of bending in the x-y plane: 12 E Iz / (G A_sy L^2).
    pub fn phi_y(&self) -> f64 {
        match (self.shear, self.section.shear_area_y_m2) {
            (true, Some(a)) => {
                12.0 * self.youngs_modulus_pa * self.section.iz_m4
                    / (self.shear_modulus_pa * a * self.length_m.powi(2))
            }
            _ => 0.0,
        }
    }

    /// Shear-flexibility ratio of bending in the x-z plane: 12 E Iy / (G A_sz L^2).
    pub fn phi_z(&self) -> f64 {
        match (self.shear, self.section.shear_area_z_m2) {
            (true, Some(a)) => {
                12.0 * self.youngs_modulus_pa * self.section.iy_m4
                    / (self.shear_modulus_pa * a * self.length_m.powi(2))
            }
            _ => 0.0,
        }
    }

    /// Stiffness in local DOFs (Przemieniecki 1968, eq. 5.116, shear included).
    pub fn stiffness_local(&self) -> Mat12 {
        let l = self.length_m;
        let e = self.youngs_modulus_pa;
        let s = &self.section;
        let mut k = Mat12::zeros();
        let ea = e * s.area_m2 / l;
        let gj = self.shear_modulus_pa * s.torsion_constant_m4 / l;
        for (i, j, v) in [
            (0, 0, ea),
            (6, 6, ea),
            (0, 6, -ea),
            (3, 3, gj),
            (9, 9, gj),
            (3, 9, -gj),
        ] {
            k[(i, j)] = v;
            k[(j, i)] = v;
        }
        // One bending plane in (v1, theta1, v2, theta2) with theta = v' (x-y plane);
        // the x-z plane has theta_y = -w', hence the sign pattern `sg` on rotations.
        let mut plane = |dofs: [usize; 4], ei: f64, phi: f64, sg: f64| {
            let c = ei / ((1.0 + phi) * l.powi(3));
            let kp = [
                [12.0, 6.0 * l, -12.0, 6.0 * l],
                [6.0 * l, (4.0 + phi) * l * l, -6.0 * l, (2.0 - phi) * l * l],
                [-12.0, -6.0 * l, 12.0, -6.0 * l],
                [6.0 * l, (2.0 - phi) * l * l, -6.0 * l, (4.0 + phi) * l * l],
            ];
            let sign = [1.0, sg, 1.0, sg];
            for r in 0..4 {
                for c2 in 0..4 {
                    k[(dofs[r], dofs[c2])] = c * kp[r][c2] * sign[r] * sign[c2];
                }
            }
        };
        plane([1, 5, 7, 11], e * s.iz_m4, self.phi_y(), 1.0);
        plane([2, 4, 8, 10], e * s.iy_m4, self.phi_z(), -1.0);
        k
    }

    /// T with q_local = T q_global: the 3x3 axes on the diagonal four times.
    pub fn transform(&self) -> Mat12 {
        let mut t = Mat12::zeros();
        for blk in 0..4 {
            t.fixed_view_mut::<3, 3>(3 * blk, 3 * blk)
                .copy_from(&self.axes);
        }
        t
    }

    /// Stiffness in global DOFs.
    pub fn stiffness(&self) -> Mat12 {
        let t = self.transform();
        t.transpose() * self.stiffness_local() * t
    }

    /// Axis displacement and section rotation at xi = x / L, local components, from
    /// local DOFs.
    pub fn interpolation_local(&self, xi: f64) -> (Mat3x12, Mat3x12) {
        let l = self.length_m;
        let (nvy, nty) = bending_shape(xi, l, self.phi_y());
        let (nvz, ntz) = bending_shape(xi, l, self.phi_z());
        let mut nu = Mat3x12::zeros();
        let mut nt = Mat3x12::zeros();
        // Axial and torsion: linear.
        nu[(0, 0)] = 1.0 - xi;
        nu[(0, 6)] = xi;
        nt[(0, 3)] = 1.0 - xi;
        nt[(0, 9)] = xi;
        // x-y plane: v with theta_z = v' (shear-rigid limit).
        for (c, dof) in [1, 5, 7, 11].into_iter().enumerate() {
            nu[(1, dof)] = nvy[c];
            nt[(2, dof)] = nty[c];
        }
        // x-z plane: w with psi = -theta_y playing theta's role.
        let sg = [1.0, -1.0, 1.0, -1.0];
        for (c, dof) in [2, 4, 8, 10].into_iter().enumerate() {
            nu[(2, dof)] = nvz[c] * sg[c];
            nt[(1, dof)] = -ntz[c] * sg[c];
        }
        (nu, nt)
    }

    /// The mass distribution as quadrature points with global interpolation.
    pub fn mass_points(&self) -> Vec<MassPoint> {
        let l = self.length_m;
        let rho = self.density_kg_m3;
        let s = &self.section;
        let t = self.transform();
        let at = self.axes.transpose();
        // Section second moments: integral of y^2 = Iz along local y, z^2 = Iy along z.
        let d_local = Matrix3::from_diagonal(&Vector3::new(0.0, s.iz_m4, s.iy_m4));
        GAUSS4
            .iter()
            .map(|&(xi, w)| {
                let (nu, nt) = self.interpolation_local(xi);
                MassPoint {
                    position: self.a + (self.b - self.a) * xi,
                    mass_kg: rho * s.area_m2 * l * w,
                    second_moment: at * d_local * self.axes * (rho * l * w),
                    nu: at * nu * t,
                    nt: at * nt * t,
                }
            })
            .collect()
    }

    /// Consistent mass matrix in global DOFs.
    pub fn mass(&self) -> Mat12 {
        self.mass_points()
            .iter()
            .fold(Mat12::zeros(), |m, p| m + p.mass_matrix())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flex::section::Section;

    fn steel() -> Material {
        Material::new("steel", 210e9, 0.3, None, 7850.0)
    }

    fn beam(shear: bool) -> Beam {
        let sec = Section::RectangularSolid {
            width_m: 0.03,
            height_m: 0.05,
        }
        .properties(0.3);
        Beam::new(
            Vector3::new(0.1, 0.2, 0.3),
            Vector3::new(0.5, 0.4, 0.1),
            Vector3::new(0.0, 0.0, 1.0),
            &steel(),
            sec,
            shear,
        )
        .unwrap()
    }

    /// Stiffness by integrating the strain energy of the same interpolation (bending
    /// EI theta'^2, shear G A_s gamma^2), by Gauss quadrature: an independent check of
    /// the closed-form matrix and of the shape functions.
    fn stiffness_by_quadrature(b: &Beam) -> Mat12 {
        let l = b.length_m;
        let (e, g) = (b.youngs_modulus_pa, b.shear_modulus_pa);
        let s = b.section;
        let h = 1e-6;
        let mut k = Mat12::zeros();
        for &(xi, w) in GAUSS4.iter() {
            let (nu0, nt0) = b.interpolation_local(xi);
            // Exact derivatives of the cubic/quadratic by central differences of
            // step h are accurate to h^2 * third derivative ~ 1e-12 relative.
            let (nup, ntp) = b.interpolation_local(xi + h);
            let (num, ntm) = b.interpolation_local(xi - h);
            let du = (nup - num) / (2.0 * h * l);
            let dt = (ntp - ntm) / (2.0 * h * l);
            let row = |m: &Mat3x12, r: usize| m.row(r).into_owned();
            let mut add = |bm: SMatrix<f64, 1, 12>, c: f64| {
                k += bm.transpose() * bm * (c * l * w);
            };
            add(row(&du, 0), e * s.area_m2);
            add(row(&dt, 0), g * s.torsion_constant_m4);
            add(row(&dt, 2), e * s.iz_m4);
            add(row(&dt, 1), e * s.iy_m4);
            if b.shear {
                // gamma_y = v' - theta_z, gamma_z = w' + theta_y.
                add(row(&du, 1) - row(&nt0, 2), g * s.shear_area_y_m2.unwrap());
                add(row(&du, 2) + row(&nt0, 1), g * s.shear_area_z_m2.unwrap());
            }
            let _ = nu0;
        }
        k
    }

    #[test]
    fn closed_form_stiffness_is_the_interpolation_energy() {
        for shear in [false, true] {
            let b = beam(shear);
            let k = b.stiffness_local();
            let kq = stiffness_by_quadrature(&b);
            let err = (k - kq).abs().max() / k.abs().max();
            assert!(err < 1e-6, "shear {shear}: {err}");
        }
    }

    #[test]
    fn euler_bernoulli_mass_is_the_classical_consistent_matrix() {
        // Przemieniecki eq. 11.23/11.26 (phi = 0): rho A L / 420 [156 22L 54 -13L; ...]
        // plus rotary rho I / (30 L) [36 3L -36 3L; 3L 4L^2 -3L -L^2; ...].
        let b = beam(false);
        let t = b.transform();
        let m = t * b.mass() * t.transpose();
        let (l, rho, s) = (b.length_m, b.density_kg_m3, b.section);
        let ma = rho * s.area_m2 * l;
        let tr = [
            [156.0, 22.0 * l, 54.0, -13.0 * l],
            [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
            [54.0, 13.0 * l, 156.0, -22.0 * l],
            [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
        ];
        let ro = [
            [36.0, 3.0 * l, -36.0, 3.0 * l],
            [3.0 * l, 4.0 * l * l, -3.0 * l, -l * l],
            [-36.0, -3.0 * l, 36.0, -3.0 * l],
            [3.0 * l, -l * l, -3.0 * l, 4.0 * l * l],
        ];
        let dofs = [1, 5, 7, 11];
        for r in 0..4 {
            for c in 0..4 {
                let want = ma / 420.0 * tr[r][c] + rho * s.iz_m4 / (30.0 * l) * ro[r][c];
                let got = m[(dofs[r], dofs[c])];
                assert!((got - want).abs() < 1e-12 * ma * l * l + 1e-12, "{r} {c}");
            }
        }
        // Axial rho A L / 6 [2 1; 1 2], torsion rho (Iy + Iz) L / 6 [2 1; 1 2].
        assert!((m[(0, 6)] - ma / 6.0).abs() < 1e-12 * ma);
        let ip = rho * (s.iy_m4 + s.iz_m4) * l;
        assert!((m[(3, 3)] - ip / 3.0).abs() < 1e-12 * ip);
    }

    #[test]
    fn timoshenko_translational_mass_matches_przemieniecki() {
        // Przemieniecki eq. 11.41: translational part with shear, over (1 + phi)^2:
        // m11 = 13/35 + 7/10 phi + 1/3 phi^2, m12 = (11/210 + 11/120 phi + 1/24 phi^2) L,
        // m13 = 9/70 + 3/10 phi + 1/6 phi^2, m14 = -(13/420 + 3/40 phi + 1/24 phi^2) L,
        // m22 = (1/105 + 1/60 phi + 1/120 phi^2) L^2, m24 = -(1/140 + 1/60 phi + 1/120 phi^2) L^2.
        let mut b = beam(true);
        b.section.iz_m4 *= 1e-9; // isolate the translational part (rotary ~ Iz)
        b.section.iy_m4 *= 1e-9;
        // Keep the shear ratio of the original section.
        let phi = {
            let b0 = beam(true);
            b0.phi_y()
        };
        b.section.shear_area_y_m2 = Some(b.section.shear_area_y_m2.unwrap() * 1e-9);
        assert!((b.phi_y() - phi).abs() < 1e-12 * phi);
        let t = b.transform();
        let m = t * b.mass() * t.transpose();
        let l = b.length_m;
        let ma = b.density_kg_m3 * b.section.area_m2 * l / (1.0 + phi).powi(2);
        let p2 = phi * phi;
        let want = [
            (1, 1, 13.0 / 35.0 + 0.7 * phi + p2 / 3.0),
            (1, 5, (11.0 / 210.0 + 11.0 / 120.0 * phi + p2 / 24.0) * l),
            (1, 7, 9.0 / 70.0 + 0.3 * phi + p2 / 6.0),
            (1, 11, -(13.0 / 420.0 + 3.0 / 40.0 * phi + p2 / 24.0) * l),
            (5, 5, (1.0 / 105.0 + phi / 60.0 + p2 / 120.0) * l * l),
            (5, 11, -(1.0 / 140.0 + phi / 60.0 + p2 / 120.0) * l * l),
        ];
        for (r, c, w) in want {
            let got = m[(r, c)] / ma;
            assert!(
                (got - w).abs() < 1e-6 * w.abs().max(1e-3),
                "{r} {c}: {got} vs {w}"
            );
        }
    }

    #[test]
    fn rigid_motions_cost_no_energy_and_carry_the_mass() {
        let b = beam(true);
        let k = b.stiffness();
        let m = b.mass();
        // Rigid rotation about global z through the origin: u = e_z x x, theta = e_z.
        let mut q = SMatrix::<f64, 12, 1>::zeros();
        for (n, x) in [b.a, b.b].iter().enumerate() {
            let u = Vector3::z().cross(x);
            for i in 0..3 {
                q[6 * n + i] = u[i];
            }
            q[6 * n + 5] = 1.0;
        }
        assert!((k * q).norm() < 1e-9 * k.norm() * q.norm());
        // Rigid translation along x: kinetic energy coefficient = element mass.
        let mut tx = SMatrix::<f64, 12, 1>::zeros();
        tx[0] = 1.0;
        tx[6] = 1.0;
        let mass = b.density_kg_m3 * b.section.area_m2 * b.length_m;
        assert!(((tx.transpose() * m * tx)[0] - mass).abs() < 1e-12 * mass);
    }

    #[test]
    fn degenerate_geometry_is_refused() {
        let s = beam(false).section;
        let e = Beam::new(
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::y(),
            &steel(),
            s,
            false,
        );
        assert_eq!(e.unwrap_err(), BeamError::ZeroLength);
        let e = Beam::new(
            Vector3::zeros(),
            Vector3::x(),
            Vector3::x(),
            &steel(),
            s,
            false,
        );
        assert_eq!(e.unwrap_err(), BeamError::OrientationParallel);
    }
}
