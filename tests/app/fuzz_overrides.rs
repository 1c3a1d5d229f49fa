//! The fuzz harness on overrides (issue 32): random `FILE:PATH = VALUE` overrides of the
//! files the default scene and the `simple` van read, written as a `--set` argument, a
//! scene's `[[override]]` table or an `--overrides` file line, and read as the command
//! line would. A case fails on a panic, a hang, an input file changed on disk, success
//! with an override known to be bad (an absurd number, a key the file lacks, a file the
//! run does not read, one value set twice, a value towride derives), and an error that
//! names neither where the override was written nor a file, line and field.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use towride_app::scene::{self, Changes};
use towride_mbs::input::{read_overrides, Loader, Override};

use crate::fuzz::Rng;

/// Cases tried in CI.
const CI_CASES: usize = 600;
const LIMIT: Duration = Duration::from_secs(60);
const SCENES: [&str; 2] = ["scenes/default.toml", "scenes/van_air/bump_50mm.toml"];

/// A numeric value of a file a scene reads: (file relative to the repository, path).
fn targets(scene: &str) -> Vec<(String, String)> {
    let loader = Loader::new();
    scene::load_with(Path::new(&repo(scene)), &Changes::default(), &loader).unwrap();
    let root = repo("");
    let mut out = Vec::new();
    for f in loader.files_read() {
        let rel = f
            .strip_prefix(&root)
            .unwrap_or(&f)
            .display()
            .to_string()
            .trim_start_matches('/')
            .to_string();
        let text = std::fs::read_to_string(&f).unwrap();
        if rel.ends_with(".tir") {
            let mut section = String::new();
            for l in text.lines() {
                let l = l.trim();
                if l.starts_with('[') {
                    section = l.trim_matches(['[', ']']).to_string();
                } else if let Some((k, v)) = l.split_once('=') {
                    let v = v.split('$').next().unwrap_or("").trim();
                    if v.parse::<f64>().is_ok() && !section.is_empty() {
                        out.push((rel.clone(), format!("{section}.{}", k.trim())));
                    }
                }
            }
        } else if rel.ends_with(".toml") {
            let t: toml::Table = text.parse().unwrap();
            numbers(&toml::Value::Table(t), "", &mut |p| {
                out.push((rel.clone(), p))
            });
        }
    }
    out
}

fn numbers(v: &toml::Value, at: &str, f: &mut dyn FnMut(String)) {
    let join = |k: &str| {
        if at.is_empty() {
            k.to_string()
        } else {
            format!("{at}.{k}")
        }
    };
    match v {
        toml::Value::Table(t) => t.iter().for_each(|(k, x)| numbers(x, &join(k), f)),
        toml::Value::Array(a) if a.iter().all(|x| x.is_table()) => {
            for (i, x) in a.iter().enumerate() {
                numbers(x, &format!("{at}[{i}]"), f);
            }
        }
        toml::Value::Float(_) | toml::Value::Integer(_) => f(at.to_string()),
        _ => {}
    }
}

/// A path of the repository, normalised (`crates/towride-app/../../` dropped).
fn repo(p: &str) -> String {
    towride_mbs::input::normalized(&Path::new(repo!("")).join(p))
        .display()
        .to_string()
}

/// One override case: how it is written, and whether it is certainly bad.
struct Case {
    overrides: Vec<(String, String, String)>,
    what: String,
    bad: bool,
}

const ABSURD: &[&str] = &["nan", "inf", "1e300", "-1e300"];
const ODD: &[&str] = &["0", "-1", "1e-300", "\"x\"", "[]", "2.5"];

