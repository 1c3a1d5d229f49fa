//! The shipped synthetic measurement (made by the vehicle model through the documented
//! sensor model: 37 ms trigger delay, speedometer +3 %, gain +5 %, noise) validated with
//! the vehicle model: the delay and the true speed are recovered and the corrected
//! comparison rates close to 1, the uncorrected one clearly lower.

use std::path::Path;

use towride_app::validate::{default_simulator, validate_run, Options};

#[test]
fn synthetic_ramp_run_is_recovered_by_the_vehicle_model() {
    let file = Path::new(repo!("measurements/synthetic/ramp_50mm_50kmh_empty.toml"));
    let sim = default_simulator();
    let v = validate_run(file, sim.as_ref(), &Options::default()).unwrap();
    let c = v.corrected.as_ref().expect("corrected comparison");
    let true_speed = 50.0 / 3.6 / 1.03;
    let shift_ms = 1e3 * c.shift_s;
    println!(
        "shift {shift_ms:.2} ms (injected 37), speed {:.4} m/s (true {true_speed:.4}), rating corrected {:.3}, uncorrected {:.3}",
        c.speed_mps,
        c.mean_rating,
        v.uncorrected.mean_rating
    );
    assert!((shift_ms - 37.0).abs() < 1.0);
    assert!((c.speed_mps / true_speed - 1.0).abs() < 0.003);
    assert!(c.mean_rating > 0.9);
    assert!(c.mean_rating > v.uncorrected.mean_rating + 0.1);
}
