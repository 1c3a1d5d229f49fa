//! The stick-slip brake (`model::stick`) against the closed form of a wheel braked on a
//! slope. A wheel of radius r carrying a mass m rolls without slip on a grade theta: about
//! its contact point it is a disc of inertia J + m r^2 driven by m g sin(theta) r. Held by
//! a brake of capacity C it stays where it is (after the bristle's elastic deflection
//! T / (C / z_ss)) while m g sin(theta) r < C, and turns at (m g sin(theta) r - C) /
//! (J + m r^2) above. The wheel here is that disc on a fixed axle, loaded by that torque;
//! the brake is the Fabia's driveline file's, its capacity the driver's hold at a
//! standstill (a zero target speed) on one front wheel; r, m (the tyre's nominal load) and
//! J (rim and tyre) are the property files'. Released (the capacity falling to zero as
//! the target speed rises), the wheel rolls at T / (J + m r^2) as if it had no brake.

use crate::common;
use towride_mbs::model::desc::{
    Axes, Body, BodyHandle, Brakes, Joint, JointHandle, JointKind, JointQuantity, Marker,
    MarkerHandle, Model, Output, Request, SpeedControl,
};
use towride_mbs::model::elements::{Applied, Force};
use towride_mbs::model::function::TimeFunction;
use towride_mbs::model::run::simulate;
use towride_mbs::model::stick::StickFriction;
use towride_mbs::model::system::System;
use towride_solver::SolverOptions;

const EYE: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// z along world y (the spin axis).
const ZY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]];

fn num(v: &toml::Value, table: &str, key: &str) -> f64 {
    v[table][key].as_float().unwrap()
}

/// The wheel on its axle with `torque` about +y, braked by `brakes`; (time, angle, spin).
fn run(
    inertia: f64,
    torque: f64,
    brakes: Brakes,
    target: TimeFunction,
    t_end: f64,
) -> (Vec<f64>, Vec<f64>) {
    let mut m = Model {
        name: "braked wheel".into(),
        ..Default::default()
    };
    m.bodies.push(Body {
        name: "wheel".into(),
        mass: 10.0,
        inertia: [[1.0, 0.0, 0.0], [0.0, inertia, 0.0], [0.0, 0.0, 1.0]],
        position: [0.0; 3],
        orientation: [1.0, 0.0, 0.0, 0.0],
        velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        modal: None,
    });
    let marker = |name: &str, body: Option<usize>, axes| Marker {
        name: name.into(),
        body: body.map(BodyHandle::new),
        position: [0.0; 3],
        axes,
        node: None,
    };
    m.markers.push(marker("axle", None, ZY));
    m.markers.push(marker("wheel_axle", Some(0), ZY));
    m.markers.push(marker("wheel_centre", Some(0), EYE));
    m.markers.push(marker("knuckle", None, EYE));
    m.joints.push(Joint {
        name: "bearing".into(),
        kind: JointKind::Revolute,
        i: MarkerHandle::new(1),
        j: MarkerHandle::new(0),
    });
    m.forces.push(Force::Applied(Applied {
        name: "slope".into(),
        i: MarkerHandle::new(2),
        force: [None, None, None],
        // Loaded over 0.5 s, slowly against the wheel's spin mode on the brake (17 Hz),
        // as a car rolled onto a grade: a step would overshoot into slip.
        torque: [
            None,
            Some(TimeFunction::Step {
                t0_s: 0.0,
                from: 0.0,
                t1_s: 0.5,
                to: torque,
            }),
            None,
        ],
        in_marker_axes: false,
    }));
    m.controls.push(SpeedControl {
        name: "driver".into(),
        sensor: MarkerHandle::new(2),
        target,
        kp: 0.0,
        ki: 0.0,
        max_torque: 1.0,
        wheels: vec![],
        feedforward_kg_m: 0.0,
        brakes: Some(brakes),
        driveline: None,
    });
    m.outputs.push(Output::new(
        "angle",
        Request::Joint {
            joint: JointHandle::new(0),
            quantity: JointQuantity::Displacement,
            axes: Axes::World,
        },
    ));
    let sys = System::new(m);
    let (mut q, mut v) = sys.initial_q_v();
    let x = sys.ext_initial(&q, &v, 0.0);
    let (y0, yp0, _) =
        towride_mbs::model::ic::initial_state(&sys, 0.0, &mut q, &mut v, &x).unwrap();
    let mut atol = vec![1e-9; sys.oe()];
    atol.extend(sys.ext_atol(1e-3));
    let opts = SolverOptions {
        rtol: 1e-7,
        atol,
        ..Default::default()
    };
    let res = simulate(
        &sys,
        0.0,
        t_end,
        200.0,
        &opts,
        Some((y0, yp0)),
        &towride_mbs::progress::Silent,
    );
    assert!(res.error.is_none(), "{:?}", res.error);
    (res.times.clone(), res.rows.iter().map(|r| r[0]).collect())
}

