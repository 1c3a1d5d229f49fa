//! `towride sensitivity`: JSON, files written, errors at the argument.

#[test]
fn sensitivity_writes_its_files_and_json() {
    let dir = std::env::temp_dir().join(format!("towride-sens-{}", std::process::id()));
    let v = crate::towride_json(&[
        "sensitivity",
        "scenes/examples/mass_spring.toml",
        "--params",
        "mass_spring.toml:spring[0].stiffness_n_m,mass_spring.toml:body[0].mass_kg",
        "--outputs",
        "k1.force.freq",
        "--method",
        "morris",
        "--trajectories",
        "3",
        "--jobs",
        "2",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["schema_version"], 3);
    assert_eq!(v["runs"], 1 + 3 * 3);
    // Raising k raises the frequency, raising m lowers it: the signs of mu.
    let mu = |i: usize| v["params"][i]["morris"][0]["mu"].as_f64().unwrap();
    assert!(mu(0) > 0.0 && mu(1) < 0.0, "{v}");
    for f in [
        "sensitivity.csv",
        "tornado_k1.force.freq.png",
        "sensitivity.html",
        "sensitivity.json",
    ] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    let csv = std::fs::read_to_string(dir.join("sensitivity.csv")).unwrap();
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .contains("k1.force.freq mu* [Hz]"),
        "{csv}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn sensitivity_refuses_an_unknown_parameter_at_the_argument() {
    let out = super::towride(&[
        "sensitivity",
        "scenes/examples/mass_spring.toml",
        "--params",
        "mass_spring.toml:spring[0].damping_n_s_m",
        "--outputs",
        "k1.force.freq",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--params mass_spring.toml:spring[0].damping_n_s_m"),
        "{err}"
    );
}

#[test]
fn sensitivity_refuses_zero_trajectories_and_range_with_oat_naming_the_bound() {
    let base = ["sensitivity", "scenes/examples/mass_spring.toml"];
    let e = crate::towride_err(
        &[&base[..], &["--method", "morris", "--trajectories", "0"]].concat(),
        2,
    );
    assert!(
        e.contains("--trajectories") && e.contains("2..=1000"),
        "{e}"
    );
    let e = crate::towride_err(&[&base[..], &["--range", "0.2"]].concat(), 2);
    assert!(
        e.contains("--range") && e.contains("--method morris"),
        "{e}"
    );
}

/// The van (a `simple` vehicle without a hitch): the study runs on its own file's
/// numbers with the default outputs, and its results go to a folder of its own.
#[test]
fn sensitivity_runs_on_the_simple_van_with_its_own_numbers() {
    let dir = std::env::temp_dir().join(format!("towride-sens-van-{}", std::process::id()));
    let v = crate::towride_json(&[
        "sensitivity",
        "scenes/van_air/bump_50mm.toml",
        "--set",
        "van_air/bump_50mm.toml:run.duration_s=0.3",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["status"], "completed", "{}", v["note"]);
    assert_eq!(v["failed"].as_array().unwrap().len(), 0);
    // The shortened run is recorded with the study (and on its page).
    assert_eq!(
        v["overrides"][0],
        "van_air/bump_50mm.toml:run.duration_s = 0.3"
    );
    assert!(v["produced_by"]["command_line"]
        .to_string()
        .contains("--set"));
    let params = v["params"].as_array().unwrap();
    assert!(params.len() >= 6, "{params:?}");
    assert!(params.iter().all(|p| p["param"]["file"]
        .as_str()
        .unwrap()
        .ends_with("van_air/van.toml")));
    std::fs::remove_dir_all(&dir).ok();
}
