//! Issue 20: no hang, no panic, no silent acceptance, nothing lost on interruption. Each
//! test is a case that hung, panicked (exit 101) or was accepted before.

use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::towride;

pub(crate) fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride_rel_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

pub(crate) fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Refused at once (exit 2, no panic) with a message containing every one of `says`.
fn refused(args: &[&str], says: &[&str]) {
    let t = Instant::now();
    let out = towride(args);
    let e = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {e}");
    assert!(
        t.elapsed() < Duration::from_secs(20),
        "{args:?} took {:?}",
        t.elapsed()
    );
    assert!(!e.contains("panicked"), "{e}");
    for s in says {
        assert!(e.contains(s), "{args:?}: `{s}` not in: {e}");
    }
}

#[test]
fn absurd_command_line_values_are_refused_before_any_work() {
    let scene = repo!("scenes/default.toml");
    // These hung: an SVD of a non-finite matrix, a run to t = 1e300 s.
    refused(
        &["doctor", scene, "--step", "0"],
        &["--step", "must not be 0"],
    );
    refused(&["doctor", scene, "--step", "nan"], &["--step", "finite"]);
    refused(
        &["linear", scene, "--at", "1e300"],
        &["--at", "accepted range"],
    );
}

#[test]
fn huge_durations_and_sample_rates_are_refused_naming_the_field() {
    let scene = repo!("scenes/default.toml");
    for (set, field) in [
        ("default.toml:run.duration_s=1e300", "run.duration_s"),
        (
            "default.toml:run.sample_rate_hz=1e300",
            "run.sample_rate_hz",
        ),
        ("default.toml:run.speed_km_h=1e300", "run.speed_km_h"),
    ] {
        refused(
            &["run", scene, "--out", "/nonexistent/never", "--set", set],
            &["default.toml:", field, "accepted range"],
        );
    }
    // Within each bound, but 3e6 samples of the scene's channels: over the memory limit.
    refused(
        &[
            "run",
            scene,
            "--out",
            "/nonexistent/never",
            "--set",
            "default.toml:run.duration_s=3000",
        ],
        &["default.toml", "run.duration_s", "GiB"],
    );
}

#[test]
fn a_plan_with_a_vanishing_speed_is_refused_at_its_line() {
    let d = tmp("plan_speed");
    let scene = std::fs::canonicalize(repo!("scenes/default.toml")).unwrap();
    let plan = d.join("plan.toml");
    std::fs::write(
        &plan,
        format!(
            "[plan]\nname = \"slow\"\nspeeds_km_h = [50.0, 1e-300]\nload_cases = [\"empty\"]\ntravel_m = 1.0\nafter_s = 0.1\n\n[[obstacle]]\nname = \"ramp\"\nscene = {:?}\n",
            scene.to_str().unwrap()
        ),
    )
    .unwrap();
    refused(
        &["run", plan.to_str().unwrap(), "--out", d.to_str().unwrap()],
        &["plan.toml:3:", "speeds_km_h[1]"],
    );
}

