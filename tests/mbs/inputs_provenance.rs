//! Every physical number of the shipped property files carries a source class
//! (`docs/hitch_mounts.md`, `input::provenance`): a new value without one fails here.

use std::path::{Path, PathBuf};

use towride_mbs::input::provenance::{read_provenance, survey, untagged_values, SourceClass};

const DIRS: [&str; 3] = [repo!("vehicles"), repo!("flex"), repo!("roads")];

#[test]
fn every_number_of_the_shipped_property_files_has_a_class() {
    let paths: Vec<PathBuf> = DIRS.iter().map(PathBuf::from).collect();
    let s = survey(&paths).unwrap();
    // The tyre files, the hitch file and the FE files are among those read.
    for f in [
        "car_185_60r14.tir",
        "trailer_155_80r13.tir",
        "hitch.toml",
        "hitch_crossbeam.toml",
    ] {
        assert!(
            s.files.iter().any(|x| x.file.ends_with(f)),
            "{f} not surveyed"
        );
    }
    let missing: Vec<String> = s
        .files
        .iter()
        .flat_map(|f| {
            f.untagged
                .iter()
                .map(move |u| format!("{}:{} {}", f.file, u.line, u.key))
        })
        .collect();
    assert!(
        missing.is_empty(),
        "numbers without a source class:\n{}",
        missing.join("\n")
    );
    let total: usize = s.counts.iter().map(|(_, n)| n).sum();
    assert!(total > 300, "{total} tagged values");
}

#[test]
fn a_published_value_names_its_source() {
    let paths: Vec<PathBuf> = DIRS.iter().map(PathBuf::from).collect();
    for f in survey(&paths).unwrap().files {
        for e in f.entries {
            assert!(
                e.source.len() >= 10,
                "{}:{} {}: [{}] without a source",
                f.file,
                e.line,
                e.key,
                e.class
            );
        }
    }
}

#[test]
fn an_untagged_value_added_to_a_shipped_file_is_found() {
    let src = Path::new(repo!("vehicles/fabia/hitch.toml"));
    let text = std::fs::read_to_string(src).unwrap();
    let dir = std::env::temp_dir().join(format!("towride-prov-it-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("hitch.toml");
    std::fs::write(
        &p,
        text.replace("[mounting]\n", "[mounting]\nextra_mass_kg = 1.0\n"),
    )
    .unwrap();
    let un = untagged_values(&p).unwrap();
    assert_eq!(un.len(), 1, "{un:?}");
    assert_eq!(un[0].key, "mounting.extra_mass_kg");
    // The mounting values themselves are tagged, with the classes the file gives.
    let e = read_provenance(src).unwrap();
    let k = e.iter().find(|e| e.key == "mounting.loss_factor").unwrap();
    assert_eq!(k.class, SourceClass::Assumed);
}
