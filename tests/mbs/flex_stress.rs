//! Nominal stress recovery (`flex::stress`): a cantilever tube against the beam-theory
//! formulas, the hitch's stress points from the modal basis against the full FE model
//! under a static ball load, and the hook root against statics.

#![allow(clippy::needless_range_loop)]

use std::path::Path;

use nalgebra::{DMatrix, DVector, Vector3};
use towride_mbs::flex::modes::static_solution;
use towride_mbs::flex::stress::{point_forces, StressModes};
use towride_mbs::flex::{FlexBody, ModalData, Options, Rule};
use towride_mbs::input::Source;

use super::flex_hitch::{modal_body_matrices, rows};

const FILE: &str = repo!("flex/hitch_crossbeam.toml");

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A cantilever tube along x (b along y, h along z, wall t), root at x = 0, stress point
/// at the root.
fn tube(l: f64, b: f64, h: f64, t: f64) -> FlexBody {
    let text = format!(
        r#"
name = "tube"
[[material]]
name = "steel"
youngs_modulus_pa = 2.1e11
poissons_ratio = 0.3
density_kg_m3 = 7850.0
[[section]]
name = "tube"
shape = "rectangular_hollow"
width_m = {b}
height_m = {h}
wall_m = {t}
[[node]]
name = "root"
position_m = [0.0, 0.0, 0.0]
[[node]]
name = "tip"
position_m = [{l}, 0.0, 0.0]
[[element]]
node_a = "root"
node_b = "tip"
section = "tube"
material = "steel"
local_y = [0.0, 1.0, 0.0]
divisions = 12
[[interface]]
name = "root"
node = "root"
[[interface]]
name = "tip"
node = "tip"
[[stress_point]]
name = "root"
node_a = "tip"
node_b = "root"
at_fraction = 1.0
"#
    );
    let src = Source::from_text(Path::new("tube.toml"), text).unwrap();
    let mesh = towride_mbs::flex::Mesh::from_source(&src, None).unwrap();
    FlexBody::from_mesh(mesh, &Options::default()).unwrap()
}

#[test]
fn cantilever_tube_root_stresses_match_beam_theory() {
    let (l, b, h, t) = (0.8, 0.072, 0.048, 0.004);
    let body = tube(l, b, h, t);
    let root = body.mesh.node_index("root").unwrap();
    let tip = body.assembly.dofs(body.mesh.node_index("tip").unwrap());
    // Hand section properties (thin-wall-free, exact for the sharp-cornered tube).
    let (bi, hi) = (b - 2.0 * t, h - 2.0 * t);
    let area = b * h - bi * hi;
    let iy = (b * h.powi(3) - bi * hi.powi(3)) / 12.0;
    let iz = (h * b.powi(3) - hi * bi.powi(3)) / 12.0;
    let wt = 2.0 * (b - t) * (h - t) * t; // Bredt
    let (pz, py, n, tq) = (-1500.0, 700.0, 20e3, 300.0);
    let mut f = vec![0.0; body.assembly.n_dof];
    f[tip[2]] = pz;
    f[tip[1]] = py;
    f[tip[0]] = n;
    f[tip[3]] = tq;
    let u = static_solution(body.assembly.k.as_ref(), &body.assembly.dofs(root), &f).unwrap();
    let nodes = body.assembly.expand(|d| u[d]);
    let forces = point_forces(&body.mesh.elements, &body.mesh.stress_points, &nodes);
    let s = body.mesh.stress_points[0].fibres.stresses(&forces[0]);
    // Root moments of a tip load on a cantilever: |M| = P L (statically determinate, so
    // shear deformation does not change them).
    let want_max = n / area + (pz.abs() * l) / (iy / (0.5 * h)) + (py.abs() * l) / (iz / (0.5 * b));
    let want_min = n / area - (pz.abs() * l) / (iy / (0.5 * h)) - (py.abs() * l) / (iz / (0.5 * b));
    let want_tau = tq / wt;
    println!(
        "root: sx_max {:.4e} (hand {want_max:.4e}), sx_min {:.4e} (hand {want_min:.4e}), tau {:.4e} (hand {want_tau:.4e}) Pa",
        s.sx_max, s.sx_min, s.tau
    );
    assert!(rel(s.sx_max, want_max) < 1e-2);
    assert!(rel(s.sx_min, want_min) < 1e-2);
    assert!(rel(s.tau, want_tau) < 1e-2);
    let mises = (want_max.powi(2) + 3.0 * want_tau.powi(2)).sqrt();
    assert!(rel(s.eq, mises) < 1e-2);
}

fn hitch(rule: Option<Rule>) -> FlexBody {
    let options = Options {
        fixed_interface_modes: None,
        rule,
    };
    FlexBody::load(
        Path::new(FILE),
        None,
        &options,
        &towride_mbs::input::Loader::new(),
    )
    .unwrap()
}

