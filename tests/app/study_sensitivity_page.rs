//! The sensitivity page as a reader sees it: a tornado chart per output, titled with its
//! name and unit; the method named as engineers write it; a negative output with its
//! sign and its elasticity; tables that fit a 1300 px window with figures to two
//! significant figures.

use std::path::{Path, PathBuf};

use towride_app::study::sensitivity::{run, write, Method, Settings, Study};
use towride_mbs::input::{Loader, Override};
use towride_mbs::progress::Silent;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride_senspage_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The mass on a spring hanging under gravity (gravity upwards from the spring's free
/// length: the spring is stretched, its force negative), a 0.5 s run.
fn hanging_mass(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(repo!("scenes/examples/mass_spring.toml")).unwrap();
    let text = text
        .replacen("end_time_s = 4.0", "end_time_s = 0.5", 1)
        .replacen(
            "gravity_m_s2 = [0.0, 0.0, -9.81]",
            "gravity_m_s2 = [0.0, 0.0, 9.81]",
            1,
        );
    let f = dir.join("mass_spring.toml");
    std::fs::write(&f, text).unwrap();
    f
}

/// An OAT study of the hanging mass over its mass and stiffness.
fn hanging_study(dir: &Path, outputs: &[&str], method: Method) -> Study {
    run(
        &Settings {
            file: hanging_mass(dir),
            params: vec![
                "mass_spring.toml:body[0].mass_kg".into(),
                "mass_spring.toml:spring[0].stiffness_n_m".into(),
            ],
            outputs: outputs.iter().map(|s| s.to_string()).collect(),
            method,
            trajectories: 2,
            jobs: 2,
            ..Settings::default()
        },
        &Silent,
    )
    .unwrap()
}

/// The text between each `open` and the next `close` in `page`.
fn between<'a>(page: &'a str, open: &str, close: &str) -> Vec<&'a str> {
    page.split(open)
        .skip(1)
        .map(|s| s.split(close).next().unwrap())
        .collect()
}

