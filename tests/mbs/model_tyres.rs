//! Tyres inside the multibody equations: a quarter car built from bodies and joints (a
//! carriage driven along x at constant speed, a hub sliding vertically on it, a wheel
//! spinning freely on the hub) rolls over a bump exactly as the tyre module's own
//! quarter rig, which integrates the same tyre with three hand-written equations.

use std::path::Path;

use towride_mbs::model::desc::{
    Axes, Body, BodyHandle, Joint, JointHandle, JointKind, Marker, MarkerHandle, MarkerQuantity,
    Model, Motion, MotionDof, Output, Request, TyreElem,
};
use towride_mbs::model::function::TimeFunction;
use towride_mbs::model::run::simulate;
use towride_mbs::model::system::System;
use towride_mbs::road::Road;
use towride_mbs::tyre::rig::{rig_options, QuarterRig};
use towride_mbs::tyre::{Tyre, TyreKind};
use towride_solver::SolverOptions;

const EYE: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// Columns x, y, z with z along world x (a slider along x).
const ZX: [[f64; 3]; 3] = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// z along world y (the wheel's spin axis).
const ZY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]];

fn body(name: &str, mass: f64, iyy: f64, at: [f64; 3], speed: f64) -> Body {
    Body {
        name: name.into(),
        mass,
        inertia: [[iyy, 0.0, 0.0], [0.0, iyy, 0.0], [0.0, 0.0, iyy]],
        position: at,
        orientation: [1.0, 0.0, 0.0, 0.0],
        velocity: [speed, 0.0, 0.0],
        angular_velocity: [0.0; 3],
        modal: None,
    }
}

fn marker(name: &str, body: Option<usize>, position: [f64; 3], axes: [[f64; 3]; 3]) -> Marker {
    Marker {
        name: name.into(),
        body: body.map(BodyHandle::new),
        position,
        axes,
        node: None,
    }
}

/// A carriage driven along x at `speed`, a hub sliding vertically on it, and a wheel
/// spinning at `omega0` on the hub, with the tyre on `road`.
#[allow(clippy::too_many_arguments)]
fn quarter_car(
    tyre: &Tyre,
    road: &Road,
    speed: f64,
    at: [f64; 3],
    mass: f64,
    rim_iyy: f64,
    omega0: f64,
    g: f64,
) -> Model {
    let wheel_mass = 10.0;
    let mut m = Model {
        name: "quarter car".into(),
        gravity: [0.0, 0.0, g],
        ..Default::default()
    };
    m.bodies.push(body("carriage", 5.0, 0.1, at, speed));
    m.bodies
        .push(body("hub", mass - wheel_mass, 0.1, at, speed));
    let mut wheel = body("wheel", wheel_mass, rim_iyy, at, speed);
    wheel.angular_velocity = [0.0, omega0, 0.0];
    m.bodies.push(wheel);
    m.markers.push(marker("ground_x", None, at, ZX));
    m.markers.push(marker("carriage_x", Some(0), [0.0; 3], ZX));
    m.markers.push(marker("carriage_z", Some(0), [0.0; 3], EYE));
    m.markers.push(marker("hub_z", Some(1), [0.0; 3], EYE));
    m.markers.push(marker("hub_spin", Some(1), [0.0; 3], ZY));
    m.markers.push(marker("wheel_spin", Some(2), [0.0; 3], ZY));
    m.markers
        .push(marker("wheel_centre", Some(2), [0.0; 3], EYE));
    let joint = |name: &str, kind, i, j| Joint {
        name: name.into(),
        kind,
        i: MarkerHandle::new(i),
        j: MarkerHandle::new(j),
    };
    m.joints
        .push(joint("carriage", JointKind::Translational, 1, 0));
    m.joints.push(joint("hub", JointKind::Translational, 3, 2));
    m.joints.push(joint("bearing", JointKind::Revolute, 5, 4));
    m.motions.push(Motion {
        name: "speed".into(),
        joint: JointHandle::new(0),
        dof: MotionDof::Translation,
        function: TimeFunction::Constant { value: speed },
        is_velocity: true,
    });
    m.tyres.push(TyreElem {
        name: "tyre".into(),
        marker: MarkerHandle::new(6),
        tyre: tyre.clone(),
    });
    m.road = Some(road.clone());
    m.outputs.push(Output::new(
        "wheel",
        Request::Marker {
            marker: MarkerHandle::new(6),
            quantity: MarkerQuantity::Position,
            axes: Axes::World,
        },
    ));
    m
}

