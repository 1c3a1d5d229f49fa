//! The sensitivity study against analytical references: Morris statistics of a known
//! function, and OAT elasticities of a mass-spring's natural frequency (f ~ sqrt(k / m):
//! -1/2 in the mass, +1/2 in the stiffness).

use std::path::PathBuf;

use towride_app::study::sensitivity::morris::{delta, design, effects};
use towride_app::study::sensitivity::{run, Method, Settings};
use towride_mbs::progress::Silent;

#[test]
fn morris_recovers_the_effects_of_a_known_function() {
    // y = 3 x0 + 2 x1^2 + 0 x2: x0's effect is 3 everywhere (sigma 0), x2 has none, x1's
    // is 2 (2 x1 + Delta), Delta = 2/3, from x1 = 0 or 1/3: 4/3 or 8/3.
    let (k, r, p) = (3, 40, 4);
    let d = design(k, r, p, 7);
    assert_eq!(d, design(k, r, p, 7).clone(), "same seed, same design");
    assert_ne!(
        d[0].points,
        design(k, r, p, 8)[0].points,
        "another seed, another design"
    );
    let f = |x: &[f64]| 3.0 * x[0] + 2.0 * x[1] * x[1];
    let y: Vec<Vec<Option<f64>>> = d
        .iter()
        .map(|t| t.points.iter().map(|x| Some(f(x))).collect())
        .collect();
    for t in &d {
        for x in &t.points {
            assert!(x.iter().all(|v| (0.0..=1.0 + 1e-12).contains(v)), "{x:?}");
        }
    }
    let e = effects(&d, &y, p);
    assert!((delta(p) - 2.0 / 3.0).abs() < 1e-15);
    assert!(
        (e[0].mu_star - 3.0).abs() < 1e-12 && e[0].sigma < 1e-12,
        "{:?}",
        e[0]
    );
    assert!(e[2].mu_star.abs() < 1e-15 && e[2].sigma.abs() < 1e-15);
    // x1's effects take only the two values; their mean and spread follow from how often
    // each base level occurs.
    let lo = d
        .iter()
        .filter(|t| {
            let j = t.order.iter().position(|&i| i == 1).unwrap();
            t.points[j][1] < 0.1
        })
        .count() as f64;
    let n = r as f64;
    let mean = (lo * 4.0 / 3.0 + (n - lo) * 8.0 / 3.0) / n;
    assert!(
        (e[1].mu_star - mean).abs() < 1e-12,
        "{:?} against {mean}",
        e[1]
    );
    assert!(e[1].sigma > 0.3 && e[1].sigma < 0.7, "{:?}", e[1]);
    // A failed run drops only the effects it takes part in.
    let mut y2 = y.clone();
    y2[0][0] = None;
    let e2 = effects(&d, &y2, p);
    assert_eq!(e2.iter().map(|e| e.effects).sum::<usize>(), k * r - 1);
}

#[test]
fn oat_elasticities_of_a_mass_spring_frequency_are_one_half() {
    let s = Settings {
        file: PathBuf::from(repo!("scenes/examples/mass_spring.toml")),
        params: vec![
            "mass_spring.toml:body[0].mass_kg".into(),
            "mass_spring.toml:spring[0].stiffness_n_m".into(),
            // Rotation about z is locked by the slide: no effect.
            "mass_spring.toml:body[0].inertia_kg_m2[2]".into(),
        ],
        outputs: vec!["k1.force.freq".into(), "k1.force.abs_peak".into()],
        method: Method::Oat,
        jobs: 1,
        ..Settings::default()
    };
    let st = run(&s, &Silent).unwrap();
    assert!(st.failed.is_empty() && st.runs == 7);
    let el = |i: usize, o: usize| st.params[i].elasticity[o].unwrap();
    assert!((el(0, 0) + 0.5).abs() < 0.01, "mass: {}", el(0, 0));
    assert!((el(1, 0) - 0.5).abs() < 0.01, "stiffness: {}", el(1, 0));
    assert!(el(2, 0).abs() < 1e-6);
    // The spring's largest force, released from its free length: 2 m g, independent of
    // k, proportional to m.
    assert!(
        (el(0, 1) - 1.0).abs() < 0.02 && el(1, 1).abs() < 0.02,
        "{} {}",
        el(0, 1),
        el(1, 1)
    );
    assert!(
        (st.outputs[0].base - (2000.0f64 / 2.0).sqrt() / (2.0 * std::f64::consts::PI)).abs() < 0.01
    );
    // The ranking puts the two half-elasticities first.
    assert!(st.ranking(0)[2].param.name.ends_with("inertia_kg_m2[2]"));
}

