//! `towride modes` as a user runs it.

use crate::{towride, towride_err, towride_json, towride_ok};

#[test]
fn modes_json_has_the_mode_table_selection_and_mass_properties() {
    let v = towride_json(&[
        "modes",
        repo!("flex/hitch_crossbeam.toml"),
        "--variant",
        "5",
        "--json",
    ]);
    let modes = v["modes"].as_array().unwrap();
    // 3 interface nodes x 6 + 8 fixed-interface modes.
    assert_eq!(modes.len(), 26);
    for (i, m) in modes.iter().enumerate() {
        assert_eq!(m["index"].as_u64().unwrap() as usize, i + 1);
        assert!(m["frequency_hz"].is_number());
        let kind = m["kind"].as_str().unwrap();
        assert_eq!(kind, if i < 6 { "rigid" } else { "elastic" });
        assert!(m["selected"].is_boolean());
        if kind == "rigid" {
            assert_eq!(m["selected"], false);
        }
    }
    assert!(v["mass_kg"].as_f64().unwrap() > 1.0);
    assert_eq!(v["com_m"].as_array().unwrap().len(), 3);
    assert_eq!(v["inertia_kg_m2"].as_array().unwrap().len(), 3);
    assert_eq!(v["variant"], 5);
}

#[test]
fn modes_cutoff_selects_by_frequency() {
    let v = towride_json(&[
        "modes",
        repo!("flex/hitch_crossbeam.toml"),
        "--cutoff",
        "300",
        "--json",
    ]);
    for m in v["modes"].as_array().unwrap() {
        let f = m["frequency_hz"].as_f64().unwrap();
        let want = m["kind"] == "elastic" && f <= 300.0;
        assert_eq!(m["selected"].as_bool().unwrap(), want, "{m}");
    }
}

#[test]
fn modes_text_and_bad_file_errors() {
    let out = towride(&[
        "modes",
        repo!("flex/hitch_crossbeam.toml"),
        "--modes",
        "7,8,9",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("explicit list [7, 8, 9]"), "{text}");
    let err = towride_err(
        &[
            "modes",
            repo!("flex/hitch_crossbeam.toml"),
            "--variant",
            "11",
        ],
        2,
    );
    assert!(
        err.contains(repo!("flex/hitch_crossbeam.toml")) && err.contains("no variant 11"),
        "{err}"
    );
}

#[test]
fn modes_reads_the_twist_beam_file() {
    let out = towride_ok(&["modes", repo!("flex/twist_beam.toml")]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("arm_left") && text.contains("arm_right") && text.contains("selection"));
}

/// Energy-based selection from a run (issue 21, item 7): a run folder whose summary gives
/// the crossbeam's strain-energy shares selects exactly the modes at or above the
/// threshold (by peak or by integral share) for the next run, `towride modes --from-run`
/// shows that selection beside the a-priori one, and a threshold outside (0, 1) is
/// refused. The shares are written by hand, so the expected selection is known.
#[test]
fn modes_from_a_run_select_the_next_runs_modes() {
    let dir = std::env::temp_dir().join(format!("towride_modes_from_{}", std::process::id()));
    let earlier = dir.join("earlier");
    std::fs::create_dir_all(&earlier).unwrap();
    let mode = |n: u32, peak: f64, integral: f64| {
        serde_json::json!({"number": n, "frequency_hz": 100.0 * n as f64,
                           "share_peak": peak, "share_integral": integral})
    };
    let summary = serde_json::json!({"modal_energy": [{"body": "hitch", "modes": [
        mode(7, 0.60, 0.55), mode(9, 0.30, 0.35), mode(10, 0.005, 0.02),
        mode(13, 0.004, 0.001), mode(18, 0.0, 0.0)]}]});
    std::fs::write(earlier.join("summary.json"), summary.to_string()).unwrap();
    let earlier_s = earlier.to_str().unwrap();

    // Side by side with the file's own selection.
    let v = towride_json(&[
        "modes",
        repo!("flex/hitch_crossbeam.toml"),
        "--from-run",
        earlier_s,
        "--json",
    ]);
    assert_eq!(v["run_based_modes"], serde_json::json!([7, 9, 10]));
    assert!(v["a_priori_modes"].as_array().unwrap().len() > 3);

    // The next run integrates exactly those modes.
    let next = dir.join("next");
    let out = towride(&[
        "run",
        repo!("scenes/default.toml"),
        "--modes-from",
        earlier_s,
        "--out",
        next.to_str().unwrap(),
        "--animation-rate-hz",
        "0",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(next.join("summary.json")).unwrap()).unwrap();
    let hitch = &s["modal_energy"].as_array().unwrap()[0];
    assert_eq!(hitch["body"], "hitch");
    let numbers: Vec<u64> = hitch["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["number"].as_u64().unwrap())
        .collect();
    assert_eq!(numbers, vec![7, 9, 10]);

    // A share threshold of 150 % is refused.
    let out = towride(&[
        "run",
        repo!("scenes/default.toml"),
        "--modes-from",
        earlier_s,
        "--modes-share",
        "150",
        "--out",
        next.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let _ = std::fs::remove_dir_all(&dir);
}