#[test]
fn a_closed_or_full_stdout_ends_quietly_without_a_panic() {
    // The reader is gone before the first line: exit 141 (SIGPIPE's code), nothing said.
    let mut child = Command::new(env!("CARGO_BIN_EXE_towride"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR")))
        .args(["modes", "flex/hitch_crossbeam.toml"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let mut e = String::new();
    child.stderr.take().unwrap().read_to_string(&mut e).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(141), "{e}");
    assert!(e.is_empty(), "{e}");
    // A full disk: one line on stderr, exit 2, and the run's files are complete.
    let d = tmp("full");
    let out = Command::new(env!("CARGO_BIN_EXE_towride"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR")))
        .args(["run", "scenes/examples/pendulum.toml", "--out"])
        .arg(&d)
        .stdout(std::fs::File::create("/dev/full").unwrap())
        .output()
        .unwrap();
    let e = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(e.contains("cannot write to standard output"), "{e}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["status"], "completed");
}

#[test]
fn a_plan_run_prints_one_json_document_and_writes_a_plan_table() {
    let d = tmp("plan_json");
    let scene = std::fs::canonicalize(repo!("scenes/default.toml")).unwrap();
    let plan = d.join("plan.toml");
    std::fs::write(
        &plan,
        format!(
            "[plan]\nname = \"two\"\nspeeds_km_h = [30.0, 50.0]\nload_cases = [\"empty\"]\ntravel_m = 1.0\nafter_s = 0.05\n\n[[obstacle]]\nname = \"ramp\"\nscene = {:?}\n",
            scene.to_str().unwrap()
        ),
    )
    .unwrap();
    // One document: serde_json refuses trailing documents.
    let j = crate::towride_json(&[
        "run",
        plan.to_str().unwrap(),
        "--out",
        d.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(j["schema_version"], 2);
    assert_eq!(j["status"], "completed");
    let cases = j["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 2);
    assert_eq!(cases[1]["summary"]["status"], "completed");
    let table = std::fs::read_to_string(d.join("plan_summary.csv")).unwrap();
    assert_eq!(table.lines().count(), 3, "{table}");
    assert!(
        table.contains("ramp_50kmh_empty,ramp,50,empty,completed"),
        "{table}"
    );
}

#[test]
fn sweep_merge_refuses_missing_shards_and_speaks_json() {
    let d = tmp("merge");
    let ds = d.to_str().unwrap();
    let f = repo!("scenes/examples/pendulum_sweep.toml");
    for s in ["0/2", "1/2"] {
        let o = towride(&["sweep", f, "--out", ds, "--shard", s]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let (s0, s1) = (
        d.join("summary_shard0of2.csv"),
        d.join("summary_shard1of2.csv"),
    );
    let merged = d.join("merged.csv");
    // Half the cases: refused (it said "3 cases merged" with exit 0).
    refused(
        &[
            "sweep",
            "merge",
            s0.to_str().unwrap(),
            "--out",
            merged.to_str().unwrap(),
        ],
        &["3 of the sweep's 6 cases are missing", "1, 3, 5"],
    );
    assert!(!merged.exists());
    let j = crate::towride_json(&[
        "sweep",
        "merge",
        s0.to_str().unwrap(),
        s1.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(j["schema_version"], 5);
    assert_eq!(
        (j["cases"].as_u64(), j["cases_total"].as_u64()),
        (Some(6), Some(6))
    );
}

/// Sends SIGINT to `child` once `ready` holds (or after `wait`).
pub(crate) fn interrupt_when(
    child: &std::process::Child,
    ready: impl Fn() -> bool,
    wait: Duration,
) {
    let t = Instant::now();
    while !ready() && t.elapsed() < wait {
        std::thread::sleep(Duration::from_millis(50));
    }
    let ok = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
}

#[test]
fn ctrl_c_stops_a_run_keeping_its_rows_with_status_interrupted() {
    let d = tmp("sigint");
    // An hour of pendulum at 1 kHz: minutes of work, stopped after a second.
    let child = Command::new(env!("CARGO_BIN_EXE_towride"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR")))
        .args([
            "run",
            "scenes/examples/pendulum.toml",
            "--set",
            "pendulum.toml:run.end_time_s=3000",
            "--out",
        ])
        .arg(&d)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    interrupt_when(&child, || false, Duration::from_millis(1500));
    let out = child.wait_with_output().unwrap();
    let e = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{e}");
    assert!(e.contains("interrupted at t ="), "{e}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["status"], "interrupted");
    let t = s["interrupted_at_s"].as_f64().unwrap();
    assert!(t > 0.0 && t < 3000.0, "{t}");
    // Every row up to the stop: 1 kHz from t = 0, the last at the time reported.
    let csv = std::fs::read_to_string(d.join("outputs.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), (t * 1000.0).round() as usize + 1);
    let last: f64 = rows
        .last()
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((last - t).abs() < 1e-9, "{last} vs {t}");
    // Nothing left under a temporary name.
    for f in std::fs::read_dir(&d).unwrap() {
        let n = f.unwrap().file_name();
        assert!(!n.to_string_lossy().ends_with(".part"), "{n:?}");
    }
}

/// The command-line part of the fuzz harness: hostile numbers for numeric options are
/// refused by the argument parser, naming the option (they hung or ran absurd work).
#[test]
fn fuzz_numeric_options_are_refused_naming_the_option() {
    let scene = repo!("scenes/default.toml");
    let flex = repo!("flex/hitch_crossbeam.toml");
    let sweep = repo!("scenes/examples/pendulum_sweep.toml");
    let options: [(&[&str], &str); 8] = [
        (&["doctor", scene], "--step"),
        (&["run", scene], "--animation-rate-hz"),
        (&["linear", scene], "--at"),
        (&["modes", flex], "--cutoff"),
        (&["modes", flex], "--share"),
        (&["sweep", sweep], "--jobs"),
        (&["stress", scene], "--jobs"),
        (
            &["validate", "synth", "--obstacle", "bump_25mm"],
            "--speed-kmh",
        ),
    ];
    let mut n = 0;
    for (args, opt) in options {
        for v in ["nan", "inf", "-1", "1e300", "abc", "1,5"] {
            let arg = format!("{opt}={v}");
            let mut a: Vec<&str> = args.to_vec();
            a.push(&arg);
            refused(&a, &[opt]);
            n += 1;
        }
    }
    println!("fuzz (command line): {n} option values refused");
}

/// The summary table without its wall times (the one column that differs run to run).
fn summary_table(csv: &std::path::Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    let head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let wall = head.iter().position(|c| c == "wall_time [s]").unwrap();
    let mut rows = vec![head];
    for l in lines {
        // The length column is a quoted array: split outside quotes only.
        let mut cells = vec![String::new()];
        let mut quoted = false;
        for ch in l.chars() {
            match ch {
                '"' => quoted = !quoted,
                ',' if !quoted => cells.push(String::new()),
                _ => cells.last_mut().unwrap().push(ch),
            }
        }
        cells[wall].clear();
        rows.push(cells);
    }
    rows
}

#[test]
fn ctrl_c_stops_a_sweep_and_resume_finishes_it_with_the_same_summary() {
    // The pendulum sweep with 40 s runs: about half a second a case, so the signal
    // lands mid-sweep (after two cases are in the journal).
    let d = tmp("sweep_sigint");
    let ex = std::path::Path::new(repo!("scenes/examples"));
    let mech = std::fs::read_to_string(ex.join("pendulum.toml")).unwrap();
    assert!(mech.contains("end_time_s = 2.5"));
    std::fs::write(
        d.join("pendulum.toml"),
        mech.replacen("end_time_s = 2.5", "end_time_s = 40.0", 1),
    )
    .unwrap();
    std::fs::copy(ex.join("pendulum_sweep.toml"), d.join("sweep.toml")).unwrap();
    let sweep = d.join("sweep.toml");
    let (whole, parts) = (d.join("whole"), d.join("parts"));
    let sweep_args = |out: &std::path::Path| -> Vec<String> {
        ["sweep", sweep.to_str().unwrap(), "--jobs", "1", "--out"]
            .iter()
            .map(|s| s.to_string())
            .chain([out.to_str().unwrap().to_string()])
            .collect()
    };
    let o = Command::new(env!("CARGO_BIN_EXE_towride"))
        .args(sweep_args(&whole))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));

    let child = Command::new(env!("CARGO_BIN_EXE_towride"))
        .args(sweep_args(&parts))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let journal = parts.join("summary.csv.journal");
    // The journal's first line is its layout version; two case rows follow it.
    let finished = || std::fs::read_to_string(&journal).is_ok_and(|j| j.lines().count() >= 3);
    interrupt_when(&child, finished, Duration::from_secs(20));
    let out = child.wait_with_output().unwrap();
    let e = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{e}");
    assert!(e.contains("--resume"), "{e}");
    // The journal is folded into a whole summary: the finished cases completed, the
    // others marked interrupted, none missing.
    assert!(!journal.exists());
    let cut = summary_table(&parts.join("summary.csv"));
    let status = cut[0].iter().position(|c| c == "status").unwrap();
    let done = cut[1..].iter().filter(|r| r[status] == "completed").count();
    let stopped = cut[1..]
        .iter()
        .filter(|r| r[status] == "interrupted")
        .count();
    assert!(done >= 2 && stopped >= 1 && done + stopped == 6, "{cut:?}");

    let mut args = sweep_args(&parts);
    args.push("--resume".into());
    let o = Command::new(env!("CARGO_BIN_EXE_towride"))
        .args(&args)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(said.contains(&format!("{done} kept from before")), "{said}");
    assert_eq!(
        summary_table(&parts.join("summary.csv")),
        summary_table(&whole.join("summary.csv"))
    );
}

#[test]
fn ctrl_c_stops_a_sensitivity_study_with_its_partial_results_labelled() {
    let d = tmp("sens_sigint");
    // Morris, 1 + 2 x 3 runs of 200 s of the mass on a spring (about 0.4 s each).
    let child = Command::new(env!("CARGO_BIN_EXE_towride"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR")))
        .args([
            "sensitivity",
            "scenes/examples/mass_spring.toml",
            "--set",
            "mass_spring.toml:run.end_time_s=200",
            "--params",
            "mass_spring.toml:spring[0].stiffness_n_m,mass_spring.toml:body[0].mass_kg",
            "--outputs",
            "k1.force.freq",
            "--method",
            "morris",
            "--trajectories",
            "2",
            "--jobs",
            "1",
            "--json",
            "--out",
        ])
        .arg(&d)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    interrupt_when(
        &child,
        || t.elapsed() > Duration::from_millis(1200),
        Duration::from_secs(5),
    );
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    // Stopped after the base run: labelled, runs not started not called failed, no NaN.
    if let Ok(v) = serde_json::from_slice::<serde_json::Value>(&out.stdout) {
        assert_eq!(v["status"], "interrupted", "{v}");
        assert!(v["not_run"].as_u64().unwrap() > 0);
        assert_eq!(v["failed"].as_array().unwrap().len(), 0, "{v}");
        let page = std::fs::read_to_string(d.join("sensitivity.html")).unwrap();
        assert!(page.contains("interrupted:") && !page.contains("NaN"));
    } else {
        assert!(
            stderr(&out).contains("before the study's base run"),
            "{}",
            stderr(&out)
        );
    }
    std::fs::remove_dir_all(&d).ok();
}
