//! The compact `simple` vehicle: the light van with rear air springs
//! (vehicles/van_air/van.toml). Its linearised body-bounce and wheel-hop frequencies
//! against the quarter-car formulas on the file's own numbers, and its runs over the
//! 50 mm bump; the van with a compact trailer at rest against the lever rule, and the
//! trailer's bounce against its ride frequency.

use std::f64::consts::PI;
use std::path::Path;

use towride_app::prelude::*;
use towride_mbs::model;

const SCENE: &str = repo!("scenes/van_air/bump_50mm.toml");
const G: f64 = 9.81; // the defaults file's gravity
const TYRE_N_M: f64 = 3.2e5;

/// Sprung mass per corner [kg]: half the axle load less the corner's unsprung mass.
fn sprung(axle_kg: f64, unsprung_kg: f64) -> f64 {
    axle_kg / 2.0 - unsprung_kg
}

/// Quarter-car references from the van file: (front ride, rear ride, front hop, rear hop)
/// [Hz]. Front: the ride frequency is the file's 1.25 Hz, its wheel rate follows from the
/// ride rate in series with the tyre. Rear: the levelled air spring's rate
/// n (p_g + p_a) A^2 / V0 with p_g = load / A and the defaults' n = 1.3.
fn references() -> [f64; 4] {
    let (ms_f, ms_r) = (sprung(1250.0, 55.0), sprung(1000.0, 75.0));
    let ride_f = ms_f * (2.0 * PI * 1.25).powi(2);
    let k_f = ride_f * TYRE_N_M / (TYRE_N_M - ride_f);
    let (a, v0) = (0.0177, 0.0045);
    let p = ms_r * G / a + 101_325.0;
    let k_r = 1.3 * p * a * a / v0;
    let ride_r = k_r * TYRE_N_M / (k_r + TYRE_N_M);
    let hz = |k: f64, m: f64| (k / m).sqrt() / (2.0 * PI);
    [
        1.25,
        hz(ride_r, ms_r),
        hz(k_f + TYRE_N_M, 55.0),
        hz(k_r + TYRE_N_M, 75.0),
    ]
}

#[test]
fn van_bounce_and_wheel_hop_match_the_quarter_car() {
    let job = Job::from_file(Path::new(SCENE), &Loader::new()).unwrap();
    let st = model::statics::equilibrium(&job.system, 0.0, &job.solver).unwrap();
    let lin = model::linear::linearise(&job.system, 0.0, &st.y).unwrap();
    let near = |f: f64, tol: f64| {
        lin.modes
            .iter()
            .map(|m| m.undamped_hz)
            .filter(|h| (h / f - 1.0).abs() < tol)
            .count()
    };
    let [ride_f, ride_r, hop_f, hop_r] = references();
    eprintln!("van references: ride {ride_f:.3} / {ride_r:.3} Hz, hop {hop_f:.2} / {hop_r:.2} Hz");
    // Bounce and pitch couple the axles a little: 3 %; each hop is a left/right pair.
    assert!(
        near(ride_f, 0.03) >= 1,
        "front ride {ride_f}: {:?}",
        lin.modes
    );
    assert!(near(ride_r, 0.03) >= 1, "rear ride {ride_r}");
    assert!(near(hop_f, 0.02) >= 2, "front hop {hop_f}");
    assert!(near(hop_r, 0.02) >= 2, "rear hop {hop_r}");
}

#[test]
fn van_runs_over_the_50mm_bump_and_lists_what_it_assumed() {
    let job = Job::from_file(Path::new(SCENE), &Loader::new()).unwrap();
    let res = job.run(&Silent).unwrap();
    assert!(res.failure().is_none(), "{:?}", res.failure());
    let summary = serde_json::to_value(&res.summary).unwrap();
    let assumed = summary["scene"]["assumed"].as_array().unwrap();
    assert!(
        assumed
            .iter()
            .any(|a| a["field"] == "front.spring.wheel_rate_n_m"),
        "{assumed:?}"
    );
    assert!(assumed.len() > 10, "{}", assumed.len());
}

