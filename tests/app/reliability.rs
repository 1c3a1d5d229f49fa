//! Issue 20 in the library: plausibility bounds at input time, `.tir` and CSV input that
//! was misread, duplicate names, and a sweep interrupted and resumed.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use towride_app::sweep::exec::run_sweep_in;
use towride_app::sweep::Sweep;
use towride_mbs::input::tir::TirFile;
use towride_mbs::input::Source;
use towride_mbs::model::spec;
use towride_mbs::progress::{Progress, Silent};
use towride_mbs::tyre::TyreParams;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride-rel-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn mechanism(text: &str) -> Result<spec::Mechanism, towride_mbs::input::InputError> {
    let src = Source::from_text(Path::new("bad.toml"), text.to_string())?;
    let f = src.parse()?;
    spec::build(&src, f)
}

#[test]
fn absurd_physical_values_are_refused_with_the_accepted_range() {
    let good = std::fs::read_to_string(repo!("scenes/examples/pendulum.toml")).unwrap();
    for (from, to, field) in [
        // A 1e300 m arm, a 1e300 kg bob, a sample rate that would fill the memory.
        (
            "cm_position_m = [1.0,",
            "cm_position_m = [1e300,",
            "body[0].cm_position_m[0]",
        ),
        ("mass_kg = 1.0", "mass_kg = 1e300", "body[0].mass_kg"),
        (
            "sample_rate_hz = 1000.0",
            "sample_rate_hz = 1e300",
            "run.sample_rate_hz",
        ),
    ] {
        assert!(good.contains(from), "{from}");
        let text = good.replacen(from, to, 1);
        let line = text.lines().position(|l| l.contains(to)).unwrap() + 1;
        let e = mechanism(&text).err().expect(to);
        let msg = e.to_string();
        assert_eq!(e.field, field, "{msg}");
        assert_eq!(e.line, Some(line), "{msg}");
        assert!(msg.starts_with("bad.toml:"), "{msg}");
        assert!(msg.contains("accepted range"), "{msg}");
    }
    // Young's modulus 1e300 Pa in a flexible-body file (modes at -4e140 Hz before).
    let flex = std::fs::read_to_string(repo!("flex/hitch_crossbeam.toml")).unwrap();
    let key = flex
        .lines()
        .find(|l| l.trim_start().starts_with("youngs_modulus_pa"))
        .expect("the file gives E");
    let text = flex.replacen(key, "youngs_modulus_pa = 1e300", 1);
    let e = Source::from_text(Path::new("flex.toml"), text)
        .err()
        .unwrap();
    assert!(e.field.ends_with("youngs_modulus_pa"), "{e}");
    assert!(e.to_string().contains("Young's modulus"), "{e}");
}

#[test]
fn the_bounds_table_in_the_docs_is_the_code_s() {
    let doc = std::fs::read_to_string(repo!("docs/reliability.md")).unwrap();
    let table = towride_mbs::input::bounds::markdown_table();
    assert!(
        doc.contains(&table),
        "docs/reliability.md: paste the table again:\n{table}"
    );
}

fn tir() -> String {
    std::fs::read_to_string(repo!("vehicles/tyres/car_185_60r14.tir")).unwrap()
}

#[test]
fn a_tir_file_with_a_byte_order_mark_reads_as_without() {
    let p = Path::new("bom.tir");
    let plain = TyreParams::from_tir(&TirFile::parse(p, &tir()).unwrap()).unwrap();
    let bom = format!("\u{feff}{}", tir());
    let with = TyreParams::from_tir(&TirFile::parse(p, &bom).unwrap()).unwrap();
    assert_eq!(format!("{plain:?}"), format!("{with:?}"));
}

#[test]
fn an_unclosed_brace_in_a_tir_file_is_refused_at_its_line() {
    // Inserted right after [VERTICAL]: it swallowed the rest of the file.
    let text = tir().replacen("[VERTICAL]\n", "[VERTICAL]\n{ a comment never closed\n", 1);
    let line = text
        .lines()
        .position(|l| l.starts_with("{ a comment"))
        .unwrap()
        + 1;
    let e = TirFile::parse(Path::new("brace.tir"), &text).err().unwrap();
    assert_eq!(e.line, Some(line), "{e}");
    assert!(e.to_string().contains("never closed"), "{e}");
}

#[test]
fn an_absurd_contact_blend_in_a_tir_file_is_refused() {
    let text = tir().replacen(
        "TOWRIDE_CONTACT_BLEND    = 1.0e-4",
        "TOWRIDE_CONTACT_BLEND    = 1e300",
        1,
    );
    let t = TirFile::parse(Path::new("blend.tir"), &text).unwrap();
    let e = TyreParams::from_tir(&t).err().unwrap();
    assert!(e.to_string().contains("TOWRIDE_CONTACT_BLEND"), "{e}");
    assert!(e.to_string().contains("contact blend"), "{e}");
}

