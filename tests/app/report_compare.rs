//! `towride compare`: max, min, |peak| and RMS differences of two runs against their
//! closed forms, like compared with like,
//! runs on different sample grids, the files written, and a bad CSV named with its line.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use towride_app::report::compare::{compare, load, write};

fn run_dir(tag: &str, dt: f64, gain: f64) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("towride-compare-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut text = String::from("time [s],hitch_fx [N],speed [m/s]\n");
    let n = (1.0 / dt).round() as usize;
    for k in 0..=n {
        let t = k as f64 * dt;
        text.push_str(&format!("{t},{},{}\n", gain * (2.0 * PI * t).sin(), 10.0));
    }
    std::fs::write(dir.join("outputs.csv"), text).unwrap();
    dir
}

#[test]
fn differences_match_the_closed_form() {
    let a = run_dir("a", 1e-3, 1.0);
    // Another grid: the reference is interpolated at these samples.
    let b = run_dir("b", 5e-4, 1.1);
    let runs = vec![load(&a).unwrap(), load(&b).unwrap()];
    let mut c = compare(&runs).unwrap();
    assert_eq!(c.channels, ["hitch_fx", "speed"]);
    let d = &c.differences[0];
    assert_eq!((d.channel.as_str(), d.unit.as_str()), ("hitch_fx", "N"));
    // Maxima at t = 0.25 s on both grids: 1 and 1.1; minima at 0.75 s: -1 and -1.1.
    assert!((d.reference_max - 1.0).abs() < 1e-12 && (d.max - 1.1).abs() < 1e-12);
    assert!((d.reference_min + 1.0).abs() < 1e-12 && (d.min + 1.1).abs() < 1e-12);
    assert!((d.reference_abs_peak - 1.0).abs() < 1e-12 && (d.abs_peak - 1.1).abs() < 1e-12);
    assert!((d.max_difference - 0.1).abs() < 1e-12);
    assert!((d.min_difference + 0.1).abs() < 1e-12);
    assert!((d.abs_peak_difference - 0.1).abs() < 1e-12);
    // 0.1 sin over one period: RMS 0.1/sqrt(2) (the sum over 2001 samples of a whole
    // period carries one extra zero sample).
    let want = 0.1 / 2f64.sqrt() * (2000.0f64 / 2001.0).sqrt();
    assert!(
        (d.rms_difference / want - 1.0).abs() < 1e-4,
        "{} vs {want}",
        d.rms_difference
    );
    assert_eq!(c.differences[1].rms_difference, 0.0);
    let out = a.join("cmp");
    write(&runs, &mut c, &out, "png").unwrap();
    assert!(out.join("compare.png").exists());
    let html = std::fs::read_to_string(out.join("compare.html")).unwrap();
    assert!(!html.contains("src=") && html.contains("uPlot"));
    for d in [&a, &b] {
        std::fs::remove_dir_all(d).ok();
    }
}

/// A run whose larger magnitude is its minimum (-35.114) against a reference whose is
/// its maximum (30.936): signed peaks read "-35.114 vs 30.936, difference -66.05"; like
/// with like gives the max, min and |peak| differences.
#[test]
fn like_is_compared_with_like() {
    let dir = |tag: &str, up: f64, down: f64| {
        let dir =
            std::env::temp_dir().join(format!("towride-compare-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut text = String::from("time [s],acc_hitch_z [m/s^2]\n");
        for k in 0..=1000 {
            let t = k as f64 * 1e-3;
            let s = (2.0 * PI * t).sin();
            text.push_str(&format!(
                "{t},{}\n",
                if s > 0.0 { up * s } else { down * s }
            ));
        }
        std::fs::write(dir.join("outputs.csv"), text).unwrap();
        dir
    };
    let (a, b) = (dir("up", 30.936, 20.0), dir("down", 25.0, 35.114));
    let c = compare(&[load(&a).unwrap(), load(&b).unwrap()]).unwrap();
    let d = &c.differences[0];
    let close = |x: f64, y: f64| (x - y).abs() < 1e-9;
    assert!(
        close(d.reference_max, 30.936) && close(d.reference_min, -20.0),
        "{d:?}"
    );
    assert!(close(d.max, 25.0) && close(d.min, -35.114), "{d:?}");
    assert!(
        close(d.reference_abs_peak, 30.936) && close(d.abs_peak, 35.114),
        "{d:?}"
    );
    assert!(close(d.max_difference, -5.936), "{d:?}");
    assert!(close(d.min_difference, -15.114), "{d:?}");
    assert!(close(d.abs_peak_difference, 4.178), "{d:?}");
    for d in [&a, &b] {
        std::fs::remove_dir_all(d).ok();
    }
}

#[test]
fn a_bad_csv_is_named_with_its_line() {
    let a = run_dir("bad", 0.1, 1.0);
    let f = a.join("outputs.csv");
    let text = std::fs::read_to_string(&f)
        .unwrap()
        .replace("10\n", "ten\n");
    std::fs::write(&f, text).unwrap();
    let e = load(Path::new(&a)).unwrap_err().to_string();
    assert!(e.contains("outputs.csv:2"), "{e}");
    assert!(e.contains("speed") && e.contains("'ten'"), "{e}");
    std::fs::remove_dir_all(&a).ok();
}
