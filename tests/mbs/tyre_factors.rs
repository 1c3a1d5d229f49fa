//! The ring tyre's independent factors (`FILE.tir:factor.NAME`): set to their file values
//! they reproduce the file; values whose raw equivalents the checks refuse give valid
//! tyres whose driven values match the closed forms of the rigid-ring relations (Pacejka
//! 2012 sec. 9.2); any point of the factors' open ranges is a valid tyre; a factor with a
//! raw value it drives is refused naming both.

use std::f64::consts::PI;
use std::path::Path;

use towride_mbs::input::tir::TirFile;
use towride_mbs::input::{read_overrides, Loader, Override};
use towride_mbs::tyre::factors::{DRIVEN, FACTORS};
use towride_mbs::tyre::TyreParams;

const CAR: &str = repo!("vehicles/tyres/car_185_60r14.tir");
const TRAILER: &str = repo!("vehicles/tyres/trailer_155_80r13.tir");
const REFERENCE: &str = repo!("vehicles/tyres/reference_205_60r15_tvd3.tir");

fn set(file: &str, pairs: &[(&str, f64)]) -> Loader {
    let name = Path::new(file).file_name().unwrap().to_str().unwrap();
    Loader::with_overrides(
        pairs
            .iter()
            .map(|(p, v)| Override::program(name, p, format!("{v:?}"), "test"))
            .collect(),
    )
}

fn raw(t: &TirFile, k: &str) -> f64 {
    let (s, key) = k.split_once('.').unwrap();
    t.f64(s, key).unwrap()
}

/// The factors of a file by their definitions (docs/road_tyre.md), from its raw values.
fn factors_by_hand(t: &TirFile) -> [f64; 7] {
    let r = |k| raw(t, k);
    let c_b = r("INERTIA.BELT_MASS") * (2.0 * PI * r("STRUCTURAL.FREQ_LONG")).powi(2);
    let c_theta = r("INERTIA.BELT_IYY") * (2.0 * PI * r("STRUCTURAL.FREQ_WINDUP")).powi(2);
    let cz = r("VERTICAL.VERTICAL_STIFFNESS");
    let r_l = r("DIMENSION.UNLOADED_RADIUS") - r("VERTICAL.FNOMIN") / cz;
    [
        r("INERTIA.MASS"),
        r("INERTIA.BELT_MASS") / r("INERTIA.MASS"),
        r("INERTIA.IYY"),
        r("INERTIA.BELT_IYY") / r("INERTIA.IYY"),
        cz,
        c_b / cz,
        1.0 - r("STRUCTURAL.LONGITUDINAL_STIFFNESS") * (1.0 / c_b + r_l * r_l / c_theta),
    ]
}

#[test]
fn factors_at_their_file_values_reproduce_every_shipped_file() {
    for file in [CAR, TRAILER, REFERENCE] {
        let plain = TirFile::read(Path::new(file), &Loader::new()).unwrap();
        let x = factors_by_hand(&plain);
        let pairs: Vec<(String, f64)> = FACTORS
            .iter()
            .zip(x)
            .map(|(f, v)| (format!("factor.{}", f.name), v))
            .collect();
        let pairs: Vec<(&str, f64)> = pairs.iter().map(|(p, v)| (p.as_str(), *v)).collect();
        let t = TirFile::read(Path::new(file), &set(file, &pairs)).unwrap();
        for k in DRIVEN {
            let (a, b) = (raw(&plain, k), raw(&t, k));
            assert!((a - b).abs() <= 1e-12 * a.abs(), "{file} {k}: {a} vs {b}");
        }
        TyreParams::from_tir(&t).unwrap();
    }
}

