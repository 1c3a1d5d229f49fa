//! `towride calibrate` as a user runs it: recordings made with a "true" van whose values
//! differ from the files (`validate synth --set`, with noise, offsets, trigger jitter and
//! a quantised time column), fitted back; the override file it writes read by
//! `validate --overrides`; a value the recordings cannot see left with its reason; bad
//! input refused with the field named.

use crate::{towride_err, towride_json, towride_ok};

const SCENE: &str = "scenes/van_air/bump_50mm.toml";
/// The truth: front damping ratio 0.25 -> 0.33 and tyre rate 320 -> 400 kN/m.
const TRUTH: [(&str, f64); 2] = [
    ("van.toml:front.damping_ratio", 0.33),
    ("van.toml:tyre.vertical_stiffness_n_m", 4.0e5),
];

fn dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("towride-calibrate-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn synth(rec: &std::path::Path, kmh: &str, seed: &str) -> std::path::PathBuf {
    let mut args: Vec<String> = [
        "validate",
        "synth",
        "--scene",
        SCENE,
        "--speed-kmh",
        kmh,
        "--load",
        "solo",
        "--out",
        rec.to_str().unwrap(),
        "--rate-hz",
        "1000",
        "--noise-rms-mps2",
        "0.05",
        "--offset-rms-mps2",
        "0.1",
        "--trigger-jitter-ms",
        "2",
        "--time-decimals",
        "3",
        "--gain-error-pct",
        "0",
        "--seed",
        seed,
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for (k, v) in TRUTH {
        args.push("--set".into());
        args.push(format!("{k}={v}"));
    }
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    towride_ok(&a);
    rec.join(format!("bump_50mm_{kmh}kmh_solo.toml"))
}

#[test]
fn calibrate_recovers_a_moved_van_and_its_overrides_predict() {
    let d = dir("van");
    let rec = d.join("rec");
    let slow = synth(&rec, "20", "7");
    let fast = synth(&rec, "40", "8");
    let out = d.join("fit");
    // Two values the bump excites and one it cannot: the rebound stop (90 mm of droop,
    // never reached over a 50 mm bump).
    let params = "van.toml:front.damping_ratio=0.1..0.6,\
                  van.toml:tyre.vertical_stiffness_n_m=2e5..6e5,\
                  simple_defaults.toml:corner.rebound_stiffness_n_m";
    let v = towride_json(&[
        "calibrate",
        slow.to_str().unwrap(),
        "--holdout",
        fast.to_str().unwrap(),
        "--params",
        params,
        "--starts",
        "3",
        "--local-fits",
        "1",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["schema_version"], 1);
    let c = &v["calibration"];
    let fitted = c["fitted"].as_array().unwrap();
    assert_eq!(fitted.len(), 2, "{c}");
    for (name, truth) in TRUTH {
        let key = name.split_once(':').unwrap().1;
        let f = fitted
            .iter()
            .find(|f| f["path"] == key)
            .unwrap_or_else(|| panic!("{key} not fitted: {c}"));
        let x = f["value"].as_f64().unwrap();
        let file = f["file_value"].as_f64().unwrap();
        // Recovered within 2 % (the file value is 25-30 % off).
        assert!(
            (x / truth - 1.0).abs() < 0.02,
            "{key}: {x} vs truth {truth}"
        );
        assert!((file / truth - 1.0).abs() > 0.15);
        let iv = f["interval"].as_array().unwrap();
        let (lo, hi) = (iv[0].as_f64().unwrap(), iv[1].as_f64().unwrap());
        assert!(lo < x && x < hi, "{key}: {lo}..{hi}");
    }
    let left = c["left"].as_array().unwrap();
    assert_eq!(left.len(), 1, "{c}");
    assert!(
        left[0][0]
            .as_str()
            .unwrap()
            .ends_with("rebound_stiffness_n_m"),
        "{left:?}"
    );
    // Fitted down to about the sensor noise (1 = the noise).
    assert!(c["rms_fitted"].as_f64().unwrap() < 2.0, "{c}");
    assert!(c["rms_start"].as_f64().unwrap() > 5.0, "{c}");
    // The override file, read back by `validate --overrides`, predicts the held-out
    // speed better than the files do.
    let ov = out.join("overrides.toml");
    let text = std::fs::read_to_string(&ov).unwrap();
    assert!(text.contains("[measured]"), "{text}");
    let rate = |extra: &[&str]| {
        let mut a = vec!["validate", fast.to_str().unwrap(), "--no-plots", "--json"];
        let o = d.join(format!("val{}", extra.len()));
        a.extend(["--out", o.to_str().unwrap()]);
        a.extend(extra);
        let j = towride_json(&a);
        j["runs"][0]["mean_rating_corrected"].as_f64().unwrap()
    };
    let before = rate(&[]);
    let after = rate(&["--overrides", ov.to_str().unwrap()]);
    assert!(after > before + 0.05, "{before} -> {after}");
    let held = &c["holdout_runs"][0];
    assert!((held["after"].as_f64().unwrap() - after).abs() < 1e-9);
}

#[test]
fn calibrate_refuses_a_value_the_scene_does_not_have() {
    let d = dir("bad");
    let rec = d.join("rec");
    let run = synth(&rec, "20", "3");
    let err = towride_err(
        &[
            "calibrate",
            run.to_str().unwrap(),
            "--params",
            "van.toml:front.no_such_value=1..2",
            "--out",
            d.join("o").to_str().unwrap(),
        ],
        2,
    );
    assert!(err.contains("no_such_value"), "{err}");
    assert!(err.contains("--params"), "{err}");
}