/// Modal coordinates of the modal body `md` held at its brackets under `load` (6
/// components, force and moment) at the ball: the floating-frame body's own statics.
fn held_eta(md: &ModalData, load: &[f64; 6]) -> Vec<f64> {
    let (_, k) = modal_body_matrices(md);
    let c = DMatrix::from_rows(
        &[rows(md, "bracket_left"), rows(md, "bracket_right")]
            .iter()
            .flat_map(|g| g.row_iter().map(|r| r.into_owned()).collect::<Vec<_>>())
            .collect::<Vec<_>>(),
    );
    let gb = rows(md, "ball");
    let (nz, nc) = (k.nrows(), c.nrows());
    let mut a = DMatrix::zeros(nz + nc, nz + nc);
    a.view_mut((0, 0), (nz, nz)).copy_from(&k);
    a.view_mut((nz, 0), (nc, nz)).copy_from(&c);
    a.view_mut((0, nz), (nz, nc)).copy_from(&c.transpose());
    let mut rhs = DVector::zeros(nz + nc);
    rhs.rows_mut(0, nz)
        .copy_from(&(gb.transpose() * DVector::from_row_slice(load)));
    let z = a.lu().solve(&rhs).unwrap();
    z.rows(6, nz - 6).iter().copied().collect()
}

#[test]
fn hitch_stress_points_from_modes_match_the_full_fe_model() {
    let body = hitch(None);
    let stress = StressModes::build(&body.mesh, &body.assembly, &body.cb);
    assert_eq!(stress.points.len(), 4);
    let held: Vec<usize> = ["bracket_left", "bracket_right"]
        .iter()
        .flat_map(|n| body.assembly.dofs(body.mesh.interface(n).unwrap().node))
        .collect();
    let ball_node = body.mesh.interface("ball").unwrap().node;
    let ball = body.assembly.dofs(ball_node);
    // A trailer nose load (down) and a braking push (forward) at the ball.
    let load = [2000.0, 0.0, -750.0, 0.0, 0.0, 0.0];
    let mut f = vec![0.0; body.assembly.n_dof];
    for d in 0..3 {
        f[ball[d]] = load[d];
    }
    let u = static_solution(body.assembly.k.as_ref(), &held, &f).unwrap();
    let nodes = body.assembly.expand(|d| u[d]);
    let direct = point_forces(&body.mesh.elements, &body.mesh.stress_points, &nodes);
    let eta = held_eta(&body.modal, &load);
    let kept: Vec<usize> = (0..body.modal.modes.len())
        .filter(|&k| body.modal.modes[k].selected)
        .collect();
    let eta_sel = held_eta(&body.modal.restrict(&kept), &load);
    let stress_sel = stress.restrict(&kept);
    for (p, sp) in stress.points.iter().enumerate() {
        let want = sp.fibres.stresses(&direct[p]);
        let got = stress.stress_at(p, &eta);
        let sel = stress_sel.stress_at(p, &eta_sel);
        println!(
            "{}: full FE sx_max {:.4e} eq {:.4e} Pa; modal all {} modes sx_max {:.4e} eq {:.4e}; selected {} modes eq {:.4e} ({:+.2} %)",
            sp.name, want.sx_max, want.eq, eta.len(), got.sx_max, got.eq, kept.len(), sel.eq,
            100.0 * (sel.eq / want.eq - 1.0)
        );
        assert!(rel(got.sx_max, want.sx_max) < 1e-2, "{}", sp.name);
        assert!(rel(got.sx_min, want.sx_min) < 1e-2, "{}", sp.name);
        assert!(rel(got.eq, want.eq) < 1e-2, "{}", sp.name);
    }
    // The hook root against statics: the hook is a cantilever from the crossbeam, so its
    // section forces at the root are the ball load and its moment about the root.
    let p = stress
        .points
        .iter()
        .position(|s| s.name == "ball_mount")
        .unwrap();
    let e = &body.mesh.elements[stress.points[p].element];
    let r = body.mesh.nodes[ball_node].position - e.beam.a;
    let fv = Vector3::new(load[0], load[1], load[2]);
    let m = r.cross(&fv);
    let (fl, ml) = (e.beam.axes * fv, e.beam.axes * m);
    let want = [fl[0], fl[1], fl[2], ml[0], ml[1], ml[2]];
    for c in 0..6 {
        assert!(
            (direct[p][c] - want[c]).abs() < 1e-6 * m.norm().max(fv.norm()),
            "component {c}: {} vs {}",
            direct[p][c],
            want[c]
        );
    }
}

#[test]
fn a_stress_point_on_a_missing_member_names_the_field() {
    let text = std::fs::read_to_string(FILE).unwrap().replacen(
        "node_b = \"cb_sensor\"\nat_fraction",
        "node_b = \"ball\"\nat_fraction",
        1,
    );
    let src = Source::from_text(Path::new("h.toml"), text).unwrap();
    let err = towride_mbs::flex::Mesh::from_source(&src, None)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("stress_point") && err.contains("node_b"),
        "{err}"
    );
}
