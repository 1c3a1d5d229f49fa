//! The command line as a user runs it: JSON fields, files written, clear errors.

use crate::{towride, towride_err, towride_json, towride_ok};

#[test]
fn verify_json_has_the_fields_a_script_needs() {
    let v = towride_json(&[
        "verify",
        "--problems",
        "hires,caraxis",
        "--tol",
        "1e-6",
        "--json",
    ]);
    let recs = v.as_array().unwrap();
    assert_eq!(recs.len(), 2);
    for r in recs {
        for key in [
            "problem",
            "rtol",
            "atol",
            "t_end",
            "y",
            "scd",
            "steps",
            "rejected_steps",
            "residual_evals",
            "jacobian_evals",
            "lu_factorizations",
            "newton_iterations",
            "wall_s",
        ] {
            assert!(r.get(key).is_some(), "missing {key} in {r}");
        }
    }
    let car = recs.iter().find(|r| r["problem"] == "caraxis").unwrap();
    // y in the test set's component order: 10 components for the car axis.
    assert_eq!(car["y"].as_array().unwrap().len(), 10);
    assert!(car["steps"].as_u64().unwrap() > 100);
}

#[test]
fn unknown_problem_is_a_clear_error() {
    let err = towride_err(&["verify", "--problems", "nosuch"], 2);
    assert!(err.contains("unknown problem `nosuch`"), "{err}");
}

