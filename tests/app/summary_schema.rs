//! The run summary's schema (version 2): every channel's max, min and |peak| with their
//! times and no signed peak anywhere; the band-limited twins of the sensor, force and
//! deflection channels through the scene's acquisition chain, checked against the
//! Butterworth's gain and phase on sines; a scene's `[acquisition]` table; sweep shards
//! and summaries of the previous layout refused by `sweep merge` and `--resume`.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use towride_app::job::{band, Job, Signal, SCHEMA_VERSION};
use towride_app::scene::channels;
use towride_app::signal::acquisition::{band_limit, AcqFilter};
use towride_app::sweep::exec::{merge, run_sweep_in};
use towride_app::sweep::Sweep;
use towride_mbs::input::Loader;
use towride_mbs::progress::Silent;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride_schema_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Amplitude and phase [deg] of the `f_hz` component of `y` (sampled at `rate`) over
/// its second half, by least squares on sin, cos and a constant.
fn tone(y: &[f64], rate: f64, f_hz: f64) -> (f64, f64) {
    let (mut ss, mut sc, mut cc, mut ys, mut yc, mut s1, mut c1, mut y1) =
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let from = y.len() / 2;
    let n = (y.len() - from) as f64;
    for (k, v) in y.iter().enumerate().skip(from) {
        let w = 2.0 * PI * f_hz * k as f64 / rate;
        let (s, c) = w.sin_cos();
        ss += s * s;
        sc += s * c;
        cc += c * c;
        ys += v * s;
        yc += v * c;
        s1 += s;
        c1 += c;
        y1 += v;
    }
    // Normal equations of [a, b, m] for a sin + b cos + m (3x3, Cramer).
    let m = [[ss, sc, s1], [sc, cc, c1], [s1, c1, n]];
    let r = [ys, yc, y1];
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(m);
    let col = |j: usize| {
        let mut x = m;
        for i in 0..3 {
            x[i][j] = r[i];
        }
        det(x) / d
    };
    let (a, b) = (col(0), col(1));
    (a.hypot(b), b.atan2(a).to_degrees())
}

/// A sine through the acquisition chain: at the cutoff the gain is 1/sqrt(2) and the
/// causal fourth-order filter lags by half a period; in the passband the gain is 1, far
/// above the cutoff the analog filter's (f/fc)^-4. On a grid of 40 fc the bilinear
/// transform is exact at fc; at the run's 1 kHz the cubic interpolation onto that grid
/// costs under 0.5 %.
#[test]
fn a_sine_through_the_acquisition_chain_has_the_butterworth_gain_and_lag() {
    let f = AcqFilter::THESIS;
    let sine = |f_hz: f64, rate: f64| -> Vec<f64> {
        (0..(2.0 * rate) as usize)
            .map(|k| (2.0 * PI * f_hz * k as f64 / rate).sin())
            .collect()
    };
    let half = 0.5_f64.sqrt();
    for (rate, at_fc) in [(4000.0, 1e-6), (1000.0, 5e-3)] {
        let through = |f_hz: f64| {
            tone(
                &band_limit(&f, &sine(f_hz, rate), rate).unwrap(),
                rate,
                f_hz,
            )
        };
        let (g, phase) = through(100.0);
        assert!((g / half - 1.0).abs() < at_fc, "{rate} Hz: gain at fc {g}");
        // Half a period late: a causal filter, as the instrument's.
        assert!(
            (phase.abs() - 180.0).abs() < 0.5,
            "{rate} Hz: phase at fc {phase}"
        );
        let (g, phase) = through(10.0);
        assert!((g - 1.0).abs() < 1e-3, "{rate} Hz: passband gain {g}");
        // The analog filter's lag at 10 Hz, its sections s^2 + 2 sin((2k-1) pi/8) s + 1
        // at s = 0.1 i: 15.0 deg.
        let analog: f64 = [1.0, 3.0]
            .iter()
            .map(|k: &f64| {
                (2.0 * (k * PI / 8.0).sin() * 0.1)
                    .atan2(1.0 - 0.01)
                    .to_degrees()
            })
            .sum();
        assert!(
            (phase + analog).abs() < 0.3,
            "{rate} Hz: passband phase {phase}, analog -{analog}"
        );
        let (g, _) = through(400.0);
        assert!(g < 0.005, "{rate} Hz: gain at 4 fc {g}");
    }
}

