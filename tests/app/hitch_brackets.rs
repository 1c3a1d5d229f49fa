//! The hitch brackets' loads into the car body (`hitch_bracket_<side>_<f,m><x,y,z>`)
//! against the mechanics of the hitch as a free body, with its mass and centre of mass
//! summed by hand from the FE file (rho A L per beam plus the ball):
//! - at rest, the brackets pass the ball load and the hitch's weight into the body, and
//!   their moments balance those about the ball, for both mount kinds;
//! - the default scene is symmetric: left and right loads are mirror images;
//! - over the bump run, Newton's law for the hitch closes: the loads on it (brackets,
//!   ball, weight) equal its mass times its centre of mass's acceleration (the kept
//!   modes are mass-orthogonal to the rigid-body modes, docs/flex.md, so the centre of
//!   mass is fixed in the body's reference frame).

use std::path::Path;

use towride_app::job::{Job, RunResult};
use towride_app::scene::{self, Channel};
use towride_mbs::input::{Loader, Override};
use towride_mbs::model::desc::{Axes, BodyQuantity, MarkerHandle, MarkerQuantity, Output, Request};

const FLEX: &str = repo!("flex/hitch_crossbeam.toml");

type V = [f64; 3];

fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: V) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// The crossbeam's (variant 5, the file's base sections) mass [kg], centre of mass and
/// the named nodes' positions, FE coordinates [m], from the flex file by hand.
struct Hand {
    mass: f64,
    com: V,
    ball: V,
    bolts: [V; 2],
}

fn hand() -> Hand {
    let t: toml::Value = toml::from_str(&std::fs::read_to_string(FLEX).unwrap()).unwrap();
    let f = |v: &toml::Value, k: &str| v[k].as_float().unwrap();
    let pos = |n: &str| -> V {
        let node = t["node"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["name"].as_str() == Some(n))
            .unwrap();
        let p = node["position_m"].as_array().unwrap();
        [0, 1, 2].map(|i| p[i].as_float().unwrap())
    };
    let area = |name: &str| -> f64 {
        let s = t["section"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["name"].as_str() == Some(name))
            .unwrap();
        match s["shape"].as_str().unwrap() {
            "rectangular_hollow" => {
                let (w, h, e) = (f(s, "width_m"), f(s, "height_m"), f(s, "wall_m"));
                w * h - (w - 2.0 * e) * (h - 2.0 * e)
            }
            "rectangular_solid" => f(s, "width_m") * f(s, "height_m"),
            "round_solid" => std::f64::consts::PI * f(s, "diameter_m").powi(2) / 4.0,
            other => panic!("section shape {other}"),
        }
    };
    let rho = f(&t["material"][0], "density_kg_m3");
    let pm = &t["point_mass"][0];
    let ball = pos(pm["node"].as_str().unwrap());
    let mut mass = f(pm, "mass_kg");
    let mut moment = ball.map(|x| x * mass);
    for e in t["element"].as_array().unwrap() {
        let (a, b) = (
            pos(e["node_a"].as_str().unwrap()),
            pos(e["node_b"].as_str().unwrap()),
        );
        let m = rho * area(e["section"].as_str().unwrap()) * norm(sub(b, a));
        mass += m;
        for c in 0..3 {
            moment[c] += m * 0.5 * (a[c] + b[c]);
        }
    }
    Hand {
        mass,
        com: moment.map(|x| x / mass),
        ball,
        bolts: [pos("br_left"), pos("br_right")],
    }
}

