//! Free rolling on a flat road: the hub force stays below 1 N, and the effective rolling
//! radius V / Omega neither drifts nor departs from the Magic Formula's rolling-radius law
//! evaluated here from the .tir file's numbers (Pacejka 2012, sec. 4.3.2).

mod common;

use std::path::Path;

use towride::road::Road;
use towride::tyre::rig::{rig_options, CleatRig, Spin};
use towride::tyre::{Tyre, TyreKind};

fn free_rolling(file: &str, kind: TyreKind, load: f64, speed: f64) {
    let tyre = Tyre::from_file(Path::new(file), kind).unwrap();
    let road = Road::from_file(Path::new("roads/flat.toml")).unwrap();
    let rig = CleatRig::new(tyre, road, speed, 0.0, load, Spin::Free, 0.6);
    let opts = rig_options(&rig.tyre, 1e-6, &[1e-3]);
    let run = rig.run(2.0, 1e-3, &opts).unwrap();
    let max_fx = run.samples.iter().map(|s| s.hub_fx_n.abs().max(s.long_force_n.abs())).fold(0.0, f64::max);
    let re: Vec<f64> = run.samples.iter().map(|s| speed / s.omega_rad_s).collect();
    let drift = re.iter().cloned().fold(f64::MIN, f64::max) - re.iter().cloned().fold(f64::MAX, f64::min);

    // MF rolling radius from the file: R_e = r0 Q_RE0 - rho0 (D atan(B rho/rho0) + F rho/rho0)
    // with rho0 = FNOMIN / Cz and the deflection rho = load / Cz (Q_V1 = 0 in these files).
    let v = |k: &str| common::tir_value(file, "VERTICAL", k);
    let r0 = common::tir_value(file, "DIMENSION", "UNLOADED_RADIUS");
    assert_eq!(v("Q_V1"), 0.0);
    let cz = v("VERTICAL_STIFFNESS");
    let rho0 = v("FNOMIN") / cz;
    let rd = load / cz / rho0;
    let re_ref = r0 * v("Q_RE0") - rho0 * (v("DREFF") * (v("BREFF") * rd).atan() + v("FREFF") * rd);
    let rel = re[re.len() - 1] / re_ref - 1.0;
    println!(
        "{file} {kind:?} at {speed} m/s, {load} N: max |Fx| {max_fx:.2e} N, R_e = V/Omega {:.6} m (drift {drift:.1e} m over 2 s), MF law {re_ref:.6} m ({:+.3} %), {} steps",
        re[re.len() - 1],
        100.0 * rel,
        run.stats.steps
    );
    assert!(max_fx < 1.0, "|Fx| = {max_fx} N");
    assert!(drift < 1e-7, "rolling radius drifts by {drift} m");
    // The ring's own weight shifts the rigid ring's deflection by m_b g / c_b (~40 um).
    assert!(rel.abs() < 1e-3, "R_e {} vs {re_ref}", re[re.len() - 1]);
}

#[test]
fn car_tyre_rolls_freely() {
    free_rolling("vehicles/tyres/car_185_60r14.tir", TyreKind::RigidRing, 3500.0, 50.0 / 3.6);
}

#[test]
fn trailer_tyre_rolls_freely() {
    free_rolling("vehicles/tyres/trailer_155_80r13.tir", TyreKind::RigidRing, 1500.0, 50.0 / 3.6);
}

#[test]
fn point_follower_rolls_freely() {
    free_rolling("vehicles/tyres/car_185_60r14.tir", TyreKind::PointFollower, 3500.0, 50.0 / 3.6);
}
