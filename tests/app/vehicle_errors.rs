//! Malformed vehicle, property and scene files give errors that name the file, the line
//! and the field. Each case copies the shipped files to a scratch folder, breaks one
//! line, and checks the error against the line it broke.

use std::path::{Path, PathBuf};

use towride_app::vehicle::{self, Options};
use towride_mbs::input::InputError;

/// A scratch folder, removed when dropped.
pub(crate) struct Scratch(PathBuf);

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

/// A scratch copy of the files a scene needs, in the repository's layout.
pub(crate) fn scratch(tag: &str) -> Scratch {
    let root = std::env::temp_dir().join(format!(
        "towride_vehicle_errors_{}_{tag}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&root);
    for f in [
        "vehicles/fabia_trailer.toml",
        "vehicles/fabia/body.toml",
        "vehicles/fabia/engine.toml",
        "vehicles/fabia/front_mcpherson.toml",
        "vehicles/fabia/rear_twist_beam.toml",
        "vehicles/fabia/driveline.toml",
        "vehicles/fabia/hitch.toml",
        "vehicles/trailer/box_trailer.toml",
        "vehicles/tyres/car_185_60r14.tir",
        "vehicles/tyres/trailer_155_80r13.tir",
        "flex/hitch_crossbeam.toml",
        "flex/twist_beam.toml",
        "roads/ramp_thesis.toml",
        "scenes/default.toml",
    ] {
        let to = root.join(f);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(Path::new(repo!("")).join(f), &to).unwrap();
    }
    Scratch(root)
}

/// Replaces the first `from` in `file` by `to`; returns the 1-based line of the change.
fn break_file(root: &Path, file: &str, from: &str, to: &str) -> usize {
    let p = root.join(file);
    let text = std::fs::read_to_string(&p).unwrap();
    let at = text
        .find(from)
        .unwrap_or_else(|| panic!("'{from}' not in {file}"));
    std::fs::write(&p, text.replacen(from, to, 1)).unwrap();
    text[..at].matches('\n').count() + 1
}

fn vehicle_error(root: &Path) -> InputError {
    vehicle::load(
        &root.join("vehicles/fabia_trailer.toml"),
        &Options::default(),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap_err()
}

fn check(e: &InputError, file: &str, line: usize, field: &str) {
    assert!(e.file.ends_with(file), "{e}");
    assert_eq!(e.line, Some(line), "{e}");
    assert!(e.field.starts_with(field), "{e}");
    assert!(e.to_string().contains(&format!(":{line}:")), "{e}");
}

#[test]
fn negative_mass_in_a_property_file() {
    let root = scratch("mass");
    let f = "vehicles/fabia/front_mcpherson.toml";
    let line = break_file(&root, f, "mass_kg = 3.2", "mass_kg = -3.2");
    check(&vehicle_error(&root), f, line, "lower_arm.mass_kg");
}

#[test]
fn misspelt_field_is_named_with_its_line() {
    let root = scratch("typo");
    let f = "vehicles/fabia/rear_twist_beam.toml";
    let line = break_file(
        &root,
        f,
        "stiffness_n_m = 32000.0",
        "stifness_n_m = 32000.0",
    );
    let e = vehicle_error(&root);
    check(&e, f, line, "spring");
    assert!(e.message.contains("stifness_n_m"), "{e}");
}

#[test]
fn seat_values_out_of_range() {
    let f = "vehicles/fabia/body.toml";
    for (from, to, field) in [
        (
            "occupant_moving_fraction = 0.8",
            "occupant_moving_fraction = 1.0",
            "seat.occupant_moving_fraction",
        ),
        (
            "cushion_damping_n_s_m = 500.0",
            "cushion_damping_n_s_m = -500.0",
            "seat.cushion_damping_n_s_m",
        ),
        (
            "occupant_damping_ratio = 0.475",
            "occupant_damping_rate = 0.475",
            "seat",
        ),
    ] {
        let root = scratch("seat");
        let line = break_file(&root, f, from, to);
        check(&vehicle_error(&root), f, line, field);
    }
}

#[test]
fn damper_pushing_the_wrong_way() {
    let root = scratch("damper");
    let f = "vehicles/fabia/front_mcpherson.toml";
    let line = break_file(&root, f, "-700.0, -480.0", "700.0, -480.0");
    check(&vehicle_error(&root), f, line, "damper.force_n[0]");
}

#[test]
fn unphysical_inertia() {
    let root = scratch("inertia");
    let f = "vehicles/fabia/front_mcpherson.toml";
    let line = break_file(&root, f, "[0.20, 0.19, 0.04]", "[0.20, 0.01, 0.04]");
    check(&vehicle_error(&root), f, line, "knuckle.inertia_kg_m2");
}

#[test]
fn wrong_template_in_the_assembly_file() {
    let root = scratch("template");
    let f = "vehicles/fabia_trailer.toml";
    let line = break_file(
        &root,
        f,
        "template = \"mcpherson\"",
        "template = \"double_wishbone\"",
    );
    check(&vehicle_error(&root), f, line, "car.front.template");
}

#[test]
fn unknown_hitch_node() {
    let root = scratch("node");
    let f = "vehicles/fabia/hitch.toml";
    let line = break_file(&root, f, "ball_node = \"ball\"", "ball_node = \"towball\"");
    check(&vehicle_error(&root), f, line, "hitch.ball_node");
}

#[test]
fn bad_sensor_axis() {
    let root = scratch("sensor");
    let f = "vehicles/fabia_trailer.toml";
    let line = break_file(
        &root,
        f,
        "axes = [\"x\", \"y\", \"z\"]",
        "axes = [\"x\", \"v\", \"z\"]",
    );
    check(&vehicle_error(&root), f, line, "sensor[8].axes[1]");
}

#[test]
fn unknown_load_case_and_bad_scene_values() {
    let root = scratch("scene");
    let f = "scenes/default.toml";
    let lc = break_file(&root, f, "load_case = \"empty\"", "load_case = \"full\"");
    // The scene chose the load case: the error is at its line (issue 31; c4bd0ca blamed
    // the trailer file), and the message names the trailer file and its cases.
    check(
        &towride_app::scene::load(&root.join(f)).unwrap_err(),
        f,
        lc,
        "scene.load_case",
    );
    let e = towride_app::scene::load(&root.join(f)).unwrap_err();
    assert!(
        e.message.contains("full")
            && e.message.contains("200kg_over_axle")
            && e.message.contains("box_trailer.toml"),
        "{e}"
    );
    break_file(&root, f, "load_case = \"full\"", "load_case = \"empty\"");
    let line = break_file(&root, f, "speed_km_h = 50.0", "speed_km_h = -50.0");
    check(
        &towride_app::scene::load(&root.join(f)).unwrap_err(),
        f,
        line,
        "run.speed_km_h",
    );
}

#[test]
fn unknown_inertia_coupling_and_the_full_level() {
    let root = scratch("coupling");
    let f = "vehicles/fabia/hitch.toml";
    let line = break_file(
        &root,
        f,
        "inertia_coupling = \"constant\"",
        "inertia_coupling = \"complete\"",
    );
    let e = vehicle_error(&root);
    check(&e, f, line, "hitch.inertia_coupling");
    assert!(e.message.contains("constant, partial or full"), "{e}");
    break_file(&root, f, "\"complete\"", "\"full\"");
    let v = vehicle::load(
        &root.join("vehicles/fabia_trailer.toml"),
        &Options::default(),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let hb = v.handles.hitch.as_ref().unwrap().body;
    let m = v.model.bodies[hb].modal.as_ref().unwrap();
    assert_eq!(m.coupling, towride_mbs::model::desc::Coupling::Full);
}

#[test]
fn bad_cross_member_kind_and_node() {
    let root = scratch("cross_member");
    let f = "vehicles/fabia/rear_twist_beam.toml";
    let line = break_file(&root, f, "kind = \"rigid\"", "kind = \"flexibel\"");
    let e = vehicle_error(&root);
    check(&e, f, line, "cross_member.kind");
    assert!(e.message.contains("flexibel"), "{e}");
    break_file(&root, f, "kind = \"flexibel\"", "kind = \"flexible\"");
    let line = break_file(&root, f, "[\"arm_left\", ", "[\"arm_lft\", ");
    let e = vehicle_error(&root);
    check(&e, f, line, "cross_member.interface_nodes[0]");
    assert!(
        e.message.contains("arm_lft") && e.message.contains("arm_left"),
        "{e}"
    );
}

#[test]
fn bad_section_in_the_cross_member_fe_file() {
    let root = scratch("cross_member_fe");
    let rear = "vehicles/fabia/rear_twist_beam.toml";
    break_file(&root, rear, "kind = \"rigid\"", "kind = \"flexible\"");
    let f = "flex/twist_beam.toml";
    let line = break_file(
        &root,
        f,
        "torsion_constant_m4 = 2.6624e-8",
        "torsion_constant_m4 = -2.6624e-8",
    );
    check(&vehicle_error(&root), f, line, "section[0]");
}

#[test]
fn bad_selection_override_of_the_cross_member() {
    let root = scratch("cross_member_selection");
    let f = "vehicles/fabia/rear_twist_beam.toml";
    break_file(&root, f, "kind = \"rigid\"", "kind = \"flexible\"");
    let line = break_file(
        &root,
        f,
        "mount = \"fixed\"\n",
        "mount = \"fixed\"\nselection = { rule = \"load_path\", band_hz = [0.0, 100.0], load_interfaces = [\"arm_middle\"] }\n",
    ) + 1;
    let e = vehicle_error(&root);
    check(&e, f, line, "cross_member.selection.load_interfaces[0]");
    assert!(e.message.contains("arm_middle"), "{e}");
}

#[test]
fn a_brake_bristle_that_cannot_stick_is_refused_at_its_field() {
    let f = "vehicles/fabia/driveline.toml";
    for (from, to, field) in [
        (
            "stick_elastic_share = 0.5",
            "stick_elastic_share = 1.0",
            "brakes.stick_elastic_share",
        ),
        (
            "stick_deflection_rad = 1.0e-3",
            "stick_deflection_rad = 0.0",
            "brakes.stick_deflection_rad",
        ),
        (
            "hold_below_m_s = 0.3",
            "hold_below_m_s = -0.3",
            "brakes.hold_below_m_s",
        ),
    ] {
        let root = scratch(field);
        let line = break_file(&root, f, from, to);
        check(&vehicle_error(&root), f, line, field);
    }
}
