//! Issue 32: what commands read and write. No command overwrites one of its inputs;
//! a named pipe, a device or a folder given as a file is refused at once (they used to
//! block forever or read until memory ran out); a survey of nothing is an error; a
//! comparison says which channels it cannot compare.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride_inputs_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs towride with `args`, killed after 20 s (a hang fails the test instead of
/// hanging it); returns the exit code (None when killed) and stderr.
fn bounded(args: &[&str]) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_towride"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    let code = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s.code();
        }
        if t.elapsed() > Duration::from_secs(20) {
            child.kill().ok();
            child.wait().ok();
            break None;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut err = String::new();
    use std::io::Read;
    child.stderr.take().unwrap().read_to_string(&mut err).ok();
    (code, err)
}

/// Refused at once with exit code 2 and a message containing every one of `says`.
fn refused(args: &[&str], says: &[&str]) {
    let (code, e) = bounded(args);
    assert_eq!(code, Some(2), "{args:?} (None: killed after 20 s): {e}");
    assert!(!e.contains("panicked"), "{e}");
    for s in says {
        assert!(e.contains(s), "{args:?}: `{s}` not in: {e}");
    }
}

fn recording(dir: &Path, name: &str) -> PathBuf {
    let mut t = String::from("time [s];FL Sprung acceleration [g];RR Sprung acceleration [g]\n");
    for k in 0..20 {
        t.push_str(&format!("{};1;1\n", k as f64 * 1e-3));
    }
    let f = dir.join(name);
    std::fs::write(&f, &t).unwrap();
    f
}

