//! The obstacle passage found in the signals alone: synthetic recordings of a 3.3 m
//! wheelbase vehicle with a known passage time, noise, gravity, body motion and a speed
//! channel drifting 5 % over the run, at 10-60 km/h. The front axle's time must come
//! within 10 ms and the implied wheelbase within 3 %; with no passage in the signals the
//! search must fail with an error, not answer.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use towride_app::validate::descriptor::PassageSpec;
use towride_app::validate::passage::{axle_sets, detect, Track};
use towride_app::validate::speed::channel_stats;

const WHEELBASE_M: f64 = 3.3;
const RATE_HZ: f64 = 2000.0;

/// Uniform and Gaussian numbers from a small linear congruential generator (the test
/// must not depend on a random crate's stream).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn gauss(&mut self) -> f64 {
        (-2.0 * self.uniform().ln()).sqrt() * (2.0 * PI * self.uniform()).cos()
    }
}

/// A recording: time, channels by simulated name, measured speed [m/s].
struct Recording {
    t: Vec<f64>,
    channels: BTreeMap<String, Vec<f64>>,
    speed: Vec<f64>,
}

/// A wheel's response after it reaches the bump at tau = 0: an abrupt onset (the wheel
/// follows the bump's curvature at once) ringing at the wheel-hop frequency, decaying
/// with time constant `decay` [s].
fn wheel_event(tau: f64, amp: f64, phase: f64, decay: f64) -> f64 {
    if tau < 0.0 {
        return 0.0;
    }
    amp * (2.0 * PI * 12.0 * tau + PI / 4.0 + phase).sin() * (-tau / decay).exp()
}

/// An obstacle with a second event where the wheel leaves it: `length_m` after the
/// entry, its amplitude the entry's times `exit_gain[axle]` (front, rear).
#[derive(Clone, Copy)]
struct Exit {
    length_m: f64,
    exit_gain: [f64; 2],
}

/// The vehicle at `kmh` with its speed drifting by `drift` over the run; the front axle
/// reaches the bump at `t_front` [s]. `events`: put the passage in the signals.
fn recording(kmh: f64, drift: f64, t_front: f64, seed: u64, events: bool) -> Recording {
    recording_with(kmh, drift, t_front, seed, events, None)
}

/// [`recording`], the obstacle's exit a second event when `exit` is given (the ring
/// then dies faster, 30 ms, as a damped wheel hop does, so the two events stand apart).
fn recording_with(
    kmh: f64,
    drift: f64,
    t_front: f64,
    seed: u64,
    events: bool,
    exit: Option<Exit>,
) -> Recording {
    let v0 = kmh / 3.6;
    // Run long enough for the rear axle plus 1.5 s at the slowest speed.
    let dur = t_front + WHEELBASE_M / (v0 * (1.0 - drift.abs())) + 1.5;
    let n = (dur * RATE_HZ) as usize;
    let acc = drift * v0 / dur;
    let x = |t: f64| v0 * t + 0.5 * acc * t * t;
    // When position x is reached (the positive root).
    let t_at = |p: f64| {
        if acc.abs() < 1e-12 {
            p / v0
        } else {
            (-v0 + (v0 * v0 + 2.0 * acc * p).sqrt()) / acc
        }
    };
    let x_bump = x(t_front);
    let t_rear = t_at(x_bump + WHEELBASE_M);
    let decay = if exit.is_some() { 0.03 } else { 0.06 };
    let exit_at = |x_axle: f64| exit.map(|e| t_at(x_axle + e.length_m));
    let exits = [exit_at(x_bump), exit_at(x_bump + WHEELBASE_M)];
    let mut rng = Rng(seed);
    let t: Vec<f64> = (0..n).map(|k| k as f64 / RATE_HZ).collect();
    let mut channels = BTreeMap::new();
    for (i, (axle, tp)) in [("front", t_front), ("rear", t_rear)]
        .into_iter()
        .enumerate()
    {
        for (j, side) in ["left", "right"].into_iter().enumerate() {
            // Larger events at speed, the rear a little weaker; noise 0.3 m/s^2 RMS,
            // body bounce at 1.3 Hz and gravity on every channel.
            let amp = (2.0 + 0.6 * v0) * (1.0 - 0.15 * i as f64) * (1.0 + 0.1 * j as f64);
            let y: Vec<f64> = t
                .iter()
                .map(|&tk| {
                    let ev = if events {
                        let out = match (exits[i], exit) {
                            (Some(te), Some(e)) => {
                                wheel_event(tk - te, amp * e.exit_gain[i], 0.5, decay)
                            }
                            _ => 0.0,
                        };
                        wheel_event(tk - tp, amp, 0.3 * j as f64, decay) + out
                    } else {
                        0.0
                    };
                    9.81 + ev + 0.8 * (2.0 * PI * 1.3 * tk + i as f64).sin() + 0.3 * rng.gauss()
                })
                .collect();
            channels.insert(format!("acc_wheel_{axle}_{side}_z"), y);
        }
    }
    let speed = t
        .iter()
        .map(|&tk| v0 + acc * tk + 0.03 * rng.gauss())
        .collect();
    Recording { t, channels, speed }
}

