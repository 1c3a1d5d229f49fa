//! Scenes: the fixed channel list, the measurement plan's cases, and the thesis's default
//! scene run from static equilibrium at speed over the ramp.

use std::path::Path;

use towride_app::scene::{self, plan};
use towride_mbs::model::desc::{Axes, MarkerQuantity, Output, Request};
use towride_mbs::model::run::simulate;
use towride_mbs::model::start::at_speed;
use towride_mbs::model::System;

const SENSORS: [&str; 11] = [
    "wheel_front_left",
    "wheel_front_right",
    "wheel_rear_left",
    "wheel_rear_right",
    "body_front_left",
    "body_front_right",
    "body_rear_left",
    "body_rear_right",
    "driver_floor",
    "hitch",
    "trailer_drawbar",
];

#[test]
fn default_scene_has_the_fixed_channels() {
    let s = scene::load(Path::new(repo!("scenes/default.toml"))).unwrap();
    let names: Vec<&str> = s.channels.iter().map(|c| c.name.as_str()).collect();
    let brackets: Vec<String> = ["left", "right"]
        .iter()
        .flat_map(|b| {
            ["fx", "fy", "fz", "mx", "my", "mz"].map(|c| format!("hitch_bracket_{b}_{c}"))
        })
        .collect();
    let mut want = vec!["speed", "hitch_fx", "hitch_fy", "hitch_fz"];
    want.extend(brackets.iter().map(|s| s.as_str()));
    want.push("trailer_ax");
    let mut acc = Vec::new();
    for (k, sensor) in SENSORS.iter().enumerate() {
        // The driver's floor point and the hitch carry three axes.
        let axes: &[&str] = if k == 8 || k == 9 {
            &["x", "y", "z"]
        } else {
            &["z"]
        };
        acc.extend(axes.iter().map(|a| format!("acc_{sensor}_{a}")));
    }
    want.extend(acc.iter().map(|s| s.as_str()));
    assert_eq!(names[..want.len()], want[..]);
    let unit = |n: &str| {
        s.channels
            .iter()
            .find(|c| c.name == n)
            .unwrap()
            .unit
            .clone()
    };
    assert_eq!(unit("hitch_fx"), "N");
    assert_eq!(unit("speed"), "m/s");
    assert_eq!(unit("acc_hitch_y"), "m/s^2");
    // The channels that need the assembled system follow.
    for r in [
        "tyre_fl_fz",
        "tyre_tr_contact",
        "hitch_eta_1",
        "hitch_strain_energy",
        "hitch_deflection_x",
    ] {
        assert!(names.contains(&r), "{r} missing");
    }
    assert_eq!(unit("tyre_fl_fz"), "N");
    assert_eq!(unit("hitch_strain_energy"), "J");
    assert_eq!(unit("hitch_deflection_x"), "m");
    assert!((s.speed - 50.0 / 3.6).abs() < 1e-12);
    assert_eq!((s.duration, s.sample_rate), (3.0, 1000.0));
    assert!(s.model().road.is_some() && s.model().tyres.len() == 6);
    assert_eq!(s.model().controls.len(), 1);
}

#[test]
fn measurement_plan_has_72_cases() {
    let p = plan::load(Path::new(repo!("scenes/measurement_plan.toml"))).unwrap();
    assert_eq!(p.cases.len(), 72);
    let mut names: Vec<&str> = p.cases.iter().map(|c| c.name.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), 72);
    let c = p.case("bump_50mm_20kmh_200kg_behind_axle").unwrap();
    assert_eq!(c.changes.speed_km_h, Some(20.0));
    // 7.5 m of travel at 20 km/h, then 1 s.
    assert!((c.changes.duration_s.unwrap() - (7.5 / (20.0 / 3.6) + 1.0)).abs() < 1e-12);
    let s = p.scene(c, &towride_mbs::input::Loader::new()).unwrap();
    assert_eq!(
        s.vehicle.design.trailer.as_ref().unwrap().load_case,
        "200kg_behind_axle"
    );
    assert!(s.road_file.ends_with("bump_50mm.toml"));
}

