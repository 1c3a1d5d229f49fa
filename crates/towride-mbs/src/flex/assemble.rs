//! Global stiffness and mass matrices; spiders as multipoint constraints eliminated at
//! assembly.
//!
//! A spider ties FE node s rigidly to its interface node m (RBE2-like):
//! u_s = u_m + theta_m x (x_s - x_m), theta_s = theta_m. The slave's six DOFs are
//! replaced by the master's through the 6x6 map R_s = [[I, -[d]x], [0, I]],
//! d = x_s - x_m, so every element is assembled as T_e^T K_e T_e with
//! T_e = diag(R_a, R_b) (elimination of dependent DOFs; Cook, Malkus, Plesha & Witt,
//! Concepts and Applications of FEA, 4th ed., sec. 9.2). Each independent node keeps six
//! DOFs (u, v, w, theta_x, theta_y, theta_z) in global axes.

use faer::Mat;
use nalgebra::{Matrix3, SMatrix, Vector3};

use super::beam::Mat12;
use super::mesh::Mesh;

pub type Mat6 = SMatrix<f64, 6, 6>;

/// Assembled model in independent DOFs.
#[derive(Clone, Debug)]
pub struct Assembly {
    /// Number of independent DOFs (six per node that is not a spider slave).
    pub n_dof: usize,
    /// First DOF of each mesh node that keeps its own DOFs (None for spider slaves).
    pub node_dof: Vec<Option<usize>>,
    /// For spider slaves: the master node and d = x_slave - x_master.
    pub tie: Vec<Option<(usize, Vector3<f64>)>>,
    /// Positions of the mesh nodes (copied for rigid-body vectors).
    pub positions: Vec<Vector3<f64>>,
    /// Global stiffness matrix in the independent DOFs [N/m, N m/rad].
    pub k: Mat<f64>,
    /// Global consistent mass matrix in the independent DOFs [kg, kg m^2].
    pub m: Mat<f64>,
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0)
}

impl Assembly {
    /// Assembles the stiffness and mass matrices of `mesh`, with its spider slaves
    /// eliminated.
    pub fn new(mesh: &Mesh) -> Assembly {
        let n = mesh.nodes.len();
        let mut tie = vec![None; n];
        for it in &mesh.interfaces {
            for &s in &it.spider {
                let d = mesh.nodes[s].position - mesh.nodes[it.node].position;
                tie[s] = Some((it.node, d));
            }
        }
        let mut node_dof = vec![None; n];
        let mut n_dof = 0;
        for i in 0..n {
            if tie[i].is_none() {
                node_dof[i] = Some(n_dof);
                n_dof += 6;
            }
        }
        let mut asm = Assembly {
            n_dof,
            node_dof,
            tie,
            positions: mesh.nodes.iter().map(|x| x.position).collect(),
            k: Mat::zeros(n_dof, n_dof),
            m: Mat::zeros(n_dof, n_dof),
        };
        for e in &mesh.elements {
            let ke = e.beam.stiffness();
            asm.scatter(e.nodes, &ke, true);
        }
        for (nodes, p) in mesh.mass_points() {
            asm.scatter(nodes, &p.mass_matrix(), false);
        }
        asm
    }

