//! Linearisation about a state (normally the static equilibrium): eigenvalues, natural
//! and damped frequencies, damping ratios, the bodies and elements that dominate each
//! mode, and the stiffness ratio S = |Re lambda|max / |Re lambda|min of the thesis (3.35).
//!
//! In velocity space (translations, body-axes rotations, modal coordinates) the linear
//! equations are M x'' + C x' + K x + D e = 0 on the tangent space B x = 0 of the
//! constraints, with K = d(-f + B^T lambda)/dx including the geometric terms of the
//! reactions, C = -df/dv (dampers and gyroscopic terms) and D the load of the extension
//! states e (tyre rings and treads, controllers), which obey E e' + F_x x + F_v x' + F_e e
//! = 0. With N an orthonormal basis of the null space of B, x = N z reduces this to an
//! unconstrained first-order system solved as a dense non-symmetric eigenproblem (faer).

use faer::Mat;
use nalgebra::{DMatrix, SymmetricEigen};
use serde::Serialize;

use super::system::System;
use super::ModelError;
use towride_solver::problem::JacobianSink;

/// A body's or element's share of a mode's energy.
#[derive(Clone, Debug, Serialize)]
pub struct Share {
    /// Body or force-element name.
    pub name: String,
    /// Share of the mode's kinetic (bodies) or strain (elements) energy, 0..1.
    pub share: f64,
}

/// One eigenvalue lambda of the linearised model with its frequencies and energy shares.
#[derive(Clone, Debug, Serialize)]
pub struct Mode {
    /// 1-based number, by ascending undamped frequency.
    pub index: usize,
    /// Re lambda [1/s] (JSON `real_1_per_s`: every number of the JSON names its unit).
    #[serde(rename = "real_1_per_s")]
    pub real: f64,
    /// Im lambda [rad/s] (JSON `imag_rad_per_s`).
    #[serde(rename = "imag_rad_per_s")]
    pub imag: f64,
    /// |lambda| / 2 pi [Hz].
    pub undamped_hz: f64,
    /// Im lambda / 2 pi [Hz]; 0 for a real (overdamped or static) root.
    pub damped_hz: f64,
    /// Damping ratio -Re lambda / |lambda| (1 for a real negative root); meaningless
    /// for a zero root (`kind` rigid), whose angle is round-off.
    pub damping_ratio: f64,
    /// What the root is: a zero root of a free motion, an unstable root, an
    /// oscillation or a real decaying root.
    pub kind: RootKind,
    /// Re lambda > 0: the growth rate [1/s] and the time the motion takes to double
    /// [s] (ln 2 / Re lambda); `None` otherwise.
    pub doubling_time_s: Option<f64>,
    /// Kinetic-energy share per body, largest first (shares > 1 %).
    pub bodies: Vec<Share>,
    /// Strain-energy share per force element, largest first (shares > 1 %).
    pub elements: Vec<Share>,
    /// The dominant motion ("car_body bounce", "wheel hop wheel_fl", "hitch vertical
    /// bending, crossbeam"):
    /// the body and direction with the largest share of the mode's kinetic energy
    /// ([`motion_shares`]); "first-order states (tyres, controllers)" when the bodies
    /// carry no kinetic energy.
    pub name: String,
    /// The kinetic-energy share of that motion, 0..1.
    pub name_share: f64,
    /// Kinetic-energy share per body and direction, largest first (shares > 1 %).
    pub motions: Vec<Share>,
    /// The mode shape in velocity space (`System::vo` layout: translation, rotation about
    /// body axes, modal coordinates per body), the phase with the largest real part, real
    /// part only; not serialised.
    #[serde(skip)]
    pub shape: Vec<f64>,
}

/// The kind of a root of the linearised model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RootKind {
    /// |lambda| below [`ZERO_ROOT_HZ`]: a motion without restoring force (a vehicle's
    /// lateral position, heading, travel), not a vibration; its damping ratio is
    /// round-off.
    Zero,
    /// Re lambda > 0 beyond round-off: the frozen state is unstable in this motion
    /// (it grows by e^(Re lambda t) as long as the state holds).
    Unstable,
    /// A complex pair: a damped oscillation.
    Oscillation,
    /// A real negative root: a decay without oscillation (overdamped, first-order).
    Decay,
}

