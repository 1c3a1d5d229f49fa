//! Folders of runs: one bad descriptor is reported and the others complete into one
//! summary table, on the command line (the vehicle model) and over the 72-run plan
//! (closed-form test simulator).

use crate::{towride, towride_json};

use std::path::PathBuf;

use crate::validate_sim::Analytic;
use towride_app::validate::plan::{plan, write_plan};
use towride_app::validate::synth::SensorModel;
use towride_app::validate::{validate_folder, write_summary, Options};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride-vfold-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    d
}

#[test]
fn cli_folder_with_one_bad_descriptor() {
    let d = tmp("cli");
    let m = d.join("runs");
    for (scene, v, load) in [
        (repo!("scenes/bump_25mm.toml"), "20", "empty"),
        (repo!("scenes/default.toml"), "50", "200kg_behind_axle"),
    ] {
        let out = towride(&[
            "validate",
            "synth",
            "--scene",
            scene,
            "--speed-kmh",
            v,
            "--load",
            load,
            "--out",
            m.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // A third run in a subfolder, written in g, then a broken copy of it.
    let sub = m.join("more");
    let out = towride(&[
        "validate",
        "synth",
        "--scene",
        repo!("scenes/bump_50mm.toml"),
        "--speed-kmh",
        "30",
        "--in-g",
        "--out",
        sub.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let good = std::fs::read_to_string(sub.join("bump_50mm_30kmh_empty.toml")).unwrap();
    assert!(good.contains("synthetic = true") && good.starts_with("# SYNTHETIC"));
    let bad = good.replace("cutoff_hz = 100.0", "cutoff_hz = \"fast\"");
    std::fs::write(sub.join("broken.toml"), &bad).unwrap();
    let bad_line = bad
        .lines()
        .position(|l| l.starts_with("cutoff_hz"))
        .unwrap()
        + 1;

    let o = d.join("out");
    let out = towride(&[
        "validate",
        m.to_str().unwrap(),
        "--out",
        o.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(1), "one failure -> exit 1");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!("broken.toml:{bad_line}:")) && err.contains("cutoff_hz"),
        "{err}"
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 3);
    assert_eq!(v["failures"].as_array().unwrap().len(), 1);
    assert!(v["wall_s"].as_f64().unwrap() > 0.0);
    assert!(v["simulator"].as_str().unwrap().contains("vehicle model"));
    for r in runs {
        assert_eq!(r["synthetic"], true);
        let shift = r["shift_s"].as_f64().unwrap();
        assert!((shift - 0.037).abs() < 1e-3, "{shift}");
        for c in r["channels"].as_array().unwrap() {
            for key in [
                "peak_measured_mps2",
                "t_peak_measured_s",
                "rms_diff_mps2",
                "correlation",
                "rating",
                "shift_s",
                "speed_mps",
            ] {
                assert!(c["corrected"][key].is_number(), "{key}: {c}");
                assert!(c["uncorrected"][key].is_number(), "{key}: {c}");
            }
        }
    }
    // One summary table: a header, 3 runs x 15 sensor channels (the thesis's 12 and the
    // driver's floor point, docs/comfort.md), one failure row.
    let csv = std::fs::read_to_string(o.join("summary.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert!(
        lines[0].starts_with(
            "run,synthetic,obstacle,load_case,nominal_speed [m/s],speed [m/s],shift [s]"
        ),
        "{}",
        lines[0]
    );
    assert_eq!(lines.len(), 1 + 3 * 15 + 1);
    assert!(lines[46].contains("broken.toml") && lines[46].contains("cutoff_hz"));
    assert!(o.join("summary.json").exists() && o.join("index.html").exists());
    let page = o.join("bump_25mm_20kmh_empty").join("report.png");
    assert!(std::fs::metadata(&page).unwrap().len() > 10_000);
    // The interactive report: per sensor an overlay in each comparison and a spectrum
    // (15 x 2 + 15 charts), the metrics table; linked from the index.
    let html = o.join("bump_25mm_20kmh_empty").join("report.html");
    let (dom, ready) = crate::browser_dom(&html);
    assert_eq!(ready.as_deref(), Some("45"));
    assert!(dom.contains("acc_trailer_drawbar_z") && dom.contains("gain ratio"));
    let index = std::fs::read_to_string(o.join("index.html")).unwrap();
    assert!(index.contains("bump_25mm_20kmh_empty/report.html"));
    assert!(o
        .join("bump_25mm_20kmh_empty")
        .join("acc_trailer_drawbar_z.png")
        .exists());

    // --no-correct on the single file: only the uncorrected comparison.
    let v = towride_json(&[
        "validate",
        sub.join("bump_50mm_30kmh_empty.toml").to_str().unwrap(),
        "--no-correct",
        "--no-plots",
        "--json",
        "--out",
        o.to_str().unwrap(),
    ]);
    assert!(v["runs"][0]["shift_s"].is_null());
    assert!(v["runs"][0]["channels"][0]["corrected"].is_null());
    assert!(v["runs"][0]["channels"][0]["uncorrected"]["rating"].is_number());
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn plan_of_72_runs_with_one_bad_file() {
    let d = tmp("plan");
    // A lighter test simulator (two channels, 1 kHz) keeps 72 runs quick.
    let sim = Analytic {
        channels: crate::validate_sim::CHANNELS[1..3].to_vec(),
        rate_hz: 1000.0,
        ..Analytic::default()
    };
    let p =
        towride_app::scene::plan::load(std::path::Path::new(repo!("scenes/measurement_plan.toml")))
            .unwrap();
    let runs = plan(&p);
    assert_eq!(runs.len(), 72);
    let mut names: Vec<&str> = runs.iter().map(|r| r.name.as_str()).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), 72, "run names are unique");
    let sensor = SensorModel {
        sample_rate_hz: 500.0,
        ..SensorModel::default()
    };
    let files = write_plan(&sim, &runs, &sensor, &d, &|_| {}).unwrap();
    assert_eq!(files.len(), 72);
    // Break one: a CSV row with a bad number.
    let csv = d.join("bump_50mm_40kmh_200kg_ahead_of_axle.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    lines[100] = lines[100].replacen(',', ",oops", 1);
    std::fs::write(&csv, lines.join("\n")).unwrap();
    let res = validate_folder(&files, &sim, &Options::default(), &|_, _| {});
    assert_eq!(res.runs.len(), 71);
    assert_eq!(res.failures.len(), 1);
    assert!(res.failures[0].1.contains(":101:"), "{}", res.failures[0].1);
    let worst = res
        .runs
        .iter()
        .map(|r| r.primary().mean_rating)
        .fold(1.0, f64::min);
    let worst_shift = res
        .runs
        .iter()
        .map(|r| (r.primary().shift_s - 0.037).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "72-run plan: lowest corrected rating {worst:.4}, largest delay error {:.3} ms, {:.2} s",
        worst_shift * 1e3,
        res.wall_s
    );
    assert!(worst > 0.85, "{worst}");
    assert!(worst_shift < 1e-3);
    let (csv, json) = write_summary(&res, &d.join("out")).unwrap();
    let rows = std::fs::read_to_string(csv).unwrap().lines().count();
    assert_eq!(rows, 1 + 71 * 2 + 1);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    assert_eq!(v["runs"].as_array().unwrap().len(), 71);
    std::fs::remove_dir_all(&d).ok();
}
