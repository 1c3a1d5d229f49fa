//! One-sided obstacles and potholes: a ramp and a pothole on the left half of the road
//! only. The heights against the hand-computed trapezoids, and the tyre's enveloping model
//! (the car tyre's tandem cams) feels them under the left wheel and not under the right.

use std::path::Path;

use towride_mbs::input::Loader;
use towride_mbs::road::Road;
use towride_mbs::tyre::{TandemCams, TyreParams};

const ROAD: &str = "[road]\nkind = \"flat\"\nheight_m = 0.0\n\n\
[[obstacle]]\nkind = \"ramp\"\nstart_m = 1.0\nheight_m = 0.05\nlength_m = 2.0\n\
length_measured_at = \"base\"\nflank_angle_deg = 45.0\ntrack = \"left\"\n\n\
[[obstacle]]\nkind = \"pothole\"\nstart_m = 5.0\ndepth_m = 0.03\nlength_m = 0.6\n\
flank_angle_deg = 45.0\ntrack = \"left\"\n\n\
[[obstacle]]\nkind = \"pothole\"\nstart_m = 8.0\ndepth_m = 0.04\nlength_m = 0.3\n\
flank_angle_deg = 90.0\ny_min_m = -1.0\ny_max_m = -0.2\n";

fn write(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("towride-onesided-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn one_sided_heights() {
    let r = Road::from_file(&write("r.toml", ROAD), &Loader::new()).unwrap();
    // Ramp: 50 mm, 45 deg flanks (50 mm run), left half only.
    assert!((r.height(1.02, 0.7) - 0.02).abs() < 1e-12);
    assert!((r.height(2.0, 0.7) - 0.05).abs() < 1e-12);
    assert_eq!(r.height(2.0, -0.7), 0.0);
    // Pothole: 30 mm deep, 0.6 m at the rim, 45 deg flanks: bottom 5.03..5.57 m.
    assert!((r.height(5.01, 0.7) + 0.01).abs() < 1e-12);
    assert!((r.height(5.3, 0.7) + 0.03).abs() < 1e-12);
    assert!((r.height(5.59, 0.7) + 0.01).abs() < 1e-12);
    assert_eq!(r.height(5.3, -0.7), 0.0);
    assert_eq!(r.height(5.7, 0.7), 0.0);
    // Rectangular pothole between y = -1.0 and -0.2: vertical faces at 8.0 and 8.3 m.
    assert!((r.height(8.0, -0.7) + 0.04).abs() < 1e-12);
    assert!((r.height(8.29, -0.7) + 0.04).abs() < 1e-12);
    assert_eq!(r.height(8.1, 0.7), 0.0);
    assert_eq!(r.height(8.1, -0.1), 0.0);
    assert!(
        r.describe().contains("pothole 30 mm deep"),
        "{}",
        r.describe()
    );
}

#[test]
fn enveloping_feels_them_on_one_side_only() {
    let r = Road::from_file(&write("e.toml", ROAD), &Loader::new()).unwrap();
    let p = TyreParams::from_file(
        Path::new(repo!("vehicles/tyres/car_185_60r14.tir")),
        &Loader::new(),
    )
    .unwrap();
    let cams = TandemCams::new(&p);
    let half_track = 0.715;
    let at = |x: f64, y: f64| cams.effective(&r, [x, y], [1.0, 0.0], [0.0, 1.0]);
    // On the ramp's 1.9 m plateau (much longer than the tyre's contact) the left wheel
    // rides the full 50 mm; the right wheel stays on the road.
    let (l, rr) = (at(2.0, half_track), at(2.0, -half_track));
    assert!((l.height - 0.05).abs() < 1e-9, "left {}", l.height);
    assert_eq!(rr.height, 0.0);
    assert!(rr.flat && !l.flat);
    // Over the pothole's 0.54 m bottom (longer than the cams reach) the left wheel drops
    // the full 30 mm; the right one stays.
    let (l, rr) = (at(5.3, half_track), at(5.3, -half_track));
    assert!((l.height + 0.03).abs() < 1e-9, "left {}", l.height);
    assert_eq!(rr.height, 0.0);
    // Entering it, the left wheel is part way down.
    let l = at(5.0, half_track);
    assert!(l.height < -1e-4 && l.height > -0.03, "left {}", l.height);
    // The rectangular pothole on the right: the right wheel dips, the left does not.
    let (l, rr) = (at(8.15, half_track), at(8.15, -half_track));
    assert!(
        rr.height < -1e-3 && rr.height > -0.04,
        "right {}",
        rr.height
    );
    assert_eq!(l.height, 0.0);
}

#[test]
fn bad_one_sided_obstacles_name_the_field() {
    for (from, to, field) in [
        ("depth_m = 0.03", "depth_m = -0.03", "depth_m"),
        (
            "track = \"left\"\n\n[[obstacle]]\nkind = \"pothole\"",
            "track = \"middle\"\n\n[[obstacle]]\nkind = \"pothole\"",
            "unknown variant `middle`",
        ),
        (
            "flank_angle_deg = 90.0\ny_min_m",
            "flank_angle_deg = 90.0\ntrack = \"right\"\ny_min_m",
            "track",
        ),
    ] {
        let text = ROAD.replacen(from, to, 1);
        assert_ne!(text, ROAD);
        let e = Road::from_file(&write("bad.toml", &text), &Loader::new())
            .unwrap_err()
            .to_string();
        assert!(e.contains(field) && e.contains("bad.toml:"), "{e}");
    }
}
