//! Integration tests of the physics crate `towride-mbs` (input files, flexible bodies,
//! road, tyre, the multibody model), one module per area, in one test binary. They use
//! nothing of the application crate: a physics test builds its model from a mechanism
//! file, a flex file or a tyre file directly.
//!
//! Paths to the repository's data go through [`repo!`]: tests run with the crate's folder
//! as their working directory.

/// A path to a file of the repository, as a `&'static str` (usable in `const`s).
macro_rules! repo {
    ($p:literal) => {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../", $p)
    };
}

#[path = "../common/mod.rs"]
mod common;

/// The crossbeam file read with the a-priori load-path rule the project shipped until
/// 2026-11-27 (it now keeps every mode, docs/flex.md): the rule `flex_hitch` and `model_modal` check.
pub(crate) fn load_path_rule() -> towride_mbs::input::Loader {
    let f = "flex/hitch_crossbeam.toml";
    let set = [
        "selection.rule=\"load_path\"",
        "selection.band_hz=[0.0, 100.0]",
        "selection.min_energy_share=0.01",
        "selection.load_interfaces=[\"ball\"]",
        "selection.load_moments=false",
    ];
    towride_mbs::input::Loader::with_overrides(
        set.iter()
            .map(|s| towride_mbs::input::Override::from_argument(&format!("{f}:{s}")).unwrap())
            .collect(),
    )
}

mod brake_stick;
mod flex_beam;
mod flex_drawbar;
mod flex_hitch;
mod flex_input;
mod flex_stress;
mod inputs_provenance;
mod law_regularised;
mod model_modal;
mod model_modal_full;
mod model_tyres;
mod road_crg;
mod road_hump;
mod road_obstacles;
mod road_one_sided;
mod road_profile_mesh;
mod road_random;
mod tyre_envelope_profile;
mod tyre_factors;
mod tyre_lateral;
mod tyre_lift_off;
mod tyre_low_speed;
mod tyre_rolling;
mod tyre_static;
mod tyre_tir;
