//! The tyres' low-speed damping (Pacejka, "Tire and Vehicle Dynamics", 3rd ed. 2012,
//! sec. 7.2.2): at a standstill the relaxation states are undamped springs, so below VXLOW
//! the slips take a term proportional to the sliding velocity, which in the linear range
//! adds -k_Vlow V to the force, k_Vlow = 1/2 k_Vlow0 (1 + cos(pi |V_x| / VXLOW)) and here
//! k_Vlow0 = DAMP_VLOW x LONGITUDINAL_STIFFNESS (LATERAL_STIFFNESS sideways). The
//! references are the .tir file's numbers, read by a plain line scan.

use std::path::Path;

use nalgebra::Vector3;
use towride_mbs::input::Loader;
use towride_mbs::road::Road;
use towride_mbs::tyre::{ContactOutputs, Tyre, TyreKind, WheelKinematics};

const CAR: &str = repo!("vehicles/tyres/car_185_60r14.tir");
const TRAILER: &str = repo!("vehicles/tyres/trailer_155_80r13.tir");
const REFERENCE: &str = repo!("vehicles/tyres/reference_205_60r15_tvd3.tir");

fn flat() -> Road {
    Road::from_file(Path::new(repo!("roads/flat.toml")), &Loader::new()).unwrap()
}

fn value(file: &str, section: &str, key: &str) -> f64 {
    crate::common::tir_value(file, section, key)
}

/// Contact forces of a wheel resting at its nominal load, its tread undeflected, while the
/// rim (not spinning) and the ring slide at `velocity` over the road.
fn sliding(file: &str, kind: TyreKind, velocity: Vector3<f64>) -> ContactOutputs {
    let t = Tyre::from_file(Path::new(file), kind, &Loader::new()).unwrap();
    let p = t.params().clone();
    let road = flat();
    let z = p.r0 - p.fnomin / p.cz;
    let rest = WheelKinematics::upright(Vector3::new(0.0, 0.0, z), Vector3::zeros(), 0.0);
    let mut x = t.initial_state(&rest, &road);
    let names = t.state_names();
    let at = |n: &str| names.iter().position(|s| s == n);
    // The ring moves with the rim (no sidewall deflection rate).
    if let Some(i) = at("ring_vx_m_s") {
        x[i] = velocity.x;
    }
    for n in ["tread_u_m", "tread_v_m", "residual_u_m"] {
        if let Some(i) = at(n) {
            x[i] = 0.0;
        }
    }
    let kin = WheelKinematics::upright(Vector3::new(0.0, 0.0, z), velocity, 0.0);
    t.outputs(&kin, &road, &x)
}

#[test]
fn below_vxlow_a_sliding_tyre_is_damped_by_damp_vlow_times_its_stiffness() {
    for (file, kind) in [
        (CAR, TyreKind::RigidRing),
        (CAR, TyreKind::PointFollower),
        (TRAILER, TyreKind::RigidRing),
    ] {
        let damp = value(file, "STRUCTURAL", "DAMP_VLOW");
        let cx = value(file, "STRUCTURAL", "LONGITUDINAL_STIFFNESS");
        let cy = value(file, "STRUCTURAL", "LATERAL_STIFFNESS");
        let vxlow = value(file, "MODEL", "VXLOW");
        assert!(damp > 0.0 && vxlow > 0.0);
        let weight = |v: f64| 0.5 * (1.0 + (std::f64::consts::PI * v / vxlow).cos());
        // Slow enough to stay in the Magic Formula's linear range (kappa ~ 1e-5).
        for v in [0.002, 0.25 * vxlow, 0.5 * vxlow] {
            let o = sliding(file, kind, Vector3::new(v, 0.0, 0.0));
            let want = -damp * cx * weight(v) * v;
            assert!(
                (o.longitudinal_force / want - 1.0).abs() < 2e-3,
                "{file} {kind:?} at {v} m/s: F_x {} N, want {want} N",
                o.longitudinal_force
            );
            // Sideways, ISO: the contact point moving left (+y) is pushed right.
            let s = 0.1 * v;
            let o = sliding(file, kind, Vector3::new(0.0, s, 0.0));
            let want = -damp * cy * s;
            assert!(
                (o.lateral_force / want - 1.0).abs() < 2e-3,
                "{file} {kind:?} sideways at {s} m/s: F_y {} N, want {want} N",
                o.lateral_force
            );
        }
        // Rolling speed: the damping is gone, the undeflected tread carries no force.
        let o = sliding(file, kind, Vector3::new(1.01 * vxlow, 0.0, 0.0));
        assert!(
            o.longitudinal_force.abs() < 1e-9,
            "{file} {kind:?} above VXLOW: {}",
            o.longitudinal_force
        );
    }
}

#[test]
fn a_file_without_damp_vlow_has_no_low_speed_damping() {
    // The TVD3 reference file (OpenTire) carries neither DAMP_VLOW nor VXLOW.
    let text = std::fs::read_to_string(REFERENCE).unwrap();
    assert!(!text.contains("DAMP_VLOW") && !text.contains("VXLOW"));
    for kind in [TyreKind::RigidRing, TyreKind::PointFollower] {
        // Its Magic Formula has shifts (a force at zero slip): compare with the resting tyre.
        let rest = sliding(REFERENCE, kind, Vector3::zeros());
        let o = sliding(REFERENCE, kind, Vector3::new(0.01, 0.0, 0.0));
        assert_eq!(o.longitudinal_force, rest.longitudinal_force, "{kind:?}");
        let o = sliding(REFERENCE, kind, Vector3::new(0.0, 0.01, 0.0));
        assert_eq!(o.lateral_force, rest.lateral_force, "{kind:?}");
    }
}

#[test]
fn damp_vlow_without_vxlow_is_refused_naming_the_key() {
    let text = std::fs::read_to_string(CAR).unwrap();
    let cut: String = text
        .lines()
        .filter(|l| !l.starts_with("VXLOW"))
        .map(|l| format!("{l}\n"))
        .collect();
    let dir = std::env::temp_dir().join(format!("towride_vxlow_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("no_vxlow.tir");
    std::fs::write(&f, cut).unwrap();
    let e = Tyre::from_file(&f, TyreKind::RigidRing, &Loader::new()).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("MODEL.VXLOW"), "{msg}");
}
