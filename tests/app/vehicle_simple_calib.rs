//! The `simple` template's values a calibration moves: the air spring's pressure as an
//! output channel, against the polytropic law of the file's gas evaluated on the spring's
//! own length (markers), and separate compression and rebound damping, against the
//! file's rates at +-v.

use std::path::{Path, PathBuf};

use towride_app::job::Job;
use towride_app::scene;
use towride_mbs::input::Loader;
use towride_mbs::model::elements::Force;

const G: f64 = 9.81;

/// The van file with the defaults path made absolute and `edit` applied, in a fresh
/// folder; returns the folder and the file.
fn van_with(tag: &str, edit: impl Fn(String) -> String) -> (PathBuf, PathBuf) {
    let root = Path::new(repo!("")).canonicalize().unwrap();
    let dir = std::env::temp_dir().join(format!("towride-calib-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let van = std::fs::read_to_string(root.join("vehicles/van_air/van.toml"))
        .unwrap()
        .replace(
            "\"../simple_defaults.toml\"",
            &format!(
                "\"{}\"",
                root.join("vehicles/simple_defaults.toml").display()
            ),
        );
    let file = dir.join("van.toml");
    std::fs::write(&file, edit(van)).unwrap();
    (dir, file)
}

#[test]
fn air_spring_pressure_follows_the_polytropic_law() {
    let root = Path::new(repo!("")).canonicalize().unwrap();
    let (dir, van) = van_with("pressure", |s| s);
    let scene_text = std::fs::read_to_string(root.join("scenes/van_air/bump_50mm.toml"))
        .unwrap()
        .replace(
            "\"../../vehicles/van_air/van.toml\"",
            &format!("\"{}\"", van.display()),
        )
        .replace(
            "\"../../roads/",
            &format!("\"{}/", root.join("roads").display()),
        )
        .replace("duration_s = 2.5", "duration_s = 1.6");
    let extra = "\n[[output]]\nquantity = \"air_spring_rl_pressure\"\n\n\
                 [[output]]\nmarker = \"spring_rl.i\"\nquantity = \"position\"\nname = \"p_si\"\n\n\
                 [[output]]\nmarker = \"spring_rl.j\"\nquantity = \"position\"\nname = \"p_sj\"\n";
    let file = dir.join("scene.toml");
    std::fs::write(&file, scene_text + extra).unwrap();
    let s = scene::load_with(&file, &scene::Changes::default(), &Loader::new()).unwrap();
    let job = Job::from_scene(s).unwrap();
    let mut res = job.run(&towride_mbs::progress::Silent).unwrap();
    assert!(res.completed());
    towride_app::report::write_run(&mut res, &job.system, &dir).unwrap();
    let csv = std::fs::read_to_string(dir.join("outputs.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header
            .split(',')
            .any(|c| c == "air_spring_rl_pressure [Pa]"),
        "{header}"
    );
    // The file's numbers: 1000 kg on the rear axle, 75 kg unsprung per corner, a
    // 0.0177 m^2 piston, 4.5 l; the defaults' n = 1.3 and 101325 Pa; the spring stands
    // 0.30 m long at the design height.
    let (area, v0, n, pa, l0) = (0.0177, 0.0045, 1.3, 101325.0, 0.30);
    let static_gauge = (1000.0 / 2.0 - 75.0) * G / area;
    let p = res.channel("air_spring_rl_pressure").unwrap();
    let ch = |n: &str| res.channel(n).unwrap();
    let (ix, iy, iz, jx, jy, jz) = (
        ch("p_si.x"),
        ch("p_si.y"),
        ch("p_si.z"),
        ch("p_sj.x"),
        ch("p_sj.y"),
        ch("p_sj.z"),
    );
    // Levelled at the design height: gauge pressure = load / area (before the bump).
    assert!(
        (p[0] / static_gauge - 1.0).abs() < 0.01,
        "{} vs {static_gauge}",
        p[0]
    );
    let (mut lo, mut hi, mut worst) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for k in 0..p.len() {
        let len =
            ((ix[k] - jx[k]).powi(2) + (iy[k] - jy[k]).powi(2) + (iz[k] - jz[k]).powi(2)).sqrt();
        // p V^n = const from the design height, V = V0 + A x.
        let want = (static_gauge + pa) * (v0 / (v0 + area * (len - l0))).powf(n) - pa;
        worst = worst.max((p[k] - want).abs());
        lo = lo.min(p[k]);
        hi = hi.max(p[k]);
    }
    assert!(worst < 0.01 * static_gauge, "worst {worst} Pa");
    // The bump moves it well beyond the tolerance.
    assert!(hi - lo > 0.1 * static_gauge, "{lo} .. {hi} Pa");
    println!(
        "static {:.0} Pa (load / area {static_gauge:.0}), range {lo:.0} .. {hi:.0} Pa, worst {worst:.1} Pa",
        p[0]
    );
}

#[test]
fn compression_and_rebound_rates_at_plus_and_minus_v() {
    let (_, van) = van_with("damping", |s| {
        let rear = s.find("[rear]").unwrap();
        let at = rear + s[rear..].find("damping_ratio = 0.25").unwrap();
        let end = at + s[at..].find('\n').unwrap();
        format!(
            "{}damping_compression_n_s_m = 1500.0\ndamping_rebound_n_s_m = 4500.0{}",
            &s[..at],
            &s[end..]
        )
    });
    let v = towride_app::vehicle::load(&van, &Default::default(), &Loader::new()).unwrap();
    let m = &v.model;
    let Force::Spring(d) = &m.forces[m.element_by_name("damper_rl").unwrap()] else {
        panic!("damper_rl is a spring-damper line")
    };
    // Motion ratio 1 (the damper stands over the wheel centre on an arm pivoting at its
    // height): the element's law is the wheel's. Extension (positive rate) is rebound.
    for speed in [0.2, 0.5, 1.0] {
        let (up, _, _) = d.damper.eval(speed);
        let (down, _, _) = d.damper.eval(-speed);
        assert!((up - 4500.0 * speed).abs() < 1e-6, "{up}");
        assert!((down + 1500.0 * speed).abs() < 1e-6, "{down}");
    }
    // Smooth through zero: the mean rate there, continuous slope.
    let (f0, s0, _) = d.damper.eval(0.0);
    assert_eq!(f0, 0.0);
    assert!((s0 - 3000.0).abs() < 1e-9, "{s0}");
    let h = 1e-7;
    let fd = (d.damper.eval(h).0 - d.damper.eval(-h).0) / (2.0 * h);
    assert!((fd - 3000.0).abs() < 1e-3, "{fd}");
    // The front keeps its single rate (damping_ratio): linear both ways.
    let Force::Spring(f) = &m.forces[m.element_by_name("damper_fl").unwrap()] else {
        panic!()
    };
    let (a, _, _) = f.damper.eval(0.5);
    let (b, _, _) = f.damper.eval(-0.5);
    assert!((a + b).abs() < 1e-9 * a.abs());
    // One rate alone is refused at its field.
    let (_, bad) = van_with("damping-bad", |s| {
        s.replace("[rear]\n", "[rear]\ndamping_rebound_n_s_m = 4500.0\n")
    });
    let e = towride_app::vehicle::load(&bad, &Default::default(), &Loader::new())
        .err()
        .unwrap();
    assert_eq!(e.field, "rear.damping_rebound_n_s_m", "{e}");
}
