//! `towride sweep` and its inputs: `--set` reaching every case, parameters checked
//! before the first case, fingerprints refusing stale or foreign results, and outputs
//! that would replace another command's results or the command's own inputs.

use std::path::{Path, PathBuf};

use crate::{towride, towride_err, towride_json};

/// A temporary folder holding a copy of the pendulum and a sweep over it.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride_swin_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    std::fs::copy(
        repo!("scenes/examples/pendulum.toml"),
        d.join("pendulum.toml"),
    )
    .unwrap();
    d
}

/// A sweep over the bob's mass with `values` (TOML) at key `path`.
fn sweep_file(d: &Path, path: &str, values: &str) -> String {
    let f = d.join("sweep.toml");
    std::fs::write(
        &f,
        format!(
            "[sweep]\nname = \"mass\"\nscene = \"pendulum.toml\"\n\n[[parameter]]\nname = \"m\"\n\
             file = \"pendulum.toml\"\npath = \"{path}\"\nvalues = {values}\n"
        ),
    )
    .unwrap();
    f.display().to_string()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn a_mistyped_key_or_a_wrong_type_is_refused_before_any_case_at_the_sweep_line() {
    let d = scratch("check");
    let out = d.join("out");
    // The key path: every case would fail with it; line 8 is `path = ...`.
    let f = sweep_file(&d, "body[0].mass_kgs", "[1.0, 2.0]");
    let e = towride_err(&["sweep", &f, "--out", s(&out)], 2);
    assert!(
        e.contains(&format!("{f}:8:")) && e.contains("parameter[0].path"),
        "{e}"
    );
    assert!(e.contains("mass_kgs"), "{e}");
    // A value of the wrong type among numbers: named by its index, at `values` (line 9).
    let f = sweep_file(&d, "body[0].mass_kg", "[1.0, \"2 kg\"]");
    let e = towride_err(&["sweep", &f, "--out", s(&out)], 2);
    assert!(
        e.contains(&format!("{f}:9:"))
            && e.contains("parameter[0].values[1]")
            && e.contains("is a string"),
        "{e}"
    );
    assert!(!out.join("summary.csv").exists(), "no case ran");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn set_reaches_every_case_and_a_swept_value_set_again_is_refused() {
    let d = scratch("set");
    let out = d.join("out");
    let f = sweep_file(&d, "body[0].mass_kg", "[1.0, 2.0]");
    // Stopped at 0.3 s, before the bob passes the bottom (quarter period 0.59 s): the
    // link tension stays below its peak 3 m g in every case.
    let j = towride_json(&[
        "sweep",
        &f,
        "--out",
        s(&out),
        "--set",
        "pendulum.toml:run.end_time_s=0.3",
        "--keep-histories",
        "--json",
    ]);
    assert_eq!(j["failed"], 0, "{j}");
    for r in j["rows"].as_array().unwrap() {
        let m: f64 = r["values"][0].as_str().unwrap().parse().unwrap();
        let t = r["figures"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x[0] == "pivot.force.z max [N]")
            .unwrap()[1]
            .as_f64()
            .unwrap();
        assert!(t < 0.9 * 3.0 * m * 9.81, "{r}");
    }
    // Each kept case records the command line and both overrides.
    let case: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("cases/case_0001/summary.json")).unwrap(),
    )
    .unwrap();
    let p = &case["produced_by"];
    assert!(p["command_line"].to_string().contains("--set"), "{p}");
    let paths: Vec<&str> = p["overrides"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["path"].as_str().unwrap())
        .collect();
    assert!(
        paths.contains(&"run.end_time_s") && paths.contains(&"body[0].mass_kg"),
        "{p}"
    );
    // The swept value also given by --set: set twice, refused before any case.
    let e = towride_err(
        &[
            "sweep",
            &f,
            "--out",
            s(&d.join("twice")),
            "--set",
            "pendulum.toml:body[0].mass_kg=3.0",
        ],
        2,
    );
    assert!(
        e.contains("set twice") && e.contains("body[0].mass_kg"),
        "{e}"
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn resume_and_merge_refuse_results_of_another_sweep() {
    let d = scratch("fp");
    let out = d.join("out");
    let f = sweep_file(&d, "body[0].mass_kg", "[1.0, 2.0]");
    let short = "pendulum.toml:run.end_time_s=0.2";
    let run = |extra: &[&str]| {
        let mut a = vec!["sweep", f.as_str(), "--set", short, "--out", s(&out)];
        a.extend(extra);
        towride(&a)
    };
    assert!(run(&[]).status.success());
    // The values changed: the old results are not this sweep's.
    sweep_file(&d, "body[0].mass_kg", "[1.0, 3.0]");
    let e = String::from_utf8_lossy(&run(&["--resume"]).stderr).into_owned();
    assert!(
        e.contains("summary.csv") && e.contains("another sweep") && e.contains("values changed"),
        "{e}"
    );
    // An input file changed (the scene): named.
    sweep_file(&d, "body[0].mass_kg", "[1.0, 2.0]");
    let scene = d.join("pendulum.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, text.replace("rtol = 1e-8", "rtol = 1e-7")).unwrap();
    let o = run(&["--resume"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("pendulum.toml changed"), "{e}");
    std::fs::write(&scene, &text).unwrap();
    let j: serde_json::Value =
        serde_json::from_slice(&run(&["--resume", "--json"]).stdout).unwrap();
    assert_eq!(j["resumed"], 2, "the same sweep resumes");

    // Shards of two sweeps (the --set differs) are not merged.
    for (i, end) in [(0, "0.2"), (1, "0.25")] {
        let set = format!("pendulum.toml:run.end_time_s={end}");
        let shard = format!("{i}/2");
        let o = towride(&[
            "sweep",
            &f,
            "--set",
            &set,
            "--shard",
            &shard,
            "--out",
            s(&d),
        ]);
        assert!(o.status.success());
    }
    let (a, b) = (
        d.join("summary_shard0of2.csv"),
        d.join("summary_shard1of2.csv"),
    );
    let e = towride_err(
        &["sweep", "merge", s(&a), s(&b), "--out", s(&d.join("m.csv"))],
        2,
    );
    assert!(
        e.contains("summary_shard1of2") && e.contains("another sweep") && e.contains("--set"),
        "{e}"
    );
    assert!(!d.join("m.csv").exists());
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn sweep_and_merge_refuse_to_overwrite_a_run_or_their_own_inputs() {
    let d = scratch("out");
    let f = sweep_file(&d, "body[0].mass_kg", "[1.0, 2.0]");
    let short = "pendulum.toml:run.end_time_s=0.2";
    // A run's folder.
    let run_dir = d.join("run");
    let scene = d.join("pendulum.toml");
    let o = towride(&["run", s(&scene), "--set", short, "--out", s(&run_dir)]);
    assert!(o.status.success());
    let before = std::fs::read(run_dir.join("summary.json")).unwrap();
    for extra in [&[][..], &["--resume"][..]] {
        let mut a = vec!["sweep", f.as_str(), "--set", short, "--out", s(&run_dir)];
        a.extend(extra);
        let e = towride_err(&a, 2);
        assert!(e.contains("another command's results"), "{e}");
    }
    assert_eq!(std::fs::read(run_dir.join("summary.json")).unwrap(), before);
    // A merge into one of its shards.
    for i in 0..2 {
        let shard = format!("{i}/2");
        let o = towride(&[
            "sweep",
            &f,
            "--set",
            short,
            "--shard",
            &shard,
            "--out",
            s(&d),
        ]);
        assert!(o.status.success());
    }
    let (a, b) = (
        d.join("summary_shard0of2.csv"),
        d.join("summary_shard1of2.csv"),
    );
    let shard = std::fs::read(&a).unwrap();
    let e = towride_err(&["sweep", "merge", s(&a), s(&b), "--out", s(&a)], 2);
    assert!(e.contains("one of the shards being merged"), "{e}");
    assert_eq!(std::fs::read(&a).unwrap(), shard);
    // Into a run's folder: refused too; elsewhere it merges.
    let into_run = run_dir.join("merged.csv");
    let e = towride_err(&["sweep", "merge", s(&a), s(&b), "--out", s(&into_run)], 2);
    assert!(e.contains("another command's results"), "{e}");
    let m = d.join("merged.csv");
    let j = towride_json(&["sweep", "merge", s(&a), s(&b), "--out", s(&m), "--json"]);
    assert_eq!(j["cases"], 2);
    // Merging again into the same table of the same sweep is fine.
    towride_json(&["sweep", "merge", s(&a), s(&b), "--out", s(&m), "--json"]);
    std::fs::remove_dir_all(&d).ok();
}
