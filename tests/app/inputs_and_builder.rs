//! Overrides reach every reader, unused overrides are errors at their origin, and the
//! model builder applies one set of checks to mechanism files and vehicle files alike.

use std::path::{Path, PathBuf};

use towride_app::job::Job;
use towride_app::scene::{self, Changes};
use towride_app::sweep::exec::run_sweep;
use towride_app::sweep::Sweep;
use towride_app::vehicle::{self, Options};
use towride_mbs::input::{InputError, Loader, Override};
use towride_mbs::progress::Silent;

/// A scratch folder, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(tag: &str) -> Scratch {
        let d = std::env::temp_dir().join(format!("towride-inb-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        Scratch(d)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// 1-based line of the first occurrence of `needle` in `text`.
fn line_of(text: &str, needle: &str) -> usize {
    text[..text.find(needle).expect("needle in text")]
        .matches('\n')
        .count()
        + 1
}

const TIR: &str = "car_185_60r14.tir";

#[test]
fn a_tir_override_reaches_the_tyre_and_a_sweep_over_it_changes_the_results() {
    let default = Path::new(repo!("scenes/default.toml"));
    // The value read by the tyre is the override's, not the file's 200 kN/m.
    let loader = Loader::with_overrides(vec![Override::program(
        TIR,
        "VERTICAL.VERTICAL_STIFFNESS",
        "260000",
        "test",
    )]);
    let s = scene::load_with(default, &Changes::default(), &loader).unwrap();
    let front = &s.model().tyres[0];
    assert_eq!(front.name, "tyre_fl");
    assert_eq!(front.tyre.params().cz, 260000.0);
    let trailer = s
        .model()
        .tyres
        .iter()
        .find(|t| t.name == "tyre_tl")
        .unwrap();
    assert_eq!(trailer.tyre.params().cz, {
        // The trailer's tyre is another file: untouched.
        let plain = scene::load(default).unwrap();
        let t = plain
            .model()
            .tyres
            .iter()
            .find(|t| t.name == "tyre_tl")
            .unwrap();
        t.tyre.params().cz
    });

    // A sweep over that value, over the first 0.15 s (the front wheels' impact).
    let d = Scratch::new("tirsweep");
    let sweep = d.write(
        "sweep.toml",
        &format!(
            "[sweep]\nname = \"tyre stiffness\"\nscene = \"{}\"\n\n\
             [[parameter]]\nname = \"cz\"\nfile = \"{TIR}\"\npath = \"VERTICAL.VERTICAL_STIFFNESS\"\nvalues = [150000.0, 260000.0]\n\n\
             [[parameter]]\nname = \"duration\"\nfile = \"default.toml\"\npath = \"run.duration_s\"\nvalues = [0.15]\n",
            default.display()
        ),
    );
    let sw = Sweep::load(&sweep).unwrap();
    let res = run_sweep(&sw, (0, 1), 2, &Silent).unwrap();
    assert_eq!(res.failed, 0, "{:?}", res.rows);
    let peak = |k: usize| {
        res.rows[k]
            .figures
            .iter()
            .find(|(n, _)| n == "acc_wheel_front_left_z abs_peak [m/s^2]")
            .unwrap()
            .1
    };
    let (soft, stiff) = (peak(0), peak(1));
    println!("front wheel |peak| acceleration: cz 150 kN/m {soft:.1}, 260 kN/m {stiff:.1} m/s^2");
    assert!((stiff / soft - 1.0).abs() > 0.01, "{soft} vs {stiff}");
}

#[test]
fn a_sweep_parameter_that_matches_nothing_is_an_error_at_its_line_and_field() {
    let d = Scratch::new("nomatch");
    let text = format!(
        "[sweep]\nname = \"typos\"\nscene = \"{}\"\n\n\
         [[parameter]]\nname = \"mass\"\nfile = \"pendulm.toml\"\npath = \"body[0].mass_kg\"\nvalues = [1.0]\n",
        repo!("scenes/examples/pendulum.toml")
    );
    let sweep = d.write("sweep.toml", &text);
    let sw = Sweep::load(&sweep).unwrap();
    // Refused before any case runs (every case would fail with it).
    let e = run_sweep(&sw, (0, 1), 1, &Silent).unwrap_err().to_string();
    let want = format!(
        "{}:{}:",
        sweep.display(),
        line_of(&text, "file = \"pendulm")
    );
    assert!(e.starts_with(&want), "{e}");
    assert!(
        e.contains("parameter[0].file") && e.contains("pendulm.toml"),
        "{e}"
    );
    assert!(e.contains("pendulum.toml"), "lists the files read: {e}");

    // The file matches but the path does not (a .tir section that does not exist).
    let text = text
        .replace("pendulm.toml", "pendulum.toml")
        .replace("body[0].mass_kg", "bodies[0].mass_kg");
    let sweep = d.write("sweep2.toml", &text);
    let e = run_sweep(&Sweep::load(&sweep).unwrap(), (0, 1), 1, &Silent)
        .unwrap_err()
        .to_string();
    let want = format!("{}:{}:", sweep.display(), line_of(&text, "path = \"bodies"));
    assert!(
        e.starts_with(&want) && e.contains("parameter[0].path"),
        "{e}"
    );
}

#[test]
fn a_scene_override_table_changes_a_vehicle_file_and_a_bad_one_is_located() {
    let d = Scratch::new("sceneov");
    let good = format!(
        "{}\n[[override]]\nfile = \"fabia/hitch.toml\"\npath = \"ball_coupling.kind\"\nvalue = \"bushing\"\n",
        default_scene_text()
    );
    let s = scene::load(&d.write("good.toml", &good)).unwrap();
    let (_, kind) = s.vehicle.handles.ball.as_ref().unwrap();
    assert!(
        matches!(kind, towride_app::vehicle::BallKind::Bushing(_)),
        "{kind:?}"
    );
    let bad = good.replace("fabia/hitch.toml", "fabia/hitchh.toml");
    let path = d.write("bad.toml", &bad);
    let e = scene::load(&path).unwrap_err();
    assert_eq!(e.file, path);
    assert_eq!(e.line, Some(line_of(&bad, "file = \"fabia/hitchh")), "{e}");
    assert_eq!(e.field, "override[0].file", "{e}");
}

/// A value set both by a scene's `[[override]]` table and by the caller (`run --set`, a
/// sweep case, a sensitivity study) takes the caller's: the scene's tables are applied
/// first. Both are recorded as used.
#[test]
fn the_callers_override_wins_over_the_scenes_own() {
    let d = Scratch::new("sceneov2");
    let path = engine_mass_scene(&d);
    let engine_mass = |s: &scene::Scene| {
        let b = &s.vehicle.model.bodies;
        b[b.iter().position(|b| b.name == "engine").unwrap()].mass
    };
    assert_eq!(engine_mass(&scene::load(&path).unwrap()), 110.0);
    let caller = towride_mbs::input::Loader::with_overrides(vec![
        towride_mbs::input::Override::from_argument("fabia/engine.toml:engine.mass_kg=130.0")
            .unwrap(),
    ]);
    let s = scene::load_with(&path, &Default::default(), &caller).unwrap();
    assert_eq!(engine_mass(&s), 130.0);
}

/// A sensitivity study perturbs the value the run uses: its base is the scene's
/// `[[override]]` value, not the file's (125 kg), and its perturbed runs change it.
#[test]
fn a_sensitivity_base_is_the_scenes_overridden_value() {
    use towride_app::study::sensitivity::params::{candidates, Base};
    let d = Scratch::new("sceneov3");
    let path = engine_mass_scene(&d);
    let all = candidates(&path, &[]).unwrap();
    let p = all
        .iter()
        .find(|p| p.path == "engine.mass_kg" && p.file.ends_with("fabia/engine.toml"))
        .expect("the engine's mass is a parameter");
    assert_eq!(p.base, Base::Scalar(110.0));
    let s = scene::load_with(
        &path,
        &Default::default(),
        &Loader::with_overrides(vec![p.scaled(1.1)]),
    )
    .unwrap();
    let b = &s.vehicle.model.bodies;
    let engine = &b[b.iter().position(|b| b.name == "engine").unwrap()];
    assert!((engine.mass - 121.0).abs() < 1e-9, "{}", engine.mass);
}

/// The default scene's text for a copy in another folder: its relative paths point back
/// to the repository.
fn default_scene_text() -> String {
    let base = std::fs::read_to_string(repo!("scenes/default.toml")).unwrap();
    let root = Path::new(repo!("")).display().to_string();
    base.replace("\"../vehicles/", &format!("\"{root}vehicles/"))
        .replace("\"../roads/", &format!("\"{root}roads/"))
}

/// The default scene with an `[[override]]` setting the engine's mass to 110 kg.
fn engine_mass_scene(d: &Scratch) -> PathBuf {
    let text = format!(
        "{}\n[[override]]\nfile = \"fabia/engine.toml\"\npath = \"engine.mass_kg\"\nvalue = 110.0\n",
        default_scene_text()
    );
    d.write("scene.toml", &text)
}

fn mechanism(d: &Scratch, name: &str, text: &str) -> Result<Job, towride_app::Error> {
    Job::from_mechanism_file(&d.write(name, text), &Loader::new())
}

fn input_error(e: towride_app::Error) -> InputError {
    match e {
        towride_app::Error::Input(e) => e,
        other => panic!("not an input error: {other}"),
    }
}

#[test]
fn a_bump_stop_clearance_of_zero_is_accepted_and_a_negative_one_refused_on_both_paths() {
    // Mechanism file.
    let d = Scratch::new("stops");
    let text = std::fs::read_to_string(repo!("scenes/examples/elements.toml")).unwrap();
    let zero = text.replacen(
        "bump_stop = { clearance_m = 0.02",
        "bump_stop = { clearance_m = 0.0",
        1,
    );
    assert_ne!(zero, text);
    mechanism(&d, "zero.toml", &zero).unwrap();
    let negative = text.replacen(
        "bump_stop = { clearance_m = 0.02",
        "bump_stop = { clearance_m = -0.01",
        1,
    );
    let e = input_error(mechanism(&d, "neg.toml", &negative).err().unwrap());
    assert_eq!(
        e.line,
        Some(line_of(&negative, "clearance_m = -0.01")),
        "{e}"
    );
    assert!(
        e.field.ends_with("bump_stop.clearance_m") && e.field.starts_with("spring["),
        "{e}"
    );
    assert!(e.message.contains("must not be negative"), "{e}");

    // Vehicle property file (the front axle's bump stop), through an override.
    let front = "fabia/front_mcpherson.toml";
    let load = |v: &str| {
        let l = Loader::with_overrides(vec![Override::program(
            front,
            "bump_stop.clearance_m",
            v,
            "test",
        )]);
        vehicle::load(
            Path::new(repo!("vehicles/fabia_trailer.toml")),
            &Options::default(),
            &l,
        )
    };
    load("0.0").unwrap();
    let e = load("-0.01").unwrap_err();
    let file = std::fs::read_to_string(repo!("vehicles/fabia/front_mcpherson.toml")).unwrap();
    assert!(e.file.ends_with(front), "{e}");
    let stop_line = line_of(&file, "[bump_stop]") + 1;
    assert_eq!(e.line, Some(stop_line), "{e}");
    assert_eq!(e.field, "bump_stop.clearance_m", "{e}");
    assert!(e.message.contains("must not be negative"), "{e}");
}

#[test]
fn duplicate_joints_self_bushings_and_unknown_tables_are_refused_with_their_line() {
    let d = Scratch::new("builder");
    let text = std::fs::read_to_string(repo!("scenes/examples/pendulum.toml")).unwrap();
    let twice = format!(
        "{text}\n[[joint]]\nname = \"pivot\"\ntype = \"spherical\"\nbody_i = \"bob\"\nbody_j = \"ground\"\nposition_m = [0.0, 0.0, 0.0]\n"
    );
    let e = input_error(mechanism(&d, "twice.toml", &twice).err().unwrap());
    assert_eq!(e.field, "joint[1].name", "{e}");
    assert!(e.message.contains("defined twice"), "{e}");

    let selfb = format!(
        "{text}\n[[bushing]]\nname = \"self\"\nbody_i = \"bob\"\nbody_j = \"bob\"\nposition_m = [1.0, 0.0, 0.0]\n\
         stiffness_n_m = [1.0, 1.0, 1.0]\ndamping_n_s_m = [0.0, 0.0, 0.0]\n\
         stiffness_n_m_rad = [1.0, 1.0, 1.0]\ndamping_n_m_s_rad = [0.0, 0.0, 0.0]\n"
    );
    let e = input_error(mechanism(&d, "self.toml", &selfb).err().unwrap());
    assert_eq!(e.field, "bushing[0].body_j", "{e}");
    assert_eq!(e.line, Some(line_of(&selfb, "body_j = \"bob\"")), "{e}");

    let unknown = format!("{text}\n[[sprng]]\nname = \"x\"\n");
    let e = input_error(mechanism(&d, "unknown.toml", &unknown).err().unwrap());
    assert_eq!(e.field, "sprng", "{e}");
    assert!(
        e.message.contains("spring") && e.message.contains("rotational_spring"),
        "{e}"
    );
}

#[test]
fn an_axle_slot_takes_any_registered_axle_template_and_names_them_when_wrong() {
    let names = towride_app::vehicle::axle::names();
    assert!(names.contains(&"mcpherson") && names.contains(&"twist_beam"));
    crate::vehicle_templates::refused_template(
        "car.rear.template",
        "trailing_arm",
        &["mcpherson", "twist_beam"],
    );
}
