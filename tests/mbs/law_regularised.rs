//! The regularised laws of the coupling head (`LawSpec::DeadBand`, `LawSpec::Friction`)
//! against their closed forms: a dead band of half-width g with stiffness k beyond it,
//! its corners rounded by a softplus of width w, tends to k (|x| - g) sign(x) outside and
//! 0 inside as w -> 0 (the error of the softplus at a distance d from a corner is
//! w ln(1 + e^(-d/w)) < w e^(-d/w)); friction T tanh(x / r) is T tanh(1) at x = r.

use towride_mbs::model::elements::{Law, LawSpec};

fn dead_band(k: f64, g: f64, w: f64) -> Law {
    LawSpec::DeadBand {
        stiffness_n_m: k,
        play_m: g,
        smoothing_m: w,
    }
    .check()
    .unwrap()
}

#[test]
fn a_smooth_dead_band_tends_to_the_sharp_one() {
    let (k, g, w) = (2.0e7, 5.0e-4, 1.0e-5);
    let law = dead_band(k, g, w);
    for x in [-2e-3f64, -1e-3, -6e-4, 0.0, 2e-4, 4e-4, 6e-4, 1e-3, 2e-3] {
        let d = (x.abs() - g).abs();
        let sharp = if x.abs() > g {
            k * (x.abs() - g) * x.signum()
        } else {
            0.0
        };
        let (f, slope, _) = law.eval(x);
        // Two corners contribute; each at most k w e^(-d/w) (the far one is negligible).
        let bound = 2.0 * k * w * (-d / w).exp() + 1e-9;
        assert!((f - sharp).abs() <= bound, "x {x}: {f} against {sharp}");
        let sharp_slope = if x.abs() > g { k } else { 0.0 };
        assert!((slope - sharp_slope).abs() <= 2.0 * k * (-d / w).exp() + 1e-6 * k);
    }
    // At the corner itself the softplus gives k w ln 2 (half of it each side).
    let (f, slope, _) = law.eval(g);
    assert!((f - k * w * 2f64.ln()).abs() < 1e-9 * k * w);
    assert!((slope - 0.5 * k).abs() < 1e-9 * k);
    // Without play it is the linear law exactly: sp(x) - sp(-x) = x.
    let linear = dead_band(k, 0.0, w);
    for x in [-1e-3f64, -1e-5, 3e-6, 2e-3] {
        assert!((linear.eval(x).0 - k * x).abs() < 1e-9 * k * x.abs());
    }
}

#[test]
fn regularised_friction_is_t_tanh_of_the_rate() {
    let law = LawSpec::Friction {
        friction_torque_n_m: 1.35,
        release_rad_s: 0.01,
    }
    .check()
    .unwrap();
    let (f, slope, _) = law.eval(0.01);
    assert!((f - 1.35 * 1f64.tanh()).abs() < 1e-12);
    assert!((slope - 1.35 / 0.01 * (1.0 - 1f64.tanh().powi(2))).abs() < 1e-9);
    assert!((law.eval(1.0).0 - 1.35).abs() < 1e-12);
    assert!((law.eval(-1.0).0 + 1.35).abs() < 1e-12);
}

#[test]
fn negative_play_and_zero_smoothing_are_refused_at_their_field() {
    for (spec, field) in [
        (
            LawSpec::DeadBand {
                stiffness_n_m: 1e7,
                play_m: -1e-4,
                smoothing_m: 1e-5,
            },
            "play_m",
        ),
        (
            LawSpec::DeadBand {
                stiffness_n_m: 1e7,
                play_m: 1e-4,
                smoothing_m: 0.0,
            },
            "smoothing_m",
        ),
        (
            LawSpec::Friction {
                friction_torque_n_m: 1.0,
                release_rad_s: 0.0,
            },
            "release_rad_s",
        ),
    ] {
        let e = spec.check().expect_err("refused");
        assert!(format!("{e:?}").contains(field), "{e:?}");
    }
}
