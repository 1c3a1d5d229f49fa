//! The run summary's comfort block on the default scene (the thesis ramp at 50 km/h):
//! the floor sensor under the driver's seat weighted Wd, Wd, Wk; its z a_w against the
//! same weighting applied in the frequency domain (Parseval over a zero-padded DFT, with
//! the standard's analogue |W(f)|), the lateral axis near zero on a straight run over a
//! full-width ramp, and the passage flagged transient.

use std::path::Path;

use towride_app::comfort::{Weighting, FLOOR_SENSOR};
use towride_app::job::Job;
use towride_mbs::input::Loader;
use towride_mbs::progress::Silent;

/// The r.m.s. over `n` samples of `y` weighted by `w` in the frequency domain: the
/// record zero-padded to 8 times its length (so the weighting's ringing after the end
/// is kept, as the time-domain filter would not keep it: see the tolerance below), each
/// bin times the analogue |W(f)|, Parseval's sum over the bins.
fn rms_by_dft(y: &[f64], rate: f64, w: Weighting) -> f64 {
    let n = y.len();
    let m = 8 * n;
    let mut sum = 0.0;
    for k in 0..=m / 2 {
        let f = k as f64 * rate / m as f64;
        let (mut re, mut im) = (0.0, 0.0);
        for (i, v) in y.iter().enumerate() {
            let ph = -2.0 * std::f64::consts::PI * (k * i % m) as f64 / m as f64;
            re += v * ph.cos();
            im += v * ph.sin();
        }
        let both = if k == 0 || k == m / 2 { 1.0 } else { 2.0 };
        sum += both * (re * re + im * im) * w.analogue_gain(f).powi(2);
    }
    (sum / m as f64 / n as f64).sqrt()
}

#[test]
fn comfort_block_of_the_default_scene() {
    let job = Job::from_file(Path::new(repo!("scenes/default.toml")), &Loader::new())
        .unwrap()
        .without_view();
    let run = job.run(&Silent).unwrap();
    let c = run.summary.comfort.as_ref().expect("a comfort block");
    assert!(c.point.contains(FLOOR_SENSOR));
    let axes: Vec<(String, &str)> = c
        .axes
        .iter()
        .map(|a| (a.channel.clone(), a.weighting.name()))
        .collect();
    let want = |ax: &str| format!("acc_{FLOOR_SENSOR}_{ax}");
    assert_eq!(
        axes,
        [(want("x"), "wd"), (want("y"), "wd"), (want("z"), "wk")]
    );
    let z = &c.axes[2].measures;
    // The ramp's shock: crest factor above 3 and MTVV/a_w above 1.5 (ISO 2631-1 6.3.3).
    assert!(c.axes[2].transient && c.transient);
    assert!(
        z.mtvv_m_s2 > 1.5 * z.rms_m_s2 && z.crest_factor > 3.0,
        "{z:?}"
    );
    // Straight over a full-width ramp: no lateral motion beyond round-off.
    assert!(c.axes[1].measures.rms_m_s2 < 1e-4 * z.rms_m_s2);
    // Eq. 9 with k = 1.
    let r: Vec<f64> = c.axes.iter().map(|a| a.measures.rms_m_s2).collect();
    let total = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    assert!((c.total_value_m_s2.unwrap() / total - 1.0).abs() < 1e-12);
    // The time-domain filter stops at the record's end, the DFT keeps the ringing past it
    // in the padding, and the filter's bilinear warping is 1.5 % at 80 Hz; the two
    // agree within 4e-5 (the record's energy lies at the body's few hertz): 0.1 %.
    let y = run.channel(&want("z")).unwrap();
    let dft = rms_by_dft(&y, 1000.0, Weighting::Wk);
    assert!(
        (z.rms_m_s2 / dft - 1.0).abs() < 1e-3,
        "{} vs {dft}",
        z.rms_m_s2
    );
}
