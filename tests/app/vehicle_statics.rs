//! The assembled vehicles at rest and linearised: wheel loads carry the weight, ride
//! heights are the design ones, the trailer's nose load follows its centre of mass, and
//! the car's body and wheel-hop frequencies lie in the passenger-car bands (body 1-1.8 Hz,
//! wheel hop below 40 Hz) and near the
//! classical half-car and quarter-car estimates made from the design data.

use std::path::Path;

use towride_app::scene::channels;
use towride_app::vehicle::{self, Options, Vehicle};
use towride_mbs::model::linear::linearise;
use towride_mbs::model::output::{channels_of, evaluate};
use towride_mbs::model::statics::equilibrium;
use towride_mbs::model::system::{ExtKind, System};
use towride_mbs::road::Road;
use towride_solver::SolverOptions;

/// A vehicle file at rest on a flat road: the vehicle, its system and the equilibrium.
pub(crate) fn at_rest(file: &str, case: Option<&str>) -> (Vehicle, System, Vec<f64>, Vec<f64>) {
    at_rest_with(file, case, &towride_mbs::input::Loader::new())
}

/// [`at_rest`] with the files read through `loader` (its overrides applied).
pub(crate) fn at_rest_with(
    file: &str,
    case: Option<&str>,
    loader: &towride_mbs::input::Loader,
) -> (Vehicle, System, Vec<f64>, Vec<f64>) {
    let mut v = vehicle::load(
        Path::new(file),
        &Options {
            load_case: case.map(String::from),
            ..Default::default()
        },
        loader,
    )
    .unwrap();
    v.model.road = Some(Road::flat(0.0));
    v.model.outputs = channels::standard(&v).0;
    let sys = System::new(v.model.clone());
    let st = equilibrium(&sys, 0.0, &SolverOptions::default()).unwrap();
    assert!(st.report.residual_force < 1e-6, "{:?}", st.report);
    (v, sys, st.y, st.yp)
}

/// The car's tyres on floating pads: their lateral stiffness at the least the file's
/// bounds accept (1e3 N/m, 1/86 of the tyre's), so the contact patch follows the track
/// change as on a ride-frequency or kinematics rig.
pub(crate) fn floating_pads() -> towride_mbs::input::Loader {
    towride_mbs::input::Loader::with_overrides(vec![towride_mbs::input::Override::program(
        "car_185_60r14.tir",
        "STRUCTURAL.LATERAL_STIFFNESS",
        "1e3",
        "floating pads",
    )])
}

/// Normal force of every tyre [N], by wheel name.
pub(crate) fn tyre_loads(sys: &System, y: &[f64]) -> Vec<(String, f64)> {
    let (_, ov, ol, _) = sys.offsets();
    let (q, vel) = (&y[..ov], &y[ov..ol]);
    let road = sys.model.road.as_ref().unwrap();
    sys.ext
        .iter()
        .filter_map(|e| match e.kind {
            ExtKind::Tyre(k) => {
                let t = &sys.model.tyres[k];
                let kin = sys.wheel_kinematics(q, vel, t.marker);
                let x = &y[sys.oe() + e.off..sys.oe() + e.off + e.n];
                Some((t.name.clone(), t.tyre.outputs(&kin, road, x).normal_force))
            }
            _ => None,
        })
        .collect()
}

#[test]
fn car_rests_on_its_design_loads_at_its_design_ride_heights() {
    let (v, sys, y, _) = at_rest(repo!("vehicles/fabia.toml"), None);
    let g = 9.81;
    let loads = tyre_loads(&sys, &y);
    let sum: f64 = loads.iter().map(|l| l.1).sum();
    let weight = v.design.total_mass_kg * g;
    assert!((sum - weight).abs() < 1e-3 * weight, "{sum} vs {weight}");
    for (name, f) in &loads {
        let d = v
            .design
            .car_corners
            .iter()
            .find(|c| format!("tyre_{}", c.wheel) == *name)
            .unwrap();
        assert!(
            (f - d.load_n).abs() < 5e-3 * d.load_n,
            "{name}: {f} vs design {}",
            d.load_n
        );
    }
    // Ride height: body point above each wheel minus the wheel centre, vertically, against
    // the same distance in the design (initial) position.
    let (_, ov, _, _) = sys.offsets();
    let q = &y[..ov];
    let (q0, _) = sys.initial_q_v();
    for (w, mk) in &v.handles.ride {
        let wc = v
            .handles
            .wheels
            .iter()
            .find(|x| &x.name == w)
            .unwrap()
            .centre;
        let h = |q: &[f64]| sys.marker_frame(q, *mk).origin[2] - sys.marker_frame(q, wc).origin[2];
        let (now, design) = (h(q), h(&q0));
        assert!(
            (now - design).abs() < 1e-3,
            "{w}: ride height {now:.5} m, design {design:.5} m"
        );
    }
}

