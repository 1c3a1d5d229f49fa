//! Roads from their TOML files: the thesis ramp and the bumps against hand-computed
//! geometry, the flatness and kink queries, and located errors for bad inputs.

use std::path::Path;

use towride_mbs::road::Road;

fn write(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("towride-road-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn thesis_ramp_geometry() {
    let r = Road::from_file(
        Path::new(repo!("roads/ramp_thesis.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    // 50 mm high, 45 deg flanks (50 mm run), 500 mm foot to foot from x = 1 m.
    let cases = [
        (0.999, 0.0),
        (1.0, 0.0),
        (1.01, 0.01),
        (1.04, 0.04),
        (1.05, 0.05),
        (1.3, 0.05),
        (1.45, 0.05),
        (1.47, 0.03),
        (1.5, 0.0),
        (2.0, 0.0),
    ];
    for (x, z) in cases {
        assert!(
            (r.height(x, 0.3) - z).abs() < 1e-12,
            "z({x}) = {}",
            r.height(x, 0.3)
        );
    }
    assert!((r.slope(1.02, 0.0).0 - 1.0).abs() < 1e-12);
    assert!((r.slope(1.48, 0.0).0 + 1.0).abs() < 1e-12);
    assert!(r.is_flat(-5.0, 0.999, 0.0));
    assert!(r.is_flat(1.501, 9.0, 0.0));
    assert!(!r.is_flat(0.5, 1.001, 0.0));
    assert!(
        !r.is_flat(1.1, 1.2, 0.0),
        "the plateau lies inside an obstacle"
    );
    let mut k = Vec::new();
    r.kinks_along([0.0, 0.0], [1.0, 0.0], 0.0, 3.0, &mut k);
    let want = [1.0, 1.05, 1.45, 1.5];
    assert_eq!(k.len(), 4);
    for (a, b) in k.iter().zip(want) {
        assert!((a - b).abs() < 1e-12, "{k:?}");
    }
    // Along a line at 60 deg to the road the same edges come at s = dx / cos 60.
    k.clear();
    let d = [0.5, 3f64.sqrt() / 2.0];
    r.kinks_along([0.0, 0.0], d, 0.0, 4.0, &mut k);
    assert!(
        (k[0] - 2.0).abs() < 1e-12 && (k[3] - 3.0).abs() < 1e-12,
        "{k:?}"
    );
}

#[test]
fn ramp_length_at_the_top() {
    let text = "[road]\nkind = \"flat\"\nheight_m = 0.1\n\n[[obstacle]]\nkind = \"ramp\"\nstart_m = 1.0\nheight_m = 0.05\nlength_m = 0.5\nlength_measured_at = \"top\"\nflank_angle_deg = 45.0\n";
    let r = Road::from_file(&write("top.toml", text), &towride_mbs::input::Loader::new()).unwrap();
    assert!((r.height(1.05, 0.0) - 0.15).abs() < 1e-12);
    assert!((r.height(1.55, 0.0) - 0.15).abs() < 1e-12);
    assert!((r.height(1.6, 0.0) - 0.1).abs() < 1e-12);
    assert!((r.height(1.575, 0.0) - 0.125).abs() < 1e-12);
}

#[test]
fn circular_bumps_of_the_measurement_plan() {
    for (file, h) in [
        (repo!("roads/bump_25mm.toml"), 0.025),
        (repo!("roads/bump_50mm.toml"), 0.05),
    ] {
        let r = Road::from_file(Path::new(file), &towride_mbs::input::Loader::new()).unwrap();
        let c = 0.5;
        let radius = (c * c / 4.0 + h * h) / (2.0 * h);
        assert!((r.height(1.25, 0.0) - h).abs() < 1e-12, "{file}");
        assert!(r.height(1.0, 0.0).abs() < 1e-12 && r.height(1.5, 0.0).abs() < 1e-12);
        for x in [1.05, 1.2, 1.4] {
            // On the circle of radius R centred (R - h) below the road at mid-chord.
            let z = r.height(x, 0.0);
            let d2 = (x - 1.25f64).powi(2) + (z + radius - h).powi(2);
            assert!((d2.sqrt() - radius).abs() < 1e-12, "{file} x = {x}");
            let fd = (r.height(x + 1e-7, 0.0) - r.height(x - 1e-7, 0.0)) / 2e-7;
            assert!((fd - r.slope(x, 0.0).0).abs() < 1e-6);
        }
    }
}

#[test]
fn step_and_lateral_extent() {
    let text = "[road]\nkind = \"flat\"\nheight_m = 0.0\n\n[[obstacle]]\nkind = \"step\"\nstart_m = 2.0\nheight_m = -0.03\ny_min_m = 0.0\ny_max_m = 1.0\n";
    let r = Road::from_file(
        &write("step.toml", text),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    assert_eq!(r.height(2.0, 0.5), -0.03, "right-continuous at the face");
    assert_eq!(r.height(1.999, 0.5), 0.0);
    assert_eq!(r.height(5.0, -0.5), 0.0, "outside the lateral range");
    assert_eq!(r.flat_height(0.0, 10.0, -2.0, -0.1), Some(0.0));
    assert_eq!(r.flat_height(0.0, 10.0, -2.0, 0.1), None);
}

#[test]
fn bad_inputs_are_located() {
    let text = "[road]\nkind = \"flat\"\nheight_m = 0.0\n\n[[obstacle]]\nkind = \"ramp\"\nstart_m = 1.0\nheight_m = -0.05\nlength_m = 0.5\nlength_measured_at = \"base\"\nflank_angle_deg = 45.0\n";
    let p = write("neg.toml", text);
    let e = Road::from_file(&p, &towride_mbs::input::Loader::new()).unwrap_err();
    println!("{e}");
    assert_eq!(e.line, Some(8));
    assert_eq!(e.field, "obstacle[0].height_m");
    let text = text
        .replace("height_m = -0.05", "height_m = 0.05")
        .replace("flank_angle_deg = 45.0", "flank_angle_deg = 5.0");
    let e = Road::from_file(
        &write("flat_flank.toml", &text),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap_err();
    println!("{e}");
    assert!(e.message.contains("no plateau"), "{e}");
    let text =
        "[road]\nkind = \"flat\"\nheight_m = 0.0\n\n[[obstacle]]\nkind = \"chicane\"\nstart_m = 1.0\n";
    let e = Road::from_file(
        &write("kind.toml", text),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap_err();
    println!("{e}");
    assert!(e.line.is_some() && e.message.contains("chicane"), "{e}");
    let text = "[road]\nkind = \"flat\"\nheight_m = 0.0\n\n[[obstacle]]\nkind = \"step\"\nstart_m = 1.0\nheight_m = 0.05\n\n[[obstacle]]\nkind = \"bump\"\nstart_m = 3.0\nheight_m = 0.02\nchord_m = 0.3\n";
    let e = Road::from_file(
        &write("overlap.toml", text),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap_err();
    println!("{e}");
    assert!(e.message.contains("overlaps"), "{e}");
    assert_eq!(e.line, Some(12));
}
