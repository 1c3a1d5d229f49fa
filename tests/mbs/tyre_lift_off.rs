//! Loss of contact: a trailer wheel (quarter rig, half of a loaded 300 kg trailer on it,
//! free spin) driven over the thesis's ramp at 50 km/h leaves the road and lands again;
//! the solver runs through lift-off and re-landing without failure and without chatter
//! (a handful of contact changes, no tensile force).

use std::path::Path;

use towride_mbs::road::Road;
use towride_mbs::tyre::rig::{rig_options, QuarterRig};
use towride_mbs::tyre::{Tyre, TyreKind};

fn contact_intervals(kind: TyreKind, mass: f64) {
    let tyre = Tyre::from_file(
        Path::new(repo!("vehicles/tyres/trailer_155_80r13.tir")),
        kind,
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let road = Road::from_file(
        Path::new(repo!("roads/ramp_thesis.toml")),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let speed = 50.0 / 3.6;
    // The trailer axle damper acts against the (much heavier, slower) box, taken as fixed.
    let rig = QuarterRig::new(tyre, road, speed, 0.0, mass, 0.5, 1500.0);
    let opts = rig_options(&rig.tyre, 1e-5, &[1e-6, 1e-4, 1e-3]);
    let t_end = 1.5;
    let run = rig.run(None, t_end, 1e-4, &opts).unwrap();
    assert!(
        run.samples.iter().all(|s| s.normal_force_n >= 0.0),
        "tensile contact force"
    );
    // Contact changes along the run.
    let mut changes = Vec::new();
    let mut on = true;
    for s in &run.samples {
        let now = s.normal_force_n > 0.0;
        if now != on {
            changes.push((s.t_s, s.x_m, now));
            on = now;
        }
    }
    let flights: Vec<(f64, f64)> = changes
        .chunks(2)
        .filter(|c| c.len() == 2 && !c[0].2 && c[1].2)
        .map(|c| (c[0].0, c[1].0))
        .collect();
    println!(
        "{kind:?} {mass} kg at 50 km/h: {} steps, {} rejected; contact changes (t s, x m, in contact): {:.3?}",
        run.stats.steps, run.stats.rejected_steps, changes
    );
    assert!(!flights.is_empty(), "the wheel never left the road");
    let longest = flights.iter().map(|f| f.1 - f.0).fold(0.0, f64::max);
    println!("  longest flight {longest:.3} s; flights {flights:.3?}");
    assert!(longest > 0.01, "no real flight");
    assert!(on, "the wheel did not land again before {t_end} s");
    assert!(
        changes.len() <= 8,
        "chatter: {} contact changes",
        changes.len()
    );
    // After landing it carries its weight again: mean load over the last 0.2 s.
    let tail: Vec<f64> = run
        .samples
        .iter()
        .filter(|s| s.t_s > t_end - 0.2)
        .map(|s| s.hub_fz_n)
        .collect();
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    let weight = -mass * rig.gravity;
    println!("  mean rim load over the last 0.2 s {mean:.1} N (rim weight {weight:.1} N)");
    assert!((mean / weight - 1.0).abs() < 0.1);
}

#[test]
fn rigid_ring_leaves_and_regains_the_road() {
    contact_intervals(TyreKind::RigidRing, 150.0);
}

#[test]
fn point_follower_leaves_and_regains_the_road() {
    contact_intervals(TyreKind::PointFollower, 150.0);
}
