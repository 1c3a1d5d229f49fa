//! Issue 36 item 2: MDF4 files written by the `falcon_mdf` crate read back through the
//! validation reader (two channel groups at their own rates, recognised by their magic
//! bytes under any name), and damaged files are refused with an error naming the file,
//! never a panic.

use std::path::{Path, PathBuf};

use falcon_mdf::write::Mf4Writer;
use towride_app::validate::csv_reader::{read_table_with, TimeSpec};

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride-mf4app-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// 2 s of a 5 Hz sine in g at 1000 Hz, and a speed ramp 36 + t km/h at 100 Hz.
fn two_group_file(path: &Path) {
    let ta: Vec<f64> = (0..2000).map(|k| k as f64 / 1000.0).collect();
    let tb: Vec<f64> = (0..200).map(|k| k as f64 / 100.0).collect();
    let acc: Vec<f64> = ta
        .iter()
        .map(|t| (2.0 * std::f64::consts::PI * 5.0 * t).sin())
        .collect();
    let speed: Vec<f64> = tb.iter().map(|t| 36.0 + t).collect();
    let mut w = Mf4Writer::new();
    w.add_group(&ta)
        .unwrap()
        .add_channel("acc_z", "g", &acc)
        .unwrap();
    w.add_group(&tb)
        .unwrap()
        .add_channel("speed", "km/h", &speed)
        .unwrap();
    w.write_to_file(path).unwrap();
}

#[test]
fn a_crate_written_file_reads_each_group_on_its_own_clock() {
    let dir = tmp("read");
    // A misnamed file: recognised by its first bytes, not its name.
    let f = dir.join("logger.dat");
    two_group_file(&f);
    let t = read_table_with(&f, &TimeSpec::column("time"), &["acc_z", "speed"]).unwrap();
    // The 100 Hz group ends at 1.99 s: the 1000 Hz rows up to it, 0..=1990.
    assert_eq!(t.time_s.len(), 1991);
    assert!((t.time_base.rate_hz - 1000.0).abs() < 1e-6);
    assert_eq!(t.units, [Some("g".to_string()), Some("km/h".to_string())]);
    for (k, &tk) in t.time_s.iter().enumerate() {
        assert!((tk - k as f64 / 1000.0).abs() < 1e-12);
        let sine = (2.0 * std::f64::consts::PI * 5.0 * tk).sin();
        assert!((t.columns[0][k] - sine).abs() < 1e-12, "acc at {tk}");
        // A ramp is exact under linear interpolation.
        assert!(
            (t.columns[1][k] - (36.0 + tk)).abs() < 1e-9,
            "speed at {tk}"
        );
    }
    assert!(t.notes.iter().any(|n| n.contains("resampled linearly")));
    let e = read_table_with(&f, &TimeSpec::column("time"), &["acc_x"]).unwrap_err();
    assert!(e.to_string().contains("no channel `acc_x`"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn truncated_and_bit_flipped_files_are_refused_without_a_panic() {
    let dir = tmp("fuzz");
    let good = dir.join("good.mf4");
    two_group_file(&good);
    let bytes = std::fs::read(&good).unwrap();
    let f = dir.join("bad.mf4");
    let read = |b: &[u8]| {
        std::fs::write(&f, b).unwrap();
        read_table_with(&f, &TimeSpec::column("time"), &["acc_z", "speed"])
    };
    for k in 0..24 {
        let n = bytes.len() * k / 24;
        let e = read(&bytes[..n]).expect_err("a truncated file");
        assert!(e.to_string().contains("bad.mf4"), "{e}");
    }
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    for _ in 0..200 {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let mut b = bytes.clone();
        let at = (seed % b.len() as u64) as usize;
        b[at] ^= 1 << (seed >> 61);
        // A flip in a sample's bits is a valid file with another value; any error
        // names the file.
        if let Err(e) = read(&b) {
            assert!(e.to_string().contains("bad.mf4"), "{e}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
