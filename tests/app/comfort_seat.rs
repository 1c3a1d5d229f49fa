//! The driver's seat (`towride_app::comfort::seat`): its time-domain filter against the
//! model's closed-form transmissibility, written here from the masses, springs and
//! dampers; the shipped seat's occupant against the published Fairley & Griffin (1989)
//! model (5 Hz, damping ratio 0.475); the run summary's seat block against the same
//! closed form applied in the frequency domain; its convergence in the solver tolerance.

use std::f64::consts::PI;
use std::path::Path;

use towride_app::comfort::seat::{read, Seat, SeatFilter};
use towride_app::comfort::{Weighting, SEAT_Z};
use towride_app::job::Job;
use towride_mbs::input::Loader;
use towride_mbs::progress::Silent;

/// (re, im) arithmetic, so the reference shares nothing with the library's complex type.
type C = (f64, f64);
fn mul(a: C, b: C) -> C {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}
fn div(a: C, b: C) -> C {
    let d = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
}
fn abs(a: C) -> f64 {
    a.0.hypot(a.1)
}

/// The closed form of a cushion (kc, cc) under a frame mass m0 and a mass m1 on (k1,
/// c1), base-excited: with the seat surface's and the moving mass's displacements X, Y
/// per unit floor displacement at w, the two force balances
/// (kc + i w cc)(1 - X) = -w^2 m0 X + (k1 + i w c1)(X - Y) and
/// -w^2 m1 Y = (k1 + i w c1)(X - Y) solved by elimination: Y = Z1 X / (Z1 - w^2 m1),
/// X = Zc / (Zc - w^2 m0 + Z1 - Z1^2 / (Z1 - w^2 m1)).
fn closed_form(m0: f64, m1: f64, k1: f64, c1: f64, kc: f64, cc: f64, f: f64) -> f64 {
    let w = 2.0 * PI * f;
    let zc = (kc, w * cc);
    let z1 = (k1, w * c1);
    let z1m = (k1 - w * w * m1, w * c1);
    let tail = div(mul(z1, z1), z1m);
    let den = (zc.0 - w * w * m0 + z1.0 - tail.0, zc.1 + z1.1 - tail.1);
    abs(div(zc, den))
}

fn reference(s: &Seat, f: f64) -> f64 {
    closed_form(
        s.frame_mass_kg,
        s.moving_mass_kg,
        s.occupant_stiffness_n_m,
        s.occupant_damping_n_s_m,
        s.cushion_stiffness_n_m,
        s.cushion_damping_n_s_m,
        f,
    )
}

/// Amplitude of the best fit a sin + b cos at `f` to the last `n` samples of `y`.
fn amplitude(y: &[f64], rate: f64, f: f64, n: usize) -> f64 {
    let (mut ss, mut sc, mut cc, mut ys, mut yc) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (k, v) in y.iter().enumerate().skip(y.len() - n) {
        let (s, c) = (2.0 * PI * f * k as f64 / rate).sin_cos();
        ss += s * s;
        sc += s * c;
        cc += c * c;
        ys += v * s;
        yc += v * c;
    }
    let d = ss * cc - sc * sc;
    let a = (ys * cc - yc * sc) / d;
    let b = (yc * ss - ys * sc) / d;
    a.hypot(b)
}

/// Steady sines through the filter at 1 kHz: the amplitude ratio is the closed form
/// times sinc^2(f h), the gain of the linear interpolation between samples the
/// first-order hold assumes. The interpolation's image at 1/h - f (relative size
/// sinc^2(1 - f h), about (f h)^2, times |T| there) folds back onto f when sampled: below
/// 2e-5 up to 40 Hz, 7e-4 at 80 Hz. Ten seconds let the slowest pole (about 5 1/s)
/// decay by e^-40 before the last two are fitted.
#[test]
fn seat_filter_steady_sines_match_the_closed_form() {
    let seat = Seat::new(55.0, 0.8, 5.0, 0.475, 5.0e4, 500.0);
    let rate = 1000.0;
    let f = SeatFilter::new(&seat, rate);
    for fq in [0.5, 1.0, 2.0, 3.457, 5.0, 8.0, 12.5, 20.0, 40.0, 80.0] {
        let u: Vec<f64> = (0..12_000)
            .map(|k| (2.0 * PI * fq * k as f64 / rate).sin())
            .collect();
        let y = f.apply(&u);
        let x = PI * fq / rate;
        let sinc2 = (x.sin() / x).powi(2);
        let got = amplitude(&y, rate, fq, 2000);
        let want = reference(&seat, fq) * sinc2;
        let tol = if fq <= 40.0 { 2e-5 } else { 1e-3 };
        assert!((got / want - 1.0).abs() < tol, "{fq} Hz: {got} vs {want}");
        // The library's own closed form agrees with the one written here.
        assert!((seat.transmissibility(fq).norm() / reference(&seat, fq) - 1.0).abs() < 1e-12);
    }
    // Below the cushion's resonance the seat moves with the floor; a slow input passes.
    let dc = f.apply(&vec![1.0; 20_000]);
    assert!((dc[19_999] - 1.0).abs() < 1e-9);
}

