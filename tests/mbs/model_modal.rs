//! The hitch crossbeam as a modal body inside the multibody equations: held at its
//! brackets by fixed joints and loaded at the ball it deflects as the full FE model;
//! released it rings at the full FE model's first held frequency.

use std::f64::consts::PI;
use std::path::Path;

use towride_mbs::flex::modes::{constrained_eigen, frequency_hz, static_solution};
use towride_mbs::flex::{FlexBody, ModalData, Options};
use towride_mbs::model::desc::{
    Applied, Axes, Body, BodyHandle, Coupling, Force, Joint, JointKind, Marker, MarkerHandle,
    MarkerQuantity, Modal, Model, Output, Request,
};
use towride_mbs::model::function::TimeFunction;
use towride_mbs::model::run::simulate;
use towride_mbs::model::statics::equilibrium;
use towride_mbs::model::system::System;
use towride_solver::SolverOptions;

const FILE: &str = repo!("flex/hitch_crossbeam.toml");
const EYE: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn hitch() -> FlexBody {
    FlexBody::load(
        Path::new(FILE),
        None,
        &Options {
            fixed_interface_modes: Some(8),
            rule: None,
        },
        &crate::load_path_rule(),
    )
    .unwrap()
}

/// The modal body held at its brackets by fixed joints to ground, with a force `load`
/// [N] (world) at the ball when given; modal damping off.
fn model(md: &ModalData, load: Option<[f64; 3]>, coupling: Coupling) -> Model {
    let mut md = md.clone();
    for m in &mut md.modes {
        m.damping_ratio = 0.0;
    }
    let f = load.map(|f| f.map(|x| Some(TimeFunction::Constant { value: x })));
    held(md, f, coupling)
}

/// The modal body `md` held at its brackets, with force functions at the ball.
fn held(md: ModalData, load: Option<[Option<TimeFunction>; 3]>, coupling: Coupling) -> Model {
    let com = md.com_m;
    let mut m = Model {
        name: "held hitch".into(),
        ..Default::default()
    };
    m.bodies.push(Body {
        name: "crossbeam".into(),
        mass: md.mass_kg,
        inertia: md.inertia_com_kg_m2,
        position: com,
        orientation: [1.0, 0.0, 0.0, 0.0],
        velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        modal: None,
    });
    for name in ["bracket_left", "bracket_right", "ball"] {
        let idx = md.nodes.iter().position(|n| n.name == name).unwrap();
        let p = md.nodes[idx].position_m;
        m.markers.push(Marker {
            name: name.into(),
            body: Some(BodyHandle::new(0)),
            position: [p[0] - com[0], p[1] - com[1], p[2] - com[2]],
            axes: EYE,
            node: Some(idx),
        });
        m.markers.push(Marker {
            name: format!("{name}_ground"),
            body: None,
            position: p,
            axes: EYE,
            node: None,
        });
    }
    for (k, name) in ["bracket_left", "bracket_right"].iter().enumerate() {
        m.joints.push(Joint {
            name: (*name).into(),
            kind: JointKind::Fixed,
            i: MarkerHandle::new(2 * k),
            j: MarkerHandle::new(2 * k + 1),
        });
    }
    if let Some(f) = load {
        m.forces.push(Force::Applied(Applied {
            name: "ball load".into(),
            i: MarkerHandle::new(4),
            force: f,
            torque: [None, None, None],
            in_marker_axes: false,
        }));
    }
    m.outputs.push(Output::new(
        "ball",
        Request::Marker {
            marker: MarkerHandle::new(4),
            quantity: MarkerQuantity::Position,
            axes: Axes::World,
        },
    ));
    m.bodies[0].modal = Some(Box::new(Modal { data: md, coupling }));
    m
}

fn bracket_dofs(b: &FlexBody) -> Vec<usize> {
    ["bracket_left", "bracket_right"]
        .iter()
        .flat_map(|n| b.assembly.dofs(b.mesh.interface(n).unwrap().node))
        .collect()
}