/// `text` with the value on 1-based `line` replaced by `value`.
fn with_value(text: &str, line: usize, value: &str) -> String {
    text.lines()
        .enumerate()
        .map(|(i, l)| match l.split_once('=') {
            Some((k, _)) if i + 1 == line => format!("{} = {value}", k.trim()),
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn every_tir_number_the_reader_reads_is_bounds_checked_at_its_line() {
    // 1e-300 N/m as LONGITUDINAL_STIFFNESS passed and ended as "singular rate equations"
    // with no file or line. A key counts as read when a non-number there is refused.
    for file in ["trailer_155_80r13.tir", "car_185_60r14.tir"] {
        let p = PathBuf::from(repo!("vehicles/tyres")).join(file);
        let text = std::fs::read_to_string(&p).unwrap();
        let t = TirFile::parse(&p, &text).unwrap();
        TyreParams::from_tir(&t).expect("the shipped file loads");
        let mut checked = Vec::new();
        for (sec, key, e) in t.entries() {
            if e.value.parse::<f64>().is_err() {
                continue;
            }
            let junk = TirFile::parse(&p, &with_value(&text, e.line, "x")).unwrap();
            if TyreParams::from_tir(&junk).is_ok() {
                continue; // not read (e.g. LATERAL_STIFFNESS, FREQ_LAT)
            }
            for bad in ["1e-300", "-1e-300", "1e300"] {
                let t = TirFile::parse(&p, &with_value(&text, e.line, bad)).unwrap();
                let err = TyreParams::from_tir(&t)
                    .err()
                    .unwrap_or_else(|| panic!("{file}: {sec}.{key} = {bad} was accepted"));
                assert_eq!(err.line, Some(e.line), "{file} {sec}.{key} = {bad}: {err}");
                assert_eq!(err.field, format!("{sec}.{key}"), "{err}");
                assert!(err.to_string().contains(file), "{err}");
            }
            checked.push(format!("{sec}.{key}"));
        }
        for must in [
            "STRUCTURAL.LONGITUDINAL_STIFFNESS",
            "VERTICAL.VERTICAL_STIFFNESS",
            "VERTICAL.FNOMIN",
            "STRUCTURAL.DAMP_RESIDUAL",
            "LONGITUDINAL_COEFFICIENTS.PKX1",
        ] {
            assert!(
                checked.iter().any(|c| c == must),
                "{file}: {must} not read?"
            );
        }
    }
}

#[test]
fn decimal_commas_in_a_comma_separated_csv_are_refused_at_their_line() {
    let d = tmp("comma");
    let f = d.join("run.csv");
    // Enough good rows that nothing but the decimal commas is wrong (with two rows the
    // reader refused the file for its length, not for the commas).
    let mut text = String::from("time [s],a [m/s^2],b [m/s^2]\n");
    for k in 0..12 {
        text += &format!("0.{k:03},1.0,2.0\n");
    }
    text += "0,012,1,5,2,5\n";
    std::fs::write(&f, text).unwrap();
    let e = towride_app::validate::csv_reader::read_table(&f, "time", &["a", "b"])
        .err()
        .unwrap();
    assert_eq!(e.line, Some(14), "{e}");
    assert!(e.to_string().contains("decimal commas"), "{e}");
    assert!(!e.field.is_empty(), "{e}");
}

#[test]
fn a_plan_listing_a_load_case_twice_is_refused() {
    let d = tmp("plan_dup");
    let scene = std::fs::canonicalize(repo!("scenes/default.toml")).unwrap();
    let plan = d.join("plan.toml");
    std::fs::write(
        &plan,
        format!(
            "[plan]\nname = \"dup\"\nspeeds_km_h = [50.0]\nload_cases = [\"empty\", \"empty\"]\ntravel_m = 1.0\nafter_s = 0.1\n\n[[obstacle]]\nname = \"ramp\"\nscene = {:?}\n",
            scene.to_str().unwrap()
        ),
    )
    .unwrap();
    let e = towride_app::scene::plan::load(&plan).err().unwrap();
    assert_eq!(e.field, "plan.load_cases[1]", "{e}");
    assert_eq!(e.line, Some(4), "{e}");
}

/// Asks to stop once `after` cases have finished (the sweep's bar counts cases).
pub(crate) struct StopAfter {
    pub(crate) done: AtomicU64,
    pub(crate) after: u64,
}

impl Progress for StopAfter {
    fn inc(&self, n: u64) {
        self.done.fetch_add(n, Ordering::SeqCst);
    }
    fn cancelled(&self) -> bool {
        self.done.load(Ordering::SeqCst) >= self.after
    }
}

#[test]
fn a_sweep_interrupted_and_resumed_gives_the_uninterrupted_summary() {
    let sweep = Sweep::load(Path::new(repo!("scenes/examples/pendulum_sweep.toml"))).unwrap();
    let whole = tmp("sweep_whole");
    let parts = tmp("sweep_parts");
    let full = run_sweep_in(&sweep, (0, 1), 1, &whole, false, &Silent).unwrap();
    assert_eq!((full.status.as_str(), full.cases), ("completed", 6));
    let stop = StopAfter {
        done: AtomicU64::new(0),
        after: 2,
    };
    let cut = run_sweep_in(&sweep, (0, 1), 1, &parts, false, &stop).unwrap();
    assert_eq!(cut.status, "interrupted");
    assert_eq!(cut.interrupted, 4);
    let resumed = run_sweep_in(&sweep, (0, 1), 1, &parts, true, &Silent).unwrap();
    assert_eq!((resumed.status.as_str(), resumed.resumed), ("completed", 2));
    // The same table, wall times aside.
    let table = |d: &Path| -> Vec<Vec<String>> {
        let mut r = csv::Reader::from_path(d.join("summary.csv")).unwrap();
        let h = r.headers().unwrap().clone();
        let wall = h.iter().position(|c| c == "wall_time [s]").unwrap();
        let mut rows = vec![h.iter().map(String::from).collect::<Vec<_>>()];
        for rec in r.records() {
            let rec = rec.unwrap();
            let mut v: Vec<String> = rec.iter().map(String::from).collect();
            v[wall].clear();
            rows.push(v);
        }
        rows
    };
    assert_eq!(table(&parts), table(&whole));
    assert!(!parts.join("summary.csv.journal").exists());
}

fn scene_error(set: &str) -> towride_mbs::input::InputError {
    let o = towride_mbs::input::Override::from_argument(set).unwrap();
    let loader = towride_mbs::input::Loader::with_overrides(vec![o]);
    match towride_app::scene::load_with(
        Path::new(repo!("scenes/default.toml")),
        &Default::default(),
        &loader,
    ) {
        Err(e) => e,
        Ok(_) => panic!("accepted: {set}"),
    }
}

/// An error about a value `--set` replaced is the `--set`'s (issue 32: the file's line
/// still holds the old value); its message names the file and the field.
fn blamed_on_set(e: &towride_mbs::input::InputError, set: &str, file: &str, field: &str) {
    assert_eq!(e.file, Path::new("command line"), "{e}");
    assert_eq!(e.field, format!("--set {set}"), "{e}");
    assert!(
        e.message.contains(file) && e.message.contains(&format!("`{field}`")),
        "{e}"
    );
}

#[test]
fn a_missing_hitch_variant_is_blamed_on_the_scene() {
    let set = "default.toml:scene.hitch_variant=11";
    let e = scene_error(set);
    blamed_on_set(&e, set, "scenes/default.toml", "scene.hitch_variant");
    assert!(e.to_string().contains("no variant 11"), "{e}");
}

#[test]
fn a_missing_referenced_file_is_named_with_the_field_that_refers_to_it() {
    let set = "hitch.toml:hitch.fe_file=\"nope.toml\"";
    let e = scene_error(set);
    blamed_on_set(&e, set, "vehicles/fabia/hitch.toml", "hitch.fe_file");
    assert!(e.to_string().contains("no file"), "{e}");
    let d = tmp("road_missing");
    let road = d.join("road.toml");
    let text = std::fs::read_to_string(repo!("roads/profile_example.toml")).unwrap();
    std::fs::write(&road, text).unwrap();
    let e = towride_mbs::road::Road::from_file(&road, &towride_mbs::input::Loader::new())
        .err()
        .unwrap();
    assert!(e.file.ends_with("road.toml"), "{e}");
    assert_eq!(e.field, "road.file", "{e}");
    assert!(e.line.is_some(), "{e}");
}

#[test]
fn coincident_hardpoints_are_blamed_on_the_hardpoints() {
    for (set, field) in [
        (
            "front_mcpherson.toml:hardpoints.lower_arm_rear_m=[0.12, 0.37, 0.190]",
            "hardpoints.lower_arm_rear_m",
        ),
        (
            "front_mcpherson.toml:hardpoints.strut_top_m=[-0.012, 0.640, 0.330]",
            "hardpoints.strut_top_m",
        ),
        // This one panicked (a tie rod of zero length).
        (
            "front_mcpherson.toml:hardpoints.tie_rod_outer_m=[-0.150, 0.330, 0.3104]",
            "hardpoints.tie_rod_outer_m",
        ),
        // These were blamed on `spring 'spring_rl': point_j_m` (in hitch.toml!), on
        // `spring 'damper_rl': point_j_m` and on the spring's stiffness.
        (
            "rear_twist_beam.toml:hardpoints.spring_upper_m=[-2.360, 0.560, 0.230]",
            "hardpoints.spring_upper_m",
        ),
        (
            "rear_twist_beam.toml:hardpoints.damper_upper_m=[-2.480, 0.600, 0.230]",
            "hardpoints.damper_upper_m",
        ),
        (
            "rear_twist_beam.toml:hardpoints.wheel_centre_m=[-2.020, 0.600, 0.300]",
            "hardpoints.wheel_centre_m",
        ),
    ] {
        let e = scene_error(set);
        let file = set.split(':').next().unwrap();
        blamed_on_set(&e, set, file, field);
        assert!(e.to_string().contains("coincides"), "{e}");
    }
}

#[test]
fn the_doctor_finds_the_default_scene_well_conditioned() {
    // It said "condition number inf: expect Newton failures" of a scene that runs
    // cleanly: the unscaled matrix, not the one the solver factors.
    let job = towride_app::job::Job::from_file(
        Path::new(repo!("scenes/default.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let rep = towride_mbs::model::doctor::examine(&job.system, &job.solver, 1e-3);
    let k = rep.newton_condition.unwrap();
    assert!(k.is_finite() && k < 1e9, "{k}");
    assert!(
        !rep.advice.iter().any(|a| a.contains("condition number")),
        "{:?}",
        rep.advice
    );
}

#[test]
fn stress_ratios_compare_like_with_like() {
    use towride_app::job::Extremes;
    use towride_app::study::stress::{agrees, ratio};
    // The default scene's hitch |peak| is a pull of 5357 N; a pull of 14570 N is 2.72
    // times it, a larger push 1.2 times a push, a smaller pull 0.8 times.
    assert!((ratio(14570.0, 5357.0) - 2.7198).abs() < 1e-3);
    assert!((ratio(6000.0, 5000.0) - 1.2).abs() < 1e-12);
    assert!((ratio(-4000.0, -5000.0) - 0.8).abs() < 1e-12);
    // A case whose |peak| is a push of 2306 N against the reference's pull of 5261 N:
    // 0.44 times the reference's magnitude, not the "-0.44x" of signed peaks.
    let e = |t: &[f64], y: &[f64]| Extremes::of(t, y.iter().copied());
    let t = [0.1, 0.2, 0.3];
    let reference = e(&t, &[1200.0, -5261.0, 300.0]);
    let push = e(&t, &[2306.0, -1500.0, 0.0]);
    assert!((ratio(push.abs_peak, reference.abs_peak) - 0.4383).abs() < 1e-4);
    assert!(ratio(push.max, reference.max) > 1.0 && ratio(push.min, reference.min) < 1.0);
    // Agreement: the |peak| within 2 % of the reference's, on the reference's side.
    assert!(agrees(&e(&t, &[1250.0, -5300.0, 0.0]), &reference));
    assert!(agrees(&e(&t, &[1320.0, -5261.0, 0.0]), &reference));
    assert!(!agrees(&e(&t, &[1200.0, -5380.0, 0.0]), &reference));
    // Within 2 % in magnitude, but a push where the reference pulls: a deviation, as
    // the signed peaks' 5300 against -5261 was.
    assert!(!agrees(&e(&t, &[5300.0, -5200.0, 0.0]), &reference));
    // Equal magnitudes on either side: the |peak| is the same whichever side it is on.
    let both = e(&t, &[5261.0, -5261.0, 0.0]);
    assert_eq!(both.abs_peak, 5261.0);
    assert_eq!(both.t_abs_peak, 0.1);
}

/// Every stress case is a model the input checks accept: a case they refuse measures the
/// checks, not the solver (the mass-ratio case's 1e-9 kg rims did, unnoticed, once the
/// checks refused masses under 1e-6 kg).
#[test]
fn every_stress_case_passes_the_input_checks() {
    use towride_app::job::Job;
    use towride_mbs::input::Loader;
    let scene = std::path::Path::new(repo!("scenes/default.toml"));
    let cases = towride_app::study::stress::cases();
    assert!(cases.len() >= 30);
    for c in &cases {
        let loader = Loader::with_overrides(c.props.clone());
        if let Err(e) = Job::from_scene_file(scene, &c.scene, &loader) {
            panic!("{} / {}: {e}", c.group, c.label);
        }
    }
}
