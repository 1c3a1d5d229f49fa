//! `validate init` on logger exports: the drafted descriptor reads without edits when the
//! column names follow the patterns, and a whole run (no trigger, quantised 5 kHz clock,
//! gravity, a drifting speed channel) validates from it with the passage found in the
//! signals.

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::Path;

use towride_app::validate::csv_reader::read_measurement;
use towride_app::validate::folder::run_json;
use towride_app::validate::init::{draft, map_columns, scene_sensors, sniff};
use towride_app::validate::timebase::TimeBaseKind;
use towride_app::validate::{
    validate_folder, validate_run, write_summary, Descriptor, Options, SimChannels, Simulator,
};

use crate::validate_logger::{dir, Clock, Logger, CORNERS, SIDES};

const SCENE: &str = repo!("scenes/default.toml");
const WHEELBASE_M: f64 = 3.3;
const G: f64 = 9.80665;

/// Sniffs the file of `log`, drafts its descriptor and reads the run with it.
fn init_and_read(
    log: &Logger,
    name: &str,
    rate: Option<f64>,
) -> towride_app::validate::csv_reader::Measurement {
    let d = dir(&format!("init-{name}"));
    let csv = d.join(format!("{name}.csv"));
    let mut text = log.text();
    if log.clock == Clock::None && rate.is_none() {
        text = format!("# Sample rate: {} Hz\n{text}", log.rate_hz);
    }
    std::fs::write(&csv, text).unwrap();
    let mut s = sniff(&csv, rate).unwrap();
    assert_eq!(s.rows, log.rows, "{name}");
    assert!(
        (s.time_base.rate_hz / log.rate_hz - 1.0).abs() < 1e-12,
        "{name}"
    );
    map_columns(&mut s, &scene_sensors(Path::new(SCENE)).unwrap());
    let out = d.join(format!("{name}.toml"));
    let text = draft(&s, Path::new(SCENE), &out);
    std::fs::write(&out, &text).unwrap();
    for (c, side) in CORNERS.iter().zip(SIDES) {
        for (part, what) in [("Sprung", "body"), ("Unsprung", "wheel")] {
            let want = format!("column = \"{c} {part} acceleration\"\nsimulated = \"acc_{what}_{side}_z\"\naxis = \"z\"\nremove_gravity = true");
            assert!(text.contains(&want), "{name}: no {want}\n{text}");
        }
    }
    assert!(text.contains("column = \"Vehicle speed\""), "{text}");
    assert!(
        text.contains("#   RL air spring pressure [bar]: not an acceleration"),
        "{text}"
    );
    let m =
        read_measurement(&Descriptor::from_file(&out).unwrap_or_else(|e| panic!("{e}\n{text}")))
            .unwrap();
    assert_eq!(m.time_s.len(), log.rows);
    // Gravity is gone: the channels' means are the signal's (zero over whole periods).
    for (c, v) in &m.channels {
        if log.clip_g.is_some() && c == "acc_wheel_front_left_z" {
            continue; // the clamp shifts its mean
        }
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        assert!(mean.abs() < 0.6, "{name}: mean {mean}");
    }
    m
}

#[test]
fn drafts_read_without_edits_for_every_layout() {
    init_and_read(&Logger::default(), "tab5k", None);
    let comma = Logger {
        sep: ',',
        units_row: false,
        rate_hz: 1000.0,
        rows: 3000,
        clock: Clock::Exact,
        acc_unit: "m/s^2",
        speed_unit: ("m/s", 1.0),
        ..Logger::default()
    };
    init_and_read(&comma, "comma1k", None);
    let semi = Logger {
        sep: ';',
        decimal_comma: true,
        rate_hz: 2000.0,
        rows: 4000,
        clock: Clock::None,
        acc_unit: "g",
        speed_unit: ("mph", 3600.0 / 1609.344),
        ..Logger::default()
    };
    let m = init_and_read(&semi, "semi_comment_rate", None);
    assert_eq!(m.time_base.kind, TimeBaseKind::Declared);
    init_and_read(&semi, "semi_given_rate", Some(2000.0));
    let clipped = Logger {
        clip_g: Some(2.0),
        rows: 5000,
        ..Logger::default()
    };
    let m = init_and_read(&clipped, "clipped", None);
    assert_eq!(
        m.clipped_samples("acc_wheel_front_left_z"),
        clipped.clipped_rows()
    );
}

/// A van with a 3.3 m wheelbase in closed form: every wheel rings at 12 Hz and every
/// body corner at 1.4 Hz from when its axle reaches a 0.5 m obstacle, less the same from
/// when it leaves it; amplitudes grow with speed.
struct Van;

fn damped(tau: f64, f: f64, zeta: f64) -> f64 {
    if tau <= 0.0 {
        return 0.0;
    }
    let w = 2.0 * PI * f;
    (-zeta * w * tau).exp() * (w * (1.0 - zeta * zeta).sqrt() * tau).sin()
}