#[test]
fn factors_reach_tyres_the_raw_values_cannot_and_match_the_closed_forms() {
    // +30 % belt mass alone exceeds the car tyre's 7.0 kg: refused.
    let e = TyreParams::from_tir(
        &TirFile::read(
            Path::new(CAR),
            &set(CAR, &[("INERTIA.BELT_MASS", 5.45 * 1.3)]),
        )
        .unwrap(),
    )
    .unwrap_err();
    assert!(e.field.contains("BELT_MASS"), "{e}");
    // -30 % tyre mass alone falls below the belt's 5.45 kg: refused.
    let e = TyreParams::from_tir(
        &TirFile::read(Path::new(CAR), &set(CAR, &[("INERTIA.MASS", 4.9)])).unwrap(),
    )
    .unwrap_err();
    assert!(e.field.contains("BELT_MASS"), "{e}");
    // The same +30 % belt mass through the total mass (belt share kept 5.45 / 7): valid.
    let t = TirFile::read(Path::new(CAR), &set(CAR, &[("factor.total_mass_kg", 9.1)])).unwrap();
    let p = TyreParams::from_tir(&t).unwrap();
    assert!((p.mass - 9.1).abs() < 1e-12);
    assert!((p.belt_mass - 5.45 * 1.3).abs() < 1e-12, "{}", p.belt_mass);
    // Ring ratio and vertical stiffness kept: c_b = 5.45 (2 pi 77)^2 as in the file, so
    // the ring frequency falls as 1 / sqrt(1.3).
    let c_b = 5.45 * (2.0 * PI * 77.0f64).powi(2);
    assert!((p.d.c_b / c_b - 1.0).abs() < 1e-12);
    assert!(
        (p.freq_long - 77.0 / 1.3f64.sqrt()).abs() < 1e-9,
        "{}",
        p.freq_long
    );
    // Nothing longitudinal moved: the overall longitudinal stiffness stays 3.0e5 N/m.
    assert!((p.cx / 3.0e5 - 1.0).abs() < 1e-12, "{}", p.cx);
    // The trailer tyre with a soft ring (ratio 1.05, FREQ_LONG far below the file's 80 Hz)
    // and a tread share of 0.9: every driven value from the closed forms.
    let (ratio, s_t) = (1.05, 0.9);
    let t = TirFile::read(
        Path::new(TRAILER),
        &set(
            TRAILER,
            &[
                ("factor.ring_stiffness_ratio", ratio),
                ("factor.longitudinal_tread_share", s_t),
            ],
        ),
    )
    .unwrap();
    let p = TyreParams::from_tir(&t).unwrap();
    let (mb, ib, cz, r0, fnom, fw) = (4.7, 0.314, 1.8e5, 0.2891, 2500.0, 59.0);
    let c_b = ratio * cz;
    assert!((p.freq_long - (c_b / mb).sqrt() / (2.0 * PI)).abs() < 1e-9);
    let r_l: f64 = r0 - fnom / cz;
    let ring = 1.0 / c_b + r_l * r_l / (ib * (2.0 * PI * fw).powi(2));
    assert!((p.cx * ring - (1.0 - s_t)).abs() < 1e-12, "{}", p.cx);
    // Residual springs in series (Pacejka 2012 sec. 9.2): c_rz = C c_b / (c_b - C) and
    // the tread's compliance is s_t of the overall longitudinal one.
    assert!((p.d.c_rz / (cz * c_b / (c_b - cz)) - 1.0).abs() < 1e-9);
    assert!((p.cx / p.d.c_rx - s_t).abs() < 1e-12);
    let f_soft = p.freq_long;
    // A raw FREQ_WINDUP 30 % down beside a factor keeps the file's tread share: C_x
    // follows the softer ring (alone, the file's C_x would exceed the ring's and be
    // refused).
    let fw = 59.0 * 0.7;
    let t = TirFile::read(
        Path::new(CAR),
        &set(
            CAR,
            &[
                ("factor.total_mass_kg", 7.0),
                ("STRUCTURAL.FREQ_WINDUP", fw),
            ],
        ),
    )
    .unwrap();
    let p = TyreParams::from_tir(&t).unwrap();
    let (c_b, r_l) = (5.45 * (2.0 * PI * 77.0f64).powi(2), 0.2888 - 3500.0 / 2e5);
    let ring_file = 1.0 / c_b + r_l * r_l / (0.364 * (2.0 * PI * 59.0f64).powi(2));
    let ring_new = 1.0 / c_b + r_l * r_l / (0.364 * (2.0 * PI * fw).powi(2));
    let s_file = 1.0 - 3.0e5 * ring_file;
    assert!((p.cx * ring_new - (1.0 - s_file)).abs() < 1e-12, "{}", p.cx);
    assert!(
        3.0e5 * ring_new > 1.0,
        "the file's C_x alone would be refused"
    );
    // The raw equivalent of the trailer's soft ring (FREQ_LONG lowered alone) is refused.
    let e = TyreParams::from_tir(
        &TirFile::read(
            Path::new(TRAILER),
            &set(TRAILER, &[("STRUCTURAL.FREQ_LONG", f_soft)]),
        )
        .unwrap(),
    )
    .unwrap_err();
    assert!(e.field.contains("LONGITUDINAL_STIFFNESS"), "{e}");
}