impl RootKind {
    /// The frequency below which a root is a zero root [Hz] ([`ZERO_ROOT_HZ`]).
    pub fn zero_hz() -> f64 {
        ZERO_ROOT_HZ
    }
}

/// Roots slower than this [Hz] are zero roots: a period of over 1000 s is no vibration
/// of a vehicle crossing an obstacle, and round-off of a singular stiffness matrix puts
/// its free motions' roots at 1e-8..1e-5 Hz.
pub const ZERO_ROOT_HZ: f64 = 1e-3;

/// The kind of the root lambda = re + i im (rad/s), and the doubling time of a growing
/// one; `scale` is the largest |lambda| of the model (round-off is relative to it).
fn classify(re: f64, im: f64, scale: f64) -> (RootKind, Option<f64>) {
    let mag = re.hypot(im);
    if mag / (2.0 * std::f64::consts::PI) < ZERO_ROOT_HZ {
        return (RootKind::Zero, None);
    }
    if re > 1e-9 * scale.max(1.0) {
        return (RootKind::Unstable, Some(std::f64::consts::LN_2 / re));
    }
    if im > 0.0 {
        (RootKind::Oscillation, None)
    } else {
        (RootKind::Decay, None)
    }
}

/// The motions a body's kinetic energy is split into: translations along world x, y, z,
/// rotations about world x, y, z, and the elastic (modal) part.
const MOTIONS: [&str; 7] = [
    "fore-aft", "lateral", "bounce", "roll", "pitch", "yaw", "elastic",
];

/// The name of motion `k` of body `name`; `wheel` when a tyre sits on the body (its
/// vertical motion is wheel hop, its rotation about the axle spin).
fn motion_name(name: &str, k: usize, wheel: bool) -> String {
    match (k, wheel) {
        (2, true) => format!("wheel hop {name}"),
        (4, true) => format!("{name} spin"),
        _ => format!("{name} {}", MOTIONS[k]),
    }
}

/// Kinetic energy of a velocity-space vector (real and imaginary parts) per body and
/// motion ([`MOTIONS`]), from each body's mass, inertia (rotated to world axes at `q`) and
/// unit modal mass; the coupling of a `full` modal body's frame and modes is left out of
/// the split (it is small at the deformations of a linearisation).
pub fn motion_energies(sys: &System, q: &[f64], xr: &[f64], xi: &[f64]) -> Vec<[f64; 7]> {
    sys.model
        .bodies
        .iter()
        .enumerate()
        .map(|(b, body)| {
            let o = sys.vo[b];
            let p = &q[sys.qo[b] + 3..sys.qo[b] + 7];
            let r = super::math::rot(&[p[0], p[1], p[2], p[3]]);
            let mut e = [0.0; 7];
            for x in [xr, xi] {
                for d in 0..3 {
                    e[d] += 0.5 * body.mass * x[o + d] * x[o + d];
                }
                // omega in world axes and J in world axes: J_w = R J R^T.
                let w: Vec<f64> = (0..3)
                    .map(|i| (0..3).map(|j| r[i][j] * x[o + 3 + j]).sum())
                    .collect();
                let jb = body.inertia;
                let jw = |i: usize, j: usize| -> f64 {
                    let mut s = 0.0;
                    for a in 0..3 {
                        for c in 0..3 {
                            s += r[i][a] * jb[a][c] * r[j][c];
                        }
                    }
                    s
                };
                for d in 0..3 {
                    let jwd: f64 = (0..3).map(|j| jw(d, j) * w[j]).sum();
                    e[3 + d] += 0.5 * w[d] * jwd;
                }
                for m in 0..sys.nm[b] {
                    e[6] += 0.5 * x[o + 6 + m] * x[o + 6 + m];
                }
            }
            e
        })
        .collect()
}

