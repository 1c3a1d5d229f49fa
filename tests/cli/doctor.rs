//! `towride doctor` prints every number with its unit, in its text and in its JSON
//! (field names carry the unit: `_s`, `_hz`, `_kg`, `_n_per_m`, ...; counts and ratios
//! are named as such).

use super::{towride_json, towride_ok};

/// Numbers of the JSON named by what they count or as ratios and shares
/// (dimensionless: also any `*_ratio`, `*_share`).
const COUNTS_AND_RATIOS: [&str; 10] = [
    "schema_version",
    "bodies",
    "equations",
    "constraint_rows",
    "dof",
    "first_order_states",
    "eigenvalues",
    "index",
    "newton_condition",
    "share",
];
const UNIT_SUFFIXES: [&str; 8] = [
    "_s",
    "_hz",
    "_kg",
    "_kg_m2",
    "_n_per_m",
    "_n_m_per_rad",
    "_1_per_s",
    "_rad_per_s",
];

fn numeric_keys(v: &serde_json::Value, key: &str, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Object(m) => m.iter().for_each(|(k, x)| numeric_keys(x, k, out)),
        serde_json::Value::Array(a) => a.iter().for_each(|x| numeric_keys(x, key, out)),
        serde_json::Value::Number(_) => out.push(key.to_string()),
        _ => {}
    }
}

#[test]
fn doctor_names_the_unit_of_every_number() {
    let scene = repo!("scenes/default.toml");
    let v = towride_json(&["doctor", scene, "--json"]);
    let mut keys = Vec::new();
    numeric_keys(&v, "", &mut keys);
    keys.sort();
    keys.dedup();
    let bare: Vec<&String> = keys
        .iter()
        .filter(|k| {
            !COUNTS_AND_RATIOS.contains(&k.as_str())
                && !k.ends_with("_ratio")
                && !k.ends_with("_share")
                && !UNIT_SUFFIXES.iter().any(|s| k.ends_with(s))
        })
        .collect();
    assert!(
        bare.is_empty(),
        "numbers without a unit in their name: {bare:?}"
    );
    // A bushing's translational stiffness in N/m against a mass, its rotational one in
    // N m/rad against an inertia; f = sqrt(k / m) / 2 pi.
    let b = v["bushings"].as_array().unwrap();
    let x = b.iter().find(|b| b["axis"] == "x").unwrap();
    let (k, m) = (
        x["stiffness_n_per_m"].as_f64().unwrap(),
        x["effective_mass_kg"].as_f64().unwrap(),
    );
    let f = x["frequency_hz"].as_f64().unwrap();
    assert!((f - (k / m).sqrt() / (2.0 * std::f64::consts::PI)).abs() < 1e-9 * f);
    let rx = b.iter().find(|b| b["axis"] == "rx").unwrap();
    assert!(rx["stiffness_n_m_per_rad"].is_number() && rx["stiffness_n_per_m"].is_null());

    // The text: every number followed by its unit (or by what it counts).
    let out = towride_ok(&["doctor", scene]);
    let text = String::from_utf8(out.stdout).unwrap();
    let after_name = text.split_once(": ").unwrap().1;
    let body = after_name.split("advice:").next().unwrap();
    let units = [
        "s",
        "[-]",
        "N/m",
        "N",
        "kg",
        "Hz",
        "bodies",
        "equations",
        "constraint",
        "modes",
        "rows",
    ];
    let mut bad = Vec::new();
    for line in body.lines() {
        let tokens: Vec<&str> = line.split_whitespace().collect();
        for (i, t) in tokens.iter().enumerate() {
            if t.trim_end_matches([',', ';', ':']).parse::<f64>().is_err() {
                continue;
            }
            let next = tokens
                .get(i + 1)
                .map(|n| n.trim_end_matches([',', ';', ':']));
            if !next.is_some_and(|n| units.contains(&n)) {
                bad.push(format!("{t} in '{line}'"));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "numbers without a unit:\n{}",
        bad.join("\n")
    );
}
