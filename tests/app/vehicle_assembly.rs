//! The vehicle templates against their property files, read independently here with a
//! plain TOML parser: total mass, left-right mirroring, hardpoints, the modal hitch's
//! mass properties against the beam FE model, the trailer load cases' centre of mass.
//! No solver involved.

use std::path::Path;

use towride_app::vehicle::{self, Options, Vehicle};
use towride_mbs::model::desc::{MarkerHandle, Model};
use towride_mbs::model::math::{add, mv, rot, sub};
use towride_mbs::tyre::TyreKind;

fn table(path: &str) -> toml::Table {
    std::fs::read_to_string(path).unwrap().parse().unwrap()
}

fn num(t: &toml::Value) -> f64 {
    t.as_float()
        .or_else(|| t.as_integer().map(|i| i as f64))
        .unwrap()
}

fn vec3(t: &toml::Value) -> [f64; 3] {
    let a = t.as_array().unwrap();
    [num(&a[0]), num(&a[1]), num(&a[2])]
}

fn mass(t: &toml::Table, key: &str) -> f64 {
    num(&t[key]["mass_kg"])
}

fn load(opts: &Options) -> Vehicle {
    vehicle::load(
        Path::new(repo!("vehicles/fabia_trailer.toml")),
        opts,
        &towride_mbs::input::Loader::new(),
    )
    .unwrap()
}

/// World position of marker `k` at the initial configuration.
fn marker_world(m: &Model, k: MarkerHandle) -> [f64; 3] {
    let mk = &m.markers[k];
    match mk.body {
        None => mk.position,
        Some(b) => add(
            &m.bodies[b].position,
            &mv(&rot(&m.bodies[b].orientation), &mk.position),
        ),
    }
}

/// Mass and centre of mass of the hitch FE model (variant `v`) from its file: sum of
/// rho A L over the beam elements (each centred at its midpoint) plus the point masses.
fn hitch_fe_mass(v: u32) -> (f64, [f64; 3]) {
    let t = table(repo!("flex/hitch_crossbeam.toml"));
    let rho = num(&t["material"][0]["density_kg_m3"]);
    let var = t["variant"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["number"].as_integer() == Some(v as i64))
        .unwrap();
    let area = |name: &str| {
        let mut s = t["section"]
            .as_array()
            .unwrap()
            .iter()
            .find(|s| s["name"].as_str() == Some(name))
            .unwrap()
            .as_table()
            .unwrap()
            .clone();
        if let Some(o) = var.get("section").and_then(|x| x.get(name)) {
            for (k, val) in o.as_table().unwrap() {
                s.insert(k.clone(), val.clone());
            }
        }
        match s["shape"].as_str().unwrap() {
            "rectangular_hollow" => {
                let (w, h, th) = (num(&s["width_m"]), num(&s["height_m"]), num(&s["wall_m"]));
                w * h - (w - 2.0 * th) * (h - 2.0 * th)
            }
            "rectangular_solid" => num(&s["width_m"]) * num(&s["height_m"]),
            "round_solid" => std::f64::consts::PI * num(&s["diameter_m"]).powi(2) / 4.0,
            other => panic!("shape {other}"),
        }
    };
    let node = |n: &str| {
        vec3(
            &t["node"]
                .as_array()
                .unwrap()
                .iter()
                .find(|x| x["name"].as_str() == Some(n))
                .unwrap()["position_m"],
        )
    };
    let (mut m, mut s) = (0.0, [0.0; 3]);
    for e in t["element"].as_array().unwrap() {
        let (a, b) = (
            node(e["node_a"].as_str().unwrap()),
            node(e["node_b"].as_str().unwrap()),
        );
        let d = sub(&b, &a);
        let me = rho
            * area(e["section"].as_str().unwrap())
            * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        m += me;
        for c in 0..3 {
            s[c] += me * 0.5 * (a[c] + b[c]);
        }
    }
    for p in t["point_mass"].as_array().unwrap() {
        let (mp, x) = (num(&p["mass_kg"]), node(p["node"].as_str().unwrap()));
        m += mp;
        for c in 0..3 {
            s[c] += mp * x[c];
        }
    }
    (m, s.map(|x| x / m))
}

