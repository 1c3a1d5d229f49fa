//! The combination's sway (snaking) mode against the classical linear car-trailer model:
//! a single-track car (lateral velocity v, yaw rate r at constant forward speed u) and a
//! trailer yawing about the ball (articulation angle theta), axle tyres with linear
//! cornering stiffness and no relaxation, no roll, no load transfer (Pacejka, "Tire and
//! Vehicle Dynamics", 3rd ed. 2012, sec. 1.3.3, the car-trailer combination; Ellis,
//! "Vehicle Dynamics", 1969, ch. 8). Its equations are written here by Kane's method from
//! the kinematics below, not taken from the source's printed matrices.
//!
//! The model's parameters come from the assembled vehicle (masses, centres of mass, yaw
//! inertias, axle and ball positions) and the tyre files (Magic Formula cornering
//! stiffness at the rigid-body axle loads); its critical speed is set against
//! `towride linear` of the full model (suspensions, roll, tyre relaxation, the flexible
//! crossbeam) run here. They must agree on where the sway mode loses its damping.

use std::path::Path;

use super::sway_mode;
use towride_app::vehicle::{self, Options, Vehicle};
use towride_mbs::input::{Loader, Override};
use towride_mbs::model::math::rot;
use towride_mbs::tyre::TyreKind;

/// The classical model's parameters (SI; lengths along the heading, positive as named).
#[derive(Clone, Copy, Debug)]
struct SingleTrack {
    /// Car: mass, yaw inertia about its centre of mass.
    m1: f64,
    i1: f64,
    /// Car centre of mass to front axle, to rear axle, to the ball.
    a: f64,
    b: f64,
    h: f64,
    /// Trailer: mass, yaw inertia about its centre of mass.
    m2: f64,
    i2: f64,
    /// Ball to the trailer's centre of mass, to its axle.
    e: f64,
    f: f64,
    /// Axle cornering stiffnesses (both tyres) [N/rad].
    cf: f64,
    cr: f64,
    ct: f64,
    /// Lateral relaxation lengths of the car's and the trailer's tyres [m] (0: none).
    sigma_car: f64,
    sigma_trailer: f64,
}

/// Mass, centre of mass (x, y) and yaw inertia about it of a set of (mass, x, y, Izz).
fn lump(parts: &[(f64, f64, f64, f64)]) -> (f64, f64, f64, f64) {
    let m: f64 = parts.iter().map(|p| p.0).sum();
    let x = parts.iter().map(|p| p.0 * p.1).sum::<f64>() / m;
    let y = parts.iter().map(|p| p.0 * p.2).sum::<f64>() / m;
    let i = parts
        .iter()
        .map(|p| p.3 + p.0 * ((p.1 - x).powi(2) + (p.2 - y).powi(2)))
        .sum();
    (m, x, y, i)
}