/// Every channel of `summary.json` has max, min and |peak| with their times, |peak| =
/// max(|max|, |min|), and no signed peak is left anywhere; each sensor, force and
/// deflection has its band-limited twin, which is the raw channel through the scene's
/// chain; `outputs.csv` has the raw columns first, the twins after.
#[test]
fn the_summary_reports_max_min_and_abs_peak_raw_and_band_limited() {
    let dir = tmp("run");
    let job = Job::from_file(Path::new(repo!("scenes/default.toml")), &Loader::new())
        .unwrap()
        .without_view();
    let mut run = job.run(&Silent).unwrap();
    towride_app::report::write_run(&mut run, &job.system, &dir).unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["schema_version"], SCHEMA_VERSION);
    assert_eq!(SCHEMA_VERSION, 2);
    // No signed peak, by any of its former names, at any depth.
    fn keys(v: &serde_json::Value, out: &mut Vec<String>) {
        match v {
            serde_json::Value::Object(m) => {
                for (k, x) in m {
                    out.push(k.clone());
                    keys(x, out);
                }
            }
            serde_json::Value::Array(a) => a.iter().for_each(|x| keys(x, out)),
            _ => {}
        }
    }
    let mut all = Vec::new();
    keys(&v, &mut all);
    for gone in ["peak", "t_peak", "peak_n", "t_peak_s"] {
        assert!(!all.iter().any(|k| k == gone), "`{gone}` in summary.json");
    }
    let chans = v["channels"].as_object().unwrap();
    for (name, c) in chans {
        let x = |k: &str| c[k].as_f64().unwrap_or_else(|| panic!("{name}: no {k}"));
        let (max, min, abs) = (x("max"), x("min"), x("abs_peak"));
        assert_eq!(abs, max.abs().max(min.abs()), "{name}");
        let t = if max.abs() >= min.abs() {
            x("t_max")
        } else {
            x("t_min")
        };
        assert_eq!(x("t_abs_peak"), t, "{name}");
        assert!(min <= max, "{name}");
    }
    // The twins: every sensor, force and deflection channel, and nothing else.
    let a = &v["acquisition"];
    assert_eq!(
        (
            a["filter"].as_str(),
            a["order"].as_u64(),
            a["cutoff_hz"].as_f64()
        ),
        (Some("butterworth"), Some(4), Some(100.0))
    );
    assert_eq!(
        (a["causal"].as_bool(), a["suffix"].as_str()),
        (Some(true), Some("_lp100"))
    );
    assert_eq!(a["grid_rate_hz"].as_f64(), Some(4000.0));
    let raw: Vec<&String> = chans
        .keys()
        .filter(|n| chans[*n]["signal"] == "raw")
        .collect();
    let mut pairs = 0;
    for n in &raw {
        let kind = channels::band(n);
        let twin = format!("{n}_lp100");
        assert_eq!(kind.is_some(), chans.contains_key(&twin), "{n}");
        if kind.is_none() {
            assert!(
                chans[*n]["twin"].is_null() && chans[*n]["shown"] == true,
                "{n}"
            );
            continue;
        }
        pairs += 1;
        let (r, b) = (&chans[*n], &chans[&twin]);
        assert_eq!(
            (r["twin"].as_str(), b["twin"].as_str()),
            (Some(twin.as_str()), Some(n.as_str()))
        );
        assert_eq!(b["signal"], "band_limited");
        assert_eq!(r["unit"], b["unit"]);
        // Accelerometers as the instrument saw them; forces and deflections raw first.
        let sensor = kind == Some(channels::Band::Sensor);
        assert_eq!(
            (b["shown"].as_bool(), r["shown"].as_bool()),
            (Some(sensor), Some(!sensor)),
            "{n}"
        );
        // The twin is the raw channel through the chain, sample for sample.
        let want = band_limit(&AcqFilter::THESIS, &run.channel(n).unwrap(), 1000.0).unwrap();
        assert_eq!(run.channel(&twin).unwrap(), want, "{twin}");
    }
    // 15 accelerometer axes (the driver's floor point among them), trailer_ax, 3 ball
    // forces, 12 bracket loads, 3 deflections, and at each of the 4 stress points 4 fibre
    // stresses and the shear stress.
    assert_eq!(pairs, 54);
    assert!(run.is_raw("hitch_fx") && !run.is_raw("hitch_fx_lp100"));
    assert_eq!(
        run.summary.channels["acc_hitch_z_lp100"].signal,
        Signal::BandLimited
    );
    // The hitch force's ringing: extremes, no signed peak.
    let h = &v["hitch_force"];
    assert_eq!(h["max_n"], chans["hitch_fx"]["max"]);
    assert_eq!(h["min_n"], chans["hitch_fx"]["min"]);
    assert_eq!(h["abs_peak_n"], chans["hitch_fx"]["abs_peak"]);
    // outputs.csv: the model's channels in their order, then the twins.
    let header = std::fs::read_to_string(dir.join("outputs.csv"))
        .unwrap()
        .lines()
        .next()
        .unwrap()
        .to_string();
    let cols: Vec<&str> = header.split(',').collect();
    let model = towride_mbs::model::output::channels(&job.system);
    assert_eq!(cols.len(), 1 + model.len() + pairs);
    for (k, c) in model.iter().enumerate() {
        assert_eq!(cols[1 + k], format!("{} [{}]", c.name, c.unit));
    }
    assert!(
        cols[1 + model.len()..]
            .iter()
            .all(|c| c.contains("_lp100 [")),
        "{header}"
    );
    assert_eq!(job.band_channels().len(), pairs);
    std::fs::remove_dir_all(&dir).ok();
}

