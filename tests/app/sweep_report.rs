//! `sweep --keep-histories` and the sweep's page: every case keeps its own files, an
//! interrupted case leaves nothing that `--resume` trusts, and the page's curves group
//! the cases by the other parameters. Checked against the pendulum's analytical peak
//! link tension 3 m g (released from horizontal), whatever its length.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicU64;

use towride_app::sweep::cases::{case_dir, cases_dir};
use towride_app::sweep::exec::{run_sweep_with, Options};
use towride_app::sweep::page;
use towride_app::sweep::Sweep;
use towride_mbs::progress::Silent;

use crate::reliability::StopAfter;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

const KEEP: Options = Options {
    jobs: 1,
    resume: false,
    keep_histories: true,
    check: None,
};

/// The largest value of column `name` of a case's outputs.csv.
fn column_max(csv: &Path, name: &str) -> f64 {
    let mut r = csv::Reader::from_path(csv).unwrap();
    let c = r
        .headers()
        .unwrap()
        .iter()
        .position(|h| h.starts_with(&format!("{name} [")))
        .unwrap();
    r.records()
        .map(|x| x.unwrap()[c].parse::<f64>().unwrap())
        .fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn kept_histories_hold_each_cases_own_run_and_survive_an_interrupted_resume() {
    let sweep = Sweep::load(Path::new(repo!("scenes/examples/pendulum_sweep.toml"))).unwrap();
    let out = tmp("sweep_keep");
    let stop = StopAfter {
        done: AtomicU64::new(0),
        after: 3,
    };
    let cut = run_sweep_with(&sweep, (0, 1), &out, &KEEP, &stop).unwrap();
    assert_eq!((cut.status.as_str(), cut.interrupted), ("interrupted", 3));
    let cases = cases_dir(&out);
    // A kill while case 4 was being written leaves its half folder under `.part`, and
    // one finished case lost its folder: resume must run both again.
    std::fs::create_dir_all(cases.join("case_0004.part")).unwrap();
    std::fs::write(cases.join("case_0004.part/outputs.csv"), "time [s]\n0\n").unwrap();
    std::fs::remove_dir_all(case_dir(&cases, 1)).unwrap();
    let resume = Options {
        resume: true,
        ..KEEP
    };
    let res = run_sweep_with(&sweep, (0, 1), &out, &resume, &Silent).unwrap();
    assert_eq!((res.status.as_str(), res.resumed), ("completed", 2));
    let names: Vec<String> = std::fs::read_dir(&cases)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 6, "{names:?}");
    assert!(names.iter().all(|n| !n.ends_with(".part")), "{names:?}");
    for r in &res.rows {
        let dir = case_dir(&cases, r.index);
        for f in ["outputs.csv", "summary.json", "report.html"] {
            assert!(dir.join(f).is_file(), "{}/{f}", dir.display());
        }
        // The folder holds this case's run: its peak link tension is 3 m g for this
        // case's mass, and the row's figure is the maximum of its own outputs.csv.
        let m: f64 = r.values[0].parse().unwrap();
        let tension = column_max(&dir.join("outputs.csv"), "pivot.force.z");
        assert!((tension / (3.0 * m * 9.81) - 1.0).abs() < 1e-4, "{tension}");
        let fig = r.figures.iter().find(|f| f.0 == "pivot.force.z max [N]");
        assert!((fig.unwrap().1 / tension - 1.0).abs() < 1e-5);
        // The summary names the files where they are, not the temporary folder.
        let s = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        assert!(!s.contains(".part"), "{s}");
    }
    // The page links every case's report.
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    for k in 0..6 {
        assert!(html.contains(&format!("cases/case_{k:04}/report.html")));
    }
    assert!(out.join("report.png").is_file());
}

#[test]
fn the_pages_curves_run_along_one_parameter_with_one_curve_per_other_value() {
    let dir = tmp("sweep_page");
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("summary.csv");
    // Two variants at three speeds (the last parameter varies fastest); case 4 failed.
    // The figure is a magnitude: the stiffer variant's larger pull plots higher.
    let mut t = String::from(
        "case,variant,speed_km_h,status,wall_time [s],hitch_fx abs_peak [N],steps,error\n",
    );
    for k in 0..6 {
        let (v, s) = (1 + k / 3, [30.0, 50.0, 60.0][k % 3]);
        let (status, peak) = if k == 4 {
            ("failed", String::new())
        } else {
            ("completed", format!("{}", 1000.0 * v as f64 + s))
        };
        t.push_str(&format!("{k},{v},{s},{status},0.1,{peak},100,\n"));
    }
    std::fs::write(&csv, t).unwrap();
    let table = page::read(&csv).unwrap();
    assert_eq!(table.parameters, ["variant", "speed_km_h"]);
    assert_eq!(page::x_parameter(&table), Some(0));
    let c = page::curves(&table, 0, 0);
    let labels: Vec<&str> = c.iter().map(|x| x.0.as_str()).collect();
    assert_eq!(
        labels,
        ["speed_km_h = 30", "speed_km_h = 50", "speed_km_h = 60"]
    );
    assert_eq!(c[0].1, [(1.0, 1030.0), (2.0, 2030.0)]);
    // The failed case (variant 2 at 50 km/h) is left out, not drawn at zero.
    assert_eq!(c[1].1, [(1.0, 1050.0)]);
    // Against speed instead: one curve per variant, sorted by speed.
    let c = page::curves(&table, 1, 0);
    assert_eq!(c[0].0, "variant = 1");
    assert_eq!(c[0].1, [(30.0, 1030.0), (50.0, 1050.0), (60.0, 1060.0)]);
    assert_eq!(page::key_figures(&table), [0]);
    let files = page::write(&csv, "two variants").unwrap();
    assert_eq!(files.html, dir.join("report.html"));
    assert!(files.png.is_file());
    assert_eq!(
        page::page_path(&dir.join("summary_shard1of4.csv"), "html"),
        dir.join("report_shard1of4.html")
    );
}
