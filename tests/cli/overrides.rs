//! Issues 31 and 32: every override takes effect or is an error located where it was
//! written; a run records what produced it and `--overrides` reproduces it; every
//! command that reads a scene takes the same input options.

use std::path::PathBuf;

use crate::{towride, towride_err, towride_json};

const SCENE: &str = repo!("scenes/default.toml");
const VAN: &str = repo!("scenes/van_air/bump_50mm.toml");
/// A run short enough for a test: the front wheels are on the ramp at 0.07 s.
const SHORT: &str = "default.toml:run.duration_s=0.15";

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride_ov_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A copy of the default scene in `dir` (its file references made absolute) with
/// `extra` appended.
fn scene_copy(dir: &std::path::Path, extra: &str) -> String {
    let text = std::fs::read_to_string(SCENE)
        .unwrap()
        .replace("\"../", &format!("\"{}/", env!("CARGO_MANIFEST_DIR")));
    let p = dir.join("scene.toml");
    std::fs::write(&p, format!("{text}\n{extra}")).unwrap();
    p.display().to_string()
}

/// The error line of a refused command (exit 2).
fn refused(args: &[&str]) -> String {
    let e = towride_err(args, 2);
    assert!(!e.contains("panicked"), "{e}");
    e
}

#[test]
fn an_override_of_the_hitch_variant_takes_effect_over_the_scene_s() {
    // c4bd0ca: the scene's hitch_variant = 5 won and the run said nothing.
    let out = tmp("variant");
    let o = out.display().to_string();
    let v = towride_json(&[
        "run",
        SCENE,
        "--json",
        "--out",
        &o,
        "--set",
        SHORT,
        "--set",
        "hitch.toml:hitch.variant=7",
    ]);
    assert_eq!(v["scene"]["hitch_variant"], 7, "{}", v["scene"]);
}

#[test]
fn one_value_set_twice_is_refused_naming_both_places() {
    let e = refused(&[
        "run",
        SCENE,
        "--set",
        "default.toml:run.duration_s=0.1",
        "--set",
        "default.toml:run.duration_s=0.2",
    ]);
    assert!(
        e.contains("set twice") && e.contains("run.duration_s=0.1") && e.contains("=0.2"),
        "{e}"
    );
    // Two [[override]] tables of one value in a scene: the second's line is named.
    let dir = tmp("twice");
    let scene = scene_copy(
        &dir,
        "[[override]]\nfile = \"front_mcpherson.toml\"\npath = \"spring.stiffness_n_m\"\nvalue = 2.0e4\n\n\
         [[override]]\nfile = \"front_mcpherson.toml\"\npath = \"spring.stiffness_n_m\"\nvalue = 2.5e4\n",
    );
    let e = refused(&["run", &scene]);
    assert!(e.contains("scene.toml:") && e.contains("set twice"), "{e}");
    assert!(e.contains("override[1]"), "{e}");
}

#[test]
fn the_command_line_wins_over_a_scene_override_and_the_record_says_so() {
    let dir = tmp("layers");
    let scene = scene_copy(
        &dir,
        "[[override]]\nfile = \"hitch.toml\"\npath = \"hitch.variant\"\nvalue = 3\n",
    );
    let o = dir.join("out").display().to_string();
    let run = |more: &[&str]| {
        let mut a = vec![
            "run",
            &scene,
            "--json",
            "--out",
            &o,
            "--set",
            "scene.toml:run.duration_s=0.1",
            "--set",
            "scene.toml:scene.hitch_variant=2",
        ];
        a.extend(more);
        towride_json(&a)
    };
    // The scene's own [[override]] of the hitch file and its hitch_variant are one
    // layer: which one decides? Neither silently.
    let e = refused(&["run", &scene]);
    assert!(e.contains("hitch"), "{e}");
    // The command line decides over both.
    let v = run(&["--set", "hitch.toml:hitch.variant=7"]);
    assert_eq!(v["scene"]["hitch_variant"], 7, "{}", v["scene"]);
    let applied = v["produced_by"]["overrides"].as_array().unwrap();
    let variants: Vec<&serde_json::Value> = applied
        .iter()
        .filter(|a| a["path"] == "hitch.variant")
        .collect();
    assert_eq!(
        variants.len(),
        1,
        "the superseded one is not in effect: {applied:?}"
    );
    assert_eq!(variants[0]["value"], "7");
    assert_eq!(variants[0]["layer"], "caller");
}

#[test]
fn a_misspelt_tir_key_is_refused_with_the_nearest_name() {
    // c4bd0ca: the key was added, read by nothing, and the run exited 0.
    let e = refused(&[
        "run",
        SCENE,
        "--set",
        "car_185_60r14.tir:VERTICAL.VERTICAL_STIFNESS=1e5",
    ]);
    assert!(
        e.contains("--set car_185_60r14.tir:VERTICAL.VERTICAL_STIFNESS=1e5")
            && e.contains("'VERTICAL_STIFFNESS'"),
        "{e}"
    );
}

