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
