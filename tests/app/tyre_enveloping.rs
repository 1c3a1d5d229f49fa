//! Quasi-static enveloping: the effective road under the car tyre as its centre moves slowly
//! over a 50 mm step and over the thesis's ramp, checked against what a real tyre does
//! (Schmeitz 2004: it feels the obstacle before its centre gets there, rises smoothly and
//! monotonically to the full height, at slopes well below the obstacle's own) and against
//! an independent brute-force cam computation. Writes a PNG of both cases.

use std::path::{Path, PathBuf};

use towride_app::report::lineplot::{line_panels, Line, LinePanel};
use towride_mbs::road::Road;
use towride_mbs::tyre::{TandemCams, TyreParams};

const TIR: &str = repo!("vehicles/tyres/car_185_60r14.tir");

struct Curve {
    x: Vec<f64>,
    w: Vec<f64>,
    tan: Vec<f64>,
    dw: Vec<f64>,
}

fn sweep(road: &Road, cams: &TandemCams, x0: f64, x1: f64, dx: f64) -> Curve {
    let n = ((x1 - x0) / dx).round() as usize;
    let mut c = Curve {
        x: vec![],
        w: vec![],
        tan: vec![],
        dw: vec![],
    };
    for i in 0..=n {
        let x = x0 + i as f64 * dx;
        let e = cams.effective(road, [x, 0.0], [1.0, 0.0], [0.0, 1.0]);
        c.x.push(x);
        c.w.push(e.height);
        c.tan.push(e.tan_slope);
        c.dw.push(e.dheight_ds);
    }
    c
}

/// Lowest point of one cam by brute force: the road and the super-ellipse sampled every
/// 10 um over the whole cam length, written from the cam definition alone.
fn brute_cam(road: &Road, p: &TyreParams, xc: f64) -> f64 {
    let a = p.ellips_length * p.r0;
    let b = p.ellips_height * p.r0;
    let c = p.ellips_order;
    let n = (2.0 * a / 1e-5) as usize;
    let mut best = f64::NEG_INFINITY;
    for i in 0..=n {
        let xi = -a + i as f64 * 1e-5;
        let z = b * (1.0 - (xi.abs() / a).powf(c)).max(0.0).powf(1.0 / c);
        best = best.max(road.height(xc + xi, 0.0) + z);
    }
    best - b
}

