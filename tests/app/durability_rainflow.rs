//! Rainflow counting, Miner damage and DEL against independent references: the worked
//! example of ASTM E1049-85 (Fig. 6; counts as in the `rainflow` package's test and
//! qats' `cycles_rangemean` docstring, both implementations of section 5.4.4), closed
//! forms for a sine, and the Python `rainflow` package (PyPI) run in the test on a
//! random sequence.

use std::path::PathBuf;
use std::process::Command;

use towride_app::durability::{
    count, damage, del, rainflow::total_cycles, turning_points, Cycle, DurabilityError,
    RangeMeanMatrix, SnCurve,
};

fn sorted(mut c: Vec<(f64, f64, f64)>) -> Vec<(f64, f64, f64)> {
    c.sort_by(|a, b| a.partial_cmp(b).unwrap());
    c
}

fn triples(c: &[Cycle]) -> Vec<(f64, f64, f64)> {
    sorted(c.iter().map(|c| (c.range, c.mean, c.count)).collect())
}

#[test]
fn astm_e1049_worked_example_is_counted_exactly() {
    let x = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0];
    let tp = turning_points(&x, 0.0).unwrap();
    assert_eq!(tp, x.to_vec());
    let cycles = count(&tp);
    // Range, mean, count: one full cycle (4, 1), half cycles as ASTM Fig. 6 counts them.
    let expected = sorted(vec![
        (3.0, -0.5, 0.5),
        (4.0, -1.0, 0.5),
        (4.0, 1.0, 1.0),
        (8.0, 1.0, 0.5),
        (6.0, 1.0, 0.5),
        (8.0, 0.0, 0.5),
        (9.0, 0.5, 0.5),
    ]);
    assert_eq!(triples(&cycles), expected);
    // Per range: 3 (0.5), 4 (1.5), 6 (0.5), 8 (1.0), 9 (0.5).
    for (r, n) in [(3.0, 0.5), (4.0, 1.5), (6.0, 0.5), (8.0, 1.0), (9.0, 0.5)] {
        let got: f64 = cycles
            .iter()
            .filter(|c| c.range == r)
            .map(|c| c.count)
            .sum();
        assert_eq!(got, n, "range {r}");
    }
    assert_eq!(total_cycles(&cycles), 4.0);
    // Padded with the zeros qats' example starts and ends with: same cycles plus the
    // two outer half cycles (2, -1) and (2, -1).
    let padded = [0.0, -2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0, 0.0];
    let c = count(&turning_points(&padded, 0.0).unwrap());
    assert_eq!(total_cycles(&c), 5.0);
}

/// A cos(2 pi t / T) of amplitude `a` over `k` whole periods, `n` samples a period, the
/// last sample the final peak.
fn cosine(a: f64, k: usize, n: usize, offset: f64) -> Vec<f64> {
    (0..=k * n)
        .map(|j| offset + a * (2.0 * std::f64::consts::PI * j as f64 / n as f64).cos())
        .collect()
}

#[test]
fn a_sine_gives_k_cycles_of_range_2a_and_its_closed_form_damage() {
    let (a, k, m, s_ref, n_ref) = (350.0, 7, 3.0, 90.0, 2.0e6);
    let x = cosine(a, k, 64, 20.0);
    let cycles = count(&turning_points(&x, 0.0).unwrap());
    assert!((total_cycles(&cycles) - k as f64).abs() < 1e-12);
    for c in &cycles {
        assert!((c.range - 2.0 * a).abs() < 1e-9 * a, "{c:?}");
        assert!((c.mean - 20.0).abs() < 1e-9 * a, "{c:?}");
    }
    let curve = SnCurve::new(m, s_ref, n_ref).unwrap();
    let d = damage(&cycles, &curve);
    let closed = k as f64 * (2.0 * a / s_ref).powf(m) / n_ref;
    assert!((d / closed - 1.0).abs() < 1e-9, "{d} vs {closed}");
    // DEL at N_eq = k cycles is the range itself; at 2e6 it scales by (k / 2e6)^(1/m).
    assert!((del(&cycles, m, k as f64).unwrap() / (2.0 * a) - 1.0).abs() < 1e-9);
    let del_ref = del(&cycles, 5.0, n_ref).unwrap();
    let closed = 2.0 * a * (k as f64 / n_ref).powf(1.0 / 5.0);
    assert!((del_ref / closed - 1.0).abs() < 1e-9);

    // A sine from zero over k periods has turning points 0, A, -A, ..., A, -A, 0:
    // 2k - 1 ranges of 2A and two of A, each a half cycle (the starting-point rule).
    let x: Vec<f64> = (0..=k * 64)
        .map(|j| a * (2.0 * std::f64::consts::PI * j as f64 / 64.0).sin())
        .collect();
    let c = count(&turning_points(&x, 0.0).unwrap());
    let big: f64 = c
        .iter()
        .filter(|c| (c.range - 2.0 * a).abs() < 1e-6)
        .map(|c| c.count)
        .sum();
    let small: f64 = c
        .iter()
        .filter(|c| (c.range - a).abs() < 1e-6)
        .map(|c| c.count)
        .sum();
    assert!(
        (big - (k as f64 - 0.5)).abs() < 1e-12 && (small - 1.0).abs() < 1e-12,
        "{c:?}"
    );
}