#[test]
fn passage_and_wheelbase_from_the_signals_over_20_cases_at_10_to_60_kmh() {
    let mut worst = (0.0_f64, 0.0_f64);
    for case in 0..21 {
        let kmh = 10.0 + 2.5 * case as f64;
        let drift = if case % 2 == 0 { 0.05 } else { -0.05 };
        let t_front = 1.0 + 0.037 * case as f64;
        let rec = recording(kmh, drift, t_front, 1000 + case, true);
        let names: Vec<String> = rec.channels.keys().cloned().collect();
        let sets = axle_sets(&PassageSpec::default(), &names);
        assert_eq!((sets.front.len(), sets.rear.len()), (2, 2), "{sets:?}");
        let track = Track::from_speed(&rec.t, &rec.speed);
        let mut notes = Vec::new();
        // The model's wheelbase only places the search window: give a different one.
        let p = detect(
            &rec.t,
            &rec.channels,
            &sets,
            &track,
            (Some(3.1), None),
            None,
            &mut notes,
        )
        .unwrap_or_else(|e| panic!("{kmh} km/h: {e}"));
        let dt_front = p.front_onset_s - t_front;
        let wb = p
            .implied_wheelbase_m
            .unwrap_or_else(|| panic!("{kmh} km/h: no rear axle: {notes:?}"));
        let wb_err = wb / WHEELBASE_M - 1.0;
        assert!(
            dt_front.abs() < 0.010,
            "{kmh} km/h: front axle {dt_front:+.4} s off"
        );
        assert!(
            wb_err.abs() < 0.03,
            "{kmh} km/h: implied wheelbase {wb:.3} m"
        );
        worst = (worst.0.max(dt_front.abs()), worst.1.max(wb_err.abs()));
        // The speed channel's drift over the run is seen as put in.
        let (mean, _, drift_pct) = channel_stats(
            &rec.t,
            &rec.speed,
            p.front_onset_s - 0.25,
            p.front_onset_s + 2.0,
            &[],
        );
        assert!(
            (drift_pct - 100.0 * drift).abs() < 0.5,
            "{kmh} km/h: drift {drift_pct:.2} %"
        );
        assert!(
            (mean * 3.6 / kmh - 1.0).abs() < 0.06,
            "{kmh} km/h: mean {:.2} km/h",
            mean * 3.6
        );
    }
    eprintln!(
        "passage: worst front-axle error {:.2} ms, worst wheelbase error {:.2} %",
        worst.0 * 1e3,
        worst.1 * 100.0
    );
}

