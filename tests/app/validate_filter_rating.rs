//! The acquisition filter against the Butterworth definition, and the rating's behaviour:
//! identical curves rate 1, scaled or shifted curves lower, monotonically.

use std::f64::consts::PI;

use towride_app::signal::butterworth::Butterworth;
use towride_app::validate::rating::{corridor_score, iso_rating, phase_score, RatingParams};

/// |H(e^{iw})| of the cascade, evaluated here from the coefficients with complex
/// arithmetic written out (independent of the crate's own `magnitude`).
fn gain(f: &Butterworth, f_hz: f64) -> f64 {
    let w = 2.0 * PI * f_hz / f.rate_hz;
    let mut g = 1.0;
    for q in &f.sections {
        // z^-1 = cos w - i sin w.
        let zr = |k: f64| (k * w).cos();
        let zi = |k: f64| -(k * w).sin();
        let num = (
            q.b[0] + q.b[1] * zr(1.0) + q.b[2] * zr(2.0),
            q.b[1] * zi(1.0) + q.b[2] * zi(2.0),
        );
        let den = (
            1.0 + q.a[0] * zr(1.0) + q.a[1] * zr(2.0),
            q.a[0] * zi(1.0) + q.a[1] * zi(2.0),
        );
        g *= num.0.hypot(num.1) / den.0.hypot(den.1);
    }
    g
}

#[test]
fn butterworth_gain_at_dc_and_cutoff() {
    for order in 1..=8 {
        for rate in [500.0, 1000.0, 4000.0] {
            let f = Butterworth::low_pass(order, 100.0, rate).unwrap();
            assert_eq!(f.sections.len(), order.div_ceil(2));
            assert!(
                (gain(&f, 0.0) - 1.0).abs() < 1e-12,
                "order {order}, {rate} Hz: DC"
            );
            let fc = gain(&f, 100.0);
            assert!(
                (fc - 0.5_f64.sqrt()).abs() < 1e-6,
                "order {order}, {rate} Hz: {fc}"
            );
            assert!((f.magnitude(100.0) - fc).abs() < 1e-12);
            // Maximally flat: monotone fall-off, steeper with the order.
            let g: Vec<f64> = (0..50).map(|i| gain(&f, i as f64 * rate / 100.0)).collect();
            assert!(
                g.windows(2).all(|w| w[1] <= w[0] + 1e-12),
                "order {order}: not monotone"
            );
        }
    }
    // The analog Butterworth magnitude 1 / sqrt(1 + (f/fc)^(2n)) holds well below
    // Nyquist (the bilinear warp is small there).
    let f = Butterworth::low_pass(4, 100.0, 20000.0).unwrap();
    let analog = 1.0 / (1.0 + 0.5_f64.powi(8)).sqrt();
    assert!((gain(&f, 50.0) - analog).abs() < 1e-4);
    assert!(Butterworth::low_pass(4, 600.0, 1000.0).is_err());
}

#[test]
fn filtering_a_sine_at_the_cutoff_halves_its_power() {
    let rate = 4000.0;
    let f = Butterworth::low_pass(4, 100.0, rate).unwrap();
    let x: Vec<f64> = (0..8000)
        .map(|k| (2.0 * PI * 100.0 * k as f64 / rate).sin())
        .collect();
    let y = f.apply(&x);
    // Amplitude over the last 0.5 s (the transient has died away).
    let amp = y[6000..].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!((amp - 0.5_f64.sqrt()).abs() < 2e-3, "{amp}");
    // A constant passes unchanged from the first sample (steady-state start).
    let c = f.apply(&[2.5; 100]);
    assert!(c.iter().all(|v| (v - 2.5).abs() < 1e-12));
}

fn pulse(n: usize, shift: f64) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let t = k as f64 * 1e-3 - 0.3 - shift;
            if t < 0.0 {
                0.0
            } else {
                10.0 * (-6.0 * t).exp() * (2.0 * PI * 8.0 * t).sin()
            }
        })
        .collect()
}

