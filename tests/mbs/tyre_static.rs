//! Static vertical stiffness and the drop test on the quarter rig: a wheel dropped on a flat
//! road bounces, then settles at the static deflection load / VERTICAL_STIFFNESS. The
//! references are the numbers in the .tir files, read here by a plain line scan.

use std::path::Path;

use towride_mbs::road::Road;
use towride_mbs::tyre::rig::{rig_options, QuarterRig, RigRun};
use towride_mbs::tyre::{Tyre, TyreKind};

const CAR: &str = repo!("vehicles/tyres/car_185_60r14.tir");
const TRAILER: &str = repo!("vehicles/tyres/trailer_155_80r13.tir");

fn drop(file: &str, kind: TyreKind, mass: f64, height: f64) -> (QuarterRig, RigRun) {
    let tyre = Tyre::from_file(Path::new(file), kind, &towride_mbs::input::Loader::new()).unwrap();
    let road = Road::from_file(
        Path::new(repo!("roads/flat.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    // A guide damper (drop-test carriage) so the run settles within seconds.
    let rig = QuarterRig::new(tyre, road, 0.0, 0.0, mass, 0.6, 1000.0);
    let opts = rig_options(&rig.tyre, 1e-7, &[1e-7, 1e-5, 1e-3]);
    let run = rig.run(Some(height), 10.0, 1e-3, &opts).unwrap();
    (rig, run)
}

/// Drops the wheel with two masses; the slope load / height change is the stiffness.
fn stiffness(file: &str, kind: TyreKind) {
    let cz = crate::common::tir_value(file, "VERTICAL", "VERTICAL_STIFFNESS");
    let r0 = crate::common::tir_value(file, "DIMENSION", "UNLOADED_RADIUS");
    let g = -crate::common::tir_value(file, "INERTIA", "GRAVITY");
    let belt = match kind {
        TyreKind::RigidRing => crate::common::tir_value(file, "INERTIA", "BELT_MASS"),
        TyreKind::PointFollower => 0.0,
    };
    let mut settled = Vec::new();
    for mass in [250.0, 350.0] {
        let (_, run) = drop(file, kind, mass, 0.10);
        let s = run.samples.last().unwrap();
        // Bounced: it left the road again after the first touch-down.
        let first = run
            .samples
            .iter()
            .position(|s| s.normal_force_n > 0.0)
            .unwrap();
        let touch = run.samples[first..]
            .iter()
            .position(|s| s.normal_force_n > 1000.0)
            .unwrap()
            + first;
        let airborne = run.samples[touch..]
            .iter()
            .filter(|s| s.normal_force_n == 0.0)
            .count();
        assert!(
            airborne > 0,
            "{file} {kind:?} {mass} kg: never left the road after landing"
        );
        // Settled: the last 0.5 s move less than 1 um.
        let tail: Vec<f64> = run.samples[run.samples.len() - 500..]
            .iter()
            .map(|s| s.z_m)
            .collect();
        let spread = tail.iter().cloned().fold(f64::MIN, f64::max)
            - tail.iter().cloned().fold(f64::MAX, f64::min);
        assert!(spread < 1e-6, "{file}: not settled, spread {spread}");
        let weight = (mass + belt) * g;
        let deflection = r0 - s.z_m;
        let expected = weight / cz;
        println!(
            "{file} {kind:?} {mass} kg: settled deflection {:.6} m, weight / Cz {:.6} m ({:+.3} %), {} steps, {} ms airborne after touch-down",
            deflection,
            expected,
            100.0 * (deflection / expected - 1.0),
            run.stats.steps,
            airborne
        );
        assert!(
            (deflection / expected - 1.0).abs() < 0.01,
            "{file}: deflection {deflection} vs {expected}"
        );
        settled.push((weight, s.z_m));
    }
    let k = (settled[1].0 - settled[0].0) / (settled[0].1 - settled[1].1);
    println!(
        "{file} {kind:?}: static stiffness {k:.1} N/m vs file {cz} N/m ({:+.4} %)",
        100.0 * (k / cz - 1.0)
    );
    assert!((k / cz - 1.0).abs() < 0.01, "{file}: stiffness {k} vs {cz}");
}

#[test]
fn car_tyre_static_stiffness_and_drop() {
    stiffness(CAR, TyreKind::RigidRing);
}

#[test]
fn trailer_tyre_static_stiffness_and_drop() {
    stiffness(TRAILER, TyreKind::RigidRing);
}

#[test]
fn point_follower_static_stiffness_and_drop() {
    stiffness(CAR, TyreKind::PointFollower);
}