/// The groups of bodies a mode is named by: each wheel (a body a tyre sits on) with the
/// light parts that move with it (the bodies connected to it by joints and force
/// elements without passing a body heavier than twice the heaviest wheel: knuckle,
/// arms, strut rod; both wheels of a twist beam), every other body alone. Each group:
/// its name, its bodies (heaviest first) and whether it carries a wheel.
pub fn naming_groups(sys: &System) -> Vec<(String, Vec<usize>, bool)> {
    let m = &sys.model;
    let nb = m.bodies.len();
    let wheel: Vec<bool> = (0..nb)
        .map(|b| m.tyres.iter().any(|t| sys.body_of(t.marker) == Some(b)))
        .collect();
    let heaviest_wheel = (0..nb)
        .filter(|&b| wheel[b])
        .map(|b| m.bodies[b].mass)
        .fold(0.0, f64::max);
    let light = |b: usize| m.bodies[b].mass <= 2.0 * heaviest_wheel;
    let mut parent: Vec<usize> = (0..nb).collect();
    fn root(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let pairs = m
        .joints
        .iter()
        .map(|j| (j.i, Some(j.j)))
        .chain(m.forces.iter().map(|f| f.markers()));
    for (i, j) in pairs {
        if let (Some(a), Some(b)) = (sys.body_of(i), j.and_then(|j| sys.body_of(j))) {
            if a != b && light(a) && light(b) {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra] = rb;
            }
        }
    }
    let mut groups: Vec<(String, Vec<usize>, bool)> = Vec::new();
    let mut seen = vec![false; nb];
    for b in 0..nb {
        if seen[b] {
            continue;
        }
        let r = root(&mut parent, b);
        let members: Vec<usize> = (0..nb).filter(|&c| root(&mut parent, c) == r).collect();
        let wheels: Vec<&str> = members
            .iter()
            .filter(|&&c| wheel[c])
            .map(|&c| m.bodies[c].name.as_str())
            .collect();
        if wheels.is_empty() {
            seen[b] = true;
            groups.push((m.bodies[b].name.clone(), vec![b], false));
        } else {
            let mut members = members;
            for &c in &members {
                seen[c] = true;
            }
            members.sort_by(|&x, &y| m.bodies[y].mass.total_cmp(&m.bodies[x].mass));
            groups.push((wheels.join("+"), members, true));
        }
    }
    groups
}

/// The shares of [`motion_energies`] pooled over [`naming_groups`], with their names,
/// largest first (all of them).
pub fn motion_shares(sys: &System, q: &[f64], xr: &[f64], xi: &[f64]) -> Vec<Share> {
    let energies = motion_energies(sys, q, xr, xi);
    let e = &energies;
    let total: f64 = e.iter().flatten().map(|v| v.max(0.0)).sum();
    let mut out: Vec<Share> = naming_groups(sys)
        .iter()
        .flat_map(|(name, members, wheel)| {
            (0..7).map(move |k| {
                let v: f64 = members.iter().map(|&b| e[b][k].max(0.0)).sum();
                let elastic = (k == 6).then(|| elastic_character(sys, members, xr, xi));
                Share {
                    name: match elastic.flatten() {
                        Some(c) => format!("{name} {c}"),
                        None => motion_name(name, k, *wheel),
                    },
                    share: if total > 0.0 { v / total } else { 0.0 },
                }
            })
        })
        .collect();
    out.sort_by(|a, b| b.share.total_cmp(&a.share));
    out
}

/// The character of the modal coordinate carrying most of the elastic kinetic energy of
/// `members` in the vector (xr, xi) ("vertical bending", [`crate::flex::character`]),
/// `None` when they have no modal coordinates.
fn elastic_character(sys: &System, members: &[usize], xr: &[f64], xi: &[f64]) -> Option<String> {
    let mut best: Option<(f64, &str)> = None;
    for &b in members {
        let Some(m) = &sys.model.bodies[b].modal else {
            continue;
        };
        for (j, mode) in m.data.modes.iter().enumerate() {
            let i = sys.vo[b] + 6 + j;
            let e = xr[i] * xr[i] + xi[i] * xi[i];
            if best.is_none_or(|(x, _)| e > x) {
                best = Some((e, mode.character.0.as_str()));
            }
        }
    }
    best.map(|(_, c)| c.to_string())
}

