//! The modelling layer against analytical and published references.

use std::path::Path;

use towride_mbs::input::Source;
use towride_mbs::model::run::{simulate, Samples};
use towride_mbs::model::spec::{self, Mechanism};
use towride_mbs::model::{doctor, linear, statics, System};
use towride_solver::problem::{DaeProblem, JacobianSink};

fn load(path: &str) -> Mechanism {
    spec::load(Path::new(path), &towride_mbs::input::Loader::new())
        .unwrap_or_else(|e| panic!("{e}"))
}

fn from_text(name: &str, text: &str) -> Result<Mechanism, towride_mbs::input::InputError> {
    let src = Source::from_text(Path::new(name), text.to_string())?;
    let file = src.parse()?;
    spec::build(&src, file)
}

fn run(m: &Mechanism, rate: f64) -> (System, Samples) {
    let sys = System::new(m.model.clone());
    let r = simulate(
        &sys,
        0.0,
        m.run.end_time_s,
        rate,
        &m.solver,
        None,
        &towride_mbs::progress::Silent,
    );
    assert!(r.error.is_none(), "{:?}", r.error);
    (sys, r)
}

/// Period from the two zero crossings of x (at T/4 and 3T/4), linear interpolation.
fn period(r: &Samples) -> f64 {
    let x = r.channel("bob.cm.position.x").unwrap();
    let mut cross = Vec::new();
    for k in 1..x.len() {
        if x[k - 1].signum() != x[k].signum() && x[k - 1] != 0.0 {
            let f = x[k - 1] / (x[k - 1] - x[k]);
            cross.push(r.times[k - 1] + f * (r.times[k] - r.times[k - 1]));
        }
    }
    2.0 * (cross[1] - cross[0])
}

const PERIOD: f64 = 2.3678419475762; // 4 sqrt(L/g) K(1/sqrt 2), L = 1 m, g = 9.81

#[test]
fn pendulum_period_with_revolute_joint() {
    let m = load(repo!("scenes/examples/pendulum.toml"));
    let (_, r) = run(&m, 20000.0);
    let t = period(&r);
    assert!(((t - PERIOD) / PERIOD).abs() < 1e-6, "period {t}");
}

#[test]
fn pendulum_period_with_stiff_bushing() {
    let text = std::fs::read_to_string(repo!("scenes/examples/pendulum.toml")).unwrap().replace(
        "gravity_m_s2 = [0.0, 0.0, -9.81]",
        "gravity_m_s2 = [0.0, 0.0, -9.81]\njoints_as_bushings = { stiffness_n_m = 1e7, damping_n_s_m = 1e2, stiffness_n_m_rad = 1e3, damping_n_m_s_rad = 1e-3 }",
    );
    let text = text.split("[[output]]\njoint").next().unwrap().to_string();
    let m = from_text("pendulum_bushing.toml", &text).unwrap();
    let (sys, r) = run(&m, 20000.0);
    assert_eq!(sys.m, 0, "the joint became a bushing");
    let t = period(&r);
    assert!(((t - PERIOD) / PERIOD).abs() < 1e-3, "period {t}");
}

#[test]
fn andrews_from_generic_bodies_matches_the_test_set() {
    let m = load(repo!("scenes/examples/andrews.toml"));
    let (sys, r) = run(&m, 1e5);
    // 7 bodies x 6 - 1 DOF = 41 independent rows out of 10 revolutes x 5 = 50.
    assert_eq!(sys.m, 41);
    assert_eq!(sys.redundant.len(), 9);
    #[allow(clippy::excessive_precision)] // digits as published in ex_andrews.R
    let q0 = [
        -0.0617138900142764496358948458001,
        0.0,
        0.455279819163070380255912382449,
        0.222668390165885884674473185609,
        0.487364979543842550225598953530,
        -0.222668390165885884674473185609,
        1.23054744454982119249735015568,
    ];
    let reference = [
        0.1581077119629904e2,
        -0.1575637105984298e2,
        0.4082224013073101e-1,
        -0.5347301163226948,
        0.5244099658805304,
        0.5347301163226948,
        0.1048080741042263e1,
    ];
    let names = ["beta", "theta", "gamma", "phi", "delta", "omega", "epsilon"];
    for k in 0..7 {
        let v = *r.channel(names[k]).unwrap().last().unwrap() + q0[k];
        let scd = -((v - reference[k]) / reference[k]).abs().log10();
        assert!(
            scd >= 4.0,
            "{}: {v} vs {} (scd {scd:.2})",
            names[k],
            reference[k]
        );
    }
}

