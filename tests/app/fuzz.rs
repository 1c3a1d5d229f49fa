//! The fuzz harness (issue 20): a mutation driver over the shipped inputs. A copy of
//! `scenes/`, `vehicles/`, `roads/`, `flex/` and one measurement is mutated one edit at
//! a time (a value replaced by NaN, 1e300, 0, a string..., a line deleted or doubled, the
//! file cut short, a CSV cell spoilt) and read, built and run as the command line would.
//! A case fails on a panic, on a case still busy after its time limit (a hang), on
//! success with input known to be bad (a non-finite or absurd number, a duplicate TOML
//! key, a number that is text), and on an error that does not name its file and field.
//!
//! In CI: `fuzz_bounded` ([`CI_CASES`] cases, figures printed). Locally, longer:
//! `TOWRIDE_FUZZ_CASES=5000 cargo test --release --test towride -- --ignored fuzz`.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use towride_app::job::Job;
use towride_mbs::input::Loader;
use towride_mbs::progress::Silent;

/// Cases tried in CI.
const CI_CASES: usize = 400;
/// Longest a case may take before it counts as a hang (the machine is shared).
const LIMIT: Duration = Duration::from_secs(60);

/// How a mutated file is exercised: read, built and (when it loads) run briefly.
#[derive(Clone, Copy, Debug)]
enum Use {
    /// The default scene: every vehicle, road, flex and tyre file goes through it.
    Scene,
    /// A mechanism file.
    Mechanism,
    /// A road file (flat, profile or height field).
    Road,
    /// A measurement descriptor and its CSV.
    Measurement,
    /// A sweep file.
    Sweep,
    /// A plan file (and its first case's scene).
    Plan,
}

/// The files mutated, each with the input that reads it.
const TARGETS: &[(&str, &str, Use)] = &[
    ("scenes/default.toml", "scenes/default.toml", Use::Scene),
    (
        "vehicles/fabia_trailer.toml",
        "scenes/default.toml",
        Use::Scene,
    ),
    (
        "vehicles/fabia/body.toml",
        "scenes/default.toml",
        Use::Scene,
    ),
    (
        "vehicles/fabia/front_mcpherson.toml",
        "scenes/default.toml",
        Use::Scene,
    ),
    (
        "vehicles/fabia/rear_twist_beam.toml",
        "scenes/default.toml",
        Use::Scene,
    ),
    (
        "vehicles/fabia/driveline.toml",
        "scenes/default.toml",
        Use::Scene,
    ),
    (
        "vehicles/fabia/hitch.toml",
        "scenes/default.toml",
        Use::Scene,
    ),
    (
        "vehicles/trailer/box_trailer.toml",
        "scenes/default.toml",
        Use::Scene,
    ),
    (
        "vehicles/tyres/car_185_60r14.tir",
        "scenes/default.toml",
        Use::Scene,
    ),
    (
        "vehicles/tyres/trailer_155_80r13.tir",
        "scenes/default.toml",
        Use::Scene,
    ),
    ("roads/ramp_thesis.toml", "scenes/default.toml", Use::Scene),
    // A `simple` vehicle: the van's few numbers and the defaults filling the rest.
    (
        "vehicles/van_air/van.toml",
        "scenes/van_air/bump_50mm.toml",
        Use::Scene,
    ),
    (
        "vehicles/simple_defaults.toml",
        "scenes/van_air/bump_50mm.toml",
        Use::Scene,
    ),
    (
        "flex/hitch_crossbeam.toml",
        "scenes/default.toml",
        Use::Scene,
    ),
    (
        "scenes/examples/pendulum.toml",
        "scenes/examples/pendulum.toml",
        Use::Mechanism,
    ),
    (
        "scenes/examples/elements.toml",
        "scenes/examples/elements.toml",
        Use::Mechanism,
    ),
    (
        "scenes/examples/andrews.toml",
        "scenes/examples/andrews.toml",
        Use::Mechanism,
    ),
    (
        "roads/profile_example.toml",
        "roads/profile_example.toml",
        Use::Road,
    ),
    (
        "roads/profile_example.csv",
        "roads/profile_example.toml",
        Use::Road,
    ),
    (
        "roads/height_field_example.csv",
        "roads/height_field_example.toml",
        Use::Road,
    ),
    (MEASUREMENT_TOML, MEASUREMENT_TOML, Use::Measurement),
    (MEASUREMENT_CSV, MEASUREMENT_TOML, Use::Measurement),
    (
        "scenes/examples/pendulum_sweep.toml",
        "scenes/examples/pendulum_sweep.toml",
        Use::Sweep,
    ),
    (
        "scenes/measurement_plan.toml",
        "scenes/measurement_plan.toml",
        Use::Plan,
    ),
];