/// Channel `side` (`front_left`, ...) `what` (`wheel`, `body`) at `t` after the front
/// axle reached the obstacle start, at `pos(t)` metres travelled since.
fn response(what: &str, side: &str, v: f64, dist_m: f64) -> f64 {
    let lag = if side.starts_with("rear") {
        WHEELBASE_M
    } else {
        0.0
    };
    let (f, z, a) = if what == "wheel" {
        (12.0, 0.3, 3.0)
    } else {
        (1.4, 0.3, 0.5)
    };
    // Time since the axle reached the start and the end of the obstacle at speed v.
    let (t_in, t_out) = ((dist_m - lag) / v, (dist_m - lag - 0.5) / v);
    a * v * (damped(t_in, f, z) - damped(t_out, f, z))
}

impl Simulator for Van {
    fn simulate(
        &self,
        _scene: &Path,
        v: f64,
        _load: &str,
    ) -> Result<SimChannels, towride_app::Error> {
        let (rate, t_obs) = (2000.0, 0.8);
        let n = ((t_obs + (WHEELBASE_M + 0.5) / v + 2.0) * rate) as usize;
        let time: Vec<f64> = (0..n).map(|k| k as f64 / rate).collect();
        let mut channels = BTreeMap::new();
        for side in SIDES {
            for what in ["wheel", "body"] {
                let y = time
                    .iter()
                    .map(|t| response(what, side, v, v * (t - t_obs)))
                    .collect();
                channels.insert(format!("acc_{what}_{side}_z"), y);
            }
        }
        Ok(SimChannels {
            time_s: time,
            channels,
            obstacle_time_s: t_obs,
        })
    }

    fn axles(&self, _scene: &Path) -> (Option<f64>, Option<f64>) {
        (Some(WHEELBASE_M), None)
    }
}

/// A 5 kHz logger export of the van at `kmh` (drifting `drift` over 4 s), stamped to
/// 1 ms, tab separated, gn with gravity; the front axle reaches the obstacle at
/// `t_front` on the logger's clock (which starts at 12.3234 s). Returns the file, the
/// start speed [m/s] and the acceleration [m/s^2].
fn van_recording(
    d: &Path,
    name: &str,
    kmh: f64,
    drift: f64,
    t_front: f64,
) -> (std::path::PathBuf, f64, f64) {
    let (rate, t0, v0) = (5000.0, 12.3234, kmh / 3.6);
    let n = 20_000;
    let acc = drift * v0 * rate / n as f64;
    let x = |t: f64| v0 * (t - t0) + 0.5 * acc * (t - t0).powi(2);
    let x_front = x(t_front);
    let mut seed = 7u64;
    let mut noise = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.02
    };
    let mut text = String::from("# towride test export, van bump run 3\nTime\tVehicle speed");
    for part in ["Sprung", "Unsprung"] {
        for c in CORNERS {
            text.push_str(&format!("\t{c} {part} acceleration"));
        }
    }
    text.push_str("\ns\tkm/h\tgn\tgn\tgn\tgn\tgn\tgn\tgn\tgn\n");
    for k in 0..n {
        let t = t0 + k as f64 / rate;
        let v = v0 + acc * (t - t0);
        let mut row = format!("{:.3}\t{:.3}", (t * 1e3).round() / 1e3, v * 3.6);
        for what in ["body", "wheel"] {
            for side in SIDES {
                let a = response(what, side, v, x(t) - x_front);
                row.push_str(&format!("\t{:.5}", 1.0 + a / G + noise()));
            }
        }
        text.push_str(&row);
        text.push('\n');
    }
    let csv = d.join(format!("{name}.csv"));
    std::fs::write(&csv, text).unwrap();
    let mut s = sniff(&csv, None).unwrap();
    map_columns(&mut s, &scene_sensors(Path::new(SCENE)).unwrap());
    let out = d.join(format!("{name}.toml"));
    std::fs::write(&out, draft(&s, Path::new(SCENE), &out)).unwrap();
    (out, v0, acc)
}

#[test]
fn a_run_without_trigger_validates_from_its_draft() {
    // 35 km/h drifting +5 % over 4 s; the front axle reaches the obstacle 1.8 s in.
    let (t0, t_front) = (12.3234, 14.1234);
    let d = dir("init-run");
    let (out, v0, acc) = van_recording(&d, "van_bump", 35.0, 0.05, t_front);
    let x_front = v0 * (t_front - t0) + 0.5 * acc * (t_front - t0).powi(2);
    let r = validate_run(&out, &Van, &Options::default()).unwrap();
    let j = run_json(&r);
    assert_eq!(j["speed_source"], "channel");
    assert_eq!(j["time_base"], "reconstructed");
    assert_eq!(j["sample_rate_hz"], 5000.0);
    // The speed over the passage, against the drifting channel's true value there.
    let v_pass = v0 + acc * (t_front + 0.3 - t0);
    let kmh = j["speed_kmh"].as_f64().unwrap();
    assert!(
        (kmh / (v_pass * 3.6) - 1.0).abs() < 0.01,
        "{kmh} km/h vs {}",
        v_pass * 3.6
    );
    let t_obs = j["obstacle_time_s"].as_f64().unwrap();
    assert!(
        (t_obs - t_front).abs() < 0.010,
        "obstacle at {t_obs} s, truly {t_front} s"
    );
    let wb = j["implied_wheelbase_m"].as_f64().unwrap();
    assert!((wb / WHEELBASE_M - 1.0).abs() < 0.03, "{wb} m");
    let rear = j["rear_axle_time_s"].as_f64().unwrap();
    let t_rear = t0 + ((-v0 + (v0 * v0 + 2.0 * acc * (x_front + WHEELBASE_M)).sqrt()) / acc);
    assert!(
        (rear - t_rear).abs() < 0.015,
        "rear axle at {rear} s, truly {t_rear} s"
    );
    for c in j["channels"].as_array().unwrap() {
        assert_eq!(c["clipped_samples"], 0, "{c}");
    }
    let rating = j["mean_rating_corrected"].as_f64().unwrap();
    assert!(
        rating > 0.9,
        "corrected rating {rating}: {}",
        serde_json::to_string_pretty(&j).unwrap()
    );
}

