//! The fuzz harness on the commands that read results rather than scenes (issue 32):
//! `compare` on spoilt run folders, `provenance` on spoilt property files, `sweep merge`
//! on spoilt shards, `sweep --resume` on a spoilt earlier result, and `sensitivity` with
//! hostile `--params` and `--outputs`. Each case runs the command as a user would (a
//! process, with a time limit) and is classified: clean error, panic, hang, silent
//! acceptance of input that is certainly bad, an input file changed on disk. The share
//! of errors naming file and line (and field) is printed.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::Rng;
use crate::reliability::tmp;

const CASES: usize = 160;
const LIMIT: Duration = Duration::from_secs(60);

/// A spoilt copy of a text file: the new text, what was done, certainly bad or not.
struct Spoilt {
    text: String,
    what: String,
    bad: bool,
}

/// Spoils one line or cell of a CSV table (first line its header).
fn spoil_csv(text: &str, rng: &mut Rng) -> Spoilt {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let rows = lines.len() - 1;
    let row = 1 + rng.below(rows.max(1));
    let ncol = lines[0].split(',').count();
    let col = rng.below(ncol);
    let cell = |v: &str, lines: &mut Vec<String>| {
        let mut f: Vec<String> = lines[row].split(',').map(str::to_string).collect();
        if col < f.len() {
            f[col] = v.to_string();
        }
        lines[row] = f.join(",");
    };
    let (what, bad) = match rng.below(9) {
        0 => {
            cell("abc", &mut lines);
            (format!("row {row} col {col} = abc"), col > 0)
        }
        1 => {
            cell("nan", &mut lines);
            (format!("row {row} col {col} = nan"), false)
        }
        2 => {
            cell("1e300", &mut lines);
            (format!("row {row} col {col} = 1e300"), false)
        }
        3 => {
            lines.truncate(1);
            ("no rows".into(), true)
        }
        4 => {
            let h: Vec<String> = lines[0].split(',').map(str::to_string).collect();
            let k = 1 + rng.below(h.len().saturating_sub(1).max(1));
            let mut h2 = h.clone();
            if k < h.len() {
                h2[k] = h[0].clone();
            }
            lines[0] = h2.join(",");
            (format!("column {k} named as column 0"), k < h.len())
        }
        5 => {
            lines[row].push_str(",1.0");
            (format!("row {row} one field longer"), true)
        }
        6 => {
            lines.remove(0);
            ("header deleted".into(), true)
        }
        7 => {
            let at = rng.below(text.len());
            let cut: String = text.chars().take(at).collect();
            return Spoilt {
                bad: !cut.contains('\n'),
                what: format!("cut at byte {at}"),
                text: cut,
            };
        }
        _ => {
            lines[row] = lines[row].replace(',', ";");
            (format!("row {row} separated by ;"), true)
        }
    };
    Spoilt {
        text: lines.join("\n") + "\n",
        what,
        bad,
    }
}

/// Spoils a JSON or TOML text: cut short, a value replaced, a line deleted.
fn spoil_text(text: &str, rng: &mut Rng) -> Spoilt {
    let lines: Vec<&str> = text.lines().collect();
    let k = rng.below(lines.len());
    match rng.below(3) {
        0 => {
            let at = rng.below(text.len());
            Spoilt {
                text: text.chars().take(at).collect(),
                what: format!("cut at byte {at}"),
                bad: false,
            }
        }
        1 => {
            let mut ls: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
            ls[k] = match ls[k].split_once([':', '=']) {
                Some((key, _)) if !key.trim_start().starts_with('#') => {
                    let sep = if ls[k].contains(": ") { ": " } else { " = " };
                    format!("{}{sep}\"x\"", key.trim_end())
                }
                _ => ls[k].clone(),
            };
            Spoilt {
                what: format!("line {}: `{}`", k + 1, ls[k]),
                text: ls.join("\n") + "\n",
                bad: false,
            }
        }
        _ => {
            let mut ls = lines.clone();
            ls.remove(k);
            Spoilt {
                text: ls.join("\n") + "\n",
                what: format!("line {} deleted", k + 1),
                bad: false,
            }
        }
    }
}

/// What one case gave.
enum Verdict {
    Ok,
    Error(String),
    Panic(String),
    Hang,
}

fn run(args: &[String]) -> Verdict {
    let mut child = Command::new(env!("CARGO_BIN_EXE_towride"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut e = String::new();
            use std::io::Read;
            child.stderr.take().unwrap().read_to_string(&mut e).ok();
            return match status.code() {
                Some(0) => Verdict::Ok,
                Some(101) | None => Verdict::Panic(e),
                _ if e.contains("panicked") => Verdict::Panic(e),
                _ => Verdict::Error(e),
            };
        }
        if t.elapsed() > LIMIT {
            let _ = child.kill();
            return Verdict::Hang;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Bytes of every file below `dir`, to find an input changed on disk.
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(snapshot(&p));
        } else {
            out.push((p.clone(), std::fs::read(&p).unwrap()));
        }
    }
    out.sort();
    out
}