fn single_track(v: &Vehicle) -> SingleTrack {
    let m = &v.model;
    let h = &v.handles;
    let tp = h.trailer_place.expect("a trailer");
    let on_trailer = |b: usize| {
        let p = h.body_place[b];
        p.translation == tp.translation && p.rotation == tp.rotation
    };
    // Every body, and the rigid rings' belts at their wheels (they have no lateral
    // freedom of their own: they yaw and slide with the rim).
    let (mut car, mut trailer) = (Vec::new(), Vec::new());
    for (k, b) in m.bodies.iter().enumerate() {
        let r = rot(&b.orientation);
        let iz = (0..3)
            .map(|i| {
                (0..3)
                    .map(|j| r[2][i] * b.inertia[i][j] * r[2][j])
                    .sum::<f64>()
            })
            .sum();
        let part = (b.mass, b.position[0], b.position[1], iz);
        if on_trailer(k) {
            &mut trailer
        } else {
            &mut car
        }
        .push(part);
    }
    let wheel_x = |names: &[&str]| {
        let xs: Vec<f64> = h
            .wheels
            .iter()
            .filter(|w| names.contains(&w.name.as_str()))
            .map(|w| m.bodies[w.body.index()].position[0])
            .collect();
        xs.iter().sum::<f64>() / xs.len() as f64
    };
    for t in &m.tyres {
        let b = m.markers[t.marker].body.unwrap();
        let p = &m.bodies[b.index()].position;
        let belt = (t.tyre.params().belt_mass, p[0], p[1], 0.0);
        if on_trailer(b.index()) {
            &mut trailer
        } else {
            &mut car
        }
        .push(belt);
    }
    let (m1, x1, _, i1) = lump(&car);
    let (m2, x2, _, i2) = lump(&trailer);
    let (xf, xr, xt) = (
        wheel_x(&["fl", "fr"]),
        wheel_x(&["rl", "rr"]),
        wheel_x(&["tl", "tr"]),
    );
    let ball = v
        .handles
        .car_place
        .point(v.handles.hitch.as_ref().unwrap().ball)[0];
    // Forward is from the rear axle to the front one.
    let s = (xf - xr).signum();
    let (a, b, hh, e, f) = (
        s * (xf - x1),
        s * (x1 - xr),
        s * (x1 - ball),
        s * (ball - x2),
        s * (ball - xt),
    );
    // Rigid-body axle loads: the trailer on its axle and the ball, the car on its axles
    // with the nose load at the ball.
    let g = 9.81;
    let nose = m2 * g * (f - e) / f;
    let ft = m2 * g * e / f;
    let ff = (m1 * g * b - nose * (hh - b)) / (a + b);
    let fr = m1 * g + nose - ff;
    let stiffness = |name: &str, fz: f64| {
        let t = m
            .tyres
            .iter()
            .find(|t| {
                let b = m.markers[t.marker].body.unwrap();
                h.wheels.iter().any(|w| w.name == name && w.body == b)
            })
            .unwrap();
        2.0 * t.tyre.params().mf.cornering_stiffness(fz).abs()
    };
    let sigma = |name: &str| {
        m.tyres
            .iter()
            .find(|t| {
                let b = m.markers[t.marker].body.unwrap();
                h.wheels.iter().any(|w| w.name == name && w.body == b)
            })
            .unwrap()
            .tyre
            .params()
            .d
            .sigma_alpha
    };
    SingleTrack {
        m1,
        i1,
        a,
        b,
        h: hh,
        m2,
        i2,
        e,
        f,
        cf: stiffness("fl", ff / 2.0),
        cr: stiffness("rl", fr / 2.0),
        ct: stiffness("tl", ft / 2.0),
        sigma_car: sigma("fl"),
        sigma_trailer: sigma("tl"),
    }
}

/// The largest real part [1/s] among the oscillatory eigenvalues of the linear model at
/// forward speed `u` [m/s], and that mode's frequency [Hz]. With relaxation lengths the
/// axle forces lag the slip: (sigma / u) F' + F = -C alpha (Pacejka 2012, sec. 7.2).
fn sway(p: &SingleTrack, u: f64) -> (f64, f64) {
    eigenvalues(p, u)
        .iter()
        .filter(|l| l.im.abs() > 1e-6 && l.im.abs() < 2.0 * std::f64::consts::PI * 3.0)
        .map(|l| (l.re, l.im.abs() / (2.0 * std::f64::consts::PI)))
        .fold((f64::NEG_INFINITY, 0.0), |best, x| {
            if x.0 > best.0 {
                x
            } else {
                best
            }
        })
}