const MEASUREMENT_TOML: &str = "measurements/synthetic/bump_25mm_10kmh_200kg_ahead_of_axle.toml";
const MEASUREMENT_CSV: &str = "measurements/synthetic/bump_25mm_10kmh_200kg_ahead_of_axle.csv";

pub(crate) use crate::common::Rng;

/// One mutation: the new text, what was done, and whether the input is certainly bad.
struct Mutation {
    text: String,
    what: String,
    bad: bool,
}

const ABSURD: &[&str] = &["nan", "inf", "-inf", "1e300", "-1e300"];
const ODD: &[&str] = &["0", "-1", "1e-300", "0.5", "7", "\"x\"", "[]"];

fn is_number(v: &str) -> bool {
    let v = v.trim();
    !v.is_empty() && v.parse::<f64>().is_ok()
}

/// The value part of a `key = value` line (TOML or .tir, comments cut), with its span.
fn value_span(line: &str, tir: bool) -> Option<(usize, usize)> {
    let eq = line.find('=')?;
    let key = line[..eq].trim();
    if key.is_empty() || key.starts_with(['#', '$', '[', '{']) || key.contains(' ') {
        return None;
    }
    let rest = &line[eq + 1..];
    let start = eq + 1 + (rest.len() - rest.trim_start().len());
    let cut = if tir { '$' } else { '#' };
    let end = line[start..]
        .find(cut)
        .map_or(line.len(), |c| start + c)
        .min(line.len());
    let end = start + line[start..end].trim_end().len();
    (end > start).then_some((start, end))
}

fn mutate(text: &str, file: &str, rng: &mut Rng) -> Mutation {
    let lines: Vec<&str> = text.lines().collect();
    let join = |ls: &[String]| ls.join("\n") + "\n";
    let owned: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    let csv = file.ends_with(".csv");
    let tir = file.ends_with(".tir");
    match rng.below(10) {
        // Cut the file short.
        0 => {
            let at = rng.below(text.len());
            let at = (0..=at)
                .rev()
                .find(|&i| text.is_char_boundary(i))
                .unwrap_or(0);
            Mutation {
                text: text[..at].to_string(),
                what: format!("cut at byte {at}"),
                bad: false,
            }
        }
        // Delete or double a line.
        1 | 2 => {
            let k = rng.below(lines.len());
            let mut ls = owned.clone();
            let double = rng.below(2) == 0;
            let key_line = !csv && !tir && value_span(lines[k], false).is_some();
            if double {
                ls.insert(k, lines[k].to_string());
            } else {
                ls.remove(k);
            }
            Mutation {
                text: join(&ls),
                what: format!(
                    "line {} {}",
                    k + 1,
                    if double { "doubled" } else { "deleted" }
                ),
                // A TOML key given twice is a syntax error.
                bad: double && key_line,
            }
        }
        // Spoil a CSV cell.
        _ if csv => {
            let rows: Vec<usize> = (0..lines.len())
                .filter(|&i| {
                    lines[i].split(',').count() > 1
                        && is_number(lines[i].split(',').next().unwrap_or(""))
                })
                .collect();
            let k = rows[rng.below(rows.len())];
            let mut cells: Vec<String> = lines[k].split(',').map(String::from).collect();
            let c = rng.below(cells.len());
            let (new, bad) = match rng.below(4) {
                0 => ("1e300".to_string(), true),
                1 => ("abc".to_string(), true),
                // A decimal comma: one more field than the header.
                2 => (cells[c].replacen('.', ",", 1), cells[c].contains('.')),
                _ => ("-1".to_string(), false),
            };
            cells[c] = new.clone();
            let mut ls = owned.clone();
            ls[k] = cells.join(",");
            Mutation {
                text: join(&ls),
                what: format!("line {} cell {} = {new}", k + 1, c + 1),
                bad,
            }
        }
        // Replace a value.
        _ => {
            let spans: Vec<(usize, (usize, usize))> = (0..lines.len())
                .filter_map(|i| value_span(lines[i], tir).map(|s| (i, s)))
                .collect();
            let (k, (a, b)) = spans[rng.below(spans.len())];
            let old = &lines[k][a..b];
            let absurd = rng.below(2) == 0;
            let new = if absurd {
                ABSURD[rng.below(ABSURD.len())]
            } else {
                ODD[rng.below(ODD.len())]
            };
            let mut ls = owned.clone();
            ls[k] = format!("{}{new}{}", &lines[k][..a], &lines[k][b..]);
            // A number made non-finite or absurd is refused by every reader of TOML; a
            // .tir key may be one towride does not read.
            let numeric = is_number(old) || (old.starts_with('[') && !old.contains('"'));
            Mutation {
                text: join(&ls),
                what: format!("line {}: `{old}` -> `{new}`", k + 1),
                bad: absurd && numeric && !tir,
            }
        }
    }
}

