//! The ISO 8608 random road against the standard's numbers: its displacement PSD (from a
//! periodogram written here, band-averaged) lies inside the class-C band from 0.05 to
//! 2 cycles/m and fits Gd(n0) = 256e-6 m^3 and w = 2; the left/right coherence matches the
//! stated model; the road is reproducible from its seed.

use std::path::Path;

use realfft::RealFftPlanner;
use towride_mbs::input::Loader;
use towride_mbs::road::Road;

/// ISO 8608:2016 class C (as reproduced by Loprencipe & Zoccali 2017): lower limit, geometric
/// mean and upper limit of Gd(n0) [m^3] at n0 = 0.1 cycles/m, waviness 2.
const C_LOWER: f64 = 128e-6;
const C_MEAN: f64 = 256e-6;
const C_UPPER: f64 = 512e-6;
const N0: f64 = 0.1;

fn class_c() -> Road {
    Road::from_file(
        Path::new(repo!("roads/iso8608_class_c.toml")),
        &Loader::new(),
    )
    .unwrap()
}

/// The two tracks sampled from the road's queries at y = +-B/2, one period (N samples).
fn tracks(r: &Road) -> (Vec<f64>, Vec<f64>, f64, f64) {
    let s = r.random_spec().unwrap();
    let n = s.samples();
    let dx = s.length / n as f64;
    let b = r.track_width().unwrap() / 2.0;
    let l = (0..n).map(|j| r.height(j as f64 * dx, b)).collect();
    let rr = (0..n).map(|j| r.height(j as f64 * dx, -b)).collect();
    (l, rr, dx, s.length)
}

/// One-sided spectrum X_k of a periodic record: the periodogram is 2 |X_k|^2 dx / N.
fn spectrum(z: &[f64]) -> Vec<realfft::num_complex::Complex<f64>> {
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(z.len());
    let mut input = z.to_vec();
    let mut out = fft.make_output_vec();
    fft.process(&mut input, &mut out).unwrap();
    out
}

/// Third-octave bands [lo, hi) from `from` up to `to` cycles/m.
fn bands(from: f64, to: f64) -> Vec<(f64, f64)> {
    let r = 2f64.powf(1.0 / 3.0);
    let mut v = Vec::new();
    let mut lo = from;
    while lo * r <= to * 1.0001 {
        v.push((lo, lo * r));
        lo *= r;
    }
    v
}

#[test]
fn class_c_psd_lies_in_the_class_band_and_fits_the_standard() {
    let r = class_c();
    let (l, rt, dx, len) = tracks(&r);
    let n = l.len();
    for z in [&l, &rt] {
        let x = spectrum(z);
        let (mut lx, mut ly) = (Vec::new(), Vec::new());
        for (lo, hi) in bands(0.05, 2.0) {
            let ks: Vec<usize> = (1..x.len())
                .filter(|&k| (lo..hi).contains(&(k as f64 / len)))
                .collect();
            assert!(ks.len() >= 10, "band {lo}..{hi}: {} harmonics", ks.len());
            let p: f64 = ks
                .iter()
                .map(|&k| 2.0 * x[k].norm_sqr() * dx / n as f64)
                .sum::<f64>()
                / ks.len() as f64;
            // The class limits averaged over the same harmonics.
            let shape: f64 = ks
                .iter()
                .map(|&k| (k as f64 / len / N0).powi(-2))
                .sum::<f64>()
                / ks.len() as f64;
            assert!(
                p > C_LOWER * shape && p < C_UPPER * shape,
                "band {lo:.3}..{hi:.3}: {p:e} outside {:e}..{:e}",
                C_LOWER * shape,
                C_UPPER * shape
            );
            let nc = (lo * hi).sqrt();
            lx.push((nc / N0).ln());
            ly.push((p / shape * (nc / N0).powi(-2)).ln());
        }
        // ISO 8608's fit: a straight line in log-log; slope -w, intercept ln Gd(n0).
        let m = lx.len() as f64;
        let (sx, sy) = (lx.iter().sum::<f64>(), ly.iter().sum::<f64>());
        let sxx: f64 = lx.iter().map(|a| a * a).sum();
        let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| a * b).sum();
        let slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
        let gd = ((sy - slope * sx) / m).exp();
        assert!((slope + 2.0).abs() < 0.05, "w = {}", -slope);
        assert!((gd / C_MEAN - 1.0).abs() < 0.1, "Gd(n0) = {gd:e}");
    }
}

