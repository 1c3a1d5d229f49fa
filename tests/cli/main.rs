//! The `towride` command as a user runs it: JSON fields, files written, clear errors.
//! One test binary for the CLI crate, a module per command.

/// A path to a file of the repository, as a `&'static str`.
macro_rules! repo {
    ($p:literal) => {
        concat!(env!("CARGO_MANIFEST_DIR"), "/", $p)
    };
}

#[path = "../app/validate_sim.rs"]
mod validate_sim;

#[path = "../common/mod.rs"]
mod common;

mod basics;
mod calibrate;
mod check;
mod comfort;
mod doctor;
mod fuzz_tools;
mod hard_cases;
mod inputs;
mod interrupt;
mod mf4;
mod modes;
mod out_guard;
mod overrides;
mod provenance;
mod rainflow;
mod reliability;
mod road;
mod sensitivity;
mod slurm;
mod slurm_real;
mod sway;
mod sway_friction;
mod sway_single_track;
mod sweep;
mod sweep_inputs;
mod sweep_rank;
mod tyre_rig;
mod validate_folder;
mod validate_pages;
mod validate_signal;

/// Runs the binary from the repository's root with `args`.
fn towride(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_towride"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR")))
        .args(args)
        .output()
        .expect("run towride")
}

/// Runs the binary with `args`, which must succeed (the panic shows its stderr), and
/// returns its output.
fn towride_ok(args: &[&str]) -> std::process::Output {
    let out = towride(args);
    assert!(
        out.status.success(),
        "towride {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The combination's sway mode from `towride linear`: the default scene rolling with the
/// ramp 60 m ahead, `sets` (FILE:PATH=VALUE) applied, its folder in `out`; the least
/// damped oscillation of the trailer body (lateral or yaw) between 0.3 and 3 Hz.
fn sway_mode(out: &std::path::Path, sets: &[String]) -> serde_json::Value {
    let s = "scenes/default.toml";
    let mut args: Vec<String> = ["linear", s, "--at", "0.05", "--json", "--out"]
        .iter()
        .map(|x| x.to_string())
        .collect();
    args.push(out.display().to_string());
    for x in std::iter::once(format!("{s}:road.obstacle_ahead_m=60")).chain(sets.iter().cloned()) {
        args.push("--set".into());
        args.push(x);
    }
    let v = towride_json(&args.iter().map(String::as_str).collect::<Vec<_>>());
    v["result"]["modes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| {
            let name = m["name"].as_str().unwrap_or("");
            let hz = m["damped_hz"].as_f64().unwrap_or(0.0);
            m["kind"] != "zero"
                && (0.3..3.0).contains(&hz)
                && name.starts_with("trailer_box")
                && (name.contains("lateral") || name.contains("yaw"))
        })
        .min_by(|a, b| {
            let z = |m: &serde_json::Value| m["damping_ratio"].as_f64().unwrap();
            z(a).total_cmp(&z(b))
        })
        .unwrap_or_else(|| panic!("no sway mode among {}", v["result"]["modes"]))
        .clone()
}

/// Runs the binary with `args` (including `--json`), which must succeed and print
/// exactly one JSON document; returns it.
fn towride_json(args: &[&str]) -> serde_json::Value {
    let out = towride_ok(args);
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "towride {}: not one JSON document ({e}): {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stdout)
        )
    })
}

/// Runs the binary with `args`, which must exit with `code`; returns its stderr.
fn towride_err(args: &[&str], code: i32) -> String {
    let out = towride(args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(
        out.status.code(),
        Some(code),
        "towride {}: {err}",
        args.join(" ")
    );
    err
}

/// The DOM of a report after its scripts ran in headless Chromium (Debian package
/// `chromium`, installed by `.ci/run`), and the `data-ready` attribute of its body (the
/// number of charts the page drew); panics on any JavaScript error the page recorded.
fn browser_dom(page: &std::path::Path) -> (String, Option<String>) {
    let profile = std::env::temp_dir().join(format!(
        "towride_cli_chromium_{}_{}",
        std::process::id(),
        page.display().to_string().len()
    ));
    let out = std::process::Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--virtual-time-budget=5000",
            "--window-size=1400,1000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("chromium (Debian package `chromium`) must be installed: .ci/run installs it");
    let _ = std::fs::remove_dir_all(&profile);
    let dom = String::from_utf8_lossy(&out.stdout).into_owned();
    let attr = |name: &str| -> Option<String> {
        let key = format!("{name}=\"");
        let a = dom.find(&key)? + key.len();
        Some(dom[a..a + dom[a..].find('"')?].to_string())
    };
    assert!(
        dom.contains("<body"),
        "no page: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        attr("data-errors"),
        None,
        "JavaScript errors in {}",
        page.display()
    );
    let ready = attr("data-ready");
    (dom, ready)
}