fn mass_spring(k: f64, m: f64) -> String {
    format!(
        r#"[model]
name = "mass on a spring"
gravity_m_s2 = [0.0, 0.0, -9.81]
[run]
end_time_s = 1.0
sample_rate_hz = 100.0
[[body]]
name = "mass"
mass_kg = {m}
inertia_kg_m2 = [0.1, 0.1, 0.1]
cm_position_m = [0.0, 0.0, 1.0]
[[joint]]
name = "guide"
type = "translational"
body_i = "mass"
body_j = "ground"
position_m = [0.0, 0.0, 1.0]
[[spring]]
name = "k"
body_i = "mass"
point_i_m = [0.0, 0.0, 1.0]
body_j = "ground"
point_j_m = [0.0, 0.0, 0.0]
stiffness_n_m = {k}
"#
    )
}

#[test]
fn linear_frequencies_match_analytical() {
    let two_pi = 2.0 * std::f64::consts::PI;
    let (k, mass) = (3000.0, 7.5);
    let m = from_text("mass_spring.toml", &mass_spring(k, mass)).unwrap();
    let sys = System::new(m.model);
    let st = statics::equilibrium(&sys, 0.0, &m.solver).unwrap();
    // static deflection m g / k
    let z = st.y[2];
    assert!((z - (1.0 - mass * 9.81 / k)).abs() < 1e-9, "z = {z}");
    let lin = linear::linearise(&sys, 0.0, &st.y).unwrap();
    assert_eq!(lin.dof, 1);
    let f = (k / mass).sqrt() / two_pi;
    assert!(
        ((lin.modes[0].undamped_hz - f) / f).abs() < 1e-6,
        "{} vs {f}",
        lin.modes[0].undamped_hz
    );

    // Two-mass chain: m1 m2 w^4 - (m1 k2 + m2 (k1 + k2)) w^2 + k1 k2 = 0
    let m = load(repo!("scenes/examples/two_mass_chain.toml"));
    let sys = System::new(m.model);
    let st = statics::equilibrium(&sys, 0.0, &m.solver).unwrap();
    let lin = linear::linearise(&sys, 0.0, &st.y).unwrap();
    let (m1, m2, k1, k2): (f64, f64, f64, f64) = (2.0, 1.0, 2000.0, 1000.0);
    let (a, b, c) = (m1 * m2, -(m1 * k2 + m2 * (k1 + k2)), k1 * k2);
    let disc = (b * b - 4.0 * a * c).sqrt();
    let w2 = [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)];
    assert_eq!(lin.modes.len(), 2);
    for (mode, w2) in lin.modes.iter().zip(w2) {
        let f = w2.sqrt() / two_pi;
        assert!(
            ((mode.undamped_hz - f) / f).abs() < 1e-6,
            "{} vs {f}",
            mode.undamped_hz
        );
    }
}

fn clamped_block(kind: &str) -> String {
    let attach = |name: &str, x: f64| {
        if kind == "fixed" {
            format!("[[joint]]\nname = \"{name}\"\ntype = \"fixed\"\nbody_i = \"block\"\nbody_j = \"ground\"\nposition_m = [{x}, 0.0, 1.0]\n")
        } else {
            format!(
                "[[bushing]]\nname = \"{name}\"\nbody_i = \"block\"\nbody_j = \"ground\"\nposition_m = [{x}, 0.0, 1.0]\nstiffness_n_m = [1e7, 1e7, 1e7]\ndamping_n_s_m = [1e3, 1e3, 1e3]\nstiffness_n_m_rad = [1e5, 1e5, 1e5]\ndamping_n_m_s_rad = [10.0, 10.0, 10.0]\n"
            )
        }
    };
    format!(
        "[model]\nname = \"block on two {kind}s\"\ngravity_m_s2 = [0.0, 0.0, -9.81]\n[run]\nend_time_s = 0.5\nsample_rate_hz = 100.0\n[[body]]\nname = \"block\"\nmass_kg = 10.0\ninertia_kg_m2 = [0.5, 0.5, 0.5]\ncm_position_m = [0.0, 0.0, 1.0]\n{}{}[[output]]\nmarker = \"block.cm\"\nquantity = \"position\"\n",
        attach("left", -0.5),
        attach("right", 0.5)
    )
}

