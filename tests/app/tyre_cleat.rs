//! Cleat rig: the wheel centre moves at constant speed and height over a 10 mm cleat and
//! over the thesis's ramp. The force histories ring at the tyre's belt resonance (checked
//! against the frequency that follows from the .tir file's ring data), and their peaks do
//! not depend on the solver tolerance (rtol 1e-4 vs 1e-6 within 1 %).

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use towride_app::report::lineplot::{line_panels, Line, LinePanel};
use towride_mbs::road::Road;
use towride_mbs::tyre::rig::{rig_options, CleatRig, RigRun, Spin};
use towride_mbs::tyre::{Tyre, TyreKind};

const CAR: &str = repo!("vehicles/tyres/car_185_60r14.tir");
const DT: f64 = 1e-4;

fn run(road: &str, speed: f64, rtol: f64, t_end: f64) -> RigRun {
    let tyre = Tyre::from_file(
        Path::new(CAR),
        TyreKind::RigidRing,
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let road = Road::from_file(Path::new(road), &towride_mbs::input::Loader::new()).unwrap();
    let rig = CleatRig::new(tyre, road, speed, 0.0, 3500.0, Spin::Free, 0.6);
    let opts = rig_options(&rig.tyre, rtol, &[1e-3]);
    rig.run(t_end, DT, &opts).unwrap()
}

struct Peaks {
    fz_max: f64,
    fx_min: f64,
    fx_max: f64,
}

fn peaks(r: &RigRun) -> Peaks {
    Peaks {
        fz_max: r
            .samples
            .iter()
            .map(|s| s.hub_fz_n)
            .fold(f64::MIN, f64::max),
        fx_min: r
            .samples
            .iter()
            .map(|s| s.hub_fx_n)
            .fold(f64::MAX, f64::min),
        fx_max: r
            .samples
            .iter()
            .map(|s| s.hub_fx_n)
            .fold(f64::MIN, f64::max),
    }
}

/// Vertical ring mode with the tyre on the road, from the file: sidewall c_b = m_b (2 pi
/// f)^2 in parallel with the residual spring c_r = C_z c_b / (c_b - C_z) (rim held).
fn loaded_vertical_frequency() -> f64 {
    let m_b = crate::common::tir_value(CAR, "INERTIA", "BELT_MASS");
    let f = crate::common::tir_value(CAR, "STRUCTURAL", "FREQ_LONG");
    let cz = crate::common::tir_value(CAR, "VERTICAL", "VERTICAL_STIFFNESS");
    let c_b = m_b * (2.0 * PI * f).powi(2);
    let c_r = cz * c_b / (c_b - cz);
    ((c_b + c_r) / m_b).sqrt() / (2.0 * PI)
}

/// In-plane modes of the ring with the tyre on the road and the rim free to spin, from
/// the file's numbers: rim rotation (inertia `rim_iyy`), ring rotation (BELT_IYY) and ring
/// translation (BELT_MASS); wind-up spring between rim and ring, sidewall spring from the
/// ring to the (held) wheel centre, and at the contact point (which moves by x_b - r phi_b)
/// the residual spring in series with the tread (slip stiffness / half contact length,
/// the brush's stiffness before it relaxes). Returns the frequencies [Hz], lowest first.
fn in_plane_modes(rim_iyy: f64) -> Vec<f64> {
    use nalgebra::{Matrix3, SymmetricEigen};
    let t = |s: &str, k: &str| crate::common::tir_value(CAR, s, k);
    let m_b = t("INERTIA", "BELT_MASS");
    let i_b = t("INERTIA", "BELT_IYY");
    let c_b = m_b * (2.0 * PI * t("STRUCTURAL", "FREQ_LONG")).powi(2);
    let c_th = i_b * (2.0 * PI * t("STRUCTURAL", "FREQ_WINDUP")).powi(2);
    let cz = t("VERTICAL", "VERTICAL_STIFFNESS");
    let fz0 = t("VERTICAL", "FNOMIN");
    let r0 = t("DIMENSION", "UNLOADED_RADIUS");
    let r = r0 - fz0 / cz;
    let c_rx = 1.0 / (1.0 / t("STRUCTURAL", "LONGITUDINAL_STIFFNESS") - 1.0 / c_b - r * r / c_th);
    // Half contact length at the nominal load and slip stiffness PKX1 FNOMIN.
    let q = fz0 / cz / r0;
    let a = r0 * (t("CONTACT_PATCH", "Q_RA2") * q + t("CONTACT_PATCH", "Q_RA1") * q.sqrt());
    let k_tread = t("LONGITUDINAL_COEFFICIENTS", "PKX1") * fz0 / a;
    let k_c = 1.0 / (1.0 / c_rx + 1.0 / k_tread);
    // Unknowns (phi_w, phi_b, x_b).
    let k = Matrix3::new(
        c_th,
        -c_th,
        0.0,
        -c_th,
        c_th + k_c * r * r,
        -k_c * r,
        0.0,
        -k_c * r,
        c_b + k_c,
    );
    let m = [rim_iyy, i_b, m_b];
    let mut a_sym = k;
    for i in 0..3 {
        for j in 0..3 {
            a_sym[(i, j)] /= (m[i] * m[j]).sqrt();
        }
    }
    let mut f: Vec<f64> = SymmetricEigen::new(a_sym)
        .eigenvalues
        .iter()
        .map(|l| l.max(0.0).sqrt() / (2.0 * PI))
        .collect();
    f.sort_by(f64::total_cmp);
    f
}

fn out_dir() -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("tyre");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn check(name: &str, road: &str, speed: f64, after_x: f64) -> RigRun {
    let t_end = (after_x + 0.6) / speed;
    let coarse = run(road, speed, 1e-4, t_end);
    let fine = run(road, speed, 1e-6, t_end);
    let (a, b) = (peaks(&coarse), peaks(&fine));
    let rel = |x: f64, y: f64| (x / y - 1.0).abs();
    println!(
        "{name}: peaks rtol 1e-4 / 1e-6: Fz max {:.1} / {:.1} N, Fx min {:.1} / {:.1} N, Fx max {:.1} / {:.1} N; steps {} / {}",
        a.fz_max, b.fz_max, a.fx_min, b.fx_min, a.fx_max, b.fx_max, coarse.stats.steps, fine.stats.steps
    );
    assert!(rel(a.fz_max, b.fz_max) < 0.01);
    assert!(rel(a.fx_min, b.fx_min) < 0.01);
    assert!(rel(a.fx_max, b.fx_max) < 0.01);

    // Free vibration once the cams have left the obstacle.
    let tail: Vec<_> = fine.samples.iter().filter(|s| s.x_m > after_x).collect();
    let fz: Vec<f64> = tail.iter().map(|s| s.hub_fz_n).collect();
    let fx: Vec<f64> = tail.iter().map(|s| s.hub_fx_n).collect();
    let f_z = crate::common::dominant_frequency(&fz, DT, 20.0, 300.0);
    let f_x = crate::common::dominant_frequency(&fx, DT, 20.0, 300.0);
    let f_ref = loaded_vertical_frequency();
    let f_long = crate::common::tir_value(CAR, "STRUCTURAL", "FREQ_LONG");
    println!(
        "{name}: dominant frequency Fz {f_z:.1} Hz (loaded vertical ring mode from the file {f_ref:.1} Hz), Fx {f_x:.1} Hz (FREQ_LONG {f_long} Hz)"
    );
    assert!(
        (f_z / f_ref - 1.0).abs() < 0.05,
        "Fz rings at {f_z} Hz, expected {f_ref}"
    );
    // Fx rings at one of the in-plane modes (rim-and-ring rotation, ring fore-aft).
    let modes = in_plane_modes(0.6);
    let nearest = modes
        .iter()
        .map(|m| (f_x / m - 1.0).abs())
        .fold(f64::MAX, f64::min);
    println!(
        "{name}: in-plane modes from the file {modes:.1?} Hz; Fx within {:.1} % of one",
        100.0 * nearest
    );
    assert!(nearest < 0.15, "Fx rings at {f_x} Hz, modes {modes:?}");
    fine
}

#[test]
fn cleat_and_ramp_show_the_ring_resonance() {
    // 10 mm x 20 mm cleat at 1 m, 40 km/h; cams clear it 0.34 m after its edge.
    let cleat = check(
        "cleat 10 mm, 40 km/h",
        repo!("roads/cleat_10mm.toml"),
        40.0 / 3.6,
        1.40,
    );
    // The thesis ramp at 20 km/h with the axle height held (drum-rig style).
    let ramp = check(
        "ramp 50 mm, 20 km/h",
        repo!("roads/ramp_thesis.toml"),
        20.0 / 3.6,
        1.85,
    );
    let panel = |r: &RigRun, name: &str| LinePanel {
        title: format!("{name}: load on the rim"),
        x_label: "time [s]".into(),
        y_label: "force [N]".into(),
        lines: vec![
            Line {
                label: "vertical Fz".into(),
                points: r.samples.iter().map(|s| (s.t_s, s.hub_fz_n)).collect(),
            },
            Line {
                label: "longitudinal Fx".into(),
                points: r.samples.iter().map(|s| (s.t_s, s.hub_fx_n)).collect(),
            },
        ],
    };
    let png = out_dir().join("cleat.png");
    line_panels(
        &png,
        &[
            panel(&cleat, "cleat 10 mm, 40 km/h"),
            panel(&ramp, "ramp 50 mm, 20 km/h"),
        ],
        1,
    )
    .unwrap();
    println!("plot: {}", png.display());
}