#[test]
fn a_braked_wheel_on_a_slope_stands_below_the_capacity_and_rolls_at_the_closed_form_above() {
    let text = std::fs::read_to_string(repo!("vehicles/fabia/driveline.toml")).unwrap();
    let d: toml::Value = toml::from_str(&text).unwrap();
    let tir = repo!("vehicles/tyres/car_185_60r14.tir");
    let front = d["brakes"]["front_wheels"].as_array().unwrap().len() as f64;
    // One front wheel's share of the hold.
    let capacity = num(&d, "brakes", "hold_torque_n_m") * num(&d, "brakes", "front_share") / front;
    let stick = StickFriction {
        deflection_rad: num(&d, "brakes", "stick_deflection_rad"),
        elastic_share: num(&d, "brakes", "stick_elastic_share"),
        damping_s: num(&d, "brakes", "stick_damping_s"),
    };
    let brakes = Brakes {
        wheels: vec![(MarkerHandle::new(2), MarkerHandle::new(3), 1.0)],
        max_torque: num(&d, "brakes", "max_torque_n_m"),
        engine_drag: num(&d, "brakes", "engine_drag_n_m"),
        blend: num(&d, "brakes", "blend_n_m"),
        stick,
        hold_torque: capacity,
        hold_speed: num(&d, "brakes", "hold_below_m_s"),
    };
    let r = common::tir_value(tir, "DIMENSION", "UNLOADED_RADIUS");
    let g = 9.81;
    let mass = common::tir_value(tir, "VERTICAL", "FNOMIN") / g;
    let rim = {
        let t = std::fs::read_to_string(repo!("vehicles/fabia/front_mcpherson.toml")).unwrap();
        let v: toml::Value = toml::from_str(&t).unwrap();
        v["wheel"]["spin_inertia_kg_m2"].as_float().unwrap()
    };
    let inertia = rim + common::tir_value(tir, "INERTIA", "IYY") + mass * r * r;
    let stopped = || TimeFunction::Constant { value: 0.0 };
    let grade = |share: f64| (share * capacity / (mass * g * r)).asin();

    // 80 % of the capacity (a 16 deg grade for this wheel): held still. Loaded slowly,
    // the bristle takes the torque at s = 0.8 of its slip deflection; the wheel turns by
    // that deflection plus the yield above z_ba: z_ss (beta + int_beta^0.8 ds / (1 -
    // alpha(s) s)), alpha the paper's yield weight, written out here.
    let theta = grade(0.8);
    let load = mass * g * theta.sin() * r;
    let (t, angle) = run(inertia, load, brakes.clone(), stopped(), 5.0);
    let at = |x: f64| t.iter().position(|&s| s >= x).unwrap();
    let b = stick.elastic_share;
    let yield_weight =
        |s: f64| 0.5 * (std::f64::consts::PI * (s - (1.0 + b) / 2.0) / (1.0 - b)).sin() + 0.5;
    let n = 20_000;
    let ds = (0.8 - b) / n as f64;
    let presliding: f64 = (0..n)
        .map(|k| {
            let s = b + (k as f64 + 0.5) * ds;
            ds / (1.0 - yield_weight(s) * s)
        })
        .sum();
    let elastic = stick.deflection_rad * (b + presliding);
    let a1 = angle[at(1.0)];
    // Creep: the spread of the angle over the last 3 s, as travel at the contact.
    let last = &angle[at(2.0)..];
    let drift = (last.iter().fold(f64::MIN, |m, &x| m.max(x))
        - last.iter().fold(f64::MAX, |m, &x| m.min(x)))
        * r;
    println!(
        "grade {:.1} deg, load {load:.1} N m against {capacity:.1} N m: deflection {:.4e} rad ({elastic:.4e} quasi-static), travel 2-5 s {drift:.3e} m",
        theta.to_degrees(),
        a1
    );
    // Within 5 %: the load's end still rings the lightly damped spin mode a little.
    assert!((a1 - elastic).abs() < 0.05 * elastic, "deflection {a1} rad");
    assert!(drift < 1e-7, "the held wheel moved {drift} m in 3 s");

    // 125 %: it slips and the wheel rolls down at (T - C) / (J + m r^2).
    let theta = grade(1.25);
    let load = mass * g * theta.sin() * r;
    let (t, angle) = run(inertia, load, brakes.clone(), stopped(), 2.0);
    let at = |x: f64| t.iter().position(|&s| s >= x).unwrap();
    let (i1, i2, i3) = (at(1.0), at(1.5), at(2.0));
    // Second difference of the angle: its acceleration while it slips.
    let h = t[i2] - t[i1];
    let alpha = (angle[i3] - 2.0 * angle[i2] + angle[i1]) / (h * h);
    let expected = (load - capacity) / inertia;
    println!(
        "grade {:.1} deg: rolls at {:.5} m/s^2, closed form {:.5}",
        theta.to_degrees(),
        alpha * r,
        expected * r
    );
    assert!(
        (alpha / expected - 1.0).abs() < 1e-3,
        "{alpha} against {expected}"
    );

    // The driver lets go: the target speed rises past the hold's speed over 2.5-3 s, the
    // capacity falls to zero with it, and the wheel held at 80 % rolls freely from then
    // on at T / (J + m r^2): nothing of the bristle is left.
    let theta = grade(0.8);
    let load = mass * g * theta.sin() * r;
    let release = TimeFunction::Step {
        t0_s: 2.5,
        from: 0.0,
        t1_s: 3.0,
        to: brakes.hold_speed,
    };
    let (t, angle) = run(inertia, load, brakes, release, 4.5);
    let at = |x: f64| t.iter().position(|&s| s >= x).unwrap();
    let held = (angle[at(2.5)] - angle[at(2.0)]).abs() * r;
    let (i1, i2, i3) = (at(3.5), at(4.0), at(4.5));
    let h = t[i2] - t[i1];
    let alpha = (angle[i3] - 2.0 * angle[i2] + angle[i1]) / (h * h);
    let free = load / inertia;
    println!("released: held to {held:.2e} m before, then {alpha:.6} rad/s^2 against {free:.6}");
    assert!(held < 1e-7, "moved {held} m while held");
    assert!((alpha / free - 1.0).abs() < 1e-3, "{alpha} against {free}");
}