/// The eigenvalues [1/s] of the linear model at forward speed `u` [m/s].
fn eigenvalues(p: &SingleTrack, u: f64) -> Vec<nalgebra::Complex<f64>> {
    use nalgebra::{DMatrix, Matrix3};
    // Generalised speeds w = (v, r, theta'), theta = car yaw - trailer yaw. Partial
    // velocities (lateral velocity and yaw rate of each body, of each axle):
    // car (1, 0, 0), (0, 1, 0); trailer centre (1, -(h + e), e), yaw (0, 1, -1);
    // front axle (1, a, 0), rear (1, -b, 0), trailer axle (1, -(h + f), f).
    // Lateral accelerations: car v' + u r; trailer v' - (h + e) r' + e theta'' + u r.
    let d1 = [1.0, 0.0, 0.0];
    let y1 = [0.0, 1.0, 0.0];
    let d2 = [1.0, -(p.h + p.e), p.e];
    let y2 = [0.0, 1.0, -1.0];
    let mut mm = Matrix3::zeros();
    for j in 0..3 {
        // Coefficients of (v', r', theta'') in equation j.
        mm[(j, 0)] = p.m1 * d1[j] + p.m2 * d2[j];
        mm[(j, 1)] = p.i1 * y1[j] - p.m2 * (p.h + p.e) * d2[j] + p.i2 * y2[j];
        mm[(j, 2)] = p.m2 * p.e * d2[j] - p.i2 * y2[j];
    }
    let minv = mm.try_inverse().unwrap();
    // Each axle: cornering stiffness, relaxation length, its lateral velocity in terms
    // of (v, r, theta', theta), its partial velocities.
    let axles = [
        (p.cf, p.sigma_car, [1.0, p.a, 0.0, 0.0], [1.0, p.a, 0.0]),
        (p.cr, p.sigma_car, [1.0, -p.b, 0.0, 0.0], [1.0, -p.b, 0.0]),
        (
            p.ct,
            p.sigma_trailer,
            [1.0, -(p.h + p.f), p.f, u],
            [1.0, -(p.h + p.f), p.f],
        ),
    ];
    // States (v, r, theta', theta, then the force of each lagging axle).
    let lag: Vec<usize> = (0..3).filter(|&k| axles[k].1 > 0.0).collect();
    let n = 4 + lag.len();
    // Generalised forces Q = G x, 3 x n.
    let mut g = DMatrix::<f64>::zeros(3, n);
    for j in 0..3 {
        g[(j, 1)] -= (p.m1 * d1[j] + p.m2 * d2[j]) * u;
        for (k, (c, sigma, vel, part)) in axles.iter().enumerate() {
            if *sigma > 0.0 {
                let s = 4 + lag.iter().position(|&l| l == k).unwrap();
                g[(j, s)] += part[j];
            } else {
                for i in 0..4 {
                    g[(j, i)] -= c * vel[i] / u * part[j];
                }
            }
        }
    }
    let mut a = DMatrix::<f64>::zeros(n, n);
    let rows = minv * g.rows(0, 3);
    a.rows_mut(0, 3).copy_from(&rows);
    a[(3, 2)] = 1.0;
    for (i, &k) in lag.iter().enumerate() {
        let (c, sigma, vel, _) = axles[k];
        let s = 4 + i;
        for q in 0..4 {
            a[(s, q)] = -c * vel[q] / sigma;
        }
        a[(s, s)] = -u / sigma;
    }
    a.complex_eigenvalues().iter().copied().collect()
}

/// The lowest speed [m/s] at which the sway mode's real part turns positive, by
/// bisection after a scan from 5 to 100 m/s.
fn critical_speed(p: &SingleTrack) -> Option<f64> {
    let mut lo = 5.0;
    let mut hi = (1..=95)
        .map(|k| 5.0 + k as f64)
        .find(|&u| sway(p, u).0 > 0.0)?;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if sway(p, mid).0 > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}

const TRAILER: &str = "box_trailer.toml";

/// The legal-limit trailer with its payload over the axle (10 kg on the ball) and spread
/// to the box's ends (I_zz 450 kg m^2), as in docs/manoeuvres.md's sway table.
fn spread_load() -> Vec<String> {
    vec![
        format!("{TRAILER}:load_case[4].payload.cm_m=[-2.46,0.0,0.745]"),
        format!("{TRAILER}:load_case[4].payload.inertia_kg_m2=[42.7,450.0,450.0]"),
    ]
}

/// The full model's sway damping ratio and frequency [Hz] at `speed` [km/h] from
/// `towride linear`.
fn full_model_sway(speed: f64, sets: &[String]) -> (f64, f64) {
    let dir = std::env::temp_dir().join(format!("towride_sway_{}_{speed}", std::process::id()));
    let s = "scenes/default.toml";
    let mut all = vec![
        format!("{s}:run.speed_km_h={speed}"),
        format!("{s}:scene.load_case=\"legal_limit_557kg\""),
    ];
    all.extend(sets.iter().cloned());
    let sway = sway_mode(&dir, &all);
    std::fs::remove_dir_all(&dir).ok();
    (
        sway["damping_ratio"].as_f64().unwrap(),
        sway["damped_hz"].as_f64().unwrap(),
    )
}