#[test]
fn a_value_towride_derives_for_a_simple_vehicle_cannot_be_overridden_silently() {
    // c4bd0ca: the van's derived tyre stiffness replaced the --set value, exit 0.
    let e = refused(&[
        "run",
        VAN,
        "--set",
        "car_185_60r14.tir:VERTICAL.VERTICAL_STIFFNESS=1e5",
    ]);
    assert!(
        e.contains("derived by towride") && e.contains("van.toml"),
        "{e}"
    );
}

#[test]
fn files_named_through_dot_dot_match_their_real_path() {
    // c4bd0ca: `vehicles/simple_defaults.toml` never matched
    // `scenes/van_air/../../vehicles/van_air/../simple_defaults.toml`.
    let out = tmp("normalised");
    let o = out.display().to_string();
    let v = towride_json(&[
        "run",
        VAN,
        "--json",
        "--out",
        &o,
        "--set",
        "van_air/bump_50mm.toml:run.duration_s=0.1",
        "--set",
        "vehicles/simple_defaults.toml:body.roll_gyration_per_track=0.42",
    ]);
    let applied = v["produced_by"]["overrides"].as_array().unwrap();
    assert!(
        applied.iter().any(|a| a["file"]
            .as_str()
            .unwrap()
            .ends_with("/vehicles/simple_defaults.toml")),
        "{applied:?}"
    );
}

#[test]
fn a_file_name_that_names_two_files_is_refused() {
    // The van's scene and the road are both bump_50mm.toml.
    let e = refused(&["run", VAN, "--set", "bump_50mm.toml:run.duration_s=0.2"]);
    assert!(
        e.contains("names two files")
            && e.contains("scenes/van_air/bump_50mm.toml")
            && e.contains("roads/bump_50mm.toml"),
        "{e}"
    );
}

#[test]
fn a_bad_override_value_is_blamed_on_the_override_not_the_file() {
    // c4bd0ca: blamed on scenes/default.toml's line, which still says 3.0.
    let e = refused(&["run", SCENE, "--set", "default.toml:run.duration_s=-1"]);
    assert!(
        e.starts_with("error: command line: field `--set default.toml:run.duration_s=-1`"),
        "{e}"
    );
    assert!(e.contains("must be positive"), "{e}");
    // A scene's [[override]]: its own line.
    let dir = tmp("blame");
    let scene = scene_copy(
        &dir,
        "[[override]]\nfile = \"front_mcpherson.toml\"\npath = \"spring.stiffness_n_m\"\nvalue = -2.0\n",
    );
    let e = refused(&["run", &scene]);
    let line = std::fs::read_to_string(&scene)
        .unwrap()
        .lines()
        .position(|l| l == "[[override]]")
        .unwrap()
        + 1;
    assert!(
        e.contains(&format!("scene.toml:{}", line + 2)) && e.contains("must be positive"),
        "{e}"
    );
}

#[test]
fn a_road_csv_override_meets_the_file_s_bounds_and_checks() {
    let road = "default.toml:road.file=\"../roads/profile_example.toml\"";
    // c4bd0ca: the value skipped the bounds and the run failed in the solver.
    let e = refused(&[
        "run",
        SCENE,
        "--set",
        road,
        "--set",
        "profile_example.csv:z_left_m[3]=1e6",
    ]);
    assert!(
        e.contains("--set profile_example.csv:z_left_m[3]=1e6") && e.contains("accepted range"),
        "{e}"
    );
    // A row check (x increasing) is the override's too.
    let e = refused(&[
        "run",
        SCENE,
        "--set",
        road,
        "--set",
        "profile_example.csv:x_m[3]=0.01",
    ]);
    assert!(
        e.contains("--set profile_example.csv:x_m[3]=0.01") && e.contains("increase strictly"),
        "{e}"
    );
}

#[test]
fn options_that_would_change_nothing_are_refused() {
    let e = refused(&["run", SCENE, "--case", "a"]);
    assert!(e.contains("--case") && e.contains("not a plan"), "{e}");
    // Radau IIA settings under a BDF method.
    let dir = tmp("radau");
    let scene = scene_copy(&dir, "");
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("[solver]\n", "[solver]\nmethod = \"variable\"\n")
        + "\n[solver.radau]\n";
    std::fs::write(&scene, text).unwrap();
    let e = refused(&["run", &scene]);
    assert!(
        e.contains("solver.radau") && e.contains("does not read"),
        "{e}"
    );
}

#[test]
fn a_misspelt_file_name_gets_the_nearest_name() {
    let e = refused(&[
        "run",
        SCENE,
        "--set",
        "default.toml:scene.vehicle=\"../vehicles/fabia_trailr.toml\"",
    ]);
    assert!(e.contains("'fabia_trailer.toml'"), "{e}");
}

