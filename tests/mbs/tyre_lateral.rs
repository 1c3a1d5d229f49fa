//! Lateral tyre forces: the side-slip rig (`tyre::rig_lateral`) against
//! (a) the Magic Formula 6.1 written out again here, independently of the crate, from
//!     Pacejka, "Tire and Vehicle Dynamics" 3rd ed. 2012, sec. 4.3.2 ((4.E9)-(4.E78),
//!     zero camber, nominal pressure, no turn slip), with the coefficients read here from
//!     the .tir text, and
//! (b) MFeval (Marco Furlan's MF 5.2/6.1/6.2 evaluator) run on the TVD3 reference tyre,
//!     tabulated in scenes/tyre_rigs/reference/mfeval_tvd3.csv (its header says how);
//! and the step response in slip angle against the first-order law with the relaxation
//! length sigma_alpha = |K_ya(FNOMIN)| / LATERAL_STIFFNESS (Pacejka 2012 sec. 7.2).

use std::collections::HashMap;
use std::path::Path;

use nalgebra::Vector3;
use towride_mbs::input::Loader;
use towride_mbs::road::Road;
use towride_mbs::tyre::rig::{rig_options, Spin};
use towride_mbs::tyre::rig_lateral::{read_reference, LateralRig};
use towride_mbs::tyre::{Tyre, TyreKind, WheelKinematics};

const CAR: &str = repo!("vehicles/tyres/car_185_60r14.tir");
const TRAILER: &str = repo!("vehicles/tyres/trailer_155_80r13.tir");
const REFERENCE: &str = repo!("vehicles/tyres/reference_205_60r15_tvd3.tir");
const MFEVAL: &str = repo!("scenes/tyre_rigs/reference/mfeval_tvd3.csv");

/// The numeric keys of a .tir file (every key name is unique among the numeric ones).
fn tir_numbers(path: &str) -> HashMap<String, f64> {
    let mut m = HashMap::new();
    for line in std::fs::read_to_string(path).unwrap().lines() {
        let body = line.split(['$', '!']).next().unwrap();
        if let Some((k, v)) = body.split_once('=') {
            if let Ok(x) = v.trim().parse::<f64>() {
                m.insert(k.trim().to_string(), x);
            }
        }
    }
    m
}

