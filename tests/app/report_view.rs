//! The reports' 3D view: poses sampled between the output samples by the integrator's
//! dense output (against the analytical solution, without changing the steps), and the
//! names `linear` gives modes (against a body on four springs whose bounce, pitch and
//! roll frequencies are analytical).

use std::path::Path;

use towride_mbs::input::Source;
use towride_mbs::model::run::{simulate, simulate_with_poses};
use towride_mbs::model::spec::{self, Mechanism};
use towride_mbs::model::{linear, statics, System};

fn from_text(name: &str, text: &str) -> Mechanism {
    let src = Source::from_text(Path::new(name), text.to_string()).unwrap();
    let file = src.parse().unwrap();
    spec::build(&src, file).unwrap_or_else(|e| panic!("{e}"))
}

/// A mass on a vertical spring along a vertical guide, released at the spring's free
/// length: z(t) = z0 - (m g / k) (1 - cos w t).
const MASS_SPRING: &str = r#"[model]
name = "mass on a spring"
gravity_m_s2 = [0.0, 0.0, -9.81]
[run]
end_time_s = 0.5
sample_rate_hz = 100.0
[[body]]
name = "mass"
mass_kg = 7.5
inertia_kg_m2 = [0.1, 0.1, 0.1]
cm_position_m = [0.0, 0.0, 1.0]
[[joint]]
name = "guide"
type = "translational"
body_i = "mass"
body_j = "ground"
position_m = [0.0, 0.0, 1.0]
[[spring]]
name = "k"
body_i = "mass"
point_i_m = [0.0, 0.0, 1.0]
body_j = "ground"
point_j_m = [0.0, 0.0, 0.0]
stiffness_n_m = 3000.0
"#;

#[test]
fn poses_between_samples_follow_the_analytical_motion_and_keep_the_steps() {
    let m = from_text("mass_spring.toml", MASS_SPRING);
    let sys = System::new(m.model.clone());
    let mut opts = m.solver.clone();
    opts.rtol = 1e-8;
    opts.atol = vec![1e-10];
    let silent = &towride_mbs::progress::Silent;
    let plain = simulate(&sys, 0.0, 0.5, 100.0, &opts, None, silent);
    // 70 Hz poses: none but the first on the 100 Hz sample grid.
    let with = simulate_with_poses(&sys, 0.0, 0.5, 100.0, 70.0, &opts, None, silent);
    assert!(plain.poses.is_none());
    assert_eq!(plain.stats.steps, with.stats.steps);
    assert_eq!(plain.rows, with.rows, "the channels change with poses");
    let p = with.poses.as_ref().unwrap();
    assert_eq!(p.times.len(), 36); // 0, 1/70, ..., 35/70 = 0.5
    let w = (3000.0f64 / 7.5).sqrt();
    let d = 7.5 * 9.81 / 3000.0;
    for (t, q) in p.times.iter().zip(&p.q) {
        let z = 1.0 - d * (1.0 - (w * t).cos());
        assert!(
            (q[2] - z).abs() < 1e-6 * d.max(1.0),
            "t = {t}: z {} vs {z}",
            q[2]
        );
        // A unit quaternion.
        let n: f64 = q[3..7].iter().map(|x| x * x).sum();
        assert!((n - 1.0).abs() < 1e-9);
    }
    // The rate is capped at the sample rate.
    let dense = simulate_with_poses(&sys, 0.0, 0.5, 100.0, 1000.0, &opts, None, silent);
    assert_eq!(dense.poses.unwrap().times.len(), 51);
}

/// A free box on four vertical springs at (+-a, +-b) in the plane of its centre of mass:
/// bounce w^2 = 4k/m, pitch w^2 = 4 k a^2 / I_yy, roll w^2 = 4 k b^2 / I_xx.
fn four_springs(m: f64, ixx: f64, iyy: f64, k: f64, a: f64, b: f64) -> String {
    let mut s = format!(
        r#"[model]
name = "box on four springs"
gravity_m_s2 = [0.0, 0.0, -9.81]
[run]
end_time_s = 1.0
sample_rate_hz = 100.0
start = "statics"
[[body]]
name = "box"
mass_kg = {m}
inertia_kg_m2 = [{ixx}, {iyy}, {izz}]
cm_position_m = [0.0, 0.0, 1.0]
"#,
        izz = ixx + iyy
    );
    for (k_, (x, y)) in [(a, b), (a, -b), (-a, b), (-a, -b)].iter().enumerate() {
        s += &format!(
            r#"[[spring]]
name = "k{k_}"
body_i = "box"
point_i_m = [{x}, {y}, 1.0]
body_j = "ground"
point_j_m = [{x}, {y}, 0.0]
stiffness_n_m = {k}
free_length_m = 1.0
"#
        );
    }
    s
}

#[test]
fn linear_names_bounce_pitch_and_roll_of_a_box_on_springs() {
    let (m, ixx, iyy, k, a, b) = (1000.0, 400.0, 1500.0, 20000.0, 1.2, 0.7);
    let mech = from_text("four_springs.toml", &four_springs(m, ixx, iyy, k, a, b));
    let sys = System::new(mech.model);
    let st = statics::equilibrium(&sys, 0.0, &mech.solver).unwrap();
    let lin = linear::linearise(&sys, 0.0, &st.y).unwrap();
    let hz = |w2: f64| w2.sqrt() / (2.0 * std::f64::consts::PI);
    for (want, f) in [
        ("box bounce", hz(4.0 * k / m)),
        ("box pitch", hz(4.0 * k * a * a / iyy)),
        ("box roll", hz(4.0 * k * b * b / ixx)),
    ] {
        let mode = lin
            .modes
            .iter()
            .min_by(|p, q| {
                (p.undamped_hz - f)
                    .abs()
                    .total_cmp(&(q.undamped_hz - f).abs())
            })
            .unwrap();
        // The springs' preload adds geometric stiffness only to the horizontal motions.
        assert!(
            (mode.undamped_hz / f - 1.0).abs() < 1e-3,
            "{want}: {} Hz vs {f} Hz",
            mode.undamped_hz
        );
        assert_eq!(mode.name, want, "mode at {f} Hz");
        assert!(mode.name_share > 0.99, "{want}: share {}", mode.name_share);
        assert!(!mode.shape.is_empty());
    }
    // The page carries one shape per moving mode and opens with the table.
    let page = towride_app::report::linear::linear_report(&sys, &st.y, &lin, "equilibrium");
    assert!(page.contains("box bounce") && page.contains("THREE"));
}

#[test]
fn the_scene_sets_the_animation_rate_and_a_negative_one_is_refused_at_its_line() {
    let text = std::fs::read_to_string(repo!("scenes/default.toml"))
        .unwrap()
        .replace("\"../", &format!("\"{}/", repo!("")));
    let dir = std::env::temp_dir().join(format!("towride-anim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = |rate: &str| {
        let path = dir.join(format!("scene_{}.toml", rate.len()));
        std::fs::write(
            &path,
            format!("{text}\n[report]\nanimation_rate_hz = {rate}\n"),
        )
        .unwrap();
        towride_app::job::Job::from_file(&path, &towride_mbs::input::Loader::new())
    };
    let job = scene("50.0").unwrap();
    assert_eq!(job.settings.animation_rate, 50.0);
    let err = scene("-5.0").err().unwrap().to_string();
    let line = text.lines().count() + 3;
    assert!(
        err.contains("animation_rate_hz") && err.contains(&format!(":{line}")),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