/// The default scene with `overrides`, its run with three extra channels: the hitch's
/// centre-of-mass acceleration in car body axes (`cm_a.x/y/z`) and the body's pitch and
/// roll (to resolve gravity in body axes).
fn run(overrides: &[(&str, &str, &str)], duration_s: Option<f64>) -> (RunResult, f64) {
    let ov = overrides
        .iter()
        .map(|(file, path, value)| Override::program(file, path, value.to_string(), "test"))
        .collect();
    let loader = Loader::with_overrides(ov);
    let changes = scene::Changes {
        duration_s,
        ..Default::default()
    };
    let mut s =
        scene::load_with(Path::new(repo!("scenes/default.toml")), &changes, &loader).unwrap();
    let m = &mut s.vehicle.model;
    let find = |name: &str| m.markers.iter().position(|k| k.name == name).unwrap();
    let (cm, car) = (find("hitch.cm"), find("car_body.cm"));
    let body = m.markers[car].body.unwrap();
    let mut extra = vec![Output::new(
        "cm_a",
        Request::Marker {
            marker: MarkerHandle::new(cm),
            quantity: MarkerQuantity::Acceleration,
            axes: Axes::Marker(MarkerHandle::new(car)),
        },
    )];
    for (name, quantity) in [("pitch", BodyQuantity::Pitch), ("roll", BodyQuantity::Roll)] {
        extra.push(Output::new(
            name,
            Request::Body {
                body,
                quantity,
                z_ref: 0.0,
            },
        ));
    }
    m.outputs.extend(extra);
    for (name, unit) in [
        ("cm_a.x", "m/s^2"),
        ("cm_a.y", "m/s^2"),
        ("cm_a.z", "m/s^2"),
        ("pitch", "rad"),
        ("roll", "rad"),
    ] {
        s.channels.push(Channel {
            name: name.into(),
            unit: unit.into(),
        });
    }
    let g = norm(s.vehicle.model.gravity);
    let job = Job::from_scene(s).unwrap();
    let res = job.run(&towride_mbs::progress::Silent).unwrap();
    assert!(res.completed());
    (res, g)
}

/// Sample `k` of the vector channels `<prefix>x/y/z`.
fn vec3(res: &RunResult, prefix: &str, k: usize) -> V {
    ["x", "y", "z"].map(|c| res.channel(&format!("{prefix}{c}")).unwrap()[k])
}

/// Gravity's acceleration in car body axes from the body's pitch and roll: the world z
/// axis in body axes is (-sin pitch, cos pitch sin roll, cos pitch cos roll) (yaw-pitch-
/// roll angles, ISO 8855).
fn gravity_in_body(res: &RunResult, k: usize, g: f64) -> V {
    let (p, r) = (
        res.channel("pitch").unwrap()[k],
        res.channel("roll").unwrap()[k],
    );
    [g * p.sin(), -g * p.cos() * r.sin(), -g * p.cos() * r.cos()]
}

/// Force and moment of bracket `side` into the body at sample `k`.
fn bracket(res: &RunResult, side: &str, k: usize) -> (V, V) {
    let get = |c: &str| res.channel(&format!("hitch_bracket_{side}_{c}")).unwrap()[k];
    (
        [get("fx"), get("fy"), get("fz")],
        [get("mx"), get("my"), get("mz")],
    )
}

fn at_rest(mount: &str) {
    let h = hand();
    let overrides = [("fabia/hitch.toml", "hitch.bracket_mount", mount)];
    let (res, g) = run(&overrides, Some(0.01));
    let ball = vec3(&res, "hitch_f", 0);
    let w = gravity_in_body(&res, 0, g).map(|x| x * h.mass);
    let ((fl, ml), (fr, mr)) = (bracket(&res, "left", 0), bracket(&res, "right", 0));
    // Forces: the body takes the ball load plus the hitch's weight.
    for c in 0..3 {
        let got = fl[c] + fr[c];
        let want = ball[c] + w[c];
        println!("{mount}: sum of bracket forces [{c}] {got:.4} N, ball + weight {want:.4} N");
        assert!(
            (got - want).abs() < 1e-3 * h.mass * g,
            "{c}: {got} vs {want}"
        );
    }
    // Moments about the ball centre: the brackets' equal the weight's.
    let mut got = [0.0; 3];
    for (f, m, p) in [(fl, ml, h.bolts[0]), (fr, mr, h.bolts[1])] {
        let t = cross(sub(p, h.ball), f);
        for c in 0..3 {
            got[c] += m[c] + t[c];
        }
    }
    let want = cross(sub(h.com, h.ball), w);
    let scale = norm(want);
    for c in 0..3 {
        println!(
            "{mount}: bracket moments about the ball [{c}] {:.4} N m, weight's {:.4} N m",
            got[c], want[c]
        );
        assert!(
            (got[c] - want[c]).abs() < 2e-3 * scale,
            "{c}: {got:?} vs {want:?}"
        );
    }
    // Mirror images in the x-z plane: y forces and x, z moments change sign.
    let mirror = [1.0, -1.0, 1.0];
    let scale = norm(fl) + norm(ml);
    for c in 0..3 {
        assert!(
            (fl[c] - mirror[c] * fr[c]).abs() < 1e-6 * scale,
            "f{c}: {fl:?} {fr:?}"
        );
        assert!(
            (ml[c] + mirror[c] * mr[c]).abs() < 1e-6 * scale,
            "m{c}: {ml:?} {mr:?}"
        );
    }
}

