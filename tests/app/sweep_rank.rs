//! `sweep rank`: a summary table ranked by one parameter over the others, checked on a
//! table written here whose means, extremes and ranks are known by hand.

use towride_app::sweep::{page, rank};

/// Three variants at two speeds; variant 2 has the lowest force, variant 3 the lowest
/// energy and variant 1 the smallest pull (the least negative minimum); one case
/// failed, one did not converge.
const TABLE: &str = "\
case,hitch_variant,speed_km_h,status,wall_time [s],hitch_fx abs_peak [N],crossbeam strain energy max [J],hitch_fx min [N],steps,converged [-],error
0,1,30,completed,0.5,100,9,-20,10,1,
1,1,60,completed,0.5,140,11,-40,10,1,
2,2,30,completed,0.5,80,6,-50,10,1,
3,2,60,completed,0.5,100,8,-70,10,0,
4,3,30,completed,0.5,120,3,-45,10,1,
5,3,60,failed,0.5,,,,,,diverged
";

fn table() -> page::Table {
    let dir = std::env::temp_dir().join(format!("towride_rank_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("summary.csv");
    std::fs::write(&csv, TABLE).unwrap();
    page::read(&csv).unwrap()
}

#[test]
fn variants_are_ranked_by_their_mean_over_the_band_with_its_extremes() {
    let r = rank::rank(&table(), "hitch_variant", &[]).unwrap();
    assert_eq!(r.over, vec!["speed_km_h".to_string()]);
    // Solver effort and the verdict are not ranked.
    let names: Vec<&str> = r.figures.iter().map(|f| f.figure.as_str()).collect();
    assert_eq!(
        names,
        [
            "hitch_fx abs_peak [N]",
            "crossbeam strain energy max [J]",
            "hitch_fx min [N]"
        ]
    );
    let fx = &r.figures[0];
    let want = [
        ("1", 120.0, 100.0, 140.0, 2, 0, 0, 2),
        ("2", 90.0, 80.0, 100.0, 2, 0, 1, 1),
        ("3", 120.0, 120.0, 120.0, 1, 1, 0, 3),
    ];
    for (e, w) in fx.entries.iter().zip(want) {
        assert_eq!(
            (e.value.as_str(), e.mean, e.min, e.max),
            (w.0, w.1, w.2, w.3)
        );
        assert_eq!((e.cases, e.missing, e.unconverged), (w.4, w.5, w.6));
        // Variants 1 and 3 tie at 120 N: the table's order decides.
        assert_eq!(e.rank, w.7, "{e:?}");
    }
    assert_eq!(fx.best, "2");
    // (140 - 100) / 120 for variant 1 is the widest band.
    assert!((fx.largest_spread - 40.0 / 120.0).abs() < 1e-12);
    assert_eq!(r.figures[1].best, "3");
    // A signed minimum ranks by its magnitude: -30 N (variant 1) before -45 and -60 N.
    let pull = &r.figures[2];
    let ranks: Vec<(f64, usize)> = pull.entries.iter().map(|e| (e.mean, e.rank)).collect();
    assert_eq!(ranks, [(-30.0, 1), (-60.0, 3), (-45.0, 2)]);
    assert_eq!(pull.best, "1");
    assert!(r.rankings_disagree);
}

#[test]
fn unknown_parameters_and_figures_are_named() {
    let t = table();
    let e = rank::rank(&t, "load_case", &[]).unwrap_err();
    assert!(
        e.contains("'load_case'") && e.contains("hitch_variant, speed_km_h"),
        "{e}"
    );
    let e = rank::rank(&t, "hitch_variant", &["hitch_fz abs_peak".into()]).unwrap_err();
    assert!(e.contains("'hitch_fz abs_peak'"), "{e}");
    // A figure asked by its name without the unit.
    let r = rank::rank(&t, "hitch_variant", &["crossbeam strain energy max".into()]).unwrap();
    assert_eq!(r.figures.len(), 1);
    assert!(!r.rankings_disagree);
}