/// The mode's name from its sorted motion shares: the largest, or the two largest of the
/// same kind (left and right wheel hop, say) when the second has at least 70 % of the
/// first's share.
fn mode_name(motions: &[Share]) -> (String, f64) {
    let kind = |n: &str| -> String {
        let w: Vec<&str> = n.split(' ').collect();
        if n.starts_with("wheel hop ") {
            "wheel hop".into()
        } else {
            w.last().copied().unwrap_or("").to_string()
        }
    };
    match motions {
        [a, b, ..] if b.share >= 0.7 * a.share && kind(&a.name) == kind(&b.name) => {
            let k = kind(&a.name);
            let who = |n: &str| -> String {
                if k == "wheel hop" {
                    n.trim_start_matches("wheel hop ").to_string()
                } else {
                    n.trim_end_matches(&format!(" {k}")).to_string()
                }
            };
            let name = if k == "wheel hop" {
                format!("wheel hop {} and {}", who(&a.name), who(&b.name))
            } else {
                format!("{} and {} {k}", who(&a.name), who(&b.name))
            };
            (name, a.share + b.share)
        }
        [a, ..] => (a.name.clone(), a.share),
        [] => (String::new(), 0.0),
    }
}

/// The eigen-analysis of the model linearised about a state.
#[derive(Clone, Debug, Serialize)]
pub struct Linearisation {
    /// Time of the state linearised about [s].
    #[serde(rename = "t_s")]
    pub t: f64,
    /// Degrees of freedom after the constraints.
    pub dof: usize,
    /// First-order states (tyre deflections and slips, controllers): with the 2 x `dof`
    /// states of the second-order part they give the eigenvalues, each conjugate pair
    /// listed once as a mode.
    pub first_order_states: usize,
    /// Eigenvalues of the state matrix (2 x dof + first-order states).
    pub eigenvalues: usize,
    /// Eigenvalues, by ascending undamped frequency.
    pub modes: Vec<Mode>,
    /// |Re lambda|max / |Re lambda|min over roots with a non-zero real part; `None` when
    /// fewer than two such roots exist (an undamped system).
    pub stiffness_ratio: Option<f64>,
}

/// Velocity-space mass matrix.
fn mass(sys: &System, q: &[f64]) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(sys.nv, sys.nv);
    for (r, c, v) in sys.mass_entries_at(q) {
        m[(r, c)] += v;
    }
    m
}

