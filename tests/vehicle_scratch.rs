use std::path::Path;
use towride::model::system::{ExtKind, System};
use towride::road::Road;
use towride::solver::SolverOptions;
use towride::vehicle::{self, Options};

#[test]
fn scratch() {
    let mut v = vehicle::load(Path::new("vehicles/fabia.toml"), &Options::default()).unwrap();
    v.model.road = Some(Road::flat(0.0));
    let m0 = v.model.clone();
    let sys = System::new(v.model);
    let opts = SolverOptions::default();
    let t = std::time::Instant::now();
    let st = towride::model::statics::equilibrium(&sys, 0.0, &opts).unwrap();
    println!("statics {:?} in {:?}", st.report, t.elapsed());
    let (_, ov, ol, _) = sys.offsets();
    let q = &st.y[..ov];
    let vv = &st.y[ov..ol];
    let mut sum = 0.0;
    for e in &sys.ext {
        if let ExtKind::Tyre(k) = e.kind {
            let te = &sys.model.tyres[k];
            let kin = sys.wheel_kinematics(q, vv, te.marker);
            let x = &st.y[sys.oe() + e.off..sys.oe() + e.off + e.n];
            let o = te.tyre.outputs(&kin, sys.model.road.as_ref().unwrap(), x);
            sum += o.normal_force;
            println!(
                "{} fz {:.2} centre z {:.5}",
                te.name, o.normal_force, kin.position.z
            );
        }
    }
    println!("sum {:.3} weight {:.3}", sum, v.design.total_mass_kg * 9.81);
    for (w, mk) in &v.handles.ride {
        let wh = v.handles.wheels.iter().find(|x| &x.name == w).unwrap();
        let b = sys.marker_frame(q, *mk).origin;
        let c = sys.marker_frame(q, wh.centre).origin;
        let b0 = m0.markers[*mk].position;
        let _ = b0;
        println!(
            "ride {} body z {:.5} wheel z {:.5} diff {:.5}",
            w,
            b[2],
            c[2],
            b[2] - c[2]
        );
    }
    for (k, f) in sys.model.forces.iter().enumerate() {
        let (_, _, meas) = sys.force_eval(k, 0.0, q, vv);
        let s: Vec<String> = meas
            .iter()
            .map(|(f, d, _)| format!("{:.1}/{:.2e}", f, d))
            .collect();
        println!("{:<28} {}", f.name(), s.join(" "));
    }
    let t = std::time::Instant::now();
    let lin = towride::model::linear::linearise(&sys, 0.0, &st.y).unwrap();
    println!("linear in {:?}", t.elapsed());
    for m in lin.modes.iter().filter(|m| m.undamped_hz < 40.0) {
        let b: Vec<String> = m
            .bodies
            .iter()
            .take(3)
            .map(|s| format!("{} {:.0}%", s.name, 100.0 * s.share))
            .collect();
        println!(
            "{:3} {:8.3} {:8.3} {:6.3} {}",
            m.index,
            m.undamped_hz,
            m.damped_hz,
            m.damping_ratio,
            b.join(", ")
        );
    }
}
