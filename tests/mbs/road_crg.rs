//! OpenCRG text files: a small LRFI file written here (10 long sections, so each record
//! spans two lines) read by `towride_mbs::road::crg` and by `pyopencrg` (PyPI, installed
//! into a venv under the test target's temporary folder), heights compared at nodes and
//! inside cells. Needs `python3` with `venv` and network access to PyPI.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use towride_mbs::input::Loader;
use towride_mbs::road::Road;

const NU: usize = 9;
const NV: usize = 10;

/// An irregular but reproducible surface [m] at cross-section i, long section j.
fn z(i: usize, j: usize) -> f64 {
    let (a, b) = (i as f64, j as f64);
    0.01 * (0.7 * a).sin() + 0.004 * (1.3 * b + 0.5 * a).cos() - 0.002 * b
        + 0.0005 * ((i * 7 + j * 3) % 5) as f64
}

fn write_crg(dir: &Path) -> PathBuf {
    let mut t = String::from(
        "$CT\nA small straight test road for towride (written by tests/mbs/road_crg.rs).\n$\n\
         $ROAD_CRG\nREFERENCE_LINE_START_U = 2.0\nREFERENCE_LINE_INCREMENT = 0.5\n\
         LONG_SECTION_V_RIGHT = -1.8\nLONG_SECTION_V_LEFT = 1.8\nLONG_SECTION_V_INCREMENT = 0.4\n$\n\
         $KD_Definition\n#:LRFI\n",
    );
    for j in 0..NV {
        let _ = writeln!(t, "D:long section {},m", j + 1);
    }
    t.push_str("$\n$$$$\n");
    for i in 0..NU {
        for j in 0..NV {
            let _ = write!(t, "{:10.7}", z(i, j));
            if j % 8 == 7 || j == NV - 1 {
                t.push('\n');
            }
        }
    }
    let p = dir.join("small.crg");
    std::fs::write(&p, t).unwrap();
    p
}

/// A folder of the test's own (tests run in parallel threads of one process).
fn dir(tag: &str) -> PathBuf {
    let d =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("crg-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A venv with pyopencrg, made once per target folder.
fn python() -> PathBuf {
    let venv = Path::new(env!("CARGO_TARGET_TMPDIR")).join("pyopencrg-venv");
    crate::common::python_with(&venv, "pyopencrg", &["pyopencrg==0.2.2"])
}

#[test]
fn heights_match_pyopencrg() {
    let d = dir("match");
    let crg = write_crg(&d);
    let toml = d.join("crg.toml");
    std::fs::write(&toml, "[road]\nkind = \"crg\"\nfile = \"small.crg\"\n").unwrap();
    let road = Road::from_file(&toml, &Loader::new()).unwrap();
    // Nodes and points inside cells (u from 2 to 6 m, v from -1.8 to 1.8 m).
    let mut pts = Vec::new();
    for k in 0..60 {
        let u = 2.0 + 4.0 * ((k as f64 * 0.618_034) % 1.0);
        let v = -1.8 + 3.6 * ((k as f64 * 0.414_214 + 0.1) % 1.0);
        pts.push((u, v));
    }
    pts.extend([(2.0, -1.8), (2.5, 0.2), (6.0, 1.8), (4.0, -0.6)]);
    let list: Vec<String> = pts.iter().map(|(u, v)| format!("({u},{v})")).collect();
    let script = format!(
        "import pyopencrg as crg\nr = crg.read({:?})\nfor u, v in [{}]:\n    print(float(r.uv_to_z(u, v)))\n",
        crg.to_str().unwrap(),
        list.join(",")
    );
    let out = Command::new(python())
        .args(["-c", &script])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let theirs: Vec<f64> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| l.trim().parse().unwrap())
        .collect();
    assert_eq!(theirs.len(), pts.len());
    for ((u, v), zt) in pts.iter().zip(&theirs) {
        let zo = road.height(*u, *v);
        // Both read the same 7-decimal text; pyopencrg may hold it in single precision.
        assert!(
            (zo - zt).abs() < 1e-6,
            "u {u} v {v}: ours {zo}, pyopencrg {zt}"
        );
    }
    // The nodes are the written values (the file's rounding: 5e-8).
    assert!((road.height(2.5, -1.4) - z(1, 1)).abs() < 6e-8);
    assert!((road.height(6.0, 1.8) - z(NU - 1, NV - 1)).abs() < 6e-8);
}

#[test]
fn unsupported_crg_is_refused_with_its_line() {
    let d = dir("bad");
    let crg = write_crg(&d);
    let text = std::fs::read_to_string(&crg).unwrap();
    let toml = d.join("bad.toml");
    std::fs::write(&toml, "[road]\nkind = \"crg\"\nfile = \"bad.crg\"\n").unwrap();
    for (from, to, want) in [
        ("#:LRFI", "#:KRBI", "bad.crg:12: data format KRBI"),
        (
            "REFERENCE_LINE_INCREMENT = 0.5",
            "REFERENCE_LINE_START_PHI = 0.3\nREFERENCE_LINE_INCREMENT = 0.5",
            "bad.crg:6: REFERENCE_LINE_START_PHI",
        ),
    ] {
        std::fs::write(d.join("bad.crg"), text.replacen(from, to, 1)).unwrap();
        let e = Road::from_file(&toml, &Loader::new())
            .unwrap_err()
            .to_string();
        assert!(e.contains(want) && e.contains("road.file"), "{e}");
    }
}
