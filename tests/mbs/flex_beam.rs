//! Uniform beams meshed with 20 elements against beam theory: Euler-Bernoulli bending
//! (clamped-free and free-free), Saint-Venant torsion, axial waves, and Timoshenko's
//! simply supported beam.

// Modes, DOFs and directions are indexed in step, as in the library.
#![allow(clippy::needless_range_loop)]

use std::f64::consts::PI;
use std::path::Path;

use faer::Mat;
use towride_mbs::flex::modes::{constrained_eigen, frequency_hz, generalized_eigen, Eigen};
use towride_mbs::flex::{Assembly, Mesh};
use towride_mbs::input::Source;

const E: f64 = 210e9;
const NU: f64 = 0.3;
const RHO: f64 = 7850.0;

/// A straight bar along x, `n` elements, solid rectangle `b` (local y = global y) by `h`.
fn bar(l: f64, b: f64, h: f64, n: usize, shear: bool) -> Mesh {
    let text = format!(
        r#"
name = "bar"
shear_deformation = {shear}
[[material]]
name = "steel"
youngs_modulus_pa = {E}
poissons_ratio = {NU}
density_kg_m3 = {RHO}
[[section]]
name = "bar"
shape = "rectangular_solid"
width_m = {b}
height_m = {h}
[[node]]
name = "root"
position_m = [0.0, 0.0, 0.0]
[[node]]
name = "tip"
position_m = [{l}, 0.0, 0.0]
[[element]]
node_a = "root"
node_b = "tip"
section = "bar"
material = "steel"
local_y = [0.0, 1.0, 0.0]
divisions = {n}
"#
    );
    let src = Source::from_text(Path::new("bar.toml"), text).unwrap();
    Mesh::from_source(&src, None).unwrap()
}

/// Which motion dominates a mode, by kinetic energy phi_i (M phi)_i per DOF type:
/// 0 axial, 1 bending in x-y (v, theta_z), 2 bending in x-z (w, theta_y), 3 torsion.
fn family(m: &Mat<f64>, e: &Eigen, k: usize) -> usize {
    let n = m.nrows();
    let v = Mat::from_fn(n, 1, |i, _| e.vectors[(i, k)]);
    let mv = m * &v;
    let mut en = [0.0; 4];
    for i in 0..n {
        let t = match i % 6 {
            0 => 0,
            1 | 5 => 1,
            2 | 4 => 2,
            _ => 3,
        };
        en[t] += v[(i, 0)] * mv[(i, 0)];
    }
    (0..4).max_by(|&a, &b| en[a].total_cmp(&en[b])).unwrap()
}

/// Frequencies of family `fam`, ascending, skipping rigid-body modes.
fn family_frequencies(m: &Mat<f64>, e: &Eigen, fam: usize) -> Vec<f64> {
    (0..e.omega2.len())
        .filter(|&k| frequency_hz(e.omega2[k]) > 1e-3 && family(m, e, k) == fam)
        .map(|k| frequency_hz(e.omega2[k]))
        .collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b
}

fn euler_bernoulli(beta_l: f64, l: f64, ei: f64, rho_a: f64) -> f64 {
    beta_l * beta_l / (2.0 * PI * l * l) * (ei / rho_a).sqrt()
}

struct Bar {
    l: f64,
    b: f64,
    h: f64,
}

const BAR: Bar = Bar {
    l: 2.0,
    b: 0.02,
    h: 0.01,
};

