//! Damage per km of a study's `[usage]` spectrum against a hand computation from the
//! spectrum (Miner: damage adds over passages), and a bad block refused with its field.

use towride_app::sweep::page::{Row, Table};
use towride_app::sweep::usage::{per_km, Mix, Usage};
use towride_app::sweep::Sweep;

fn row(case: usize, v: &str, speed: &str, d: Option<f64>) -> Row {
    Row {
        case,
        values: vec![v.into(), speed.into()],
        status: "completed".into(),
        figures: vec![d, Some(1.0)],
        error: String::new(),
        link: None,
    }
}

#[test]
fn damage_per_km_is_obstacles_times_the_share_weighted_passage_damage() {
    let fig = "hitch_stress_p IIW damage per passage [-]";
    let table = Table {
        parameters: vec!["hitch_variant".into(), "speed_km_h".into()],
        figures: vec![fig.into(), "hitch_fx abs_peak [N]".into()],
        rows: vec![
            row(0, "1", "40.0", Some(2.0e-6)),
            row(1, "1", "50.0", Some(4.0e-6)),
            row(2, "2", "40.0", Some(1.0e-6)),
            row(3, "2", "50.0", None),
        ],
    };
    let usage = Usage {
        obstacles_per_km: 3.0,
        mix: vec![
            Mix {
                values: vec![("speed_km_h".into(), "40.0".into())],
                share: 0.25,
            },
            Mix {
                values: vec![("speed_km_h".into(), "50".into())],
                share: 0.75,
            },
        ],
        provenance: Vec::new(),
    };
    let out = per_km(&table, &usage);
    assert_eq!(out.len(), 2, "{out:?}");
    // Variant 1: 3 x (0.25 x 2e-6 + 0.75 x 4e-6) = 1.05e-5 per km; D = 0.5 after
    // 0.5 / 1.05e-5 = 47 619 km.
    assert_eq!(out[0].group, vec![("hitch_variant".into(), "1".into())]);
    assert_eq!(out[0].figure, fig);
    let d = out[0].damage_per_km.unwrap();
    assert!((d - 1.05e-5).abs() < 1e-18, "{d}");
    assert!((out[0].km_to_allowable.unwrap() - 47_619.047_619).abs() < 1e-3);
    // Variant 2 misses its 50 km/h case: no number rather than a partial sum.
    assert_eq!(out[1].damage_per_km, None);
}

#[test]
fn a_usage_block_whose_shares_do_not_add_to_one_is_refused_with_its_field() {
    let dir = std::env::temp_dir().join(format!("towride-usage-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("study.toml");
    let text = format!(
        "[sweep]\nname = \"u\"\nscene = \"{}\"\n\n[[parameter]]\nname = \"speed_km_h\"\n\
         file = \"scenes/default.toml\"\npath = \"run.speed_km_h\"\nvalues = [40.0, 50.0]\n\n\
         [usage]\nobstacles_per_km = 1.0\n\
         mix = [{{ speed_km_h = 40.0, share = 0.5 }}, {{ speed_km_h = 50.0, share = 0.4 }}]\n",
        repo!("scenes/default.toml")
    );
    std::fs::write(&f, &text).unwrap();
    let e = Sweep::load(&f).unwrap_err().to_string();
    assert!(
        e.contains("study.toml") && e.contains("usage.mix") && e.contains("0.9"),
        "{e}"
    );
    // A value the sweep does not run.
    std::fs::write(
        &f,
        text.replace("share = 0.4", "share = 0.5")
            .replace("50.0, share", "55.0, share"),
    )
    .unwrap();
    let e = Sweep::load(&f).unwrap_err().to_string();
    assert!(
        e.contains("usage.mix[1].speed_km_h") && e.contains("55.0"),
        "{e}"
    );
    // The shipped study's block loads.
    let s = Sweep::load(std::path::Path::new(repo!("scenes/hitch_study.toml"))).unwrap();
    let u = s
        .usage
        .expect("the shipped study declares a usage spectrum");
    assert!((u.mix.iter().map(|m| m.share).sum::<f64>() - 1.0).abs() < 1e-12);
    // Its values carry their source class, which the study page shows beside the damage.
    let keys: Vec<(&str, &str)> = u
        .provenance
        .iter()
        .map(|e| (e.key.as_str(), e.class.as_str()))
        .collect();
    assert_eq!(
        keys,
        [
            ("usage.obstacles_per_km", "assumed"),
            ("usage.mix", "assumed")
        ]
    );
    std::fs::remove_dir_all(&dir).ok();
}
