//! `towride compare`: peak and RMS differences of two runs against their closed forms,
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
    let mut c = compare(&runs);
    assert_eq!(c.channels, ["hitch_fx", "speed"]);
    let d = &c.differences[0];
    assert_eq!((d.channel.as_str(), d.unit.as_str()), ("hitch_fx", "N"));
    // Peaks at t = 0.25 s on both grids: 1 and 1.1.
    assert!((d.reference_peak - 1.0).abs() < 1e-12 && (d.peak - 1.1).abs() < 1e-12);
    assert!((d.peak_difference - 0.1).abs() < 1e-12);
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
