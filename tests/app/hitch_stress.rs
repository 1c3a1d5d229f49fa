//! The hitch's nominal-stress channels in a run: present with units in `outputs.csv`, and
//! at rest the hook root (`ball_mount`) carries what statics says: the trailer's nose load
//! at the ball and the hook's and ball's weight, a cantilever from the crossbeam.

use std::f64::consts::PI;
use std::path::Path;

use towride_app::job::Job;
use towride_app::scene;
use towride_mbs::input::Loader;

const FLEX: &str = repo!("flex/hitch_crossbeam.toml");

#[test]
fn ball_mount_stress_at_rest_matches_statics_of_the_hook() {
    let loader = Loader::new();
    let file = Path::new(repo!("scenes/default.toml"));
    let s = scene::load_with(file, &scene::Changes::default(), &loader).unwrap();
    let job = Job::from_scene(s).unwrap();
    let mut res = job.run(&towride_mbs::progress::Silent).unwrap();
    assert!(res.completed());
    let dir = std::env::temp_dir().join(format!("towride-stress-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    towride_app::report::write_run(&mut res, &job.system, &dir).unwrap();
    let csv = std::fs::read_to_string(dir.join("outputs.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for p in ["weld_left", "weld_right", "ball_mount", "mid_span"] {
        for c in ["sx_max", "sx_min", "tau", "eq"] {
            let h = format!("hitch_stress_{p}_{c} [Pa]");
            assert!(header.split(',').any(|x| x == h), "{h} not in {header}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();

    // Hand statics from the flex file's numbers.
    let t: toml::Value = toml::from_str(&std::fs::read_to_string(FLEX).unwrap()).unwrap();
    let pos = |n: &str| -> [f64; 3] {
        let node = t["node"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["name"].as_str() == Some(n))
            .unwrap();
        let p = node["position_m"].as_array().unwrap();
        [0, 1, 2].map(|i| p[i].as_float().unwrap())
    };
    let sec = t["section"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["name"].as_str() == Some("hook"))
        .unwrap();
    let d = sec["diameter_m"].as_float().unwrap();
    let rho = t["material"][0]["density_kg_m3"].as_float().unwrap();
    let ball_mass = t["point_mass"][0]["mass_kg"].as_float().unwrap();
    let g = 9.81;
    let (area, w) = (PI * d * d / 4.0, PI * d.powi(3) / 32.0);
    let root = pos("cb_mid");
    let chain = ["cb_mid", "hook_low", "hook_rear", "ball"].map(pos);
    // Downward loads and their horizontal levers about the root section.
    let fz = res.channel("hitch_fz").unwrap()[0].abs();
    let mut weight = fz + ball_mass * g;
    let mut moment = (fz + ball_mass * g) * (root[0] - chain[3][0]);
    for k in 0..3 {
        let (a, b) = (chain[k], chain[k + 1]);
        let len = ((b[0] - a[0]).powi(2) + (b[2] - a[2]).powi(2)).sqrt();
        let m = rho * area * len * g;
        weight += m;
        moment += m * (root[0] - 0.5 * (a[0] + b[0]));
    }
    // The root element points down the hook: the hanging loads pull along it.
    let axis = [chain[1][0] - root[0], chain[1][2] - root[2]];
    let n = weight * axis[1].abs() / axis[0].hypot(axis[1]);
    let want = n / area + moment / w;
    let got = res.channel("hitch_stress_ball_mount_sx_max").unwrap()[0];
    println!("ball mount at rest: {got:.4e} Pa, statics {want:.4e} Pa (nose load {fz:.1} N)");
    assert!((got - want).abs() < 0.02 * want, "{got} vs {want}");
}