/// Magic Formula 6.1 at zero camber, written out from the book; returns (F_x, F_y, M_z).
fn mf61(p: &HashMap<String, f64>, fz: f64, kappa: f64, alpha: f64) -> (f64, f64, f64) {
    let g = |k: &str| *p.get(k).unwrap_or_else(|| panic!("{k} missing"));
    let l = |k: &str| *p.get(k).unwrap_or(&1.0);
    let sgn = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
    let fz0 = g("FNOMIN") * l("LFZO");
    let r0 = g("UNLOADED_RADIUS");
    let dfz = (fz - fz0) / fz0;
    let prime = |lam: f64| 10.0 * lam / (1.0 + 9.0 * lam); // (4.E8), A_mu = 10
                                                           // (4.E9)-(4.E18)
    let kx = kappa + (g("PHX1") + g("PHX2") * dfz) * l("LHX");
    let cx = g("PCX1") * l("LCX");
    let dx = (g("PDX1") + g("PDX2") * dfz) * l("LMUX") * fz;
    let kxk = fz * (g("PKX1") + g("PKX2") * dfz) * (g("PKX3") * dfz).exp() * l("LKX");
    let ex = ((g("PEX1") + g("PEX2") * dfz + g("PEX3") * dfz * dfz)
        * (1.0 - g("PEX4") * sgn(kx))
        * l("LEX"))
    .min(1.0);
    let bx = kxk / (cx * dx);
    let svx = fz * (g("PVX1") + g("PVX2") * dfz) * l("LVX") * prime(l("LMUX"));
    let fx0 = dx * (cx * (bx * kx - ex * (bx * kx - (bx * kx).atan())).atan()).sin() + svx;
    // (4.E19)-(4.E30)
    let kya = g("PKY1") * fz0 * (g("PKY4") * (fz / (g("PKY2") * fz0)).atan()).sin() * l("LKY");
    let shy = (g("PHY1") + g("PHY2") * dfz) * l("LHY");
    let svy = fz * (g("PVY1") + g("PVY2") * dfz) * l("LVY") * prime(l("LMUY"));
    let ay = alpha + shy;
    let cy = g("PCY1") * l("LCY");
    let muy = (g("PDY1") + g("PDY2") * dfz) * l("LMUY");
    let dy = muy * fz;
    let ey = ((g("PEY1") + g("PEY2") * dfz) * (1.0 - g("PEY3") * sgn(ay)) * l("LEY")).min(1.0);
    let by = kya / (cy * dy);
    let fy0 = dy * (cy * (by * ay - ey * (by * ay - (by * ay).atan())).atan()).sin() + svy;
    // (4.E50)-(4.E57)
    let w =
        |b: f64, c: f64, e: f64, x: f64| (c * (b * x - e * (b * x - (b * x).atan())).atan()).cos();
    let bxa = g("RBX1") * (g("RBX2") * kappa).atan().cos() * l("LXAL");
    let exa = (g("REX1") + g("REX2") * dfz).min(1.0);
    let fx = fx0 * w(bxa, g("RCX1"), exa, alpha + g("RHX1")) / w(bxa, g("RCX1"), exa, g("RHX1"));
    // (4.E58)-(4.E67)
    let dvyk = muy * fz * (g("RVY1") + g("RVY2") * dfz) * (g("RVY4") * alpha).atan().cos();
    let svyk = dvyk * (g("RVY5") * (g("RVY6") * kappa).atan()).sin() * l("LVYKA");
    let shyk = g("RHY1") + g("RHY2") * dfz;
    let byk = g("RBY1") * (g("RBY2") * (alpha - g("RBY3"))).atan().cos() * l("LYKA");
    let eyk = (g("REY1") + g("REY2") * dfz).min(1.0);
    let fy = fy0 * w(byk, g("RCY1"), eyk, kappa + shyk) / w(byk, g("RCY1"), eyk, shyk) + svyk;
    // (4.E31)-(4.E49), (4.E71)-(4.E78), tan form of the equivalent slips (MF-Tyre 6.1)
    let at = alpha + g("QHZ1") + g("QHZ2") * dfz;
    let ar = alpha + shy + svy / kya;
    let bt = (g("QBZ1") + g("QBZ2") * dfz + g("QBZ3") * dfz * dfz) * l("LKY") / l("LMUY");
    let ct = g("QCZ1");
    let dt = fz * (r0 / fz0) * (g("QDZ1") + g("QDZ2") * dfz) * l("LTR");
    let et = ((g("QEZ1") + g("QEZ2") * dfz + g("QEZ3") * dfz * dfz)
        * (1.0 + g("QEZ4") * 2.0 / std::f64::consts::PI * (bt * ct * at).atan()))
    .min(1.0);
    let br = g("QBZ9") * l("LKY") / l("LMUY") + g("QBZ10") * by * cy;
    let dr = fz * r0 * (g("QDZ6") + g("QDZ7") * dfz) * l("LRES") * l("LMUY") * alpha.cos();
    let q = (kxk / kya * kappa).powi(2);
    let at_eq = (at.tan().powi(2) + q).sqrt().atan() * sgn(at);
    let ar_eq = (ar.tan().powi(2) + q).sqrt().atan() * sgn(ar);
    let t = dt
        * (ct * (bt * at_eq - et * (bt * at_eq - (bt * at_eq).atan())).atan()).cos()
        * alpha.cos();
    let mzr = dr * (br * ar_eq).atan().cos();
    let s = r0 * (g("SSZ1") + g("SSZ2") * fy / fz0) * l("LS");
    (fx, fy, -t * (fy - svyk) + mzr + s * fx)
}

fn flat() -> Road {
    Road::from_file(Path::new(repo!("roads/flat.toml")), &Loader::new()).unwrap()
}

fn tyre(file: &str, kind: TyreKind) -> Tyre {
    Tyre::from_file(Path::new(file), kind, &Loader::new()).unwrap()
}

/// Runs the rig at (load, alpha) for `t` seconds from its steady state; returns the last
/// sample.
fn steady(
    file: &str,
    kind: TyreKind,
    speed: f64,
    load: f64,
    alpha: f64,
) -> towride_mbs::tyre::rig::RigSample {
    let rig = LateralRig::new(
        tyre(file, kind),
        flat(),
        speed,
        alpha,
        0.0,
        load,
        Spin::Driven,
        0.4,
    );
    let opts = rig_options(&rig.tyre, 1e-7, &[1e-3]);
    rig.run(0.4, 0.4, &opts).unwrap().samples.pop().unwrap()
}

