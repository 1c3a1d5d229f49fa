//! The tandem cams on the ISO 8608 class C road (a two-track profile sampled every 5 cm)
//! against the definition of the enveloping model, evaluated here by brute force: the cam
//! rests at max over xi of [h(s + xi) + z_c(xi)] (Schmeitz 2004; Pacejka 2012 sec. 10.2),
//! found on each stretch between the profile's nodes (x = j dx) and track lines
//! (y = +-B/2) by a dense grid and a ternary refinement, using only `Road::height` and the
//! contour. The tyre's fast path solves each stretch as an exact quadratic instead; with
//! the heading yawed the stretches are truly quadratic (the blend across the tracks), so a
//! fast path that dropped the quadratic term fails at the large yaw angle.

use std::path::Path;

use towride_mbs::input::Loader;
use towride_mbs::road::Road;
use towride_mbs::tyre::{TandemCams, TyreParams};

fn setup() -> (Road, TandemCams) {
    let road = Road::from_file(
        Path::new(repo!("roads/iso8608_class_c.toml")),
        &Loader::new(),
    )
    .unwrap();
    let p = TyreParams::from_file(
        Path::new(repo!("vehicles/tyres/car_185_60r14.tir")),
        &Loader::new(),
    )
    .unwrap();
    (road, TandemCams::new(&p))
}

/// The cam's rest w by brute force on the line p + eta d, eta in [s - xi_max, s + xi_max].
fn brute_cam(road: &Road, cams: &TandemCams, p: [f64; 2], d: [f64; 2], s: f64) -> f64 {
    let spec = road.random_spec().unwrap();
    let dx = spec.length / spec.samples() as f64;
    let half = road.track_width().unwrap() / 2.0;
    let (s0, s1) = (s - cams.xi_max, s + cams.xi_max);
    // Stretch ends: the window's ends, node crossings and track-line crossings.
    let mut cuts = vec![s0, s1];
    let (xa, xb) = (p[0] + s0 * d[0], p[0] + s1 * d[0]);
    let (j0, j1) = (
        (xa.min(xb) / dx).floor() as i64,
        (xa.max(xb) / dx).ceil() as i64,
    );
    for j in j0..=j1 {
        let e = (j as f64 * dx - p[0]) / d[0];
        if e > s0 && e < s1 {
            cuts.push(e);
        }
    }
    for y in [half, -half] {
        if d[1] != 0.0 {
            let e = (y - p[1]) / d[1];
            if e > s0 && e < s1 {
                cuts.push(e);
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    let g = |eta: f64| road.height(p[0] + eta * d[0], p[1] + eta * d[1]) + cams.contour(eta - s);
    let mut best = f64::NEG_INFINITY;
    for w in cuts.windows(2) {
        let (mut lo, mut hi) = (w[0], w[1]);
        best = best.max(g(lo)).max(g(hi));
        // Grid, then ternary search around the best grid point (g is concave here).
        let n = 64;
        let h = (hi - lo) / n as f64;
        let k = (0..=n)
            .max_by(|&i, &j| g(lo + i as f64 * h).total_cmp(&g(lo + j as f64 * h)))
            .unwrap();
        (lo, hi) = (
            (lo + (k as f64 - 1.0) * h).max(w[0]),
            (lo + (k as f64 + 1.0) * h).min(w[1]),
        );
        for _ in 0..100 {
            let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if g(m1) < g(m2) {
                lo = m1;
            } else {
                hi = m2;
            }
        }
        best = best.max(g(0.5 * (lo + hi)));
    }
    best - cams.b
}

#[test]
fn envelope_on_profile_pieces_matches_the_definition() {
    let (road, cams) = setup();
    let mut kinks = Vec::new();
    let mut worst = 0.0f64;
    let mut n = 0;
    for yaw in [0.0f64, 0.01, -0.03, 0.35] {
        let d = [yaw.cos(), yaw.sin()];
        for x in [12.3456, 100.01, 250.0, 487.123, 800.77] {
            for y in [0.7, 0.55, 0.0, -0.71, -0.9] {
                for s in [-0.5 * cams.l_s, 0.5 * cams.l_s] {
                    let (w, _, flat) = cams.cam(&road, [x, y], d, s, &mut kinks);
                    assert!(!flat);
                    let wb = brute_cam(&road, &cams, [x, y], d, s);
                    // The exact maximum is never below a sampled one.
                    assert!(w >= wb - 1e-12, "yaw {yaw} x {x} y {y}: {w} < {wb}");
                    worst = worst.max(w - wb);
                    n += 1;
                }
            }
        }
    }
    assert_eq!(n, 200);
    // The brute-force search converges to ~1e-13 m; allow 1e-11 m.
    assert!(worst < 1e-11, "largest difference {worst:e} m");
}

#[test]
fn envelope_slope_on_profile_matches_differenced_heights() {
    // dw/ds from the envelope theorem against a central difference of the brute-force
    // rest height, step 1e-6 m: difference error ~ 1e-13 m / 1e-6 m = 1e-7.
    let (road, cams) = setup();
    let mut kinks = Vec::new();
    let h = 1e-6;
    let mut checked = 0;
    for yaw in [0.0f64, 0.02, 0.35] {
        let d = [yaw.cos(), yaw.sin()];
        for i in 0..20 {
            let p = [37.0 + 23.17 * i as f64, 0.6 - 0.06 * i as f64];
            let (_, dw, _) = cams.cam(&road, p, d, 0.0, &mut kinks);
            let fd =
                (brute_cam(&road, &cams, p, d, h) - brute_cam(&road, &cams, p, d, -h)) / (2.0 * h);
            assert!(
                (dw - fd).abs() < 1e-5,
                "yaw {yaw} at {p:?}: dw/ds {dw} vs {fd}"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 60);
}

#[test]
fn envelope_effective_road_on_profile_matches_the_definition() {
    // The tandems' average (Schmeitz 2004: w the mean of the front and rear cam, tan beta
    // their difference over l_s, averaged across the tread) from the brute-force cams.
    let (road, cams) = setup();
    let yaw = 0.05f64;
    let (d, l) = ([yaw.cos(), yaw.sin()], [-yaw.sin(), yaw.cos()]);
    for x in [3.0, 333.3, 666.6] {
        let c = [x, 0.4];
        let e = cams.effective(&road, c, d, l);
        let n = cams.offsets.len() as f64;
        let (mut w, mut tan) = (0.0, 0.0);
        for &o in &cams.offsets {
            let p = [c[0] + o * l[0], c[1] + o * l[1]];
            let wf = brute_cam(&road, &cams, p, d, 0.5 * cams.l_s);
            let wr = brute_cam(&road, &cams, p, d, -0.5 * cams.l_s);
            w += 0.5 * (wf + wr) / n;
            tan += (wf - wr) / cams.l_s / n;
        }
        assert!((e.height - w).abs() < 1e-11, "x {x}: {} vs {w}", e.height);
        assert!(
            (e.tan_slope - tan).abs() < 1e-9,
            "x {x}: {} vs {tan}",
            e.tan_slope
        );
        assert!(!e.flat);
    }
}
