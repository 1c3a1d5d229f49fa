//! The `full` coupling level of a modal body (docs/flex.md, "Coupling levels").
//!
//! A free-floating hitch (no gravity, no joints, modal damping off) spinning about a
//! non-principal axis with an initial modal deflection must conserve its angular momentum
//! about the centre of mass and its kinetic plus strain energy. Both are measured
//! independently of the reduced equations: from the FE model's own mass points (the
//! quadrature points whose sum is the consistent mass matrix) moved by the nodal motion
//! reconstructed from the modal state, and the FE stiffness matrix. A round free bar
//! that keeps only the modes the frame's rotation does not load (torsion and symmetric
//! bending) must move as the rigid body: the analytical torque-free precession.

use std::path::Path;

use nalgebra::{DMatrix, Matrix3, Vector3};
use towride_mbs::flex::{FlexBody, ModalData, Options};
use towride_mbs::model::desc::{Body, Coupling, Modal, Model};
use towride_mbs::model::system::System;
use towride_solver::{Advance, Bdf, DaeMethod, DaeProblem, SolverOptions};

/// World rotation matrix of a unit quaternion (w, x, y, z), body to world.
fn rot(p: &[f64]) -> Matrix3<f64> {
    let (w, x, y, z) = (p[0], p[1], p[2], p[3]);
    Matrix3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// The free modal body `md` with initial angular velocity `omega` (world) and coupling.
fn free_body(md: &ModalData, omega: [f64; 3], coupling: Coupling) -> System {
    let mut md = md.clone();
    for m in &mut md.modes {
        m.damping_ratio = 0.0;
    }
    let mut model = Model {
        name: "free modal body".into(),
        ..Default::default()
    };
    model.bodies.push(Body {
        name: "body".into(),
        mass: md.mass_kg,
        inertia: md.inertia_com_kg_m2,
        position: md.com_m,
        orientation: [1.0, 0.0, 0.0, 0.0],
        velocity: [0.0; 3],
        angular_velocity: omega,
        modal: Some(Box::new(Modal { data: md, coupling })),
    });
    System::new(model)
}

/// Angular momentum and energy of the deformed, moving FE model, independent of the
/// reduced equations.
struct Reference {
    /// The FE mass points: element nodes, position, mass, second moment D, interpolation
    /// of axis displacement and section rotation from the 12 element DOFs.
    points: Vec<([usize; 2], towride_mbs::flex::beam::MassPoint)>,
    /// Per kept mode, the six-DOF motion of every mesh node.
    shapes: Vec<Vec<[f64; 6]>>,
    /// y_j^T K y_k with the assembled FE stiffness.
    stiffness: DMatrix<f64>,
    /// Independent nodes (node, first DOF), positions, FE mass matrix: for the
    /// nodal-momentum version p = M x'.
    nodes: Vec<(usize, usize)>,
    positions: Vec<Vector3<f64>>,
    mass_matrix: DMatrix<f64>,
    com: Vector3<f64>,
}

/// What the reference measures at one state.
struct Measure {
    /// Angular momentum about the centre of mass, world [N m s]: from the mass points,
    /// and from the FE mass matrix and the nodal velocities.
    h: Vector3<f64>,
    h_nodal: Vector3<f64>,
    kinetic: f64,
    strain: f64,
}

impl Reference {
    fn new(b: &FlexBody, md: &ModalData) -> Reference {
        let cols: Vec<usize> = md.modes.iter().map(|m| m.number - 1).collect();
        let asm = &b.assembly;
        let shapes = cols
            .iter()
            .map(|&k| asm.expand(|d| b.cb.modes[(d, k)]))
            .collect();
        let nd = asm.n_dof;
        let n = cols.len();
        let k = DMatrix::from_fn(nd, nd, |r, c| asm.k[(r, c)]);
        let y = DMatrix::from_fn(nd, n, |r, j| b.cb.modes[(r, cols[j])]);
        let nodes = (0..asm.node_dof.len())
            .filter_map(|i| asm.node_dof[i].map(|d| (i, d)))
            .collect();
        Reference {
            points: b.mesh.mass_points(),
            shapes,
            stiffness: y.transpose() * k * &y,
            nodes,
            positions: asm.positions.clone(),
            mass_matrix: DMatrix::from_fn(nd, nd, |r, c| asm.m[(r, c)]),
            com: Vector3::from(md.com_m),
        }
    }

    /// At body state: quaternion p, modal coordinates eta, velocity u (world), angular
    /// velocity om (body axes), modal rates zeta (H about the centre of mass and the
    /// energies do not depend on the position).
    fn measure(
        &self,
        p: &[f64],
        eta: &[f64],
        u: &Vector3<f64>,
        om: &Vector3<f64>,
        zeta: &[f64],
    ) -> Measure {
        let a = rot(p);
        let field = |node: usize, c: &[f64]| -> [f64; 6] {
            let mut out = [0.0; 6];
            for (j, x) in c.iter().enumerate() {
                for (i, o) in out.iter_mut().enumerate() {
                    *o += self.shapes[j][node][i] * x;
                }
            }
            out
        };
        let elem = |nodes: [usize; 2], c: &[f64]| -> nalgebra::SVector<f64, 12> {
            let (fa, fb) = (field(nodes[0], c), field(nodes[1], c));
            nalgebra::SVector::<f64, 12>::from_fn(|i, _| if i < 6 { fa[i] } else { fb[i - 6] })
        };
        // Slice centroids: body-frame position from the CM, velocity (world), mass.
        let mut slices = Vec::with_capacity(self.points.len());
        let mut mass = 0.0;
        let mut first = Vector3::zeros();
        for (nodes, mp) in &self.points {
            let (qe, qd) = (elem(*nodes, eta), elem(*nodes, zeta));
            let rho = mp.position - self.com + mp.nu * qe;
            let vel = u + a * (om.cross(&rho) + mp.nu * qd);
            mass += mp.mass_kg;
            first += rho * mp.mass_kg;
            slices.push((rho, vel, mp.nt * qe, mp.nt * qd));
        }
        let cm = first / mass;
        let mut h = Vector3::zeros();
        let mut kinetic = 0.0;
        let eye = Matrix3::identity();
        for ((_, mp), (rho, vel, th, thd)) in self.points.iter().zip(&slices) {
            let m = mp.mass_kg;
            let d = mp.second_moment;
            // Points of the slice at offset d sit at T d, T = 1 + ~theta, and move with
            // omega x T d + theta' x d (body axes).
            let t = eye + th.cross_matrix();
            let tdt = t * d * t.transpose();
            let spin =
                (eye * tdt.trace() - tdt) * om + thd * (t * d).trace() - d * t.transpose() * thd;
            h += (a * (rho - cm)).cross(&(vel * m)) + a * spin;
            kinetic += 0.5 * m * vel.norm_squared()
                + 0.5 * om.dot(&((eye * tdt.trace() - tdt) * om))
                + om.dot(&(thd * (t * d).trace() - d * t.transpose() * thd))
                + 0.5 * thd.dot(&((eye * d.trace() - d) * thd));
        }
        let e = DMatrix::from_column_slice(eta.len(), 1, eta);
        let strain = 0.5 * (e.transpose() * &self.stiffness * &e)[(0, 0)];
        // Nodal version: body-frame nodal velocities, p = M x', H = sum (x - c) x p_t + p_r.
        let nd = self.mass_matrix.nrows();
        let mut xd = DMatrix::zeros(nd, 1);
        let mut pos = Vec::new();
        let ub = a.transpose() * u;
        for &(node, dof) in &self.nodes {
            let (fe, fz) = (field(node, eta), field(node, zeta));
            let x = self.positions[node] - self.com + Vector3::new(fe[0], fe[1], fe[2]);
            let vt = ub + om.cross(&x) + Vector3::new(fz[0], fz[1], fz[2]);
            let vr = om + Vector3::new(fz[3], fz[4], fz[5]);
            for c in 0..3 {
                xd[(dof + c, 0)] = vt[c];
                xd[(dof + 3 + c, 0)] = vr[c];
            }
            pos.push((x, dof));
        }
        let pm = &self.mass_matrix * xd;
        let mut hn = Vector3::zeros();
        for (x, dof) in pos {
            let pt = Vector3::new(pm[(dof, 0)], pm[(dof + 1, 0)], pm[(dof + 2, 0)]);
            let pr = Vector3::new(pm[(dof + 3, 0)], pm[(dof + 4, 0)], pm[(dof + 5, 0)]);
            hn += (x - cm).cross(&pt) + pr;
        }
        Measure {
            h,
            h_nodal: a * hn,
            kinetic,
            strain,
        }
    }
}

/// Runs `sys` from `eta0` to `t_end` at `rtol` and the model's absolute tolerances
/// times `atol` (`System::atol`), and calls `at(t, q, v)` every `dt`.
fn run(
    sys: &System,
    eta0: &[f64],
    t_end: f64,
    dt: f64,
    (rtol, atol): (f64, f64),
    mut at: impl FnMut(f64, &[f64], &[f64]),
) -> usize {
    let (mut q, mut v) = sys.initial_q_v();
    q[7..7 + eta0.len()].copy_from_slice(eta0);
    let (y0, yp0, _) =
        towride_mbs::model::ic::initial_state(sys, 0.0, &mut q, &mut v, &[]).unwrap();
    let opts = SolverOptions {
        rtol,
        atol: sys.atol(atol),
        ..Default::default()
    };
    let mut bdf = Bdf::new(sys, 0.0, &y0, &yp0, opts).unwrap();
    bdf.set_stop_time(t_end);
    let n = DaeProblem::size(sys);
    let (mut y, mut yp) = (vec![0.0; n], vec![0.0; n]);
    at(0.0, &y0[..sys.nq], &y0[sys.nq..sys.nq + sys.nv]);
    let steps = (t_end / dt).round() as usize;
    for k in 1..=steps {
        let t = (k as f64 * dt).min(t_end);
        while bdf.advance(t).unwrap() != Advance::Reached {}
        bdf.interpolate(t, &mut y, &mut yp);
        at(t, &y[..sys.nq], &y[sys.nq..sys.nq + sys.nv]);
    }
    bdf.stats().steps
}

fn hitch() -> FlexBody {
    FlexBody::load(
        Path::new(repo!("flex/hitch_crossbeam.toml")),
        None,
        &Options {
            fixed_interface_modes: Some(8),
            rule: None,
        },
        &towride_mbs::input::Loader::new(),
    )
    .unwrap()
}

/// Largest relative drifts of a free-body run against the reference: angular momentum
/// (mass points), energy (mass points + FE stiffness), angular momentum from the FE mass
/// matrix and nodal velocities, and the reduced model's own v^T M v / 2 + strain energy.
#[derive(Debug, Default)]
struct Drift {
    h: f64,
    e: f64,
    h_nodal: f64,
    e_own: f64,
}

fn spin_run(
    re: &Reference,
    md: &ModalData,
    coupling: Coupling,
    omega: [f64; 3],
    eta0: &[f64],
    t_end: f64,
    tol: (f64, f64),
) -> Drift {
    let sys = free_body(md, omega, coupling);
    let nm = md.modes.len();
    let mut first: Option<(Vector3<f64>, f64, Vector3<f64>, f64)> = None;
    let mut d = Drift::default();
    let wall = std::time::Instant::now();
    let steps = run(&sys, eta0, t_end, 2e-3, tol, |_t, q, v| {
        let (eta, zeta) = (&q[7..7 + nm], &v[6..6 + nm]);
        let u = Vector3::new(v[0], v[1], v[2]);
        let om = Vector3::new(v[3], v[4], v[5]);
        let m = re.measure(&q[3..7], eta, &u, &om, zeta);
        let e = m.kinetic + m.strain;
        let mut own = sys.strain_energy(0, q).0;
        for (rr, c, x) in sys.mass_entries_at(q) {
            own += 0.5 * v[rr] * x * v[c];
        }
        match &first {
            None => {
                if coupling == Coupling::Full {
                    // The reduced model's kinetic energy is the FE body's.
                    assert!((own / e - 1.0).abs() < 1e-10, "{own} vs {e}");
                }
                first = Some((m.h, e, m.h_nodal, own));
            }
            Some((h0, e0, hn0, own0)) => {
                d.h = d.h.max((m.h - h0).norm() / h0.norm());
                d.e = d.e.max((e - e0).abs() / e0);
                d.h_nodal = d.h_nodal.max((m.h_nodal - hn0).norm() / hn0.norm());
                d.e_own = d.e_own.max((own - own0).abs() / own0);
            }
        }
    });
    let (h0, e0, _, _) = first.unwrap();
    println!(
        "{coupling:?}, rtol {:.0e}: |H| {:.6} N m s, E {:.6} J, {t_end} s, {steps} steps, {:.2} s wall: max |dH|/|H| {:.2e}, max |dE|/E {:.2e}; H from p = M x' {:.2e}; own energy {:.2e}",
        tol.0,
        h0.norm(),
        e0,
        wall.elapsed().as_secs_f64(),
        d.h,
        d.e,
        d.h_nodal,
        d.e_own
    );
    d
}

#[test]
fn free_spinning_hitch_conserves_momentum_and_energy_with_full_coupling() {
    let b = hitch();
    // The four lowest elastic modes (166-273 Hz): enough coupling to see, few enough
    // oscillations to resolve at tight tolerances.
    let md = b.modal.restrict(&[0, 1, 2, 3]);
    let re = Reference::new(&b, &md);
    // |omega| 14.5 rad/s about a non-principal axis: 1.6 s is about 3.7 turns.
    let omega = [4.0, 7.0, 12.0];
    // About 1.5 mm at the ball.
    let eta0 = [4e-3, -3e-3, 3e-3, 2e-3];
    let t_end = 1.6;
    // The two measures of H agree on a rigid motion (it lies in the element
    // interpolation); on a deformed one p = M x' misses the rotation of the deformation
    // (omega x Phi eta is not a field the nodal rotations of M describe), so only the
    // mass-point measure is exact there.
    let (p, u, om) = ([1.0, 0.0, 0.0, 0.0], Vector3::zeros(), Vector3::from(omega));
    let rigid = re.measure(&p, &[0.0; 4], &u, &om, &[0.0; 4]);
    let bent = re.measure(&p, &eta0, &u, &om, &[0.0; 4]);
    let rel = |m: &Measure| (m.h_nodal - m.h).norm() / m.h.norm();
    println!(
        "H from p = M x' against the mass points: rigid {:.1e}, deflected {:.1e}",
        rel(&rigid),
        rel(&bent)
    );
    assert!(rel(&rigid) < 1e-12);
    let loose = (1e-8, 1e-6);
    let full = spin_run(&re, &md, Coupling::Full, omega, &eta0, t_end, loose);
    let partial = spin_run(&re, &md, Coupling::Partial, omega, &eta0, t_end, loose);
    let constant = spin_run(&re, &md, Coupling::Constant, omega, &eta0, t_end, loose);
    let tight = (1e-10, 1e-7);
    let full_tight = spin_run(&re, &md, Coupling::Full, omega, &eta0, t_end, tight);
    let constant_tight = spin_run(&re, &md, Coupling::Constant, omega, &eta0, t_end, tight);
    // Only `full` conserves what the FE body conserves. Its energy drift is the
    // integrator's numerical damping of the undamped modes: the constant level, which
    // conserves its own (decoupled) energy exactly, loses the same in its own measure.
    assert!(full.h < 1e-6, "{full:?}");
    assert!(
        full.e < 1.5 * constant.e_own && full.e < 1e-5,
        "{full:?} {constant:?}"
    );
    assert!(full_tight.h < 1e-8 && full_tight.e < 1e-6, "{full_tight:?}");
    assert!(
        full_tight.e < 1.5 * constant_tight.e_own,
        "{constant_tight:?}"
    );
    // The truncated levels violate both by orders of magnitude more (reported above).
    assert!(partial.h > 100.0 * full.h && constant.h > 100.0 * full.h);
}

#[test]
fn at_zero_deformation_full_coupling_has_the_rigid_mass_matrix_and_the_partial_loads() {
    let b = hitch();
    let md = b.modal.selected();
    let omega = [4.0, -7.0, 12.0];
    let full = free_body(&md, omega, Coupling::Full);
    let partial = free_body(&md, omega, Coupling::Partial);
    let (q, mut v) = full.initial_q_v();
    v[0] = 1.5;
    let dense = |s: &System| {
        let mut m = DMatrix::<f64>::zeros(s.nv, s.nv);
        for (r, c, x) in s.mass_entries_at(&q) {
            m[(r, c)] += x;
        }
        m
    };
    let (mf, mp) = (dense(&full), dense(&partial));
    let dm = (&mf - &mp).abs().max() / mp.abs().max();
    let (ff, fp) = (
        full.element_loads(0.0, &q, &v),
        partial.element_loads(0.0, &q, &v),
    );
    let scale = fp.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let df = ff
        .iter()
        .zip(&fp)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()))
        / scale;
    println!(
        "eta = zeta = 0, {} modes: max |M_full - M_rigid| / max |M| = {dm:.1e}, max |f_full - f_partial| / max |f| = {df:.1e}",
        md.modes.len()
    );
    // What is left is I3 and I4 of the kept modes, zero to rounding (mass-orthogonal
    // to the rigid-body modes).
    assert!(dm < 1e-10 && df < 1e-10);
}