#[test]
fn steady_side_slip_matches_the_formula_written_out_here() {
    let deg = [-12.0, -6.0, -3.0, -1.0, 0.0, 0.5, 2.0, 5.0, 10.0];
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for (file, loads) in [
        (CAR, [2000.0, 3500.0, 5000.0]),
        (TRAILER, [500.0, 1500.0, 2500.0]),
        (REFERENCE, [2000.0, 4000.0, 6000.0]),
    ] {
        let p = tir_numbers(file);
        for kind in [TyreKind::RigidRing, TyreKind::PointFollower] {
            for load in loads {
                for a in deg {
                    let alpha = f64::to_radians(a);
                    let s = steady(file, kind, 13.9, load, alpha);
                    // The rig reaches the slip angle it was set to...
                    assert!(
                        (s.slip_angle_rad - alpha).abs() < 1e-9,
                        "{file} {a}: {}",
                        s.slip_angle_rad
                    );
                    // ... and its forces are the formula's at its own state (normal force,
                    // longitudinal slip kappa' and slip angle alpha').
                    let (fx, fy, mz) = mf61(&p, s.normal_force_n, s.slip, s.slip_angle_rad);
                    let (dx, dy, dm) = (
                        (s.long_force_n - fx).abs(),
                        (s.lateral_force_n - fy).abs(),
                        (s.aligning_moment_n_m - mz).abs(),
                    );
                    assert!(
                        dy <= 1e-6 * fy.abs().max(1.0),
                        "{file} {kind:?} {load} N {a} deg: Fy {} vs {fy}",
                        s.lateral_force_n
                    );
                    assert!(
                        dm <= 1e-6 * mz.abs().max(1.0),
                        "{file} {kind:?} {load} N {a} deg: Mz {} vs {mz}",
                        s.aligning_moment_n_m
                    );
                    assert!(
                        dx <= 1e-6 * fx.abs().max(1.0),
                        "{file} {kind:?} {load} N {a} deg: Fx {} vs {fx}",
                        s.long_force_n
                    );
                    // The rig holds the load and zero longitudinal slip (driven rim).
                    assert!(
                        (s.normal_force_n - load).abs() < 5e-5 * load,
                        "{file} {load}: {}",
                        s.normal_force_n
                    );
                    worst = (worst.0.max(dx), worst.1.max(dy), worst.2.max(dm));
                }
            }
        }
    }
    eprintln!(
        "rig vs formula written out here: |dFx| {:.2e} N, |dFy| {:.2e} N, |dMz| {:.2e} N m",
        worst.0, worst.1, worst.2
    );
}

#[test]
fn steady_side_slip_of_the_reference_tyre_matches_mfeval() {
    let table = read_reference(Path::new(MFEVAL)).unwrap();
    assert!(table.len() >= 45, "{} rows", table.len());
    let p = tir_numbers(REFERENCE);
    let (mut dfy, mut dmz, mut rel) = (0.0f64, 0.0f64, 0.0f64);
    for r in &table {
        // The formula written out here against MFeval, every row (pure and combined).
        let (fx, fy, mz) = mf61(&p, r.fz_n, r.kappa, r.alpha_rad);
        assert!(
            (fx - r.fx_n).abs() < 1e-3 + 1e-7 * r.fx_n.abs(),
            "{r:?}: Fx {fx}"
        );
        assert!(
            (fy - r.fy_n).abs() < 1e-3 + 1e-7 * r.fy_n.abs(),
            "{r:?}: Fy {fy}"
        );
        assert!(
            (mz - r.mz_n_m).abs() < 1e-4 + 1e-7 * r.mz_n_m.abs(),
            "{r:?}: Mz {mz}"
        );
        // The crate's formula likewise (combined slip included).
        let t = tyre(REFERENCE, TyreKind::PointFollower);
        let f = t.params().mf.forces(r.kappa, r.alpha_rad, r.fz_n, true);
        assert!(
            (f.fy - r.fy_n).abs() < 1e-3 + 1e-7 * r.fy_n.abs(),
            "{r:?}: crate Fy {}",
            f.fy
        );
        assert!(
            (f.mz - r.mz_n_m).abs() < 1e-4 + 1e-7 * r.mz_n_m.abs(),
            "{r:?}: crate Mz {}",
            f.mz
        );
        if r.kappa != 0.0 {
            continue;
        }
        // The rig (rigid ring, rim driven: kappa 0) at MFeval's speed, 16.7 m/s.
        let s = steady(REFERENCE, TyreKind::RigidRing, 16.7, r.fz_n, r.alpha_rad);
        let (ey, em) = (
            (s.lateral_force_n - r.fy_n).abs(),
            (s.aligning_moment_n_m - r.mz_n_m).abs(),
        );
        // Tolerances: the rig sets the load through the axle height; with the file's F_x
        // shifts the ring's in-plane offset, and with it F_z, moves by up to 0.15 N in
        // 6000 N as F_x changes with alpha (G_xa): 0.05 % of |F_y| and 0.05 N m.
        assert!(
            ey <= 5e-4 * r.fy_n.abs().max(100.0),
            "{r:?}: rig Fy {}",
            s.lateral_force_n
        );
        assert!(em <= 0.05, "{r:?}: rig Mz {}", s.aligning_moment_n_m);
        dfy = dfy.max(ey);
        dmz = dmz.max(em);
        rel = rel.max(ey / r.fy_n.abs().max(100.0));
    }
    eprintln!(
        "rig vs MFeval: |dFy| {dfy:.3} N ({:.4} %), |dMz| {dmz:.4} N m",
        100.0 * rel
    );
}

