//! `towride comfort` as a user runs it: sines of known frequency in a CSV written here
//! against the ISO 2631-1 Table 3 weighting factors and the closed forms of a_w and VDV,
//! the units of the header, and errors naming file, line and field.

use crate::{towride_err, towride_json};

fn dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("towride-comfort-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// x: 1 Hz, 0.2 g; y: 2 Hz, 0.5 m/s^2; z: 4 Hz, 1.5 m/s^2; 40 s at 1 kHz.
fn sines_csv(path: &std::path::Path) {
    let mut s = String::from("# three sines\ntime [s],seat_x [g],seat_y [m/s^2],seat_z [m/s^2]\n");
    let w = 2.0 * std::f64::consts::PI;
    for i in 0..40_000 {
        let t = i as f64 / 1000.0;
        s.push_str(&format!(
            "{t},{},{},{}\n",
            0.2 * (w * t).sin(),
            0.5 * (w * 2.0 * t).sin(),
            1.5 * (w * 4.0 * t).sin()
        ));
    }
    std::fs::write(path, s).unwrap();
}

/// A sine of amplitude A at f has a_w = |W(f)| A / sqrt(2) and, over T, VDV =
/// (3/8)^(1/4) |W(f)| A T^(1/4) (the mean of sin^4 is 3/8). |W| from ISO 2631-1
/// Table 3 (x 1000): Wd 1011 at 1 Hz, 890 at 2 Hz; Wk 967 at 4 Hz. The total value is
/// the root sum of squares (k = 1 for comfort). Tolerance 1 %: the table's rounding
/// (0.05 %) and the filters' start from rest in the record.
#[test]
fn comfort_of_sines_matches_the_iso_table_and_closed_forms() {
    let d = dir("sines");
    let f = d.join("seat.csv");
    sines_csv(&f);
    let v = towride_json(&[
        "comfort",
        f.to_str().unwrap(),
        "--columns",
        "seat_x,seat_y,seat_z",
        "--json",
    ]);
    assert_eq!(v["schema_version"], 1);
    assert_eq!(v["sample_rate_hz"].as_f64().unwrap().round(), 1000.0);
    let g = 9.80665;
    let expect = [
        ("x", "wd", "g", 1.011, 0.2 * g),
        ("y", "wd", "m/s^2", 0.890, 0.5),
        ("z", "wk", "m/s^2", 0.967, 1.5),
    ];
    let t = 40.0_f64;
    let mut sq = 0.0;
    for (a, (axis, w, unit, table, amp)) in v["axes"].as_array().unwrap().iter().zip(expect) {
        assert_eq!(a["axis"], axis);
        assert_eq!(a["weighting"], w);
        assert_eq!(a["unit"], unit);
        let rms = table * amp / 2f64.sqrt();
        let vdv = (3.0f64 / 8.0).powf(0.25) * table * amp * t.powf(0.25);
        let got = |k: &str| a[k].as_f64().unwrap();
        assert!((got("rms_m_s2") / rms - 1.0).abs() < 0.01, "{a}: a_w {rms}");
        assert!(
            (got("vdv_m_s1_75") / vdv - 1.0).abs() < 0.01,
            "{a}: VDV {vdv}"
        );
        // Every 1 s window of the steady state holds whole periods: MTVV >= a_w; the
        // filters' start from rest overshoots for a few seconds at 1 Hz (6 %).
        let mtvv = got("mtvv_m_s2") / got("rms_m_s2");
        assert!((0.999..1.08).contains(&mtvv), "{a}");
        assert_eq!(a["transient"], false);
        sq += rms * rms;
    }
    let total = v["total_value_m_s2"].as_f64().unwrap();
    assert!((total / sq.sqrt() - 1.0).abs() < 0.01, "{total}");
    // Health factors 1.4, 1.4, 1 raise the total value (ISO 2631-1 7.2.3).
    let h = towride_json(&[
        "comfort",
        f.to_str().unwrap(),
        "--columns",
        "seat_x,seat_y,seat_z",
        "--assessment",
        "health",
        "--json",
    ]);
    let r = |k: usize| v["axes"][k]["rms_m_s2"].as_f64().unwrap();
    let hv = ((1.4 * r(0)).powi(2) + (1.4 * r(1)).powi(2) + r(2).powi(2)).sqrt();
    assert!((h["total_value_m_s2"].as_f64().unwrap() / hv - 1.0).abs() < 1e-12);
}

#[test]
fn comfort_errors_name_file_line_and_field() {
    let d = dir("bad");
    let fine: String = (0..600)
        .map(|i| format!("{},{}\n", i as f64 / 500.0, 0.1))
        .collect();
    let jitter: String = (0..600)
        .map(|i| {
            format!(
                "{},{}\n",
                i as f64 / 500.0 + if i == 300 { 1e-3 } else { 0.0 },
                0.1
            )
        })
        .collect();
    let slow: String = (0..600)
        .map(|i| format!("{},{}\n", i as f64 / 100.0, 0.1))
        .collect();
    let cases = [
        (
            "force.csv",
            format!("time [s],a_z [N]\n{fine}"),
            ":1: field `a_z`: unit [N] is not an acceleration",
        ),
        (
            "nounit.csv",
            format!("time [s],a_z\n{fine}"),
            ":1: field `a_z`: no unit in the header",
        ),
        (
            "text.csv",
            format!("time [s],a_z [g]\n0,0.1\n0.002,x\n{fine}"),
            ":3: field `a_z`: `x` is not a number",
        ),
        (
            "jitter.csv",
            format!("time [s],a_z [g]\n{jitter}"),
            ":302: field `time`: time step",
        ),
        (
            "slow.csv",
            format!("time [s],a_z [g]\n{slow}"),
            "too low for Wk",
        ),
    ];
    for (name, text, want) in cases {
        let f = d.join(name);
        std::fs::write(&f, text).unwrap();
        let err = towride_err(
            &["comfort", f.to_str().unwrap(), "--columns", "a_z", "--json"],
            2,
        );
        assert!(err.contains(name) && err.contains(want), "{name}: {err}");
    }
    let f = d.join("force.csv");
    let err = towride_err(
        &[
            "comfort",
            f.to_str().unwrap(),
            "--columns",
            "a_z",
            "--axes",
            "x,y",
        ],
        2,
    );
    assert!(err.contains("--axes lists 2 values for 1 columns"), "{err}");
}

/// On a run's `outputs.csv`: the floor point's columns read back from the CSV give the
/// summary's comfort block (the CSV's printed digits aside), and the band-limited twin
/// needs `--axes` (its name ends in `_lp100`).
#[test]
fn comfort_of_a_runs_outputs_matches_its_summary() {
    let d = dir("run");
    let out = d.join("run");
    crate::towride_ok(&["run", "scenes/default.toml", "--out", out.to_str().unwrap()]);
    let csv = out.join("outputs.csv");
    let v = towride_json(&[
        "comfort",
        csv.to_str().unwrap(),
        "--columns",
        "acc_driver_floor_x,acc_driver_floor_y,acc_driver_floor_z",
        "--json",
    ]);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let c = &s["comfort"];
    for k in 0..3 {
        for m in ["rms_m_s2", "vdv_m_s1_75", "mtvv_m_s2"] {
            let (a, b) = (
                v["axes"][k][m].as_f64().unwrap(),
                c["axes"][k][m].as_f64().unwrap(),
            );
            assert!(
                (a - b).abs() <= 1e-6 * b.abs().max(1e-3),
                "{k} {m}: {a} vs {b}"
            );
        }
    }
    let err = towride_err(
        &[
            "comfort",
            csv.to_str().unwrap(),
            "--columns",
            "acc_driver_floor_z_lp100",
        ],
        2,
    );
    assert!(err.contains("give --axes"), "{err}");
}