#[test]
fn bushing_brackets_carry_the_ball_load_and_the_hitch_weight_at_rest() {
    at_rest("\"bushing\"");
}

#[test]
fn fixed_brackets_carry_the_ball_load_and_the_hitch_weight_at_rest() {
    at_rest("\"fixed\"");
}

#[test]
fn newtons_law_for_the_hitch_closes_over_the_bump_run() {
    let h = hand();
    let (res, g) = run(&[], None);
    let n = res.channel("hitch_fx").unwrap().len();
    let (mut worst, mut peak) = (0.0f64, 0.0f64);
    for k in 0..n {
        let ball = vec3(&res, "hitch_f", k);
        let w = gravity_in_body(&res, k, g).map(|x| x * h.mass);
        let ((fl, _), (fr, _)) = (bracket(&res, "left", k), bracket(&res, "right", k));
        let a = vec3(&res, "cm_a.", k);
        for c in 0..3 {
            // The brackets' loads on the hitch are minus theirs on the body.
            let sum = ball[c] + w[c] - fl[c] - fr[c];
            worst = worst.max((sum - h.mass * a[c]).abs());
            peak = peak.max(ball[c].abs());
        }
    }
    println!("hitch Newton residual: worst {worst:.3} N against a ball-force peak {peak:.1} N");
    // The samples are interpolated between steps (measured: 4.0 N, 0.08 % of the peak).
    assert!(worst < 2e-3 * peak, "{worst} N vs peak {peak} N");
}

/// The run summary's durability block covers the ball force, every bracket load
/// component and each stress point's equivalent stress, each in its unit; its DELs equal
/// those of the PyPI `rainflow` package (3.2.0) run on the same samples:
/// DEL = (sum n r^3 / 2e6)^(1/3).
#[test]
fn the_run_durability_block_covers_brackets_and_stresses_as_the_rainflow_package_counts() {
    let (res, _) = run(&[], None);
    let d = &res.summary.durability;
    let units = |u: &str| d.iter().filter(|x| x.unit == u).count();
    assert_eq!(
        (d.len(), units("N"), units("N m"), units("Pa")),
        (19, 9, 6, 4)
    );
    let py = crate::common::python_with(
        &std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("rainflow-venv"),
        "rainflow",
        &["rainflow==3.2.0"],
    );
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("brackets-del");
    std::fs::create_dir_all(&dir).unwrap();
    for name in [
        "hitch_bracket_left_fx",
        "hitch_bracket_right_my",
        "hitch_stress_mid_span_eq",
    ] {
        let x = res.channel(name).unwrap();
        let input = dir.join(format!("{name}.txt"));
        let text: Vec<String> = x.iter().map(|v| format!("{v:e}")).collect();
        std::fs::write(&input, text.join("\n")).unwrap();
        let script = "import sys, rainflow\n\
            x = [float(l) for l in open(sys.argv[1])]\n\
            s = sum(n * r ** 3 for r, n in rainflow.count_cycles(x))\n\
            print(repr((s / 2e6) ** (1 / 3)))\n";
        let out = std::process::Command::new(&py)
            .arg("-c")
            .arg(script)
            .arg(&input)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let theirs: f64 = String::from_utf8(out.stdout)
            .unwrap()
            .trim()
            .parse()
            .unwrap();
        let ours = d.iter().find(|e| e.channel == name).unwrap().del_at_n_ref;
        println!("{name}: DEL {ours:.6e}, rainflow package {theirs:.6e}");
        assert!(
            (ours / theirs - 1.0).abs() < 1e-9,
            "{name}: {ours} vs {theirs}"
        );
    }
}
