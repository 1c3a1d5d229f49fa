//! `towride tyre-rig` as a user runs it.

use crate::{towride_err, towride_json};

#[test]
fn tyre_rig_json_and_files() {
    let dir = std::env::temp_dir().join(format!("towride-rigcli-{}", std::process::id()));
    let v = towride_json(&[
        "tyre-rig",
        repo!("scenes/tyre_rigs/cleat_car_40kmh.toml"),
        "--json",
        "--rtol",
        "1e-5",
        "--out",
        dir.to_str().unwrap(),
    ]);
    for key in [
        "hub_fz_max_n",
        "hub_fx_min_n",
        "steps",
        "airborne_s",
        "final_rolling_radius_m",
    ] {
        assert!(v[key].is_number(), "{key} missing: {v}");
    }
    assert_eq!(v["rig"], "cleat");
    assert!(v["hub_fz_max_n"].as_f64().unwrap() > 5000.0);
    let csv = std::fs::read_to_string(dir.join("cleat_car_40kmh.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header.starts_with("t_s,x_m,z_m,omega_rad_s,hub_fx_n"),
        "{header}"
    );
    assert!(dir.join("cleat_car_40kmh.png").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn tyre_rig_bad_file_names_it() {
    let dir = std::env::temp_dir().join(format!("towride-rigbad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("bad.toml");
    std::fs::write(
        &f,
        "[tyre]\nfile = \"x.tir\"\nmodel = \"rigid-ring\"\n[road]\nfile = \"r.toml\"\n[rig]\nkind = \"cleat\"\n[output]\ndt_s = 1e-3\n",
    )
    .unwrap();
    let err = towride_err(&["tyre-rig", f.to_str().unwrap()], 2);
    assert!(
        err.contains("bad.toml:6") && err.contains("speed_m_s"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
