//! `towride sweep`: the Cartesian product over property-file values, in parallel and in
//! shards, checked against the pendulum's analytical peak link tension 3 m g (released
//! from horizontal), whatever its length.

use crate::{towride, towride_json};

fn table(path: &std::path::Path) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let mut rows = vec![r.headers().unwrap().iter().map(String::from).collect()];
    rows.extend(
        r.records()
            .map(|x| x.unwrap().iter().map(String::from).collect()),
    );
    rows
}

#[test]
fn sweep_runs_the_product_in_parallel_and_shards_merge_to_the_same_table() {
    let dir = std::env::temp_dir().join(format!("towride_sweep_{}", std::process::id()));
    let d = dir.to_str().unwrap();
    let f = repo!("scenes/examples/pendulum_sweep.toml");
    let j = towride_json(&["sweep", f, "--out", d, "--jobs", "2", "--json"]);
    assert_eq!(j["cases"], 6);
    assert_eq!(j["failed"], 0);
    let full = table(&dir.join("summary.csv"));
    let col = |name: &str| full[0].iter().position(|h| h == name).unwrap();
    let (cm, ct) = (col("mass_kg"), col("pivot.force.z max [N]"));
    for row in &full[1..] {
        let m: f64 = row[cm].parse().unwrap();
        let t: f64 = row[ct].parse().unwrap();
        assert!((t / (3.0 * m * 9.81) - 1.0).abs() < 1e-5, "{row:?}");
    }
    for i in 0..2 {
        let s = format!("{i}/2");
        assert!(towride(&["sweep", f, "--out", d, "--shard", &s])
            .status
            .success());
    }
    let merged = dir.join("merged.csv");
    let shards = [
        dir.join("summary_shard0of2.csv"),
        dir.join("summary_shard1of2.csv"),
    ];
    let out = towride(&[
        "sweep",
        "merge",
        shards[0].to_str().unwrap(),
        shards[1].to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let m = table(&merged);
    // Same cases, same figures (wall times differ).
    let wall = col("wall_time [s]");
    let strip = |t: &Vec<Vec<String>>| -> Vec<Vec<String>> {
        t.iter()
            .map(|r| {
                r.iter()
                    .enumerate()
                    .filter(|(k, _)| *k != wall)
                    .map(|(_, v)| v.clone())
                    .collect()
            })
            .collect()
    };
    assert_eq!(strip(&m), strip(&full));
}

#[test]
fn a_failing_case_is_recorded_and_the_others_go_on() {
    let dir = std::env::temp_dir().join(format!("towride_sweep_bad_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("bad_sweep.toml");
    let scene = std::fs::canonicalize(repo!("scenes/examples/pendulum.toml")).unwrap();
    std::fs::write(
        &f,
        format!(
            "[sweep]\nname = \"bad mass\"\nscene = {:?}\n\n[[parameter]]\nname = \"mass_kg\"\nfile = \"pendulum.toml\"\npath = \"body[0].mass_kg\"\nvalues = [1.0, -1.0, 2.0]\n",
            scene.to_str().unwrap()
        ),
    )
    .unwrap();
    let out = towride(&[
        "sweep",
        f.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["failed"], 1);
    let rows = j["rows"].as_array().unwrap();
    assert_eq!(rows[0]["status"], "completed");
    assert_eq!(rows[2]["status"], "completed");
    let e = rows[1]["error"].as_str().unwrap();
    assert!(e.contains("pendulum.toml") && e.contains("mass_kg"), "{e}");
}

/// A `[robustness]` block through the command: the pendulum's peak link tension is
/// 3 m g whatever the bob's inertia, so moving the (tiny) inertia keeps the order of the
/// masses (tau-b 1) and the lightest bob best; a bad block is refused with its line.
#[test]
fn a_robustness_block_ranks_the_pendulum_masses_as_3_m_g_does() {
    let dir = std::env::temp_dir().join(format!("towride_robust_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("study.toml");
    let text = format!(
        "[sweep]\nname = \"pendulum robustness\"\nscene = \"{}\"\n\n\
         [[parameter]]\nname = \"mass_kg\"\nfile = \"pendulum.toml\"\npath = \"body[0].mass_kg\"\n\
         values = [2.0, 0.5, 1.0]\n\n\
         [[parameter]]\nname = \"length\"\nfile = \"pendulum.toml\"\npath = \"body[0].cm_position_m\"\n\
         values = [[0.5, 0.0, 0.0], [1.0, 0.0, 0.0]]\n\n\
         [robustness]\nparams = [\"pendulum.toml:body[0].inertia_kg_m2\"]\nby = \"mass_kg\"\n\
         figures = [\"pivot.force.z max\"]\nsubset = {{ length = [[1.0, 0.0, 0.0]] }}\nrange = 0.3\n",
        repo!("scenes/examples/pendulum.toml")
    );
    std::fs::write(&f, &text).unwrap();
    let out = dir.join("out");
    let j = towride_json(&[
        "sweep",
        f.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--jobs",
        "2",
        "--json",
    ]);
    let r = &j["robustness"];
    assert_eq!(r["status"], "completed");
    assert_eq!(r["cases_per_run"], 3);
    assert_eq!(r["nominal"]["figures"][0]["best"], "0.5");
    let p = r["perturbations"].as_array().unwrap();
    assert_eq!(p.len(), 2);
    for q in p {
        let o = &q["outcomes"][0];
        assert_eq!(o["figure"], "pivot.force.z max [N]");
        assert_eq!(
            (o["best"].as_str(), o["tau_b"].as_f64()),
            (Some("0.5"), Some(1.0))
        );
        assert_eq!(o["stays_best"], true);
    }
    // --no-robustness runs the grid alone: the same six cases, no block.
    let alone = towride_json(&[
        "sweep",
        f.to_str().unwrap(),
        "--out",
        dir.join("alone").to_str().unwrap(),
        "--jobs",
        "2",
        "--no-robustness",
        "--json",
    ]);
    assert!(alone["robustness"].is_null(), "{}", alone["robustness"]);
    assert_eq!(alone["cases"], 6);
    // range = 2 (line 22 of the file): refused before any run, naming line and field.
    std::fs::write(&f, text.replace("range = 0.3", "range = 2.0")).unwrap();
    let o = towride(&["sweep", f.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && !e.contains("panicked"), "{e}");
    assert!(
        e.contains("study.toml:22") && e.contains("robustness.range"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
