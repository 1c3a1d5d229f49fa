use std::path::Path;
use towride::road::Road;
use towride::tyre::rig::*;
use towride::tyre::*;

#[test]
fn smoke() {
    for (roadf, v) in [("roads/cleat_10mm.toml", 11.11), ("roads/ramp_thesis.toml", 5.0)] {
    let tyre = Tyre::from_file(Path::new("vehicles/tyres/car_185_60r14.tir"), TyreKind::RigidRing).unwrap();
    let road = Road::from_file(Path::new(roadf)).unwrap();
    let rig = CleatRig::new(tyre, road, v, 0.0, 3500.0, Spin::Free, 0.6);
    for rtol in [1e-4, 1e-6] {
    let opts = rig_options(&rig.tyre, rtol, &[1e-3]);
    let t0 = std::time::Instant::now();
    let run = rig.run(2.0 / v , 1e-4, &opts);
    let run = match run { Ok(r) => r, Err(e) => { println!("ERR {e}"); continue; } };
    println!("{roadf} rtol {rtol} {:?} {:?}", run.stats, t0.elapsed());
    let mx = run.samples.iter().map(|s| s.hub_fz_n).fold(f64::MIN, f64::max);
    let mn = run.samples.iter().map(|s| s.hub_fx_n).fold(f64::MAX, f64::min);
    let mxx = run.samples.iter().map(|s| s.hub_fx_n).fold(f64::MIN, f64::max);
    let fnmin = run.samples.iter().map(|s| s.normal_force_n).fold(f64::MAX, f64::min);
    println!("peak fz {mx} fx min {mn} max {mxx} fn min {fnmin}");
    }
    }
}
