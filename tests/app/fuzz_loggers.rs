//! The fuzz harness on logger files (issue 32): a recording spoilt in the ways real
//! loggers spoil them (binary junk, no rows, one row, NaN and infinite cells, huge
//! values, 100 k columns, mixed separators, a units row of the wrong length, time going
//! backwards, a byte-order mark, UTF-16 with and without its mark, Latin-1, repeated
//! columns, long rows), each read by `validate init`'s sniffer and by `validate`'s
//! reader through its descriptor. A case fails on a panic, a hang, success where the file
//! is certainly bad, refusal where it is valid, and an error that names no file; the
//! share naming file, line and field is printed and must reach 98 %.

use std::path::Path;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use towride_app::validate::csv_reader::read_measurement;
use towride_app::validate::init::sniff;
use towride_app::validate::Descriptor;

const RUN: &str = "measurements/synthetic/bump_25mm_40kmh_empty";
const LIMIT: Duration = Duration::from_secs(60);

/// What a spoilt file must give: `Some(true)` an error, `Some(false)` a result, `None`
/// either (the reader may repair it, e.g. a NaN is a missing sample).
struct Spoilt {
    name: &'static str,
    bytes: Vec<u8>,
    /// For `validate`'s reader.
    refuse: Option<bool>,
    /// For the sniffer of `validate init`.
    sniff_refuse: Option<bool>,
}

fn cases(text: &str) -> Vec<Spoilt> {
    let lines: Vec<&str> = text.lines().collect();
    let head = lines.iter().position(|l| l.starts_with("time")).unwrap();
    let (pre, header, rows) = (&lines[..head], lines[head], &lines[head + 1..]);
    let join = |ls: Vec<String>| (ls.join("\n") + "\n").into_bytes();
    let with_rows = |rs: Vec<String>| {
        let mut v: Vec<String> = pre.iter().map(|s| s.to_string()).collect();
        v.push(header.to_string());
        v.extend(rs);
        join(v)
    };
    let all = || rows.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let cell = |k: usize, col: usize, v: &str| {
        let mut r = all();
        let mut f: Vec<String> = r[k].split(',').map(|s| s.to_string()).collect();
        f[col] = v.to_string();
        r[k] = f.join(",");
        with_rows(r)
    };
    let ncol = header.split(',').count();
    let wide_header: String = (0..100_000).map(|k| format!(",c{k} [m/s^2]")).collect();
    let mut out = vec![
        Spoilt {
            name: "binary junk",
            bytes: (0..4096u32)
                .map(|k| (k.wrapping_mul(2_654_435_761) >> 13) as u8)
                .collect(),
            refuse: Some(true),
            sniff_refuse: Some(true),
        },
        Spoilt {
            name: "empty",
            bytes: Vec::new(),
            refuse: Some(true),
            sniff_refuse: Some(true),
        },
        Spoilt {
            name: "header only",
            bytes: with_rows(vec![]),
            refuse: Some(true),
            sniff_refuse: Some(true),
        },
        Spoilt {
            name: "one row",
            bytes: with_rows(vec![rows[0].to_string()]),
            refuse: Some(true),
            sniff_refuse: None,
        },
        Spoilt {
            name: "a NaN cell",
            bytes: cell(500, 3, "nan"),
            refuse: None,
            sniff_refuse: None,
        },
        Spoilt {
            name: "an infinite cell",
            bytes: cell(500, 3, "inf"),
            refuse: None,
            sniff_refuse: None,
        },
        Spoilt {
            name: "a huge value",
            bytes: cell(500, 3, "1e300"),
            refuse: Some(true),
            sniff_refuse: None,
        },
        Spoilt {
            name: "time going backwards",
            bytes: cell(500, 0, "0.001"),
            refuse: Some(true),
            sniff_refuse: None,
        },
        Spoilt {
            name: "a repeated column",
            bytes: {
                let h = header.replacen("body_front_right_z", "body_front_left_z", 1);
                let mut v: Vec<String> = pre.iter().map(|s| s.to_string()).collect();
                v.push(h);
                v.extend(all());
                join(v)
            },
            refuse: Some(true),
            sniff_refuse: Some(true),
        },
        Spoilt {
            name: "a row longer than the header",
            bytes: {
                let mut r = all();
                r[300] += ",1.0";
                with_rows(r)
            },
            refuse: Some(true),
            sniff_refuse: Some(true),
        },
        Spoilt {
            name: "mixed separators",
            bytes: {
                let mut r = all();
                r[300] = r[300].replace(',', ";");
                with_rows(r)
            },
            refuse: Some(true),
            sniff_refuse: None,
        },
        Spoilt {
            name: "a units row of the wrong length",
            bytes: {
                let mut v: Vec<String> = pre.iter().map(|s| s.to_string()).collect();
                v.push(
                    header
                        .split(',')
                        .map(|h| h.split(" [").next().unwrap())
                        .collect::<Vec<_>>()
                        .join(","),
                );
                v.push(vec!["s"; ncol - 2].join(","));
                v.extend(all());
                join(v)
            },
            refuse: Some(true),
            sniff_refuse: None,
        },
        Spoilt {
            name: "a byte-order mark",
            bytes: {
                let mut b = vec![0xEF, 0xBB, 0xBF];
                b.extend(text.as_bytes());
                b
            },
            refuse: Some(false),
            sniff_refuse: Some(false),
        },
        Spoilt {
            name: "UTF-16",
            bytes: {
                let mut b = vec![0xFF, 0xFE];
                for u in text.encode_utf16() {
                    b.extend(u.to_le_bytes());
                }
                b
            },
            refuse: Some(false),
            sniff_refuse: Some(false),
        },
        Spoilt {
            name: "UTF-16 without a byte-order mark",
            bytes: text.encode_utf16().flat_map(|u| u.to_le_bytes()).collect(),
            refuse: Some(true),
            sniff_refuse: Some(true),
        },
        Spoilt {
            // A Windows-1252 export: `µ` as one byte in a comment.
            name: "Latin-1",
            bytes: {
                let mut b = b"# range 16 g, \xB5-controller\n".to_vec();
                b.extend(text.as_bytes());
                b
            },
            refuse: Some(false),
            sniff_refuse: Some(false),
        },
        Spoilt {
            name: "100 k columns",
            bytes: {
                let mut v = vec![format!("time [s]{wide_header}")];
                for k in 0..5 {
                    v.push(format!("{}{}", k as f64 * 0.002, ",0.0".repeat(100_000)));
                }
                join(v)
            },
            refuse: Some(true),
            sniff_refuse: None,
        },
    ];
    // Cut short at a few places.
    for (k, at) in [(0, 7usize), (1, text.len() / 2), (2, text.len() - 3)] {
        let name = ["cut in the comments", "cut mid-file", "cut in the last row"][k];
        out.push(Spoilt {
            name,
            bytes: text.as_bytes()[..at].to_vec(),
            refuse: if k == 0 { Some(true) } else { None },
            sniff_refuse: if k == 0 { Some(true) } else { None },
        });
    }
    out
}

