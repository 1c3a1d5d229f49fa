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

/// The recording `run` with its front wheel sensors clipped at `range_g` (the CSV's
/// values held at the range, the descriptor giving the range): what a logger with a
/// too-small range records.
fn clip_front_wheels(run: &std::path::Path, range_g: f64) -> std::path::PathBuf {
    let desc = std::fs::read_to_string(run).unwrap();
    let csv_path = run.with_extension("csv");
    let lim = range_g * 9.80665;
    let mut header: Option<Vec<usize>> = None;
    let mut out = String::new();
    for line in std::fs::read_to_string(&csv_path).unwrap().lines() {
        if line.starts_with('#') || line.trim().is_empty() {
            out.push_str(line);
        } else if let Some(cols) = &header {
            let mut v: Vec<String> = line.split(',').map(str::to_string).collect();
            for &i in cols {
                let x: f64 = v[i].parse().unwrap();
                v[i] = format!("{}", x.clamp(-lim, lim));
            }
            out.push_str(&v.join(","));
        } else {
            header = Some(
                line.split(',')
                    .enumerate()
                    .filter(|(_, h)| h.starts_with("wheel_front"))
                    .map(|(i, _)| i)
                    .collect(),
            );
            out.push_str(line);
        }
        out.push('\n');
    }
    assert_eq!(header.map(|h| h.len()), Some(2));
    let clipped_csv = run.with_file_name("clipped.csv");
    std::fs::write(&clipped_csv, out).unwrap();
    let name = csv_path.file_name().unwrap().to_str().unwrap();
    let mut d = desc.replace(&format!("data = \"{name}\""), "data = \"clipped.csv\"");
    for c in ["wheel_front_left_z", "wheel_front_right_z"] {
        d = d.replace(
            &format!("column = \"{c}\"\n"),
            &format!("column = \"{c}\"\nrange_g = {range_g}\n"),
        );
    }
    let p = run.with_file_name("clipped.toml");
    std::fs::write(&p, d).unwrap();
    p
}

/// The front wheel sensors clip at 4 g (their peaks reach about 6.7 g): the clipped
/// samples are left out of the residual and the values are still recovered (with them
/// in, measured: tyre rate -5.6 %, damping +19 %). With the features residual the
/// clipped channels give no features (their largest extremum is unknown) and the others
/// pin the values down within 5 %.
#[test]
fn calibrate_leaves_clipped_samples_out_and_fits_features() {
    let d = dir("clip");
    let rec = d.join("rec");
    let run = clip_front_wheels(&synth(&rec, "20", "7"), 4.0);
    let params =
        "van.toml:front.damping_ratio=0.1..0.6,van.toml:tyre.vertical_stiffness_n_m=2e5..6e5";
    for (residual, tol) in [("history", 0.02), ("features", 0.05)] {
        let out = d.join(format!("fit_{residual}"));
        let v = towride_json(&[
            "calibrate",
            run.to_str().unwrap(),
            "--params",
            params,
            "--residual",
            residual,
            "--starts",
            "3",
            "--local-fits",
            "1",
            "--out",
            out.to_str().unwrap(),
            "--json",
        ]);
        let c = &v["calibration"];
        for (name, truth) in TRUTH {
            let key = name.split_once(':').unwrap().1;
            let f = c["fitted"]
                .as_array()
                .unwrap()
                .iter()
                .find(|f| f["path"] == key)
                .unwrap_or_else(|| panic!("{residual}: {key} not fitted: {c}"));
            let x = f["value"].as_f64().unwrap();
            assert!(
                (x / truth - 1.0).abs() < tol,
                "{residual}: {key}: {x} vs truth {truth}"
            );
        }
        for ch in c["targets"][0]["channels"].as_array().unwrap() {
            let name = ch["name"].as_str().unwrap();
            let clipped = ch["clipped_samples"].as_u64().unwrap();
            let features = ch["features"].as_array().unwrap().len();
            if name.starts_with("acc_wheel_front") {
                assert!(clipped > 10, "{residual}: {name} clipped {clipped}");
                assert_eq!(features, 0, "{residual}: {name}");
            } else {
                assert_eq!(clipped, 0, "{residual}: {name}");
                let want = if residual == "features" { 1 } else { 0 };
                assert!(features >= want, "{residual}: {name}: {features} features");
            }
        }
    }
}