fn make(targets: &[(String, String)], rng: &mut Rng) -> Case {
    let (file, path) = &targets[rng.below(targets.len())];
    // The file's name, or more of its path.
    let name = Path::new(file)
        .file_name()
        .unwrap()
        .to_string_lossy()
        .to_string();
    let file = if rng.below(2) == 0 {
        name
    } else {
        file.clone()
    };
    match rng.below(8) {
        0 | 1 => {
            let v = ABSURD[rng.below(ABSURD.len())];
            Case {
                what: format!("{file}:{path} = {v}"),
                overrides: vec![(file, path.clone(), v.into())],
                // A number the file's reader ignores may hold anything: only the
                // command's own checks say; `nan` and `inf` are no TOML numbers.
                bad: true,
            }
        }
        2 | 3 => {
            let v = ODD[rng.below(ODD.len())];
            Case {
                what: format!("{file}:{path} = {v}"),
                overrides: vec![(file, path.clone(), v.into())],
                bad: false,
            }
        }
        4 => {
            // A misspelt key: one letter doubled.
            let mut p = path.clone();
            let at = p.rfind(|c: char| c.is_ascii_alphabetic()).unwrap_or(0);
            p.insert(at, p.as_bytes()[at] as char);
            Case {
                what: format!("{file}:{p} (misspelt) = 1"),
                overrides: vec![(file, p, "1".into())],
                bad: true,
            }
        }
        5 => Case {
            what: format!("nothing_{file}:{path} = 1"),
            overrides: vec![(format!("nothing_{file}"), path.clone(), "1".into())],
            bad: true,
        },
        6 => Case {
            what: format!("{file}:{path} set twice"),
            overrides: vec![
                (file.clone(), path.clone(), "1".into()),
                (file, path.clone(), "2".into()),
            ],
            bad: true,
        },
        _ => Case {
            what: format!("{file}:{path} = 1.01 (plausible)"),
            overrides: vec![(file, path.clone(), "1.01".into())],
            bad: false,
        },
    }
}

/// How a case is written: each override's origin text the error must name.
#[derive(Clone, Copy, Debug)]
enum Form {
    Argument,
    SceneTable,
    OverridesFile,
}

fn exercise(
    dir: &Path,
    scene: &str,
    case: &[(String, String, String)],
    form: Form,
) -> Result<(), String> {
    let s = |e: &dyn std::fmt::Display| e.to_string();
    // The default scene read with the caller's overrides `ov`.
    let load = |ov: Vec<Override>| {
        scene::load_with(
            Path::new(&repo(scene)),
            &Changes::default(),
            &Loader::with_overrides(ov),
        )
        .map(|_| ())
        .map_err(|e| s(&e))
    };
    match form {
        Form::Argument => load(
            case.iter()
                .map(|(f, p, v)| Override::from_argument(&format!("{f}:{p}={v}")))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|e| s(&e))?,
        ),
        Form::OverridesFile => {
            let mut text = String::new();
            for (f, p, v) in case {
                text += &format!("{:?} = {v}\n", format!("{f}:{p}"));
            }
            let file = dir.join("ov.toml");
            std::fs::write(&file, text).unwrap();
            load(read_overrides(&file).map_err(|e| s(&e))?)
        }
        Form::SceneTable => {
            let base = repo(scene);
            let parent = Path::new(&base).parent().unwrap().display().to_string();
            let mut text = std::fs::read_to_string(&base)
                .unwrap()
                .replace("= \"../", &format!("= \"{parent}/../"));
            for (f, p, v) in case {
                text += &format!("\n[[override]]\nfile = {f:?}\npath = {p:?}\nvalue = {v}\n");
            }
            let file = dir.join("scene.toml");
            std::fs::write(&file, text).unwrap();
            scene::load_with(&file, &Changes::default(), &Loader::new())
                .map(|_| ())
                .map_err(|e| s(&e))
        }
    }
}

/// Errors naming where the override was written, or a file with its line and a field.
fn located(msg: &str, form: Form) -> (bool, bool) {
    let origin = match form {
        Form::Argument => msg.contains("command line: field `--set "),
        Form::SceneTable => msg.contains("scene.toml:") && msg.contains("field `override["),
        Form::OverridesFile => msg.contains("ov.toml:"),
    };
    let (file_line, field) = crate::fuzz::located(msg);
    let file_line = file_line && field;
    (origin, file_line)
}

