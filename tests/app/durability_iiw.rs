//! The IIW check and the coupling rating: the IIW S-N curve's damage of a constant
//! amplitude cosine above and below the knee against the closed forms of the curve
//! (Hobbacher, IIW-2259-15, chapter 3: N = 2e6 (FAT / S)^3 to N = 1e7, slope 5 (variable)
//! or 22 (constant amplitude) beyond); a run's signed fibre stresses against its
//! envelope channels; the D-value against UN R55's formula for the shipped masses.

use std::path::Path;

use towride_app::durability::iiw::IiwCurve;
use towride_app::durability::{count, turning_points};
use towride_app::job::Job;
use towride_app::scene;
use towride_mbs::input::Loader;

fn cosine(a: f64, k: usize) -> Vec<f64> {
    (0..=k * 64)
        .map(|j| 5.0e6 + a * (2.0 * std::f64::consts::PI * j as f64 / 64.0).cos())
        .collect()
}

#[test]
fn constant_amplitude_damage_above_and_below_the_knee_matches_the_closed_form() {
    let fat = 71.0e6;
    let k = 9;
    // The knee range: 2e6 FAT^3 = 1e7 S_knee^3, so S_knee = FAT / 5^(1/3) = 41.52 MPa.
    let knee = fat / 5f64.powf(1.0 / 3.0);
    let va = IiwCurve::variable_amplitude(fat).unwrap();
    let ca = IiwCurve::constant_amplitude(fat).unwrap();
    assert!((va.knee_pa() / knee - 1.0).abs() < 1e-12);
    // Above the knee: a range of 100 MPa lives 2e6 (71/100)^3 = 715 822 cycles.
    let c = count(&turning_points(&cosine(50.0e6, k), 0.0).unwrap());
    let closed = k as f64 / (2.0e6 * (71.0f64 / 100.0).powi(3));
    for curve in [va, ca] {
        let d = curve.damage(&c);
        assert!((d / closed - 1.0).abs() < 1e-9, "{d} vs {closed}");
    }
    // Below: a range of 30 MPa lives 1e7 (S_knee / 30 MPa)^5 (variable amplitude) or
    // ^22 (constant amplitude).
    let c = count(&turning_points(&cosine(15.0e6, k), 0.0).unwrap());
    for (curve, m) in [(va, 5), (ca, 22)] {
        let closed = k as f64 / (1.0e7 * (knee / 30.0e6).powi(m));
        let d = curve.damage(&c);
        assert!((d / closed - 1.0).abs() < 1e-9, "m = {m}: {d} vs {closed}");
    }
    // The curve is continuous at the knee.
    assert!((va.cycles_to_failure(knee * (1.0 + 1e-12)) / 1e7 - 1.0).abs() < 1e-9);
    assert!((va.cycles_to_failure(knee * (1.0 - 1e-12)) / 1e7 - 1.0).abs() < 1e-9);
    assert!(IiwCurve::variable_amplitude(-1.0).is_err());
}

#[test]
fn a_run_checks_fibres_and_coupling_against_the_shipped_ratings() {
    let loader = Loader::new();
    let file = Path::new(repo!("scenes/default.toml"));
    let s = scene::load_with(file, &scene::Changes::default(), &loader).unwrap();
    let job = Job::from_scene(s).unwrap();
    let res = job.run(&towride_mbs::progress::Silent).unwrap();
    assert!(res.completed());
    // The box sections' four corners' signed stresses give the envelope channels
    // sample by sample.
    for p in ["weld_left", "weld_right", "ball_mount", "mid_span"] {
        let ch = |c: &str| res.channel(&format!("hitch_stress_{p}_{c}")).unwrap();
        let (hi, lo) = (ch("sx_max"), ch("sx_min"));
        let f: Vec<Vec<f64>> = (1..=4).map(|k| ch(&format!("sx_f{k}"))).collect();
        for j in 0..hi.len() {
            let mx = f.iter().map(|y| y[j]).fold(f64::MIN, f64::max);
            let mn = f.iter().map(|y| y[j]).fold(f64::MAX, f64::min);
            let tol = 1e-9 * hi[j].abs().max(lo[j].abs()).max(1.0);
            if p == "ball_mount" {
                // The hook's round section: the four fibres on the axes lie inside the
                // envelope N/A +- |M|/W and reach at least 1/sqrt(2) of its bending part.
                let axial = 0.5 * (f[0][j] + f[1][j]);
                let bend = f.iter().map(|y| (y[j] - axial).abs()).fold(0.0, f64::max);
                assert!(mx <= hi[j] + tol && mn >= lo[j] - tol, "{p} at {j}");
                assert!(bend >= (hi[j] - axial) / 2f64.sqrt() - tol, "{p} at {j}");
            } else {
                assert!(
                    (mx - hi[j]).abs() < tol && (mn - lo[j]).abs() < tol,
                    "{p} at {j}"
                );
            }
        }
    }
    let sum = &res.summary;
    assert_eq!(sum.fat_check.len(), 4);
    for c in &sum.fat_check {
        assert_eq!(c.fat_mpa, 71.0, "{c:?}");
        assert!(
            c.damage_per_passage > 0.0 && c.damage_per_passage < 1.0,
            "{c:?}"
        );
    }
    // UN R55: D = g T C / (T + C), from the shipped hitch file's masses.
    let t: toml::Value =
        toml::from_str(&std::fs::read_to_string(repo!("vehicles/fabia/hitch.toml")).unwrap())
            .unwrap();
    let r = &t["rating"];
    let (tm, cm) = (
        r["towing_vehicle_max_mass_kg"].as_float().unwrap() / 1000.0,
        r["trailer_max_mass_kg"].as_float().unwrap() / 1000.0,
    );
    let d_kn = 9.81 * tm * cm / (tm + cm);
    let cp = sum.coupling.as_ref().expect("the shipped hitch is rated");
    assert!((cp.rating.d_value_n / (1000.0 * d_kn) - 1.0).abs() < 1e-12);
    // 1.56 t and 1.0 t: D = 9.81 x 1.56 / 2.56 = 5.978 kN.
    assert!((cp.rating.d_value_n - 5977.97).abs() < 0.01, "{cp:?}");
    assert!((cp.rating.test_amplitude_n / cp.rating.d_value_n - 0.6).abs() < 1e-12);
    let (fx, fy, fz) = (
        res.channel("hitch_fx").unwrap(),
        res.channel("hitch_fy").unwrap(),
        res.channel("hitch_fz").unwrap(),
    );
    let peak = (0..fx.len())
        .map(|k| (fx[k].powi(2) + fy[k].powi(2) + fz[k].powi(2)).sqrt())
        .fold(0.0, f64::max);
    assert!((cp.ball_force_peak_n - peak).abs() < 1e-9 * peak);
    let amp = 0.5
        * (fx.iter().cloned().fold(f64::MIN, f64::max)
            - fx.iter().cloned().fold(f64::MAX, f64::min));
    // The largest rainflow range of a history is its max minus its min.
    assert!(
        (cp.fx_amplitude_n - amp).abs() < 1e-9 * amp,
        "{cp:?} vs {amp}"
    );
}
