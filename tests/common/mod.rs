//! Helpers shared by the test binaries.

#![allow(dead_code)]

use std::path::Path;

/// A number from a .tir file read by a plain line scan (independent of the crate's
/// reader): the first `KEY = value` line with that key inside `[section]`.
pub fn tir_value(file: &str, section: &str, key: &str) -> f64 {
    let text = std::fs::read_to_string(Path::new(file)).unwrap();
    let mut in_section = false;
    for line in text.lines() {
        let l = line.trim();
        if l.starts_with('[') {
            in_section = l == format!("[{section}]");
            continue;
        }
        if in_section {
            if let Some((k, v)) = l.split_once('=') {
                if k.trim() == key {
                    let v = v.split('$').next().unwrap().trim();
                    return v.parse().unwrap();
                }
            }
        }
    }
    panic!("{key} not in [{section}] of {file}");
}

/// Frequency [Hz] of the largest peak of the Hann-windowed spectrum of `y` (sampled every
/// `dt`) between `f_lo` and `f_hi`, by a direct DFT scan in 0.1 Hz steps.
pub fn dominant_frequency(y: &[f64], dt: f64, f_lo: f64, f_hi: f64) -> f64 {
    let n = y.len();
    let mean = y.iter().sum::<f64>() / n as f64;
    let w: Vec<f64> = (0..n)
        .map(|i| {
            let hann = 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / (n - 1) as f64).cos();
            (y[i] - mean) * hann
        })
        .collect();
    let mut best = (0.0, f_lo);
    let mut f = f_lo;
    while f <= f_hi {
        let (mut re, mut im) = (0.0, 0.0);
        for (i, v) in w.iter().enumerate() {
            let ph = 2.0 * std::f64::consts::PI * f * i as f64 * dt;
            re += v * ph.cos();
            im += v * ph.sin();
        }
        let mag = re * re + im * im;
        if mag > best.0 {
            best = (mag, f);
        }
        f += 0.1;
    }
    best.1
}

/// A small deterministic generator (xorshift64*) for the fuzz harnesses: the cases are
/// the same on every run.
pub struct Rng(pub u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    /// A number in `0..n`.
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// True when `msg` names a file with its line (`x.toml:12:`), and when a field.
pub fn located(msg: &str) -> (bool, bool) {
    let file_line = [".toml:", ".tir:", ".csv:", ".json:"].iter().any(|ext| {
        msg.match_indices(ext).any(|(i, _)| {
            msg[i + ext.len()..]
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_digit())
        })
    });
    (file_line, msg.contains("field `"))
}

/// A Python interpreter that can `import <import>`: a venv at `venv` (under the test
/// target's temporary folder), made and filled from PyPI with `packages` on first use.
/// The tests that compare with a well-known Python implementation share it.
pub fn python_with(venv: &Path, import: &str, packages: &[&str]) -> std::path::PathBuf {
    use std::process::Command;
    let py = venv.join("bin/python");
    let ok = |c: &mut Command| c.status().is_ok_and(|s| s.success());
    if !ok(Command::new(&py).args(["-c", &format!("import {import}")])) {
        assert!(
            ok(Command::new("python3").args(["-m", "venv"]).arg(venv)),
            "python3 -m venv {} failed (install python3-venv)",
            venv.display()
        );
        assert!(
            ok(Command::new(&py)
                .args(["-m", "pip", "install", "-q"])
                .args(packages)),
            "pip install {packages:?} failed (network access to PyPI needed)"
        );
    }
    py
}