#[test]
fn trailer_nose_load_follows_each_load_case() {
    let tf: toml::Table = std::fs::read_to_string(repo!("vehicles/trailer/box_trailer.toml"))
        .unwrap()
        .parse()
        .unwrap();
    let axle_x = tf["hardpoints"]["wheel_centre_m"][0].as_float().unwrap();
    let g = 9.81;
    let mut nose = Vec::new();
    for case in [
        "empty",
        "200kg_over_axle",
        "200kg_ahead_of_axle",
        "200kg_behind_axle",
    ] {
        let (v, sys, y, yp) = at_rest(repo!("vehicles/fabia_trailer.toml"), Some(case));
        let sum: f64 = tyre_loads(&sys, &y).iter().map(|l| l.1).sum();
        let weight = v.design.total_mass_kg * g;
        assert!(
            (sum - weight).abs() < 1e-3 * weight,
            "{case}: {sum} vs {weight}"
        );
        // Ball load from the trailer's centre of mass, a lever between the ball and the
        // axle in the static (deformed) position: the trailer sinks and pitches when
        // loaded, which moves its centre of mass relative to the axle.
        let (_, ov, _, _) = sys.offsets();
        let q = &y[..ov];
        let place = v.handles.trailer_place.unwrap();
        let (mut m, mut mx) = (0.0, 0.0);
        for (b, body) in v.model.bodies.iter().enumerate() {
            if v.handles.body_place[b] == place {
                m += body.mass;
                mx += body.mass * sys.pose(q, b).0[0];
            }
        }
        let wheels: Vec<_> = v
            .handles
            .wheels
            .iter()
            .filter(|w| w.name.starts_with('t'))
            .collect();
        let mut axle = 0.0;
        for w in &wheels {
            let belt = v.model.tyres[w.tyre].tyre.params().belt_mass;
            let x = sys.marker_frame(q, w.centre).origin[0];
            m += belt;
            mx += belt * x;
            axle += x / wheels.len() as f64;
        }
        let ball = sys
            .marker_frame(q, v.model.marker_by_name("ball_coupling.i").unwrap())
            .origin[0];
        let want = m * g * (mx / m - axle) / (ball - axle);
        let chans = channels_of(&sys.model);
        let vals = evaluate(&sys, 0.0, &y, &yp);
        let fz = vals[chans.iter().position(|c| c.name == "hitch_fz").unwrap()];
        // The drawbar pushes the car down by the nose load.
        assert!(
            (-fz - want).abs() < 1e-3 * want.abs() + 0.5,
            "{case}: hitch_fz {fz} N, lever {want} N"
        );
        // At the design geometry the files' centre of mass gives it within a kilogram.
        let t = v.design.trailer.as_ref().unwrap();
        let design = t.mass_kg * g * (t.cm_m[0] - axle_x) / (0.0 - axle_x);
        assert!(
            (-fz - design).abs() < g,
            "{case}: hitch_fz {fz} N, design lever {design} N"
        );
        nose.push(-fz);
    }
    // Ahead of the axle loads the ball more than over it, behind it lifts the ball.
    assert!(
        nose[2] > nose[1] && nose[1] > nose[3] && nose[3] < 0.0,
        "{nose:?}"
    );
}

/// Frequencies [Hz] of the half car (bounce z, pitch theta) from the design data:
/// ride rates of the axles (wheel rate in series with the tyre), sprung mass and the
/// body's pitch inertia (about the sprung centre of mass).
fn half_car(v: &Vehicle) -> (f64, f64) {
    let cz = crate::common::tir_value(
        repo!("vehicles/tyres/car_185_60r14.tir"),
        "VERTICAL",
        "VERTICAL_STIFFNESS",
    );
    let c = &v.design.car_corners;
    let ride = |k: usize| 2.0 * c[k].wheel_rate_n_m * cz / (c[k].wheel_rate_n_m + cz);
    let (kf, kr) = (ride(0), ride(2));
    let unsprung: f64 = c.iter().map(|x| x.unsprung_kg).sum();
    let m = v.design.car_mass_kg - unsprung;
    // Sprung centre of mass: the car's less the unsprung masses at the axles.
    let xr = v.handles.wheels[2].design_centre[0];
    let xs = (v.design.car_mass_kg * v.design.car_cm_m[0] - 2.0 * c[2].unsprung_kg * xr) / m;
    let (a, b) = (-xs, xs - xr);
    let body = &v.model.bodies[v.handles.car_body];
    let hitch = &v.model.bodies[v.handles.hitch.as_ref().unwrap().body];
    let mut iyy = body.inertia[1][1]
        + body.mass * (body.position[0] - xs).powi(2)
        + hitch.inertia[1][1]
        + hitch.mass * (hitch.position[0] - xs).powi(2);
    if let Some(e) = v.model.bodies.iter().find(|b| b.name == "engine") {
        iyy += e.inertia[1][1] + e.mass * (e.position[0] - xs).powi(2);
    }
    let k = nalgebra::Matrix2::new(
        kf + kr,
        kr * b - kf * a,
        kr * b - kf * a,
        kf * a * a + kr * b * b,
    );
    let minv = nalgebra::Matrix2::new(1.0 / m, 0.0, 0.0, 1.0 / iyy);
    let e = (minv * k).eigenvalues().unwrap();
    let f = |l: f64| l.sqrt() / (2.0 * std::f64::consts::PI);
    let (f1, f2) = (f(e[0]), f(e[1]));
    (f1.min(f2), f1.max(f2))
}