#[test]
fn quarter_car_from_bodies_and_joints_rolls_as_the_tyre_rig() {
    let file = Path::new(repo!("vehicles/tyres/car_185_60r14.tir"));
    let tyre = Tyre::from_file(
        file,
        TyreKind::RigidRing,
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let road = Road::from_file(
        Path::new(repo!("roads/bump_25mm.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let speed = 40.0 / 3.6;
    let (mass, rim_iyy, x0) = (300.0, 0.6, 0.0);
    let rig = QuarterRig::new(tyre.clone(), road.clone(), speed, x0, mass, rim_iyy, 0.0);
    let t_end = 0.4;
    let dt = 1e-3;
    let opts_rig = rig_options(&rig.tyre, 1e-6, &[1e-7, 1e-5, 1e-4]);
    let reference = rig.run(None, t_end, dt, &opts_rig).unwrap();
    let (y_rig, _) = rig.initial(None);
    let n = tyre.n_states();
    let (z0, omega0) = (y_rig[n], y_rig[n + 2]);

    let g = tyre.params().gravity;
    let m = quarter_car(&tyre, &road, speed, [x0, 0.0, z0], mass, rim_iyy, omega0, g);
    let sys = System::new(m);
    let (mut q, mut v) = sys.initial_q_v();
    let x = y_rig[..n].to_vec();
    let (y0, yp0, _) =
        towride_mbs::model::ic::initial_state(&sys, 0.0, &mut q, &mut v, &x).unwrap();
    let mut atol = vec![1e-7; sys.oe()];
    atol.extend(sys.ext_atol(1.0));
    let opts = SolverOptions {
        rtol: 1e-6,
        atol,
        h_max: opts_rig.h_max,
        ..Default::default()
    };
    let run = simulate(
        &sys,
        0.0,
        t_end,
        1.0 / dt,
        &opts,
        Some((y0, yp0)),
        &towride_mbs::progress::Silent,
    );
    assert!(run.error.is_none(), "{:?}", run.error);
    let z_ref: Vec<f64> = reference.samples.iter().map(|s| s.z_m).collect();
    let z: Vec<f64> = run.rows.iter().map(|r| r[2]).collect();
    assert_eq!(z.len(), z_ref.len());
    let travel = z_ref.iter().fold(f64::MIN, |a, b| a.max(*b))
        - z_ref.iter().fold(f64::MAX, |a, b| a.min(*b));
    let worst = z
        .iter()
        .zip(&z_ref)
        .fold(0.0f64, |a, (p, r)| a.max((p - r).abs()));
    println!(
        "wheel-centre travel over the bump {:.3} mm; largest difference multibody vs rig {:.3e} mm ({:.2} % of travel); steps {} vs {}",
        1e3 * travel,
        1e3 * worst,
        100.0 * worst / travel,
        run.stats.steps,
        reference.stats.steps
    );
    assert!(travel > 5e-3);
    assert!(worst < 0.01 * travel);
}

/// The frame transport that lets a re-used iteration matrix follow a spinning wheel
/// (`DaeProblem::transport`): after the wheel has turned 0.6 rad on its axle, the matrix
/// built before the turn, applied through the transport, solves as the exact matrix at the
/// new state does; the old matrix alone is off by tens of percent.
#[test]
fn iteration_matrix_transport_follows_the_wheel_spin() {
    use nalgebra::{DMatrix, DVector};
    use towride_mbs::model::math::{mtv, qmul, rot};
    use towride_solver::problem::{DaeProblem, JacobianSink, Transport};

    let tyre = Tyre::from_file(
        Path::new(repo!("vehicles/tyres/car_185_60r14.tir")),
        TyreKind::RigidRing,
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let road = Road::from_file(
        Path::new(repo!("roads/bump_25mm.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let speed = 40.0 / 3.6;
    let (mass, rim_iyy) = (300.0, 0.6);
    let rig = QuarterRig::new(tyre.clone(), road.clone(), speed, 0.0, mass, rim_iyy, 0.0);
    let (y_rig, _) = rig.initial(None);
    let n = tyre.n_states();
    let g = tyre.params().gravity;
    let at = [0.0, 0.0, y_rig[n]];
    let sys = System::new(quarter_car(
        &tyre,
        &road,
        speed,
        at,
        mass,
        rim_iyy,
        y_rig[n + 2],
        g,
    ));
    let (mut q, mut v) = sys.initial_q_v();
    let (mut y0, yp0, _) =
        towride_mbs::model::ic::initial_state(&sys, 0.0, &mut q, &mut v, &y_rig[..n]).unwrap();
    // A camber and steer rate, so that the spin turns the wheel's body-axes components.
    let (o, w) = (sys.qo[2] + 3, sys.nq + sys.vo[2] + 3);
    y0[w] += 0.4;
    y0[w + 2] -= 0.3;

    // The same motion with the wheel turned by phi about its axle (body y).
    let phi: f64 = 0.6;
    let e = [(0.5 * phi).cos(), 0.0, (0.5 * phi).sin(), 0.0];
    let dr = rot(&e);
    let turn = |y: &[f64]| {
        let mut y = y.to_vec();
        let p = qmul(&[y[o], y[o + 1], y[o + 2], y[o + 3]], &e);
        y[o..o + 4].copy_from_slice(&p);
        let a = mtv(&dr, &[y[w], y[w + 1], y[w + 2]]);
        y[w..w + 3].copy_from_slice(&a);
        y
    };
    let (y1, yp1) = (turn(&y0), turn(&yp0));

    let size = sys.size();
    let cj = 1e3;
    let matrix = |y: &[f64], yp: &[f64]| {
        let mut entries = Vec::new();
        assert!(sys.jacobian(0.0, y, yp, cj, &mut JacobianSink::new(&mut entries)));
        let mut j = DMatrix::zeros(size, size);
        for (r, c, val) in entries {
            j[(r, c)] += val;
        }
        j
    };
    let (old, new) = (matrix(&y0, &yp0).lu(), matrix(&y1, &yp1).lu());
    // A velocity-constraint violation to correct: what a Newton step on a spinning wheel
    // meets (the bearing rows turn with the wheel).
    let (_, _, _, om) = sys.offsets();
    let b: Vec<f64> = (0..size)
        .map(|i| {
            if (om..sys.oe()).contains(&i) {
                ((i * 7919 % 101) as f64 / 50.0) - 1.0
            } else {
                0.0
            }
        })
        .collect();
    let exact = new.solve(&DVector::from_vec(b.clone())).unwrap();
    let stale = old.solve(&DVector::from_vec(b.clone())).unwrap();
    let mut bt = b.clone();
    sys.transport(&y0, &y1, &mut bt, Transport::Rows);
    let mut moved = old.solve(&DVector::from_vec(bt)).unwrap();
    sys.transport(&y0, &y1, moved.as_mut_slice(), Transport::Columns);
    // Compared on the wheel's angular-velocity correction.
    let rel = |x: &DVector<f64>| (x.rows(w, 3) - exact.rows(w, 3)).norm() / exact.rows(w, 3).norm();
    println!(
        "relative difference from the exact solve: transported {:.2e}, stale {:.2e}",
        rel(&moved),
        rel(&stale)
    );
    assert!(rel(&moved) < 1e-6, "transported {:.3e}", rel(&moved));
    assert!(rel(&stale) > 1e-2, "stale {:.3e}", rel(&stale));
}
