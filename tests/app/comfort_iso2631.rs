//! ISO 2631-1 weightings and measures (`towride_app::comfort`) against the standard's
//! tabulated weighting factors and closed-form results.

use towride_app::comfort::metrics::{combined, measures, mtvv, Assessment};
use towride_app::comfort::{weighted_measures, Weighting, WeightingFilter};

/// Third-octave centres 0.5 to 80 Hz of ISO 2631-1 Table 3.
const F: [f64; 23] = [
    0.5, 0.63, 0.8, 1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0, 10.0, 12.5, 16.0, 20.0,
    25.0, 31.5, 40.0, 50.0, 63.0, 80.0,
];

/// ISO 2631-1 Table 3 weighting factors (printed x 1000: integers, one decimal below
/// 100) at [`F`], as transcribed in public code (two independent transcriptions agree;
/// see `docs/comfort.md`).
const WK: [f64; 23] = [
    0.418, 0.459, 0.477, 0.482, 0.484, 0.494, 0.531, 0.631, 0.804, 0.967, 1.039, 1.054, 1.036,
    0.988, 0.902, 0.768, 0.636, 0.513, 0.405, 0.314, 0.246, 0.186, 0.132,
];
const WD: [f64; 23] = [
    0.853, 0.944, 0.992, 1.011, 1.008, 0.968, 0.890, 0.776, 0.642, 0.512, 0.409, 0.323, 0.253,
    0.212, 0.161, 0.125, 0.100, 0.0800, 0.0632, 0.0494, 0.0388, 0.0295, 0.0211,
];

/// Half a unit of the table's last printed digit (x 1000: integers, then one decimal).
fn half_unit(t: f64) -> f64 {
    if t >= 0.1 {
        5e-4
    } else {
        5e-5
    }
}

/// The analogue definition reproduces the printed factors within their rounding plus
/// 0.05 % of the value (the largest excess seen is 0.03 %, Wk at 16 Hz: the standard
/// computed its table with its own rounding). One printed value disagrees with the
/// standard's own formula: Wd at 10 Hz, printed 212 where the formula gives 201.7 and
/// the neighbours (253 at 8 Hz, 161 at 12.5 Hz) fall smoothly through about 202.
#[test]
fn comfort_analogue_weighting_matches_iso_table() {
    for (w, table) in [(Weighting::Wk, WK), (Weighting::Wd, WD)] {
        for (f, t) in F.iter().zip(table) {
            let a = w.analogue_gain(*f);
            if w == Weighting::Wd && *f == 10.0 {
                assert!((a - 0.2017).abs() < 1e-4 && (a - t).abs() > 0.01, "{a}");
                continue;
            }
            let tol = half_unit(t) + 5e-4 * t;
            assert!((a - t).abs() <= tol, "{w:?} at {f} Hz: {a:.5} vs table {t}");
        }
    }
}

/// The digital filters at 1 kHz (the scenes' output rate) follow the analogue gain:
/// within 0.01 % up to 5 Hz, 0.1 % up to 12.5 Hz and 1.5 % up to 80 Hz, for every weighting. The bilinear
/// transform's warping grows as (f/rate)^2 away from the prewarped corners; 1.5 % is
/// 0.13 dB at 80 Hz, where the weightings are already below 0.14. Where a weighting
/// is below 0.01 (Wf above 2 Hz) the error is taken relative to 0.01. At 5 kHz the error
/// falls to 0.1 %.
#[test]
fn comfort_digital_weighting_follows_analogue() {
    for w in Weighting::ALL {
        for (rate, tol_hi) in [(1000.0, 0.015), (5000.0, 0.001)] {
            let d = WeightingFilter::new(w, rate).unwrap();
            for f in F.iter().chain(&[0.1, 0.16, 0.25]) {
                let (a, g) = (w.analogue_gain(*f), d.gain(*f));
                let tol = if *f <= 5.0 {
                    1e-4
                } else if *f <= 12.5 {
                    1e-3
                } else {
                    tol_hi
                };
                // Relative to the gain, or to 0.01 where the weighting cuts the band off.
                assert!(
                    (g - a).abs() / a.max(0.01) <= tol,
                    "{w:?} {rate} Hz at {f} Hz: {g} vs {a}"
                );
            }
        }
        // The digital factors at the table's frequencies against the printed ones.
        if w == Weighting::Wk {
            let d = WeightingFilter::new(w, 1000.0).unwrap();
            for (f, t) in F.iter().zip(WK) {
                assert!((d.gain(*f) / t - 1.0).abs() < 0.015, "{f} Hz");
            }
        }
    }
    assert!(WeightingFilter::new(Weighting::Wk, 150.0).is_none());
}

