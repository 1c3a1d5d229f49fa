//! Issue 36 item 2: ASAM MDF4 files written by asammdf (the reference implementation,
//! installed from PyPI into a venv cached in the target folder) validate exactly as the
//! text recording they were made from, and asammdf reads back what `run --format mf4`
//! writes.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::towride_ok;

/// A Python with asammdf and numpy: a venv under the target folder, made once.
fn asammdf_python() -> PathBuf {
    let venv = Path::new(env!("CARGO_TARGET_TMPDIR")).join("asammdf-venv");
    crate::common::python_with(&venv, "asammdf, numpy", &["asammdf", "numpy"])
}

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride-mf4-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn an_mf4_made_by_asammdf_validates_as_its_text_recording() {
    let py = asammdf_python();
    let dir = tmp("val");
    let stem = "bump_25mm_10kmh_200kg_ahead_of_axle";
    let src = Path::new(repo!("measurements/synthetic")).join(format!("{stem}.csv"));
    let desc = std::fs::read_to_string(src.with_extension("toml")).unwrap();
    let scene = repo!("scenes/bump_25mm.toml");
    let desc = desc.replace("\"../../scenes/bump_25mm.toml\"", &format!("{scene:?}"));
    std::fs::copy(&src, dir.join(format!("{stem}.csv"))).unwrap();
    std::fs::write(dir.join("text.toml"), &desc).unwrap();
    let mf4 = dir.join("rec.mf4");
    let ok = Command::new(&py)
        .arg(repo!("tests/app/csv_to_mf4.py"))
        .arg(&src)
        .arg(&mf4)
        .arg("10")
        .status()
        .unwrap()
        .success();
    assert!(ok, "asammdf conversion");
    let desc_mf4 = desc.replace(&format!("data = \"{stem}.csv\""), "data = \"rec.mf4\"");
    assert_ne!(desc, desc_mf4);
    std::fs::write(dir.join("mf4.toml"), desc_mf4).unwrap();
    let line = |d: &str| {
        let out = dir.join(format!("out-{d}"));
        let o = towride_ok(&[
            "validate",
            dir.join(format!("{d}.toml")).to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let text = String::from_utf8_lossy(&o.stdout).into_owned();
        // The lines after the run's name: rating, speed, shift, rate, passage.
        let at = text.find("[synthetic]").expect(&text);
        text[at..].lines().take(3).collect::<Vec<_>>().join("\n")
    };
    let (text, mdf) = (line("text"), line("mf4"));
    assert!(text.contains("rating") && text.contains("500 Hz"), "{text}");
    assert_eq!(text, mdf);
    // validate init reads both groups: the 50 Hz speed group is found as the speed.
    let init = dir.join("init.toml");
    towride_ok(&[
        "validate",
        "init",
        mf4.to_str().unwrap(),
        "--scene",
        scene,
        "--out",
        init.to_str().unwrap(),
    ]);
    let draft = std::fs::read_to_string(&init).unwrap();
    assert!(
        draft.contains("vehicle_speed (50.000000 Hz) resampled"),
        "{draft}"
    );
    assert!(draft.contains("column = \"vehicle_speed\""), "{draft}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn asammdf_reads_what_run_format_mf4_writes() {
    let py = asammdf_python();
    let dir = tmp("run");
    let d = dir.to_str().unwrap();
    towride_ok(&[
        "run",
        repo!("scenes/examples/two_mass_chain.toml"),
        "--out",
        d,
        "--format",
        "csv,mf4",
    ]);
    let script = r#"
import sys, numpy as np
from asammdf import MDF
m = MDF(sys.argv[1])
rows = [l.rstrip("\n").split(",") for l in open(sys.argv[2])]
head = [h.rsplit(" [", 1) for h in rows[0]]
data = np.array([[float(x) for x in r] for r in rows[1:]])
n = 0
for k, (name, unit) in enumerate(head[1:], start=1):
    s = m.get(name)
    assert s.unit == unit[:-1], (name, s.unit, unit)
    assert np.allclose(s.timestamps, data[:, 0], rtol=1e-9, atol=0), name
    assert np.allclose(s.samples, data[:, k], rtol=1e-9, atol=1e-300), name
    n += 1
print(n, len(data))
"#;
    let o = Command::new(&py)
        .args(["-c", script])
        .arg(dir.join("outputs.mf4"))
        .arg(dir.join("outputs.csv"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let said = String::from_utf8_lossy(&o.stdout);
    let n: Vec<usize> = said
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    assert!(n[0] > 0 && n[1] > 10, "{said}");
    std::fs::remove_dir_all(&dir).ok();
}