#[test]
fn modal_hitch_in_the_multibody_model_deflects_and_rings_as_the_full_fe_model() {
    let b = hitch();
    let held = bracket_dofs(&b);
    let ball = b.assembly.dofs(b.mesh.interface("ball").unwrap().node);
    // First held mode of the full FE model and its direction at the ball.
    let eig = constrained_eigen(b.assembly.k.as_ref(), b.assembly.m.as_ref(), &held).unwrap();
    let f1 = frequency_hz(eig.omega2[0]);
    let dir: Vec<f64> = (0..3).map(|c| eig.vectors[(ball[c], 0)]).collect();
    let d = (0..3)
        .max_by(|&i, &j| dir[i].abs().total_cmp(&dir[j].abs()))
        .unwrap();
    let mut load = [0.0; 3];
    load[d] = 2000.0;
    // Full FE static deflection at the ball.
    let mut f = vec![0.0; b.assembly.n_dof];
    f[ball[d]] = load[d];
    let u = static_solution(b.assembly.k.as_ref(), &held, &f).unwrap();
    let want = u[ball[d]];

    // Every coupling level: held at the brackets the body barely rotates, so they agree.
    for coupling in [Coupling::Constant, Coupling::Partial, Coupling::Full] {
        let opts = SolverOptions {
            rtol: 1e-8,
            ..Default::default()
        };
        let sys = System::new(model(&b.modal, Some(load), coupling));
        let st = equilibrium(&sys, 0.0, &opts).unwrap();
        let p0 = b.modal.node("ball").unwrap().position_m;
        let ball_marker = MarkerHandle::new(4);
        let got = sys.marker_frame(&st.y[..sys.nq], ball_marker).origin[d] - p0[d];
        println!(
            "{coupling:?}: ball deflection under {} N along axis {d}: full FE {want:.6e} m, modal body in the multibody model {got:.6e} m ({:+.3} %)",
            load[d],
            100.0 * (got / want - 1.0)
        );
        assert!((got / want - 1.0).abs() < 0.01);

        // Release: the same deflected state without the load.
        let free = System::new(model(&b.modal, None, coupling));
        let mut q = st.y[..free.nq].to_vec();
        let mut v = vec![0.0; free.nv];
        let (y0, yp0, _) =
            towride_mbs::model::ic::initial_state(&free, 0.0, &mut q, &mut v, &[]).unwrap();
        let t_end = 40.0 / f1;
        let rate = 200.0 * f1;
        let opts = SolverOptions {
            rtol: 1e-7,
            ..Default::default()
        };
        let run = simulate(
            &free,
            0.0,
            t_end,
            rate,
            &opts,
            Some((y0, yp0)),
            &towride_mbs::progress::Silent,
        );
        assert!(run.error.is_none(), "{:?}", run.error);
        let x: Vec<f64> = run.rows.iter().map(|r| r[d] - p0[d]).collect();
        // Upward zero crossings, linearly interpolated.
        let mut crossings = Vec::new();
        for k in 1..x.len() {
            if x[k - 1] < 0.0 && x[k] >= 0.0 {
                let s = x[k - 1] / (x[k - 1] - x[k]);
                crossings.push(run.times[k - 1] + s * (run.times[k] - run.times[k - 1]));
            }
        }
        let n = crossings.len() - 1;
        let f_run = n as f64 / (crossings[n] - crossings[0]);
        println!(
            "{coupling:?}: released: rings at {f_run:.3} Hz over {n} periods; full FE first held mode {f1:.3} Hz ({:+.3} %)",
            100.0 * (f_run / f1 - 1.0)
        );
        assert!(n > 30);
        assert!((f_run / f1 - 1.0).abs() < 0.005);
    }
    let _ = PI;
}

/// A half-sine pulse of `peak` lasting `width` seconds from t = 0.01 s, as a table.
fn pulse(peak: f64, width: f64) -> TimeFunction {
    let n = 40;
    let mut time_s = vec![0.0];
    let mut value = vec![0.0];
    for k in 0..=n {
        let s = k as f64 / n as f64;
        time_s.push(0.01 + s * width);
        value.push(peak * (PI * s).sin());
    }
    time_s.push(1.0);
    value.push(0.0);
    TimeFunction::Table { time_s, value }
}

#[test]
fn strain_energy_selection_after_a_run_agrees_with_the_a_priori_load_path_rule() {
    use towride_mbs::flex::selection::select;
    use towride_mbs::flex::Rule;
    use towride_mbs::model::energy::{select_by_energy, strain_shares};
    let b = hitch();
    let Rule::LoadPath(lp) = b.rule.clone() else {
        panic!("the hitch file selects by load paths");
    };
    // The scene's load mix at the ball: the trailer pushes and presses on it.
    let lp = towride_mbs::flex::LoadPath {
        load_n: Some([7500.0, 0.0, -2500.0]),
        ..lp
    };
    let a_priori = select(&b.modal, &Rule::LoadPath(lp.clone())).unwrap();
    let kept: Vec<usize> = b
        .modal
        .modes
        .iter()
        .zip(&a_priori.selected)
        .filter(|(_, s)| **s)
        .map(|(m, _)| m.number)
        .collect();
    // The trailer's push at the ball as the wheels hit the ramp (digest 4: about 7.5 kN
    // over some 40 ms) with a vertical component, all modes in the run.
    let f = [Some(pulse(7500.0, 0.04)), None, Some(pulse(-2500.0, 0.04))];
    let sys = System::new(held(b.modal.clone(), Some(f), Coupling::Constant));
    let (mut q, mut v) = sys.initial_q_v();
    let (y0, yp0, _) =
        towride_mbs::model::ic::initial_state(&sys, 0.0, &mut q, &mut v, &[]).unwrap();
    let opts = SolverOptions {
        rtol: 1e-6,
        ..Default::default()
    };
    let run = simulate(
        &sys,
        0.0,
        0.1,
        5000.0,
        &opts,
        Some((y0, yp0)),
        &towride_mbs::progress::Silent,
    );
    assert!(run.error.is_none(), "{:?}", run.error);
    let shares = strain_shares(&sys, &run);
    let energy = select_by_energy(&shares[0], lp.min_energy_share);
    for m in &shares[0].modes {
        println!(
            "mode {:2} {:8.1} Hz: peak share {:6.2} %, integral share {:6.2} %, a-priori share {:6.2} %",
            m.number,
            m.frequency_hz,
            100.0 * m.share_peak,
            100.0 * m.share_integral,
            100.0 * a_priori.max_share.as_ref().unwrap()[b.modal.modes.iter().position(|x| x.number == m.number).unwrap()]
        );
    }
    println!(
        "kept by strain energy after the run: {energy:?}; by the a-priori load-path rule: {kept:?}"
    );
    // Per mode the two shares agree within 3 percentage points, and both methods make
    // the same decision for every mode not within 30 % of the threshold (a mode at
    // 0.9 % in one and 1.1 % in the other sits on the fence in both).
    let prior = a_priori.max_share.as_ref().unwrap();
    let thr = lp.min_energy_share;
    for (k, m) in shares[0].modes.iter().enumerate() {
        assert!((m.share_peak - prior[k]).abs() < 0.03, "mode {}", m.number);
        let clear = |s: f64| s < 0.7 * thr || s > 1.3 * thr;
        if clear(m.share_peak) && clear(prior[k]) {
            assert_eq!(
                energy.contains(&m.number),
                kept.contains(&m.number),
                "mode {}",
                m.number
            );
        }
    }
}
