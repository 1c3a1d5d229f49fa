//! `validate init` on a logger file whose sensors carry fixed offsets besides gravity and
//! one of which clips: the draft records each offset measured over the quiet part before
//! the passage (against the offsets written into the file), the clipping level as the
//! clipped sensor's range and the stated default for the others, and the run read with
//! the draft has every channel at zero before the passage.

use std::path::Path;

use towride_app::validate::csv_reader::read_measurement;
use towride_app::validate::init::{draft, map_columns, scene_sensors, sniff};
use towride_app::validate::offsets::DEFAULT_RANGE_G;
use towride_app::validate::Descriptor;

use crate::validate_logger::{dir, CORNERS, SIDES};

const SCENE: &str = repo!("scenes/default.toml");
const G: f64 = 9.80665;
const RATE_HZ: f64 = 5000.0;
/// The front wheels reach the obstacle here [s]; the rear ones 0.4 s later.
const PASSAGE_S: f64 = 1.0;
/// Where the FL wheel sensor clips [g].
const CLIP_G: f64 = 6.0;

/// The fixed offset of corner `c`'s sensor, sprung or not [g].
fn bias(c: usize, unsprung: bool) -> f64 {
    [0.013, -0.021, 0.034, -0.008][c] + if unsprung { 0.05 } else { 0.0 }
}

/// A damped ring from `t0`: the axle's event.
fn ring(t: f64, t0: f64, f: f64, amp: f64) -> f64 {
    if t < t0 {
        return 0.0;
    }
    let tau = t - t0;
    amp * (-4.0 * tau).exp() * (2.0 * std::f64::consts::PI * f * tau).sin()
}

#[test]
fn offsets_before_the_passage_and_ranges_are_proposed() {
    let d = dir("init-offsets");
    let rows = 15_000;
    let mut text = String::from("Time [s]\tVehicle speed [km/h]");
    for part in ["Sprung", "Unsprung"] {
        for c in CORNERS {
            text.push_str(&format!("\t{c} {part} acceleration [gn]"));
        }
    }
    text.push('\n');
    // White noise of 2 mg from a linear congruential generator (Knuth's MMIX constants).
    let mut state: u64 = 42;
    let mut noise = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.002 * 12f64.sqrt()
    };
    for k in 0..rows {
        let t = k as f64 / RATE_HZ;
        let mut row = format!("{t:.6}\t20.0");
        for unsprung in [false, true] {
            for c in 0..4 {
                let t0 = PASSAGE_S + if c >= 2 { 0.4 } else { 0.0 };
                let (f, amp) = if unsprung { (12.0, 3.0) } else { (1.3, 0.2) };
                let amp = if unsprung && c == 0 { 9.0 } else { amp };
                let mut r = 1.0 + bias(c, unsprung) + ring(t, t0, f, amp) + noise();
                if unsprung && c == 0 {
                    r = r.clamp(-CLIP_G, CLIP_G);
                }
                row.push_str(&format!("\t{r:.7}"));
            }
        }
        text.push_str(&row);
        text.push('\n');
    }
    let csv = d.join("offsets.csv");
    std::fs::write(&csv, text).unwrap();
    let mut s = sniff(&csv, None).unwrap();
    let [a, b] = s.quiet_window_s.expect("a quiet window");
    assert!(a == 0.0 && b > 0.8 && b < PASSAGE_S, "{a} .. {b}");
    map_columns(&mut s, &scene_sensors(Path::new(SCENE)).unwrap());
    let out = d.join("offsets.toml");
    let draft_text = draft(&s, Path::new(SCENE), &out);
    std::fs::write(&out, &draft_text).unwrap();
    for (c, side) in CORNERS.iter().zip(SIDES).enumerate() {
        for (part, what, unsprung) in [("Sprung", "body", false), ("Unsprung", "wheel", true)] {
            let head = format!(
                "column = \"{} {part} acceleration\"\nsimulated = \"acc_{what}_{}_z\"\naxis = \"z\"\nremove_gravity = true",
                side.0, side.1
            );
            let at = draft_text
                .find(&head)
                .unwrap_or_else(|| panic!("{head}\n{draft_text}"));
            let block = &draft_text[at + head.len()..];
            let value = |key: &str| -> f64 {
                let l = block.lines().find(|l| l.starts_with(key)).unwrap();
                l[key.len()..]
                    .split('#')
                    .next()
                    .unwrap()
                    .trim()
                    .parse()
                    .unwrap()
            };
            let off = value("offset_g = ");
            assert!((off - bias(c, unsprung)).abs() < 2e-4, "{head}: {off}");
            let range = value("range_g = ");
            let want = if unsprung && c == 0 {
                CLIP_G
            } else {
                DEFAULT_RANGE_G
            };
            assert_eq!(range, want, "{head}");
        }
    }
    // Read with the draft: gravity and offsets gone before the passage.
    let m = read_measurement(&Descriptor::from_file(&out).unwrap()).unwrap();
    let quiet: Vec<usize> = (0..m.time_s.len()).filter(|&k| m.time_s[k] < 0.9).collect();
    for (name, v) in &m.channels {
        let mean = quiet.iter().map(|&k| v[k]).sum::<f64>() / quiet.len() as f64;
        assert!(
            mean.abs() < 2e-4 * G,
            "{name}: {mean} m/s^2 before the passage"
        );
    }
    assert!(m.clipped_samples("acc_wheel_front_left_z") > 10);
}
