//! Sway above the critical speed against the coupling head's yaw friction: a sway started
//! well below the describing function's threshold A* = 4 T / (pi w c_crit) dies out, one
//! started well above it grows (docs/manoeuvres.md, "Coupling friction"). c_crit and w
//! come from `towride linear` with a viscous yaw damper at the head, the describing
//! function of Coulomb friction (energy per cycle 4 T A against pi c w A^2) from the
//! docs; the time-domain runs use the friction law itself. Without the yaw friction the
//! small pulse's sway grows (from 1.08 A* at +0.18 1/s, measured 2026-11-27), so the test
//! fails if the friction law stops acting. Each run costs under 10 s of CPU at the
//! tighter atol (rtol 1e-6, atol x 1e-3), which the friction's reversals need.

use std::path::Path;

const TRAILER: &str = "vehicles/trailer/box_trailer.toml";
const HITCH: &str = "vehicles/fabia/hitch.toml";
const SPEED: &str = "300";
/// Yaw friction of the head [N m]: the describing function puts A* near 1 deg at 300 km/h.
const T_N_M: f64 = 6.25;
/// The file's plain head friction about x and y (kept as shipped).
const PLAIN: &str = "{ friction_torque_n_m = 1.35, release_rad_s = 0.01 }";

/// The legal-limit trailer, 10 kg on the ball, payload spread, the coupling head with
/// `z_law` about its vertical axis (FILE:PATH=VALUE overrides).
fn loading(scene: &str, z_law: &str) -> Vec<String> {
    vec![
        format!("{scene}:run.speed_km_h={SPEED}"),
        format!("{scene}:scene.load_case=\"legal_limit_557kg\""),
        format!("{TRAILER}:load_case[4].payload.cm_m=[-2.46,0.0,0.745]"),
        format!("{TRAILER}:load_case[4].payload.inertia_kg_m2=[42.7,450.0,450.0]"),
        format!("{HITCH}:ball_coupling.kind=\"coupling_head\""),
        format!(
            "{HITCH}:ball_coupling.coupling_head.damping_n_m_s_rad=[{PLAIN}, {PLAIN}, {z_law}]"
        ),
    ]
}

/// The sway mode (damping ratio, frequency [Hz]) with a viscous yaw damper c at the head.
fn sway(dir: &Path, c: f64) -> (f64, f64) {
    let m = crate::sway_mode(
        &dir.join("linear"),
        &loading("scenes/default.toml", &format!("{c}")),
    );
    (
        m["damping_ratio"].as_f64().unwrap(),
        m["damped_hz"].as_f64().unwrap(),
    )
}

/// The articulation's half-cycle amplitudes [rad] after 6 s of a run whose steering pulse
/// is the lane-change scene's times `scale`.
fn envelope(dir: &Path, scale: f64, name: &str) -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(repo!("scenes/lane_change.toml")).unwrap();
    let scenes = std::fs::canonicalize(repo!("scenes")).unwrap();
    let mut s = text.replace("\"../", &format!("\"{}/../", scenes.display()));
    let start = s.find("value = [").unwrap() + "value = [".len();
    let end = start + s[start..].find(']').unwrap();
    let values: Vec<String> = s[start..end]
        .split(',')
        .map(|v| format!("{:.12e}", v.trim().parse::<f64>().unwrap() * scale))
        .collect();
    s.replace_range(start..end, &values.join(", "));
    s.push_str(
        "\n[[output]]\nelement = \"ball_coupling\"\nquantity = \"deflection\"\nname = \"head\"\n",
    );
    let file = dir.join(format!("{name}.toml"));
    std::fs::write(&file, s).unwrap();
    let f = file.display().to_string();
    let out = dir.join(name);
    let mut args = vec![
        "run".to_string(),
        f.clone(),
        "--out".into(),
        out.display().to_string(),
    ];
    let law = format!("{{ friction_torque_n_m = {T_N_M}, release_rad_s = 0.01 }}");
    let run = [
        "run.duration_s=12",
        "run.sample_rate_hz=100",
        "solver.rtol=1e-6",
        "run.atol_scale=1e-3",
    ];
    for v in loading(&f, &law)
        .into_iter()
        .chain(run.iter().map(|v| format!("{f}:{v}")))
    {
        args.extend(["--set".into(), v]);
    }
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    crate::towride_ok(&a);
    let mut r = csv::Reader::from_path(out.join("outputs.csv")).unwrap();
    let col = r
        .headers()
        .unwrap()
        .iter()
        .position(|c| c == "head.rz [rad]")
        .unwrap();
    let rows: Vec<(f64, f64)> = r
        .records()
        .map(|x| {
            let x = x.unwrap();
            (x[0].parse().unwrap(), x[col].parse().unwrap())
        })
        .filter(|&(t, _)| t >= 6.0)
        .collect();
    // Between sign changes, the largest |angle|.
    let mut peaks = Vec::new();
    let mut best = (0.0, 0.0);
    for w in rows.windows(2) {
        if w[0].1.abs() > best.1 {
            best = (w[0].0, w[0].1.abs());
        }
        if w[0].1.signum() != w[1].1.signum() {
            peaks.push(best);
            best = (0.0, 0.0);
        }
    }
    peaks.remove(0); // the first half-cycle is cut at 6 s
    peaks
}

/// Least-squares slope of ln(amplitude) against time [1/s].
fn growth(p: &[(f64, f64)]) -> f64 {
    let n = p.len() as f64;
    let (mt, ml) = (
        p.iter().map(|q| q.0).sum::<f64>() / n,
        p.iter().map(|q| q.1.ln()).sum::<f64>() / n,
    );
    let num: f64 = p.iter().map(|q| (q.0 - mt) * (q.1.ln() - ml)).sum();
    let den: f64 = p.iter().map(|q| (q.0 - mt).powi(2)).sum();
    num / den
}

#[test]
fn coupling_friction_stops_a_small_sway_above_the_critical_speed_and_not_a_large_one() {
    let dir = std::env::temp_dir().join(format!("towride_sway_friction_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // c_crit: the damping ratio is nearly linear in the damper; one secant step from
    // 0 and 100 N m s/rad, then the frequency there.
    let (z0, _) = sway(&dir, 0.0);
    let (z1, _) = sway(&dir, 100.0);
    assert!(
        z0 < 0.0 && z1 > 0.0,
        "unstable without a damper, stable with 100: {z0} {z1}"
    );
    let c_crit = 100.0 * z0 / (z0 - z1);
    let (zc, hz) = sway(&dir, c_crit);
    assert!(zc.abs() < 1e-3, "neutral at c_crit {c_crit}: {zc}");
    let a_star = 4.0 * T_N_M / (std::f64::consts::PI * 2.0 * std::f64::consts::PI * hz * c_crit);

    // The pulse sizes that start the sway at about 0.6 A* and 1.6 A* (checked below).
    for (scale, lo, hi, grows) in [(0.15, 0.45, 0.75, false), (0.222, 1.3, 1.9, true)] {
        let p = envelope(&dir, scale, &format!("scale_{scale}"));
        assert!(p.len() >= 6, "{p:?}");
        let a0 = p[0].1 / a_star;
        let g = growth(&p);
        // Decay or growth first: without the friction the small sway grows (and starts
        // larger, the pulse no longer braked by it).
        assert_eq!(g > 0.0, grows, "start {a0} A*: slope {g} 1/s, {p:?}");
        assert!(
            (lo..hi).contains(&a0),
            "start amplitude {a0} A* (A* {a_star} rad): {p:?}"
        );
    }
}