#[test]
fn a_folder_of_runs_gives_peak_trends_and_wheel_hop_frequencies() {
    let d = dir("init-folder");
    let files: Vec<_> = [20.0, 30.0, 45.0]
        .iter()
        .map(|&kmh| van_recording(&d, &format!("van_{kmh:.0}"), kmh, 0.0, 13.9).0)
        .collect();
    let res = validate_folder(&files, &Van, &Options::default(), &|_, _| {});
    assert!(res.failures.is_empty(), "{:?}", res.failures);
    write_summary(&res, &d).unwrap();
    let text = std::fs::read_to_string(d.join("trends.csv")).unwrap();
    let html = std::fs::read_to_string(d.join("trends.html")).unwrap();
    assert!(html.contains("<svg") && html.contains("acc_wheel_front_left_z"));
    let mut rows = 0;
    for line in text.lines().skip(1) {
        let c: Vec<&str> = line.split(',').collect();
        if !c[0].starts_with("acc_wheel") {
            continue;
        }
        rows += 1;
        // Measured and simulated wheel-hop frequencies agree. The closed form's entry
        // and exit pulses, 0.5 m / v apart, cancel at v / 0.5 m (11 Hz at 20 km/h) and
        // pull the peak down at low speed; at 45 km/h (25 Hz) the ring's 11.45 Hz
        // (12 Hz, damping 0.3) shows.
        let (fm, fs): (f64, f64) = (c[7].parse().unwrap(), c[8].parse().unwrap());
        assert!((fm - fs).abs() < 1.0, "{line}");
        if c[1] == "van_45" {
            assert!((fm - 12.0 * (1.0f64 - 0.09).sqrt()).abs() < 1.5, "{line}");
        }
        // Peaks grow with speed (amplitude proportional to it) and agree.
        let (m, s): (f64, f64) = (c[3].parse().unwrap(), c[4].parse().unwrap());
        assert!((m / s - 1.0).abs() < 0.1, "{line}");
    }
    assert_eq!(rows, 12);
}

/// Issue 31 item 11: the column drafted as `[speed] column` is mapped; the draft's list
/// of unmapped columns named it anyway ("Vehicle speed [km/h]: vehicle speed"). A second
/// speed column is unmapped, saying which one is the speed channel.
#[test]
fn the_speed_column_is_mapped_not_listed_as_unmapped() {
    let d = dir("init-speed");
    let csv = d.join("speeds.csv");
    let mut text = String::from(
        "time [s],FL Unsprung acceleration [g],Vehicle speed [km/h],GPS speed [km/h],RL air spring pressure [bar]\n",
    );
    for k in 0..200 {
        let t = k as f64 * 0.001;
        let _ = std::fmt::Write::write_fmt(
            &mut text,
            format_args!("{t:.3},{:.4},30.0,30.1,5.2\n", 1.0 + 0.1 * (40.0 * t).sin()),
        );
    }
    std::fs::write(&csv, text).unwrap();
    let mut s = sniff(&csv, None).unwrap();
    map_columns(&mut s, &scene_sensors(Path::new(SCENE)).unwrap());
    let draft = draft(&s, Path::new(SCENE), &d.join("speeds.toml"));
    assert!(draft.contains("[speed]") && draft.contains("column = \"Vehicle speed\""));
    let unmapped = draft
        .split("# Columns not mapped onto the scene's channels:")
        .nth(1)
        .expect("the pressure and the second speed are unmapped");
    let listed: Vec<&str> = unmapped
        .lines()
        .filter_map(|l| l.strip_prefix("#   "))
        .collect();
    assert_eq!(listed.len(), 2, "{listed:?}");
    assert!(listed[0].starts_with("GPS speed [km/h]: ") && listed[0].contains("`Vehicle speed`"));
    assert!(listed[1].starts_with("RL air spring pressure [bar]: not an acceleration"));
    // The sniff as `validate init --json` prints it: the speed column has no reason to be
    // unmapped.
    let j = serde_json::to_value(&s).unwrap();
    let speed = j["columns"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "Vehicle speed")
        .unwrap();
    assert!(speed["unmapped"].is_null(), "{speed}");
}