#[test]
fn rating_of_identical_scaled_and_shifted_curves() {
    let n = 1500;
    let t = pulse(n, 0.0);
    let same = iso_rating(&t, &t, 1e-3);
    assert_eq!(same.overall, 1.0, "{same:?}");
    let mut last = 1.0;
    for k in [1.02, 1.05, 1.1, 1.2, 1.4, 1.8] {
        let c: Vec<f64> = t.iter().map(|v| v * k).collect();
        let r = iso_rating(&t, &c, 1e-3);
        eprintln!("scaled x{k}: {r:?}");
        assert!(r.overall < last, "x{k}: {} not below {last}", r.overall);
        last = r.overall;
    }
    let mut last = 1.0;
    for ms in [2.0, 5.0, 10.0, 20.0, 40.0, 80.0] {
        let c = pulse(n, ms * 1e-3);
        let r = iso_rating(&t, &c, 1e-3);
        eprintln!("shifted {ms} ms: {r:?}");
        assert!(r.overall < last, "{ms} ms: {} not below {last}", r.overall);
        last = r.overall;
    }
}

#[test]
fn sub_scores_follow_their_definitions() {
    let p = RatingParams::default();
    let t = pulse(1000, 0.0);
    // Corridor: recomputed point by point from the definition.
    let c: Vec<f64> = t.iter().map(|v| v * 1.3).collect();
    let tmax = t.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let expect: f64 = t
        .iter()
        .zip(&c)
        .map(|(a, b)| {
            let d = (a - b).abs();
            let (di, d_o) = (0.05 * tmax, 0.5 * tmax);
            if d <= di {
                1.0
            } else if d >= d_o {
                0.0
            } else {
                ((d_o - d) / (d_o - di)).powi(2)
            }
        })
        .sum::<f64>()
        / 1000.0;
    assert!((corridor_score(&t, &c, &p) - expect).abs() < 1e-12);
    // Phase: a pure delay of 25 samples of 1000 scores 1 - 25 / 200.
    let d = pulse(1000, 0.025);
    let (lag, score) = phase_score(&t, &d, &p);
    assert_eq!(lag, 25, "the compared curve is 25 samples late");
    assert!((score - (1.0 - 25.0 / 200.0)).abs() < 1e-12, "{score}");
}

/// Issue 31 item 11: a run page's spectra. Bounce at 1.2 Hz and pitch at 2.0 Hz in a 4 s
/// window at 500 Hz (a 10 km/h passage) are two peaks with a dip between (the run
/// report's Welch segments, 0.98 Hz apart here, made them one); the density keeps the
/// power (Parseval:
/// the integral is the mean square, a^2 / 2 per tone) and stops at the band's top.
#[test]
fn page_spectra_resolve_two_body_modes_and_keep_the_power() {
    use towride_app::validate::spectra::{band_hz, density};
    let fs = 500.0;
    let t: Vec<f64> = (0..2000).map(|k| k as f64 / fs).collect();
    let tone = |a: f64, f: f64, t: f64| a * (2.0 * std::f64::consts::PI * f * t).sin();
    let y: Vec<f64> = t
        .iter()
        .map(|&t| tone(1.0, 1.2, t) + tone(0.8, 2.0, t) + tone(0.1, 150.0, t))
        .collect();
    let p = density(&y, fs, 100.0).unwrap();
    let df = p.freq[1] - p.freq[0];
    assert!(df <= 0.25, "bins {df} Hz apart");
    assert!(*p.freq.last().unwrap() <= 100.0, "past the band");
    assert!((p.segment_s - 4.0).abs() < 1e-9 && p.segments == 1);
    let at = |f: f64| p.density[(f / df).round() as usize];
    let dip = (6..=7)
        .map(|k| at(1.2 + 0.1 * k as f64))
        .fold(f64::INFINITY, f64::min);
    assert!(
        dip < 0.5 * at(1.2).min(at(2.0)),
        "no dip between 1.2 and 2.0 Hz: {dip} against {} and {}",
        at(1.2),
        at(2.0)
    );
    // The tones' power below 100 Hz: (1 + 0.64) / 2; the 150 Hz tone is out of the band.
    let power: f64 = p.density.iter().sum::<f64>() * df;
    assert!((power / 0.82 - 1.0).abs() < 0.03, "power {power}");
    // The band: the lowest of the two Nyquist frequencies and the cut-off when known.
    assert_eq!(band_hz(500.0, 1000.0, 100.0), 100.0);
    assert_eq!(band_hz(2000.0, 500.0, f64::NAN), 250.0);
}
