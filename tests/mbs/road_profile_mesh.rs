//! Two-track CSV profiles and the parry3d height field, against interpolation written
//! out here from the CSV data.

use std::path::Path;

use towride_mbs::road::Road;

fn rows(file: &str) -> Vec<Vec<f64>> {
    std::fs::read_to_string(file)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('x'))
        .map(|l| l.split(',').map(|v| v.trim().parse().unwrap()).collect())
        .collect()
}

#[test]
fn two_track_profile() {
    let r = Road::from_file(
        Path::new(repo!("roads/profile_example.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let data = rows(repo!("roads/profile_example.csv"));
    let half = 1.43 / 2.0;
    for w in data.windows(2).step_by(7) {
        let x = 0.3 * w[0][0] + 0.7 * w[1][0];
        let zl = 0.3 * w[0][1] + 0.7 * w[1][1];
        let zr = 0.3 * w[0][2] + 0.7 * w[1][2];
        assert!((r.height(x, half) - zl).abs() < 1e-12);
        assert!((r.height(x, 2.0) - zl).abs() < 1e-12);
        assert!((r.height(x, -half) - zr).abs() < 1e-12);
        assert!((r.height(x, 0.0) - 0.5 * (zl + zr)).abs() < 1e-12);
    }
    assert!(r.is_flat(0.0, 1.7, half));
    assert!(!r.is_flat(0.0, 1.9, half));
    assert!(
        r.is_flat(1.7, 2.5, -half),
        "the right track is flat where the left has its hump"
    );
    assert!(!r.is_flat(2.8, 3.2, -half));
    let mut k = Vec::new();
    r.kinks_along([1.0, half], [1.0, 0.0], 0.0, 0.11, &mut k);
    assert_eq!(k.len(), 5, "nodes every 25 mm: {k:?}");
}

#[test]
fn bad_profile_names_its_line() {
    let dir = std::env::temp_dir().join(format!("towride-prof-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("p.csv"),
        "# comment\nx_m,z_left_m,z_right_m\n0.0,0,0\n1.0,0,0\n0.5,0,0\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("p.toml"),
        "[road]\nkind = \"profile\"\nfile = \"p.csv\"\ntrack_width_m = 1.4\n",
    )
    .unwrap();
    let e = Road::from_file(&dir.join("p.toml"), &towride_mbs::input::Loader::new()).unwrap_err();
    println!("{e}");
    assert_eq!(e.line, Some(5));
    assert_eq!(e.field, "x_m");
    assert!(e.file.ends_with("p.csv"));
}

/// Height on the grid's triangles (diagonal from (i, j) to (i+1, j+1)), written out here.
fn triangle_height(data: &[Vec<f64>], x: f64, y: f64) -> f64 {
    let (dx, dy, nx) = (0.05, 0.25, 81usize);
    let i = (x / dx).floor() as usize;
    let j = ((y + 1.0) / dy).floor() as usize;
    let z = |a: usize, b: usize| data[(j + b) * nx + i + a][2];
    let u = x / dx - i as f64;
    let v = (y + 1.0) / dy - j as f64;
    if u >= v {
        // Triangle (0,0), (1,0), (1,1).
        z(0, 0) + u * (z(1, 0) - z(0, 0)) + v * (z(1, 1) - z(1, 0))
    } else {
        // Triangle (0,0), (1,1), (0,1).
        z(0, 0) + v * (z(0, 1) - z(0, 0)) + u * (z(1, 1) - z(0, 1))
    }
}

#[test]
fn height_field_through_parry() {
    let r = Road::from_file(
        Path::new(repo!("roads/height_field_example.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let data = rows(repo!("roads/height_field_example.csv"));
    let mut worst: f64 = 0.0;
    for k in 0..200 {
        let x = 1.4 + 1.2 * (k as f64 * 0.618).fract();
        let y = -0.9 + 1.8 * (k as f64 * 0.371).fract();
        worst = worst.max((r.height(x, y) - triangle_height(&data, x, y)).abs());
    }
    println!("height field: worst difference to the triangle planes {worst:.2e} m");
    assert!(worst < 1e-12);
    // Slope from the hit triangle's normal against differences inside one triangle.
    let (x, y) = (1.8125, 0.3);
    let (sx, sy) = r.slope(x, y);
    let fx = (triangle_height(&data, x + 1e-6, y) - triangle_height(&data, x - 1e-6, y)) / 2e-6;
    let fy = (triangle_height(&data, x, y + 1e-6) - triangle_height(&data, x, y - 1e-6)) / 2e-6;
    assert!(
        (sx - fx).abs() < 1e-6 && (sy - fy).abs() < 1e-6,
        "{sx} {sy} vs {fx} {fy}"
    );
    assert_eq!(r.flat_height(0.0, 1.4, -1.0, 1.0), Some(0.0));
    assert_eq!(r.flat_height(0.0, 1.6, -1.0, 1.0), None);
    let mut k = Vec::new();
    r.kinks_along([1.0, 0.1], [1.0, 0.0], 0.0, 0.2, &mut k);
    // Grid lines every 50 mm (both ends included) plus one diagonal in each of 4 cells.
    assert_eq!(k.len(), 9, "{k:?}");
}