fn out_dir() -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("tyre");
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn step_and_ramp_enveloping() {
    let p = TyreParams::from_file(Path::new(TIR), &towride_mbs::input::Loader::new()).unwrap();
    let cams = TandemCams::new(&p);
    let step = Road::from_file(
        Path::new(repo!("roads/step_50mm.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let ramp = Road::from_file(
        Path::new(repo!("roads/ramp_thesis.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let h = 0.05;
    let foot = 1.0;
    let dx = 2e-4;

    // --- 50 mm step at x = 1 m.
    let s = sweep(&step, &cams, 0.4, 1.6, dx);
    for i in 1..s.w.len() {
        assert!(
            s.w[i] >= s.w[i - 1] - 1e-12,
            "step: w falls at x = {}",
            s.x[i]
        );
    }
    let first = s.x[s.w.iter().position(|&w| w > 1e-6).unwrap()];
    assert!(
        first < foot - 0.05,
        "step: first rise at {first} m, not ahead of the foot"
    );
    assert!(
        (s.w.last().unwrap() - h).abs() < 1e-12,
        "step: full height not reached"
    );
    let max_tan_step = s.tan.iter().cloned().fold(0.0, f64::max);
    let max_deg_step = max_tan_step.atan().to_degrees();
    // A point follower sees a vertical face; the enveloped step must stay far below 45 deg.
    assert!(
        max_deg_step < 35.0,
        "step: largest effective slope {max_deg_step} deg"
    );
    // Continuity: no increment larger than the steepest effective slope allows.
    let max_dwdx = s.dw.iter().cloned().fold(0.0, f64::max);
    for i in 1..s.w.len() {
        assert!(
            s.w[i] - s.w[i - 1] <= 1.01 * max_dwdx * dx + 1e-12,
            "step: jump at x = {}",
            s.x[i]
        );
    }

    // --- the thesis ramp, foot at 1 m, top 1.05..1.45 m, back to 0 at 1.5 m.
    let r = sweep(&ramp, &cams, 0.4, 2.1, dx);
    let i_top = r.x.iter().position(|&x| x >= 1.25).unwrap();
    for i in 1..=i_top {
        assert!(
            r.w[i] >= r.w[i - 1] - 1e-12,
            "ramp: w falls on the way up at {}",
            r.x[i]
        );
    }
    for i in i_top + 1..r.w.len() {
        assert!(
            r.w[i] <= r.w[i - 1] + 1e-12,
            "ramp: w rises on the way down at {}",
            r.x[i]
        );
    }
    let first = r.x[r.w.iter().position(|&w| w > 1e-6).unwrap()];
    assert!(first < foot - 0.05, "ramp: first rise at {first} m");
    assert!(
        (r.w[i_top] - h).abs() < 1e-12,
        "ramp: full height not reached: {}",
        r.w[i_top]
    );
    let max_deg_ramp = r
        .tan
        .iter()
        .map(|t| t.abs())
        .fold(0.0, f64::max)
        .atan()
        .to_degrees();
    // The point follower sees the flank itself.
    let (flank, _) = ramp.slope(1.025, 0.0);
    let flank_deg = flank.atan().to_degrees();
    assert!((flank_deg - 45.0).abs() < 1e-9);
    assert!(
        max_deg_ramp < 30.0,
        "ramp: largest effective slope {max_deg_ramp} deg"
    );

    // --- independent reference: one tandem, brute-force cams, several positions.
    let single = {
        let mut q = p.clone();
        q.ellips_nwidth = 1;
        TandemCams::new(&q)
    };
    for &x in &[0.82, 0.9, 0.95, 0.99, 1.02, 1.1, 1.3, 1.48, 1.6] {
        for road in [&step, &ramp] {
            let e = single.effective(road, [x, 0.0], [1.0, 0.0], [0.0, 1.0]);
            let wf = brute_cam(road, &p, x + 0.5 * single.l_s);
            let wr = brute_cam(road, &p, x - 0.5 * single.l_s);
            assert!(
                (e.height - 0.5 * (wf + wr)).abs() < 2e-6,
                "x = {x}: {} vs {}",
                e.height,
                0.5 * (wf + wr)
            );
            assert!(
                (e.tan_slope - (wf - wr) / single.l_s).abs() < 5e-5,
                "x = {x}: slope {} vs {}",
                e.tan_slope,
                (wf - wr) / single.l_s
            );
        }
    }

    // --- the slope derivative (envelope theorem) against differences of the height.
    let mut worst: (f64, f64) = (0.0, 0.0);
    for i in 1..r.w.len() - 1 {
        let fd = (r.w[i + 1] - r.w[i - 1]) / (2.0 * dx);
        // Skip the few points next to a kink of w, where differences straddle it.
        if (r.dw[i + 1] - r.dw[i - 1]).abs() < 1e-3 && (fd - r.dw[i]).abs() > worst.0 {
            worst = ((fd - r.dw[i]).abs(), r.x[i]);
        }
    }
    println!(
        "worst dw/ds difference {:.2e} at x = {:.4}",
        worst.0, worst.1
    );
    assert!(
        worst.0 < 1e-3,
        "dw/ds differs from differences by {worst:?}"
    );

    println!(
        "enveloping: step first rise {:.4} m, max slope {max_deg_step:.2} deg; ramp max slope {max_deg_ramp:.2} deg (flank {flank_deg:.1} deg), l_s {:.4} m, cam a {:.4} b {:.4} m",
        s.x[s.w.iter().position(|&w| w > 1e-6).unwrap()],
        cams.l_s,
        cams.a,
        cams.b
    );

    let png = out_dir().join("enveloping.png");
    let height = |c: &Curve, road: &Road, name: &str| LinePanel {
        title: format!("{name}: effective height"),
        x_label: "wheel centre x [m]".into(),
        y_label: "height [mm]".into(),
        lines: vec![
            Line {
                label: "road under the centre (point follower)".into(),
                points: c
                    .x
                    .iter()
                    .map(|&x| (x, road.height(x, 0.0) * 1e3))
                    .collect(),
            },
            Line {
                label: "effective height (tandem cams)".into(),
                points: c.x.iter().zip(&c.w).map(|(&x, &w)| (x, w * 1e3)).collect(),
            },
        ],
    };
    let slope = |c: &Curve, road: &Road, name: &str| LinePanel {
        title: format!("{name}: effective forward slope"),
        x_label: "wheel centre x [m]".into(),
        y_label: "slope angle [deg]".into(),
        lines: vec![
            Line {
                label: "road under the centre (point follower)".into(),
                points: c
                    .x
                    .iter()
                    .map(|&x| (x, road.slope(x, 0.0).0.atan().to_degrees()))
                    .collect(),
            },
            Line {
                label: "effective slope (tandem cams)".into(),
                points: c
                    .x
                    .iter()
                    .zip(&c.tan)
                    .map(|(&x, &t)| (x, t.atan().to_degrees()))
                    .collect(),
            },
        ],
    };
    let ramp_name = "thesis ramp 50 mm / 500 mm / 45 deg";
    line_panels(
        &png,
        &[
            height(&s, &step, "50 mm step"),
            slope(&s, &step, "50 mm step"),
            height(&r, &ramp, ramp_name),
            slope(&r, &ramp, ramp_name),
        ],
        2,
    )
    .unwrap();
    assert!(std::fs::metadata(&png).unwrap().len() > 1000);
    println!("plot: {}", png.display());
}