#[test]
fn bench_solver_writes_csv_and_png() {
    let dir = std::env::temp_dir().join(format!("towride-bench-{}", std::process::id()));
    let out = towride(&[
        "bench",
        "solver",
        "--problems",
        "vdpol",
        "--tightest",
        "5",
        "--min-wall",
        "0",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("work_precision.csv")).unwrap();
    assert!(csv.starts_with("problem,method,rtol [-]"), "{csv}");
    // 3 tolerances x 2 methods + header.
    assert_eq!(csv.lines().count(), 7);
    let png = std::fs::read(dir.join("work_precision.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn run_linear_and_doctor_speak_json() {
    let dir = std::env::temp_dir().join(format!("towride-run-{}", std::process::id()));
    let v = towride_json(&[
        "run",
        repo!("scenes/examples/two_mass_chain.toml"),
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["status"], "completed");
    for key in [
        "steps",
        "newton_iterations",
        "jacobian_evals",
        "wall_s",
        "channels",
        "statics",
    ] {
        assert!(!v[key].is_null(), "missing {key}");
    }
    let csv = std::fs::read_to_string(dir.join("outputs.csv")).unwrap();
    assert!(
        csv.starts_with("time [s],m2.cm.position.x [m]"),
        "{}",
        &csv[..80]
    );
    assert_eq!(csv.lines().count(), 1 + 1001);

    let v = towride_json(&[
        "linear",
        repo!("scenes/examples/two_mass_chain.toml"),
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    let f = v["result"]["modes"][0]["undamped_hz"].as_f64().unwrap();
    assert!((f - 500f64.sqrt() / (2.0 * std::f64::consts::PI)).abs() < 1e-6);
    assert!(dir.join("linear.html").is_file());
    assert_eq!(v["report"].as_str(), dir.join("linear.html").to_str());

    let v = towride_json(&["doctor", repo!("scenes/examples/andrews.toml"), "--json"]);
    assert_eq!(v["redundant"].as_array().unwrap().len(), 9);
    assert!(v["newton_condition"].as_f64().unwrap() > 1.0);
}

#[test]
fn a_bad_mechanism_file_is_named_with_its_line() {
    let path = std::env::temp_dir().join(format!("towride-bad-{}.toml", std::process::id()));
    let text = std::fs::read_to_string(repo!("scenes/examples/pendulum.toml"))
        .unwrap()
        .replace("mass_kg = 1.0", "mass_kg = -1.0");
    std::fs::write(&path, text).unwrap();
    let err = towride_err(&["run", path.to_str().unwrap()], 2);
    assert!(
        err.contains(".toml:17:") && err.contains("body[0].mass_kg") && err.contains("positive"),
        "{err}"
    );
}

#[test]
fn plan_lists_its_cases_on_the_command_line() {
    let out = towride_ok(&["run", repo!("scenes/measurement_plan.toml"), "--list"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.lines().count(), 72);
    assert!(text.lines().any(|l| l == "ramp_50mm_50kmh_empty"));
}

#[test]
fn set_replaces_a_value_for_one_run_and_a_set_that_matches_nothing_is_refused() {
    let dir = std::env::temp_dir().join(format!("towride-set-{}", std::process::id()));
    let d = dir.to_str().unwrap();
    let pendulum = repo!("scenes/examples/pendulum.toml");
    let peak_tension = |extra: &[&str]| {
        let mut args = vec!["run", pendulum, "--out", d, "--json"];
        args.extend_from_slice(extra);
        let v = towride_json(&args);
        v["channels"]["pivot.force.z"]["max"].as_f64().unwrap()
    };
    // Released from horizontal, the link tension peaks at 3 m g at the bottom.
    let one = peak_tension(&[]);
    let two = peak_tension(&["--set", "pendulum.toml:body[0].mass_kg=2.0"]);
    assert!((one / (3.0 * 9.81) - 1.0).abs() < 1e-4, "{one}");
    assert!((two / (3.0 * 2.0 * 9.81) - 1.0).abs() < 1e-4, "{two}");

    let err = towride_err(
        &[
            "run",
            pendulum,
            "--out",
            d,
            "--set",
            "pendulm.toml:body[0].mass_kg=2.0",
        ],
        2,
    );
    assert!(
        err.contains("--set pendulm.toml:body[0].mass_kg=2.0") && err.contains("matches no file"),
        "{err}"
    );
    let out = towride(&["run", pendulum, "--set", "pendulum.toml=2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("FILE:PATH=VALUE"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bench_scaling_times_each_family_by_phase() {
    let dir = std::env::temp_dir().join(format!("towride-scaling-{}", std::process::id()));
    let v = towride_json(&[
        "bench",
        "scaling",
        "--chain",
        "2,8",
        "--ladder",
        "1,3",
        "--hitch-modes",
        "2",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(v["schema_version"], 1);
    let pts = v["points"].as_array().unwrap();
    assert_eq!(pts.len(), 5);
    for p in pts {
        assert_eq!(p["status"], "completed", "{p}");
        let (n, rows) = (
            p["size"].as_u64().unwrap(),
            p["constraint_rows"].as_u64().unwrap(),
        );
        let parts: f64 = ["setup_s", "start_s", "integration_s", "outputs_s"]
            .iter()
            .map(|k| p[k].as_f64().unwrap())
            .sum();
        assert!((parts - p["total_s"].as_f64().unwrap()).abs() < 1e-6, "{p}");
        match p["family"].as_str().unwrap() {
            // Five rows per revolute joint, none repeated.
            "chain" => assert_eq!((rows, p["redundant_rows"].as_u64().unwrap()), (5 * n, 0)),
            // A planar four-bar of 3D revolutes: 20 rows, 17 independent.
            "ladder" => assert_eq!(
                (rows, p["redundant_rows"].as_u64().unwrap()),
                (17 * n, 3 * n)
            ),
            _ => assert_eq!(n, 2),
        }
    }
    let csv = std::fs::read_to_string(dir.join("scaling.csv")).unwrap();
    assert!(csv.starts_with("family,size [-],equations [-]"), "{csv}");
    let png = std::fs::read(dir.join("scaling.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // A vehicle case the study file does not have is refused by name.
    let out = towride(&[
        "bench",
        "scaling",
        "--hitch-modes",
        "7",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("hitch_modes = 7") && err.contains("scaling.toml"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn list_names_shows_what_a_scene_can_ask_for() {
    let v = towride_json(&[
        "run",
        repo!("scenes/default.toml"),
        "--list-names",
        "--json",
    ]);
    assert_eq!(v["schema_version"], 1);
    let names: Vec<&str> = v["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q["name"].as_str().unwrap())
        .collect();
    for n in [
        "susp_fl_travel",
        "damper_rl_force",
        "body_pitch",
        "tyre_tr_fx",
    ] {
        assert!(names.contains(&n), "{n} not in {names:?}");
    }
    let markers = v["markers"].as_array().unwrap();
    assert!(markers.iter().any(|m| m == "wheel_fl.centre"));
    assert!(v["fixed_channels"][1]["name"] == "hitch_fx");
}

#[test]
fn bench_replot_redraws_a_stored_table_and_names_a_bad_cell() {
    let dir = std::env::temp_dir().join(format!("towride_replot_{}", std::process::id()));
    let d = dir.to_str().unwrap();
    let out = towride(&[
        "bench",
        "--replot",
        repo!("docs/data/bench_default.csv"),
        "--out",
        d,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(std::fs::metadata(dir.join("bench.png")).unwrap().len() > 10_000);
    // A table of bench.json version 1 (the signed peak, `hitch_peak [N]`) replots too.
    let text = std::fs::read_to_string(repo!("docs/data/bench_default.csv")).unwrap();
    let v1 = dir.join("v1.csv");
    let old = text
        .replace("hitch_abs_peak [N]", "hitch_peak [N]")
        .replace("hitch_abs_peak_error [-]", "hitch_peak_error [-]");
    assert!(old.contains(",hitch_peak [N],hitch_peak_error [-],"));
    std::fs::write(&v1, old).unwrap();
    let png = dir.join("v1");
    let out = towride(&[
        "bench",
        "--replot",
        v1.to_str().unwrap(),
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(std::fs::metadata(png.join("bench.png")).unwrap().len() > 10_000);
    // A table cut by hand: the error names the file, the line and the column.
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, text.replacen(",completed,0.", ",completed,x0.", 1)).unwrap();
    let err = towride_err(&["bench", "--replot", bad.to_str().unwrap(), "--out", d], 2);
    assert!(
        err.contains("bad.csv") && err.contains("wall [s]") && err.contains('2'),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `run --json` on a scene carries the assumed inputs its text output lists, read from
/// the scene's sensitivity study in `out/sensitivity/<key>` under the working directory
/// (a scene outside it: its stem and the FNV-1a of its path, as `sensitivity` writes it).
#[test]
fn run_json_lists_the_assumed_inputs_of_the_scenes_study() {
    let dir = std::env::temp_dir().join(format!("towride-assumed-cli-{}", std::process::id()));
    let scene = towride_mbs::input::normalized(std::path::Path::new(repo!("scenes/default.toml")));
    let hash = towride_app::sweep::fingerprint::fnv1a(scene.to_str().unwrap().as_bytes());
    let study = dir.join(format!("out/sensitivity/default_{:08x}", hash as u32));
    std::fs::create_dir_all(&study).unwrap();
    let param = |path: &str, e: f64| {
        serde_json::json!({
            "param": {
                "name": format!("vehicles/trailer/box_trailer.toml:{path}"),
                "file": "vehicles/trailer/box_trailer.toml",
                "path": path,
            },
            "elasticity": [e],
        })
    };
    let json = serde_json::json!({
        "method": "oat",
        "outputs": [{"name": "hitch_fx.abs_peak", "unit": "N"}],
        // body.mass_kg is tagged [scaled], half.inertia_kg_m2 [assumed].
        "params": [param("body.mass_kg", 0.54), param("half.inertia_kg_m2", 0.22)],
    });
    std::fs::write(study.join("sensitivity.json"), json.to_string()).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_towride"))
        .current_dir(&dir)
        .args([
            "run",
            repo!("scenes/default.toml"),
            "--out",
            "run",
            "--json",
        ])
        .output()
        .expect("run towride");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "completed");
    let a = &v["assumed_inputs"];
    assert_eq!(a["output"], "hitch_fx.abs_peak", "{a}");
    let inputs = a["inputs"].as_array().unwrap();
    assert_eq!(inputs.len(), 1, "{a}");
    assert_eq!(inputs[0]["rank"], 2);
    assert_eq!(
        inputs[0]["parameter"],
        "vehicles/trailer/box_trailer.toml:half.inertia_kg_m2"
    );
    assert_eq!(inputs[0]["class"], "assumed");
    std::fs::remove_dir_all(&dir).ok();
}
