//! Free rolling on a flat road: the hub force stays below 1 N, and the effective rolling
//! radius V / Omega neither drifts nor departs from the Magic Formula's rolling-radius law
//! evaluated here from the .tir file's numbers (Pacejka 2012, sec. 4.3.2).

use std::path::Path;

use towride_mbs::road::Road;
use towride_mbs::tyre::rig::{rig_options, CleatRig, Spin};
use towride_mbs::tyre::{Tyre, TyreKind};

/// Starts with the rim spinning 2 % too fast (driving slip), lets it settle for 1 s, then
/// watches 2 s of free rolling.
fn free_rolling(file: &str, kind: TyreKind, load: f64, speed: f64) {
    let tyre = Tyre::from_file(Path::new(file), kind, &towride_mbs::input::Loader::new()).unwrap();
    let road = Road::from_file(
        Path::new(repo!("roads/flat.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let mut rig = CleatRig::new(tyre, road, speed, 0.0, load, Spin::Free, 0.6);
    rig.initial_spin_factor = 1.02;
    let opts = rig_options(&rig.tyre, 1e-6, &[1e-3]);
    let all = rig.run(3.0, 1e-3, &opts).unwrap();
    let first_fx = all.samples[0].long_force_n;
    let run = towride_mbs::tyre::rig::RigRun {
        samples: all
            .samples
            .iter()
            .filter(|s| s.t_s >= 1.0)
            .cloned()
            .collect(),
        ..all
    };
    let max_fx = run
        .samples
        .iter()
        .map(|s| s.hub_fx_n.abs().max(s.long_force_n.abs()))
        .fold(0.0, f64::max);
    let re: Vec<f64> = run.samples.iter().map(|s| speed / s.omega_rad_s).collect();
    let drift =
        re.iter().cloned().fold(f64::MIN, f64::max) - re.iter().cloned().fold(f64::MAX, f64::min);

    // MF rolling radius from the file: R_e = r0 Q_RE0 - rho0 (D atan(B rho/rho0) + F rho/rho0)
    // with rho0 = FNOMIN / Cz and the deflection rho = load / Cz (Q_V1 = 0 in these files).
    let v = |k: &str| crate::common::tir_value(file, "VERTICAL", k);
    let r0 = crate::common::tir_value(file, "DIMENSION", "UNLOADED_RADIUS");
    assert_eq!(v("Q_V1"), 0.0);
    let cz = v("VERTICAL_STIFFNESS");
    let rho0 = v("FNOMIN") / cz;
    let rd = load / cz / rho0;
    let re_ref = r0 * v("Q_RE0") - rho0 * (v("DREFF") * (v("BREFF") * rd).atan() + v("FREFF") * rd);
    let rel = re[re.len() - 1] / re_ref - 1.0;
    assert!(
        first_fx.abs() > 100.0,
        "the 2 % spin offset should start with a real force"
    );
    println!(
        "{file} {kind:?} at {speed} m/s, {load} N: Fx at start {first_fx:.0} N; after 1 s max |Fx| {max_fx:.2e} N, R_e = V/Omega {:.6} m (drift {drift:.1e} m over 2 s), MF law {re_ref:.6} m ({:+.3} %), {} steps",
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
    free_rolling(
        repo!("vehicles/tyres/car_185_60r14.tir"),
        TyreKind::RigidRing,
        3500.0,
        50.0 / 3.6,
    );
}

#[test]
fn trailer_tyre_rolls_freely() {
    free_rolling(
        repo!("vehicles/tyres/trailer_155_80r13.tir"),
        TyreKind::RigidRing,
        1500.0,
        50.0 / 3.6,
    );
}

#[test]
fn point_follower_rolls_freely() {
    free_rolling(
        repo!("vehicles/tyres/car_185_60r14.tir"),
        TyreKind::PointFollower,
        3500.0,
        50.0 / 3.6,
    );
}

/// Rolling slowly over the 50 mm step with the rim free: the effective plane tilts, the
/// rim load leans back with it (horizontal component -F_n sin(beta) of the normal force),
/// while the slip stays near zero: the slope rate enters the rolling speed, so turning the
/// effective plane creates no spurious longitudinal slip or tread force.
#[test]
fn slow_roll_over_a_step_makes_no_spurious_slip() {
    let tyre = Tyre::from_file(
        Path::new(repo!("vehicles/tyres/car_185_60r14.tir")),
        TyreKind::RigidRing,
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let road = Road::from_file(
        Path::new(repo!("roads/step_50mm.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let speed = 0.5;
    // Axle held 50 mm higher after the step is impossible on a cleat rig; use the quarter
    // rig (vertical freedom) with a guide damper so it climbs quasi-statically.
    let rig = towride_mbs::tyre::rig::QuarterRig::new(tyre, road, speed, 0.5, 350.0, 0.6, 20000.0);
    let opts = rig_options(&rig.tyre, 1e-6, &[1e-6, 1e-4, 1e-3]);
    let run = rig.run(None, 1.4, 1e-3, &opts).unwrap();
    let mut worst_slip: f64 = 0.0;
    let mut worst_lean: f64 = 0.0;
    let mut max_beta: f64 = 0.0;
    for s in &run.samples {
        let beta = s.effective_slope.atan();
        max_beta = max_beta.max(beta.abs());
        worst_slip = worst_slip.max(s.slip.abs());
        // Horizontal rim load against the tilt of the normal force.
        let lean = s.hub_fx_n + s.normal_force_n * beta.sin();
        worst_lean = worst_lean.max(lean.abs());
    }
    let fz_max = run
        .samples
        .iter()
        .map(|s| s.normal_force_n)
        .fold(0.0, f64::max);
    println!(
        "slow roll over the step: largest effective slope {:.1} deg, largest |slip| {worst_slip:.2e}, largest |Fx_hub + F_n sin(beta)| {worst_lean:.1} N (F_n up to {fz_max:.0} N)",
        max_beta.to_degrees()
    );
    assert!(max_beta.to_degrees() > 10.0, "the step was not climbed");
    assert!(worst_slip < 1e-3, "spurious slip {worst_slip}");
    assert!(
        worst_lean < 0.02 * fz_max,
        "rim load does not follow the tilted normal: {worst_lean} N"
    );
}

/// The rigid-ring tyre rolls over the CSV profile and the parry3d height field (the cams
/// work on any road type); its effective road follows each hump, filtered more on the
/// short 0.4 m hump of the profile than on the 1 m hump of the height field, and never
/// above the road.
#[test]
fn rolls_over_profile_and_height_field_roads() {
    for (file, peak, ratio) in [
        (repo!("roads/profile_example.toml"), 0.015, 0.8),
        (repo!("roads/height_field_example.toml"), 0.05, 0.95),
    ] {
        let tyre = Tyre::from_file(
            Path::new(repo!("vehicles/tyres/car_185_60r14.tir")),
            TyreKind::RigidRing,
            &towride_mbs::input::Loader::new(),
        )
        .unwrap();
        let road = Road::from_file(Path::new(file), &towride_mbs::input::Loader::new()).unwrap();
        let speed = 30.0 / 3.6;
        let rig =
            towride_mbs::tyre::rig::QuarterRig::new(tyre, road, speed, 0.0, 300.0, 0.6, 3000.0);
        let opts = rig_options(&rig.tyre, 1e-5, &[1e-6, 1e-4, 1e-3]);
        let run = rig.run(None, 4.0 / speed, 1e-3, &opts).unwrap();
        let w_max = run
            .samples
            .iter()
            .map(|s| s.effective_height_m)
            .fold(f64::MIN, f64::max);
        let road_max = run
            .samples
            .iter()
            .map(|s| rig.road.height(s.x_m, 0.0))
            .fold(f64::MIN, f64::max);
        println!(
            "{file}: {} steps, road peak under the centre {road_max:.4} m, effective height peak {w_max:.4} m",
            run.stats.steps
        );
        assert!((road_max - peak).abs() < 1e-3);
        assert!(
            w_max <= road_max + 1e-9 && w_max > ratio * road_max,
            "{w_max} vs {road_max}"
        );
    }
}
