//! Sensitivity studies on any vehicle and what they say when runs fail or are stopped:
//! a `simple` vehicle's own numbers as parameters, defaults without a hitch, a study
//! with failed or unstarted runs labelled at its top, no NaN, base values of 0
//! undefined, and results kept apart per scene.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicU64;

use towride_app::study::sensitivity::{default_dir, parameters, run, write, Method, Settings};
use towride_mbs::input::{Loader, Override};
use towride_mbs::progress::Silent;

use crate::reliability::StopAfter;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride_sens_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The mass on a spring, copied with `edit` applied and a 0.5 s run.
fn mass_spring(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(repo!("scenes/examples/mass_spring.toml")).unwrap();
    let f = dir.join("mass_spring.toml");
    std::fs::write(
        &f,
        edit(text.replacen("end_time_s = 4.0", "end_time_s = 0.5", 1)),
    )
    .unwrap();
    f
}

#[test]
fn a_simple_vehicle_is_studied_over_its_own_files_numbers_without_a_hitch() {
    let scene = PathBuf::from(repo!("scenes/van_air/bump_50mm.toml"));
    let short = Override::from_argument("van_air/bump_50mm.toml:run.duration_s=0.4").unwrap();
    let s = Settings {
        file: scene.clone(),
        base: Loader::with_overrides(vec![short]),
        jobs: 2,
        ..Settings::default()
    };
    let (found, _) = parameters(&s).unwrap();
    let names: Vec<&str> = found.iter().map(|p| p.name.as_str()).collect();
    for want in [
        "van.toml:mass.total_kg",
        "van.toml:front.spring.ride_frequency_hz",
        "van.toml:front.damping_ratio",
        "van.toml:tyre.vertical_stiffness_n_m",
        "van.toml:front.unsprung_kg",
    ] {
        assert!(names.iter().any(|n| n.ends_with(want)), "{want}: {names:?}");
    }
    // Two of them, with the default outputs (the accelerometers: the van has no hitch).
    let s = Settings {
        params: vec![
            "van.toml:tyre.vertical_stiffness_n_m".into(),
            "van.toml:front.spring.ride_frequency_hz".into(),
        ],
        ..s
    };
    let st = run(&s, &Silent).unwrap();
    assert_eq!(
        (st.status.as_str(), st.failed.len(), st.runs),
        ("completed", 0, 5)
    );
    assert!(st.note.is_none());
    assert!(
        st.outputs[0].name.starts_with("acc_") && st.outputs[0].name.ends_with(".abs_peak"),
        "{:?}",
        st.outputs
    );
    // A stiffer tyre passes more of the bump to the front wheel (first output).
    let e = st.params[0].elasticity[0].unwrap();
    assert!(e > 0.2, "tyre stiffness elasticity {e}");
}

#[test]
fn a_model_with_neither_hitch_nor_accelerometer_suggests_one_of_its_own_channels() {
    use towride_app::job::Job;
    use towride_app::study::sensitivity::outputs::resolve;
    let job = Job::from_file(
        Path::new(repo!("scenes/examples/mass_spring.toml")),
        &Loader::new(),
    )
    .unwrap();
    let e = resolve(&[], &job).unwrap_err().to_string();
    let hint = e.rsplit("--outputs ").next().unwrap();
    let named = hint.split_whitespace().next().unwrap();
    assert!(resolve(&[named.to_string()], &job).is_ok(), "{named}: {e}");
}

