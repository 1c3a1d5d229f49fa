//! Linearisation about a state (normally the static equilibrium): eigenvalues, natural
//! and damped frequencies, damping ratios, the bodies and elements that dominate each
//! mode, and the stiffness ratio S = |Re lambda|max / |Re lambda|min of the thesis (3.35).
//!
//! In velocity space (translations and body-axes rotations) the linear equations are
//! M x'' + C x' + K x = 0 on the tangent space B x = 0 of the constraints, with
//! K = d(-f + B^T lambda)/dx including the geometric terms of the reactions and
//! C = -df/dv (dampers and gyroscopic terms). With N an orthonormal basis of the null
//! space of B, x = N z reduces this to an unconstrained system whose first-order form is
//! solved as a dense non-symmetric eigenproblem (faer).

use faer::Mat;
use nalgebra::{DMatrix, SymmetricEigen};
use serde::Serialize;

use super::statics::tangent;
use super::system::System;
use crate::solver::problem::JacobianSink;

#[derive(Clone, Debug, Serialize)]
pub struct Share {
    pub name: String,
    pub share: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct Mode {
    pub index: usize,
    pub real: f64,
    pub imag: f64,
    /// |lambda| / 2 pi [Hz].
    pub undamped_hz: f64,
    /// Im lambda / 2 pi [Hz]; 0 for a real (overdamped or static) root.
    pub damped_hz: f64,
    pub damping_ratio: f64,
    /// Kinetic-energy share per body, largest first (shares > 1 %).
    pub bodies: Vec<Share>,
    /// Strain-energy share per force element, largest first (shares > 1 %).
    pub elements: Vec<Share>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Linearisation {
    pub t: f64,
    /// Degrees of freedom after the constraints.
    pub dof: usize,
    pub modes: Vec<Mode>,
    /// |Re lambda|max / |Re lambda|min over roots with a non-zero real part; `None` when
    /// fewer than two such roots exist (an undamped system).
    pub stiffness_ratio: Option<f64>,
}

/// Mass matrix (velocity space) of the rigid bodies.
fn mass(sys: &System) -> DMatrix<f64> {
    let n = 6 * sys.nb();
    let mut m = DMatrix::zeros(n, n);
    for (k, b) in sys.model.bodies.iter().enumerate() {
        for c in 0..3 {
            m[(6 * k + c, 6 * k + c)] = b.mass;
            for d in 0..3 {
                m[(6 * k + 3 + c, 6 * k + 3 + d)] = b.inertia[c][d];
            }
        }
    }
    m
}

/// -df/dv in velocity space.
fn damping(sys: &System, t: f64, y: &[f64]) -> DMatrix<f64> {
    let (_, ov, ol, _) = sys.offsets();
    let n = 6 * sys.nb();
    let mut e = Vec::new();
    sys.jacobian_entries(t, y, 0.0, &mut JacobianSink { entries: &mut e }, false);
    let mut c = DMatrix::zeros(n, n);
    for &(r, col, v) in &e {
        if (ov..ol).contains(&r) && (ov..ol).contains(&col) {
            c[(r - ov, col - ov)] += v;
        }
    }
    c
}

/// Orthonormal basis of the null space of B (n x (n - rank)).
fn null_space(b: &DMatrix<f64>) -> DMatrix<f64> {
    let n = b.ncols();
    let btb = b.transpose() * b;
    let eig = SymmetricEigen::new(btb);
    let mut idx: Vec<usize> = (0..n).collect();
    idx.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let rank = b.nrows().min(n);
    let keep = n - rank;
    let mut out = DMatrix::zeros(n, keep);
    for (c, &i) in idx.iter().take(keep).enumerate() {
        out.set_column(c, &eig.eigenvectors.column(i));
    }
    out
}

/// Linearises about the solver state (t, y) and solves the eigenproblem.
pub fn linearise(sys: &System, t: f64, y: &[f64]) -> Result<Linearisation, String> {
    let (k, b) = tangent(sys, t, y);
    let c = damping(sys, t, y);
    let m = mass(sys);
    let nmat = null_space(&b);
    let nd = nmat.ncols();
    let mr = nmat.transpose() * &m * &nmat;
    let kr = nmat.transpose() * &k * &nmat;
    let cr = nmat.transpose() * &c * &nmat;
    let mr_inv = mr
        .clone()
        .try_inverse()
        .ok_or("the reduced mass matrix is singular")?;
    let a_k = &mr_inv * &kr;
    let a_c = &mr_inv * &cr;
    let mut a = Mat::<f64>::zeros(2 * nd, 2 * nd);
    for i in 0..nd {
        a[(i, nd + i)] = 1.0;
        for j in 0..nd {
            a[(nd + i, j)] = -a_k[(i, j)];
            a[(nd + i, nd + j)] = -a_c[(i, j)];
        }
    }
    let eig = a
        .eigen()
        .map_err(|e| format!("eigenvalue solver failed: {e:?}"))?;
    let s = eig.S();
    let u = eig.U();
    let elements = element_stiffness(sys, t, y);
    let mut modes = Vec::new();
    for i in 0..2 * nd {
        let l = s[i];
        if l.im < 0.0 {
            continue; // report each conjugate pair once
        }
        // mode shape in velocity space: x = N z
        let mut xr = vec![0.0; 6 * sys.nb()];
        let mut xi = vec![0.0; 6 * sys.nb()];
        for r in 0..6 * sys.nb() {
            for j in 0..nd {
                xr[r] += nmat[(r, j)] * u[(j, i)].re;
                xi[r] += nmat[(r, j)] * u[(j, i)].im;
            }
        }
        let quad = |mat: &DMatrix<f64>| -> f64 {
            let (mr_, mi_) = (
                mat * DMatrix::from_column_slice(xr.len(), 1, &xr),
                mat * DMatrix::from_column_slice(xi.len(), 1, &xi),
            );
            xr.iter().zip(mr_.iter()).map(|(a, b)| a * b).sum::<f64>()
                + xi.iter().zip(mi_.iter()).map(|(a, b)| a * b).sum::<f64>()
        };
        let mut bodies: Vec<Share> = sys
            .model
            .bodies
            .iter()
            .enumerate()
            .map(|(bk, body)| {
                let mut mb = DMatrix::zeros(6 * sys.nb(), 6 * sys.nb());
                for c1 in 0..3 {
                    mb[(6 * bk + c1, 6 * bk + c1)] = body.mass;
                    for c2 in 0..3 {
                        mb[(6 * bk + 3 + c1, 6 * bk + 3 + c2)] = body.inertia[c1][c2];
                    }
                }
                Share {
                    name: body.name.clone(),
                    share: quad(&mb).abs(),
                }
            })
            .collect();
        let mut elems: Vec<Share> = elements
            .iter()
            .map(|(name, ke)| Share {
                name: name.clone(),
                share: quad(ke).abs(),
            })
            .collect();
        normalise(&mut bodies);
        normalise(&mut elems);
        let mag = l.re.hypot(l.im);
        modes.push(Mode {
            index: 0,
            real: l.re,
            imag: l.im,
            undamped_hz: mag / (2.0 * std::f64::consts::PI),
            damped_hz: l.im / (2.0 * std::f64::consts::PI),
            damping_ratio: if mag > 0.0 { -l.re / mag } else { 0.0 },
            bodies,
            elements: elems,
        });
    }
    modes.sort_by(|a, b| a.undamped_hz.total_cmp(&b.undamped_hz));
    for (i, m) in modes.iter_mut().enumerate() {
        m.index = i + 1;
    }
    let big = modes
        .iter()
        .fold(0.0f64, |acc, m| acc.max(m.real.hypot(m.imag)));
    let reals: Vec<f64> = modes
        .iter()
        .map(|m| m.real.abs())
        .filter(|r| *r > 1e-9 * big.max(1e-300))
        .collect();
    let stiffness_ratio = if reals.len() >= 2 {
        Some(
            reals.iter().fold(0.0f64, |a, b| a.max(*b))
                / reals.iter().fold(f64::INFINITY, |a, b| a.min(*b)),
        )
    } else {
        None
    };
    Ok(Linearisation {
        t,
        dof: nd,
        modes,
        stiffness_ratio,
    })
}

fn normalise(v: &mut Vec<Share>) {
    let total: f64 = v.iter().map(|s| s.share).sum();
    if total > 0.0 {
        for s in v.iter_mut() {
            s.share /= total;
        }
    }
    v.retain(|s| s.share > 0.01);
    v.sort_by(|a, b| b.share.total_cmp(&a.share));
}

/// Each force element's own tangent stiffness in velocity space (for strain shares).
fn element_stiffness(sys: &System, t: f64, y: &[f64]) -> Vec<(String, DMatrix<f64>)> {
    let nb = sys.nb();
    let (_, ov, ol, _) = sys.offsets();
    let q = &y[..7 * nb];
    let v = &y[ov..ol];
    let mut out = Vec::new();
    for fe in 0..sys.n_forces() {
        let name = sys.force_name(fe);
        let (bs, gl) = sys.force_eval_dual(fe, t, q, v);
        let mut ke = DMatrix::zeros(6 * nb, 6 * nb);
        for s in 0..2 {
            let Some(b) = bs[s] else { continue };
            for c in 0..6 {
                for (side, body) in bs.iter().enumerate() {
                    let Some(bb) = body else { continue };
                    let d = &gl[s][c].d;
                    let p = [q[7 * bb + 3], q[7 * bb + 4], q[7 * bb + 5], q[7 * bb + 6]];
                    let qm = super::math::qmat(&p);
                    for l in 0..3 {
                        ke[(6 * b + c, 6 * bb + l)] -= d[13 * side + l];
                        for a in 0..4 {
                            ke[(6 * b + c, 6 * bb + 3 + l)] -=
                                d[13 * side + 3 + a] * 0.5 * qm[a][l];
                        }
                    }
                }
            }
        }
        out.push((name, ke));
    }
    out
}
