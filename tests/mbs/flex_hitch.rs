//! The hitch crossbeam (flex/hitch_crossbeam.toml) reduced by Craig-Bampton, checked
//! against the full finite-element model it comes from, and its crossbeam tube against
//! the thesis's mode table.

// Modes, DOFs and directions are indexed in step, as in the library.
#![allow(clippy::needless_range_loop)]

use std::f64::consts::PI;
use std::path::Path;

use faer::Mat;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use towride_mbs::flex::modes::{
    constrained_eigen, count_rigid, frequency_hz, generalized_eigen, static_solution,
};
use towride_mbs::flex::selection::band_amplification;
use towride_mbs::flex::{FlexBody, ModalData, ModeKind, Options, Rule};

const FILE: &str = repo!("flex/hitch_crossbeam.toml");

fn hitch(n_fixed: usize) -> FlexBody {
    FlexBody::load(
        Path::new(FILE),
        None,
        &Options {
            fixed_interface_modes: Some(n_fixed),
            rule: None,
        },
        &crate::load_path_rule(),
    )
    .unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Bracket DOFs of the full model (the interface nodes carry the bolts' spiders).
fn bracket_dofs(b: &FlexBody) -> Vec<usize> {
    ["bracket_left", "bracket_right"]
        .iter()
        .flat_map(|n| b.assembly.dofs(b.mesh.interface(n).unwrap().node))
        .collect()
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0)
}

/// Rows of an interface node's six DOFs in modal-body coordinates
/// (rigid translation, rigid rotation about the body origin, modal coordinates).
pub(super) fn rows(md: &ModalData, name: &str) -> DMatrix<f64> {
    let n = md.node(name).unwrap();
    let nm = md.modes.len();
    let mut g = DMatrix::zeros(6, 6 + nm);
    let sx = skew(&Vector3::from(n.position_m));
    for i in 0..3 {
        g[(i, i)] = 1.0;
        g[(3 + i, 3 + i)] = 1.0;
        for j in 0..3 {
            g[(i, 3 + j)] = -sx[(i, j)];
        }
    }
    for (k, s) in n.shapes.iter().enumerate() {
        for i in 0..6 {
            g[(i, 6 + k)] = s[i];
        }
    }
    g
}

/// Mass and stiffness of a floating-frame modal body linearised about rest, in
/// (a, theta, eta), from the inertia invariants only: kinetic energy
/// 1/2 int rho |a + theta x s + Phi eta'|^2 gives [[I1 1, -~I2, I3], [~I2, I7, I4],
/// [I3^T, I4^T, I6]].
pub(super) fn modal_body_matrices(md: &ModalData) -> (DMatrix<f64>, DMatrix<f64>) {
    let inv = &md.invariants;
    let nm = md.modes.len();
    let n = 6 + nm;
    let mut m = DMatrix::zeros(n, n);
    let s2 = skew(&Vector3::from(inv.i2));
    for i in 0..3 {
        m[(i, i)] = inv.i1;
        for j in 0..3 {
            m[(i, 3 + j)] = -s2[(i, j)];
            m[(3 + i, j)] = s2[(i, j)];
            m[(3 + i, 3 + j)] = inv.i7[i][j];
        }
    }
    for k in 0..nm {
        for i in 0..3 {
            m[(i, 6 + k)] = inv.i3[k][i];
            m[(6 + k, i)] = inv.i3[k][i];
            m[(3 + i, 6 + k)] = inv.i4[k][i];
            m[(6 + k, 3 + i)] = inv.i4[k][i];
        }
        for l in 0..nm {
            m[(6 + k, 6 + l)] = inv.i6[k][l];
        }
    }
    let mut k = DMatrix::zeros(n, n);
    for (j, mode) in md.modes.iter().enumerate() {
        k[(6 + j, 6 + j)] = mode.stiffness;
    }
    (m, k)
}

/// Basis of the null space of c (rows = constraints).
fn null_space(c: &DMatrix<f64>) -> DMatrix<f64> {
    let n = c.ncols();
    let svd = c.clone().svd(false, true);
    let vt = svd.v_t.unwrap();
    let smax = svd.singular_values.max();
    let rank = svd
        .singular_values
        .iter()
        .filter(|&&s| s > 1e-12 * smax)
        .count();
    // Complete the row space to R^n: Gram-Schmidt of unit vectors against it.
    let mut basis: Vec<DVector<f64>> = (0..rank).map(|i| vt.row(i).transpose()).collect();
    let mut out = Vec::new();
    for e in 0..n {
        let mut v = DVector::zeros(n);
        v[e] = 1.0;
        for _ in 0..2 {
            for b in &basis {
                let p = b.dot(&v);
                v -= b * p;
            }
        }
        if v.norm() > 1e-6 {
            let v = v.normalize();
            basis.push(v.clone());
            out.push(v);
        }
    }
    DMatrix::from_columns(&out)
}

#[test]
fn craig_bampton_reproduces_the_free_free_frequencies() {
    let b = hitch(8);
    let full = generalized_eigen(b.assembly.k.as_ref(), b.assembly.m.as_ref()).unwrap();
    let nr = count_rigid(&full.omega2).unwrap();
    assert_eq!(nr, 6);
    let cb: Vec<f64> = b
        .table()
        .iter()
        .filter(|r| r.kind == ModeKind::Elastic)
        .map(|r| r.frequency_hz)
        .collect();
    for k in 0..4 {
        let f_full = frequency_hz(full.omega2[nr + k]);
        println!(
            "elastic mode {}: full FE {f_full:.3} Hz, Craig-Bampton(8) {:.3} Hz, error {:.2e}",
            k + 1,
            cb[k],
            rel(cb[k], f_full)
        );
        assert!(rel(cb[k], f_full) < 5e-3, "mode {k}: {} vs {f_full}", cb[k]);
    }
    assert_eq!(
        b.table()
            .iter()
            .filter(|r| r.kind == ModeKind::Rigid)
            .count(),
        6
    );
}

#[test]
fn orthonormalised_modes_have_unit_mass_and_rigid_modes_are_orthogonal() {
    let b = hitch(8);
    let y = &b.cb.modes;
    let p = y.transpose() * &b.assembly.m * y;
    let mut worst_diag: f64 = 0.0;
    let mut worst_rigid_elastic: f64 = 0.0;
    for i in 0..p.nrows() {
        for j in 0..p.ncols() {
            let want = if i == j { 1.0 } else { 0.0 };
            worst_diag = worst_diag.max((p[(i, j)] - want).abs());
            if (b.cb.kinds[i] == ModeKind::Rigid) != (b.cb.kinds[j] == ModeKind::Rigid) {
                worst_rigid_elastic = worst_rigid_elastic.max(p[(i, j)].abs());
            }
        }
    }
    println!("max |Y^T M Y - I| = {worst_diag:.2e}, max |Y_r^T M Y_e| = {worst_rigid_elastic:.2e}");
    assert!(worst_diag < 1e-10);
    assert!(worst_rigid_elastic < 1e-10);
    // Stiffness diagonal: Y^T K Y = diag(omega^2).
    let kk = y.transpose() * &b.assembly.k * y;
    let scale = b.cb.omega2.last().unwrap();
    for i in 0..kk.nrows() {
        for j in 0..kk.ncols() {
            let want = if i == j { b.cb.omega2[i] } else { 0.0 };
            assert!((kk[(i, j)] - want).abs() < 1e-9 * scale);
        }
    }
}

/// Ball deflection of the modal body `md` held at its brackets under `load` along `d`.
fn held_ball_deflection(md: &ModalData, d: usize, load: f64) -> DVector<f64> {
    let (_, k) = modal_body_matrices(md);
    let c = DMatrix::from_rows(
        &[rows(md, "bracket_left"), rows(md, "bracket_right")]
            .iter()
            .flat_map(|g| g.row_iter().map(|r| r.into_owned()).collect::<Vec<_>>())
            .collect::<Vec<_>>(),
    );
    let gb = rows(md, "ball");
    let nz = k.nrows();
    let nc = c.nrows();
    let mut a = DMatrix::zeros(nz + nc, nz + nc);
    a.view_mut((0, 0), (nz, nz)).copy_from(&k);
    a.view_mut((nz, 0), (nc, nz)).copy_from(&c);
    a.view_mut((0, nz), (nz, nc)).copy_from(&c.transpose());
    let mut rhs = DVector::zeros(nz + nc);
    rhs.rows_mut(0, nz)
        .copy_from(&(gb.row(d).transpose() * load));
    let z = a.lu().solve(&rhs).unwrap();
    (&gb * z.rows(0, nz)).rows(0, 3).into_owned()
}

#[test]
fn modal_hitch_held_at_brackets_deflects_as_the_full_model() {
    let b = hitch(8);
    let held = bracket_dofs(&b);
    let ball = b.assembly.dofs(b.mesh.interface("ball").unwrap().node);
    let kept = b.modal.selected();
    for (d, load) in [(0, 1000.0), (1, 1000.0), (2, -1000.0)] {
        let mut f = vec![0.0; b.assembly.n_dof];
        f[ball[d]] = load;
        let u = static_solution(b.assembly.k.as_ref(), &held, &f).unwrap();
        let want = Vector3::new(u[ball[0]], u[ball[1]], u[ball[2]]);
        // All modes of the reduced basis: exact up to rounding (constraint modes).
        let all = held_ball_deflection(&b.modal, d, load);
        // The modes the load-path rule keeps.
        let sel = held_ball_deflection(&kept, d, load);
        println!(
            "ball load {load} N along {d}: full FE {:.6e} m, modal (all {} modes) {:.6e} m, modal (selected {}) {:.6e} m ({:+.2} %)",
            want[d], b.modal.modes.len(), all[d], kept.modes.len(), sel[d], 100.0 * (sel[d] / want[d] - 1.0)
        );
        assert!(rel(all[d], want[d]) < 1e-2);
        assert!((all - want).norm() < 1e-2 * want.norm());
        assert!(rel(sel[d], want[d]) < 2e-2);
    }
}

#[test]
fn modal_hitch_held_at_brackets_has_the_full_models_first_frequency() {
    let b = hitch(8);
    let md = &b.modal;
    let full = constrained_eigen(
        b.assembly.k.as_ref(),
        b.assembly.m.as_ref(),
        &bracket_dofs(&b),
    )
    .unwrap();
    let f_full = frequency_hz(full.omega2[0]);
    let (m, k) = modal_body_matrices(md);
    let c = DMatrix::from_rows(
        &[rows(md, "bracket_left"), rows(md, "bracket_right")]
            .iter()
            .flat_map(|g| g.row_iter().map(|r| r.into_owned()).collect::<Vec<_>>())
            .collect::<Vec<_>>(),
    );
    let z = null_space(&c);
    let mc = z.transpose() * &m * &z;
    let kc = z.transpose() * &k * &z;
    // Generalised eigenproblem by Cholesky of the (positive definite) mass.
    let l = mc.cholesky().unwrap().l();
    let li = l.clone().try_inverse().unwrap();
    let a = &li * kc * li.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let mut ev: Vec<f64> = a.symmetric_eigen().eigenvalues.iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    let f_red = ev[0].sqrt() / (2.0 * PI);
    println!("held at the brackets: first frequency full FE {f_full:.3} Hz, modal body {f_red:.3} Hz, error {:.2e}", rel(f_red, f_full));
    assert!(rel(f_red, f_full) < 5e-3);
}

#[test]
fn invariants_match_the_mass_matrix_and_a_lumped_computation() {
    let b = hitch(8);
    let md = &b.modal;
    let inv = &md.invariants;
    // Mass and first moment from the FE mass matrix and rigid-body vectors.
    let (m, c) = towride_mbs::flex::craig_bampton::mass_and_centre(&b.assembly);
    assert!(rel(inv.i1, m) < 1e-12);
    for i in 0..3 {
        assert!((md.com_m[i] - c[i]).abs() < 1e-12);
    }
    // I7 = R_r^T M R_r (rotations about the origin).
    let r = b.assembly.rigid_body_vectors(&Vector3::zeros());
    let g = r.transpose() * &b.assembly.m * &r;
    for i in 0..3 {
        for j in 0..3 {
            assert!((inv.i7[i][j] - g[(3 + i, 3 + j)]).abs() < 1e-12 * g[(3, 3)]);
        }
    }
    // Modal mass identity; first-order coupling vanishes for mean-axis modes.
    let n = inv.i6.len();
    for j in 0..n {
        for k in 0..n {
            let want = if j == k { 1.0 } else { 0.0 };
            assert!((inv.i6[j][k] - want).abs() < 1e-10);
        }
        for i in 0..3 {
            assert!(inv.i3[j][i].abs() < 1e-9 && inv.i4[j][i].abs() < 1e-9);
        }
    }
    // I5, I6 and I9 of the second-order tensor Q_jk = sum over the quadrature points
    // of m u_j u_k^T + ~th_j D ~th_k^T, summed here point by point from the definition
    // (the library forms it as matrix products).
    let every: Vec<Vec<[f64; 6]>> = (0..n)
        .map(|j| b.assembly.expand(|d| b.cb.modes[(d, 6 + j)]))
        .collect();
    let points = b.mesh.mass_points();
    for (j, k) in [(0, 0), (0, 3), (5, 2), (n - 1, n - 2), (n - 1, n - 1)] {
        let mut qjk = Matrix3::zeros();
        for (nodes, mp) in &points {
            let qe = |m: usize| {
                nalgebra::SVector::<f64, 12>::from_fn(|i, _| every[m][nodes[i / 6]][i % 6])
            };
            let (uj, uk) = (mp.nu * qe(j), mp.nu * qe(k));
            let (tj, tk) = (skew(&(mp.nt * qe(j))), skew(&(mp.nt * qe(k))));
            qjk += uj * uk.transpose() * mp.mass_kg + tj * mp.second_moment * tk.transpose();
        }
        let scale = qjk.norm().max(1e-3);
        let i9 = qjk.transpose() - Matrix3::identity() * qjk.trace();
        let mine = Matrix3::from_fn(|r, c| inv.i9[j][k][r][c]);
        assert!((mine - i9).norm() < 1e-12 * scale, "I9 {j} {k}");
        assert!(
            (inv.i6[j][k] - qjk.trace()).abs() < 1e-12 * scale,
            "I6 {j} {k}"
        );
        let i5 = Vector3::new(
            qjk[(1, 2)] - qjk[(2, 1)],
            qjk[(2, 0)] - qjk[(0, 2)],
            qjk[(0, 1)] - qjk[(1, 0)],
        );
        assert!(
            (Vector3::from(inv.i5[j][k]) - i5).norm() < 1e-12 * scale,
            "I5 {j} {k}"
        );
    }
    // I5, I8, I9 against MBDyn's lumped-mass formulas (struct/modal.cc): element masses
    // lumped half to each node, section rotary inertia left out as MBDyn does for these
    // terms. Both simplifications cost a few per cent (measured 0.5-4 % on the three
    // lowest modes); a sign or convention error would cost 100 % or more.
    let mesh = &b.mesh;
    let shapes: Vec<Vec<[f64; 6]>> = (0..3)
        .map(|j| {
            let k = 6 + j;
            b.assembly.expand(|d| b.cb.modes[(d, k)])
        })
        .collect();
    let mut lumped = vec![0.0; mesh.nodes.len()];
    for e in &mesh.elements {
        let me = e.beam.density_kg_m3 * e.beam.section.area_m2 * e.beam.length_m;
        lumped[e.nodes[0]] += 0.5 * me;
        lumped[e.nodes[1]] += 0.5 * me;
    }
    for p in &mesh.point_masses {
        lumped[p.node] += p.mass_kg;
    }
    let t = |j: usize, n: usize| Vector3::new(shapes[j][n][0], shapes[j][n][1], shapes[j][n][2]);
    for j in 0..3 {
        let mut i8 = Matrix3::zeros();
        for (n, &mi) in lumped.iter().enumerate() {
            i8 -= skew(&mesh.nodes[n].position) * skew(&t(j, n)) * mi;
        }
        let mine = Matrix3::from_fn(|r, c| inv.i8[j][r][c]);
        let err = (mine - i8).norm() / i8.norm();
        println!("I8 mode {}: relative difference to lumped {err:.2e}", j + 7);
        assert!(err < 5e-2);
        for k in 0..3 {
            let mut i9 = Matrix3::zeros();
            let mut i5 = Vector3::zeros();
            for (n, &mi) in lumped.iter().enumerate() {
                i9 += skew(&t(j, n)) * skew(&t(k, n)) * mi;
                i5 += skew(&t(j, n)) * t(k, n) * mi;
            }
            let mine = Matrix3::from_fn(|r, c| inv.i9[j][k][r][c]);
            let err = (mine - i9).norm() / i9.norm();
            assert!(err < 5e-2, "I9 {j} {k}: {err}");
            let mine5 = Vector3::from(inv.i5[j][k]);
            // I5_jj = 0 by antisymmetry; compare the others against the I9 scale.
            assert!((mine5 - i5).norm() < 5e-2 * i9.norm(), "I5 {j} {k}");
        }
    }
}

#[test]
fn load_path_selection_agrees_with_the_full_model_and_keeps_the_low_modes() {
    let b = hitch(8);
    let Rule::LoadPath(lp) = &b.rule else {
        panic!("the hitch file selects by load paths");
    };
    assert_eq!(lp.band_hz, [0.0, 100.0]);
    // Independent reference: full FE static responses to unit ball forces, brackets
    // held, projected on the full model's free-free modes.
    let asm = &b.assembly;
    let full = generalized_eigen(asm.k.as_ref(), asm.m.as_ref()).unwrap();
    let held = bracket_dofs(&b);
    let ball = asm.dofs(b.mesh.interface("ball").unwrap().node);
    let nf = full.omega2.len();
    let mut full_share = vec![0.0f64; nf];
    for d in 0..3 {
        let mut f = vec![0.0; asm.n_dof];
        f[ball[d]] = 1.0;
        let u = static_solution(asm.k.as_ref(), &held, &f).unwrap();
        let um = Mat::from_fn(asm.n_dof, 1, |i, _| u[i]);
        let eta = full.vectors.transpose() * &asm.m * &um;
        let e: Vec<f64> = (0..nf)
            .map(|k| {
                if k < 6 {
                    return 0.0;
                }
                let fk = frequency_hz(full.omega2[k]);
                let a = band_amplification(fk, b.mesh.damping.ratio(k + 1, fk), lp.band_hz);
                (a * full.omega2[k] * eta[(k, 0)]).powi(2) / full.omega2[k]
            })
            .collect();
        let tot: f64 = e.iter().sum();
        for k in 0..nf {
            full_share[k] = full_share[k].max(e[k] / tot);
        }
    }
    let share = b.selection.max_share.as_ref().unwrap();
    // Modes the reduction reproduces (frequency within 0.5 %) must get the same share.
    let mut compared = 0;
    for (j, m) in b.modal.modes.iter().enumerate() {
        let k = m.number - 1;
        let f_full = frequency_hz(full.omega2[k]);
        if rel(m.frequency_hz, f_full) > 5e-3 {
            continue;
        }
        compared += 1;
        println!(
            "mode {}: {:.1} Hz, share reduced {:.4}, full {:.4}, selected {}",
            m.number, m.frequency_hz, share[j], full_share[k], m.selected
        );
        assert!(
            (share[j] - full_share[k]).abs() < 2e-3 + 0.02 * full_share[k],
            "mode {}",
            m.number
        );
        if (full_share[k] - lp.min_energy_share).abs() > 2e-3 {
            assert_eq!(
                m.selected,
                full_share[k] >= lp.min_energy_share,
                "mode {}",
                m.number
            );
        }
    }
    assert!(compared >= 6);
    // The low modes that carry the ball's load path are kept; the kHz-range modes
    // that store no energy of it are dropped.
    for m in &b.modal.modes {
        let k = m.number - 1;
        if m.frequency_hz < 500.0 && full_share[k] > 0.05 {
            assert!(
                m.selected,
                "mode {} ({:.0} Hz) carries {:.1} %",
                m.number,
                m.frequency_hz,
                100.0 * full_share[k]
            );
        }
    }
    let top = b.modal.modes.last().unwrap();
    assert!(top.frequency_hz > 4000.0 && !top.selected);
}

#[test]
fn every_variant_builds_and_variant_5_is_the_base() {
    let base = hitch(8);
    for v in 1..=10 {
        let b = FlexBody::load(
            Path::new(FILE),
            Some(v),
            &Options::default(),
            &towride_mbs::input::Loader::new(),
        )
        .unwrap();
        let f: Vec<f64> = b
            .table()
            .iter()
            .filter(|r| r.kind == ModeKind::Elastic)
            .take(4)
            .map(|r| r.frequency_hz)
            .collect();
        println!(
            "variant {v:>2} ({}): mass {:.2} kg, first elastic modes {:.1} {:.1} {:.1} {:.1} Hz",
            b.mesh.variant.as_ref().unwrap().description,
            b.modal.mass_kg,
            f[0],
            f[1],
            f[2],
            f[3]
        );
        if v == 5 {
            for (r, s) in b.table().iter().zip(&base.table()) {
                assert_eq!(r.frequency_hz, s.frequency_hz);
            }
        }
    }
}

/// The thesis's Fig. 5.20 table is a crossbeam body of 24 modes (6 rigid + 18): three
/// interface nodes (two brackets and the hook seat, 18 constraint modes) plus six
/// fixed-interface modes. The tube of variant 5 between the bracket roots, reduced the
/// same way, reproduces its first four elastic modes.
#[test]
fn variant_5_crossbeam_tube_reproduces_the_thesis_mode_table() {
    let mesh =
        towride_mbs::flex::Mesh::read(Path::new(FILE), Some(5), &towride_mbs::input::Loader::new())
            .unwrap();
    let sec = &mesh
        .sections
        .iter()
        .find(|(n, _)| n == "crossbeam")
        .unwrap()
        .1;
    let towride_mbs::flex::section::Section::RectangularHollow {
        width_m,
        height_m,
        wall_m,
    } = *sec
    else {
        panic!("crossbeam is a rectangular tube");
    };
    let pos = |n: &str| mesh.nodes[mesh.node_index(n).unwrap()].position;
    let (r, l) = (pos("cb_right"), pos("cb_left"));
    let text = format!(
        r#"name = "crossbeam tube"
fixed_interface_modes = 6
[[material]]
name = "steel"
youngs_modulus_pa = 2.1e11
poissons_ratio = 0.3
density_kg_m3 = 7850.0
[[section]]
name = "tube"
shape = "rectangular_hollow"
width_m = {width_m}
height_m = {height_m}
wall_m = {wall_m}
[[node]]
name = "r"
position_m = [{}, {}, {}]
[[node]]
name = "m"
position_m = [{}, {}, {}]
[[node]]
name = "l"
position_m = [{}, {}, {}]
[[element]]
node_a = "r"
node_b = "m"
section = "tube"
material = "steel"
local_y = [1.0, 0.0, 0.0]
divisions = 10
[[element]]
node_a = "m"
node_b = "l"
section = "tube"
material = "steel"
local_y = [1.0, 0.0, 0.0]
divisions = 10
[[interface]]
name = "r"
node = "r"
[[interface]]
name = "l"
node = "l"
[[interface]]
name = "hook_seat"
node = "m"
"#,
        r[0],
        r[1],
        r[2],
        0.5 * (r[0] + l[0]),
        0.0,
        r[2],
        l[0],
        l[1],
        l[2]
    );
    let src = towride_mbs::input::Source::from_text(Path::new("tube.toml"), text).unwrap();
    let tube = towride_mbs::flex::Mesh::from_source(&src, None).unwrap();
    let body = FlexBody::from_mesh(tube, &Options::default()).unwrap();
    assert_eq!(body.table().len(), 24);
    let thesis = [317.0, 436.1, 837.8, 1155.6];
    let f: Vec<f64> = body
        .table()
        .iter()
        .filter(|r| r.kind == ModeKind::Elastic)
        .map(|r| r.frequency_hz)
        .collect();
    for k in 0..4 {
        println!(
            "crossbeam tube mode {}: {:.1} Hz, thesis {:.1} Hz, difference {:+.2} %",
            k + 7,
            f[k],
            thesis[k],
            100.0 * (f[k] / thesis[k] - 1.0)
        );
        assert!(rel(f[k], thesis[k]) < 1e-2);
    }
}
