//! A scene's `[[output]]` tables: the default scene asks for front-left suspension travel,
//! rear-left damper force and body pitch; `outputs.csv` carries them with units, and each
//! is checked against its own computation from marker positions and velocities (the
//! body's rotation rebuilt from three of its points, the damper law from the property
//! file through a natural cubic spline solved here). Unknown names are errors at their
//! field with the closest names suggested.

use std::path::{Path, PathBuf};

use towride_app::job::Job;
use towride_app::scene;
use towride_mbs::input::Loader;

type V = [f64; 3];

fn sub(a: &V, b: &V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: &V, b: &V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: &V, b: &V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: &V) -> V {
    let n = dot(a, a).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}

/// Orthonormal frame (columns) spanned by three points.
fn frame(p: &[V; 3]) -> [V; 3] {
    let e1 = unit(&sub(&p[1], &p[0]));
    let e3 = unit(&cross(&e1, &sub(&p[2], &p[0])));
    [e1, cross(&e3, &e1), e3]
}

/// Rotation taking the points `p0` to `p` (rigidly moved): R = F F0^T, as rows.
fn rotation(p0: &[V; 3], p: &[V; 3]) -> [V; 3] {
    let (f0, f) = (frame(p0), frame(p));
    std::array::from_fn(|r| std::array::from_fn(|c| (0..3).map(|k| f[k][r] * f0[k][c]).sum()))
}

/// Natural cubic spline through (x, y) at t, linear beyond the ends: the second
/// derivatives from the full (dense) system solved by Gaussian elimination.
fn natural_spline(x: &[f64], y: &[f64], t: f64) -> f64 {
    let n = x.len();
    let mut a = vec![vec![0.0; n + 1]; n];
    a[0][0] = 1.0;
    a[n - 1][n - 1] = 1.0;
    for i in 1..n - 1 {
        let (h0, h1) = (x[i] - x[i - 1], x[i + 1] - x[i]);
        a[i][i - 1] = h0 / 6.0;
        a[i][i] = (h0 + h1) / 3.0;
        a[i][i + 1] = h1 / 6.0;
        a[i][n] = (y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0;
    }
    for c in 0..n {
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            let pivot = a[c].clone();
            for (x, p) in a[r].iter_mut().zip(&pivot).skip(c) {
                *x -= f * p;
            }
        }
    }
    let mut m = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|k| a[r][k] * m[k]).sum();
        m[r] = (a[r][n] - s) / a[r][r];
    }
    let value = |i: usize, t: f64| {
        let h = x[i + 1] - x[i];
        let (p, q) = ((x[i + 1] - t) / h, (t - x[i]) / h);
        p * y[i]
            + q * y[i + 1]
            + ((p.powi(3) - p) * m[i] + (q.powi(3) - q) * m[i + 1]) * h * h / 6.0
    };
    let slope = |i: usize, t: f64| {
        let h = x[i + 1] - x[i];
        let (p, q) = ((x[i + 1] - t) / h, (t - x[i]) / h);
        (y[i + 1] - y[i]) / h - (3.0 * p * p - 1.0) * h * m[i] / 6.0
            + (3.0 * q * q - 1.0) * h * m[i + 1] / 6.0
    };
    if t < x[0] {
        return y[0] + slope(0, x[0]) * (t - x[0]);
    }
    if t > x[n - 1] {
        return y[n - 1] + slope(n - 2, x[n - 1]) * (t - x[n - 1]);
    }
    let i = (0..n - 1).find(|&i| t <= x[i + 1]).unwrap();
    value(i, t)
}

