//! Steering through the rack (`[run.steering]`): a steady low-speed turn follows the
//! kinematic (Ackermann) yaw rate of the steer angle the knuckles take, with wheelbase and
//! steer angle measured on the model's own markers; without steering no rack is built; a
//! front axle that cannot steer is refused at the field.

use std::path::{Path, PathBuf};

use towride_app::job::Job;
use towride_app::scene;

/// A scene file in a temporary folder, paths absolute.
fn scene_file(tag: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("towride_steer_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join(format!("{tag}.toml"));
    let repo = std::fs::canonicalize(repo!("")).unwrap();
    std::fs::write(&f, text.replace("REPO", &repo.display().to_string())).unwrap();
    f
}

const TURN: &str = r#"
[scene]
name = "steady turn"
vehicle = "REPO/vehicles/fabia_trailer.toml"
load_case = "empty"
hitch_variant = 5
[road]
file = "REPO/roads/flat.toml"
[run]
speed_km_h = 15.0
duration_s = 6.0
sample_rate_hz = 200.0
start = "equilibrium_at_speed"
settle_s = 0.5
[run.steering]
rack_m = { type = "table", time_s = [0.5, 1.5], value = [0.0, 0.003] }
[solver]
rtol = 1e-4
[[output]]
marker = "car_body.cm"
quantity = "angular_velocity"
axes = "car_body.cm"
name = "yaw"
"#;

/// Position outputs of markers in the car body's axes.
fn positions(markers: &[&str]) -> String {
    markers
        .iter()
        .map(|m| {
            format!(
                "[[output]]\nmarker = \"{m}\"\nquantity = \"position\"\naxes = \"car_body.cm\"\nname = \"p_{}\"\n",
                m.replace('.', "_")
            )
        })
        .collect()
}

#[test]
fn a_steady_low_speed_turn_follows_the_kinematic_yaw_rate_of_the_steer_angle() {
    let marks = [
        "tie_rod_outer_fl.j",
        "knuckle_fl.cm",
        "tie_rod_outer_fr.j",
        "knuckle_fr.cm",
        "wheel_fl.centre",
        "wheel_rl.centre",
    ];
    let file = scene_file("turn", &format!("{TURN}{}", positions(&marks)));
    let s = scene::load(&file).unwrap();
    assert!(s
        .vehicle
        .model
        .bodies
        .iter()
        .any(|b| b.name == "steering_rack"));
    let job = Job::from_scene(s).unwrap();
    let res = job.run(&towride_mbs::progress::Silent).unwrap();
    assert!(res.completed());
    let ch = |n: &str| res.channel(n).unwrap();
    let p = |m: &str, c: &str, k: usize| ch(&format!("p_{}.{c}", m.replace('.', "_")))[k];
    let last = res.samples.times.len() - 1;
    // The steer angle: the yaw of a knuckle-fixed line (knuckle centre of mass to the tie
    // rod's outer joint) in the body's axes, against its design direction.
    let yaw_of = |t: &str, k: &str, i: usize| {
        (p(t, "y", i) - p(k, "y", i)).atan2(p(t, "x", i) - p(k, "x", i))
    };
    let delta: f64 = [
        ("tie_rod_outer_fl.j", "knuckle_fl.cm"),
        ("tie_rod_outer_fr.j", "knuckle_fr.cm"),
    ]
    .iter()
    .map(|(t, k)| yaw_of(t, k, last) - yaw_of(t, k, 0))
    .sum::<f64>()
        / 2.0;
    // Rack travel to the left with the tie rods behind the axle steers to the right.
    assert!(delta < -0.01, "steer angle {delta} rad");
    let wheelbase = p("wheel_fl.centre", "x", 0) - p("wheel_rl.centre", "x", 0);
    let v = ch("speed")[last];
    let yaw = ch("yaw.z");
    let kinematic = v * delta.tan() / wheelbase;
    // Steady: the last second does not move.
    let k1 = res.samples.times.iter().position(|&t| t >= 5.0).unwrap();
    assert!(
        (yaw[k1] - yaw[last]).abs() < 1e-3 * yaw[last].abs(),
        "{} {}",
        yaw[k1],
        yaw[last]
    );
    // At 0.16 m/s^2 of lateral acceleration the understeer and the line's tilt with the
    // kingpin take a few per cent off the kinematic value.
    let ratio = yaw[last] / kinematic;
    assert!(
        ratio > 0.95 && ratio < 1.01,
        "yaw rate {} against {kinematic}: {ratio}",
        yaw[last]
    );
}

#[test]
fn without_steering_no_rack_is_built_and_an_axle_that_cannot_steer_is_refused() {
    let s = scene::load(Path::new(repo!("scenes/default.toml"))).unwrap();
    assert!(!s
        .vehicle
        .model
        .bodies
        .iter()
        .any(|b| b.name == "steering_rack"));
    assert!(s.vehicle.model.motions.is_empty());
    // The van's compact file has no McPherson front axle.
    let van = std::fs::read_to_string(repo!("scenes/van_air/bump_50mm.toml")).unwrap();
    let folder = std::fs::canonicalize(repo!("scenes/van_air")).unwrap();
    let text = format!(
        "{}\n[run.steering]\nrack_m = {{ type = \"constant\", value = 0.001 }}\n",
        van.replace("\"../", &format!("\"{}/../", folder.display()))
    );
    let f = scene_file("van", &text);
    let e = scene::load(&f).unwrap_err().to_string();
    let line = text.lines().position(|l| l == "[run.steering]").unwrap() + 1;
    assert!(
        e.contains(&format!(":{line}:")) && e.contains("run.steering"),
        "{e}"
    );
    assert!(e.contains("no steering rack"), "{e}");
}
