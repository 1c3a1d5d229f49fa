//! Issue 31 item 6: a channel that carries only sensor noise (`acc_hitch_y` in a
//! straight run) is flagged and left out of the run's mean rating.

use crate::towride_json;

#[test]
fn a_channel_of_noise_alone_is_flagged_and_left_out_of_the_mean() {
    // At 10 km/h over the 50 mm ramp the tyres feel the obstacle well before it: the
    // quiet road must end before that (a first version took it for noise).
    for run in [
        repo!("measurements/synthetic/bump_25mm_40kmh_empty.toml"),
        repo!("measurements/synthetic/ramp_50mm_10kmh_empty.toml"),
    ] {
        noise_alone_is_left_out(run);
    }
}

fn noise_alone_is_left_out(run: &str) {
    let out = std::env::temp_dir().join(format!("towride_signal_{}", std::process::id()));
    let o = out.display().to_string();
    let d = towride_json(&["validate", run, "--json", "--out", &o]);
    let r = &d["runs"][0];
    assert_eq!(
        r["without_signal"],
        serde_json::json!(["acc_hitch_y"]),
        "{r}"
    );
    let mut sum = 0.0;
    let mut n = 0;
    for c in r["channels"].as_array().unwrap() {
        let f = &c["corrected"];
        let snr = f["signal_to_noise"].as_f64().unwrap();
        if c["channel"] == "acc_hitch_y" {
            // Noise alone: its RMS in the window is its RMS on the quiet road.
            assert!(snr < 2.0 && f["has_signal"] == false, "{c}");
        } else {
            assert!(snr > 10.0 && f["has_signal"] == true, "{c}");
            sum += f["rating"].as_f64().unwrap();
            n += 1;
        }
    }
    let mean = r["mean_rating_corrected"].as_f64().unwrap();
    assert!(
        (mean - sum / n as f64).abs() < 1e-12,
        "{mean} vs {}",
        sum / n as f64
    );
}

/// Issue 31 item 5: a logger without a trigger, made by the model itself without any
/// error: the uncorrected comparison is aligned on the detected passage less the
/// detector's lag in the simulation, as the corrected one, so the peaks fall on the
/// recording's (c4bd0ca: every peak a sample early, the uncorrected rating 0.95).
#[test]
fn without_a_trigger_the_uncorrected_baseline_is_aligned_on_the_passage() {
    let dir = std::env::temp_dir().join(format!("towride_notrig_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let d = dir.display().to_string();
    crate::towride_ok(&[
        "validate",
        "synth",
        "--scene",
        repo!("scenes/bump_25mm.toml"),
        "--speed-kmh",
        "40",
        "--out",
        &d,
        "--noise-rms-mps2",
        "0",
        "--trigger-delay-ms",
        "0",
        "--speed-error-pct",
        "0",
        "--gain-error-pct",
        "0",
        "--foil-jitter-ms",
        "0",
    ]);
    // The same run without its foils and photocell: the passage is found in the signals.
    let with = std::fs::read_to_string(dir.join("bump_25mm_40kmh_empty.toml")).unwrap();
    let mut kept = Vec::new();
    let mut skip = false;
    for l in with.lines() {
        if l.starts_with("[trigger") || l.starts_with("[[trigger") {
            skip = true;
            continue;
        }
        if skip && l.starts_with('[') {
            skip = false;
        }
        if !skip {
            kept.push(l);
        }
    }
    let file = dir.join("no_trigger.toml");
    std::fs::write(&file, kept.join("\n")).unwrap();
    let f = file.display().to_string();
    let out = dir.join("out").display().to_string();
    let v = towride_json(&["validate", &f, "--json", "--out", &out]);
    let r = &v["runs"][0];
    assert!(r["passage"].is_object(), "{}", r["passage"]);
    let dts: Vec<f64> = r["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let u = &c["uncorrected"];
            u["t_peak_simulated_s"].as_f64().unwrap() - u["t_peak_measured_s"].as_f64().unwrap()
        })
        .collect();
    let mean = dts.iter().sum::<f64>() / dts.len() as f64;
    assert!(
        mean.abs() < 0.5e-3,
        "peaks off by {mean:e} s on average: {dts:?}"
    );
    assert!(dts.iter().all(|d| d.abs() <= 1.0e-3 + 1e-12), "{dts:?}");
    let u = r["mean_rating_uncorrected"].as_f64().unwrap();
    assert!(u > 0.98, "uncorrected rating {u} on the model's own data");
}
