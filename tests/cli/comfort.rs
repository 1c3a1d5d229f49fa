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

/// |T| of a cushion (kc, cc) under a frame mass m0 and a mass m1 on (k1, c1), by the two
/// force balances at f (tests/app/comfort_seat.rs derives it).
fn seat_gain(m0: f64, m1: f64, k1: f64, c1: f64, kc: f64, cc: f64, f: f64) -> f64 {
    let w = 2.0 * std::f64::consts::PI * f;
    let (z1r, z1i) = (k1, w * c1);
    let (dr, di) = (k1 - w * w * m1, w * c1);
    // Z1^2 / (Z1 - w^2 m1)
    let (nr, ni) = (z1r * z1r - z1i * z1i, 2.0 * z1r * z1i);
    let d2 = dr * dr + di * di;
    let (tr, ti) = ((nr * dr + ni * di) / d2, (ni * dr - nr * di) / d2);
    let (br, bi) = (kc - w * w * m0 + z1r - tr, w * cc + z1i - ti);
    (kc * kc + (w * cc).powi(2)).sqrt() / br.hypot(bi)
}

/// `--seat`: a body file written here (60 kg on the cushion, 0.75 of it on a 5 Hz,
/// 0.475 spring; cushion 40 kN/m, 400 N s/m) takes the z column of the sines through the
/// seat: its a_w is the Table 3 factor (Wk 967 at 4 Hz) times the seat's |T(4 Hz)| times
/// A / sqrt(2); x and y stay as without the seat. Tolerance 1 % as above.
#[test]
fn comfort_seat_option_takes_z_through_the_seat() {
    let d = dir("seat");
    let f = d.join("seat.csv");
    sines_csv(&f);
    let body = d.join("body.toml");
    std::fs::write(
        &body,
        "[body]\nmass_kg = 800.0\n\n[seat]\noccupant_mass_kg = 60.0\noccupant_moving_fraction = 0.75\n\
         occupant_natural_frequency_hz = 5.0\noccupant_damping_ratio = 0.475\n\
         cushion_stiffness_n_m = 40000.0\ncushion_damping_n_s_m = 400.0\n",
    )
    .unwrap();
    let args = |seat: bool| {
        let mut a = vec![
            "comfort".to_string(),
            f.display().to_string(),
            "--columns".into(),
            "seat_x,seat_y,seat_z".into(),
            "--json".into(),
        ];
        if seat {
            a.extend(["--seat".into(), body.display().to_string()]);
        }
        a
    };
    let run = |seat: bool| {
        let a = args(seat);
        towride_json(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let (plain, seated) = (run(false), run(true));
    let m1 = 0.75 * 60.0;
    let k1 = m1 * (2.0 * std::f64::consts::PI * 5.0f64).powi(2);
    let c1 = 2.0 * 0.475 * (k1 * m1).sqrt();
    let t4 = seat_gain(15.0, m1, k1, c1, 40_000.0, 400.0, 4.0);
    let want = 0.967 * t4 * 1.5 / 2f64.sqrt();
    let z = &seated["axes"][2];
    assert_eq!(z["channel"], "seat_z (seat surface)");
    let got = z["rms_m_s2"].as_f64().unwrap();
    assert!(
        (got / want - 1.0).abs() < 0.01,
        "a_w {got} vs {want} (|T| {t4})"
    );
    for k in [0, 1] {
        assert_eq!(seated["axes"][k]["rms_m_s2"], plain["axes"][k]["rms_m_s2"]);
    }
    assert_eq!(seated["seat"]["columns"][0], "seat_z");
    assert!(plain.get("seat").is_none());
}

#[test]
fn comfort_seat_errors_name_file_line_and_field() {
    let d = dir("seat-bad");
    let f = d.join("seat.csv");
    sines_csv(&f);
    let cases = [
        (
            "none.toml",
            "[body]\nmass_kg = 800.0\n",
            "no [seat] section",
        ),
        (
            "fraction.toml",
            "[seat]\noccupant_mass_kg = 60.0\noccupant_moving_fraction = 1.2\n\
             occupant_natural_frequency_hz = 5.0\noccupant_damping_ratio = 0.475\n\
             cushion_stiffness_n_m = 40000.0\ncushion_damping_n_s_m = 400.0\n",
            "field `seat.occupant_moving_fraction`: must be below 1",
        ),
        (
            "missing.toml",
            "[seat]\noccupant_mass_kg = 60.0\n",
            "missing field `occupant_moving_fraction`",
        ),
    ];
    for (name, text, want) in cases {
        let b = d.join(name);
        std::fs::write(&b, text).unwrap();
        let err = towride_err(
            &[
                "comfort",
                f.to_str().unwrap(),
                "--columns",
                "seat_x,seat_z",
                "--seat",
                b.to_str().unwrap(),
            ],
            2,
        );
        assert!(err.contains(name) && err.contains(want), "{name}: {err}");
        if name == "fraction.toml" {
            assert!(err.contains("fraction.toml:3:"), "{err}");
        }
    }
    let b = d.join("fraction.toml");
    std::fs::write(
        &b,
        "[seat]\noccupant_mass_kg = 60.0\noccupant_moving_fraction = 0.7\n\
         occupant_natural_frequency_hz = 5.0\noccupant_damping_ratio = 0.475\n\
         cushion_stiffness_n_m = 40000.0\ncushion_damping_n_s_m = 400.0\n",
    )
    .unwrap();
    let err = towride_err(
        &[
            "comfort",
            f.to_str().unwrap(),
            "--columns",
            "seat_x",
            "--seat",
            b.to_str().unwrap(),
        ],
        2,
    );
    assert!(err.contains("no vertical (z) column"), "{err}");
}