#[test]
fn the_gate_drops_reversals_smaller_than_it() {
    // A cosine with a ripple of range 2 x 0.4 on it: the gate 1.0 removes the ripple.
    let x: Vec<f64> = cosine(10.0, 3, 200, 0.0)
        .iter()
        .enumerate()
        .map(|(j, v)| v + 0.4 * (2.0 * std::f64::consts::PI * j as f64 / 8.0).sin())
        .collect();
    let exact = count(&turning_points(&x, 0.0).unwrap());
    let gated = count(&turning_points(&x, 1.0).unwrap());
    assert!(
        total_cycles(&exact) > 3.0 + 10.0,
        "{}",
        total_cycles(&exact)
    );
    assert!((total_cycles(&gated) - 3.0).abs() < 1e-12, "{gated:?}");
}

#[test]
fn bad_input_is_a_typed_error() {
    assert!(matches!(
        turning_points(&[1.0, f64::NAN, 2.0], 0.0),
        Err(DurabilityError::NotFinite { index: 1, .. })
    ));
    assert_eq!(
        turning_points(&[1.0, 2.0], 0.0),
        Err(DurabilityError::TooShort { found: 2 })
    );
    assert!(matches!(
        turning_points(&[1.0, 2.0, 0.0], -1.0),
        Err(DurabilityError::Parameter { name: "gate", .. })
    ));
    assert!(SnCurve::new(0.0, 1.0, 1.0).is_err());
    assert!(del(&[], 3.0, -1.0).is_err());
}

#[test]
fn the_matrix_keeps_every_cycle_in_stated_bins() {
    let x = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0];
    let cycles = count(&turning_points(&x, 0.0).unwrap());
    let m = RangeMeanMatrix::of(&cycles, 9, 3).unwrap();
    assert_eq!(m.range_edges.first(), Some(&0.0));
    assert_eq!(m.range_edges.last(), Some(&9.0));
    let total: f64 = m.counts.iter().flatten().sum();
    assert_eq!(total, 4.0);
    // The last range bin [8, 9] holds ranges 8 (1.0) and 9 (0.5); bin [3, 4) range 3.
    assert_eq!(m.counts[8].iter().sum::<f64>(), 1.5);
    assert_eq!(m.counts[3].iter().sum::<f64>(), 0.5);
}

/// A venv under the target dir with the PyPI `rainflow` package, created on first use.
fn python_rainflow() -> PathBuf {
    let venv = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("rainflow-venv");
    crate::common::python_with(&venv, "rainflow", &["rainflow==3.2.0"])
}

#[test]
fn agrees_with_the_python_rainflow_package_on_a_random_sequence() {
    // A reproducible pseudo-random walk (64-bit LCG, Knuth's MMIX constants).
    let mut s: u64 = 20_261_127;
    let x: Vec<f64> = (0..2000)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 200.0
        })
        .collect();
    let ours = triples(&count(&turning_points(&x, 0.0).unwrap()));

    let py = python_rainflow();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("rainflow-compare");
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join("x.txt");
    let text: Vec<String> = x.iter().map(|v| format!("{v:e}")).collect();
    std::fs::write(&input, text.join("\n")).unwrap();
    let script = "import sys, rainflow\n\
        x = [float(l) for l in open(sys.argv[1])]\n\
        for r, m, n, i, j in rainflow.extract_cycles(x):\n    print(repr(r), repr(m), repr(n))\n";
    let out = Command::new(&py)
        .arg("-c")
        .arg(script)
        .arg(&input)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let theirs = sorted(
        String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(|l| {
                let v: Vec<f64> = l.split(' ').map(|t| t.parse().unwrap()).collect();
                (v[0], v[1], v[2])
            })
            .collect(),
    );
    assert!(theirs.len() > 500, "{} cycles", theirs.len());
    assert_eq!(ours.len(), theirs.len());
    for (a, b) in ours.iter().zip(&theirs) {
        assert!(
            (a.0 - b.0).abs() < 1e-12 * 200.0 && (a.1 - b.1).abs() < 1e-12 * 200.0 && a.2 == b.2,
            "{a:?} vs {b:?}"
        );
    }
}
