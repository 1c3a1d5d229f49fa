//! Tyres inside the multibody equations: a quarter car built from bodies and joints (a
//! carriage driven along x at constant speed, a hub sliding vertically on it, a wheel
//! spinning freely on the hub) rolls over a bump exactly as the tyre module's own
//! quarter rig, which integrates the same tyre with three hand-written equations.

use std::path::Path;

use towride::model::desc::{
    Axes, Body, Joint, JointKind, Marker, MarkerQuantity, Model, Motion, MotionDof, Output,
    Request, TyreElem,
};
use towride::model::function::TimeFunction;
use towride::model::run::simulate;
use towride::model::system::System;
use towride::road::Road;
use towride::solver::SolverOptions;
use towride::tyre::rig::{rig_options, QuarterRig};
use towride::tyre::{Tyre, TyreKind};

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
        body,
        position,
        axes,
        node: None,
    }
}

#[test]
fn quarter_car_from_bodies_and_joints_rolls_as_the_tyre_rig() {
    let file = Path::new("vehicles/tyres/car_185_60r14.tir");
    let tyre = Tyre::from_file(file, TyreKind::RigidRing).unwrap();
    let road = Road::from_file(Path::new("roads/bump_25mm.toml")).unwrap();
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
    let wheel_mass = 10.0;
    let at = [x0, 0.0, z0];
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
        i,
        j,
    };
    m.joints
        .push(joint("carriage", JointKind::Translational, 1, 0));
    m.joints.push(joint("hub", JointKind::Translational, 3, 2));
    m.joints.push(joint("bearing", JointKind::Revolute, 5, 4));
    m.motions.push(Motion {
        name: "speed".into(),
        joint: 0,
        dof: MotionDof::Translation,
        function: TimeFunction::Constant { value: speed },
        is_velocity: true,
    });
    m.tyres.push(TyreElem {
        name: "tyre".into(),
        marker: 6,
        tyre: tyre.clone(),
    });
    m.road = Some(road);
    m.outputs.push(Output::new(
        "wheel",
        Request::Marker {
            marker: 6,
            quantity: MarkerQuantity::Position,
            axes: Axes::World,
        },
    ));
    let sys = System::new(m);
    let (mut q, mut v) = sys.initial_q_v();
    let x = y_rig[..n].to_vec();
    let (y0, yp0, _) = towride::model::ic::initial_state(&sys, 0.0, &mut q, &mut v, &x).unwrap();
    let mut atol = vec![1e-7; sys.oe()];
    atol.extend(sys.ext_atol(1.0));
    let opts = SolverOptions {
        rtol: 1e-6,
        atol,
        h_max: opts_rig.h_max,
        ..Default::default()
    };
    let run = simulate(&sys, 0.0, t_end, 1.0 / dt, &opts, Some((y0, yp0)), None);
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
