//! Issue 32 item 8: every long command keeps the run/sweep contract when stopped by
//! Ctrl-C: what was computed is written and labelled `interrupted`, work not begun is
//! listed as not run (never as failed), and the exit code is 130.

use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::reliability::{interrupt_when, stderr, tmp};

/// Runs towride with `args` and `--out <dir>`, sends SIGINT after `after`.
fn stopped(args: &[&str], dir: &std::path::Path, after: Duration) -> Output {
    let child = Command::new(env!("CARGO_BIN_EXE_towride"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .arg("--out")
        .arg(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    interrupt_when(&child, || t.elapsed() > after, after * 2);
    let out = child.wait_with_output().unwrap();
    assert!(!stderr(&out).contains("panicked"), "{}", stderr(&out));
    out
}

fn json(path: std::path::PathBuf) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap()
}

#[test]
fn ctrl_c_stops_a_plan_with_exit_130_and_its_cases_not_run_listed() {
    let d = tmp("plan_sigint");
    let scene = std::fs::canonicalize(repo!("scenes/default.toml")).unwrap();
    let plan = d.join("plan.toml");
    // Twelve short cases one after another: seconds of work, stopped after one.
    let speeds: Vec<String> = (0..12).map(|k| format!("{}.0", 20 + 5 * k)).collect();
    std::fs::write(
        &plan,
        format!(
            "[plan]\nname = \"twelve\"\nspeeds_km_h = [{}]\nload_cases = [\"empty\"]\ntravel_m = 1.0\nafter_s = 0.3\n\n[[obstacle]]\nname = \"ramp\"\nscene = {:?}\n",
            speeds.join(", "),
            scene.to_str().unwrap()
        ),
    )
    .unwrap();
    let out = stopped(
        &["run", plan.to_str().unwrap(), "--jobs", "1"],
        &d.join("out"),
        Duration::from_millis(1500),
    );
    let e = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{e}");
    assert!(e.contains("cases not run"), "{e}");
    let table = std::fs::read_to_string(d.join("out/plan_summary.csv")).unwrap();
    assert_eq!(table.lines().count(), 13, "{table}");
    assert!(table.contains(",not_run,"), "{table}");
    assert!(!table.contains("failed"), "{table}");
}

#[test]
fn ctrl_c_stops_stress_with_its_cases_labelled() {
    let d = tmp("stress_sigint");
    let out = stopped(
        &[
            "stress",
            "scenes/default.toml",
            "--only",
            "thesis",
            "--jobs",
            "1",
        ],
        &d,
        Duration::from_millis(2500),
    );
    let e = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{e}");
    if e.contains("during the reference run") {
        assert!(!d.join("stress.json").exists());
        return;
    }
    let s = json(d.join("stress.json"));
    assert_eq!(s["status"], "interrupted", "{s}");
    let outcomes = s["outcomes"].as_array().unwrap();
    let stopped = outcomes
        .iter()
        .filter(|o| {
            o["status"] == "not run: interrupted"
                || o["status"].as_str().unwrap().starts_with("interrupted")
        })
        .count();
    assert!(
        stopped > 0 && stopped as u64 == s["interrupted"].as_u64().unwrap(),
        "{s}"
    );
    assert!(
        outcomes
            .iter()
            .all(|o| !o["status"].as_str().unwrap().starts_with("failed")),
        "{s}"
    );
}

#[test]
fn ctrl_c_stops_bench_with_its_runs_labelled() {
    let d = tmp("bench_sigint");
    let out = stopped(
        &[
            "bench",
            "scenes/default.toml",
            "--tol",
            "1e-3,1e-4,1e-5",
            "--repeat",
            "1",
            "--jobs",
            "1",
        ],
        &d,
        Duration::from_millis(4000),
    );
    let e = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{e}");
    if e.contains("during the reference run") {
        assert!(!d.join("bench.json").exists());
        return;
    }
    let b = json(d.join("bench.json"));
    assert_eq!(b["status"], "interrupted", "{b}");
    let runs = b["runs"].as_array().unwrap();
    assert!(
        runs.iter()
            .all(|p| !p["status"].as_str().unwrap().starts_with("failed")),
        "{b}"
    );
    assert!(!std::fs::read_to_string(d.join("bench.csv"))
        .unwrap()
        .contains("failed"));
}

#[test]
fn ctrl_c_stops_a_folder_validation_with_the_runs_not_validated_listed() {
    let d = tmp("validate_sigint");
    let out = stopped(
        &["validate", "measurements/synthetic"],
        &d,
        Duration::from_millis(2500),
    );
    let e = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{e}");
    assert!(e.contains("not validated"), "{e}");
    let s = json(d.join("summary.json"));
    assert_eq!(s["status"], "interrupted");
    let (done, not_run) = (
        s["runs"].as_array().unwrap().len(),
        s["not_run"].as_array().unwrap().len(),
    );
    assert!(
        not_run > 0 && done + not_run + s["failures"].as_array().unwrap().len() == 72,
        "{s}"
    );
    assert!(s["failures"].as_array().unwrap().is_empty(), "{s}");
    let index = std::fs::read_to_string(d.join("index.html")).unwrap();
    assert!(
        index.contains(&format!("Interrupted: {not_run} run(s) not validated")),
        "{index}"
    );
}