/// A free round steel bar, 1 m x 40 mm, along x, interfaces at both ends.
const BAR: &str = r#"
name = "round_bar"
description = "free round bar for the rigid limit"
[[material]]
name = "steel"
youngs_modulus_pa = 2.1e11
poissons_ratio = 0.3
density_kg_m3 = 7850.0
[[section]]
name = "bar"
shape = "round_solid"
diameter_m = 0.04
[[node]]
name = "a"
position_m = [0.0, 0.0, 0.0]
[[node]]
name = "b"
position_m = [1.0, 0.0, 0.0]
[[element]]
node_a = "a"
node_b = "b"
section = "bar"
material = "steel"
local_y = [0.0, 1.0, 0.0]
divisions = 20
[[interface]]
name = "end_a"
node = "a"
[[interface]]
name = "end_b"
node = "b"
[selection]
rule = "all"
"#;

#[test]
fn full_coupling_without_modal_excitation_spins_as_the_rigid_body() {
    let path = std::env::temp_dir().join(format!("towride_round_bar_{}.toml", std::process::id()));
    std::fs::write(&path, BAR).unwrap();
    let b = FlexBody::load(
        &path,
        None,
        &Options::default(),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    std::fs::remove_file(&path).ok();
    // Torsion and symmetric bending modes of a round bar: the frame's rotation puts no
    // centrifugal load on them (symmetric part of I8 zero) and omega' none (I4 zero), so
    // spun with eta = zeta = 0 they stay at rest and the body must move as the rigid body.
    let inv = &b.modal.invariants;
    let sym = |j: usize| {
        let a = inv.i8[j];
        (0..3)
            .flat_map(|r| (0..3).map(move |c| (a[r][c] + a[c][r]).abs()))
            .fold(0.0, f64::max)
    };
    let big = (0..b.modal.modes.len()).map(sym).fold(0.0, f64::max);
    let unloaded: Vec<usize> = (0..b.modal.modes.len())
        .filter(|&j| sym(j) < 1e-9 * big)
        .collect();
    assert!(unloaded.len() >= 2, "{unloaded:?}");
    let md = b.modal.restrict(&unloaded);
    let j0 = md.inertia_com_kg_m2;
    let (ix, it) = (j0[0][0], j0[1][1]);
    assert!((j0[2][2] / it - 1.0).abs() < 1e-12);
    // Spin about a non-principal axis: torque-free precession of the axisymmetric body,
    // omega_x constant, (omega_y + i omega_z) = (w_y0 + i w_z0) exp(i Omega t),
    // Omega = (Ix - It) / It omega_x (Euler's equations).
    let w0 = [20.0, 3.0, -1.0];
    let big_om = (ix - it) / it * w0[0];
    let exact = |t: f64| {
        let (c, s) = ((big_om * t).cos(), (big_om * t).sin());
        [w0[0], w0[1] * c - w0[2] * s, w0[1] * s + w0[2] * c]
    };
    let t_end = 3.0 * 2.0 * std::f64::consts::PI / big_om.abs();
    let nm = md.modes.len();
    let mut traj = Vec::new();
    for coupling in [Coupling::Full, Coupling::Constant] {
        let sys = free_body(&md, w0, coupling);
        let (mut err, mut eta_max) = (0.0f64, 0.0f64);
        let mut w = Vec::new();
        run(
            &sys,
            &vec![0.0; nm],
            t_end,
            t_end / 200.0,
            (1e-10, 1e-7),
            |t, q, v| {
                let e = exact(t);
                for c in 0..3 {
                    err = err.max((v[3 + c] - e[c]).abs() / 20.0);
                }
                for j in 0..nm {
                    eta_max = eta_max.max(q[7 + j].abs());
                }
                w.push([v[3], v[4], v[5]]);
            },
        );
        println!(
            "{coupling:?}, {nm} unloaded modes, {:.3} s ({:.1} precession periods): max |omega - exact| / |omega_x| {err:.2e}, max |eta| {eta_max:.1e}",
            t_end,
            3.0
        );
        // eta stays at the solver's tolerance (it scales with atol: rounding of the
        // coupling terms through the Newton iterations, not a load).
        assert!(err < 1e-8, "{coupling:?}: {err}");
        assert!(eta_max < 1e-12, "{coupling:?}: {eta_max}");
        traj.push(w);
    }
    let d = traj[0]
        .iter()
        .zip(&traj[1])
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
        .fold(0.0, f64::max);
    println!("full against constant: max |omega difference| {d:.2e} rad/s");
    assert!(d < 1e-7);
}
