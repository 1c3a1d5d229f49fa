//! `validate init` on recordings it used to draft a descriptor from that `validate`
//! refused or misread (issue 32): sample rates outside the bounds or 0, `--rate-hz`
//! beside a time column, two columns of one name, rows longer than the header.

use std::path::PathBuf;

use towride_app::validate::init::sniff;

fn file(tag: &str, text: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride-initin-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let f = d.join(format!("{tag}.csv"));
    std::fs::write(&f, text).unwrap();
    f
}

/// 20 rows of two acceleration columns, with a time column when `time`.
fn rows(time: bool) -> String {
    let mut t = String::from(if time { "time [s];" } else { "" });
    t.push_str("FL Sprung acceleration [g];RR Sprung acceleration [g]\n");
    for k in 0..20 {
        if time {
            t.push_str(&format!("{};", k as f64 * 1e-3));
        }
        t.push_str("1;1\n");
    }
    t
}

#[test]
fn sample_rates_are_bounded_as_validate_bounds_them() {
    let f = file("norate", &rows(false));
    for (rate, says) in [
        (1e12, "1e12 lies outside the accepted range"),
        (0.0, "must be positive, got 0; accepted"),
        (-5.0, "must be positive, got -5; accepted"),
        (f64::NAN, "must be finite"),
    ] {
        let e = sniff(&f, Some(rate)).unwrap_err().to_string();
        assert!(
            e.contains("norate.csv") && e.contains("--rate-hz") && e.contains(says),
            "{rate}: {e}"
        );
        assert!(!e.contains("time does not increase"), "{e}");
    }
    assert_eq!(sniff(&f, Some(500.0)).unwrap().time_base.rate_hz, 500.0);
    // A rate declared in a comment is held to the same bounds, named by its line.
    let f = file(
        "comment",
        &format!("# logger export\n# sample rate: 1e12 Hz\n{}", rows(false)),
    );
    let e = sniff(&f, None).unwrap_err().to_string();
    assert!(
        e.contains("comment.csv:2") && e.contains("outside the accepted range"),
        "{e}"
    );
}

#[test]
fn a_rate_beside_a_time_column_is_an_error() {
    let f = file("timed", &rows(true));
    let e = sniff(&f, Some(1000.0)).unwrap_err().to_string();
    assert!(
        e.contains("timed.csv:1:1")
            && e.contains("field `time`")
            && e.contains(
                "the file has a time column `time`; --rate-hz applies only to files without one"
            ),
        "{e}"
    );
    assert_eq!(sniff(&f, None).unwrap().rows, 20);
}

#[test]
fn repeated_column_names_and_long_rows_are_errors() {
    let dup = rows(true).replacen("RR Sprung acceleration", "FL Sprung acceleration", 1);
    let e = sniff(&file("dup", &dup), None).unwrap_err().to_string();
    assert!(
        e.contains("dup.csv:1:")
            && e.contains("field `FL Sprung acceleration`")
            && e.contains("column 3 repeats the name of column 2"),
        "{e}"
    );
    // Spelled differently, the same column to a reader that ignores case and spacing.
    let dup = rows(true).replacen("RR Sprung acceleration", "fl sprung  ACCELERATION", 1);
    assert!(sniff(&file("dup2", &dup), None).is_err());
    // Line 12 has a value past the last column.
    let long: String = rows(true)
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 11 {
                format!("{l};7\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let e = sniff(&file("long", &long), None).unwrap_err().to_string();
    assert!(
        e.contains("long.csv:12:") && e.contains("row has 4 fields, the header has 3"),
        "{e}"
    );
}

/// The header is looked up for each separator in turn: tried with `;` first, a
/// comma-separated header is one cell, and it was normalised again for each of the
/// columns looked up: 100 000 columns took over 10 minutes; now well under a second.
#[test]
fn a_wide_recording_is_sniffed_in_linear_time() {
    let n = 20_000;
    let mut t = String::from("time [s]");
    for k in 0..n {
        t.push_str(&format!(",p{k} [bar]"));
    }
    t.push('\n');
    let row = ",1.5".repeat(n);
    for k in 0..10 {
        t.push_str(&format!("{}{row}\n", k as f64 * 1e-3));
    }
    let f = file("wide", &t);
    let start = std::time::Instant::now();
    let s = sniff(&f, None).unwrap();
    assert_eq!(s.columns.len(), n);
    assert!(
        start.elapsed() < std::time::Duration::from_secs(10),
        "{:?}",
        start.elapsed()
    );
}
