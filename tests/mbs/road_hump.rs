//! The speed hump of continuous shape (`kind = "hump"`): each end of the blend against
//! its profile in closed form (a circle through the feet and the crest; a trapezoid),
//! the area against the segment and trapezoid formulas, continuity in the shape value,
//! and located errors.

use std::path::Path;

use towride_mbs::input::Loader;
use towride_mbs::road::{Hump, Road};

fn road(shape: f64, angle: f64) -> Road {
    let text = format!(
        "[road]\nkind = \"flat\"\nheight_m = 0.0\n\n[[obstacle]]\nkind = \"hump\"\nstart_m = 1.0\n\
         height_m = 0.05\nlength_m = 0.5\nshape = {shape}\nflank_angle_deg = {angle}\n"
    );
    let dir = std::env::temp_dir().join(format!("towride-hump-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(format!("hump_{shape}_{angle}.toml"));
    std::fs::write(&p, text).unwrap();
    Road::from_file(&p, &Loader::new()).unwrap()
}

#[test]
fn ends_of_the_blend_are_the_pure_profiles() {
    // shape 0: the circle through (1, 0), (1.25, 0.05), (1.5, 0): centre (1.25, 0.05 - R)
    // with R = (0.25^2 + 0.05^2) / (2 * 0.05) = 0.65 m.
    let round = road(0.0, 45.0);
    for x in [1.0, 1.02, 1.1, 1.25, 1.33, 1.49] {
        let want = (0.65f64 * 0.65 - (x - 1.25) * (x - 1.25)).sqrt() - 0.6;
        assert!((round.height(x, 0.0) - want).abs() < 1e-12, "x {x}");
        let slope = -(x - 1.25) / (0.65f64 * 0.65 - (x - 1.25) * (x - 1.25)).sqrt();
        assert!((round.slope(x, 0.0).0 - slope).abs() < 1e-9, "x {x}");
    }
    // shape 1 with 45 deg flanks: 50 mm run, plateau 1.05 .. 1.45 m.
    let flat = road(1.0, 45.0);
    for (x, z) in [
        (1.0, 0.0),
        (1.02, 0.02),
        (1.05, 0.05),
        (1.3, 0.05),
        (1.47, 0.03),
    ] {
        assert!((flat.height(x, 0.0) - z).abs() < 1e-12, "x {x}");
    }
    assert!((flat.slope(1.02, 0.0).0 - 1.0).abs() < 1e-12);
    assert!((flat.slope(1.47, 0.0).0 + 1.0).abs() < 1e-12);
    // shape 0.5 halfway, to the bit of the two formulas.
    let half = road(0.5, 45.0);
    for x in [1.01, 1.2, 1.48] {
        let z = 0.5 * (round.height(x, 0.0) + flat.height(x, 0.0));
        assert!((half.height(x, 0.0) - z).abs() < 1e-15);
    }
    assert_eq!(half.height(0.999, 0.0), 0.0);
    assert_eq!(half.height(1.5, 0.0), 0.0);
    // The feet and the plateau edges are the kinks.
    let mut k = Vec::new();
    half.kinks_along([0.0, 0.0], [1.0, 0.0], 0.0, 3.0, &mut k);
    let want = [1.0, 1.05, 1.45, 1.5];
    assert_eq!(k.len(), 4, "{k:?}");
    for (a, b) in k.iter().zip(want) {
        assert!((a - b).abs() < 1e-12, "{k:?}");
    }
}

#[test]
fn area_and_height_follow_the_blend() {
    // Segment area R^2 acos((R-h)/R) - (R-h) sqrt(2Rh - h^2); trapezoid h (L - f).
    let (r, h): (f64, f64) = (0.65, 0.05);
    let segment = r * r * ((r - h) / r).acos() - (r - h) * (2.0 * r * h - h * h).sqrt();
    for (shape, angle) in [(0.0, 45.0), (0.3, 30.0), (0.7, 60.0), (1.0, 90.0)] {
        let f = if angle == 90.0 {
            0.0
        } else {
            h / f64::to_radians(angle).tan()
        };
        let want = (1.0 - shape) * segment + shape * h * (0.5 - f);
        let hump = Hump::new(1.0, h, 0.5, shape, angle).unwrap();
        assert!((hump.area() - want).abs() < 1e-15);
        // Midpoint rule over the road's own heights, 100000 cells.
        let rd = road(shape, angle);
        let n = 100_000;
        let dx = 0.5 / n as f64;
        let a: f64 = (0..n)
            .map(|i| rd.height(1.0 + (i as f64 + 0.5) * dx, 0.0) * dx)
            .sum();
        assert!((a - want).abs() < 1e-8, "shape {shape}: {a} vs {want}");
        // The crest is the height whatever the shape.
        assert!((rd.height(1.25, 0.0) - h).abs() < 1e-12);
    }
}

#[test]
fn height_and_slope_are_continuous_in_the_shape() {
    // d z / d shape = z_trapezoid - z_circle, at most h: a shape step of 1e-6 moves the
    // surface by at most 5e-8 m and the slope by at most 1e-6 x (|slope| bound 1 + 0.4).
    let a = Hump::new(1.0, 0.05, 0.5, 0.4, 45.0).unwrap();
    let b = Hump::new(1.0, 0.05, 0.5, 0.4 + 1e-6, 45.0).unwrap();
    for i in 0..=500 {
        let x = 1.0 + 0.5 * i as f64 / 500.0 - 1e-9;
        if x < 1.0 {
            continue;
        }
        let (za, sa) = a.at(x);
        let (zb, sb) = b.at(x);
        assert!((za - zb).abs() <= 0.05 * 1e-6 + 1e-15, "x {x}");
        assert!((sa - sb).abs() <= 1.5e-6, "x {x}");
    }
}

#[test]
fn bad_humps_are_located() {
    let dir = std::env::temp_dir().join(format!("towride-hump-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (field, line) in [("shape = 1.5", 8), ("flank_angle_deg = 0.0", 9)] {
        let mut text = "[road]\nkind = \"flat\"\nheight_m = 0.0\n[[obstacle]]\nkind = \"hump\"\n\
                        start_m = 1.0\nheight_m = 0.05\nlength_m = 0.5\nshape = 0.5\nflank_angle_deg = 45.0\n"
            .to_string();
        let key = field.split(' ').next().unwrap();
        let old = text
            .lines()
            .find(|l| l.starts_with(&format!("{key} ")))
            .unwrap()
            .to_string();
        text = text.replace(&old, field);
        let p = dir.join(format!("{key}.toml"));
        std::fs::write(&p, &text).unwrap();
        let e = Road::from_file(Path::new(&p), &Loader::new()).unwrap_err();
        assert_eq!(e.line, Some(line + 1), "{e}");
        assert_eq!(e.field, format!("obstacle[0].{key}"), "{e}");
    }
    // A 90 deg flank on a hump higher than half its length: no circle.
    assert!(Hump::new(0.0, 0.3, 0.5, 1.0, 90.0).is_err());
    // 10 deg flanks of a 50 mm hump need 0.57 m: longer than 0.5 m.
    assert!(Hump::new(0.0, 0.05, 0.5, 1.0, 10.0).is_err());
}
