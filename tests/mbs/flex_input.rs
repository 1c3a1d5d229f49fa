//! Malformed flexible-body files are refused with the file, the line and the field.

use std::path::PathBuf;

use towride_mbs::flex::Mesh;

const GOOD: &str = r#"name = "frame"

[[material]]
name = "steel"
youngs_modulus_pa = 2.1e11
poissons_ratio = 0.3
density_kg_m3 = 7850.0

[[section]]
name = "tube"
shape = "rectangular_hollow"
width_m = 0.06
height_m = 0.04
wall_m = 0.003

[[node]]
name = "a"
position_m = [0.0, 0.0, 0.0]
[[node]]
name = "b"
position_m = [1.0, 0.0, 0.0]
[[node]]
name = "c"
position_m = [1.0, 0.5, 0.0]

[[element]]
node_a = "a"
node_b = "b"
section = "tube"
material = "steel"
divisions = 4

[[element]]
node_a = "b"
node_b = "c"
section = "tube"
material = "steel"
divisions = 2

[[interface]]
name = "end"
node = "a"

[[variant]]
number = 1
section.tube = { wall_m = 0.002 }
"#;

fn write(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("towride-flex-input-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// 1-based line of the `n`-th occurrence (0-based) of `needle`.
fn line_of(text: &str, needle: &str, n: usize) -> usize {
    let at = text.match_indices(needle).nth(n).unwrap().0;
    text[..at].matches('\n').count() + 1
}

fn refuse(name: &str, text: &str, variant: Option<u32>) -> String {
    let p = write(name, text);
    let e = Mesh::read(&p, variant, &towride_mbs::input::Loader::new()).unwrap_err();
    let s = e.to_string();
    assert!(s.starts_with(&p.display().to_string()), "{s}");
    s
}

#[test]
fn the_good_file_reads() {
    let p = write("good.toml", GOOD);
    let m = Mesh::read(&p, None, &towride_mbs::input::Loader::new()).unwrap();
    assert_eq!(m.elements.len(), 6);
    assert_eq!(m.nodes.len(), 3 + 3 + 1);
    Mesh::read(&p, Some(1), &towride_mbs::input::Loader::new()).unwrap();
}

#[test]
fn element_naming_a_missing_node() {
    let text = GOOD.replacen("node_b = \"c\"", "node_b = \"d\"", 1);
    let e = refuse("missing_node.toml", &text, None);
    let line = line_of(&text, "node_b = \"d\"", 0);
    assert!(e.contains(&format!(":{line}:")), "{e}");
    assert!(e.contains("field `element[1].node_b`"), "{e}");
    assert!(e.contains("missing node `d`"), "{e}");
}

#[test]
fn zero_length_element() {
    let text = GOOD.replacen(
        "position_m = [1.0, 0.5, 0.0]",
        "position_m = [1.0, 0.0, 0.0]",
        1,
    );
    let e = refuse("zero_length.toml", &text, None);
    let line = line_of(&text, "node_b = \"c\"", 0);
    assert!(e.contains(&format!(":{line}:")), "{e}");
    assert!(e.contains("field `element[1].node_b`"), "{e}");
    assert!(e.contains("zero-length"), "{e}");
}

#[test]
fn zero_wall_thickness() {
    let text = GOOD.replacen("wall_m = 0.003", "wall_m = 0.0", 1);
    let e = refuse("zero_wall.toml", &text, None);
    let line = line_of(&text, "wall_m = 0.0", 0);
    assert!(e.contains(&format!(":{line}:")), "{e}");
    assert!(e.contains("field `section[0].wall_m`"), "{e}");
    assert!(e.contains("must be positive"), "{e}");
}

#[test]
fn zero_wall_thickness_in_a_variant_points_at_the_variant() {
    let text = GOOD.replacen("{ wall_m = 0.002 }", "{ wall_m = 0.0 }", 1);
    let e = refuse("zero_wall_variant.toml", &text, Some(1));
    let line = line_of(&text, "section.tube = { wall_m = 0.0 }", 0);
    assert!(e.contains(&format!(":{line}:")), "{e}");
    assert!(e.contains("field `variant[0].section.tube.wall_m`"), "{e}");
    // The base sections are fine, so without the variant the file reads.
    Mesh::read(
        &write("zero_wall_variant_base.toml", &text),
        None,
        &towride_mbs::input::Loader::new(),
    )
    .unwrap();
}

#[test]
fn interface_node_not_in_the_mesh() {
    let text = GOOD.replacen("node = \"a\"", "node = \"z\"", 1);
    let e = refuse("interface.toml", &text, None);
    let line = line_of(&text, "node = \"z\"", 0);
    assert!(e.contains(&format!(":{line}:")), "{e}");
    assert!(e.contains("field `interface[0].node`"), "{e}");
    assert!(e.contains("not in the mesh"), "{e}");
}

#[test]
fn unknown_keys_and_unknown_variants_are_refused() {
    let text = GOOD.replacen("wall_m = 0.003", "wal_m = 0.003", 1);
    let e = refuse("typo.toml", &text, None);
    let line = line_of(&text, "wal_m", 0);
    assert!(e.contains(&format!(":{line}:")), "{e}");
    assert!(e.contains("wal_m"), "{e}");
    let e = refuse("variant.toml", GOOD, Some(7));
    assert!(e.contains("no variant 7"), "{e}");
}