#[test]
fn a_load_case_the_scene_names_is_blamed_on_the_scene() {
    // c4bd0ca: reported at vehicles/trailer/box_trailer.toml:66:1.
    let dir = tmp("loadcase");
    let scene = scene_copy(&dir, "");
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("load_case = \"empty\"", "load_case = \"emtpy\"");
    std::fs::write(&scene, text).unwrap();
    let e = refused(&["run", &scene]);
    assert!(
        e.contains("scene.toml:9") && e.contains("scene.load_case") && e.contains("'empty'"),
        "{e}"
    );
}

#[test]
fn absurd_simple_vehicles_are_refused_with_the_bound() {
    for (set, says) in [
        ("van.toml:mass.cg_height_m=5", "centre-of-mass height"),
        ("van.toml:mass.cg_height_m=100", "centre-of-mass height"),
        ("van.toml:geometry.wheelbase_m=1000", "wheelbase"),
        // Within the height bound, but it would tip at 0.7 g.
        ("van.toml:mass.cg_height_m=1.2", "static stability factor"),
    ] {
        let e = refused(&["run", VAN, "--set", set]);
        assert!(e.contains(says) && e.contains(set), "{set}: {e}");
    }
}

#[test]
fn a_run_records_what_produced_it_and_its_overrides_file_reproduces_it() {
    let dir = tmp("provenance");
    let (a, b) = (dir.join("a"), dir.join("b"));
    let (ad, bd) = (a.display().to_string(), b.display().to_string());
    let first = towride_json(&[
        "run",
        SCENE,
        "--json",
        "--out",
        &ad,
        "--set",
        SHORT,
        "--set",
        "default.toml:run.speed_km_h=40",
    ]);
    let p = &first["produced_by"];
    assert_eq!(p["towride_version"], env!("CARGO_PKG_VERSION"));
    assert!(p["git_commit"].as_str().is_some_and(|c| !c.is_empty()));
    let cl: Vec<&str> = p["command_line"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|x| x.as_str())
        .collect();
    assert!(cl.contains(&"default.toml:run.speed_km_h=40"), "{cl:?}");
    // The title does not claim the scene's 50 km/h.
    let name = first["name"].as_str().unwrap();
    assert!(name.contains("run.speed_km_h = 40"), "{name}");
    let file = a.join("overrides.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(
        text.contains("/scenes/default.toml:run.speed_km_h\" = 40  # --set"),
        "{text}"
    );
    // Applied again from the file: the same inputs, the same answer.
    let f = file.display().to_string();
    let again = towride_json(&["run", SCENE, "--json", "--out", &bd, "--overrides", &f]);
    assert_eq!(again["scene"], first["scene"]);
    assert_eq!(
        again["hitch_force"]["abs_peak_n"],
        first["hitch_force"]["abs_peak_n"]
    );
    let paths = |v: &serde_json::Value| -> Vec<(String, String)> {
        v["produced_by"]["overrides"]
            .as_array()
            .unwrap()
            .iter()
            .map(|o| (o["path"].to_string(), o["value"].to_string()))
            .collect()
    };
    assert_eq!(paths(&again), paths(&first));
    // The report says it too.
    let html = std::fs::read_to_string(a.join("report.html")).unwrap();
    assert!(html.contains("Produced by"), "report without provenance");
}

#[test]
fn every_command_that_reads_a_scene_takes_set_and_overrides() {
    // c4bd0ca: `linear --set` was an unknown argument; doctor, bench, stress and
    // tyre-rig had none either. An override nobody reads is refused by each.
    let bad = "nothing.toml:a.b=1";
    let rig = repo!("scenes/tyre_rigs/drop_car.toml");
    for args in [
        vec!["run", SCENE],
        vec!["linear", SCENE],
        vec!["doctor", SCENE],
        vec!["bench", SCENE, "--tol", "1e-3", "--repeat", "1"],
        vec!["stress", SCENE, "--only", "thesis"],
        vec!["tyre-rig", rig],
    ] {
        let mut a = args.clone();
        a.extend(["--set", bad]);
        let e = refused(&a);
        assert!(
            e.contains(&format!("--set {bad}")) && e.contains("matches no file"),
            "{args:?}: {e}"
        );
    }
    for cmd in [
        "run",
        "linear",
        "doctor",
        "bench",
        "stress",
        "tyre-rig",
        "validate",
        "sweep",
        "sensitivity",
    ] {
        let out = towride(&[cmd, "--help"]);
        let help = String::from_utf8_lossy(&out.stdout);
        assert!(
            help.contains("--set") && help.contains("--overrides"),
            "{cmd} --help lacks --set or --overrides"
        );
    }
}
