//! The combination's sway (snaking) mode: the decay rate and period `towride linear`
//! gives for the least damped loading (the legal-limit trailer with its payload over the
//! axle and spread along the box, 130 km/h) against the decay a time-domain run shows
//! after a small steering input (docs/manoeuvres.md, "Sway").

use std::path::PathBuf;

const TRAILER: &str = "vehicles/trailer/box_trailer.toml";

/// The least damped loading: nose load of the empty trailer only, payload yaw inertia
/// 450 kg m^2 (FILE:PATH=VALUE overrides).
fn loading(scene: &str) -> Vec<String> {
    vec![
        format!("{scene}:run.speed_km_h=130"),
        format!("{scene}:scene.load_case=\"legal_limit_557kg\""),
        format!("{TRAILER}:load_case[4].payload.cm_m=[-2.46,0.0,0.745]"),
        format!("{TRAILER}:load_case[4].payload.inertia_kg_m2=[42.7,450.0,450.0]"),
    ]
}

#[test]
fn the_sway_mode_decays_in_a_run_at_the_rate_the_linear_analysis_gives() {
    let dir = std::env::temp_dir().join(format!("towride_sway_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Linear: the default scene rolling at 130 km/h, the ramp far ahead.
    let sway = crate::sway_mode(&dir.join("linear"), &loading("scenes/default.toml"));
    let (sigma, hz) = (
        sway["real_1_per_s"].as_f64().unwrap(),
        sway["damped_hz"].as_f64().unwrap(),
    );
    // Damped well enough to measure over a few cycles, lightly enough to see them.
    assert!(
        (-0.6..-0.05).contains(&sigma),
        "the sway mode's real part: {sway}"
    );

    // Time domain: the lane-change scene's input scaled down 20 times (0.1 mm of rack),
    // so the sway stays small and linear while it grows.
    let text = std::fs::read_to_string(repo!("scenes/lane_change.toml")).unwrap();
    let scenes = std::fs::canonicalize(repo!("scenes")).unwrap();
    let mut small = text.replace("\"../", &format!("\"{}/../", scenes.display()));
    let start = small.find("value = [").unwrap() + "value = [".len();
    let end = start + small[start..].find(']').unwrap();
    let values: Vec<String> = small[start..end]
        .split(',')
        .map(|v| format!("{:.9}", v.trim().parse::<f64>().unwrap() / 20.0))
        .collect();
    small.replace_range(start..end, &values.join(", "));
    let file: PathBuf = dir.join("small_steer.toml");
    std::fs::write(&file, small).unwrap();
    let f = file.display().to_string();
    let mut args = vec![
        "run".to_string(),
        f.clone(),
        "--out".into(),
        dir.join("run").display().to_string(),
    ];
    for v in loading(&f)
        .into_iter()
        .chain([format!("{f}:run.duration_s=10")])
    {
        args.extend(["--set".into(), v]);
    }
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    crate::towride_ok(&a);
    let mut r = csv::Reader::from_path(dir.join("run/outputs.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let col = h
        .iter()
        .position(|c| c.starts_with("trailer_yaw_rate.z "))
        .unwrap();
    let rows: Vec<(f64, f64)> = r
        .records()
        .map(|x| {
            let x = x.unwrap();
            (x[0].parse().unwrap(), x[col].parse().unwrap())
        })
        .collect();
    // Positive peaks of the trailer's yaw rate after the input (it ends at 3 s).
    let peaks: Vec<(f64, f64)> = (1..rows.len() - 1)
        .filter(|&k| {
            rows[k].0 > 3.5
                && rows[k].1 > rows[k - 1].1
                && rows[k].1 >= rows[k + 1].1
                && rows[k].1 > 0.0
        })
        .map(|k| rows[k])
        .collect();
    assert!(peaks.len() >= 4, "{peaks:?}");
    let (a, b) = (peaks[0], peaks[peaks.len() - 1]);
    let cycles = (peaks.len() - 1) as f64;
    let period = (b.0 - a.0) / cycles;
    let rate = (b.1 / a.1).ln() / (b.0 - a.0);
    assert!(
        (period * hz - 1.0).abs() < 0.02,
        "period {period} s against {hz} Hz"
    );
    assert!(
        (rate / sigma - 1.0).abs() < 0.10,
        "decay {rate} against {sigma} 1/s"
    );
}
