//! `towride compare` on inputs that used to give numbers meaning nothing (issues 31 and
//! 32): modal coordinates of different Craig-Bampton bases, kN against N, g against
//! m/s^2, runs with no time in common, header-only and single-row files, time that
//! does not increase, two columns of one name.

use std::path::PathBuf;

use towride_app::report::compare::{compare, load, write, DIFFERENT_BASES};

fn dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride-cmpin-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A run folder with `outputs.csv` of `text`.
fn run(tag: &str, text: &str) -> PathBuf {
    let d = dir(tag);
    std::fs::write(d.join("outputs.csv"), text).unwrap();
    d
}

/// `hitch_fx [unit]` = `gain * t` and three modal coordinates over 0..1 s, with a
/// summary.json naming hitch variant `variant` and its kept modes `modes`.
fn modal_run(tag: &str, variant: u64, modes: &[(u64, f64)]) -> PathBuf {
    let mut text =
        String::from("time [s],hitch_fx [N],hitch_eta_1 [-],hitch_eta_2 [-],hitch_eta_3 [-]\n");
    for k in 0..=10 {
        let t = k as f64 * 0.1;
        text.push_str(&format!(
            "{t},{t},{},{},{}\n",
            0.1 * t,
            0.2 * t,
            variant as f64 * t
        ));
    }
    let d = run(tag, &text);
    let modes: Vec<serde_json::Value> = modes
        .iter()
        .map(|(n, f)| serde_json::json!({"number": n, "frequency_hz": f, "peak_j": 1.0}))
        .collect();
    let summary = serde_json::json!({
        "scene": {"hitch_variant": variant},
        "modal_energy": [{"body": "hitch", "peak_total_j": 1.0, "modes": modes}],
    });
    std::fs::write(d.join("summary.json"), summary.to_string()).unwrap();
    d
}

#[test]
fn modal_coordinates_of_different_bases_are_marked_and_left_out() {
    let v1 = [(7, 119.15), (8, 150.49), (10, 217.64)];
    let a = modal_run("v1", 1, &v1);
    let b = modal_run("v10", 10, &[(8, 199.35), (9, 282.64), (10, 357.3)]);
    let same = modal_run("v1b", 1, &v1);
    let runs = [load(&a).unwrap(), load(&b).unwrap()];
    let mut c = compare(&runs).unwrap();
    assert_eq!(c.channels, ["hitch_fx"]);
    assert!(
        c.differences.iter().all(|d| d.channel == "hitch_fx"),
        "{:?}",
        c.differences
    );
    assert_eq!(c.not_comparable.len(), 1);
    let n = &c.not_comparable[0];
    assert_eq!(n.reason, DIFFERENT_BASES);
    assert_eq!(n.channels, ["hitch_eta_1", "hitch_eta_2", "hitch_eta_3"]);
    assert!(
        n.detail.contains("variant 10") && n.detail.contains("variant 1,"),
        "{}",
        n.detail
    );
    let json = serde_json::to_value(&c).unwrap();
    assert_eq!(
        json["not_comparable"][0]["reason"],
        "not comparable (different modal bases)"
    );
    // The page carries the same statement (its script draws the table from it).
    let out = a.join("cmp");
    write(&runs, &mut c, &out, "svg").unwrap();
    let html = std::fs::read_to_string(out.join("compare.html")).unwrap();
    assert!(html.contains("not comparable (different modal bases)"));
    assert!(html.contains("Not comparable"));
    // Same variant, same modes: compared as any channel.
    let c = compare(&[load(&a).unwrap(), load(&same).unwrap()]).unwrap();
    assert!(c.not_comparable.is_empty());
    assert_eq!(c.channels.len(), 4);
    // A modal body whose modes moved (the same variant, a stiffness changed): refused.
    let moved = modal_run("v1m", 1, &[(7, 119.15), (8, 150.49), (10, 230.0)]);
    let c = compare(&[load(&a).unwrap(), load(&moved).unwrap()]).unwrap();
    assert_eq!(c.not_comparable.len(), 1);
    for d in [a, b, same, moved] {
        std::fs::remove_dir_all(d).ok();
    }
}