#[test]
fn every_point_of_the_open_ranges_is_a_valid_tyre_and_the_edges_are_refused() {
    // A reproducible spread (SplitMix64-free LCG: the values only need to cover the box).
    let mut state = 12345u64;
    let mut u = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let mut valid = 0;
    for _ in 0..200 {
        let pairs = [
            ("factor.total_mass_kg", 7.0 * 10f64.powf(2.0 * u() - 1.0)),
            ("factor.belt_mass_share", u()),
            (
                "factor.spin_inertia_kg_m2",
                0.47 * 10f64.powf(2.0 * u() - 1.0),
            ),
            ("factor.belt_inertia_share", u()),
            ("factor.vertical_stiffness_n_m", 2e5 * 10f64.powf(u() - 0.5)),
            (
                "factor.ring_stiffness_ratio",
                1.0 + 100f64.powf(2.0 * u() - 1.0),
            ),
            ("factor.longitudinal_tread_share", u()),
        ];
        let t = TirFile::read(Path::new(CAR), &set(CAR, &pairs)).unwrap();
        // Only the plausibility table (docs/reliability.md) may refuse a corner where
        // tiny shares multiply into an absurd magnitude; never a coupling check.
        match TyreParams::from_tir(&t) {
            Ok(_) => valid += 1,
            Err(e) if e.message.contains("accepted range") => {}
            Err(e) => panic!("{pairs:?}: {e}"),
        }
    }
    assert!(valid >= 190, "{valid} of 200");
    for (p, v) in [
        ("factor.belt_mass_share", 1.0),
        ("factor.belt_inertia_share", 0.0),
        ("factor.ring_stiffness_ratio", 1.0),
        ("factor.longitudinal_tread_share", 1.0),
        ("factor.total_mass_kg", -1.0),
    ] {
        let e = TirFile::read(Path::new(CAR), &set(CAR, &[(p, v)])).unwrap_err();
        assert!(
            e.to_string().contains(p) && e.message.contains("open range"),
            "{e}"
        );
    }
    let e =
        TirFile::read(Path::new(CAR), &set(CAR, &[("factor.belt_mass_shar", 0.5)])).unwrap_err();
    assert!(e.message.contains("belt_mass_share"), "{e}");
}

#[test]
fn an_overrides_file_with_a_factor_and_a_value_it_drives_is_refused_naming_both() {
    let dir = std::env::temp_dir().join(format!("towride-factors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("overrides.toml");
    std::fs::write(
        &f,
        "\"car_185_60r14.tir:factor.total_mass_kg\" = 8.0\n\
         \"car_185_60r14.tir:STRUCTURAL.FREQ_LONG\" = 70.0\n",
    )
    .unwrap();
    let l = Loader::with_overrides(read_overrides(&f).unwrap());
    let e = TirFile::read(Path::new(CAR), &l).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("overrides.toml:2"), "{msg}");
    assert!(msg.contains("STRUCTURAL.FREQ_LONG"), "{msg}");
    assert!(
        msg.contains("factor.total_mass_kg") && msg.contains("overrides.toml:1"),
        "{msg}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
