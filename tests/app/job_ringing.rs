//! The hitch-force ringing estimator against synthetic damped sinusoids with known
//! damping ratio and frequency.

use std::f64::consts::PI;
use towride_app::job::ringing::ringing;

/// A forced rise, then x(t) = A exp(-zeta wn t) sin(wd t) after t0, over a slow trailer
/// bounce and a static offset, sampled at 1 kHz.
fn signal(zeta: f64, f_n: f64, t0: f64, slow_n: f64) -> (Vec<f64>, Vec<f64>) {
    let wn = 2.0 * PI * f_n;
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let t: Vec<f64> = (0..3000).map(|k| k as f64 * 1e-3).collect();
    let y = t
        .iter()
        .map(|&t| {
            let slow = 150.0 + slow_n * (2.0 * PI * 4.0 * t).sin();
            let ring = if t < t0 {
                0.0
            } else {
                -5000.0 * (-zeta * wn * (t - t0)).exp() * (wd * (t - t0) + 0.3).sin()
            };
            slow + ring
        })
        .collect();
    (t, y)
}

#[test]
fn damping_and_frequency_of_a_damped_sinusoid_are_recovered() {
    for (zeta, f) in [(0.03, 33.0), (0.08, 30.0), (0.015, 45.0)] {
        let fd = f * (1.0f64 - zeta * zeta).sqrt();
        // A slow motion that may carry more energy over the run than the ringing: the
        // decay is still the ringing's.
        let (t, y) = signal(zeta, f, 0.5, 300.0);
        let r = ringing("hitch_fx", &t, &y).unwrap();
        let z = r.damping_ratio.expect("damping fitted");
        assert!((z - zeta).abs() < 0.08 * zeta, "zeta {z} against {zeta}");
        // The ringing dominating, as in the hitch force.
        let (t, y) = signal(zeta, f, 0.5, 40.0);
        let r = ringing("hitch_fx", &t, &y).unwrap();
        let z = r.damping_ratio.expect("damping fitted");
        assert!((z - zeta).abs() < 0.08 * zeta, "zeta {z} against {zeta}");
        assert!((r.dominant_hz.unwrap() - fd).abs() < 0.5, "{r:?}");
        let d = r.decay.clone().unwrap();
        assert!((d.frequency_hz - fd).abs() < 0.02 * fd, "{d:?}");
        assert!(d.half_cycles >= 4 && d.fit_r2 > 0.99, "{d:?}");
        // RMS from its definition.
        let rms = (y.iter().map(|v| v * v).sum::<f64>() / y.len() as f64).sqrt();
        assert!((r.rms_n - rms).abs() < 1e-9 * rms);
        assert!(
            r.abs_peak_n > 4000.0 && r.t_abs_peak_s > 0.5 && r.t_abs_peak_s < 0.53,
            "{r:?}"
        );
        // |peak| is the larger magnitude of max and min, at the time of that one.
        assert_eq!(r.abs_peak_n, r.max_n.abs().max(r.min_n.abs()), "{r:?}");
        let side = if r.max_n.abs() >= r.min_n.abs() {
            r.t_max_s
        } else {
            r.t_min_s
        };
        assert_eq!(r.t_abs_peak_s, side, "{r:?}");
    }
}

#[test]
fn no_damping_without_a_decay() {
    // A steady sinusoid does not decay: no damping ratio is claimed.
    let t: Vec<f64> = (0..2000).map(|k| k as f64 * 1e-3).collect();
    let y: Vec<f64> = t.iter().map(|&t| (2.0 * PI * 20.0 * t).sin()).collect();
    let r = ringing("x", &t, &y).unwrap();
    assert!(r.damping_ratio.is_none(), "{r:?}");
    assert!((r.dominant_hz.unwrap() - 20.0).abs() < 0.2);
}