#[test]
fn validate_init_never_overwrites_its_inputs() {
    let scene = repo!("scenes/default.toml");
    let d = tmp("init_self");
    // A recording named .toml: the default --out is the recording itself.
    let rec = recording(&d, "run.toml");
    let before = std::fs::read(&rec).unwrap();
    let r = rec.to_str().unwrap();
    refused(
        &["validate", "init", r, "--scene", scene, "--force"],
        &["run.toml", "is the recording", "never overwrites its input"],
    );
    // Named through another path, a symbolic link and a hard link.
    let other = d.join("sub/../run.toml");
    std::fs::create_dir_all(d.join("sub")).unwrap();
    std::os::unix::fs::symlink(&rec, d.join("link.toml")).unwrap();
    std::fs::hard_link(&rec, d.join("hard.toml")).unwrap();
    for out in [other, d.join("link.toml"), d.join("hard.toml")] {
        let o = out.to_str().unwrap();
        refused(
            &[
                "validate", "init", r, "--scene", scene, "--out", o, "--force",
            ],
            &["is the recording", "(the same file)"],
        );
    }
    assert_eq!(
        std::fs::read(&rec).unwrap(),
        before,
        "the recording was changed"
    );
    // The scene is an input too.
    let copy = d.join("scene.toml");
    std::fs::copy(scene, &copy).unwrap();
    let csv = recording(&d, "run.csv");
    refused(
        &[
            "validate",
            "init",
            csv.to_str().unwrap(),
            "--scene",
            copy.to_str().unwrap(),
            "--out",
            copy.to_str().unwrap(),
            "--force",
        ],
        &["is the scene"],
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn validate_init_says_what_is_wrong_with_a_rate() {
    let scene = repo!("scenes/default.toml");
    let d = tmp("init_rate");
    let rec = recording(&d, "run.csv");
    let r = rec.to_str().unwrap();
    let out = d.join("run_draft.toml");
    let o = out.to_str().unwrap();
    let args = |rate: &'static str| -> Vec<&str> {
        vec![
            "validate",
            "init",
            r,
            "--scene",
            scene,
            "--out",
            o,
            "--rate-hz",
            rate,
        ]
    };
    refused(&args("0"), &["--rate-hz", "must not be 0", "accepted"]);
    refused(&args("1e12"), &["--rate-hz", "accepted range"]);
    refused(
        &args("1000"),
        &["the file has a time column `time`; --rate-hz applies only to files without one"],
    );
    assert!(!out.exists());
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn what_is_not_a_regular_file_is_refused_at_once() {
    let scene = repo!("scenes/default.toml");
    let d = tmp("fifo");
    let fifo = d.join("pipe.csv");
    let ok = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(ok.success());
    let p = fifo.to_str().unwrap();
    let out = d.join("x.toml");
    let o = out.to_str().unwrap();
    refused(
        &["validate", "init", p, "--scene", scene, "--out", o],
        &["pipe.csv", "is a named pipe, not a regular file"],
    );
    refused(&["provenance", p], &["pipe.csv", "is a named pipe"]);
    refused(&["provenance", "/dev/zero"], &["/dev/zero", "is a device"]);
    refused(&["provenance", "/dev/null"], &["/dev/null", "is a device"]);
    // Larger than the caps (sparse files: nothing is written or read): refused by size.
    let big = d.join("big.toml");
    std::fs::File::create(&big)
        .unwrap()
        .set_len((64 << 20) + 1)
        .unwrap();
    refused(
        &["provenance", big.to_str().unwrap()],
        &["big.toml", "is 65 MiB, more than the 64 MiB read"],
    );
    let huge = d.join("huge.csv");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len((1 << 30) + 1)
        .unwrap();
    refused(
        &[
            "validate",
            "init",
            huge.to_str().unwrap(),
            "--scene",
            scene,
            "--out",
            o,
        ],
        &["huge.csv", "more than the 1024 MiB read"],
    );
    // A comparison's outputs.csv a pipe.
    let (a, b) = (d.join("a"), d.join("b"));
    std::fs::create_dir_all(&a).unwrap();
    std::fs::create_dir_all(&b).unwrap();
    std::fs::write(a.join("outputs.csv"), "time [s],x [m]\n0,0\n1,1\n").unwrap();
    Command::new("mkfifo")
        .arg(b.join("outputs.csv"))
        .status()
        .unwrap();
    refused(
        &[
            "compare",
            a.to_str().unwrap(),
            b.to_str().unwrap(),
            "--out",
            d.join("c").to_str().unwrap(),
        ],
        &["outputs.csv", "is a named pipe"],
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn provenance_of_nothing_is_an_error() {
    let d = tmp("prov_empty");
    refused(
        &["provenance", d.to_str().unwrap()],
        &["no property file (.toml or .tir) in this folder"],
    );
    let f = d.join("empty.toml");
    std::fs::write(&f, "\n  \n").unwrap();
    refused(
        &["provenance", f.to_str().unwrap()],
        &["empty.toml", "is empty"],
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn compare_marks_modal_coordinates_of_different_bases_and_refuses_units() {
    let d = tmp("cmp");
    let mk = |name: &str, variant: u64, unit: &str| {
        let r = d.join(name);
        std::fs::create_dir_all(&r).unwrap();
        let mut t = format!("time [s],hitch_fz [{unit}],hitch_eta_1 [-]\n");
        for k in 0..=10 {
            t.push_str(&format!("{},{k},{k}\n", k as f64 * 0.1));
        }
        std::fs::write(r.join("outputs.csv"), t).unwrap();
        let s = serde_json::json!({
            "scene": {"hitch_variant": variant},
            "modal_energy": [{"body": "hitch", "modes": [{"number": 7 + variant, "frequency_hz": 100.0 * variant as f64}]}],
        });
        std::fs::write(r.join("summary.json"), s.to_string()).unwrap();
        r.to_str().unwrap().to_string()
    };
    let (v1, v10, g) = (mk("v1", 1, "N"), mk("v10", 10, "N"), mk("g", 1, "g"));
    let out = d.join("out");
    let o = out.to_str().unwrap();
    let res = crate::towride_ok(&["compare", &v1, &v10, "--out", o]);
    let text = String::from_utf8_lossy(&res.stdout);
    let line = text
        .lines()
        .find(|l| l.contains("hitch_eta_1"))
        .unwrap_or("");
    assert!(
        line.contains("not comparable (different modal bases)"),
        "{text}"
    );
    assert!(
        line.contains("variant 10") && !line.contains("RMS"),
        "{text}"
    );
    let v = crate::towride_json(&["compare", &v1, &v10, "--out", o, "--json"]);
    assert_eq!(v["schema_version"], 3);
    assert_eq!(v["not_comparable"][0]["channels"][0], "hitch_eta_1");
    assert!(v["differences"]
        .as_array()
        .unwrap()
        .iter()
        .all(|d| d["channel"] == "hitch_fz"));
    refused(
        &["compare", &v1, &g, "--out", o],
        &["g/outputs.csv:1", "hitch_fz", "unit [g] does not convert"],
    );
    std::fs::remove_dir_all(&d).ok();
}