#[test]
fn over_constrained_body_runs_and_doctor_names_it() {
    let m = from_text("fixed.toml", &clamped_block("fixed")).unwrap();
    let (sys, r) = run(&m, 100.0);
    assert_eq!(sys.redundant.len(), 6);
    let z = r.channel("block.cm.position.z").unwrap();
    assert!(z.iter().all(|v| (v - 1.0).abs() < 1e-9));
    let rep = doctor::examine(&sys, &m.solver, 1e-3);
    assert_eq!(rep.redundant.len(), 6);
    assert!(
        rep.redundant
            .iter()
            .all(|r| r.row.contains("fixed joint 'right'")),
        "{:?}",
        rep.redundant
    );
    assert!(rep
        .redundant
        .iter()
        .all(|r| r.duplicates.iter().any(|d| d.contains("'left'"))));
    assert!(
        rep.advice
            .iter()
            .any(|a| a.contains("'right' over-constrains") && a.contains("bushing")),
        "{:?}",
        rep.advice
    );

    let m = from_text("bushings.toml", &clamped_block("bushing")).unwrap();
    let (sys, _) = run(&m, 100.0);
    assert!(sys.redundant.is_empty());
    let rep = doctor::examine(&sys, &m.solver, 1e-3);
    assert!(rep.redundant.is_empty());
    assert!(!rep.advice.iter().any(|a| a.contains("over-constrains")));
}

/// Deterministic shuffle (linear congruential), so the test is repeatable.
fn shuffle<T>(v: &mut [T], seed: &mut u64) {
    for i in (1..v.len()).rev() {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let j = (*seed >> 33) as usize % (i + 1);
        v.swap(i, j);
    }
}

#[test]
fn renumbering_bodies_and_joints_changes_nothing() {
    // At a tight tolerance both runs are converged, so any difference left is what the
    // ordering itself changes (pivoting, summation order), not the step sequence. The
    // accelerations are solved at each sample: the interpolant's derivative carries the
    // integration error (here 4e-8 of the scale), which follows the step sequence.
    let text = std::fs::read_to_string(repo!("scenes/examples/elements.toml"))
        .unwrap()
        .replace("rtol = 1e-7", "rtol = 1e-12")
        .replace("atol = [1e-8]", "atol = [1e-12]")
        .replace("[run]\n", "[run]\naccelerations = \"solve\"\n");
    let base = from_text("elements.toml", &text).unwrap();
    let (_, r0) = run(&base, 500.0);
    let mut seed = 12345u64;
    for trial in 0..3 {
        let mut doc: toml::Table = toml::from_str(&text).unwrap();
        for key in ["body", "joint", "spring", "bushing", "motion", "output"] {
            if let Some(toml::Value::Array(a)) = doc.get_mut(key) {
                shuffle(a, &mut seed);
            }
        }
        let shuffled = toml::to_string(&doc).unwrap();
        let m = from_text("shuffled.toml", &shuffled).unwrap();
        let (_, r) = run(&m, 500.0);
        for ch in &r0.channels {
            let a = r0.channel(&ch.name).unwrap();
            let b = r.channel(&ch.name).unwrap();
            let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
            let worst = a
                .iter()
                .zip(&b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                worst <= 1e-9 * scale,
                "trial {trial}: {} differs by {worst:e} (scale {scale:e})",
                ch.name
            );
        }
    }
}

