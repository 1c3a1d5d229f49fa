//! The front axle's bump steer and camber gain: the design analysis (the strut's velocity
//! analysis, body held and bushings rigid) against the assembled multibody model, whose
//! wheels move when gravity is scaled about the value the springs were preloaded for, and
//! the bump steer against the range published for production front axles.

use towride_mbs::model::math::{mtv, mv, rot, sub};
use towride_mbs::model::statics::equilibrium;
use towride_mbs::model::system::System;
use towride_mbs::road::Road;
use towride_solver::SolverOptions;

use towride_app::vehicle::{self, Options};

/// Toe (toe-in positive) and camber (top out positive) [rad] of the knuckle of a left
/// wheel, and its wheel centre's height [m], all in the car body's axes.
fn toe_camber_height(sys: &System, y: &[f64], knuckle: &str, wheel: &str) -> (f64, f64, f64) {
    let index = |n: &str| {
        sys.model
            .bodies
            .iter()
            .position(|b| b.name == n)
            .unwrap_or_else(|| panic!("no body {n}"))
    };
    let (pb, qb) = sys.pose(y, index("car_body"));
    let (_, qk) = sys.pose(y, index(knuckle));
    let (pw, _) = sys.pose(y, index(wheel));
    let rb = rot(&qb);
    // The knuckle's spin axis (+y at the design position) in the body's axes.
    let a = mtv(&rb, &mv(&rot(&qk), &[0.0, 1.0, 0.0]));
    let h = mtv(&rb, &sub(&pw, &pb))[2];
    (a[0].atan2(a[1]), -a[2].asin(), h)
}

#[test]
fn front_bump_steer_and_camber_gain_of_the_model_match_the_design_analysis() {
    let mut v = vehicle::load(
        std::path::Path::new(repo!("vehicles/fabia.toml")),
        &Options::default(),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let fl = v
        .design
        .car_corners
        .iter()
        .find(|c| c.wheel == "fl")
        .unwrap()
        .clone();
    let fr = v
        .design
        .car_corners
        .iter()
        .find(|c| c.wheel == "fr")
        .unwrap();
    // Mirrored sides steer alike; production front axles toe out in bump by 2 to 10
    // deg/m (roll understeer; suspensiondesigner.com "KPI - Bump/Roll Steer", Wikipedia
    // "Bump steer"). The E90-scaled tie rod height gave -30.4 deg/m.
    assert!((fl.bump_steer_deg_m - fr.bump_steer_deg_m).abs() < 1e-9);
    assert!(
        (-10.0..=-2.0).contains(&fl.bump_steer_deg_m),
        "bump steer {} deg/m",
        fl.bump_steer_deg_m
    );
    // McPherson struts gain negative camber in bump.
    assert!(fl.camber_gain_deg_m < 0.0, "{}", fl.camber_gain_deg_m);

    // The multibody model at 0.9 g and 1.1 g: the springs were preloaded for 1 g, so
    // the body sinks and rises about the design position by some 15 mm at the front.
    // The tyres' lateral stiffness would hold the contact patch against the track change,
    // so the pads float.
    v = vehicle::load(
        std::path::Path::new(repo!("vehicles/fabia.toml")),
        &Options::default(),
        &crate::vehicle_statics::floating_pads(),
    )
    .unwrap();
    v.model.road = Some(Road::flat(0.0));
    let g = v.model.gravity;
    let at = |f: f64| {
        let mut m = v.model.clone();
        m.gravity = [g[0] * f, g[1] * f, g[2] * f];
        let sys = System::new(m);
        let st = equilibrium(&sys, 0.0, &SolverOptions::default()).unwrap();
        assert!(st.report.residual_force < 1e-6, "{:?}", st.report);
        toe_camber_height(&sys, &st.y, "knuckle_fl", "wheel_fl")
    };
    let (lo, hi) = (at(0.9), at(1.1));
    let rise = hi.2 - lo.2;
    assert!((0.01..0.03).contains(&rise), "travel {rise} m");
    let bump = ((hi.0 - lo.0) / rise).to_degrees();
    let camber = ((hi.1 - lo.1) / rise).to_degrees();
    // A central difference over the travel; the bushings' compliance under the changed
    // loads is the rest.
    assert!(
        (bump / fl.bump_steer_deg_m - 1.0).abs() < 0.05,
        "model {bump} deg/m against the design analysis {} deg/m",
        fl.bump_steer_deg_m
    );
    assert!(
        (camber / fl.camber_gain_deg_m - 1.0).abs() < 0.05,
        "model {camber} deg/m against the design analysis {} deg/m",
        fl.camber_gain_deg_m
    );
}