#[test]
fn another_si_prefix_is_converted_and_another_unit_refused() {
    let rows = |unit: &str, scale: f64| {
        let mut t = format!("time [s],hitch_fx [{unit}],acc_hitch_z [m/s^2]\n");
        for k in 0..=10 {
            t.push_str(&format!(
                "{},{},1\n",
                k as f64 * 0.1,
                2000.0 * k as f64 * scale
            ));
        }
        t
    };
    let n = run("n", &rows("N", 1.0));
    let kn = run("kn", &rows("kN", 1e-3));
    let c = compare(&[load(&n).unwrap(), load(&kn).unwrap()]).unwrap();
    let d = &c.differences[0];
    assert_eq!((d.channel.as_str(), d.unit.as_str()), ("hitch_fx", "N"));
    assert!(
        (d.max - 20000.0).abs() < 1e-9 && d.max_difference.abs() < 1e-9,
        "{d:?}"
    );
    assert!(d.rms_difference < 1e-9, "{d:?}");
    assert_eq!(c.conversions.len(), 1);
    assert_eq!(
        (c.conversions[0].from.as_str(), c.conversions[0].factor),
        ("kN", 1e3)
    );
    // g might be a gram or gravity: not guessed.
    let g = run(
        "g",
        &rows("N", 1.0).replace("acc_hitch_z [m/s^2]", "acc_hitch_z [g]"),
    );
    let e = compare(&[load(&n).unwrap(), load(&g).unwrap()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("towride-cmpin-g") && e.contains("outputs.csv:1"),
        "{e}"
    );
    assert!(
        e.contains("acc_hitch_z") && e.contains("[g]") && e.contains("[m/s^2]"),
        "{e}"
    );
    for d in [n, kn, g] {
        std::fs::remove_dir_all(d).ok();
    }
}

#[test]
fn runs_with_no_time_in_common_are_refused() {
    let at = |t0: f64| {
        let mut t = String::from("time [s],hitch_fx [N]\n");
        for k in 0..=10 {
            t.push_str(&format!("{},{k}\n", t0 + k as f64 * 0.1));
        }
        t
    };
    let (a, b) = (run("early", &at(0.0)), run("late", &at(2.0)));
    let e = compare(&[load(&a).unwrap(), load(&b).unwrap()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("towride-cmpin-late") && e.contains("no time in common"),
        "{e}"
    );
    assert!(!e.contains("NaN"), "{e}");
    for d in [a, b] {
        std::fs::remove_dir_all(d).ok();
    }
}

#[test]
fn malformed_files_are_named_with_line_and_field() {
    let cases = [
        (
            "header",
            "time [s],hitch_fx [N]\n",
            "outputs.csv:2",
            "no data rows",
        ),
        (
            "single",
            "time [s],hitch_fx [N]\n0,1\n",
            "outputs.csv:2",
            "one data row",
        ),
        (
            "reversed",
            "time [s],hitch_fx [N]\n0,1\n0.2,1\n0.1,1\n",
            "outputs.csv:4",
            "time does not increase: 0.1 s after 0.2 s on line 3",
        ),
        (
            "repeated",
            "time [s],hitch_fx [N]\n0,1\n0,1\n",
            "outputs.csv:3",
            "time does not increase",
        ),
        (
            "duplicate",
            "time [s],hitch_fx [N],hitch_fx [N]\n0,1,2\n0.1,1,2\n",
            "outputs.csv:1",
            "column 3 repeats the name of column 2",
        ),
    ];
    for (tag, text, at, says) in cases {
        let d = run(tag, text);
        let e = load(&d).unwrap_err().to_string();
        assert!(e.contains(at) && e.contains(says), "{tag}: {e}");
        if tag == "duplicate" || tag == "reversed" {
            let field = if tag == "duplicate" {
                "hitch_fx"
            } else {
                "time"
            };
            assert!(e.contains(field), "{tag}: {e}");
        }
        std::fs::remove_dir_all(d).ok();
    }
}
