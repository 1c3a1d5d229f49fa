//! Logger exports as they come (tab, comma or semicolon separators, a comment line, a
//! units row, `gn`, time columns quantised to 1 ms at 5 kHz, no time column, gravity
//! offsets, a drifting speed channel, clipped channels) read exactly: sample count and
//! rate, SI values against the signal written, every repair listed.

use std::path::{Path, PathBuf};

use towride_app::validate::csv_reader::read_measurement;
use towride_app::validate::timebase::TimeBaseKind;
use towride_app::validate::Descriptor;

const G: f64 = 9.80665;

pub(crate) fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride-vlog-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// How the logger writes time.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Clock {
    /// Exact times, 6 decimals.
    Exact,
    /// Rounded to 1 ms.
    Millis,
    /// No time column.
    None,
}

/// A logger export in the style of a speed-bump test drive.
#[derive(Clone)]
pub(crate) struct Logger {
    pub sep: char,
    pub decimal_comma: bool,
    pub rate_hz: f64,
    pub rows: usize,
    pub clock: Clock,
    /// First row's time [s].
    pub t0: f64,
    /// Units row (else units in the header as `name [unit]`).
    pub units_row: bool,
    /// Acceleration unit written.
    pub acc_unit: &'static str,
    /// Speed unit written and its factor from m/s.
    pub speed_unit: (&'static str, f64),
    /// Speed at the start [m/s] and its change over the run [share].
    pub speed: (f64, f64),
    /// Clamp the FL unsprung channel at this reading [g].
    pub clip_g: Option<f64>,
}

impl Default for Logger {
    fn default() -> Self {
        Logger {
            sep: '\t',
            decimal_comma: false,
            rate_hz: 5000.0,
            rows: 10_000,
            clock: Clock::Millis,
            t0: 12.3456,
            units_row: true,
            acc_unit: "gn",
            speed_unit: ("km/h", 3.6),
            speed: (30.0 / 3.6, 0.05),
            clip_g: None,
        }
    }
}

pub(crate) const CORNERS: [&str; 4] = ["FL", "FR", "RL", "RR"];
/// The scene's sensor of each corner.
pub(crate) const SIDES: [&str; 4] = ["front_left", "front_right", "rear_left", "rear_right"];

impl Logger {
    /// Speed at row k [m/s]: a straight-line drift.
    pub fn speed_at(&self, k: usize) -> f64 {
        self.speed.0 * (1.0 + self.speed.1 * k as f64 / (self.rows - 1) as f64)
    }

    /// Kinematic vertical acceleration [m/s^2] of corner `c`, sprung or not, at row k.
    pub fn acc(&self, c: usize, unsprung: bool, k: usize) -> f64 {
        let t = k as f64 / self.rate_hz;
        let (f, a) = if unsprung { (12.0, 15.0) } else { (1.3, 1.5) };
        a * (2.0 * std::f64::consts::PI * f * t + c as f64).sin()
    }

    /// The reading of an accelerometer on z in g: +1 g at rest, clamped where asked.
    pub fn reading_g(&self, c: usize, unsprung: bool, k: usize) -> f64 {
        let r = 1.0 + self.acc(c, unsprung, k) / G;
        match self.clip_g {
            Some(lim) if c == 0 && unsprung => r.clamp(-lim, lim),
            _ => r,
        }
    }

    /// Rows of the FL unsprung channel at the clamp.
    pub fn clipped_rows(&self) -> usize {
        (0..self.rows)
            .filter(|&k| {
                self.clip_g
                    .is_some_and(|l| (1.0 + self.acc(0, true, k) / G).abs() >= l)
            })
            .count()
    }