/// A copy of the default scene (paths made absolute) with `extra` appended, in a fresh
/// folder.
fn scene_with(tag: &str, extra: &str) -> (PathBuf, PathBuf) {
    let root = Path::new(repo!("")).canonicalize().unwrap();
    let text = std::fs::read_to_string(root.join("scenes/default.toml"))
        .unwrap()
        .replace("\"../", &format!("\"{}/", root.display()));
    let dir = std::env::temp_dir().join(format!("towride-outputs-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("scene.toml");
    std::fs::write(&file, format!("{text}\n{extra}")).unwrap();
    (file, dir)
}

const ASKED: &str = r#"
[[output]]
quantity = "susp_fl_travel"

[[output]]
quantity = "damper_rl_force"

[[output]]
quantity = "body_pitch"

# The independent references: world positions and velocities of markers.
[[output]]
marker = "wheel_fl.centre"
quantity = "position"
name = "p_wc_fl"

[[output]]
marker = "ride_fl"
quantity = "position"
name = "p_ride_fl"

[[output]]
marker = "ride_fr"
quantity = "position"
name = "p_ride_fr"

[[output]]
marker = "ride_rl"
quantity = "position"
name = "p_ride_rl"

[[output]]
marker = "damper_rl.i"
quantity = "position"
name = "p_di"

[[output]]
marker = "damper_rl.j"
quantity = "position"
name = "p_dj"

[[output]]
marker = "damper_rl.i"
quantity = "velocity"
name = "v_di"

[[output]]
marker = "damper_rl.j"
quantity = "velocity"
name = "v_dj"
"#;

/// Design (t = build) world position of a marker, from the model's body poses: every
/// body of the built vehicle starts unrotated.
fn design_position(s: &scene::Scene, name: &str) -> V {
    let m = s.model();
    let mk = &m.markers[m.marker_by_name(name).unwrap()];
    match mk.body {
        None => mk.position,
        Some(b) => {
            assert_eq!(m.bodies[b].orientation, [1.0, 0.0, 0.0, 0.0]);
            let p = m.bodies[b].position;
            [
                p[0] + mk.position[0],
                p[1] + mk.position[1],
                p[2] + mk.position[2],
            ]
        }
    }
}

#[test]
fn requested_outputs_match_marker_kinematics() {
    let (file, dir) = scene_with("asked", ASKED);
    let loader = Loader::new();
    let s = scene::load_with(&file, &scene::Changes::default(), &loader).unwrap();
    let design: Vec<V> = ["wheel_fl.centre", "ride_fl", "ride_fr", "ride_rl"]
        .iter()
        .map(|n| design_position(&s, n))
        .collect();
    let job = Job::from_scene(s).unwrap();
    let mut res = job.run(&towride_mbs::progress::Silent).unwrap();
    assert!(res.completed());
    towride_app::report::write_run(&mut res, &job.system, &dir).unwrap();
    let csv = std::fs::read_to_string(dir.join("outputs.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for h in [
        "susp_fl_travel [m]",
        "damper_rl_force [N]",
        "body_pitch [rad]",
    ] {
        assert!(header.split(',').any(|c| c == h), "{h} not in {header}");
    }
    let ch = |n: &str| res.channel(n).unwrap();
    let v3 = |n: &str, k: usize| -> V {
        [0, 1, 2].map(|c| ch(&format!("{n}.{}", ["x", "y", "z"][c]))[k])
    };
    let (travel, damper, pitch) = (
        ch("susp_fl_travel"),
        ch("damper_rl_force"),
        ch("body_pitch"),
    );
    let text = std::fs::read_to_string(repo!("vehicles/fabia/rear_twist_beam.toml")).unwrap();
    let table: toml::Value = toml::from_str(&text).unwrap();
    let col = |k: &str| -> Vec<f64> {
        table["damper"][k]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_float().unwrap())
            .collect()
    };
    let (dv, df) = (col("velocity_m_s"), col("force_n"));
    let p0 = [design[1], design[2], design[3]];
    let (mut travel_max, mut damper_max, mut pitch_max) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..res.samples.times.len() {
        let p = [v3("p_ride_fl", k), v3("p_ride_fr", k), v3("p_ride_rl", k)];
        let r = rotation(&p0, &p);
        // Euler yaw-pitch-roll: R[2][0] = -sin(pitch).
        let want_pitch = -r[2][0].asin();
        let z_body = [r[0][2], r[1][2], r[2][2]];
        let want_travel =
            dot(&sub(&v3("p_wc_fl", k), &p[0]), &z_body) - (design[0][2] - design[1][2]);
        let d = sub(&v3("p_di", k), &v3("p_dj", k));
        let rate = dot(&d, &sub(&v3("v_di", k), &v3("v_dj", k))) / dot(&d, &d).sqrt();
        // The damper pulls its ends together in extension: positive pushing apart.
        let want_damper = -natural_spline(&dv, &df, rate);
        assert!(
            (pitch[k] - want_pitch).abs() < 1e-9,
            "pitch {} vs {want_pitch} at {k}",
            pitch[k]
        );
        assert!(
            (travel[k] - want_travel).abs() < 1e-9,
            "travel {} vs {want_travel} at {k}",
            travel[k]
        );
        assert!(
            (damper[k] - want_damper).abs() < 1e-6 * (1.0 + want_damper.abs()),
            "damper {} vs {want_damper} at {k}",
            damper[k]
        );
        travel_max = travel_max.max(want_travel.abs());
        damper_max = damper_max.max(want_damper.abs());
        pitch_max = pitch_max.max(want_pitch.abs());
    }
    // The ramp moves all three well beyond rounding: 10s of mm, 100s of N, mrad.
    assert!(travel_max > 0.01, "travel {travel_max} m");
    assert!(damper_max > 100.0, "damper {damper_max} N");
    assert!(pitch_max > 1e-3, "pitch {pitch_max} rad");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn unknown_output_names_suggest_the_closest() {
    for (extra, field, hint) in [
        (
            "[[output]]\nquantity = \"susp_fl_travle\"\n",
            "output[0].quantity",
            "'susp_fl_travel'",
        ),
        (
            "[[output]]\nelement = \"damper_lr\"\nquantity = \"force\"\n",
            "output[0].element",
            "'damper_rl'",
        ),
        (
            "[[output]]\nmarker = \"ride_fl\"\nquantity = \"postion\"\n",
            "output[0].quantity",
            "'position'",
        ),
    ] {
        let (file, dir) = scene_with("bad", extra);
        let e = scene::load_with(&file, &scene::Changes::default(), &Loader::new())
            .unwrap_err()
            .to_string();
        assert!(e.contains("scene.toml"), "{e}");
        assert!(e.contains(field), "{e}");
        assert!(e.contains(hint), "{e}");
        // At the line of the field (the last table's).
        let key = field.rsplit('.').next().unwrap();
        let text = std::fs::read_to_string(&file).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let line = 1 + lines.iter().rposition(|l| l.starts_with(key)).unwrap();
        assert!(e.contains(&format!("scene.toml:{line}:")), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}

#[test]
fn trailer_corners_come_from_the_model_not_from_their_names() {
    let loader = Loader::new();
    let mut s = scene::load_with(
        Path::new(repo!("scenes/default.toml")),
        &scene::Changes::default(),
        &loader,
    )
    .unwrap();
    let names = |s: &scene::Scene| -> Vec<String> {
        towride_app::scene::outputs::quantities(&s.vehicle)
            .into_iter()
            .map(|q| q.name)
            .filter(|n| n.starts_with("susp_") && n.ends_with("_travel"))
            .collect()
    };
    assert_eq!(
        names(&s),
        [
            "susp_fl_travel",
            "susp_fr_travel",
            "susp_rl_travel",
            "susp_rr_travel",
            "susp_tl_travel",
            "susp_tr_travel"
        ]
    );
    // Trailer wheels under other names are still the trailer's corners (measured against
    // the trailer box), and a car wheel never becomes one.
    for w in &mut s.vehicle.handles.wheels[4..] {
        w.name = format!("axle2_{}", w.name);
    }
    let n = names(&s);
    assert!(n.contains(&"susp_axle2_tl_travel".to_string()), "{n:?}");
    assert!(n.contains(&"susp_axle2_tr_travel".to_string()), "{n:?}");
    assert_eq!(n.len(), 6);
}