/// Issue 31 item 11: at 10 km/h a 0.5 m bump's entry and exit are two events 0.18 s
/// apart, and the larger one may be the exit on one axle and the entry on the other (a
/// synthetic bump_25mm run at 10 km/h: 1.926 m implied against 2.462 m). The passage
/// is the entry on both: the wheelbase within 1.5 % at 10, 20 and 50 km/h.
#[test]
fn an_obstacle_s_exit_is_not_taken_for_its_entry_at_low_speed() {
    let exit = Exit {
        length_m: 0.4,
        exit_gain: [1.15, 0.85],
    };
    for (case, kmh) in [10.0, 20.0, 50.0].into_iter().enumerate() {
        let t_front = 1.1;
        let rec = recording_with(kmh, 0.02, t_front, 500 + case as u64, true, Some(exit));
        let names: Vec<String> = rec.channels.keys().cloned().collect();
        let sets = axle_sets(&PassageSpec::default(), &names);
        let track = Track::from_speed(&rec.t, &rec.speed);
        let mut notes = Vec::new();
        let p = detect(
            &rec.t,
            &rec.channels,
            &sets,
            &track,
            (Some(WHEELBASE_M), None),
            None,
            &mut notes,
        )
        .unwrap_or_else(|e| panic!("{kmh} km/h: {e}"));
        let wb = p
            .implied_wheelbase_m
            .unwrap_or_else(|| panic!("{kmh} km/h: no rear axle: {notes:?}"));
        eprintln!(
            "{kmh} km/h: front onset {:+.1} ms, implied wheelbase {wb:.3} m",
            (p.front_onset_s - t_front) * 1e3
        );
        assert!(
            (p.front_onset_s - t_front).abs() < 0.010,
            "{kmh} km/h: front onset {:.4} s, the entry at {t_front} s",
            p.front_onset_s
        );
        assert!(
            (wb / WHEELBASE_M - 1.0).abs() < 0.015,
            "{kmh} km/h: implied wheelbase {wb:.3} m, the vehicle's {WHEELBASE_M} m"
        );
    }
}

#[test]
fn no_visible_passage_is_an_error_not_an_answer() {
    for (case, kmh) in [10.0, 35.0, 60.0].into_iter().enumerate() {
        let rec = recording(kmh, 0.05, 1.2, 77 + case as u64, false);
        let names: Vec<String> = rec.channels.keys().cloned().collect();
        let sets = axle_sets(&PassageSpec::default(), &names);
        let track = Track::from_speed(&rec.t, &rec.speed);
        let e = detect(
            &rec.t,
            &rec.channels,
            &sets,
            &track,
            (Some(3.3), None),
            None,
            &mut Vec::new(),
        )
        .map(|p| p.front_onset_s)
        .expect_err("noise alone must not give a passage")
        .to_string();
        assert!(
            e.contains("no obstacle passage visible") && e.contains("noise"),
            "{e}"
        );
    }
}

/// Issue 31 item 12: a logger's speed that falls to a quarter for 0.4 s while the car
/// keeps its speed is a dropout, found and left out of the mean; a real deceleration
/// of 3 m/s^2 over the same window is not.
#[test]
fn a_speed_dropout_is_found_and_left_out_and_a_deceleration_is_not() {
    use towride_app::validate::speed::{channel_stats, dropouts};
    let rate = 100.0;
    let t: Vec<f64> = (0..300).map(|k| k as f64 / rate).collect();
    let v0 = 11.1;
    // Speed sensor noise of +-0.05 m/s (a deterministic pattern).
    let noise = |k: usize| 0.05 * ((k as f64 * 1.7).sin());
    let mut v: Vec<f64> = (0..300).map(|k| v0 + noise(k)).collect();
    for (k, x) in v.iter_mut().enumerate() {
        if (120..160).contains(&k) {
            *x = 0.25 * v0;
        }
    }
    let d = dropouts(&t, &v, 0.0, 3.0);
    assert_eq!(d.len(), 1, "{d:?}");
    assert!(
        (d[0][0] - 1.20).abs() < 1e-9 && (d[0][1] - 1.59).abs() < 1e-9,
        "{d:?}"
    );
    let (mean, range, _) = channel_stats(&t, &v, 0.0, 3.0, &d);
    assert!((mean - v0).abs() < 0.01, "{mean}");
    assert!(range[0] > v0 - 0.1, "{range:?}");
    // Averaged in, the dropout would have cost 10 % of the speed.
    let (blind, _, _) = channel_stats(&t, &v, 0.0, 3.0, &[]);
    assert!(blind < 0.92 * v0, "{blind}");
    // Braking at 3 m/s^2 from 12 m/s: 9 m/s of change over the window, gradual.
    let braking: Vec<f64> = t.iter().map(|&ti| 12.0 - 3.0 * ti).collect();
    assert!(dropouts(&t, &braking, 0.0, 3.0).is_empty());
}
