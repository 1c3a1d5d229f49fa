//! Issue 32 item 1: no command writes over one of its own inputs or another command's
//! results; it says so and stops, the files byte for byte as they were.

use crate::{towride_err, towride_ok};

const SCENE: &str = repo!("scenes/default.toml");

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("towride_guard_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn run_and_validate_refuse_to_write_over_their_inputs_or_other_results() {
    let run = tmp("run");
    let r = run.display().to_string();
    towride_ok(&[
        "run",
        SCENE,
        "--out",
        &r,
        "--set",
        "default.toml:run.duration_s=0.05",
    ]);
    // Its overrides file read back into the same folder would be rewritten as read.
    let ov = run.join("overrides.toml");
    let before = std::fs::read(&ov).unwrap();
    let o = ov.display().to_string();
    let e = towride_err(&["run", SCENE, "--out", &r, "--overrides", &o], 2);
    assert!(e.contains("an input of this run"), "{e}");
    assert_eq!(std::fs::read(&ov).unwrap(), before);
    // A validation into the run's folder would replace the run's summary.
    let summary = std::fs::read(run.join("summary.json")).unwrap();
    let e = towride_err(
        &[
            "validate",
            repo!("measurements/synthetic/bump_25mm_40kmh_empty.toml"),
            "--out",
            &r,
        ],
        2,
    );
    assert!(e.contains("holds the results of run"), "{e}");
    assert_eq!(std::fs::read(run.join("summary.json")).unwrap(), summary);
    // And a run into a validation's folder.
    let val = tmp("val");
    let v = val.display().to_string();
    towride_ok(&[
        "validate",
        repo!("measurements/synthetic/bump_25mm_40kmh_empty.toml"),
        "--out",
        &v,
    ]);
    let vs = std::fs::read(val.join("summary.json")).unwrap();
    let e = towride_err(&["run", SCENE, "--out", &v], 2);
    assert!(e.contains("holds the results of validate"), "{e}");
    assert_eq!(std::fs::read(val.join("summary.json")).unwrap(), vs);
    // The studies refuse a run's folder before any work, and a run refuses theirs.
    for args in [
        vec!["stress", SCENE, "--only", "thesis"],
        vec!["bench", SCENE, "--tol", "1e-3", "--repeat", "1"],
        vec!["sensitivity", SCENE],
    ] {
        let mut a = args.clone();
        a.extend(["--out", r.as_str()]);
        let e = towride_err(&a, 2);
        assert!(e.contains("holds the results of run"), "{args:?}: {e}");
    }
    assert_eq!(std::fs::read(run.join("summary.json")).unwrap(), summary);
    let study = tmp("study");
    std::fs::create_dir_all(&study).unwrap();
    std::fs::write(study.join("stress.json"), "{}").unwrap();
    let s = study.display().to_string();
    let e = towride_err(&["run", SCENE, "--out", &s], 2);
    assert!(e.contains("holds the results of stress"), "{e}");
    // A run again into its own folder is the normal workflow.
    towride_ok(&[
        "run",
        SCENE,
        "--out",
        &r,
        "--set",
        "default.toml:run.duration_s=0.05",
    ]);
}

#[test]
fn tyre_rig_refuses_a_run_folder_and_to_write_over_its_reference_table() {
    // A folder holding a run's results: the rig's files would sit among them.
    let run = tmp("rig_run");
    std::fs::create_dir_all(&run).unwrap();
    std::fs::write(run.join("summary.json"), r#"{"kind": "scene"}"#).unwrap();
    let e = towride_err(
        &[
            "tyre-rig",
            repo!("scenes/tyre_rigs/drop_car.toml"),
            "--out",
            &run.display().to_string(),
        ],
        2,
    );
    assert!(e.contains("holds the results of run"), "{e}");
    // A lateral rig whose reference table is where its sweep CSV would go.
    let dir = tmp("rig_ref");
    std::fs::create_dir_all(&dir).unwrap();
    let rig = std::fs::read_to_string(repo!("scenes/tyre_rigs/lateral_reference.toml"))
        .unwrap()
        .replace("\"../../", &format!("\"{}/", repo!("")))
        .replace("\"reference/mfeval_tvd3.csv\"", "\"lr_sweep.csv\"");
    std::fs::write(dir.join("lr.toml"), rig).unwrap();
    let table = std::fs::read(repo!("scenes/tyre_rigs/reference/mfeval_tvd3.csv")).unwrap();
    std::fs::write(dir.join("lr_sweep.csv"), &table).unwrap();
    let d = dir.display().to_string();
    let e = towride_err(
        &[
            "tyre-rig",
            &dir.join("lr.toml").display().to_string(),
            "--out",
            &d,
        ],
        2,
    );
    assert!(e.contains("an input of this tyre-rig"), "{e}");
    assert_eq!(std::fs::read(dir.join("lr_sweep.csv")).unwrap(), table);
}

#[test]
fn validate_synth_refuses_to_write_over_a_recording() {
    let dir = tmp("synth");
    std::fs::create_dir_all(&dir).unwrap();
    // A recording (not made by synth) with the name a plan run would take.
    let rec = dir.join("bump_25mm_40kmh_empty.csv");
    let text = b"time [s],a [m/s^2]\n0,0\n0.001,0.1\n".to_vec();
    std::fs::write(&rec, &text).unwrap();
    let d = dir.display().to_string();
    let single = [
        "validate",
        "synth",
        "--scene",
        SCENE,
        "--speed-kmh",
        "40",
        "--name",
        "bump_25mm_40kmh_empty",
        "--out",
        &d,
    ];
    let e = towride_err(&single, 2);
    assert!(e.contains("not a synthetic run"), "{e}");
    // The plan stops before its first simulation, not at the run in the way.
    let e = towride_err(&["validate", "synth", "--plan", "--out", &d], 2);
    assert!(e.contains("not a synthetic run"), "{e}");
    assert_eq!(std::fs::read(&rec).unwrap(), text);
    // A synthetic run is rewritten: the usual workflow.
    std::fs::remove_file(&rec).unwrap();
    towride_ok(&single);
    towride_ok(&single);
    assert!(std::fs::read_to_string(&rec)
        .unwrap()
        .starts_with("# SYNTHETIC DATA"));
}