    /// The file's text.
    pub fn text(&self) -> String {
        let s = self.sep.to_string();
        let mut names: Vec<String> = Vec::new();
        let mut units: Vec<&str> = Vec::new();
        if self.clock != Clock::None {
            names.push("Time".into());
            units.push("s");
        }
        names.push("Vehicle speed".into());
        units.push(self.speed_unit.0);
        for part in ["Sprung", "Unsprung"] {
            for c in CORNERS {
                names.push(format!("{c} {part} acceleration"));
                units.push(self.acc_unit);
            }
        }
        names.extend(["RL air spring pressure".into(), "IMU yaw rate".into()]);
        units.extend(["bar", "deg/s"]);
        let mut out =
            String::from("# towride test export, speed bump run 7, logger firmware 2.1\n");
        if self.units_row {
            out.push_str(&names.join(&s));
            out.push('\n');
            out.push_str(&units.join(&s));
        } else {
            let h: Vec<String> = names
                .iter()
                .zip(&units)
                .map(|(n, u)| format!("{n} [{u}]"))
                .collect();
            out.push_str(&h.join(&s));
        }
        out.push('\n');
        let scale = if self.acc_unit == "m/s^2" { G } else { 1.0 };
        for k in 0..self.rows {
            let t = self.t0 + k as f64 / self.rate_hz;
            let mut row: Vec<String> = Vec::new();
            match self.clock {
                Clock::Exact => row.push(format!("{t:.6}")),
                Clock::Millis => row.push(format!("{:.3}", (t * 1e3).round() / 1e3)),
                Clock::None => {}
            }
            row.push(format!("{:.5}", self.speed_at(k) * self.speed_unit.1));
            for unsprung in [false, true] {
                for c in 0..4 {
                    row.push(format!("{:.7}", self.reading_g(c, unsprung, k) * scale));
                }
            }
            row.push(format!("{:.3}", 2.4 + 0.1 * (k as f64 * 0.01).sin()));
            row.push(format!("{:.3}", 0.2 * (k as f64 * 0.003).cos()));
            let mut line = row.join(&s);
            if self.decimal_comma {
                line = line.replace('.', ",");
            }
            out.push_str(&line);
            out.push('\n');
        }
        out
    }