#[test]
fn left_right_coherence_follows_the_stated_model() {
    // The shipped road's model, 10 km long: 10x the harmonics per band, so the estimate's
    // scatter (below) is small enough to tell the model from, say, gamma^2 in its place.
    let text = std::fs::read_to_string(repo!("roads/iso8608_class_c.toml")).unwrap();
    let dir = std::env::temp_dir().join(format!("towride-random-coh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let long = dir.join("long.toml");
    std::fs::write(
        &long,
        text.replace("length_m = 1000.0", "length_m = 10000.0"),
    )
    .unwrap();
    let r = Road::from_file(&long, &Loader::new()).unwrap();
    let s = r.random_spec().unwrap().clone();
    let (l, rt, _, len) = tracks(&r);
    let (xl, xr) = (spectrum(&l), spectrum(&rt));
    let mut checked = 0;
    for (lo, hi) in bands(0.05, 2.0) {
        let ks: Vec<usize> = (1..xl.len())
            .filter(|&k| (lo..hi).contains(&(k as f64 / len)))
            .collect();
        // Frequency-smoothed (Daniell) cross- and auto-spectra over the band's harmonics.
        let sxy: realfft::num_complex::Complex<f64> =
            ks.iter().map(|&k| xl[k] * xr[k].conj()).sum();
        let sxx: f64 = ks.iter().map(|&k| xl[k].norm_sqr()).sum();
        let syy: f64 = ks.iter().map(|&k| xr[k].norm_sqr()).sum();
        let msc = sxy.norm_sqr() / (sxx * syy);
        // The model's expectation over the same harmonics, weighted by their power
        // (gamma = exp(-c n B), the model written out here, not the code's function).
        let w: Vec<f64> = ks.iter().map(|&k| (k as f64 / len).powi(-2)).collect();
        let sw: f64 = w.iter().sum();
        let g: f64 = ks
            .iter()
            .zip(&w)
            .map(|(&k, wk)| wk * (-s.coherence_decay * (k as f64 / len) * s.track_width).exp())
            .sum::<f64>()
            / sw;
        let k_eff = sw * sw / w.iter().map(|a| a * a).sum::<f64>();
        // Random error of a coherence estimate from k_eff independent averages
        // (Bendat & Piersol, Random Data, 4th ed., eq. 9.82):
        // sigma[gamma^2] = sqrt(2) |gamma| (1 - gamma^2) / sqrt(k_eff), plus the bias of an
        // estimate of zero coherence, ~1/k_eff. Four sigma.
        let tol = 4.0 * 2f64.sqrt() * g * (1.0 - g * g) / k_eff.sqrt() + 2.0 / k_eff;
        assert!(
            (msc - g * g).abs() < tol,
            "band {lo:.3}..{hi:.3}: coherence^2 {msc:.3}, model {:.3} +- {tol:.3}",
            g * g
        );
        checked += 1;
    }
    assert!(checked >= 15);
}

#[test]
fn seeded_and_reproducible() {
    let text = std::fs::read_to_string(repo!("roads/iso8608_class_c.toml")).unwrap();
    let dir = std::env::temp_dir().join(format!("towride-random-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let other = dir.join("seed.toml");
    std::fs::write(&other, text.replace("seed = 8608", "seed = 8609")).unwrap();
    let a = class_c();
    let b = class_c();
    let c = Road::from_file(&other, &Loader::new()).unwrap();
    let xs = [0.0, 1.234, 50.0, 999.9];
    for x in xs {
        assert_eq!(a.height(x, 0.5).to_bits(), b.height(x, 0.5).to_bits());
    }
    assert!(xs[1..]
        .iter()
        .any(|&x| a.height(x, 0.5) != c.height(x, 0.5)));
    // Starts and ends at z = 0 (a constant shift per track), flat outside.
    assert_eq!(a.height(0.0, 0.715), 0.0);
    assert_eq!(a.height(-3.0, 0.0), 0.0);
    assert_eq!(a.height(1003.0, -0.715), 0.0);
}

#[test]
fn bad_random_roads_are_refused_with_the_field() {
    let base = std::fs::read_to_string(repo!("roads/iso8608_class_c.toml")).unwrap();
    let dir = std::env::temp_dir().join(format!("towride-random-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (from, to, field) in [
        ("class = \"C\"", "class = \"K\"", "class"),
        ("dx_m = 0.05", "dx_m = 0.07", "dx_m"),
        (
            "n_max_cycles_per_m = 10.0",
            "n_max_cycles_per_m = 11.0",
            "n_max_cycles_per_m",
        ),
        ("class = \"C\"", "class = \"C\"\ngd_n0_m3 = 1e-4", "class"),
    ] {
        let p = dir.join("bad.toml");
        std::fs::write(&p, base.replace(from, to)).unwrap();
        let e = Road::from_file(&p, &Loader::new()).unwrap_err().to_string();
        assert!(e.contains(field) && e.contains("bad.toml"), "{e}");
    }
}