fn sine(a: f64, f: f64, rate: f64, t: f64) -> Vec<f64> {
    let n = (t * rate).round() as usize;
    (0..n)
        .map(|i| a * (2.0 * std::f64::consts::PI * f * i as f64 / rate).sin())
        .collect()
}

/// A pure sine through the filter: in steady state its weighted r.m.s. is
/// A/sqrt(2) x |W(f)| (the analogue gain) and its VDV over T whole periods is
/// (3/8)^(1/4) A |W| T^(1/4): the mean of sin^4 over whole periods is 3/8.
#[test]
fn comfort_sine_rms_and_vdv_closed_form() {
    let rate = 1000.0;
    for (w, f) in [
        (Weighting::Wk, 4.0),
        (Weighting::Wk, 1.0),
        (Weighting::Wd, 2.0),
    ] {
        let a = 1.7;
        let x = WeightingFilter::new(w, rate)
            .unwrap()
            .apply(&sine(a, f, rate, 30.0));
        // Drop the first 20 s: the 0.4 Hz high-pass has settled to 1e-6 by then.
        let tail = &x[20_000..];
        let m = measures(tail, 1.0 / rate).unwrap();
        let g = w.analogue_gain(f);
        let rms = a / 2f64.sqrt() * g;
        assert!(
            (m.rms_m_s2 / rms - 1.0).abs() < 1e-3,
            "{w:?} {f}: {m:?} vs {rms}"
        );
        let vdv = (3.0_f64 / 8.0).powf(0.25) * a * g * 10f64.powf(0.25);
        assert!((m.vdv_m_s1_75 / vdv - 1.0).abs() < 1e-3, "{m:?} vs {vdv}");
        // A steady sine: every 1 s window holds whole periods, MTVV equals a_w.
        assert!((m.mtvv_m_s2 / rms - 1.0).abs() < 1e-3);
        assert!((m.crest_factor - 2f64.sqrt()).abs() < 2e-3);
        assert!(!m.transient());
    }
    // Unweighted, sampled: the discrete mean of sin^4 over whole periods is exactly 3/8.
    let m = measures(&sine(2.0, 5.0, 1000.0, 4.0), 1e-3).unwrap();
    let vdv = (3.0_f64 / 8.0).powf(0.25) * 2.0 * 4f64.powf(0.25);
    assert!((m.vdv_m_s1_75 / vdv - 1.0).abs() < 1e-12);
}

/// MTVV uses the 1 s linear running r.m.s. (ISO 2631-1 eq. 2): a 0.5 s burst of a sine
/// of amplitude A in 10 s of quiet gives (A^2/2 x 0.5 s / 1 s)^(1/2) = A/2, while a_w
/// over the 10 s is A/sqrt(40); the crest and MTVV ratios flag it as transient.
#[test]
fn comfort_mtvv_of_a_burst() {
    let mut x = vec![0.0; 10_000];
    let burst = sine(3.0, 10.0, 1000.0, 0.5);
    x[4000..4500].copy_from_slice(&burst);
    assert!((mtvv(&x, 1e-3, 1.0) - 1.5).abs() < 1e-9);
    let m = measures(&x, 1e-3).unwrap();
    assert!((m.rms_m_s2 - 3.0 / 40f64.sqrt()).abs() < 1e-9);
    assert!(m.transient() && m.mtvv_m_s2 > 1.5 * m.rms_m_s2);
    assert!(measures(&[], 1e-3).is_none() && measures(&x, 0.0).is_none());
}

/// The vibration total value (ISO 2631-1 eq. 9) with comfort (1, 1, 1) and health
/// (1.4, 1.4, 1) factors; and the weighted measures of a channel in one call.
#[test]
fn comfort_combined_and_weighted_measures() {
    let r = [0.3, 0.4, 1.2];
    assert!((combined(r, Assessment::Comfort) - 1.3).abs() < 1e-12);
    let h = (0.42f64.powi(2) + 0.56f64.powi(2) + 1.44).sqrt();
    assert!((combined(r, Assessment::Health) - h).abs() < 1e-12);
    let x = sine(1.0, 8.0, 2000.0, 40.0);
    let m = weighted_measures(&x, 2000.0, Weighting::Wk).unwrap();
    // Whole record including the start transient: within 1 % of the steady value.
    let rms = Weighting::Wk.analogue_gain(8.0) / 2f64.sqrt();
    assert!((m.rms_m_s2 / rms - 1.0).abs() < 0.01, "{m:?}");
    assert!(weighted_measures(&x, 100.0, Weighting::Wk).is_none());
}