/// Names the file, and its line and field.
fn located(msg: &str, file: &str) -> (bool, bool) {
    let named = msg.contains(file);
    let line_field = msg.match_indices(&format!("{file}:")).any(|(i, _)| {
        msg[i + file.len() + 1..]
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_digit())
    }) && msg.contains("field `");
    (named, line_field)
}

#[test]
fn fuzz_loggers_bounded() {
    let repo = Path::new(repo!(""));
    let dir = std::env::temp_dir().join(format!("towride-fuzz-log-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(repo.join(format!("{RUN}.csv"))).unwrap();
    let desc = std::fs::read_to_string(repo.join(format!("{RUN}.toml")))
        .unwrap()
        .replace("\"../../", &format!("\"{}/", repo.display()));
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let (mut tried, mut errors, mut named, mut full) = (0, 0, 0, 0);
    let mut failures: Vec<String> = Vec::new();
    let wall = Instant::now();
    for (k, c) in cases(&text).into_iter().enumerate() {
        let sub = dir.join(format!("c{k}"));
        std::fs::create_dir_all(&sub).unwrap();
        let csv = sub.join("bump_25mm_40kmh_empty.csv");
        std::fs::write(&csv, &c.bytes).unwrap();
        std::fs::write(sub.join("run.toml"), &desc).unwrap();
        for (reader, expect) in [("validate init", c.sniff_refuse), ("validate", c.refuse)] {
            tried += 1;
            let (tx, rx) = mpsc::channel();
            let (csv2, toml) = (csv.clone(), sub.join("run.toml"));
            std::thread::spawn(move || {
                let r = std::panic::catch_unwind(|| -> Result<(), String> {
                    if reader == "validate init" {
                        sniff(&csv2, None).map(|_| ()).map_err(|e| e.to_string())
                    } else {
                        let d = Descriptor::from_file(&toml).map_err(|e| e.to_string())?;
                        read_measurement(&d).map(|_| ()).map_err(|e| e.to_string())
                    }
                });
                let _ = tx.send(r);
            });
            let label = format!("{} ({reader})", c.name);
            match rx.recv_timeout(LIMIT) {
                Err(_) => failures.push(format!("hang: {label}")),
                Ok(Err(_)) => failures.push(format!("panic: {label}")),
                Ok(Ok(Ok(()))) => {
                    if expect == Some(true) {
                        failures.push(format!("silently accepted: {label}"));
                    }
                }
                Ok(Ok(Err(msg))) => {
                    errors += 1;
                    if expect == Some(false) {
                        failures.push(format!("valid input refused: {label}: {msg}"));
                    }
                    let (n, f) = located(&msg, "bump_25mm_40kmh_empty.csv");
                    named += n as usize;
                    full += f as usize;
                    if !n {
                        failures.push(format!("names no file: {label}: {msg}"));
                    } else if !f {
                        println!("  file only: {label}: {msg}");
                    }
                }
            }
        }
    }
    std::panic::set_hook(hook);
    let pct = |n: usize| 100.0 * n as f64 / errors.max(1) as f64;
    println!(
        "fuzz loggers: {tried} cases in {:.1} s, {errors} errors: {:.1} % name the file, {:.1} % file, line and field; {} failures",
        wall.elapsed().as_secs_f64(),
        pct(named),
        pct(full),
        failures.len()
    );
    for f in &failures {
        println!("  {f}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(failures.is_empty(), "{failures:#?}");
    // The goal: errors name file, line and field.
    assert!(
        pct(full) >= 98.0,
        "{:.1} % name file, line and field",
        pct(full)
    );
}