/// The iteration matrix dF/dy + cj dF/dy' as a dense matrix.
fn dense_jacobian(sys: &System, t: f64, y: &[f64], cj: f64) -> DMatrix<f64> {
    let n = sys.size();
    let mut e = Vec::new();
    sys.jacobian_entries(t, y, cj, &mut JacobianSink::new(&mut e), false);
    let mut out = DMatrix::zeros(n, n);
    for (r, c, v) in e {
        out[(r, c)] += v;
    }
    out
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
pub fn linearise(sys: &System, t: f64, y: &[f64]) -> Result<Linearisation, ModelError> {
    let (_, ov, ol, om) = sys.offsets();
    let oe = sys.oe();
    let (nv, ne) = (sys.nv, sys.ne);
    let j0 = dense_jacobian(sys, t, y, 0.0);
    let mut h = DMatrix::zeros(sys.nq, nv);
    for (r, c, v) in sys.q_map(&y[..ov]) {
        h[(r, c)] += v;
    }
    let blk = |r0: usize, nr: usize, c0: usize, nc: usize| j0.view((r0, c0), (nr, nc)).into_owned();
    let k = blk(ov, nv, 0, sys.nq) * &h;
    let c = blk(ov, nv, ov, nv);
    let d = blk(ov, nv, oe, ne);
    let b = blk(ol, om - ol, 0, sys.nq) * &h;
    let fx = blk(oe, ne, 0, sys.nq) * &h;
    let fv = blk(oe, ne, ov, nv);
    let fe = blk(oe, ne, oe, ne);
    let e_rate = dense_jacobian(sys, t, y, 1.0)
        .view((oe, oe), (ne, ne))
        .into_owned()
        - &fe;
    let m = mass(sys, &y[..sys.nq]);
    let nmat = null_space(&b);
    let nd = nmat.ncols();
    let mr = nmat.transpose() * &m * &nmat;
    let kr = nmat.transpose() * &k * &nmat;
    let cr = nmat.transpose() * &c * &nmat;
    let dr = nmat.transpose() * &d;
    let mr_inv = mr
        .clone()
        .try_inverse()
        .ok_or_else(|| ModelError::Linearise("the reduced mass matrix is singular".into()))?;
    let e_inv = e_rate.try_inverse().ok_or_else(|| {
        ModelError::Linearise(
            "the extension states' rate matrix is singular (an algebraic tyre state)".into(),
        )
    })?;
    let a_k = &mr_inv * &kr;
    let a_c = &mr_inv * &cr;
    let a_d = &mr_inv * &dr;
    let e_x = &e_inv * &fx * &nmat;
    let e_v = &e_inv * &fv * &nmat;
    let e_e = &e_inv * &fe;
    let ns = 2 * nd + ne;
    let mut a = Mat::<f64>::zeros(ns, ns);
    for i in 0..nd {
        a[(i, nd + i)] = 1.0;
        for j in 0..nd {
            a[(nd + i, j)] = -a_k[(i, j)];
            a[(nd + i, nd + j)] = -a_c[(i, j)];
        }
        for j in 0..ne {
            a[(nd + i, 2 * nd + j)] = -a_d[(i, j)];
        }
    }
    for i in 0..ne {
        for j in 0..nd {
            a[(2 * nd + i, j)] = -e_x[(i, j)];
            a[(2 * nd + i, nd + j)] = -e_v[(i, j)];
        }
        for j in 0..ne {
            a[(2 * nd + i, 2 * nd + j)] = -e_e[(i, j)];
        }
    }
    let eig = a
        .eigen()
        .map_err(|e| ModelError::Linearise(format!("eigenvalue solver failed: {e:?}")))?;
    let s = eig.S();
    let u = eig.U();
    let elements = element_stiffness(sys, t, y);
    let mut modes = Vec::new();
    for i in 0..ns {
        let l = s[i];
        if l.im < 0.0 {
            continue; // report each conjugate pair once
        }
        // mode shape in velocity space: x = N z
        let mut xr = vec![0.0; nv];
        let mut xi = vec![0.0; nv];
        for r in 0..nv {
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
                let mut mb = DMatrix::zeros(nv, nv);
                let range = sys.vo[bk]..sys.vo[bk] + 6 + sys.nm[bk];
                for (r, c, v) in sys.mass_entries_at(&y[..sys.nq]) {
                    if range.contains(&r) {
                        mb[(r, c)] += v;
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
        let kinetic: f64 = bodies.iter().map(|s| s.share).sum();
        normalise(&mut bodies);
        normalise(&mut elems);
        let mut motions = motion_shares(sys, &y[..sys.nq], &xr, &xi);
        // A mode of the tyre and controller states alone moves no mass.
        let moving = kinetic > 1e-12 * (dot(&xr, &xr) + dot(&xi, &xi));
        let (name, name_share) = if moving && !motions.is_empty() {
            mode_name(&motions)
        } else {
            ("first-order states (tyres, controllers)".to_string(), 0.0)
        };
        motions.retain(|s| s.share > 0.01);
        let shape = real_shape(&xr, &xi);
        let mag = l.re.hypot(l.im);
        modes.push(Mode {
            index: 0,
            real: l.re,
            imag: l.im,
            undamped_hz: mag / (2.0 * std::f64::consts::PI),
            damped_hz: l.im / (2.0 * std::f64::consts::PI),
            damping_ratio: if mag > 0.0 { -l.re / mag } else { 0.0 },
            kind: RootKind::Decay,
            doubling_time_s: None,
            bodies,
            elements: elems,
            name,
            name_share,
            motions,
            shape,
        });
    }
    modes.sort_by(|a, b| a.undamped_hz.total_cmp(&b.undamped_hz));
    for (i, m) in modes.iter_mut().enumerate() {
        m.index = i + 1;
    }
    let big = modes
        .iter()
        .fold(0.0f64, |acc, m| acc.max(m.real.hypot(m.imag)));
    for m in &mut modes {
        (m.kind, m.doubling_time_s) = classify(m.real, m.imag, big);
    }
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
        first_order_states: ne,
        eigenvalues: ns,
        modes,
        stiffness_ratio,
    })
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Re(e^{i phi} (xr + i xi)) at the phase phi that makes it largest.
fn real_shape(xr: &[f64], xi: &[f64]) -> Vec<f64> {
    let (a, b, c) = (dot(xr, xr), dot(xr, xi), dot(xi, xi));
    let phi = 0.5 * (-2.0 * b).atan2(a - c);
    let (cp, sp) = (phi.cos(), phi.sin());
    xr.iter().zip(xi).map(|(r, i)| r * cp - i * sp).collect()
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

/// Each force element's own tangent stiffness in velocity space (for strain shares), by
/// finite differences of its generalised loads over its bodies' position increments.
fn element_stiffness(sys: &System, t: f64, y: &[f64]) -> Vec<(String, DMatrix<f64>)> {
    let (_, ov, ol, _) = sys.offsets();
    let q = &y[..ov];
    let v = &y[ov..ol];
    let nv = sys.nv;
    let mut out = Vec::new();
    for (fe, _) in sys.model.each_element() {
        let name = sys.force_name(fe);
        let load = |q: &[f64]| -> Vec<f64> {
            let (bs, gl, _) = sys.force_eval(fe, t, q, v);
            let mut f = vec![0.0; nv];
            for s in 0..2 {
                if let Some(b) = bs[s] {
                    for (c, x) in gl[s].iter().enumerate() {
                        f[sys.vo[b] + c] += x;
                    }
                }
            }
            f
        };
        let f0 = load(q);
        let mut ke = DMatrix::zeros(nv, nv);
        let mut bodies: Vec<usize> = sys.force_bodies(fe).into_iter().flatten().collect();
        bodies.dedup();
        for b in bodies {
            for col in sys.vo[b]..sys.vo[b] + 6 + sys.nm[b] {
                let h = 1e-7;
                let mut dx = vec![0.0; nv];
                dx[col] = h;
                let mut qp = q.to_vec();
                sys.apply_increment(&mut qp, &dx);
                let f1 = load(&qp);
                for r in 0..nv {
                    ke[(r, col)] = -(f1[r] - f0[r]) / h;
                }
            }
        }
        out.push((name, ke));
    }
    out
}

#[cfg(test)]
mod root_kinds {
    use super::{classify, RootKind};

    #[test]
    fn zero_unstable_oscillating_and_decaying_roots_are_told_apart() {
        let scale = 2.0 * std::f64::consts::PI * 200.0;
        // Round-off roots of free motions, whatever their angle.
        for (re, im) in [(-5e-8, 0.0), (8.5e-7, 0.0), (1e-6, 3e-6)] {
            assert_eq!(classify(re, im, scale), (RootKind::Zero, None));
        }
        // A frozen state growing at 0.5 1/s doubles in ln 2 / 0.5 s.
        let (k, t) = classify(0.5, 0.0, scale);
        assert_eq!(k, RootKind::Unstable);
        assert!((t.unwrap() - std::f64::consts::LN_2 / 0.5).abs() < 1e-15);
        assert_eq!(classify(0.2, 10.0, scale).0, RootKind::Unstable);
        assert_eq!(classify(-1.0, 10.0, scale).0, RootKind::Oscillation);
        assert_eq!(classify(-30.0, 0.0, scale).0, RootKind::Decay);
    }
}
