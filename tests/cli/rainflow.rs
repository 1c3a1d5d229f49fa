//! `towride rainflow` as a user runs it: the ASTM E1049-85 example from a CSV, the
//! files of `--out`, and errors naming file, line and field with a non-zero exit code.

use crate::{towride_err, towride_json};

fn dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("towride-rainflow-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn rainflow_counts_the_astm_example_and_writes_its_files() {
    let d = dir("ok");
    let f = d.join("load.csv");
    // ASTM E1049-85 Fig. 6 history, in a `name [unit]` column beside a time column.
    let x = [-2, 1, -3, 5, -1, 3, -4, 4, -2];
    let rows: Vec<String> = x
        .iter()
        .enumerate()
        .map(|(i, v)| format!("{i},{v}"))
        .collect();
    std::fs::write(&f, format!("time [s],stress [MPa]\n{}\n", rows.join("\n"))).unwrap();
    let out = d.join("out");
    let v = towride_json(&[
        "rainflow",
        f.to_str().unwrap(),
        "--column",
        "stress",
        "--s-ref",
        "90",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(v["schema_version"], 1);
    assert_eq!(v["unit"], "MPa");
    assert_eq!(v["cycles"], 4.0);
    assert_eq!(v["full_cycles"], 1);
    assert_eq!(v["half_cycles"], 6);
    assert_eq!(v["largest_range"], 9.0);
    // DEL = (sum n S^3 / 2e6)^(1/3), the ASTM counts by hand:
    // 0.5 * 27 + 1.5 * 64 + 0.5 * 216 + 1.0 * 512 + 0.5 * 729 = 1094.
    let del = (1094.0f64 / 2.0e6).powf(1.0 / 3.0);
    assert!((v["del_at_n_ref"].as_f64().unwrap() / del - 1.0).abs() < 1e-12);
    let damage = 1094.0 / 90f64.powi(3) / 2.0e6;
    assert!((v["damage"].as_f64().unwrap() / damage - 1.0).abs() < 1e-12);
    let csv = std::fs::read_to_string(out.join("rainflow_stress.csv")).unwrap();
    assert!(
        csv.starts_with("range [MPa],mean [MPa],count [-]\n"),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), 8);
    assert!(out.join("rainflow_stress_matrix.csv").is_file());
    let png = std::fs::read(out.join("rainflow_stress.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
}

#[test]
fn rainflow_errors_name_file_line_and_field() {
    let d = dir("bad");
    let cases = [
        ("missing.csv", "a [N]\n1\n2\n3\n", "b", "no column `b`"),
        (
            "text.csv",
            "a [N]\n1\n2\nabc\n4\n",
            "a",
            ":4: field `a`: `abc` is not a number",
        ),
        (
            "nan.csv",
            "a [N]\n1\nNaN\n3\n4\n",
            "a",
            ":3: field `a`: `NaN` is not a finite number",
        ),
        (
            "short.csv",
            "a [N]\n1\n2\n",
            "a",
            "2 values: rainflow counting needs at least 3",
        ),
    ];
    for (name, text, column, want) in cases {
        let f = d.join(name);
        std::fs::write(&f, text).unwrap();
        let err = towride_err(&["rainflow", f.to_str().unwrap(), "--column", column], 2);
        assert!(err.contains(name) && err.contains(want), "{name}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let f = d.join("missing.csv");
    let err = towride_err(
        &["rainflow", f.to_str().unwrap(), "--column", "a", "--m", "0"],
        2,
    );
    assert!(err.contains("m = 0"), "{err}");
}
