//! All ten crossbeam variants run the default scene, and the crossbeam's peak deflection
//! (ball relative to brackets) falls monotonically as the variants stiffen.

use std::path::Path;

use towride_app::job::Job;
use towride_app::scene::Changes;
use towride_mbs::input::Loader;
use towride_mbs::progress::Silent;

fn peak_deflection(variant: u32) -> (f64, f64) {
    let changes = Changes {
        hitch_variant: Some(variant),
        ..Default::default()
    };
    let r = Job::from_scene_file(
        Path::new(repo!("scenes/default.toml")),
        &changes,
        &Loader::new(),
    )
    .unwrap()
    .run(&Silent)
    .unwrap();
    assert!(r.completed(), "variant {variant}: {:?}", r.failure());
    let ch = |n: &str| r.channel(n).unwrap();
    let (x, y, z) = (
        ch("hitch_deflection_x"),
        ch("hitch_deflection_y"),
        ch("hitch_deflection_z"),
    );
    let d = (0..x.len()).fold(0.0f64, |m, k| {
        m.max((x[k] * x[k] + y[k] * y[k] + z[k] * z[k]).sqrt())
    });
    (d, r.abs_peak("hitch_fx").unwrap())
}

#[test]
fn all_ten_variants_run_and_stiffer_crossbeams_deflect_less() {
    let results: Vec<(u32, (f64, f64))> = std::thread::scope(|s| {
        let handles: Vec<_> = [(1..=5), (6..=10)]
            .into_iter()
            .map(|range| {
                s.spawn(move || range.map(|v| (v, peak_deflection(v))).collect::<Vec<_>>())
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect()
    });
    for (v, (d, f)) in &results {
        println!(
            "variant {v:2}: largest ball deflection {:.3} mm, hitch_fx |peak| {f:.0} N",
            d * 1e3
        );
    }
    for w in results.windows(2) {
        assert!(
            w[1].1 .0 < w[0].1 .0,
            "variant {} deflects no less than {}",
            w[1].0,
            w[0].0
        );
    }
}