#[test]
fn analytic_jacobian_matches_finite_differences() {
    for file in [
        repo!("scenes/examples/elements.toml"),
        repo!("scenes/examples/andrews.toml"),
    ] {
        let m = load(file);
        let sys = System::new(m.model.clone());
        let (mut q, mut v) = sys.initial_q_v();
        let (mut y, yp, _) =
            towride_mbs::model::ic::initial_state(&sys, 0.0, &mut q, &mut v, &[]).unwrap();
        // a generic state: velocities and multipliers perturbed, mu = 0 (GGL solution)
        let (_, ov, ol, om) = sys.offsets();
        for (i, x) in y[ov..om].iter_mut().enumerate() {
            *x += 0.3 * ((i as f64) * 1.7).sin() * (1.0 + x.abs());
        }
        let _ = ol;
        let (t, cj) = (0.137, 250.0);
        let n = sys.size();
        let mut e = Vec::new();
        sys.jacobian(t, &y, &yp, cj, &mut JacobianSink::new(&mut e));
        let mut a = vec![vec![0.0; n]; n];
        for (r, c, val) in e {
            a[r][c] += val;
        }
        let res = |y: &[f64], yp: &[f64]| {
            let mut r = vec![0.0; n];
            sys.residual(t, y, yp, &mut r);
            r
        };
        let mut worst: f64 = 0.0;
        let mut norm: f64 = 0.0;
        for j in 0..n {
            let h = 1e-6 * (1.0 + y[j].abs());
            let (mut ya, mut yb, mut ypa, mut ypb) = (y.clone(), y.clone(), yp.clone(), yp.clone());
            ya[j] += h;
            yb[j] -= h;
            ypa[j] += h;
            ypb[j] -= h;
            let (r1, r2) = (res(&ya, &yp), res(&yb, &yp));
            let (r3, r4) = (res(&y, &ypa), res(&y, &ypb));
            for i in 0..n {
                let fd = (r1[i] - r2[i]) / (2.0 * h) + cj * (r3[i] - r4[i]) / (2.0 * h);
                worst = worst.max((fd - a[i][j]).abs());
                norm = norm.max(fd.abs());
            }
        }
        assert!(
            worst < 1e-6 * norm,
            "{file}: worst {worst:e}, norm {norm:e}"
        );
    }
}

#[test]
fn malformed_files_are_refused_with_file_line_and_field() {
    let good = std::fs::read_to_string(repo!("scenes/examples/pendulum.toml")).unwrap();
    let cases = [
        (
            "mass_kg = 1.0",
            "mass_kg = 1.0\ncolour = \"red\"",
            "colour",
            "body[0]",
        ),
        ("mass_kg = 1.0\n", "", "mass_kg", "body[0]"),
        (
            "inertia_kg_m2 = [1e-9, 1e-9, 1e-9]",
            "inertia_kg_m2 = [1e-9, -1e-9, 1e-9]",
            "positive",
            "body[0].inertia_kg_m2[1]",
        ),
        (
            "body_j = \"ground\"",
            "body_j = \"frame\"",
            "frame",
            "joint[0].body_j",
        ),
        (
            "cm_position_m = [1.0, 0.0, 0.0]",
            "cm_position_m = [1.0, nan, 0.0]",
            "finite",
            "body[0].cm_position_m[1]",
        ),
    ];
    for (from, to, says, field) in cases {
        assert!(good.contains(from));
        let text = good.replacen(from, to, 1);
        let err = match from_text("bad.toml", &text) {
            Err(e) => e,
            Ok(_) => panic!("accepted: {to}"),
        };
        let msg = err.to_string();
        assert!(err.line.is_some(), "{msg}");
        assert!(msg.starts_with("bad.toml:"), "{msg}");
        assert!(msg.contains(says), "{msg}");
        assert!(err.field.starts_with(field), "{msg} (field {})", err.field);
        // the line named holds the offending text (or its table header)
        let line = text.lines().nth(err.line.unwrap() - 1).unwrap();
        let key = field.rsplit('.').next().unwrap().split('[').next().unwrap();
        assert!(
            line.contains(key) || line.contains("[[body]]") || line.contains(says),
            "line {}: {line} ({msg})",
            err.line.unwrap()
        );
    }
}

