//! `towride provenance` as a user runs it: classes of the shipped files, and a number
//! without a class found by file, line and key with exit code 1.

use crate::{towride, towride_json};

#[test]
fn provenance_lists_classes_and_fails_on_an_untagged_number() {
    let v = towride_json(&["provenance", repo!("vehicles/fabia/hitch.toml"), "--json"]);
    assert_eq!(v["schema_version"], 1);
    assert_eq!(v["untagged"], 0);
    let entries = v["files"][0]["entries"].as_array().unwrap();
    let lf = entries
        .iter()
        .find(|e| e["key"] == "mounting.loss_factor")
        .unwrap();
    assert_eq!(lf["class"], "assumed");

    let dir = std::env::temp_dir().join(format!("towride-provcli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("part.toml");
    std::fs::write(
        &f,
        "[part]\nmass_kg = 3.0  # [measured] scale, 2024\nlength_m = 0.5\n",
    )
    .unwrap();
    let out = towride(&["provenance", f.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("3  UNTAGGED   part.length_m"), "{text}");
    assert!(
        text.contains("measured   part.mass_kg: scale, 2024"),
        "{text}"
    );
    let out = towride(&["provenance", f.to_str().unwrap(), "--class", "guessed"]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