#[test]
fn car_body_and_wheel_hop_frequencies() {
    // On floating pads, as a ride-frequency rig measures: at rest the tyre's lateral
    // stiffness resists the McPherson's track change and stiffens the front (bounce
    // 1.42 -> 1.48 Hz), which the half-car estimate (wheel rate and tyre rate in series)
    // leaves out; rolling, the lateral slip relaxes that resistance.
    let (v, sys, y, _) = at_rest_with(repo!("vehicles/fabia.toml"), None, &floating_pads());
    let lin = linearise(&sys, 0.0, &y).unwrap();
    let unsprung = |n: &str| {
        ["wheel_", "knuckle_", "arm_", "lca_"]
            .iter()
            .any(|p| n.starts_with(p))
    };
    // Body modes: the car body dominates, lightly damped, above the rigid-body and
    // tyre-slip roots. The tyres' lateral stiffness couples the body's lateral, roll and
    // yaw motions at rest (sway about 1.4 Hz, yaw about 2.3 Hz, roll about 3.4 Hz): the
    // half-car estimate is for the modes in the vertical plane, bounce and pitch.
    let share = |m: &towride_mbs::model::linear::Mode, dirs: &[&str]| -> f64 {
        m.motions
            .iter()
            .filter(|s| dirs.iter().any(|d| s.name == format!("car_body {d}")))
            .map(|s| s.share)
            .sum()
    };
    let body_modes: Vec<&towride_mbs::model::linear::Mode> = lin
        .modes
        .iter()
        .filter(|m| m.undamped_hz > 0.8 && m.undamped_hz < 4.0 && m.damping_ratio < 0.5)
        .filter(|m| {
            // At 1-2 Hz the engine moves with the body on its 6-10 Hz mounts: both
            // together are the sprung mass.
            let sprung: f64 = m
                .bodies
                .iter()
                .filter(|b| b.name == "car_body" || b.name == "engine")
                .map(|b| b.share)
                .sum();
            m.bodies.first().is_some_and(|b| b.name == "car_body") && sprung > 0.8
        })
        .collect();
    let body: Vec<f64> = body_modes
        .iter()
        .filter(|m| share(m, &["bounce", "pitch"]) > share(m, &["lateral", "roll", "yaw"]))
        .map(|m| m.undamped_hz)
        .collect();
    assert_eq!(body.len(), 2, "bounce, pitch: {body:?}");
    // Roll stays a body mode, on the springs and the tyres' lateral stiffness.
    assert!(
        body_modes
            .iter()
            .any(|m| m.motions.first().is_some_and(|s| s.name == "car_body roll")),
        "no roll-dominated body mode below 4 Hz"
    );
    let (lo, hi) = half_car(&v);
    for (f, est) in body.iter().take(2).zip([lo, hi]) {
        assert!((1.0..=1.8).contains(f), "body mode {f} Hz");
        assert!(
            (f - est).abs() < 0.1 * est,
            "body mode {f} Hz, half-car estimate {est} Hz"
        );
    }
    // Wheel hop (below 40 Hz; bushing modes lie higher): unsprung parts move, the
    // suspension springs (or the twist beam) store the energy; two per axle (in phase,
    // in antiphase).
    let hop: Vec<f64> = lin
        .modes
        .iter()
        // Zero roots (free motions) have arbitrary shapes: no vibration.
        .filter(|m| m.kind != towride_mbs::model::linear::RootKind::Zero)
        .filter(|m| m.undamped_hz < 40.0)
        .filter(|m| m.bodies.first().is_some_and(|b| unsprung(&b.name)))
        .filter(|m| {
            m.elements
                .first()
                .is_some_and(|e| e.name.starts_with("spring_") || e.name.starts_with("twist_beam"))
        })
        .map(|m| m.undamped_hz)
        .collect();
    assert_eq!(hop.len(), 4, "{hop:?}");
    for f in &hop {
        assert!((9.0..=16.0).contains(f), "wheel hop {f} Hz");
    }
    // Quarter car, in phase: tyre and wheel rate on the unsprung mass.
    let cz = crate::common::tir_value(
        repo!("vehicles/tyres/car_185_60r14.tir"),
        "VERTICAL",
        "VERTICAL_STIFFNESS",
    );
    for c in &v.design.car_corners {
        let est = ((cz + c.wheel_rate_n_m) / c.unsprung_kg).sqrt() / (2.0 * std::f64::consts::PI);
        assert!(
            hop.iter().any(|f| (f - est).abs() < 0.1 * est),
            "{}: estimate {est} Hz, modes {hop:?}",
            c.wheel
        );
    }
}