#[test]
fn cantilever_matches_euler_bernoulli_torsion_and_axial_theory() {
    let mesh = bar(BAR.l, BAR.b, BAR.h, 20, false);
    let asm = Assembly::new(&mesh);
    let root = asm.dofs(mesh.node_index("root").unwrap());
    let e = constrained_eigen(asm.k.as_ref(), asm.m.as_ref(), &root).unwrap();
    let a = BAR.b * BAR.h;
    let iz = BAR.h * BAR.b.powi(3) / 12.0;
    let iy = BAR.b * BAR.h.powi(3) / 12.0;
    let beta = [1.875104068711961, 4.694091132974174, 7.854757438237613];
    for (fam, i) in [(1, iz), (2, iy)] {
        let f = family_frequencies(&asm.m, &e, fam);
        for n in 0..3 {
            let want = euler_bernoulli(beta[n], BAR.l, E * i, RHO * a);
            assert!(
                rel(f[n], want) < 2e-3,
                "plane {fam} mode {n}: {} vs {want}",
                f[n]
            );
            println!(
                "clamped-free plane {fam} mode {}: {:.4} Hz, theory {want:.4}, error {:.2e}",
                n + 1,
                f[n],
                rel(f[n], want)
            );
        }
    }
    // Torsion theta'' = (rho Ip / G J) theta_tt, clamped-free: f = c / (4 L).
    let p = mesh.sections[0].1.properties(NU);
    let g = E / (2.0 * (1.0 + NU));
    let c_t = (g * p.torsion_constant_m4 / (RHO * (p.iy_m4 + p.iz_m4))).sqrt();
    let f_t = family_frequencies(&asm.m, &e, 3)[0];
    assert!(rel(f_t, c_t / (4.0 * BAR.l)) < 2e-3, "torsion {f_t}");
    let f_a = family_frequencies(&asm.m, &e, 0)[0];
    let want = (E / RHO).sqrt() / (4.0 * BAR.l);
    assert!(rel(f_a, want) < 2e-3, "axial {f_a} vs {want}");
    println!(
        "clamped-free torsion {f_t:.3} (error {:.2e}), axial {f_a:.3} (error {:.2e})",
        rel(f_t, c_t / (4.0 * BAR.l)),
        rel(f_a, want)
    );
}

#[test]
fn free_free_bar_matches_euler_bernoulli_torsion_and_axial_theory() {
    let mesh = bar(BAR.l, BAR.b, BAR.h, 20, false);
    let asm = Assembly::new(&mesh);
    let e = generalized_eigen(asm.k.as_ref(), asm.m.as_ref()).unwrap();
    // Six rigid-body modes at rounding level.
    let f7 = frequency_hz(e.omega2[6]);
    for k in 0..6 {
        assert!(frequency_hz(e.omega2[k]).abs() < 1e-4 * f7);
    }
    let a = BAR.b * BAR.h;
    let iz = BAR.h * BAR.b.powi(3) / 12.0;
    let iy = BAR.b * BAR.h.powi(3) / 12.0;
    let beta = [4.730040744862704, 7.853204624095838, 10.99560783800167];
    for (fam, i) in [(1, iz), (2, iy)] {
        let f = family_frequencies(&asm.m, &e, fam);
        for n in 0..3 {
            let want = euler_bernoulli(beta[n], BAR.l, E * i, RHO * a);
            assert!(
                rel(f[n], want) < 2e-3,
                "plane {fam} mode {n}: {} vs {want}",
                f[n]
            );
            println!(
                "free-free plane {fam} mode {}: {:.4} Hz, theory {want:.4}, error {:.2e}",
                n + 1,
                f[n],
                rel(f[n], want)
            );
        }
    }
    let p = mesh.sections[0].1.properties(NU);
    let g = E / (2.0 * (1.0 + NU));
    let c_t = (g * p.torsion_constant_m4 / (RHO * (p.iy_m4 + p.iz_m4))).sqrt();
    let f_t = family_frequencies(&asm.m, &e, 3)[0];
    assert!(rel(f_t, c_t / (2.0 * BAR.l)) < 2e-3, "torsion {f_t}");
    let f_a = family_frequencies(&asm.m, &e, 0)[0];
    let want = (E / RHO).sqrt() / (2.0 * BAR.l);
    assert!(rel(f_a, want) < 2e-3, "axial {f_a} vs {want}");
    println!(
        "free-free torsion {f_t:.3} (error {:.2e}), axial {f_a:.3} (error {:.2e})",
        rel(f_t, c_t / (2.0 * BAR.l)),
        rel(f_a, want)
    );
}

