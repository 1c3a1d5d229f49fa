//! Sensitivity and calibration over a ring tyre's independent factors: the default lists
//! offer the factors instead of the coupled `.tir` values, a Morris study over +-30 % of
//! every factor has no refused run where the raw values' has, and calibrate's automatic
//! bounds stay inside a factor's open range.

use std::path::{Path, PathBuf};

use towride_app::calibrate::output::auto_candidates;
use towride_app::study::sensitivity::params::candidates;
use towride_app::study::sensitivity::{run, Method, Settings};
use towride_mbs::progress::Silent;

const SCENE: &str = repo!("scenes/car_ramp.toml");
const TYRE: &str = "vehicles/tyres/car_185_60r14.tir";
const FACTORS: [&str; 7] = [
    "total_mass_kg",
    "belt_mass_share",
    "spin_inertia_kg_m2",
    "belt_inertia_share",
    "vertical_stiffness_n_m",
    "ring_stiffness_ratio",
    "longitudinal_tread_share",
];

fn morris(params: Vec<String>) -> towride_app::study::sensitivity::Study {
    let s = Settings {
        file: PathBuf::from(SCENE),
        params,
        method: Method::Morris,
        trajectories: 2,
        jobs: 2,
        ..Settings::default()
    };
    run(&s, &Silent).unwrap()
}

#[test]
fn a_morris_study_over_the_tyre_factors_refuses_no_run() {
    let st = morris(
        FACTORS
            .iter()
            .map(|f| format!("{TYRE}:factor.{f}"))
            .collect(),
    );
    assert_eq!(st.runs, 2 * (FACTORS.len() + 1) + 1);
    assert!(st.failed.is_empty(), "{:?}", st.failed);
    // Every factor moved the output in some step (each is live in the model).
    for p in &st.params {
        assert_eq!(p.morris[0].effects, 2, "{}", p.param.name);
    }
    // The same +-30 % on the raw values the factors drive leaves the valid region:
    // BELT_MASS x 1.3 exceeds MASS x 0.7, and so on.
    let raw = [
        "INERTIA.MASS",
        "INERTIA.BELT_MASS",
        "INERTIA.IYY",
        "INERTIA.BELT_IYY",
    ];
    let st = morris(raw.iter().map(|k| format!("{TYRE}:{k}")).collect());
    assert!(!st.failed.is_empty(), "raw values: no refused run");
}

#[test]
fn default_lists_offer_the_factors_instead_of_the_values_they_drive() {
    let all = candidates(Path::new(SCENE), &["tyres".into()]).unwrap();
    let names: Vec<&str> = all.iter().map(|p| p.name.as_str()).collect();
    for f in FACTORS {
        assert!(
            names.contains(&format!("{TYRE}:factor.{f}").as_str()),
            "{f}"
        );
    }
    // Calibrate's automatic list: the assumed factors (the total mass is `assumed` in
    // the file, so is every factor computed from it), no raw value they drive, and
    // bounds that keep a share below 1.
    let (specs, _) = auto_candidates(Path::new(SCENE)).unwrap();
    let of = |n: &str| specs.iter().find(|s| s.name == format!("{TYRE}:{n}"));
    let share = of("factor.belt_mass_share").expect("belt share offered");
    assert_eq!(share.class, "assumed");
    let s = 5.45 / 7.0;
    // The margin to 1 halves at most: hi = 1 - (1 - s) / 2.
    assert!(
        (share.hi - (1.0 - (1.0 - s) / 2.0)).abs() < 1e-12,
        "{}",
        share.hi
    );
    assert!((share.lo - s / 2.0).abs() < 1e-12, "{}", share.lo);
    let mass = of("factor.total_mass_kg").expect("total mass offered");
    assert!((mass.lo - 3.5).abs() < 1e-12 && (mass.hi - 14.0).abs() < 1e-12);
    for k in ["INERTIA.MASS", "INERTIA.BELT_MASS", "STRUCTURAL.FREQ_LONG"] {
        assert!(of(k).is_none(), "{k} offered beside the factors");
    }
}