/// The assumed inputs among the most sensitive ones are read from a study's ranking and
/// the source classes written in the vehicle files: a `scaled` and a `published` value
/// ranked above or beside an `assumed` one are left out, a parameter of a file the scene
/// does not read is skipped, and ranks are those of the study.
#[test]
fn assumed_inputs_are_the_assumed_values_among_the_highest_ranked() {
    use towride_app::study::sensitivity::assumed::assumed_inputs;
    let scene = PathBuf::from(repo!("scenes/default.toml"));
    let dir = std::env::temp_dir().join(format!("towride-assumed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let param = |file: &str, path: &str, e: f64| {
        serde_json::json!({
            "param": {"name": format!("{file}:{path}"), "file": file, "path": path},
            "elasticity": [e],
        })
    };
    let study = serde_json::json!({
        "method": "oat",
        "outputs": [{"name": "hitch_fx.abs_peak", "unit": "N"}],
        "params": [
            // `# [assumed] light box trailer class estimate` in the file.
            param("vehicles/trailer/box_trailer.toml", "half.mass_kg", 0.5),
            // `# [scaled] empty trailer 100 kg (thesis 5.5.3.1) ...`
            param("vehicles/trailer/box_trailer.toml", "body.mass_kg", -0.9),
            // `# [published] standard gravity ...`
            param("vehicles/fabia.toml", "vehicle.gravity_m_s2", 0.7),
            param("vehicles/no_such_file.toml", "a.b_kg", 0.6),
            param("vehicles/trailer/box_trailer.toml", "wheel.mass_kg", 0.01),
        ],
    });
    std::fs::write(dir.join("sensitivity.json"), study.to_string()).unwrap();
    let a = assumed_inputs(&scene, &dir, 4);
    assert_eq!(a.note, None);
    assert_eq!(a.output.as_deref(), Some("hitch_fx.abs_peak"));
    // Ranked by |elasticity|: body 0.9, gravity 0.7, missing file 0.6, half 0.5; the
    // wheel (0.01) is fifth, outside the top four.
    assert_eq!(a.inputs.len(), 1, "{a:?}");
    let i = &a.inputs[0];
    assert_eq!(
        (i.rank, i.parameter.as_str(), i.class.as_str()),
        (
            4,
            "vehicles/trailer/box_trailer.toml:half.mass_kg",
            "assumed"
        )
    );
    assert_eq!(i.sensitivity, 0.5);
    assert!(i.source.contains("light box trailer"), "{}", i.source);
    // Without a study the answer says so and lists nothing.
    let none = assumed_inputs(&scene, &dir.join("nothing"), 10);
    assert!(none.inputs.is_empty() && none.note.unwrap().contains("towride sensitivity"));
    std::fs::remove_dir_all(&dir).ok();
}

/// The outputs by their names: `abs_peak`, `max`, `min` of raw or band-limited channels;
/// the former `peak` and `peak100` refused with the name to use, the defaults the hitch
/// force's |peak| and every accelerometer as the instrument saw it.
#[test]
fn outputs_are_named_abs_peak_max_min_raw_or_band_limited() {
    use towride_app::job::Job;
    use towride_app::study::sensitivity::outputs::{resolve, Measure};
    use towride_mbs::input::Loader;
    let job = Job::from_file(
        std::path::Path::new(repo!("scenes/default.toml")),
        &Loader::new(),
    )
    .unwrap();
    let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let o = resolve(
        &names(&["hitch_fx.abs_peak", "hitch_fx.min", "acc_hitch_z_lp100.max"]),
        &job,
    )
    .unwrap();
    assert_eq!(
        o.iter().map(|s| s.measure).collect::<Vec<_>>(),
        [Measure::AbsPeak, Measure::Min, Measure::Max]
    );
    assert_eq!(o[2].unit, "m/s^2");
    let e = resolve(&names(&["hitch_fx.peak"]), &job)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("hitch_fx.abs_peak") && e.contains("hitch_fx.min"),
        "{e}"
    );
    let e = resolve(&names(&["acc_hitch_z.peak100"]), &job)
        .unwrap_err()
        .to_string();
    assert!(e.contains("acc_hitch_z_lp100.abs_peak"), "{e}");
    let d: Vec<String> = resolve(&[], &job)
        .unwrap()
        .iter()
        .map(|s| s.name())
        .collect();
    assert_eq!(
        d[..4],
        [
            "hitch_fx.abs_peak",
            "hitch_fx.rms",
            "hitch_fx.freq",
            "acc_trailer_drawbar_z.abs_peak"
        ]
    );
    assert!(
        d.contains(&"acc_hitch_z_lp100.abs_peak".to_string()),
        "{d:?}"
    );
    assert!(
        !d.iter()
            .any(|n| n.contains("peak100") || n.ends_with(".peak")),
        "{d:?}"
    );
}