#[test]
fn stubby_simply_supported_beam_matches_timoshenko_theory() {
    // L/h = 10: shear and rotary inertia lower the frequencies by several per cent.
    let (l, b, h) = (0.6, 0.06, 0.04);
    let mesh = bar(l, b, h, 20, true);
    let asm = Assembly::new(&mesh);
    let root = asm.dofs(mesh.node_index("root").unwrap());
    let tip = asm.dofs(mesh.node_index("tip").unwrap());
    // Pins: both ends held in y and z; axial motion and twist held at the root.
    let fixed = [root[0], root[1], root[2], root[3], tip[1], tip[2]];
    let e = constrained_eigen(asm.k.as_ref(), asm.m.as_ref(), &fixed).unwrap();
    let p = mesh.sections[0].1.properties(NU);
    let g = E / (2.0 * (1.0 + NU));
    // Bending in x-y: I = Iz, shear area A_sy. Timoshenko's equations with
    // w = W sin(kx), psi = Psi cos(kx) give
    // rho A rho I l^2 - (rho A (E I k^2 + kGA) + kGA k^2 rho I) l + kGA E I k^4 = 0.
    let (ra, ri, ei, kga) = (
        RHO * p.area_m2,
        RHO * p.iz_m4,
        E * p.iz_m4,
        g * p.shear_area_y_m2.unwrap(),
    );
    let f = family_frequencies(&asm.m, &e, 1);
    for n in 1..=3 {
        let k = n as f64 * PI / l;
        let qa = ra * ri;
        let qb = -(ra * (ei * k * k + kga) + kga * k * k * ri);
        let qc = kga * ei * k.powi(4);
        let lam = (-qb - (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa);
        let want = lam.sqrt() / (2.0 * PI);
        let eb = (k * k) * (ei / ra).sqrt() / (2.0 * PI);
        println!("Timoshenko SS mode {n}: {:.3} Hz, theory {want:.3} (Euler-Bernoulli {eb:.3}), error {:.2e}", f[n - 1], rel(f[n - 1], want));
        assert!(
            rel(f[n - 1], want) < 2e-3,
            "mode {n}: {} vs {want}",
            f[n - 1]
        );
        // The effect is real: Euler-Bernoulli would be off by more than 1 %.
        assert!(eb > 1.01 * want);
    }
}

/// The words a mode is named by (`flex::character`) follow its strain energy: on the
/// free-free bar along x the bending modes in the x-y and x-z planes are "lateral" and
/// "vertical bending", the twisting ones "torsion about x", the stretching one "axial
/// along x", each with over 99 % of the strain energy, and the first mode named torsion
/// and the first named axial sit at Saint-Venant's and the axial-wave frequency.
#[test]
fn modes_are_named_by_their_strain_energy() {
    use towride_mbs::flex::character::character;
    let mesh = bar(BAR.l, BAR.b, BAR.h, 20, false);
    let asm = Assembly::new(&mesh);
    let e = generalized_eigen(asm.k.as_ref(), asm.m.as_ref()).unwrap();
    let want = [
        "axial along x, bar",
        "lateral bending, bar",
        "vertical bending, bar",
        "torsion about x, bar",
    ];
    let (mut torsion, mut axial) = (None, None);
    // Every mode up to just above the first axial one (1293 Hz).
    let up_to = 1.1 * (E / RHO).sqrt() / (2.0 * BAR.l);
    for k in (6..e.omega2.len()).filter(|&k| frequency_hz(e.omega2[k]) < up_to) {
        let shape = asm.expand(|d| e.vectors[(d, k)]);
        let (name, share) = character(&mesh, &shape);
        assert_eq!(name, want[family(&asm.m, &e, k)], "mode {k}");
        assert!(share > 0.99, "mode {k}: {share}");
        let f = frequency_hz(e.omega2[k]);
        if name.starts_with("torsion") && torsion.is_none() {
            torsion = Some(f);
        }
        if name.starts_with("axial") && axial.is_none() {
            axial = Some(f);
        }
    }
    let p = mesh.sections[0].1.properties(NU);
    let g = E / (2.0 * (1.0 + NU));
    let c_t = (g * p.torsion_constant_m4 / (RHO * (p.iy_m4 + p.iz_m4))).sqrt();
    assert!(rel(torsion.unwrap(), c_t / (2.0 * BAR.l)) < 2e-3);
    assert!(rel(axial.unwrap(), (E / RHO).sqrt() / (2.0 * BAR.l)) < 2e-3);
}