#[test]
fn a_study_whose_runs_failed_says_so_first_and_leaves_the_figure_empty() {
    let d = tmp("failed");
    // At the mass bound (1e5 kg): the run at 1.1 times it is refused.
    let f = mass_spring(&d, |t| t.replacen("mass_kg = 2.0", "mass_kg = 1.0e5", 1));
    let mut st = run(
        &Settings {
            file: f,
            params: vec!["mass_spring.toml:body[0].mass_kg".into()],
            outputs: vec!["k1.force.abs_peak".into()],
            jobs: 1,
            ..Settings::default()
        },
        &Silent,
    )
    .unwrap();
    assert_eq!((st.status.as_str(), st.failed.len()), ("partial", 1));
    let note = st.note.clone().unwrap();
    assert!(note.starts_with("1 of 3 runs failed"), "{note}");
    assert_eq!(st.params[0].elasticity[0], None);
    let out = d.join("out");
    write::write(&mut st, &out).unwrap();
    let page = std::fs::read_to_string(out.join("sensitivity.html")).unwrap();
    let (banner, ranking) = (page.find(&note).unwrap(), page.find("<h2>Ranking").unwrap());
    assert!(banner < ranking, "the note comes before the figures");
    assert!(!out.join("tornado.png").exists(), "no bar: no chart");
    let json = std::fs::read_to_string(out.join("sensitivity.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(
        (v["status"].as_str(), v["note"].as_str()),
        (Some("partial"), Some(note.as_str()))
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn an_interrupted_morris_study_is_labelled_with_runs_not_run_and_no_nan() {
    let d = tmp("stop");
    let f = mass_spring(&d, |t| t);
    let s = Settings {
        file: f,
        params: vec![
            "mass_spring.toml:body[0].mass_kg".into(),
            "mass_spring.toml:spring[0].stiffness_n_m".into(),
        ],
        outputs: vec!["k1.force.freq".into()],
        method: Method::Morris,
        trajectories: 3,
        jobs: 1,
        ..Settings::default()
    };
    // 1 + 3 x 3 runs; stopped after the base run and the first point.
    let stop = StopAfter {
        done: AtomicU64::new(0),
        after: 2,
    };
    let mut st = run(&s, &stop).unwrap();
    assert_eq!(st.status, "interrupted");
    assert!(
        st.failed.is_empty(),
        "not started is not failed: {:?}",
        st.failed
    );
    assert_eq!(st.not_run, 10 - 2);
    assert!(st
        .note
        .as_deref()
        .unwrap()
        .starts_with("interrupted: 8 of 10 runs not run"));
    for p in &st.params {
        assert!(p.note.is_some(), "no completed pair: {:?}", p.note);
    }
    let out = d.join("out");
    write::write(&mut st, &out).unwrap();
    for f in ["sensitivity.json", "sensitivity.csv", "sensitivity.html"] {
        let t = std::fs::read_to_string(out.join(f)).unwrap();
        assert!(!t.contains("NaN"), "{f}: {t}");
    }
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_base_value_of_zero_has_no_elasticity() {
    let d = tmp("zero");
    let f = mass_spring(&d, |t| {
        t.replacen(
            "stiffness_n_m = 2000.0",
            "stiffness_n_m = 2000.0\ndamping_n_s_m = 0.0",
            1,
        )
    });
    let st = run(
        &Settings {
            file: f,
            params: vec!["mass_spring.toml:spring[0].damping_n_s_m".into()],
            outputs: vec!["k1.force.abs_peak".into()],
            jobs: 1,
            ..Settings::default()
        },
        &Silent,
    )
    .unwrap();
    assert_eq!(st.params[0].elasticity[0], None, "not 0");
    assert!(st.params[0]
        .note
        .as_deref()
        .unwrap()
        .contains("base value 0"));
    let page = write::page(&st);
    assert!(page.contains(">undefined<"), "{page}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn studies_of_two_scenes_of_one_name_are_kept_apart() {
    use towride_app::study::sensitivity::assumed::assumed_inputs;
    let (fabia, van) = (
        Path::new("scenes/bump_50mm.toml"),
        Path::new("scenes/van_air/bump_50mm.toml"),
    );
    assert_ne!(default_dir(fabia), default_dir(van));
    assert_eq!(
        default_dir(van),
        Path::new("out/sensitivity/scenes_van_air_bump_50mm")
    );
    // A study of the Fabia's scene lists nothing for the van's.
    let d = tmp("apart");
    let study = serde_json::json!({
        "file": repo!("scenes/bump_50mm.toml"),
        "method": "oat",
        "outputs": [{"name": "hitch_fx.abs_peak", "unit": "N"}],
        "params": [{
            "param": {"name": "vehicles/trailer/box_trailer.toml:half.mass_kg",
                      "file": "vehicles/trailer/box_trailer.toml", "path": "half.mass_kg"},
            "elasticity": [0.5],
        }],
    });
    std::fs::write(d.join("sensitivity.json"), study.to_string()).unwrap();
    let a = assumed_inputs(Path::new(repo!("scenes/van_air/bump_50mm.toml")), &d, 10);
    assert!(a.inputs.is_empty(), "{a:?}");
    assert!(a.note.unwrap().contains("another scene"));
    // The Fabia's own scene still reads it.
    let a = assumed_inputs(Path::new(repo!("scenes/bump_50mm.toml")), &d, 10);
    assert_eq!(a.note, None);
    std::fs::remove_dir_all(&d).ok();
}
