//! The engine on its mounts (`vehicles/fabia/engine.toml`): body and engine together are
//! the lumped car body the files held before issue 21, and the model holds the engine as
//! a body on its three mounts.

use std::path::Path;

use towride_app::vehicle::{self, Options};

fn table(path: &str) -> toml::Table {
    std::fs::read_to_string(path).unwrap().parse().unwrap()
}

fn nums(v: &toml::Value) -> Vec<f64> {
    match v {
        toml::Value::Array(a) => a.iter().flat_map(nums).collect(),
        toml::Value::Float(f) => vec![*f],
        toml::Value::Integer(i) => vec![*i as f64],
        _ => panic!("not a number: {v}"),
    }
}

/// Mass, centre of mass and inertia tensor (about its centre of mass) of a mass table.
fn part(t: &toml::Table, key: &str) -> (f64, [f64; 3], [[f64; 3]; 3]) {
    let m = nums(&t[key]["mass_kg"])[0];
    let c = nums(&t[key]["cm_m"]);
    let i = nums(&t[key]["inertia_kg_m2"]);
    let (xy, xz, yz) = if i.len() == 6 {
        (i[3], i[4], i[5])
    } else {
        (0.0, 0.0, 0.0)
    };
    (
        m,
        [c[0], c[1], c[2]],
        [[i[0], xy, xz], [xy, i[1], yz], [xz, yz, i[2]]],
    )
}

/// Steiner term m (|d|^2 1 - d d^T): the inertia of a point mass at offset d.
fn steiner(m: f64, d: [f64; 3]) -> [[f64; 3]; 3] {
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let mut s = [[0.0; 3]; 3];
    for r in 0..3 {
        for c in 0..3 {
            s[r][c] = m * (if r == c { dd } else { 0.0 } - d[r] * d[c]);
        }
    }
    s
}

#[test]
fn body_and_engine_together_are_the_lumped_body_of_before() {
    // The lumped car body of the files before the engine was split off (issue 21): the
    // reference, written out here rather than read from any file.
    let (m0, c0, i0) = (955.0, [-0.929, 0.0, 0.56], [367.0, 1375.0, 1565.0]);
    let (mb, cb, ib) = part(&table(repo!("vehicles/fabia/body.toml")), "body");
    let (me, ce, ie) = part(&table(repo!("vehicles/fabia/engine.toml")), "engine");
    let m = mb + me;
    assert!((m - m0).abs() < 1e-9, "total mass {m}");
    let c: Vec<f64> = (0..3).map(|k| (mb * cb[k] + me * ce[k]) / m).collect();
    for k in 0..3 {
        assert!((c[k] - c0[k]).abs() < 1e-5, "centre of mass {c:?}");
    }
    let d = |p: [f64; 3]| [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
    let (sb, se) = (steiner(mb, d(cb)), steiner(me, d(ce)));
    for r in 0..3 {
        for col in 0..3 {
            let i = ib[r][col] + ie[r][col] + sb[r][col] + se[r][col];
            let want = if r == col { i0[r] } else { 0.0 };
            assert!(
                (i - want).abs() < 0.01,
                "inertia [{r}][{col}] {i} vs {want}"
            );
        }
    }
}

#[test]
fn the_engine_is_a_body_on_three_mounts_with_the_file_s_mass() {
    let v = vehicle::load(
        Path::new(repo!("vehicles/fabia_trailer.toml")),
        &Options::default(),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
    let (me, _, _) = part(&table(repo!("vehicles/fabia/engine.toml")), "engine");
    let e = v
        .model
        .bodies
        .iter()
        .position(|b| b.name == "engine")
        .unwrap();
    assert_eq!(v.model.bodies[e].mass, me);
    let mounts: Vec<&str> = v
        .model
        .forces
        .iter()
        .map(|f| f.name())
        .filter(|n| n.starts_with("engine_mount_"))
        .collect();
    assert_eq!(
        mounts,
        [
            "engine_mount_right",
            "engine_mount_left",
            "engine_mount_torque_rod"
        ]
    );
}

#[test]
fn an_engine_on_two_mounts_is_refused_at_the_mount_table() {
    let root = crate::vehicle_errors::scratch("engine_mounts");
    let engine = root.join("vehicles/fabia/engine.toml");
    let text = std::fs::read_to_string(&engine).unwrap();
    let cut = text.find("[[mount]]\nname = \"torque_rod\"").unwrap();
    std::fs::write(&engine, &text[..cut]).unwrap();
    let e = vehicle::load(
        &root.join("vehicles/fabia_trailer.toml"),
        &Options::default(),
        &towride_mbs::input::Loader::new(),
    )
    .err()
    .unwrap();
    let s = e.to_string();
    assert!(
        s.contains("engine.toml") && s.contains("`mount`") && s.contains("at least 3"),
        "{s}"
    );
}