/// Reads, builds and briefly runs `entry` as its command would; the error text if any.
fn exercise(root: &Path, entry: &str, how: Use) -> Result<(), String> {
    let path = root.join(entry);
    let s = |e: &dyn std::fmt::Display| e.to_string();
    match how {
        Use::Scene | Use::Mechanism => {
            let mut job = Job::from_file(&path, &Loader::new()).map_err(|e| s(&e))?;
            // Runs are cut to 0.3 s (the default scene's ramp is at 0.07 s).
            job.settings.t_end = job.settings.t_end.min(0.3);
            let r = job.run(&Silent).map_err(|e| s(&e))?;
            // A run the solver stops is a located result, not a crash.
            let _ = r.failure();
            Ok(())
        }
        Use::Road => towride_mbs::road::Road::from_file(&path, &Loader::new())
            .map(|_| ())
            .map_err(|e| s(&e)),
        Use::Measurement => {
            let d = towride_app::validate::Descriptor::from_file(&path).map_err(|e| s(&e))?;
            towride_app::validate::csv_reader::read_measurement(&d)
                .map(|_| ())
                .map_err(|e| s(&e))
        }
        Use::Sweep => towride_app::sweep::Sweep::load(&path)
            .map(|_| ())
            .map_err(|e| s(&e)),
        Use::Plan => {
            let p = towride_app::scene::plan::load(&path).map_err(|e| s(&e))?;
            p.scene(&p.cases[0], &Loader::new())
                .map(|_| ())
                .map_err(|e| s(&e))
        }
    }
}

pub(crate) use crate::common::located;

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let p = e.path();
        if p.is_dir() {
            copy_dir(&p, &to.join(e.file_name()));
        } else {
            std::fs::copy(&p, to.join(e.file_name())).unwrap();
        }
    }
}

/// The harness's figures.
#[derive(Debug, Default)]
struct Figures {
    cases: usize,
    panics: Vec<String>,
    hangs: Vec<String>,
    silent: Vec<String>,
    errors: usize,
    with_file_line: usize,
    with_field: usize,
    unlocated: Vec<String>,
    /// Models read but without a static equilibrium (the statics' message).
    no_equilibrium: Vec<String>,
    accepted: usize,
    wall_s: f64,
}

