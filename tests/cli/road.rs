//! `towride road` as a user runs it: the class C road's PSD verdict against ISO 8608's
//! class C limits (128e-6 and 512e-6 m^3 at n0 = 0.1 cycles/m), the profile CSV against
//! the hand-computed one-sided pothole, and located errors.

use crate::{towride_err, towride_json};

fn out_dir(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("towride-roadcli-{tag}-{}", std::process::id()))
}

#[test]
fn class_c_psd_lies_in_the_class_band() {
    let dir = out_dir("c");
    let v = towride_json(&[
        "road",
        repo!("roads/iso8608_class_c.toml"),
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(v["schema_version"], 1);
    let p = &v["psd"];
    // ISO 8608:2016 class C: Gd(n0) from 128e-6 to 512e-6 m^3, geometric mean 256e-6.
    assert!(
        (p["lower_m3"].as_f64().unwrap() - 128e-6).abs() < 1e-12,
        "{p}"
    );
    assert!(
        (p["upper_m3"].as_f64().unwrap() - 512e-6).abs() < 1e-12,
        "{p}"
    );
    for side in ["left", "right"] {
        let t = &p[side];
        // Welch bins scatter (about 18 averaged segments); the class band is a factor 4
        // wide, so nearly every bin from 0.05 to 2 cycles/m must lie inside it.
        assert!(
            t["fraction_inside"].as_f64().unwrap() >= 0.95,
            "{side}: {t}"
        );
        assert!(t["bins_in_band"].as_u64().unwrap() > 100, "{side}: {t}");
        let g = t["fitted_gd_n0_m3"].as_f64().unwrap();
        assert!(g > 128e-6 && g < 512e-6, "{side}: {g}");
    }
    for f in ["road_profile.csv", "road_profile.png", "road_psd.png"] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    let csv = std::fs::read_to_string(dir.join("road_profile.csv")).unwrap();
    assert_eq!(csv.lines().next().unwrap(), "x [m],z_left [m],z_right [m]");
    assert_eq!(csv.lines().count(), 1 + 20001);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn one_sided_pothole_profile() {
    let dir = out_dir("p");
    let v = towride_json(&[
        "road",
        repo!("roads/pothole_left_30mm.toml"),
        "--track-width-m",
        "1.43",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(v["psd"].is_null());
    let csv = std::fs::read_to_string(dir.join("road_profile.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect();
    // 30 mm deep, rim 1.0..1.6 m, 45 deg flanks: bottom 1.03..1.57 m, left track only.
    for r in &rows {
        let (x, zl, zr) = (r[0], r[1], r[2]);
        let want = if (1.03..=1.57).contains(&x) {
            -0.03
        } else if (1.0..1.03).contains(&x) {
            -(x - 1.0)
        } else if (1.57..1.6).contains(&x) {
            -(1.6 - x)
        } else {
            0.0
        };
        assert!((zl - want).abs() < 1e-9, "x {x}: left {zl}, want {want}");
        if x < 4.9 {
            assert_eq!(zr, 0.0, "x {x}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn roads_without_tracks_or_length_are_refused() {
    let dir = out_dir("e");
    let e = towride_err(
        &[
            "road",
            repo!("roads/pothole_left_30mm.toml"),
            "--out",
            dir.to_str().unwrap(),
        ],
        2,
    );
    assert!(
        e.contains("pothole_left_30mm.toml") && e.contains("--track-width-m"),
        "{e}"
    );
    let e = towride_err(
        &[
            "road",
            repo!("roads/flat.toml"),
            "--track-width-m",
            "1.4",
            "--out",
            dir.to_str().unwrap(),
        ],
        2,
    );
    assert!(e.contains("flat.toml") && e.contains("--length-m"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