    /// The independent node carrying `node`'s motion and the map from its DOFs.
    pub fn carrier(&self, node: usize) -> (usize, Mat6) {
        match self.tie[node] {
            None => (node, Mat6::identity()),
            Some((master, d)) => {
                let mut r = Mat6::identity();
                r.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-skew(&d)));
                (master, r)
            }
        }
    }

    /// The six DOF indices of an independent node.
    pub fn dofs(&self, node: usize) -> [usize; 6] {
        let b = self.node_dof[node].expect("an independent node");
        [b, b + 1, b + 2, b + 3, b + 4, b + 5]
    }

    fn scatter(&mut self, nodes: [usize; 2], ke: &Mat12, stiffness: bool) {
        let (ma, ra) = self.carrier(nodes[0]);
        let (mb, rb) = self.carrier(nodes[1]);
        let mut t = Mat12::zeros();
        t.fixed_view_mut::<6, 6>(0, 0).copy_from(&ra);
        t.fixed_view_mut::<6, 6>(6, 6).copy_from(&rb);
        let kr = t.transpose() * ke * t;
        let mut idx = [0usize; 12];
        idx[..6].copy_from_slice(&self.dofs(ma));
        idx[6..].copy_from_slice(&self.dofs(mb));
        let target = if stiffness { &mut self.k } else { &mut self.m };
        for r in 0..12 {
            for c in 0..12 {
                target[(idx[r], idx[c])] += kr[(r, c)];
            }
        }
    }

    /// Six-DOF motion of every mesh node from a vector of independent DOFs.
    pub fn expand(&self, q: impl Fn(usize) -> f64) -> Vec<[f64; 6]> {
        (0..self.tie.len())
            .map(|node| {
                let (c, r) = self.carrier(node);
                let d = self.dofs(c);
                let qc = SMatrix::<f64, 6, 1>::from_fn(|i, _| q(d[i]));
                let u = r * qc;
                [u[0], u[1], u[2], u[3], u[4], u[5]]
            })
            .collect()
    }

    /// Rigid-body motions as columns (n_dof x 6): translations along x, y, z, then
    /// rotations about x, y, z through `centre`.
    pub fn rigid_body_vectors(&self, centre: &Vector3<f64>) -> Mat<f64> {
        let mut r = Mat::zeros(self.n_dof, 6);
        for (node, base) in self.node_dof.iter().enumerate() {
            let Some(b) = *base else { continue };
            let x = self.positions[node] - centre;
            for d in 0..3 {
                r[(b + d, d)] = 1.0;
                let u = Vector3::ith(d, 1.0).cross(&x);
                for i in 0..3 {
                    r[(b + i, 3 + d)] = u[i];
                }
                r[(b + 3 + d, 3 + d)] = 1.0;
            }
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flex::modes::static_solution;
    use crate::input::Source;
    use std::path::Path;

    /// A cantilever whose tip is tied by a spider to a node offset by e along z: a
    /// lateral force F on that node bends the beam and twists it by the moment e F, so
    /// the node moves F L^3 / (3 E I_z) + e^2 F L / (G J) (Euler-Bernoulli, Saint-Venant).
    #[test]
    fn spider_transmits_force_and_moment_rigidly() {
        let (l, e): (f64, f64) = (0.8, 0.15);
        let text = format!(
            r#"name = "spider"
shear_deformation = false
[[material]]
name = "steel"
youngs_modulus_pa = 2.1e11
poissons_ratio = 0.3
density_kg_m3 = 7850.0
[[section]]
name = "bar"
shape = "round_solid"
diameter_m = 0.03
[[node]]
name = "root"
position_m = [0.0, 0.0, 0.0]
[[node]]
name = "tip"
position_m = [{l}, 0.0, 0.0]
[[node]]
name = "arm"
position_m = [{l}, 0.0, {e}]
[[element]]
node_a = "root"
node_b = "tip"
section = "bar"
material = "steel"
divisions = 4
[[interface]]
name = "root"
node = "root"
[[interface]]
name = "arm"
node = "arm"
spider = ["tip"]
"#
        );
        let src = Source::from_text(Path::new("spider.toml"), text).unwrap();
        let mesh = Mesh::from_source(&src, None).unwrap();
        let asm = Assembly::new(&mesh);
        let root = asm.dofs(mesh.node_index("root").unwrap());
        let arm = asm.dofs(mesh.node_index("arm").unwrap());
        let f = 100.0;
        let mut load = vec![0.0; asm.n_dof];
        load[arm[1]] = f;
        let u = static_solution(asm.k.as_ref(), &root, &load).unwrap();
        let d = 0.03f64;
        let i = std::f64::consts::PI * d.powi(4) / 64.0;
        let (em, g) = (2.1e11, 2.1e11 / 2.6);
        let want = f * l.powi(3) / (3.0 * em * i) + e * e * f * l / (g * 2.0 * i);
        assert!(
            (u[arm[1]] - want).abs() < 1e-9 * want,
            "{} vs {want}",
            u[arm[1]]
        );
        // The tied tip follows the arm rigidly: theta_x equal, tip y = arm y - e theta_x.
        let tip = asm.expand(|k| u[k])[mesh.node_index("tip").unwrap()];
        assert!((tip[3] - u[arm[3]]).abs() < 1e-12);
        assert!((tip[1] - (u[arm[1]] + e * u[arm[3]])).abs() < 1e-12);
    }
}