/// A scene's `[acquisition]`: another filter renames the twins, `none` leaves the raw
/// channels alone, an unknown kind is named at its line.
#[test]
fn a_scene_declares_its_acquisition_chain() {
    let dir = tmp("acq");
    let base = std::fs::read_to_string(repo!("scenes/default.toml")).unwrap();
    let scenes = std::fs::canonicalize(repo!("scenes")).unwrap();
    let base = base
        .replace(
            "\"../vehicles/",
            &format!("\"{}/../vehicles/", scenes.display()),
        )
        .replace("\"../roads/", &format!("\"{}/../roads/", scenes.display()));
    let scene = |tag: &str, table: &str| {
        let p = dir.join(format!("{tag}.toml"));
        std::fs::write(&p, format!("{base}\n[acquisition]\n{table}\n")).unwrap();
        Job::from_file(&p, &Loader::new())
    };
    let j = scene(
        "lp60",
        "filter = \"butterworth\"\norder = 2\ncutoff_hz = 60.0",
    )
    .unwrap();
    let f = j.acquisition().unwrap();
    assert_eq!(
        (f.order, f.cutoff_hz, f.suffix()),
        (2, 60.0, "_lp60".to_string())
    );
    assert!(j.band_channels().iter().any(|c| c.0 == "acc_hitch_z_lp60"));
    let none = scene("none", "filter = \"none\"").unwrap();
    assert!(none.acquisition().is_none() && none.band_channels().is_empty());
    let e = scene("bessel", "filter = \"bessel\"")
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("bessel.toml") && e.contains("acquisition.filter"),
        "{e}"
    );
    let e = scene("order", "filter = \"butterworth\"\norder = 0")
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("acquisition.order"), "{e}");
    // Without the table: the thesis's chain.
    let d = Job::from_file(Path::new(repo!("scenes/default.toml")), &Loader::new()).unwrap();
    assert_eq!(d.acquisition(), Some(AcqFilter::THESIS));
    assert_eq!(
        band::twins(
            ["acc_hitch_z", "speed", "hitch_fx", "acc_hitch_z_lp100"],
            &AcqFilter::THESIS
        ),
        [
            (0, "acc_hitch_z_lp100".to_string()),
            (2, "hitch_fx_lp100".to_string())
        ]
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Sweep files of summary version 3 (signed peaks) are refused, naming the file and
/// both versions: a shard's JSON twin by `sweep merge`; a summary, its twin or a journal
/// by `--resume`. Version 3 kept no max or min, so they cannot be converted.
#[test]
fn merge_and_resume_refuse_the_previous_layout() {
    let sweep = Sweep::load(Path::new(repo!("scenes/examples/pendulum_sweep.toml"))).unwrap();
    let dir = tmp("v3");
    for s in 0..2 {
        run_sweep_in(&sweep, (s, 2), 2, &dir, false, &Silent).unwrap();
    }
    let csv = |s: usize| dir.join(format!("summary_shard{s}of2.csv"));
    let merged = dir.join("merged.csv");
    let m = merge(&[csv(0), csv(1)], &merged).unwrap();
    assert_eq!((m.cases, m.schema_version), (6, 5));
    // Shard 1 as version 6 wrote it.
    let twin = csv(1).with_extension("json");
    let text = std::fs::read_to_string(&twin).unwrap();
    let old = text.replace("\"schema_version\": 8", "\"schema_version\": 6");
    assert_ne!(old, text);
    std::fs::write(&twin, &old).unwrap();
    std::fs::remove_file(&merged).unwrap();
    let e = merge(&[csv(0), csv(1)], &merged).unwrap_err().to_string();
    assert!(
        e.contains("summary_shard1of2.json")
            && e.contains("schema version 6")
            && e.contains("version 8"),
        "{e}"
    );
    assert!(!merged.exists());
    // --resume of that shard: refused by its twin.
    let e = run_sweep_in(&sweep, (1, 2), 1, &dir, true, &Silent)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("summary_shard1of2.json") && e.contains("schema version 6"),
        "{e}"
    );
    // A version 3 summary whose twin is gone: known by its signed-peak columns.
    let legacy = tmp("v3csv");
    std::fs::write(
        legacy.join("summary.csv"),
        "case,mass_kg,length,status,wall_time [s],hitch_fx peak [N],steps,error\n0,0.5,\"[0.5, 0.0, 0.0]\",completed,0.1,-1.0,10,\n",
    )
    .unwrap();
    let e = run_sweep_in(&sweep, (0, 1), 1, &legacy, true, &Silent)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("summary.csv") && e.contains("version 3 or older"),
        "{e}"
    );
    // A journal of a killed version-3 run (rows without the version line) and one with
    // another version's line.
    let journal = tmp("v3journal");
    let row = r#"{"index":0,"values":["0.5","[0.5, 0.0, 0.0]"],"status":"completed","error":null,"wall_s":0.1,"figures":[["hitch_fx peak [N]",-1.0]]}"#;
    for (text, says) in [
        (format!("{row}\n"), "version 3 or older"),
        (
            format!("{{\"schema_version\":3}}\n{row}\n"),
            "schema version 3",
        ),
    ] {
        std::fs::write(journal.join("summary.csv.journal"), text).unwrap();
        let e = run_sweep_in(&sweep, (0, 1), 1, &journal, true, &Silent)
            .unwrap_err()
            .to_string();
        assert!(e.contains("summary.csv.journal") && e.contains(says), "{e}");
    }
    // The current version resumes: a journal of this version's rows is taken as it is.
    let ok = tmp("v4journal");
    let r = run_sweep_in(&sweep, (0, 1), 2, &ok, false, &Silent).unwrap();
    std::fs::remove_file(ok.join("summary.csv")).unwrap();
    std::fs::remove_file(ok.join("summary.json")).unwrap();
    let head = |fp: Option<&towride_app::sweep::fingerprint::Fingerprint>| {
        let v = towride_app::sweep::exec::SCHEMA_VERSION;
        let mut text = match fp {
            Some(f) => format!(
                "{{\"schema_version\":{v},\"fingerprint\":{}}}\n",
                serde_json::to_string(f).unwrap()
            ),
            None => format!("{{\"schema_version\":{v}}}\n"),
        };
        for row in &r.rows {
            text.push_str(&serde_json::to_string(row).unwrap());
            text.push('\n');
        }
        text
    };
    // Without a fingerprint nothing says the rows are of this sweep: refused.
    std::fs::write(ok.join("summary.csv.journal"), head(None)).unwrap();
    let e = run_sweep_in(&sweep, (0, 1), 2, &ok, true, &Silent)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("summary.csv.journal") && e.contains("no fingerprint"),
        "{e}"
    );
    std::fs::write(ok.join("summary.csv.journal"), head(r.fingerprint.as_ref())).unwrap();
    let again = run_sweep_in(&sweep, (0, 1), 2, &ok, true, &Silent).unwrap();
    assert_eq!(again.resumed, 6);
    for d in [dir, legacy, journal, ok] {
        std::fs::remove_dir_all(d).ok();
    }
}