fn copy(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        if e.path().is_file() {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// One case: the command line, the inputs it must leave as they were, the file an
/// error should name, and whether the input is certainly bad.
struct Case {
    surface: &'static str,
    args: Vec<String>,
    inputs: PathBuf,
    names: String,
    what: String,
    bad: bool,
}

/// The results the cases spoil, made once.
struct Base {
    run_a: PathBuf,
    run_b: PathBuf,
    shard0: PathBuf,
    shard1: PathBuf,
    whole: PathBuf,
}

fn base(root: &Path) -> Base {
    let t = |args: &[&str]| {
        let o = crate::towride(args);
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    };
    let b = Base {
        run_a: root.join("a"),
        run_b: root.join("b"),
        shard0: root.join("s0"),
        shard1: root.join("s1"),
        whole: root.join("w"),
    };
    let pendulum = "scenes/examples/pendulum.toml";
    t(&["run", pendulum, "--out", &s(&b.run_a)]);
    t(&[
        "run",
        pendulum,
        "--out",
        &s(&b.run_b),
        "--set",
        "pendulum.toml:body[0].mass_kg=2.0",
    ]);
    let sweep = "scenes/examples/pendulum_sweep.toml";
    for (k, d) in [&b.shard0, &b.shard1].into_iter().enumerate() {
        t(&[
            "sweep",
            sweep,
            "--shard",
            &format!("{k}/2"),
            "--jobs",
            "1",
            "--out",
            &s(d),
        ]);
    }
    t(&["sweep", sweep, "--jobs", "1", "--out", &s(&b.whole)]);
    b
}

fn make(k: usize, b: &Base, root: &Path, rng: &mut Rng) -> Case {
    let dir = root.join(format!("c{k}"));
    let spoil = |file: &Path, rng: &mut Rng| -> Spoilt {
        let text = std::fs::read_to_string(file).unwrap();
        if file.extension().is_some_and(|e| e == "csv") {
            spoil_csv(&text, rng)
        } else {
            spoil_text(&text, rng)
        }
    };
    match rng.below(5) {
        0 => {
            let run = dir.join("b");
            copy(&b.run_b, &run);
            // Mostly the table; its summary twin a quarter of the time.
            let f = run.join(if rng.below(4) < 3 {
                "outputs.csv"
            } else {
                "summary.json"
            });
            let sp = spoil(&f, rng);
            std::fs::write(&f, &sp.text).unwrap();
            Case {
                surface: "compare",
                args: vec![
                    "compare".into(),
                    s(&b.run_a),
                    s(&run),
                    "--out".into(),
                    s(&dir.join("cmp")),
                ],
                inputs: run,
                names: f.file_name().unwrap().to_string_lossy().into(),
                what: sp.what,
                bad: sp.bad && f.ends_with("outputs.csv"),
            }
        }
        1 => {
            let files = [
                "vehicles/van_air/van.toml",
                "vehicles/fabia/hitch.toml",
                "vehicles/trailer/box_trailer.toml",
            ];
            let src = Path::new(env!("CARGO_MANIFEST_DIR")).join(files[rng.below(3)]);
            let text = std::fs::read_to_string(&src).unwrap();
            std::fs::create_dir_all(&dir).unwrap();
            let f = dir.join(src.file_name().unwrap());
            // A source class misspelt, or the text spoilt.
            let (text, what, bad) = if rng.below(2) == 0 && text.contains("[assumed]") {
                let n = text.matches("[assumed]").count();
                let at = rng.below(n);
                let mut seen = 0;
                let t = text
                    .split_inclusive('\n')
                    .map(|l| {
                        if l.contains("[assumed]") {
                            seen += 1;
                            if seen == at + 1 {
                                return l.replacen("[assumed]", "[asumed]", 1);
                            }
                        }
                        l.to_string()
                    })
                    .collect::<String>();
                (t, format!("class {at} misspelt"), true)
            } else {
                let sp = spoil_text(&text, rng);
                (sp.text, sp.what, false)
            };
            std::fs::write(&f, text).unwrap();
            Case {
                surface: "provenance",
                args: vec!["provenance".into(), s(&f)],
                inputs: dir.clone(),
                names: f.file_name().unwrap().to_string_lossy().into(),
                what,
                bad,
            }
        }
        2 => {
            let sh = dir.join("s1");
            copy(&b.shard1, &sh);
            let name = if rng.below(2) == 0 {
                "summary_shard1of2.csv"
            } else {
                "summary_shard1of2.json"
            };
            let sp = spoil(&sh.join(name), rng);
            std::fs::write(sh.join(name), &sp.text).unwrap();
            Case {
                surface: "sweep merge",
                args: vec![
                    "sweep".into(),
                    "merge".into(),
                    s(&b.shard0.join("summary_shard0of2.csv")),
                    s(&sh.join("summary_shard1of2.csv")),
                    "--out".into(),
                    s(&dir.join("merged.csv")),
                ],
                inputs: sh,
                names: name.into(),
                what: sp.what,
                bad: sp.bad && name.ends_with(".csv"),
            }
        }
        3 => {
            let w = dir.join("w");
            copy(&b.whole, &w);
            let name = if rng.below(2) == 0 {
                "summary.csv"
            } else {
                "summary.json"
            };
            let sp = spoil(&w.join(name), rng);
            std::fs::write(w.join(name), &sp.text).unwrap();
            Case {
                surface: "sweep --resume",
                args: vec![
                    "sweep".into(),
                    "scenes/examples/pendulum_sweep.toml".into(),
                    "--resume".into(),
                    "--jobs".into(),
                    "1".into(),
                    "--out".into(),
                    s(&w),
                ],
                // The resumed sweep rewrites its own summary: nothing to hold fixed.
                inputs: PathBuf::new(),
                names: name.into(),
                what: sp.what,
                bad: false,
            }
        }
        _ => {
            let params = [
                "pendulum.toml:body[0].mass_kg=0..1",
                "nofile.toml:body[0].mass_kg",
                "pendulum.toml:body[9].mass_kg",
                "pendulum.toml:body[0].mas_kg",
                "pendulum.toml:",
                ":body[0].mass_kg",
                "pendulum.toml:body[0].mass_kg=5..1",
                "pendulum.toml:body[0].mass_kg=nan..1",
                "pendulum.toml:body[0].mass_kg,pendulum.toml:body[0].mass_kg",
            ];
            let outputs = [
                "pivot.force.z.abs_peak",
                "nochannel.max",
                "pivot.force.z.median",
                "",
            ];
            let (p, o) = (rng.below(params.len()), rng.below(outputs.len()));
            Case {
                surface: "sensitivity",
                args: vec![
                    "sensitivity".into(),
                    "scenes/examples/pendulum.toml".into(),
                    "--params".into(),
                    params[p].into(),
                    "--outputs".into(),
                    outputs[o].into(),
                    "--out".into(),
                    s(&dir.join("sens")),
                ],
                inputs: PathBuf::new(),
                names: String::new(),
                what: format!("--params {} --outputs {}", params[p], outputs[o]),
                bad: true,
            }
        }
    }
}

#[test]
fn fuzz_result_readers_bounded() {
    let root = tmp("fuzz_tools");
    let b = base(&root);
    let mut rng = Rng(0x5eed_0036);
    let (mut errors, mut named, mut lined) = (0, 0, 0);
    let mut per: std::collections::BTreeMap<&str, usize> = Default::default();
    let mut failures = Vec::new();
    let wall = Instant::now();
    for k in 0..CASES {
        let c = make(k, &b, &root, &mut rng);
        *per.entry(c.surface).or_default() += 1;
        let before = (!c.inputs.as_os_str().is_empty()).then(|| snapshot(&c.inputs));
        let label = format!("{} ({})", c.surface, c.what);
        match run(&c.args) {
            Verdict::Hang => failures.push(format!("hang: {label}")),
            Verdict::Panic(e) => failures.push(format!("panic: {label}: {e}")),
            Verdict::Ok if c.bad => failures.push(format!("silently accepted: {label}")),
            Verdict::Ok => {}
            Verdict::Error(e) => {
                errors += 1;
                let first = e.lines().find(|l| l.starts_with("error")).unwrap_or(&e);
                // Argument cases name the option; file cases the file.
                let names_it = if c.names.is_empty() {
                    first.contains("--params") || first.contains("--outputs")
                } else {
                    first.contains(&c.names)
                };
                named += names_it as usize;
                let (line, _) = crate::common::located(first);
                lined += (line || c.names.is_empty()) as usize;
                if !names_it {
                    failures.push(format!("names no file or option: {label}: {first}"));
                } else if !line && !c.names.is_empty() {
                    println!("  file only: {label}: {first}");
                }
            }
        }
        if let Some(before) = before {
            if snapshot(&c.inputs) != before {
                failures.push(format!("input changed: {label}"));
            }
        }
    }
    let pct = |n: usize| 100.0 * n as f64 / errors.max(1) as f64;
    println!(
        "fuzz result readers: {CASES} cases ({per:?}) in {:.1} s, {errors} errors: {:.1} % name the file, {:.1} % with its line or the option; {} failures",
        wall.elapsed().as_secs_f64(),
        pct(named),
        pct(lined),
        failures.len()
    );
    for f in &failures {
        println!("  {f}");
    }
    let _ = std::fs::remove_dir_all(&root);
    assert!(failures.is_empty(), "{failures:#?}");
    assert!(pct(lined) >= 98.0, "{:.1} % located", pct(lined));
}
