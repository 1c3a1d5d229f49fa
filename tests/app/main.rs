//! Integration tests of the application crate `towride-app` (vehicle templates, scenes,
//! the run pipeline, studies, sweeps, validation, reports), one module per area, all in
//! one test binary (as ripgrep does), so the test build links one executable for the crate.
//! The physics crate's own tests are `tests/mbs/`.
//!
//! Paths to the repository's data (`scenes/`, `vehicles/`, `flex/`, ...) go through
//! [`repo!`]: tests run with the crate's folder as their working directory.

/// A path to a file of the repository, as a `&'static str` (usable in `const`s).
macro_rules! repo {
    ($p:literal) => {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../", $p)
    };
}

#[path = "../common/mod.rs"]
mod common;
mod validate_sim;

mod comfort_iso2631;
mod comfort_seat;
mod comfort_summary;
mod durability_iiw;
mod durability_rainflow;
mod fuzz;
mod fuzz_loggers;
mod fuzz_overrides;
mod hitch_brackets;
mod hitch_stress;
mod inputs_and_builder;
mod job_ringing;
mod model_mechanisms;
mod model_scaling;
mod module_order;
mod reliability;
mod report_compare;
mod report_compare_inputs;
mod report_figures;
mod report_html;
mod report_run_figures;
mod report_view;
mod scene_outputs;
mod study_sensitivity;
mod study_sensitivity_page;
mod study_sensitivity_runs;
mod study_tyre_factors;
mod summary_schema;
mod sweep_rank;
mod sweep_report;
mod sweep_robust;
mod sweep_usage;
mod tyre_cleat;
mod tyre_enveloping;
mod validate_csv;
mod validate_filter_rating;
mod validate_init;
mod validate_init_inputs;
mod validate_init_offsets;
mod validate_logger;
mod validate_mf4;
mod validate_passage;
mod validate_recovery;
mod validate_vehicle;
mod vehicle_assembly;
mod vehicle_braking;
mod vehicle_drawbar;
mod vehicle_driveline;
mod vehicle_engine;
mod vehicle_errors;
mod vehicle_kinematics;
mod vehicle_scene;
mod vehicle_simple;
mod vehicle_simple_calib;
mod vehicle_statics;
mod vehicle_steering;
mod vehicle_templates;
mod vehicle_twist_beam;
mod vehicle_variants;