/// What the shipped inputs hold, to see that no case changed them.
fn fingerprint() -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for d in ["scenes", "vehicles", "roads", "flex"] {
        let mut stack = vec![PathBuf::from(repo(d))];
        while let Some(p) = stack.pop() {
            for e in std::fs::read_dir(&p).unwrap().flatten() {
                let q = e.path();
                if q.is_dir() {
                    stack.push(q);
                } else {
                    out.push((q.clone(), std::fs::read(&q).unwrap()));
                }
            }
        }
    }
    out.sort();
    out
}

#[test]
fn fuzz_overrides_bounded() {
    let before = fingerprint();
    let dir = std::env::temp_dir().join(format!("towride-fuzz-ov-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tg: Vec<Vec<(String, String)>> = SCENES.iter().map(|s| targets(s)).collect();
    let mut rng = Rng(0x5eed_0032);
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let (mut panics, mut hangs, mut silent, mut vague) = (vec![], vec![], vec![], vec![]);
    let (mut errors, mut at_origin, mut accepted) = (0, 0, 0);
    let wall = Instant::now();
    for k in 0..CI_CASES {
        let si = k % SCENES.len();
        let mut case = make(&tg[si], &mut rng);
        // A .tir key the tyre reader does not read may hold anything (as in the file
        // fuzz harness): it counts as read when a word there is refused.
        if case.bad && case.overrides.len() == 1 && case.overrides[0].0.ends_with(".tir") {
            let (f, p, _) = &case.overrides[0];
            let probe = [(f.clone(), p.clone(), "x".to_string())];
            let d = dir.join("probe");
            std::fs::create_dir_all(&d).unwrap();
            if exercise(&d, SCENES[si], &probe, Form::Argument).is_ok() {
                case.bad = false;
            }
        }
        let form = [Form::Argument, Form::SceneTable, Form::OverridesFile][rng.below(3)];
        let label = format!("case {k}: {} {:?}: {}", SCENES[si], form, case.what);
        let (tx, rx) = mpsc::channel();
        let (d, sc, ov) = (
            dir.join(format!("c{k}")),
            SCENES[si],
            case.overrides.clone(),
        );
        std::fs::create_dir_all(&d).unwrap();
        std::thread::spawn(move || {
            let _ = tx.send(std::panic::catch_unwind(|| exercise(&d, sc, &ov, form)));
        });
        match rx.recv_timeout(LIMIT) {
            Err(_) => {
                hangs.push(label);
                break;
            }
            Ok(Err(_)) => panics.push(label),
            Ok(Ok(Ok(()))) => {
                accepted += 1;
                if case.bad {
                    silent.push(label);
                }
            }
            Ok(Ok(Err(msg))) => {
                errors += 1;
                let (origin, file_line) = located(&msg, form);
                at_origin += origin as usize;
                if !(origin || file_line) {
                    vague.push(format!("{label}: {msg}"));
                }
            }
        }
    }
    std::panic::set_hook(hook);
    let changed = fingerprint() != before;
    let located_pct = 100.0 * (errors - vague.len()) as f64 / errors.max(1) as f64;
    println!(
        "fuzz overrides: {CI_CASES} cases in {:.1} s: {} panics, {} hangs, {} silent acceptances, inputs changed: {}; {accepted} accepted, {errors} errors: {located_pct:.1} % name where the override was written or a file, line and field ({:.1} % the override's own place)",
        wall.elapsed().as_secs_f64(),
        panics.len(),
        hangs.len(),
        silent.len(),
        if changed { "YES" } else { "0" },
        100.0 * at_origin as f64 / errors.max(1) as f64
    );
    for (what, l) in [
        ("panic", &panics),
        ("hang", &hangs),
        ("silent", &silent),
        ("vague", &vague),
    ] {
        for x in l {
            println!("  {what}: {x}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(panics.is_empty() && hangs.is_empty() && !changed);
    assert!(silent.is_empty(), "silently accepted: {silent:#?}");
    assert!(located_pct >= 98.0, "vague errors: {vague:#?}");
}
