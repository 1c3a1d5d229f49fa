//! One registry of templates serves both kinds of vehicle file: the `simple` set's axle
//! (`trailing_arm_axle`) and trailer (`lumped_trailer`) are registered beside the
//! Fabia's, so an assembly file can name them with property files of their own. The
//! Fabia with a trailing-arm rear axle on air springs and a lumped trailer on a
//! trailing-arm axle, at rest: its tyres carry the design loads, the files' wheel rates
//! are the wheels' and the air springs' pressures are listed as derived. Typed options
//! (`ball_coupling`, `rear_cross_member`) are refused where they are read, with file,
//! line and field.

use std::path::{Path, PathBuf};

use towride_app::vehicle::{self, axle, trailer, Options};
use towride_mbs::input::{InputError, Loader};

/// A scratch folder, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(tag: &str) -> Scratch {
        let d = std::env::temp_dir().join(format!(
            "towride_vehicle_templates_{}_{tag}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        Scratch(d)
    }

    /// Writes `text` to `name` in the folder; returns its path.
    fn write(&self, name: &str, text: &str) -> String {
        let p = self.0.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The Fabia's rear twist-beam hardpoints and parts as a trailing-arm axle: arms on the
/// twist beam's pivots, air springs on its spring seats (area 0.01 m^2, 20 kN/m at the
/// wheel), its damper line with linear damping.
const REAR_AXLE: &str = r#"
[hardpoints]
wheel_centre_m = [-2.462, 0.7125, 0.278]
pivot_m = [-2.020, 0.600, 0.300]
spring_lower_m = [-2.360, 0.560, 0.230]
spring_upper_m = [-2.360, 0.560, 0.470]
damper_lower_m = [-2.480, 0.600, 0.230]
damper_upper_m = [-2.540, 0.580, 0.620]

[arm]
mass_kg = 14.0
cm_m = [-2.268, 0.536, 0.280]
inertia_kg_m2 = [0.40, 0.32, 0.68]

[wheel]
mass_kg = 12.5
spin_inertia_kg_m2 = 0.23
tilt_inertia_kg_m2 = 0.13

[spring]
kind = "air"
effective_area_m2 = 0.01
wheel_rate_n_m = 20000.0
polytropic_exponent = 1.3
atmosphere_pa = 101325.0
table_span = 0.6
table_points = 61

[damper]
wheel_damping_n_s_m = 1500.0

[bump_stop]
clearance_m = 0.062
stiffness_n_m = 7.5e6
exponent = 2.0
damping_n_s_m = 500.0
damping_depth_m = 0.005

[pivot_bushing]
stiffness_n_m = [1.5e6, 4.0e6, 1.0e6]
damping_n_s_m = [7.5e2, 2.0e3, 5.0e2]
stiffness_n_m_rad = [1.0e3, 1.0e3, 40.0]
damping_n_m_s_rad = [0.5, 0.5, 0.02]

[torsion]
stiffness_n_m_rad = 1800.0
damping_n_m_s_rad = 1.5
"#;

/// A trailer axle in trailer coordinates: arms pivoting ahead of the wheels at their
/// height, coils of 15 kN/m at the wheel standing over them.
const TRAILER_AXLE: &str = r#"
[hardpoints]
wheel_centre_m = [-2.460, 0.670, 0.2866]
pivot_m = [-2.010, 0.620, 0.2866]
spring_lower_m = [-2.460, 0.520, 0.2866]
spring_upper_m = [-2.460, 0.520, 0.5866]
damper_lower_m = [-2.460, 0.590, 0.2866]
damper_upper_m = [-2.460, 0.590, 0.6366]

[arm]
mass_kg = 6.0
cm_m = [-2.460, 0.670, 0.2866]
inertia_kg_m2 = [0.06, 0.06, 0.06]

[wheel]
mass_kg = 5.0
spin_inertia_kg_m2 = 0.11
tilt_inertia_kg_m2 = 0.065

[spring]
kind = "coil"
wheel_rate_n_m = 15000.0

[damper]
wheel_damping_n_s_m = 600.0

[pivot_bushing]
stiffness_n_m = [5.0e6, 5.0e6, 2.0e6]
damping_n_s_m = [2.5e3, 2.5e3, 1.0e3]
stiffness_n_m_rad = [2.0e4, 2.0e4, 1000.0]
damping_n_m_s_rad = [2.0, 2.0, 12.0]

[torsion]
stiffness_n_m_rad = 500.0
damping_n_m_s_rad = 2.0
"#;

/// A lumped trailer on the ball of the Fabia's hitch (0.375 m high).
const TRAILER: &str = r#"
[trailer]
coupling_m = [0.0, 0.0, 0.375]
axle = { template = "trailing_arm_axle", file = "trailer_axle.toml" }

[body]
mass_kg = 78.0
cm_m = [-2.10, 0.0, 0.58]
inertia_kg_m2 = [10.0, 40.0, 47.0]

[[load_case]]
name = "empty"

[[load_case]]
name = "100kg_over_axle"
payload = { mass_kg = 100.0, cm_m = [-2.46, 0.0, 0.70], inertia_kg_m2 = [4.0, 6.0, 8.0] }
"#;

/// The Fabia with the trailing-arm rear and the lumped trailer: an assembly file in
/// `d`, the shipped files addressed by absolute paths.
fn fabia_with_simple_templates(d: &Scratch) -> String {
    d.write("rear_trailing_arm.toml", REAR_AXLE);
    d.write("trailer_axle.toml", TRAILER_AXLE);
    d.write("lumped_trailer.toml", TRAILER);
    let v = |f: &str| Path::new(repo!("vehicles")).join(f).display().to_string();
    let text = format!(
        r#"
[vehicle]
name = "Fabia on the simple set's templates"
gravity_m_s2 = [0.0, 0.0, -9.81]

[car]
body = {{ template = "lumped_body", file = "{body}" }}
engine = {{ template = "engine_on_mounts", file = "{engine}" }}
front = {{ template = "mcpherson", file = "{front}", tyre = "{car_tyre}" }}
rear = {{ template = "trailing_arm_axle", file = "rear_trailing_arm.toml", tyre = "{car_tyre}" }}
driveline = {{ template = "speed_control", file = "{driveline}" }}
hitch = {{ template = "modal_hitch", file = "{hitch}" }}

[trailer]
template = "lumped_trailer"
file = "lumped_trailer.toml"
tyre = "{trailer_tyre}"
"#,
        body = v("fabia/body.toml"),
        engine = v("fabia/engine.toml"),
        front = v("fabia/front_mcpherson.toml"),
        car_tyre = v("tyres/car_185_60r14.tir"),
        driveline = v("fabia/driveline.toml"),
        hitch = v("fabia/hitch.toml"),
        trailer_tyre = v("tyres/trailer_155_80r13.tir"),
    );
    d.write("fabia_simple_templates.toml", &text)
}

#[test]
fn the_registry_lists_the_simple_sets_axle_and_trailer() {
    let axles = axle::names();
    for t in ["mcpherson", "twist_beam", "trailing_arm_axle"] {
        assert!(axles.contains(&t), "{axles:?}");
    }
    let trailers = trailer::names();
    for t in ["box_trailer", "lumped_trailer"] {
        assert!(trailers.contains(&t), "{trailers:?}");
    }
    // A trailer template the registry lacks is refused with the ones it has.
    refused_template(
        "trailer.template",
        "caravan",
        &["box_trailer", "lumped_trailer"],
    );
}

/// Loads the Fabia with the template at `field` of its assembly file replaced by
/// `name`, which the registry lacks: the error names that field and the registered
/// templates `known`.
pub(crate) fn refused_template(field: &str, name: &str, known: &[&str]) {
    let l = Loader::with_overrides(vec![towride_mbs::input::Override::program(
        "fabia_trailer.toml",
        field,
        format!("{name:?}"),
        "test",
    )]);
    let e = vehicle::load(
        Path::new(repo!("vehicles/fabia_trailer.toml")),
        &Options::default(),
        &l,
    )
    .unwrap_err();
    assert_eq!(e.field, field, "{e}");
    assert!(known.iter().all(|k| e.message.contains(k)), "{e}");
}

#[test]
fn an_assembly_file_builds_the_fabia_on_the_simple_sets_templates_and_it_rests_on_its_design_loads()
{
    let d = Scratch::new("fabia");
    let file = fabia_with_simple_templates(&d);
    for (case, payload) in [("empty", 0.0), ("100kg_over_axle", 100.0)] {
        let (v, sys, y, _) = super::vehicle_statics::at_rest(&file, Some(case));
        for b in ["arm_rl", "arm_rr", "trailer_arm_tl", "trailer_box", "hitch"] {
            assert!(v.handles.bodies.contains_key(b), "{b}");
        }
        for j in ["rear_axle", "trailer_axle", "ball_coupling"] {
            assert!(v.model.joints.iter().any(|x| x.name == j), "{j}");
        }
        // The files' rates at the wheel are what the design statics find at the wheels.
        let c = &v.design.car_corners;
        for k in [2, 3] {
            let rate = c[k].wheel_rate_n_m;
            assert!((rate / 20_000.0 - 1.0).abs() < 1e-9, "{:?}", c[k]);
        }
        let t = v.design.trailer.as_ref().unwrap();
        assert_eq!(t.load_case, case);
        for k in 0..2 {
            let rate = t.corners[k].wheel_rate_n_m;
            assert!((rate / 15_000.0 - 1.0).abs() < 1e-9, "{rate}");
        }
        // The air springs' pressures are derived values, of an assembly file too.
        for (k, w) in [(2, "rl"), (3, "rr")] {
            let field = format!("air_spring_{w}.gauge_pressure_pa");
            let a = v.assumed.iter().find(|a| a.field == field).unwrap();
            let p = c[k].preload / 0.01;
            assert!((a.value / p - 1.0).abs() < 1e-12, "{a:?} vs {p}");
        }
        // At rest the tyres carry the weight, the trailer's its design axle load (the
        // springs are preloaded for the empty trailer) plus the payload over the axle;
        // it sinks and pitches a little, which moves the levers: 1 %.
        let loads = super::vehicle_statics::tyre_loads(&sys, &y);
        let sum = |p: &str| -> f64 {
            loads
                .iter()
                .filter(|l| l.0.starts_with(p))
                .map(|l| l.1)
                .sum()
        };
        let weight = v.design.total_mass_kg * 9.81;
        assert!(
            (sum("tyre_") - weight).abs() < 1e-3 * weight,
            "{loads:?} vs {weight}"
        );
        let axle = t.corners.iter().map(|c| c.load_n).sum::<f64>() + payload * 9.81;
        let on_axle = sum("tyre_t");
        assert!(
            (on_axle - axle).abs() < 1e-2 * axle,
            "{case}: trailer tyres {on_axle} N, design {axle} N"
        );
    }
}

fn scene_error(d: &Scratch, scene_line: &str) -> (InputError, String, usize) {
    let base = std::fs::read_to_string(repo!("scenes/default.toml")).unwrap();
    let vehicle = Path::new(repo!("vehicles/fabia_trailer.toml"))
        .display()
        .to_string();
    let road = Path::new(repo!("roads/ramp_thesis.toml"))
        .display()
        .to_string();
    let text = base
        .replace("../vehicles/fabia_trailer.toml", &vehicle)
        .replace("../roads/ramp_thesis.toml", &road)
        .replacen("[scene]\n", &format!("[scene]\n{scene_line}\n"), 1);
    let line = text.lines().position(|l| l == scene_line).unwrap() + 1;
    let file = d.write("scene.toml", &text);
    let e = towride_app::scene::load(Path::new(&file)).unwrap_err();
    (e, file, line)
}

#[test]
fn typed_options_are_refused_where_they_are_read() {
    let d = Scratch::new("options");
    for (line, field, bad) in [
        (
            "rear_cross_member = \"flexibel\"",
            "scene.rear_cross_member",
            "flexibel",
        ),
        ("ball_coupling = \"ball\"", "scene.ball_coupling", "ball"),
    ] {
        let (e, file, at) = scene_error(&d, line);
        assert_eq!(e.file, PathBuf::from(&file), "{e}");
        assert_eq!(e.line, Some(at), "{e}");
        assert_eq!(e.field, field, "{e}");
        assert!(e.message.contains(bad), "{e}");
    }
    // In the hitch file, read through an override, located at its line.
    let l = Loader::with_overrides(vec![towride_mbs::input::Override::program(
        "fabia/hitch.toml",
        "ball_coupling.kind",
        "\"rigid\"",
        "test",
    )]);
    let e = vehicle::load(
        Path::new(repo!("vehicles/fabia_trailer.toml")),
        &Options::default(),
        &l,
    )
    .unwrap_err();
    assert!(e.file.ends_with("fabia/hitch.toml"), "{e}");
    assert_eq!(e.field, "ball_coupling.kind", "{e}");
    assert!(e.line.is_some() && e.message.contains("rigid"), "{e}");
    // A compact file's axles have no flexible cross member, its hitch no bushing.
    for opts in [
        Options {
            rear_cross_member: Some(vehicle::CrossMember::Flexible),
            ..Default::default()
        },
        Options {
            ball_coupling: Some(vehicle::BallCoupling::Bushing),
            ..Default::default()
        },
    ] {
        let e = vehicle::load(
            Path::new(repo!("vehicles/van_air/van.toml")),
            &opts,
            &Loader::new(),
        )
        .unwrap_err();
        assert_eq!(e.field, "vehicle.template", "{e}");
        assert!(e.line.is_some(), "{e}");
    }
}
