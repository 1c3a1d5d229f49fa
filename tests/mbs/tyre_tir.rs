//! The .tir reader refuses bad files with the file, the line and the key named, and the
//! shipped files reproduce their own ring frequencies through the derived stiffnesses.

use std::f64::consts::PI;
use std::path::Path;

use towride_mbs::input::tir::TirFile;
use towride_mbs::tyre::{Tyre, TyreKind, TyreParams};

const CAR: &str = repo!("vehicles/tyres/car_185_60r14.tir");

fn edited(from: &str, to: &str) -> (String, usize) {
    let text = std::fs::read_to_string(CAR).unwrap();
    let line = text
        .lines()
        .position(|l| l.starts_with(from))
        .expect("line present")
        + 1;
    let out: Vec<String> = text
        .lines()
        .map(|l| {
            if l.starts_with(from) {
                to.to_string()
            } else {
                l.to_string()
            }
        })
        .collect();
    (out.join("\n") + "\n", line)
}

fn section_line(text: &str, section: &str) -> usize {
    text.lines()
        .position(|l| l.trim() == format!("[{section}]"))
        .unwrap()
        + 1
}

#[test]
fn negative_stiffness_is_refused_at_its_line() {
    let (text, line) = edited(
        "VERTICAL_STIFFNESS",
        "VERTICAL_STIFFNESS       = -200000   $ typo",
    );
    let path = Path::new("bad_stiffness.tir");
    let e = TyreParams::from_tir(&TirFile::parse(path, &text).unwrap()).unwrap_err();
    let msg = e.to_string();
    println!("{msg}");
    assert_eq!(e.line, Some(line));
    assert!(
        msg.starts_with(&format!("bad_stiffness.tir:{line}:")),
        "{msg}"
    );
    assert!(msg.contains("VERTICAL.VERTICAL_STIFFNESS"), "{msg}");
    assert!(msg.contains("must be positive"), "{msg}");
}

#[test]
fn missing_key_is_refused_at_its_section() {
    let (text, _) = edited("PKX1", "$ PKX1 removed");
    let path = Path::new("no_pkx1.tir");
    let e = TyreParams::from_tir(&TirFile::parse(path, &text).unwrap()).unwrap_err();
    let msg = e.to_string();
    println!("{msg}");
    let sec = section_line(&text, "LONGITUDINAL_COEFFICIENTS");
    assert_eq!(e.line, Some(sec));
    assert!(msg.starts_with(&format!("no_pkx1.tir:{sec}:")), "{msg}");
    assert!(msg.contains("LONGITUDINAL_COEFFICIENTS.PKX1"), "{msg}");
    assert!(msg.contains("missing key PKX1"), "{msg}");
}

#[test]
fn errors_from_a_real_file_name_it() {
    let dir = std::env::temp_dir().join(format!("towride-tir-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (text, line) = edited(
        "BELT_MASS",
        "BELT_MASS                = 9.0   $ more than the tyre",
    );
    let file = dir.join("heavy_belt.tir");
    std::fs::write(&file, text).unwrap();
    let e = Tyre::from_file(
        &file,
        TyreKind::RigidRing,
        &towride_mbs::input::Loader::new(),
    )
    .unwrap_err();
    println!("{e}");
    assert_eq!(e.file, file);
    assert_eq!(e.line, Some(line));
    assert_eq!(e.field, "INERTIA.BELT_MASS");
    // Out-of-range physics: a ring too soft for the tyre's vertical stiffness.
    let (text, line) = edited("FREQ_LONG", "FREQ_LONG                = 20.0");
    let e =
        TyreParams::from_tir(&TirFile::parse(Path::new("soft.tir"), &text).unwrap()).unwrap_err();
    println!("{e}");
    assert_eq!(
        (e.line, e.field.as_str()),
        (Some(line), "STRUCTURAL.FREQ_LONG")
    );
    // Non-SI units are refused.
    let (text, line) = edited("LENGTH", "LENGTH                   = 'mm'");
    let e = TyreParams::from_tir(&TirFile::parse(Path::new("mm.tir"), &text).unwrap()).unwrap_err();
    assert_eq!((e.line, e.field.as_str()), (Some(line), "UNITS.LENGTH"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn shipped_files_reproduce_their_ring_data() {
    for file in [CAR, repo!("vehicles/tyres/trailer_155_80r13.tir")] {
        let p = TyreParams::from_file(Path::new(file), &towride_mbs::input::Loader::new()).unwrap();
        let t = |s: &str, k: &str| crate::common::tir_value(file, s, k);
        let f_long = (p.d.c_b / t("INERTIA", "BELT_MASS")).sqrt() / (2.0 * PI);
        let f_wind = (p.d.c_theta / t("INERTIA", "BELT_IYY")).sqrt() / (2.0 * PI);
        assert!((f_long / t("STRUCTURAL", "FREQ_LONG") - 1.0).abs() < 1e-12);
        assert!((f_wind / t("STRUCTURAL", "FREQ_WINDUP") - 1.0).abs() < 1e-12);
        // Series springs give back the overall stiffnesses.
        let cz = 1.0 / (1.0 / p.d.c_b + 1.0 / p.d.c_rz);
        assert!((cz / t("VERTICAL", "VERTICAL_STIFFNESS") - 1.0).abs() < 1e-12);
        let r = p.d.r_loaded0;
        let cx = 1.0 / (1.0 / p.d.c_b + r * r / p.d.c_theta + 1.0 / p.d.c_rx);
        assert!((cx / t("STRUCTURAL", "LONGITUDINAL_STIFFNESS") - 1.0).abs() < 1e-12);
        // Plausible bands for a passenger-car tyre.
        if file == CAR {
            assert!((150e3..=250e3).contains(&t("VERTICAL", "VERTICAL_STIFFNESS")));
            assert!((t("DIMENSION", "UNLOADED_RADIUS") - 0.29).abs() < 0.01);
            assert!((75.0..=80.0).contains(&t("STRUCTURAL", "FREQ_LONG")));
            assert!((55.0..=60.0).contains(&t("STRUCTURAL", "FREQ_WINDUP")));
        }
        println!(
            "{file}: c_b {:.4e} N/m, c_theta {:.4e} N m/rad, c_rz {:.4e} N/m, c_rx {:.4e} N/m, a0 {:.4} m, l_s {:.4} m",
            p.d.c_b, p.d.c_theta, p.d.c_rz, p.d.c_rx, p.d.a0, p.d.l_s
        );
    }
}
