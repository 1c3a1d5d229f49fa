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
    assert_eq!(v["schema_version"], 2);
    assert_eq!(v["runs"], 1 + 3 * 3);
    // Raising k raises the frequency, raising m lowers it: the signs of mu.
    let mu = |i: usize| v["params"][i]["morris"][0]["mu"].as_f64().unwrap();
    assert!(mu(0) > 0.0 && mu(1) < 0.0, "{v}");
    for f in [
        "sensitivity.csv",
        "tornado.png",
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
