//! Issue 31 item 6: a channel that carries only sensor noise (`acc_hitch_y` in a
//! straight run) is flagged and left out of the run's mean rating.

use crate::towride_json;

#[test]
fn a_channel_of_noise_alone_is_flagged_and_left_out_of_the_mean() {
    let out = std::env::temp_dir().join(format!("towride_signal_{}", std::process::id()));
    let o = out.display().to_string();
    let d = towride_json(&[
        "validate",
        repo!("measurements/synthetic/bump_25mm_40kmh_empty.toml"),
        "--json",
        "--out",
        &o,
    ]);
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