#[test]
fn a_step_in_slip_angle_relaxes_over_sigma_alpha() {
    for (file, load, speed, a_deg) in [
        (CAR, 3500.0, 13.9, 1.0),
        (TRAILER, 1500.0, 13.9, 2.0),
        (REFERENCE, 4000.0, 16.7, 2.0),
    ] {
        let p = tir_numbers(file);
        let fz0 = p["FNOMIN"];
        let kya0 = p["PKY1"] * fz0 * (p["PKY4"] * (1.0 / p["PKY2"]).atan()).sin();
        let sigma = kya0.abs() / p["LATERAL_STIFFNESS"];
        for kind in [TyreKind::RigidRing, TyreKind::PointFollower] {
            let alpha = f64::to_radians(a_deg);
            let mut rig = LateralRig::new(
                tyre(file, kind),
                flat(),
                speed,
                alpha,
                0.0,
                load,
                Spin::Driven,
                0.4,
            );
            rig.step = true;
            assert!((rig.tyre.params().d.sigma_alpha - sigma).abs() < 1e-12 * sigma);
            let dt = 2e-4;
            let opts = rig_options(&rig.tyre, 1e-8, &[1e-3]);
            let run = rig.run(8.0 * sigma / speed, dt, &opts).unwrap();
            let mut worst = 0.0f64;
            let mut s63 = None;
            for w in run.samples.windows(2) {
                let s = speed * w[1].t_s;
                let got = w[1].slip_angle_rad.tan() / alpha.tan();
                let want = 1.0 - (-s / sigma).exp();
                worst = worst.max((got - want).abs());
                let prev = w[0].slip_angle_rad.tan() / alpha.tan();
                let target = 1.0 - (-1.0f64).exp();
                if s63.is_none() && prev < target && got >= target {
                    let s0 = speed * w[0].t_s;
                    s63 = Some(s0 + (target - prev) / (got - prev) * (s - s0));
                }
            }
            let s63 = s63.unwrap();
            eprintln!("{file} {kind:?}: sigma_alpha {sigma:.4} m, 63 % after {s63:.4} m, |error| {worst:.1e}");
            assert!(
                worst < 1e-4,
                "{file} {kind:?}: first-order law off by {worst}"
            );
            assert!(
                (s63 / sigma - 1.0).abs() < 1e-3,
                "{file} {kind:?}: {s63} m vs {sigma} m"
            );
        }
    }
}

#[test]
fn at_standstill_the_tyre_is_a_lateral_spring_of_the_lateral_stiffness() {
    // No forward speed: nothing divides by it; the lateral deflection v integrates the
    // contact point's side speed and F_y = K_ya(F_z) / sigma_alpha tan^-1-law ~ -C_y v.
    let road = flat();
    for kind in [TyreKind::RigidRing, TyreKind::PointFollower] {
        let t = tyre(CAR, kind);
        let p = t.params().clone();
        let z = p.r0 - p.fnomin / p.cz;
        let kin =
            WheelKinematics::upright(Vector3::new(0.0, 0.0, z), Vector3::new(0.0, 0.02, 0.0), 0.0);
        let mut x = t.initial_state(&kin, &road);
        let iv = t
            .state_names()
            .iter()
            .position(|s| s == "tread_v_m")
            .unwrap();
        assert_eq!(x[iv], 0.0);
        let mut res = vec![0.0; x.len()];
        let xdot = vec![0.0; x.len()];
        t.residual(0.0, &kin, &road, &x, &xdot, &mut res);
        assert!(res.iter().all(|r| r.is_finite()));
        // v' = V_cy at rest.
        assert!((res[iv] + 0.02).abs() < 1e-12, "{}", res[iv]);
        // The spring alone: no side speed, so the low-speed damping adds nothing
        // (tests/mbs/tyre_low_speed.rs checks it).
        x[iv] = 1e-4;
        let kin = WheelKinematics::upright(Vector3::new(0.0, 0.0, z), Vector3::zeros(), 0.0);
        let o = t.outputs(&kin, &road, &x);
        let k = -o.lateral_force / 1e-4;
        let cy = tir_numbers(CAR)["LATERAL_STIFFNESS"] * o.normal_force / p.fnomin;
        // K_ya(F_z) / K_ya(FNOMIN) ~ F_z / FNOMIN near the nominal load: 3 %.
        assert!(
            (k / cy - 1.0).abs() < 0.03,
            "{kind:?}: {k} vs {cy} (F_z {})",
            o.normal_force
        );
        let hub = t.hub_load(&kin, &road, &x);
        assert!((hub.force.y - o.lateral_force).abs() < 1e-9 * o.lateral_force.abs());
    }
}