#[test]
fn total_mass_is_the_sum_of_the_property_files() {
    let body = table(repo!("vehicles/fabia/body.toml"));
    let engine = table(repo!("vehicles/fabia/engine.toml"));
    let front = table(repo!("vehicles/fabia/front_mcpherson.toml"));
    let rear = table(repo!("vehicles/fabia/rear_twist_beam.toml"));
    let trailer = table(repo!("vehicles/trailer/box_trailer.toml"));
    let car_tyre =
        crate::common::tir_value(repo!("vehicles/tyres/car_185_60r14.tir"), "INERTIA", "MASS");
    let tr_tyre = crate::common::tir_value(
        repo!("vehicles/tyres/trailer_155_80r13.tir"),
        "INERTIA",
        "MASS",
    );
    let (hitch, _) = hitch_fe_mass(5);
    let car = mass(&body, "body")
        + mass(&engine, "engine")
        + 2.0
            * (["knuckle", "lower_arm", "strut_rod", "tie_rod", "wheel"]
                .iter()
                .map(|k| mass(&front, k))
                .sum::<f64>()
                + mass(&rear, "half")
                + mass(&rear, "wheel"))
        + 4.0 * car_tyre
        + hitch;
    let tr =
        mass(&trailer, "body") + 2.0 * (mass(&trailer, "half") + mass(&trailer, "wheel") + tr_tyre);
    for kind in [TyreKind::RigidRing, TyreKind::PointFollower] {
        let v = load(&Options {
            tyre_kind: Some(kind),
            ..Default::default()
        });
        let belts: f64 = v
            .model
            .tyres
            .iter()
            .map(|t| match kind {
                TyreKind::RigidRing => t.tyre.params().belt_mass,
                TyreKind::PointFollower => 0.0,
            })
            .sum();
        let bodies: f64 = v.model.bodies.iter().map(|b| b.mass).sum();
        assert!(
            ((bodies + belts) - (car + tr)).abs() < 1e-9 * (car + tr),
            "{kind:?}: {} vs {}",
            bodies + belts,
            car + tr
        );
        assert!((v.design.total_mass_kg - (car + tr)).abs() < 1e-9 * (car + tr));
        assert!((v.design.car_mass_kg - car).abs() < 1e-9 * car);
    }
    // The vehicle classes the templates model: a ~1100 kg car, a 100 kg empty trailer.
    assert!((car - 1100.0).abs() < 30.0, "car {car} kg");
    assert!((tr - 100.0).abs() < 1e-9, "trailer {tr} kg");
}

#[test]
fn right_side_mirrors_the_left_and_hardpoints_are_where_the_files_say() {
    let v = load(&Options::default());
    let m = &v.model;
    let mut pairs = 0;
    for (k, mk) in m.each_marker() {
        let Some((l, r)) = [("_fl", "_fr"), ("_rl", "_rr"), ("_tl", "_tr")]
            .into_iter()
            // A side tag not followed by a letter (`knuckle_fl`, not `driver_floor`).
            .find(|(l, _)| {
                mk.name.match_indices(l).any(|(i, _)| {
                    !mk.name[i + l.len()..]
                        .chars()
                        .next()
                        .is_some_and(|c| c.is_ascii_lowercase())
                })
            })
        else {
            continue;
        };
        let right = mk.name.replace(l, r);
        let j = m
            .marker_by_name(&right)
            .unwrap_or_else(|| panic!("no {right} for {}", mk.name));
        let (a, b) = (marker_world(m, k), marker_world(m, j));
        assert!(
            (a[0] - b[0]).abs() < 1e-12
                && (a[1] + b[1]).abs() < 1e-12
                && (a[2] - b[2]).abs() < 1e-12,
            "{} {a:?} / {right} {b:?}",
            mk.name
        );
        // Axes: z along the mirrored line (either sense: joint axes and pins are lines).
        let za = mv(
            &rot(&m.bodies[mk.body.unwrap()].orientation),
            &[mk.axes[0][2], mk.axes[1][2], mk.axes[2][2]],
        );
        let mj = &m.markers[j];
        let zb = mv(
            &rot(&m.bodies[mj.body.unwrap()].orientation),
            &[mj.axes[0][2], mj.axes[1][2], mj.axes[2][2]],
        );
        let mirrored = |s: f64| {
            (za[0] - s * zb[0]).abs() + (za[1] + s * zb[1]).abs() + (za[2] - s * zb[2]).abs()
        };
        assert!(
            mirrored(1.0).min(mirrored(-1.0)) < 1e-12,
            "{} axes {za:?} / {zb:?}",
            mk.name
        );
        pairs += 1;
    }
    assert!(pairs > 40, "{pairs} mirrored marker pairs");
    // Inertia products with y change sign.
    let kl = &m.bodies[v.handles.bodies["knuckle_fl"]];
    let kr = &m.bodies[v.handles.bodies["knuckle_fr"]];
    assert_eq!(kl.inertia[0][0], kr.inertia[0][0]);
    assert_eq!(kl.inertia[0][1], -kr.inertia[0][1]);

    // Hardpoints: vehicle coordinates of the files = world at x offset 0.
    let front = table(repo!("vehicles/fabia/front_mcpherson.toml"));
    let rear = table(repo!("vehicles/fabia/rear_twist_beam.toml"));
    let at = |name: &str| marker_world(m, m.marker_by_name(name).unwrap());
    let hp = |t: &toml::Table, k: &str| vec3(&t["hardpoints"][k]);
    let close = |a: [f64; 3], b: [f64; 3]| (0..3).all(|c| (a[c] - b[c]).abs() < 1e-12);
    assert!(close(
        at("lca_front_bushing_fl.j"),
        hp(&front, "lower_arm_front_m")
    ));
    assert!(close(at("ball_joint_fl.i"), hp(&front, "ball_joint_m")));
    assert!(close(at("top_mount_fl.j"), hp(&front, "strut_top_m")));
    assert!(close(at("spring_fl.i"), hp(&front, "spring_seat_m")));
    assert!(close(at("wheel_fl.centre"), hp(&front, "wheel_centre_m")));
    assert!(close(at("arm_bushing_rl.j"), hp(&rear, "pivot_m")));
    assert!(close(at("spring_rl.j"), hp(&rear, "spring_upper_m")));
    assert!(close(at("knuckle_fl.cm"), vec3(&front["knuckle"]["cm_m"])));
    let mut right = hp(&rear, "wheel_centre_m");
    right[1] = -right[1];
    assert!(close(at("wheel_rr.centre"), right));
}

