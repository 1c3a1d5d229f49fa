//! Synthetic runs with a known trigger delay (37 ms), speedometer error (+3 %), gain error
//! (+5 %) and noise: validation must recover the delay within 1 ms and the speed within
//! 0.3 %, rate the corrected comparison close to 1, and the uncorrected one clearly lower.

use std::path::PathBuf;

use crate::validate_sim::Analytic;
use towride_app::validate::synth::{make_synthetic, SensorModel, SynthRun, TriggerLayout};
use towride_app::validate::{validate_run, Options};

fn tmp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("towride-{name}-{}", std::process::id()))
}

#[test]
fn injected_errors_are_recovered() {
    let dir = tmp("recovery");
    let sim = Analytic::default();
    let sensor = SensorModel::default();
    // The sensor model's documented values (docs/validation.md), spelled out here rather than trusted from the defaults.
    let (delay, speed_err, gain_err) = (0.037, 0.03, 0.05);
    let sensor = SensorModel {
        trigger_delay_s: delay,
        speed_error_pct: speed_err * 100.0,
        gain_error_pct: gain_err * 100.0,
        noise_rms_mps2: 0.05,
        ..sensor
    };
    let mut worst = (0.0_f64, 0.0_f64, 1.0_f64, 0.0_f64);
    for (i, kmh) in [10.0, 20.0, 40.0, 60.0].into_iter().enumerate() {
        let run = SynthRun {
            name: format!("run_{kmh}"),
            scene: PathBuf::from(repo!("roads/bump_25mm.toml")),
            obstacle: "bump_25mm".into(),
            nominal_speed_kmh: kmh,
            load_case: "200kg_over_axle".into(),
            truth: Vec::new(),
        };
        let s = SensorModel {
            seed: 11 + i as u64,
            ..sensor.clone()
        };
        let desc = make_synthetic(&sim, &run, &s, &TriggerLayout::default(), &dir).unwrap();
        let r = validate_run(&desc, &sim, &Options::default()).unwrap();
        let c = r.corrected.as_ref().unwrap();
        let v_true = kmh / 3.6 / (1.0 + speed_err);
        let delay_err = (c.shift_s - delay).abs();
        let speed_rel = (c.speed_mps / v_true - 1.0).abs();
        let (rc, ru) = (c.mean_rating, r.uncorrected.mean_rating);
        eprintln!(
            "{kmh} km/h: shift {:.3} ms (error {:.3} ms), speed error {:.4} %, rating corrected {rc:.4}, uncorrected {ru:.4}, gain ratios {:?}",
            c.shift_s * 1e3,
            delay_err * 1e3,
            speed_rel * 100.0,
            c.channels.iter().map(|f| (f.gain_ratio * 1e4).round() / 1e4).collect::<Vec<_>>()
        );
        assert!(delay_err < 1e-3, "{kmh} km/h: delay error {delay_err} s");
        assert!(speed_rel < 3e-3, "{kmh} km/h: speed error {speed_rel}");
        assert!(rc > 0.9, "{kmh} km/h: corrected rating {rc}");
        // With the photocell 10 m before the obstacle, a speedometer reading 3 % high
        // places the obstacle early by 3 % of the approach time (28 ms at 40 km/h), which
        // the 37 ms delay nearly cancels near 40 km/h: there the drop is small by physics.
        let margin = if kmh == 40.0 { 0.02 } else { 0.1 };
        assert!(
            ru < rc - margin,
            "{kmh} km/h: uncorrected {ru} vs corrected {rc}"
        );
        for f in &c.channels {
            assert!(
                (f.gain_ratio - (1.0 + gain_err)).abs() < 0.01,
                "{}: gain ratio {}",
                f.channel,
                f.gain_ratio
            );
            assert!(f.rating.overall > 0.75, "{}: {:?}", f.channel, f.rating);
        }
        worst = (
            worst.0.max(delay_err),
            worst.1.max(speed_rel),
            worst.2.min(rc),
            worst.3.max(ru),
        );
    }
    eprintln!(
        "worst: delay error {:.3} ms, speed error {:.4} %, lowest corrected rating {:.4}, highest uncorrected {:.4}",
        worst.0 * 1e3,
        worst.1 * 100.0,
        worst.2,
        worst.3
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn no_errors_no_shift() {
    // Without injected errors the shift and the speed error vanish (to the foil jitter).
    let dir = tmp("clean");
    let sim = Analytic::default();
    let s = SensorModel {
        trigger_delay_s: 0.0,
        speed_error_pct: 0.0,
        gain_error_pct: 0.0,
        noise_rms_mps2: 0.0,
        foil_jitter_s: 0.0,
        ..SensorModel::default()
    };
    let run = SynthRun {
        name: "clean".into(),
        scene: PathBuf::from(repo!("roads/bump_25mm.toml")),
        obstacle: "bump_25mm".into(),
        nominal_speed_kmh: 30.0,
        load_case: "empty".into(),
        truth: Vec::new(),
    };
    let desc = make_synthetic(&sim, &run, &s, &TriggerLayout::default(), &dir).unwrap();
    let r = validate_run(&desc, &sim, &Options::default()).unwrap();
    let c = r.corrected.as_ref().unwrap();
    eprintln!(
        "clean: shift {:.4} ms, rating {:.5}",
        c.shift_s * 1e3,
        c.mean_rating
    );
    assert!(c.shift_s.abs() < 2e-4, "shift {}", c.shift_s);
    assert!((c.speed_mps * 3.6 / 30.0 - 1.0).abs() < 1e-6);
    assert!(c.mean_rating > 0.99, "{}", c.mean_rating);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn gravity_offset_is_zeroed_when_asked() {
    let dir = tmp("offset");
    let sim = Analytic::default();
    let run = SynthRun {
        name: "offset".into(),
        scene: PathBuf::from(repo!("roads/bump_25mm.toml")),
        obstacle: "bump_25mm".into(),
        nominal_speed_kmh: 20.0,
        load_case: "empty".into(),
        truth: Vec::new(),
    };
    let desc = make_synthetic(
        &sim,
        &run,
        &SensorModel::default(),
        &TriggerLayout::default(),
        &dir,
    )
    .unwrap();
    let rate = |d: &std::path::Path| {
        validate_run(d, &sim, &Options::default())
            .unwrap()
            .corrected
            .unwrap()
    };
    let before = rate(&desc);
    // A DC accelerometer reads +1 g at rest on every channel.
    let csv = dir.join("offset.csv");
    let text: Vec<String> = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .map(|l| {
            if l.starts_with('#') || l.starts_with("time") {
                return l.to_string();
            }
            let v: Vec<String> = l
                .split(',')
                .enumerate()
                .map(|(i, x)| {
                    if i == 0 {
                        x.to_string()
                    } else {
                        format!("{:.6}", x.parse::<f64>().unwrap() + 9.80665)
                    }
                })
                .collect();
            v.join(",")
        })
        .collect();
    std::fs::write(&csv, text.join("\n")).unwrap();
    let offset = rate(&desc);
    let toml = std::fs::read_to_string(&desc)
        .unwrap()
        .replace("gain = 1.0\n", "gain = 1.0\nzero_before_obstacle = true\n");
    std::fs::write(&desc, toml).unwrap();
    let zeroed = rate(&desc);
    eprintln!(
        "rating without offset {:.4}, with 1 g offset {:.4}, zeroed {:.4}",
        before.mean_rating, offset.mean_rating, zeroed.mean_rating
    );
    assert!(offset.mean_rating < before.mean_rating - 0.2);
    assert!((zeroed.mean_rating - before.mean_rating).abs() < 0.01);
    assert!((zeroed.shift_s - before.shift_s).abs() < 2e-4);
    std::fs::remove_dir_all(&dir).ok();
}
