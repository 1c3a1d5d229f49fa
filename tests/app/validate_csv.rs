//! Reading recorded CSV files: separators, decimal commas, units, junk lines, missing and
//! repeated samples, and located errors for what cannot be recovered.

use std::path::{Path, PathBuf};

use towride_app::validate::csv_reader::{read_measurement, read_table};
use towride_app::validate::Descriptor;

const G: f64 = 9.80665;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride-vcsv-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Two channels sampled at 500 Hz: a = sin, b = a decaying cosine [m/s^2].
fn signal(k: usize) -> (f64, f64, f64) {
    let t = k as f64 / 500.0;
    (
        t,
        3.0 * (7.0 * t).sin(),
        -2.0 * (-t).exp() * (11.0 * t).cos(),
    )
}

fn descriptor(d: &Path, csv: &str, units: (&str, &str)) -> PathBuf {
    let text = format!(
        "scene = \"scene.toml\"\nobstacle = \"bump\"\nnominal_speed_kmh = 30.0\nload_case = \"empty\"\ndata = \"{csv}\"\n\
         [acquisition]\nfilter = \"butterworth\"\norder = 4\ncutoff_hz = 100.0\n\
         [trigger]\nphotocell_position_m = -10.0\nphotocell_time_s = 0.0\n\
         [[trigger.foil]]\nposition_m = -10.0\ntime_s = 0.0\n[[trigger.foil]]\nposition_m = -2.0\ntime_s = 0.96\n\
         [[channel]]\ncolumn = \"a\"\nsimulated = \"acc_a_z\"\naxis = \"z\"\nunit = \"{}\"\n\
         [[channel]]\ncolumn = \"b\"\nsimulated = \"acc_b_z\"\naxis = \"z\"\nunit = \"{}\"\n",
        units.0, units.1
    );
    let p = d.join(csv.replace(".csv", ".toml"));
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn g_with_decimal_commas_reads_as_si_with_points() {
    let d = dir("units");
    // Reference: plain comma-separated, m/s^2, decimal points.
    let mut plain = String::from("time [s],a [m/s^2],b [m/s^2]\n");
    // The same data as a German logger writes it: junk lines, `;`, decimal commas, g,
    // columns in another order, time in ms.
    let mut german =
        String::from("Messung 17;Kanal;\nDatum;01.06.2024\n\nb [g];Zeit;time [ms];a [g]\n");
    for k in 0..400 {
        let (t, a, b) = signal(k);
        plain.push_str(&format!("{t:.6},{a:.9},{b:.9}\n"));
        let row = format!("{:.11};x;{:.3};{:.11}\n", b / G, t * 1e3, a / G);
        german.push_str(&row.replace('.', ","));
    }
    std::fs::write(d.join("plain.csv"), plain).unwrap();
    std::fs::write(d.join("german.csv"), german).unwrap();
    let p = read_measurement(
        &Descriptor::from_file(&descriptor(&d, "plain.csv", ("m/s^2", "m/s^2"))).unwrap(),
    )
    .unwrap();
    let g = read_measurement(
        &Descriptor::from_file(&descriptor(&d, "german.csv", ("g", "g"))).unwrap(),
    )
    .unwrap();
    assert_eq!(p.time_s.len(), 400);
    assert_eq!(g.time_s.len(), 400);
    assert!(
        p.notes.is_empty() && g.notes.is_empty(),
        "{:?} {:?}",
        p.notes,
        g.notes
    );
    for k in 0..400 {
        assert!((p.time_s[k] - g.time_s[k]).abs() < 1e-9);
        for c in ["acc_a_z", "acc_b_z"] {
            let (x, y) = (p.channels[c][k], g.channels[c][k]);
            assert!((x - y).abs() < 1e-8, "{c}[{k}]: {x} vs {y}");
        }
    }
    // Against the generating function, independent of either file.
    let (_, a100, _) = signal(100);
    assert!((g.channels["acc_a_z"][100] - a100).abs() < 1e-8);
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn junk_missing_repeated_and_empty_are_repaired() {
    let d = dir("repair");
    let mut text =
        String::from("logger v2.1 export\n# operator: nobody\n;;;\ntime;a;b\ns;m/s^2;m/s^2\n");
    for k in 0..300 {
        if k == 120 || k == 121 {
            continue; // two missing samples
        }
        let (t, a, b) = signal(k);
        let line = if k == 200 {
            format!("{t:.4};{a:.9};\n")
        } else {
            format!("{t:.4};{a:.9};{b:.9}\n")
        };
        text.push_str(&line.replace('.', ","));
        if k == 60 {
            text.push_str(&line.replace('.', ",")); // a repeated sample
        }
    }
    let f = d.join("run.csv");
    std::fs::write(&f, text).unwrap();
    let t = read_table(&f, "time", &["a", "b"]).unwrap();
    assert_eq!(t.header_line, 4);
    assert_eq!(t.separator, ';');
    assert!(t.decimal_comma);
    assert_eq!(
        t.units,
        vec![Some("m/s^2".to_string()), Some("m/s^2".to_string())]
    );
    assert_eq!(t.time_s.len(), 300, "one grid after the repairs");
    let joined = t.notes.join("\n");
    assert!(joined.contains("2 missing sample(s)"), "{joined}");
    assert!(joined.contains("repeated sample"), "{joined}");
    assert!(joined.contains("empty value in b"), "{joined}");
    assert_eq!(t.notes.len(), 3, "{joined}");
    for k in [120, 121, 200] {
        let (tk, a, b) = signal(k);
        assert!((t.time_s[k] - tk).abs() < 1e-9);
        // Linear interpolation over 2 ms of smooth signals: a few 1e-3 at most.
        assert!(
            (t.columns[0][k] - a).abs() < 5e-3,
            "a[{k}] {} vs {a}",
            t.columns[0][k]
        );
        assert!(
            (t.columns[1][k] - b).abs() < 5e-3,
            "b[{k}] {} vs {b}",
            t.columns[1][k]
        );
    }
    std::fs::remove_dir_all(&d).ok();
}

fn write_rows(f: &Path, head: &str, rows: impl Fn(usize, f64, f64, f64) -> String) {
    let mut text = String::from(head);
    for k in 0..100 {
        let (t, a, b) = signal(k);
        text.push_str(&rows(k, t, a, b));
    }
    std::fs::write(f, text).unwrap();
}

#[test]
fn unrecoverable_files_name_file_line_and_column() {
    let d = dir("bad");
    let f = d.join("bad_number.csv");
    // Header on line 2; data row k is on line k + 3; row 40 has a broken number in b.
    write_rows(&f, "junk\ntime [s],a [g],b [g]\n", |k, t, a, b| {
        if k == 40 {
            format!("{t:.4},{a:.6},1.2.3\n")
        } else {
            format!("{t:.4},{a:.6},{b:.6}\n")
        }
    });
    let e = read_table(&f, "time", &["a", "b"]).unwrap_err();
    let (t, a, _) = signal(40);
    let col = format!("{t:.4},{a:.6},").chars().count() + 1;
    assert_eq!((e.line, e.column), (Some(43), Some(col)), "{e}");
    assert_eq!(e.field, "b");
    assert!(
        e.to_string()
            .starts_with(&format!("{}:43:{col}: field `b`", f.display())),
        "{e}"
    );

    let f = d.join("time_back.csv");
    write_rows(&f, "time [s];a [g];b [g]\n", |k, t, a, b| {
        let t = if k == 50 { t - 0.1 } else { t };
        format!("{t:.4};{a:.6};{b:.6}\n")
    });
    let e = read_table(&f, "time", &["a", "b"]).unwrap_err();
    assert_eq!(
        (e.line, e.column, e.field.as_str()),
        (Some(52), Some(1), "time"),
        "{e}"
    );
    assert!(e.message.contains("goes back"), "{e}");

    let f = d.join("long_gap.csv");
    write_rows(&f, "time [s];a [g];b [g]\n", |k, t, a, b| {
        if (30..60).contains(&k) {
            String::new()
        } else {
            format!("{t:.4};{a:.6};{b:.6}\n")
        }
    });
    let e = read_table(&f, "time", &["a", "b"]).unwrap_err();
    assert_eq!((e.line, e.column), (Some(32), Some(1)), "{e}");
    assert!(e.message.contains("30 samples missing"), "{e}");

    let f = d.join("short_row.csv");
    write_rows(&f, "time [s];a [g];b [g]\n", |k, t, a, b| {
        if k == 10 {
            format!("{t:.4};{a:.6}\n")
        } else {
            format!("{t:.4};{a:.6};{b:.6}\n")
        }
    });
    let e = read_table(&f, "time", &["a", "b"]).unwrap_err();
    assert_eq!((e.line, e.field.as_str()), (Some(12), "b"), "{e}");
    assert!(e.column.is_some(), "{e}");

    let f = d.join("no_header.csv");
    write_rows(&f, "time [s];a [g];c [g]\n", |_, t, a, b| {
        format!("{t:.4};{a:.6};{b:.6}\n")
    });
    let e = read_table(&f, "time", &["a", "b"]).unwrap_err();
    assert_eq!(e.line, Some(1), "{e}");
    assert!(e.message.contains("lacks [\"b\"]"), "{e}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn descriptor_errors_are_located() {
    let d = dir("desc");
    let good = std::fs::read_to_string(descriptor(&d, "x.csv", ("g", "g"))).unwrap();
    let cases = [
        (
            "cutoff_hz = 100.0",
            "cutoff_hz = -100.0",
            "acquisition.cutoff_hz",
            "positive",
        ),
        (
            "load_case = \"empty\"",
            "load_case = \"full\"",
            "load_case",
            "unknown load case",
        ),
        (
            "position_m = -2.0\ntime_s = 0.96",
            "position_m = -2.0\ntime_s = -0.5",
            "trigger.foil",
            "do not increase",
        ),
        (
            "simulated = \"acc_b_z\"\naxis = \"z\"",
            "simulated = \"acc_b_z\"\naxis = \"x\"",
            "channel[1].axis",
            "axis x",
        ),
        (
            "unit = \"g\"\n[[channel]]",
            "unit = \"gee\"\n[[channel]]",
            "channel[0].unit",
            "unknown unit",
        ),
        (
            "nominal_speed_kmh = 30.0",
            "speed_kmh = 30.0",
            "",
            "speed_kmh",
        ),
    ];
    for (from, to, field, msg) in cases {
        assert!(good.contains(from), "{from}");
        let text = good.replacen(from, to, 1);
        let p = d.join("bad.toml");
        std::fs::write(&p, &text).unwrap();
        let e = Descriptor::from_file(&p).unwrap_err();
        assert!(e.field.starts_with(field), "{field}: {e}");
        assert!(e.message.contains(msg), "{msg}: {e}");
        assert!(e.line.is_some(), "{e}");
        assert!(
            e.to_string().starts_with(&format!("{}:", p.display())),
            "{e}"
        );
    }
    std::fs::remove_dir_all(&d).ok();
}