fn spread_vehicle() -> Vehicle {
    let loader = Loader::with_overrides(
        spread_load()
            .iter()
            .map(|a| Override::from_argument(a).unwrap())
            .collect(),
    );
    vehicle::load(
        Path::new(repo!("vehicles/fabia_trailer.toml")),
        &Options {
            load_case: Some("legal_limit_557kg".into()),
            tyre_kind: Some(TyreKind::RigidRing),
            ..Default::default()
        },
        &loader,
    )
    .unwrap()
}

#[test]
fn the_reference_model_behind_a_massless_trailer_is_the_bicycle_model() {
    // With the trailer's mass and inertia gone and no relaxation, the car's (v, r) obey
    // the two-degree-of-freedom single-track model, whose eigenvalues are those of
    // A = [[-(Cf + Cr) / (m u), -(a Cf - b Cr) / (m u) - u],
    //      [-(a Cf - b Cr) / (I u), -(a^2 Cf + b^2 Cr) / (I u)]],
    // and the trailer's axle follows its ball: theta' = -(u / f) theta (no slip).
    let p = SingleTrack {
        m2: 1e-6,
        i2: 1e-6,
        sigma_car: 0.0,
        sigma_trailer: 0.0,
        ..single_track(&spread_vehicle())
    };
    let u = 25.0;
    let (m, i) = (p.m1, p.i1);
    let a11 = -(p.cf + p.cr) / (m * u);
    let a12 = -(p.a * p.cf - p.b * p.cr) / (m * u) - u;
    let a21 = -(p.a * p.cf - p.b * p.cr) / (i * u);
    let a22 = -(p.a * p.a * p.cf + p.b * p.b * p.cr) / (i * u);
    let (tr, det) = (a11 + a22, a11 * a22 - a12 * a21);
    let disc = nalgebra::Complex::new(tr * tr / 4.0 - det, 0.0).sqrt();
    let want = [
        nalgebra::Complex::new(tr / 2.0, 0.0) + disc,
        nalgebra::Complex::new(tr / 2.0, 0.0) - disc,
        nalgebra::Complex::new(-u / p.f, 0.0),
    ];
    let got = eigenvalues(&p, u);
    for w in want {
        let near = got
            .iter()
            .map(|g| (g - w).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(near < 1e-6 * w.norm().max(1.0), "{w} not in {got:?}");
    }
}

#[test]
fn the_sway_mode_and_its_critical_speed_match_the_classical_linear_model() {
    let p = single_track(&spread_vehicle());
    let uc = critical_speed(&p).expect("the spread load snakes below 100 m/s") * 3.6;
    for kmh in [60.0, 160.0] {
        let reference = sway(&p, kmh / 3.6);
        let (_, hz) = full_model_sway(kmh, &spread_load());
        // The same mode: frequency within 10 %.
        assert!(
            (hz / reference.1 - 1.0).abs() < 0.10,
            "{kmh} km/h: {hz} Hz, {reference:?}"
        );
    }
    // The full model's critical speed, where its damping ratio changes sign between two
    // linearisations 20 km/h apart around the reference's. It has what the rigid
    // single-track model leaves out (roll, the front axle's roll understeer of -5 deg/m
    // bump steer, suspension compliance, the flexible crossbeam), so agreement within
    // 15 % is what is asked; the E90-scaled tie rod (-30 deg/m) gave 114 km/h against
    // 225 km/h (docs/manoeuvres.md, "The classical linear model").
    let lo = 20.0 * (uc / 20.0).floor();
    let (z_lo, _) = full_model_sway(lo, &spread_load());
    let (z_hi, _) = full_model_sway(lo + 20.0, &spread_load());
    let (mut a, mut za, mut b, mut zb) = (lo, z_lo, lo + 20.0, z_hi);
    // Step outwards (at most 60 km/h either way) until the sign changes.
    for _ in 0..3 {
        if za > 0.0 && zb <= 0.0 {
            break;
        }
        if za <= 0.0 {
            (b, zb) = (a, za);
            a -= 20.0;
            za = full_model_sway(a, &spread_load()).0;
        } else {
            (a, za) = (b, zb);
            b += 20.0;
            zb = full_model_sway(b, &spread_load()).0;
        }
    }
    assert!(
        za > 0.0 && zb <= 0.0,
        "no sign change between {a} and {b} km/h"
    );
    let full = a + (b - a) * za / (za - zb);
    assert!(
        (full / uc - 1.0).abs() < 0.15,
        "critical speed {full} km/h against the classical model's {uc} km/h"
    );
}
