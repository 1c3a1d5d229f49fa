//! `towride modes` as a user runs it.

use crate::towride;

#[test]
fn modes_json_has_the_mode_table_selection_and_mass_properties() {
    let out = towride(&[
        "modes",
        repo!("flex/hitch_crossbeam.toml"),
        "--variant",
        "5",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
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
    let out = towride(&[
        "modes",
        repo!("flex/hitch_crossbeam.toml"),
        "--cutoff",
        "300",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
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
    let out = towride(&[
        "modes",
        repo!("flex/hitch_crossbeam.toml"),
        "--variant",
        "11",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(repo!("flex/hitch_crossbeam.toml")) && err.contains("no variant 11"),
        "{err}"
    );
}

#[test]
fn modes_reads_the_twist_beam_file() {
    let out = towride(&["modes", repo!("flex/twist_beam.toml")]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("arm_left") && text.contains("arm_right") && text.contains("selection"));
}