#[test]
fn modal_hitch_carries_the_fe_mass_properties_for_every_variant() {
    let origin = vec3(&table(repo!("vehicles/fabia/hitch.toml"))["hitch"]["fe_origin_m"]);
    let mut masses = Vec::new();
    for variant in 1..=10u32 {
        let v = load(&Options {
            hitch_variant: Some(variant),
            ..Default::default()
        });
        let h = v.handles.hitch.as_ref().unwrap();
        assert_eq!(h.variant, variant);
        let b = &v.model.bodies[h.body];
        let md = &b.modal.as_ref().unwrap().data;
        let (m_fe, cm_fe) = hitch_fe_mass(variant);
        assert!(
            (b.mass - m_fe).abs() < 1e-9 * m_fe,
            "variant {variant}: {} vs {m_fe}",
            b.mass
        );
        for c in 0..3 {
            assert!(
                (b.position[c] - (origin[c] + cm_fe[c])).abs() < 1e-9,
                "variant {variant} cm"
            );
            for r in 0..3 {
                assert_eq!(b.inertia[r][c], md.inertia_com_kg_m2[r][c]);
            }
        }
        let full = towride_mbs::flex::modal_data(
            Path::new(repo!("flex/hitch_crossbeam.toml")),
            Some(variant),
        )
        .unwrap();
        assert_eq!(
            md.modes.len(),
            full.modes.iter().filter(|m| m.selected).count()
        );
        // Markers on nodes sit at the node's undeformed position.
        for mk in v
            .model
            .markers
            .iter()
            .filter(|mk| mk.body == Some(h.body) && mk.node.is_some())
        {
            let n = &md.nodes[mk.node.unwrap()];
            for c in 0..3 {
                assert!(
                    (mk.position[c] - (n.position_m[c] - md.com_m[c])).abs() < 1e-12,
                    "{}",
                    mk.name
                );
            }
        }
        masses.push(m_fe);
    }
    // The variants differ (stiffer sections weigh more).
    assert!(masses.windows(2).any(|w| w[0] != w[1]));
}

#[test]
fn load_cases_move_the_trailer_centre_of_mass_where_the_file_says() {
    let tf = table(repo!("vehicles/trailer/box_trailer.toml"));
    let cases = tf["load_case"].as_array().unwrap();
    let centre = |v: &Vehicle| {
        let place = v.handles.trailer_place.unwrap();
        let (mut m, mut s) = (0.0, [0.0; 3]);
        for (b, body) in v.model.bodies.iter().enumerate() {
            if v.handles.body_place[b] != place {
                continue;
            }
            m += body.mass;
            s = add(&s, &body.position.map(|x| x * body.mass));
        }
        for w in v.handles.wheels.iter().filter(|w| w.name.starts_with('t')) {
            let belt = v.model.tyres[w.tyre].tyre.params().belt_mass;
            m += belt;
            s = add(&s, &marker_world(&v.model, w.centre).map(|x| x * belt));
        }
        (m, sub(&s.map(|x| x / m), &place.translation))
    };
    let empty = load(&Options {
        load_case: Some("empty".into()),
        ..Default::default()
    });
    let (m0, c0) = centre(&empty);
    // The thesis's four and the legal-limit case (docs/manoeuvres.md).
    assert_eq!(cases.len(), 5);
    for c in cases {
        let name = c["name"].as_str().unwrap();
        let v = load(&Options {
            load_case: Some(name.into()),
            ..Default::default()
        });
        let (m, cm) = centre(&v);
        let want = match c.get("payload") {
            None => (m0, c0),
            Some(p) => {
                let (mp, xp) = (num(&p["mass_kg"]), vec3(&p["cm_m"]));
                let s = add(&c0.map(|x| x * m0), &xp.map(|x| x * mp));
                (m0 + mp, s.map(|x| x / (m0 + mp)))
            }
        };
        assert!((m - want.0).abs() < 1e-9, "{name}: mass {m}");
        let d = v.design.trailer.as_ref().unwrap();
        assert_eq!(d.load_case, name);
        for k in 0..3 {
            assert!(
                (cm[k] - want.1[k]).abs() < 1e-9,
                "{name}: cm {cm:?} vs {:?}",
                want.1
            );
            assert!(
                (d.cm_m[k] - want.1[k]).abs() < 1e-9,
                "{name}: design cm {:?}",
                d.cm_m
            );
        }
    }
}