/// The shipped seat (vehicles/fabia/body.toml): its occupant is the Fairley & Griffin
/// model as Brammer & Peterson give it (Biomedical Engineering and Design Handbook,
/// 2009, p. 272): natural angular frequency 31.4 rad/s (5 Hz), damping ratio 0.475. At
/// that frequency a mass on a spring and damper has apparent mass m1 (1 - i / (2 zeta)):
/// the real part of the whole is the occupant's mass, the imaginary part -m1 / 0.95.
/// The largest |T| the library quotes is the largest of the closed form on a fine grid.
#[test]
fn shipped_seat_is_the_published_occupant_model() {
    let seat = read(Path::new(repo!("vehicles/fabia/body.toml"))).unwrap();
    let m1 = seat.moving_mass_kg;
    let wn = (seat.occupant_stiffness_n_m / m1).sqrt();
    assert!((wn / 31.4 - 1.0).abs() < 1e-3, "{wn} rad/s");
    let zeta = seat.occupant_damping_n_s_m / (2.0 * (seat.occupant_stiffness_n_m * m1).sqrt());
    assert!((zeta - 0.475).abs() < 1e-12);
    let am = seat.apparent_mass(5.0);
    let total = seat.frame_mass_kg + m1;
    assert!((am.re / total - 1.0).abs() < 1e-12, "{am}");
    assert!((am.im / (-m1 / 0.95) - 1.0).abs() < 1e-12, "{am}");
    let (f_peak, t_peak) = seat.resonance();
    let (mut fg, mut tg) = (0.0, 0.0);
    for k in 1..80_000 {
        let f = k as f64 * 1e-3;
        let t = reference(&seat, f);
        if t > tg {
            (fg, tg) = (f, t);
        }
    }
    assert!((f_peak - fg).abs() < 2e-3 && (t_peak / tg - 1.0).abs() < 1e-6);
}

/// The r.m.s. over the record of `y` (at `rate`) weighted by |W(f)| |T(f)| in the
/// frequency domain (Parseval over a DFT zero-padded to 8 times the length, which keeps
/// the ringing past the record's end).
fn rms_by_dft(y: &[f64], rate: f64, gain: impl Fn(f64) -> f64) -> f64 {
    let n = y.len();
    let m = 8 * n;
    let mut sum = 0.0;
    for k in 0..=m / 2 {
        let f = k as f64 * rate / m as f64;
        let (mut re, mut im) = (0.0, 0.0);
        for (i, v) in y.iter().enumerate() {
            let ph = -2.0 * PI * (k * i % m) as f64 / m as f64;
            re += v * ph.cos();
            im += v * ph.sin();
        }
        let both = if k == 0 || k == m / 2 { 1.0 } else { 2.0 };
        sum += both * (re * re + im * im) * gain(f).powi(2);
    }
    (sum / m as f64 / n as f64).sqrt()
}

fn default_job() -> Job {
    Job::from_file(Path::new(repo!("scenes/default.toml")), &Loader::new())
        .unwrap()
        .without_view()
}

/// The default scene's seat block: the seat z a_w against the floor channel weighted by
/// Wk and the closed-form |T| in the frequency domain (the time-domain filters stop at
/// the record's end and the weighting's bilinear warping is 1.5 % at 80 Hz: 0.2 %);
/// x and y are the floor's; the SEAT value is the ratio of the two a_w.
#[test]
fn seat_block_of_the_default_scene() {
    let run = default_job().run(&Silent).unwrap();
    let floor = run.summary.comfort.as_ref().unwrap();
    let s = run.summary.comfort_seat.as_ref().expect("a seat block");
    let z = s.comfort.axes.iter().find(|a| a.channel == SEAT_Z).unwrap();
    let y = run.channel("acc_driver_floor_z").unwrap();
    let want = rms_by_dft(&y, 1000.0, |f| {
        Weighting::Wk.analogue_gain(f) * reference(&s.seat, f)
    });
    assert!(
        (z.measures.rms_m_s2 / want - 1.0).abs() < 2e-3,
        "{} vs {want}",
        z.measures.rms_m_s2
    );
    for ax in [0, 1] {
        assert_eq!(s.comfort.axes[ax].measures, floor.axes[ax].measures);
    }
    let floor_z = &floor.axes[2].measures;
    assert!((s.seat_value_rms - z.measures.rms_m_s2 / floor_z.rms_m_s2).abs() < 1e-12);
}

/// The seat's figures of the default scene at rtol 1e-6 (atol / 100) against the
/// default tolerance: within 2 %.
#[test]
fn seat_comfort_converged_in_the_tolerance() {
    let base = default_job().run(&Silent).unwrap();
    let tight = default_job().tightened(100.0).run(&Silent).unwrap();
    let pick = |r: &towride_app::job::RunResult| {
        let s = r.summary.comfort_seat.clone().unwrap();
        let z = s
            .comfort
            .axes
            .iter()
            .find(|a| a.channel == SEAT_Z)
            .unwrap()
            .measures;
        [
            z.rms_m_s2,
            z.vdv_m_s1_75,
            z.mtvv_m_s2,
            z.peak_m_s2,
            s.comfort.total_value_m_s2.unwrap(),
        ]
    };
    for (a, b) in pick(&base).into_iter().zip(pick(&tight)) {
        assert!((a / b - 1.0).abs() < 0.02, "{a} vs {b}");
    }
}