/// First time |channel| exceeds `level`.
fn onset(t: &[f64], y: &[f64], level: f64) -> f64 {
    t.iter()
        .zip(y)
        .find(|(_, v)| v.abs() > level)
        .map(|(t, _)| *t)
        .unwrap()
}

#[test]
fn default_scene_runs_over_the_ramp() {
    let s = scene::load(Path::new(repo!("scenes/default.toml"))).unwrap();
    // Plus the trailer's left wheel centre, to see when it meets the ramp.
    let mut model = s.model().clone();
    let tl = s
        .vehicle
        .handles
        .wheels
        .iter()
        .find(|w| w.name == "tl")
        .unwrap();
    model.outputs.push(Output::new(
        "tl",
        Request::Marker {
            marker: tl.centre,
            quantity: MarkerQuantity::Acceleration,
            axes: Axes::World,
        },
    ));
    let sys = System::new(model.clone());
    let opts = s.solver_for(&sys);
    let (y0, yp0, rep) = at_speed(&model, s.speed, s.settle, &opts).unwrap();
    assert!(rep.statics.residual_force < 1e-6);
    let res = simulate(
        &sys,
        0.0,
        s.duration,
        s.sample_rate,
        &opts,
        Some((y0, yp0)),
        &towride_mbs::progress::Silent,
    );
    assert!(res.error.is_none(), "{:?}", res.error);
    let ch = |n: &str| res.channel(n).unwrap();
    let t = &res.times;
    // The ramp's foot is 1 m ahead of the front wheels; the trailer's wheels follow at
    // the distance the vehicle files give (the tyre meets a 45 deg flank a little before
    // its centre is over the foot).
    let front = onset(t, &ch("acc_wheel_front_left_z"), 20.0);
    assert!(
        (0.04..=0.09).contains(&front),
        "front wheels reach the ramp at {front} s"
    );
    let h = &s.vehicle.handles;
    let world_x = |k: usize| s.model().bodies[h.wheels[k].body].position[0];
    let t_trailer = (world_x(0) - world_x(4) + 1.0) / s.speed;
    // The ramp is the trailer wheel's largest event: its onset is where the wheel's
    // acceleration first reaches half its peak (earlier, smaller bumps come through the
    // hitch from the car's wheels).
    let a_tl = ch("tl.z");
    let peak = a_tl.iter().fold(0.0_f64, |p, v| p.max(v.abs()));
    let trailer = onset(t, &a_tl, 0.5 * peak);
    assert!(
        (trailer - t_trailer).abs() < 0.04 && (0.44..=0.55).contains(&trailer),
        "trailer wheels at {trailer} s (geometry {t_trailer} s)"
    );
    // Peak longitudinal hitch force when the trailer hits the ramp: of the thesis's order
    // (~75 m/s^2 x 100 kg = 7.5 kN, read off its figure), within 40 % below to a third
    // above; the model gives 5.0 kN with the driveline inertia and every crossbeam mode
    // (docs/manoeuvres.md, docs/flex.md), 5.2 kN without them.
    let fx = ch("hitch_fx");
    let (k, peak) =
        fx.iter().enumerate().fold(
            (0, 0.0f64),
            |a, (k, v)| if v.abs() > a.1.abs() { (k, *v) } else { a },
        );
    assert!(
        (4.5e3..=10e3).contains(&peak.abs()),
        "peak hitch_fx {peak} N at {} s",
        t[k]
    );
    assert!((t[k] - trailer).abs() < 0.1, "peak at {} s", t[k]);
    // The driveline holds the speed within 1 km/h away from the obstacle.
    let speed = ch("speed");
    for (ti, v) in t.iter().zip(&speed) {
        if *ti < 0.05 || *ti > 1.5 {
            assert!((v - s.speed).abs() < 1.0 / 3.6, "speed {v} m/s at {ti} s");
        }
    }
    // At t = 0 the drawbar rests on the ball with the empty trailer's nose load.
    let nose = s.vehicle.design.trailer.as_ref().unwrap().empty_ball_load_n;
    assert!(
        (-ch("hitch_fz")[0] - nose).abs() < 0.02 * nose,
        "hitch_fz(0) {}",
        ch("hitch_fz")[0]
    );
}