#[test]
fn statics_from_far_away() {
    // A 1 kg bar, CM 0.5 m from a pivot about y, on a torsion spring (20 N m/rad, free
    // when horizontal), started 2.5 rad away. Equilibrium: k theta = -m g r cos(theta),
    // unique because k > m g r.
    let (k, m, g, r) = (20.0f64, 1.0f64, 9.81f64, 0.5f64);
    let th0 = 2.5f64;
    let text = format!(
        r#"[model]
name = "bar on a torsion spring"
gravity_m_s2 = [0.0, 0.0, -{g}]
[run]
end_time_s = 1.0
sample_rate_hz = 100.0
start = "statics"
[[body]]
name = "bar"
mass_kg = {m}
inertia_kg_m2 = [0.001, 0.02, 0.02]
cm_position_m = [{x}, 0.0, {z}]
x_axis = [{cx}, 0.0, {cz}]
[[joint]]
name = "pivot"
type = "revolute"
body_i = "bar"
body_j = "ground"
position_m = [0.0, 0.0, 0.0]
z_axis = [0.0, -1.0, 0.0]
[[rotational_spring]]
name = "torsion"
body_i = "bar"
body_j = "ground"
position_m = [0.0, 0.0, 0.0]
z_axis = [0.0, -1.0, 0.0]
x_axis = [1.0, 0.0, 0.0]
stiffness_n_m_rad = {k}
# markers are made at the initial pose, so the spring is free {th0} rad back from there
free_angle_rad = -{th0}
"#,
        x = r * th0.cos(),
        z = r * th0.sin(),
        cx = th0.cos(),
        cz = th0.sin()
    );
    let mech = from_text("torsion.toml", &text).unwrap();
    let sys = System::new(mech.model);
    let st = statics::equilibrium(&sys, 0.0, &mech.solver).unwrap();
    // independent root of k th + m g r cos th = 0 by bisection
    let (mut lo, mut hi) = (-1.0f64, 1.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if k * mid + m * g * r * mid.cos() > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let th = 0.5 * (lo + hi);
    let (x, z) = (st.y[0], st.y[2]);
    assert!(
        (z.atan2(x) - th).abs() < 1e-9,
        "angle {} vs {th}",
        z.atan2(x)
    );
    assert!(
        st.report.iterations > 2 && st.report.residual_force < 1e-8,
        "{:?}",
        st.report
    );
}

/// The bob's acceleration against the pendulum's own kinematics: centripetal v^2/L (from
/// energy, v^2 = -2 g z) plus the tangential part of gravity. From the acceleration-level
/// solve the centripetal part comes entirely from the constraint acceleration term and
/// holds to round-off at the sampled state; from the integrator's interpolant it carries
/// the integration error of v' (rtol = atol = 1e-8 here).
#[test]
fn pendulum_acceleration_has_the_centripetal_term() {
    let worst_of = |source: &str| {
        let text = std::fs::read_to_string(repo!("scenes/examples/pendulum.toml"))
            .unwrap()
            .replace(
                "sample_rate_hz = 1000.0",
                &format!("sample_rate_hz = 1000.0\naccelerations = \"{source}\""),
            )
            .replace(
                "[[output]]\nmarker = \"bob.cm\"\nquantity = \"position\"",
                "[[output]]\nmarker = \"bob.cm\"\nquantity = \"position\"\n\n[[output]]\nmarker = \"bob.cm\"\nquantity = \"acceleration\"",
            );
        let m = from_text("pendulum_acc.toml", &text).unwrap();
        let (_, r) = run(&m, 200.0);
        let ch = |n: &str| r.channel(n).unwrap_or_else(|| panic!("no channel {n}"));
        let (x, z) = (ch("bob.cm.position.x"), ch("bob.cm.position.z"));
        let (ax, az) = (ch("bob.cm.acceleration.x"), ch("bob.cm.acceleration.z"));
        let g = 9.81;
        let mut worst = 0.0f64;
        for k in 1..x.len() {
            let l = (x[k] * x[k] + z[k] * z[k]).sqrt();
            let (rx, rz) = (x[k] / l, z[k] / l);
            let centripetal = -2.0 * g * z[k] / l;
            let g_radial = -g * rz;
            let want = [
                -centripetal * rx - g_radial * rx,
                -centripetal * rz - g - g_radial * rz,
            ];
            worst = worst
                .max((ax[k] - want[0]).abs())
                .max((az[k] - want[1]).abs());
        }
        worst / g
    };
    let solve = worst_of("solve");
    assert!(solve < 1e-5, "solve: largest acceleration error {solve} g");
    let interp = worst_of("interpolant");
    assert!(
        interp < 1e-5,
        "interpolant: largest acceleration error {interp} g"
    );
    eprintln!("largest acceleration error: solve {solve:.2e} g, interpolant {interp:.2e} g");
}

/// The constraint rows' velocity Jacobian B and time derivative g_t (written in closed
/// form on the marker frames) against central differences of the rows along each
/// velocity-space direction and in time: rigid joints and a motor (Andrews' mechanism,
/// the elements example), and the vehicle, whose hitch brackets and ball sit on a modal
/// body's markers.
#[test]
fn constraint_jacobian_matches_differences_of_the_rows() {
    let mut systems = Vec::new();
    for file in [
        repo!("scenes/examples/andrews.toml"),
        repo!("scenes/examples/elements.toml"),
    ] {
        systems.push((file, System::new(load(file).model)));
    }
    let scene = towride_app::scene::load(Path::new(repo!("scenes/default.toml"))).unwrap();
    systems.push((
        repo!("scenes/default.toml"),
        System::new(scene.model().clone()),
    ));
    for (file, sys) in &systems {
        let (q0, v0) = sys.initial_q_v();
        // A general state: every body turned and moved a little, modes deflected.
        let mut q = q0.clone();
        let dx: Vec<f64> = (0..v0.len())
            .map(|i| 0.02 * ((i * 37 % 11) as f64 / 11.0 - 0.5))
            .collect();
        sys.apply_increment(&mut q, &dx);
        let t = 0.013;
        let mut worst = 0.0f64;
        for e in &sys.cons {
            let ev = sys.con_eval(e, t, &q);
            let bodies = sys.bodies_of(e.mi, e.mj);
            let scale = ev.b.iter().fold(1e-12f64, |m, x| m.max(x.abs()));
            for (side, body) in bodies.iter().enumerate() {
                let Some(b) = body else { continue };
                for c in 0..ev.w[side] {
                    let h = 1e-6;
                    let mut d = vec![0.0; sys.nv];
                    d[sys.vo[*b] + c] = h;
                    let mut qp = q.clone();
                    sys.apply_increment(&mut qp, &d);
                    d[sys.vo[*b] + c] = -h;
                    let mut qm = q.clone();
                    sys.apply_increment(&mut qm, &d);
                    let (gp, gm) = (sys.con_eval(e, t, &qp).g, sys.con_eval(e, t, &qm).g);
                    for r in 0..ev.g.len() {
                        let fd = (gp[r] - gm[r]) / (2.0 * h);
                        worst = worst.max((fd - ev.at(r, side, c)).abs() / scale);
                    }
                }
            }
            let h = 1e-6;
            let (gp, gm) = (sys.con_eval(e, t + h, &q).g, sys.con_eval(e, t - h, &q).g);
            for r in 0..ev.g.len() {
                worst = worst.max(((gp[r] - gm[r]) / (2.0 * h) - ev.gt[r]).abs() / scale);
            }
        }
        // Central differences at h = 1e-6: truncation ~h^2, round-off ~1e-16/h.
        assert!(
            worst < 1e-7,
            "{file}: largest relative difference {worst:e}"
        );
        eprintln!("{file}: B and g_t agree with central differences to {worst:.1e}");
    }
}

/// The dF/dy' part the system reports with its iteration matrix (`add_scaled`, used to
/// rebuild the matrix for a new step size) equals (J(cj) - J(0)) / cj: every cj term is
/// reported, none twice.
#[test]
fn reported_yp_part_is_the_cj_part_of_the_matrix() {
    let scene = towride_app::scene::load(Path::new(repo!("scenes/default.toml"))).unwrap();
    for sys in [
        System::new(load(repo!("scenes/examples/elements.toml")).model),
        System::new(scene.model().clone()),
    ] {
        let n = sys.size();
        let (q, v) = sys.initial_q_v();
        let mut y = q.clone();
        y.extend_from_slice(&v);
        y.resize(n, 0.0);
        let yp = vec![0.0; n];
        let dense = |e: &[(usize, usize, f64)]| {
            let mut a = vec![0.0; n * n];
            for &(r, c, x) in e {
                a[r * n + c] += x;
            }
            a
        };
        let cj = 1.7e3;
        let (mut e1, mut yp_e, mut e0) = (Vec::new(), Vec::new(), Vec::new());
        sys.jacobian(
            0.0,
            &y,
            &yp,
            cj,
            &mut JacobianSink::with_yp(&mut e1, &mut yp_e),
        );
        sys.jacobian(0.0, &y, &yp, 0.0, &mut JacobianSink::new(&mut e0));
        let (a1, a0, m) = (dense(&e1), dense(&e0), dense(&yp_e));
        let scale = a1.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        let worst = (0..n * n).fold(0.0f64, |w, k| w.max((a1[k] - a0[k] - cj * m[k]).abs()));
        assert!(!yp_e.is_empty());
        assert!(
            worst <= 1e-9 * scale,
            "cj part differs by {worst:e} (scale {scale:e})"
        );
    }
}

/// Each rigid constraint's Jacobian pattern written from its topology equals the entries
/// its structural evaluation emits, as a set, on the vehicle and four example mechanisms
/// (so the iteration matrix keeps its structure and its fill-reducing order).
#[test]
fn rigid_constraint_patterns_from_topology_match_their_structural_evaluation() {
    let vehicle = towride_app::job::Job::from_scene_file(
        Path::new(repo!("scenes/default.toml")),
        &Default::default(),
        &towride_mbs::input::Loader::new(),
    )
    .expect("default scene");
    let (checked, differ) = vehicle.system.check_rigid_patterns();
    assert!(checked >= 10, "{checked} constraints checked");
    assert!(differ.is_empty(), "patterns differ: {differ:?}");
    for example in [
        repo!("scenes/examples/andrews.toml"),
        repo!("scenes/examples/elements.toml"),
        repo!("scenes/examples/pendulum.toml"),
        repo!("scenes/examples/two_mass_chain.toml"),
    ] {
        let sys = System::new(load(example).model);
        let (_, differ) = sys.check_rigid_patterns();
        assert!(differ.is_empty(), "{example}: patterns differ: {differ:?}");
    }
}

/// `Request::Transmitted` of a bushing: a block whose centre of mass is the bushing's
/// marker I, hung on the ground (J) by a bushing stiffer in z than in x, under gravity
/// at 45 deg in the x-z plane. At rest the ground takes the weight W, and since the
/// deflection d = K^-1 W is not parallel to W the moment about J is d x W:
/// m_y = (m g)^2 (1/k_x - 1/k_z) (the bushing's own torque is zero: W acts at I).
#[test]
fn a_bushing_passes_its_load_and_the_deflections_moment_into_body_j() {
    use towride_mbs::model::desc::{Axes, Carrier, ElementHandle, Output, Request};
    let (mass, g, kx, kz) = (10.0, 9.81, 1.0e4, 2.0e4);
    let text = format!(
        r#"[model]
name = "block on a bushing"
gravity_m_s2 = [{g}, 0.0, -{g}]
[run]
end_time_s = 1.0
sample_rate_hz = 100.0
[[body]]
name = "block"
mass_kg = {mass}
inertia_kg_m2 = [0.1, 0.1, 0.1]
cm_position_m = [0.0, 0.0, 1.0]
[[bushing]]
name = "mount"
body_i = "block"
body_j = "ground"
position_m = [0.0, 0.0, 1.0]
stiffness_n_m = [{kx}, {kx}, {kz}]
damping_n_s_m = [10.0, 10.0, 10.0]
stiffness_n_m_rad = [1000.0, 1000.0, 1000.0]
damping_n_m_s_rad = [1.0, 1.0, 1.0]
"#
    );
    let mut m = from_text("block.toml", &text).unwrap();
    m.model.outputs = vec![Output::new(
        "mount",
        Request::Transmitted {
            by: Carrier::Element(ElementHandle::new(0)),
            axes: Axes::World,
        },
    )];
    let sys = System::new(m.model.clone());
    let st = statics::equilibrium(&sys, 0.0, &m.solver).unwrap();
    let got = towride_mbs::model::output::evaluate(&sys, 0.0, &st.y, &st.yp);
    let w = mass * g;
    let want = [w, 0.0, -w, 0.0, w * w * (1.0 / kx - 1.0 / kz), 0.0];
    println!("transmitted {got:?}, statics {want:?}");
    for c in 0..6 {
        assert!(
            (got[c] - want[c]).abs() < 1e-6 * w,
            "{c}: {got:?} vs {want:?}"
        );
    }
}