fn fuzz(cases: usize, seed: u64) -> Figures {
    let repo = Path::new(repo!(""));
    let root: PathBuf =
        std::env::temp_dir().join(format!("towride-fuzz-{seed}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    for d in ["scenes", "vehicles", "roads", "flex"] {
        copy_dir(&repo.join(d), &root.join(d));
    }
    std::fs::create_dir_all(root.join("measurements/synthetic")).unwrap();
    for f in [MEASUREMENT_TOML, MEASUREMENT_CSV] {
        std::fs::copy(repo.join(f), root.join(f)).unwrap();
    }
    // Panics are counted, not printed case by case.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let mut fig = Figures::default();
    let mut rng = Rng(seed | 1);
    let wall = Instant::now();
    for k in 0..cases {
        let (file, entry, how) = TARGETS[k % TARGETS.len()];
        let original = std::fs::read_to_string(root.join(file)).unwrap();
        let m = mutate(&original, file, &mut rng);
        std::fs::write(root.join(file), &m.text).unwrap();
        let label = format!("case {k}: {file} {}", m.what);
        let (tx, rx) = mpsc::channel();
        let r = root.clone();
        std::thread::spawn(move || {
            let out = std::panic::catch_unwind(|| exercise(&r, entry, how));
            let _ = tx.send(out);
        });
        fig.cases += 1;
        match rx.recv_timeout(LIMIT) {
            Err(_) => {
                // Left running; the harness fails. Its file stays mutated for it.
                fig.hangs.push(label);
                break;
            }
            Ok(Err(_)) => fig.panics.push(label),
            Ok(Ok(Ok(()))) => {
                fig.accepted += 1;
                if m.bad {
                    fig.silent.push(label);
                }
            }
            // A model that reads but has no equilibrium near its start (a tyre moment no
            // spring balances) is the physics' verdict, as a run the solver stops is: it
            // names the equation, not a file line. Counted apart, and only for values
            // not certainly bad (those must be refused at their line).
            Ok(Ok(Err(msg))) if !m.bad && msg.contains("static equilibrium") => {
                fig.no_equilibrium.push(format!("{label}: {msg}"));
            }
            Ok(Ok(Err(msg))) => {
                fig.errors += 1;
                let (fl, field) = located(&msg);
                fig.with_file_line += fl as usize;
                fig.with_field += field as usize;
                if !(fl && field) {
                    fig.unlocated.push(format!("{label}: {msg}"));
                }
            }
        }
        std::fs::write(root.join(file), &original).unwrap();
    }
    fig.wall_s = wall.elapsed().as_secs_f64();
    std::panic::set_hook(hook);
    if fig.hangs.is_empty() {
        let _ = std::fs::remove_dir_all(&root);
    }
    fig
}

fn report(f: &Figures) {
    let pct = |n: usize| 100.0 * n as f64 / f.errors.max(1) as f64;
    println!(
        "fuzz: {} cases in {:.1} s: {} panics, {} hangs, {} silent acceptances; {} accepted, \
         {} without static equilibrium, {} errors: {:.1} % name file and line, {:.1} % name \
         the field",
        f.cases,
        f.wall_s,
        f.panics.len(),
        f.hangs.len(),
        f.silent.len(),
        f.accepted,
        f.no_equilibrium.len(),
        f.errors,
        pct(f.with_file_line),
        pct(f.with_field)
    );
    for (what, list) in [
        ("panic", &f.panics),
        ("hang", &f.hangs),
        ("silently accepted", &f.silent),
        ("unlocated", &f.unlocated),
        ("no static equilibrium", &f.no_equilibrium),
    ] {
        for l in list {
            println!("  {what}: {l}");
        }
    }
}

fn check(f: &Figures) {
    report(f);
    assert!(f.panics.is_empty(), "panics: {:?}", f.panics);
    assert!(f.hangs.is_empty(), "hangs: {:?}", f.hangs);
    assert!(f.silent.is_empty(), "silently accepted: {:?}", f.silent);
    assert!(
        f.unlocated.is_empty(),
        "errors without file, line or field: {:#?}",
        f.unlocated
    );
}

#[test]
fn fuzz_bounded() {
    check(&fuzz(CI_CASES, 20));
}

#[test]
#[ignore = "long: run with -- --ignored fuzz"]
fn fuzz_long() {
    let n = std::env::var("TOWRIDE_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2000);
    let seed = std::env::var("TOWRIDE_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    check(&fuzz(n, seed));
}