    /// Writes the file and a descriptor naming its columns; `range_g` on FL unsprung.
    pub fn write(&self, d: &Path, name: &str, range_g: Option<f64>) -> PathBuf {
        let csv = format!("{name}.csv");
        std::fs::write(d.join(&csv), self.text()).unwrap();
        let mut t = format!(
            "scene = \"{}\"\ndata = \"{csv}\"\n[acquisition]\nfilter = \"butterworth\"\norder = 4\ncutoff_hz = 100.0\n\
             [speed]\ncolumn = \"Vehicle speed\"\n",
            repo!("scenes/default.toml")
        );
        if self.clock == Clock::None {
            t = format!("sample_rate_hz = {}\n{t}", self.rate_hz);
        } else {
            t = format!("time_column = \"Time\"\n{t}");
        }
        for (part, what) in [("Sprung", "body"), ("Unsprung", "wheel")] {
            for (c, side) in CORNERS.iter().zip(SIDES) {
                t.push_str(&format!(
                    "[[channel]]\ncolumn = \"{c} {part} acceleration\"\nsimulated = \"acc_{what}_{side}_z\"\naxis = \"z\"\nremove_gravity = true\n"
                ));
                if part == "Unsprung" && *c == "FL" {
                    if let Some(r) = range_g {
                        t.push_str(&format!("range_g = {r}\n"));
                    }
                }
            }
        }
        let p = d.join(format!("{name}.toml"));
        std::fs::write(&p, t).unwrap();
        p
    }
}

/// Reads `log` as `name` and checks count, rate, SI values and gravity removal.
fn check(
    log: &Logger,
    name: &str,
    kind: TimeBaseKind,
) -> towride_app::validate::csv_reader::Measurement {
    let d = dir(name);
    let desc = Descriptor::from_file(&log.write(&d, name, None)).unwrap();
    let m = read_measurement(&desc).unwrap();
    assert_eq!(m.time_s.len(), log.rows, "{name}: {:?}", m.notes);
    assert_eq!(m.time_base.kind, kind, "{name}");
    assert!(
        (m.rate_hz / log.rate_hz - 1.0).abs() < 1e-12,
        "{name}: {} Hz",
        m.rate_hz
    );
    // Times on the logger's clock (to the stamp's rounding when rebuilt).
    let tol = if kind == TimeBaseKind::Reconstructed {
        0.5e-3 + 1e-9
    } else {
        1e-6
    };
    let t0 = if kind == TimeBaseKind::Declared {
        0.0
    } else {
        log.t0
    };
    for k in (0..log.rows).step_by(97) {
        let want = t0 + k as f64 / log.rate_hz;
        assert!(
            (m.time_s[k] - want).abs() <= tol,
            "{name} t[{k}] {} vs {want}",
            m.time_s[k]
        );
    }
    // Sample spacing is uniform: no dropped or doubled rows.
    let dt = 1.0 / log.rate_hz;
    assert!(
        m.time_s.windows(2).all(|w| (w[1] - w[0] - dt).abs() < 1e-9),
        "{name}"
    );
    for (c, (corner, side)) in CORNERS.iter().zip(SIDES).enumerate() {
        for (unsprung, what) in [(false, "body"), (true, "wheel")] {
            let y = &m.channels[&format!("acc_{what}_{side}_z")];
            for k in (0..log.rows).step_by(131) {
                let want = log.acc(c, unsprung, k);
                assert!(
                    (y[k] - want).abs() < 1e-5,
                    "{name} {corner} {what}[{k}]: {} vs {want}",
                    y[k]
                );
            }
        }
    }
    let v = m.speed_mps.as_ref().expect("speed channel");
    for k in (0..log.rows).step_by(211) {
        assert!((v[k] - log.speed_at(k)).abs() < 1e-4, "{name} speed[{k}]");
    }
    m
}

#[test]
fn tab_separated_gn_units_row_quantised_5_khz_clock_is_rebuilt() {
    let log = Logger::default();
    let m = check(&log, "tab5k", TimeBaseKind::Reconstructed);
    assert_eq!(
        m.time_base.rows_per_stamp.map(|r| (r * 10.0).round()),
        Some(50.0)
    );
    assert!(
        m.notes
            .iter()
            .any(|n| n.contains("quantised to 1.000 ms") && n.contains("rebuilt")),
        "{:?}",
        m.notes
    );
    // Nothing else was repaired: no row is a "repeated sample".
    assert_eq!(m.notes.len(), 1, "{:?}", m.notes);
}

#[test]
fn comma_separated_units_in_header_exact_clock_m_per_s() {
    let log = Logger {
        sep: ',',
        units_row: false,
        rate_hz: 1000.0,
        rows: 3000,
        clock: Clock::Exact,
        acc_unit: "m/s^2",
        speed_unit: ("m/s", 1.0),
        ..Logger::default()
    };
    let m = check(&log, "comma1k", TimeBaseKind::Column);
    assert!(m.notes.is_empty(), "{:?}", m.notes);
}

#[test]
fn semicolon_decimal_comma_without_time_column_uses_declared_rate_mph() {
    let log = Logger {
        sep: ';',
        decimal_comma: true,
        rate_hz: 2000.0,
        rows: 4000,
        clock: Clock::None,
        acc_unit: "g",
        speed_unit: ("mph", 3600.0 / 1609.344),
        ..Logger::default()
    };
    let m = check(&log, "semi_norate", TimeBaseKind::Declared);
    assert!(
        m.notes
            .iter()
            .any(|n| n.contains("no time column") && n.contains("2000 Hz")),
        "{:?}",
        m.notes
    );
}

#[test]
fn a_5_khz_file_with_a_declared_rate_that_disagrees_is_refused_with_its_line() {
    let log = Logger::default();
    let d = dir("badrate");
    let p = log.write(&d, "badrate", None);
    let text = std::fs::read_to_string(&p).unwrap();
    std::fs::write(&p, format!("sample_rate_hz = 4000.0\n{text}")).unwrap();
    let e = read_measurement(&Descriptor::from_file(&p).unwrap())
        .unwrap_err()
        .to_string();
    assert!(e.contains("badrate.csv") && e.contains("4000"), "{e}");
}

#[test]
fn clipped_samples_are_counted_at_the_given_range_and_flagged_without_one() {
    let log = Logger {
        clip_g: Some(2.0),
        rows: 5000,
        ..Logger::default()
    };
    let want = log.clipped_rows();
    assert!(want > 100, "the test signal must clip: {want}");
    let d = dir("clip");
    let with =
        read_measurement(&Descriptor::from_file(&log.write(&d, "ranged", Some(2.0))).unwrap())
            .unwrap();
    assert_eq!(with.clipped_samples("acc_wheel_front_left_z"), want);
    assert_eq!(with.clipped_samples("acc_wheel_front_right_z"), 0);
    assert!(
        with.notes
            .iter()
            .any(|n| n.contains(&format!("{want} sample(s)"))),
        "{:?}",
        with.notes
    );
    // Without range_g the flat top at a standard range is reported, nothing left out.
    let without =
        read_measurement(&Descriptor::from_file(&log.write(&d, "plain", None)).unwrap()).unwrap();
    assert_eq!(without.clipped_samples("acc_wheel_front_left_z"), 0);
    assert!(
        without
            .notes
            .iter()
            .any(|n| n.contains("flat top at 2 g") || n.contains("looks like a clipped")),
        "{:?}",
        without.notes
    );
}