/// The van with a compact trailer (a 750 kg-class single-axle box trailer, class values)
/// at rest, empty and with a payload ahead of its axle: the trailer's tyres carry
/// g (m x_cg + m_p x_p) / x_axle (moments about the ball), the ball the rest, and the
/// car's axles the ball load through the lever over the wheelbase; the empty trailer
/// bounces about the ball at its ride frequency.
#[test]
fn van_with_a_trailer_rests_on_the_lever_rule_loads_and_bounces_at_its_ride_frequency() {
    let dir = std::env::temp_dir().join(format!("towride-simple-trailer-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let van = std::fs::read_to_string(repo!("vehicles/van_air/van.toml")).unwrap();
    let defaults = Path::new(repo!("vehicles/simple_defaults.toml"));
    let van = van.replace("../simple_defaults.toml", defaults.to_str().unwrap());
    let (m, xc, xa, behind) = (400.0, 2.2, 2.5, 1.0);
    let (pm, xp) = (150.0, 1.9);
    let file = dir.join("van_trailer.toml");
    let trailer = format!(
        "\n[trailer]\nmass_kg = {m}\ncg_behind_ball_m = {xc}\ncg_height_m = 0.6\n\
         axle_behind_ball_m = {xa}\ntrack_m = 1.5\nball_height_m = 0.45\n\
         ball_behind_rear_axle_m = {behind}\n\
         axle = {{ unsprung_kg = 30.0, spring = {{ kind = \"coil\", ride_frequency_hz = 1.6 }}, damping_ratio = 0.2 }}\n\
         tyre = {{ size = \"155/80 R13\", vertical_stiffness_n_m = 1.8e5, mass_kg = 7.0 }}\n\
         [[trailer.load_case]]\nname = \"empty\"\npayload_kg = 0.0\n\
         payload_behind_ball_m = {xp}\npayload_height_m = 0.5\n\
         [[trailer.load_case]]\nname = \"ahead\"\npayload_kg = {pm}\n\
         payload_behind_ball_m = {xp}\npayload_height_m = 0.5\n"
    );
    std::fs::write(&file, van + &trailer).unwrap();
    let (wheelbase, car_front_kg, car_rear_kg) = (3.3, 1250.0, 1000.0);
    for (case, payload) in [("empty", 0.0), ("ahead", pm)] {
        let (_, sys, y, _) = super::vehicle_statics::at_rest(file.to_str().unwrap(), Some(case));
        if case == "empty" {
            // Bounce of the empty trailer about the ball: with the defaults' dynamic index
            // of 1 its sprung body's inertia about the ball, seen at the axle, is the
            // axle's sprung load, so (car held) it bounces at the file's 1.6 Hz ride
            // frequency; the car's motion moves it by less than 2 %.
            let lin = towride_mbs::model::linear::linearise(&sys, 0.0, &y).unwrap();
            let hz: Vec<f64> = lin.modes.iter().map(|m| m.undamped_hz).collect();
            assert!(hz.iter().any(|h| (h / 1.6 - 1.0).abs() < 0.02), "{hz:?}");
        }
        let loads = super::vehicle_statics::tyre_loads(&sys, &y);
        let sum = |p: &[&str]| -> f64 {
            loads
                .iter()
                .filter(|l| p.iter().any(|n| l.0.ends_with(n)))
                .map(|l| l.1)
                .sum()
        };
        let axle = G * (m * xc + payload * xp) / xa;
        let ball = G * (m + payload) - axle;
        let (front, rear, trailer) = (sum(&["fl", "fr"]), sum(&["rl", "rr"]), sum(&["tl", "tr"]));
        eprintln!("{case}: tyres {loads:?}; trailer axle {axle:.1} N, ball {ball:.1} N");
        // The trailer pitches and sinks a little at rest, which moves the levers: 0.5 %.
        assert!(
            (trailer - axle).abs() < 0.005 * axle,
            "{case}: trailer {trailer} vs {axle}"
        );
        let want_f = car_front_kg * G - ball * behind / wheelbase;
        let want_r = car_rear_kg * G + ball * (wheelbase + behind) / wheelbase;
        assert!(
            (front - want_f).abs() < 0.005 * want_f,
            "{case}: front {front} vs {want_f}"
        );
        assert!(
            (rear - want_r).abs() < 0.005 * want_r,
            "{case}: rear {rear} vs {want_r}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