#[test]
fn every_output_has_its_own_tornado_chart_titled_with_its_name_and_unit() {
    let d = tmp("charts");
    let outputs = ["k1.force.abs_peak", "k1.force.min", "k1.force.freq"];
    let mut st = hanging_study(&d, &outputs, Method::Oat);
    let out = d.join("out");
    write::write(&mut st, &out).unwrap();
    let page = std::fs::read_to_string(out.join("sensitivity.html")).unwrap();
    let images: Vec<&str> = between(&page, "<img src=\"", "\"");
    assert_eq!(
        images.len(),
        outputs.len(),
        "one chart per output: {images:?}"
    );
    for (img, (name, unit)) in images.iter().zip(outputs.iter().zip(["N", "N", "Hz"])) {
        assert!(out.join(img).is_file(), "{img} written");
        assert!(img.contains(name), "{img} is the chart of {name}");
        // Its text alternative names the output and its unit, as its title does.
        let after = &page[page.find(img).unwrap()..];
        let alt = between(after, "alt=\"", "\"")[0];
        assert!(alt.contains(&format!("{name} [{unit}]")), "{name}: {alt}");
    }
    // The study lists each chart among its files.
    let pngs = st.written.iter().filter(|w| w.ends_with(".png")).count();
    assert_eq!(pngs, outputs.len(), "{:?}", st.written);
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn the_method_is_named_as_engineers_write_it() {
    let d = tmp("method");
    let st = hanging_study(&d, &["k1.force.freq"], Method::Oat);
    let page = write::page(&st);
    let intro = between(&page, "</h1>", "</p>")[0];
    assert!(intro.contains("OAT (one-at-a-time) study"), "{intro}");
    assert!(!page.contains("Oat"), "no Debug spelling");
    let st = hanging_study(&d, &["k1.force.freq"], Method::Morris);
    let intro = write::page(&st);
    let intro = between(&intro, "</h1>", "</p>")[0].to_string();
    assert!(intro.contains("<b>Morris screening"), "{intro}");
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn a_negative_output_keeps_its_sign_and_has_an_elasticity() {
    let d = tmp("negative");
    let st = hanging_study(&d, &["k1.force.min", "k1.force.abs_peak"], Method::Oat);
    let (min, peak) = (&st.outputs[0], &st.outputs[1]);
    // Stretched: the force's largest magnitude is a pull of about 2 m g = 39 N.
    assert!(min.base < -30.0, "{min:?}");
    assert_eq!(peak.base, -min.base);
    // The peak pull is 2 m g: proportional to the mass (elasticity 1), whatever the
    // stiffness; |y| changes as y does, so the sign of y is no reason to drop it.
    let e = st.params[0].elasticity[0].expect("an elasticity of a negative output");
    assert!((e - 1.0).abs() < 0.02, "mass: {e}");
    // Read through the JSON, as a reader of `sensitivity.json` does.
    let json = serde_json::to_value(peak).unwrap();
    assert_eq!(
        json["base_signed"].as_f64(),
        Some(min.base),
        "the peak's own sign"
    );
    let page = write::page(&st);
    let rows = between(&page, "<tr><td>k1.force.", "</tr>");
    let shown = format!("{:.2} N", min.base);
    assert!(
        rows[0].contains(&shown),
        "the min's base {shown}: {}",
        rows[0]
    );
    assert!(
        rows[1].contains(&shown),
        "the |peak|'s signed value {shown}: {}",
        rows[1]
    );
    assert!(!page.contains("NaN"));
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn tables_of_many_outputs_fit_the_window_with_two_significant_figures() {
    let scene = PathBuf::from(repo!("scenes/van_air/bump_50mm.toml"));
    let short = Override::from_argument("van_air/bump_50mm.toml:run.duration_s=0.4").unwrap();
    let mut outputs: Vec<String> = ["front_left", "front_right", "rear_left", "rear_right"]
        .iter()
        .flat_map(|w| ["abs_peak", "max", "min"].map(|m| format!("acc_wheel_{w}_z_lp100.{m}")))
        .collect();
    outputs.truncate(10);
    let st = run(
        &Settings {
            file: scene,
            base: Loader::with_overrides(vec![short]),
            params: vec!["van.toml:tyre.vertical_stiffness_n_m".into()],
            outputs: outputs.clone(),
            jobs: 2,
            ..Settings::default()
        },
        &Silent,
    )
    .unwrap();
    let page = write::page(&st);
    // Ten outputs: two tables, eight and two output columns beside the parameter.
    let tables = between(&page, "<table class=\"figures\">", "</table>");
    assert_eq!(tables.len(), 2, "{page}");
    let heads = |t: &str| between(t, "<th class=\"out\">", "</th>").len();
    assert_eq!((heads(tables[0]), heads(tables[1])), (8, 2));
    // Every output's column names its unit.
    let named = tables
        .iter()
        .flat_map(|t| between(t, "<th class=\"out\">", "</th>"))
        .filter(|h| h.ends_with("[m/s²]"))
        .count();
    assert_eq!(named, 10);
    // The figures: signed, two significant figures (0.87, not 0.8695).
    let e = st.params[0].elasticity[0].unwrap();
    let cells: Vec<&str> = between(tables[0], "<td style=\"", "</td>")
        .into_iter()
        .map(|c| c.rsplit('>').next().unwrap())
        .collect();
    assert_eq!(cells.len(), 8, "{cells:?}");
    let want = format!("{e:+.2}");
    assert!(e > 0.1 && e < 1.0, "{e}");
    assert_eq!(cells[0], want, "{cells:?}");
    for c in &cells {
        let digits: String = c
            .split('e')
            .next()
            .unwrap()
            .chars()
            .filter(char::is_ascii_digit)
            .collect();
        let figures = digits.trim_start_matches('0').len();
        assert!(figures <= 2 && c.starts_with(['+', '-']), "{c}");
    }
}
