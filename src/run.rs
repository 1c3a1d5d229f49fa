//! `towride run FILE`: integrate a mechanism file, a scene or a plan's cases and write
//! the outputs (`outputs.csv`, `summary.json`, a scene's plot page).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use clap::Args;

use towride_app::job::{convergence, ChannelSummary, Job, RunResult, RunStatus, Signal};
use towride_app::report::plan_run::PlanRun;
use towride_app::scene::plan;
use towride_app::scene::{self, channels, Changes, SceneError};
use towride_mbs::flex::feedback::RunModes;
use towride_mbs::input::Loader;

use crate::CliResult;

#[derive(Args, Debug)]
pub struct RunArgs {
    /// A mechanism file, a scene (`[scene]`) or a plan (`[plan]`), TOML.
    pub(crate) file: PathBuf,
    /// Output folder for outputs.csv and summary.json (a plan: one folder per case).
    #[arg(long, default_value = "out")]
    pub(crate) out: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    pub(crate) json: bool,
    /// Plans: run only these cases (comma-separated names; `--list` shows them).
    #[arg(long, value_delimiter = ',')]
    pub(crate) case: Vec<String>,
    /// Plans: list the cases and stop.
    #[arg(long)]
    pub(crate) list: bool,
    #[command(flatten)]
    pub(crate) inputs: crate::inputs::InputArgs,
    /// Scenes: list what `[[output]]` tables can ask for (named quantities, bodies,
    /// markers, joints, elements) and stop.
    #[arg(long)]
    pub(crate) list_names: bool,
    /// Scenes: pose rate of the report's 3D view [Hz], replacing `[report]
    /// animation_rate_hz` (default 200); 0 switches the view off.
    #[arg(long, value_name = "HZ", value_parser = crate::bounded::hz)]
    pub(crate) animation_rate_hz: Option<f64>,
    /// Select the modal bodies' modes from this earlier run's strain-energy shares (its
    /// folder, holding summary.json) instead of their files' rules.
    #[arg(long, value_name = "RUN_DIR")]
    pub(crate) modes_from: Option<PathBuf>,
    /// With --modes-from: the strain-energy share a mode needs [%] (default 1).
    #[arg(long, requires = "modes_from", value_parser = crate::bounded::share_pct)]
    pub(crate) modes_share: Option<f64>,
    /// Check convergence: run the job again at rtol and atol ten times tighter and judge
    /// every reported channel's max, min and RMS (band-limited where the scene has an
    /// acquisition chain) against it; the verdict goes into summary.json and the report.
    #[arg(long)]
    pub(crate) check: bool,
    /// With --check: the relative difference a converged channel may show [%] (default 2).
    #[arg(long, requires = "check", value_parser = crate::bounded::share_pct)]
    pub(crate) check_threshold: Option<f64>,
    /// Output formats: `csv` (outputs.csv, always written: the run page and `compare`
    /// read it) and `mf4` (outputs.mf4 as well, ASAM MDF4); comma-separated.
    #[arg(long, value_delimiter = ',', value_enum, default_value = "csv")]
    pub(crate) format: Vec<OutFormat>,
    /// Plans: cases run at once (default: the machine's cores).
    #[arg(long, value_parser = crate::bounded::jobs)]
    pub(crate) jobs: Option<usize>,
}

/// A format `run` writes its samples in.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutFormat {
    /// outputs.csv
    Csv,
    /// outputs.mf4 (ASAM MDF4)
    Mf4,
}

pub fn run(a: &RunArgs) -> CliResult {
    let loader = a.inputs.loader()?;
    let at = towride_mbs::input::InputError {
        file: "command line".into(),
        line: None,
        column: None,
        field: "--modes-from".into(),
        message: String::new(),
        kind: Default::default(),
    };
    let run_modes = match &a.modes_from {
        // Modal bodies with modes to select are a vehicle's: a mechanism file has none.
        Some(_) if !scene::is_scene(&a.file) && !plan::is_plan(&a.file) => {
            return Err(towride_mbs::input::InputError {
                message: format!(
                    "{} is a mechanism file: --modes-from selects the modes of a scene's modal bodies",
                    a.file.display()
                ),
                ..at
            }
            .into());
        }
        Some(dir) => {
            let share = a.modes_share.map_or(0.01, |p| p / 100.0);
            Some(Arc::new(towride_mbs::flex::feedback::from_run(
                dir, share, &at,
            )?))
        }
        None => None,
    };
    if a.list_names {
        return list_names(a, &loader, run_modes);
    }
    let check = Check::of(a);
    let mf4 = a.format.contains(&OutFormat::Mf4);
    if !plan::is_plan(&a.file) {
        // Plan-only options would change nothing here: say so rather than ignore them.
        let plan_only = [
            (!a.case.is_empty(), "--case"),
            (a.list, "--list"),
            (a.jobs.is_some(), "--jobs"),
        ];
        if let Some((_, flag)) = plan_only.iter().find(|(given, _)| *given) {
            return Err(towride_mbs::input::InputError {
                field: flag.to_string(),
                message: format!(
                    "{flag} chooses among a plan's cases; {} is not a plan (no [plan] table)",
                    a.file.display()
                ),
                ..at
            }
            .into());
        }
        let build = || -> Result<Job, Box<dyn std::error::Error>> {
            let mut job = if scene::is_scene(&a.file) {
                let changes = Changes {
                    animation_rate_hz: a.animation_rate_hz,
                    run_modes: run_modes.clone(),
                    ..Changes::default()
                };
                Job::from_scene_file(&a.file, &changes, &loader)?
            } else {
                let mut job = Job::from_file(&a.file, &loader)?;
                if let Some(r) = a.animation_rate_hz {
                    job.settings.animation_rate = r;
                }
                job
            };
            job.produced_by = crate::inputs::stamp(&job.produced_by);
            Ok(job)
        };
        let job = build()?;
        claim_out(&a.out, &a.file, &a.inputs, &loader)
            .map_err(|e| -> Box<dyn std::error::Error> { e })?;
        let companion = match check {
            Some(_) => Some(build()?.tightened(convergence::TIGHTEN)),
            None => None,
        };
        crate::interrupt::install();
        let res = run_job(&job, companion.as_ref().zip(check), &a.out, a.json, mf4)
            .map_err(|e| -> Box<dyn std::error::Error> { e })?;
        if a.json && job.scene.is_some() {
            // The summary plus the assumed inputs, as the text output lists them.
            // Plain data: serialisation cannot fail.
            let mut v = serde_json::to_value(&res.summary).unwrap_or_default();
            v["assumed_inputs"] = serde_json::to_value(assumed(&a.file)).unwrap_or_default();
            println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default());
        } else if a.json {
            println!("{}", res.summary.to_json());
        } else if job.scene.is_some() {
            print_assumed(&a.file);
        }
        return Ok(exit_code(&res, &a.out));
    }
    let p = plan::load(&a.file)?;
    if a.list {
        for c in &p.cases {
            println!("{}", c.name);
        }
        return Ok(0);
    }
    for name in &a.case {
        if p.case(name).is_none() {
            return Err(SceneError::NoSuchCase(format!(
                "{}: no case '{name}' (--list shows them)",
                a.file.display()
            ))
            .into());
        }
    }
    crate::interrupt::install();
    let cases: Vec<_> = p
        .cases
        .iter()
        .filter(|c| a.case.is_empty() || a.case.contains(&c.name))
        .collect();
    let jobs = a
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    // Cases run in parallel as a sweep's do; each writes its own folder, and the console
    // lists them afterwards in the plan's order, as a one-at-a-time run would.
    let run_case = |c: &plan::Case, quiet: bool| -> Result<Option<RunResult>, DynError> {
        let out = a.out.join(&c.name);
        if crate::interrupt::requested() {
            return Ok(None);
        }
        let mut changes = c.changes.clone();
        changes.run_modes.clone_from(&run_modes);
        let build = || -> Result<Job, DynError> {
            let mut job = Job::from_scene(scene::load_with(&c.scene, &changes, &loader)?)?;
            if let Some(r) = a.animation_rate_hz {
                job.settings.animation_rate = r;
            }
            job.produced_by = crate::inputs::stamp(&job.produced_by);
            Ok(job)
        };
        let go = || -> Result<RunResult, DynError> {
            let job = build()?;
            claim_out(&out, &c.scene, &a.inputs, &loader)?;
            let companion = match check {
                Some(_) => Some(build()?.tightened(convergence::TIGHTEN)),
                None => None,
            };
            run_job(
                &job,
                companion.as_ref().zip(check),
                &out,
                a.json || quiet,
                mf4,
            )
        };
        go().map(Some)
    };
    let results: Vec<Result<Option<RunResult>, DynError>> = if jobs > 1 && cases.len() > 1 {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(jobs)
            .build()
            .map_err(|e| format!("thread pool: {e}"))?;
        let bar = crate::progress(cases.len() as u64, a.json);
        let res: Vec<Result<Option<RunResult>, DynError>> = pool.install(|| {
            use rayon::prelude::*;
            cases
                .par_iter()
                .map(|c| {
                    let r = run_case(c, true);
                    bar.0.inc(1);
                    r
                })
                .collect()
        });
        bar.0.finish_and_clear();
        if !a.json {
            for r in res.iter().flatten().flatten() {
                print_summary(r);
            }
        }
        res
    } else {
        cases.iter().map(|c| run_case(c, false)).collect()
    };
    let mut code = 0;
    let mut table = PlanRun::new(&p, &a.file);
    let results_len = results.len();
    let started = results.iter().filter(|r| !matches!(r, Ok(None))).count();
    for (c, r) in cases.iter().zip(results) {
        let out = a.out.join(&c.name);
        let res = r.map_err(|e| -> Box<dyn std::error::Error> { e })?;
        if let Some(res) = &res {
            code = code.max(exit_code(res, &out));
        }
        table.push(c, &out, res.as_ref());
    }
    // Cases never started because of an interruption: the plan did not complete.
    let not_run = results_len - started;
    if crate::interrupt::requested() && not_run > 0 {
        eprintln!(
            "interrupted: {not_run} of {} cases not run (their rows say so); run the plan again with --case to finish them",
            cases.len()
        );
        code = code.max(crate::interrupt::EXIT);
    }
    let csv = table.write(&a.out)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&table)?);
    } else {
        println!("plan summary: {}", csv.display());
    }
    Ok(code)
}

/// Prints what a scene's `[[output]]` tables can name.
fn list_names(a: &RunArgs, loader: &Loader, run_modes: Option<Arc<RunModes>>) -> CliResult {
    if !scene::is_scene(&a.file) || plan::is_plan(&a.file) {
        return Err(SceneError::Plan {
            file: a.file.clone(),
            message: "--list-names needs a scene file (with [scene])".into(),
        }
        .into());
    }
    let changes = Changes {
        run_modes,
        ..Changes::default()
    };
    let s = scene::load_with(&a.file, &changes, loader)?;
    let n = &s.names;
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(n).expect("names serialise")
        );
        return Ok(0);
    }
    println!("named quantities ([[output]] quantity = \"...\"):");
    for q in &n.quantities {
        println!("  {:<26} {:<9} {}", q.name, format!("[{}]", q.unit), q.what);
    }
    println!("fixed channels (always written):");
    for c in &n.fixed_channels {
        println!("  {:<26} [{}]", c.name, c.unit);
    }
    let list = |title: &str, items: Vec<String>| {
        println!("{title}:");
        for i in items {
            println!("  {i}");
        }
    };
    list("bodies (centre of mass marker <body>.cm)", n.bodies.clone());
    list(
        "markers (marker = ...; position, velocity, acceleration, angular_velocity, angular_acceleration)",
        n.markers.clone(),
    );
    list(
        "joints (joint = ...; force, torque, displacement)",
        n.joints.clone(),
    );
    list(
        "elements (element = ...; force, deflection, velocity)",
        n.elements
            .iter()
            .map(|(e, k)| format!("{e:<26} {k}"))
            .collect(),
    );
    Ok(0)
}

/// What a run writes into its folder.
const RUN_FILES: [&str; 5] = [
    "outputs.csv",
    "summary.json",
    "report.html",
    "plots.png",
    "overrides.toml",
];

/// Refuses an output folder holding another command's results, or one of whose files
/// the run reads (an `--overrides out/overrides.toml` would be rewritten as it is read).
fn claim_out(
    out: &Path,
    file: &Path,
    inputs: &crate::inputs::InputArgs,
    loader: &Loader,
) -> Result<(), DynError> {
    let mut read = loader.files_read();
    read.push(file.to_path_buf());
    read.extend(inputs.overrides.clone());
    towride_app::atomic::claim(out, "run", &RUN_FILES, &read).map_err(|e| e.into())
}

/// An error a plan's case may end with, on any thread.
type DynError = Box<dyn std::error::Error + Send + Sync>;

/// `--check`: its relative threshold.
#[derive(Clone, Copy, Debug)]
struct Check {
    threshold: f64,
}

impl Check {
    fn of(a: &RunArgs) -> Option<Check> {
        a.check.then(|| Check {
            threshold: a
                .check_threshold
                .map_or(convergence::DEFAULT_THRESHOLD, |p| p / 100.0),
        })
    }
}

/// Runs one job (and its companion at a tighter tolerance for a convergence check),
/// writes its files and, without `--json`, prints its summary.
fn run_job(
    job: &Job,
    check: Option<(&Job, Check)>,
    out: &Path,
    json: bool,
    mf4: bool,
) -> Result<RunResult, DynError> {
    if !json {
        for w in &job.warnings {
            eprintln!("warning: {w}");
        }
    }
    let samples = (job.settings.t_end * job.settings.sample_rate).round() as u64;
    let pb = crate::progress(samples, json);
    let mut res = job.run(&pb)?;
    if let Some((companion, c)) = check.filter(|_| !crate::interrupt::requested()) {
        let pb = crate::progress(samples, json);
        let tight = companion.run(&pb)?;
        res.summary.convergence = convergence::verdict(&res, &tight, job.solver.rtol, c.threshold);
        if res.summary.convergence.is_none() && !json {
            eprintln!(
                "warning: no convergence verdict: {}",
                match tight.failure() {
                    Some((e, t)) => format!("the companion run stopped at t = {t:.6} s: {e}"),
                    None => "the run or its companion did not complete".into(),
                }
            );
        }
    }
    towride_app::report::write_run_as(&mut res, &job.system, out, mf4)?;
    if !json {
        print_summary(&res);
    }
    Ok(res)
}

/// 0 completed, 1 stopped by the solver, 130 interrupted (each said on stderr).
fn exit_code(res: &RunResult, out: &Path) -> i32 {
    let csv = out.join("outputs.csv");
    if let Some((e, t)) = res.failure() {
        eprintln!(
            "error: run stopped at t = {t:.6} s: {e}\n  results up to that time are in {}",
            csv.display()
        );
        return 1;
    }
    if let Some(t) = res.summary.interrupted_at_s {
        eprintln!(
            "interrupted at t = {t:.6} s: results up to that time are in {}",
            csv.display()
        );
        return crate::interrupt::EXIT;
    }
    0
}

fn print_summary(r: &RunResult) {
    let s = &r.summary;
    println!(
        "{}: {} in {:.1} s wall, {} steps, {} Newton iterations, {} Jacobians; outputs in {}",
        s.name,
        match s.status {
            RunStatus::Completed => "completed",
            RunStatus::Failed => "FAILED",
            RunStatus::Interrupted => "INTERRUPTED",
        },
        s.wall_s,
        s.solver.steps,
        s.solver.newton_iterations,
        s.solver.jacobian_evals,
        s.outputs_csv.as_deref().unwrap_or("")
    );
    if let Some(d) = s.durability.first() {
        // One line per group: ball forces, bracket loads, crossbeam stresses
        // (docs/durability.md).
        println!(
            "  DEL at N_ref {:.0e}, m = {} (rainflow, ASTM E1049):",
            d.n_ref, d.m
        );
        for (label, prefix) in [
            ("ball", "hitch_f"),
            ("brackets", "hitch_bracket_"),
            ("stress", "hitch_stress_"),
        ] {
            let dels: Vec<String> = s
                .durability
                .iter()
                .filter(|d| d.channel.starts_with(prefix))
                .map(|d| format!("{} {:.3e} {}", d.channel, d.del_at_n_ref, d.unit))
                .collect();
            if !dels.is_empty() {
                println!("    {label}: {}", dels.join(", "));
            }
        }
    }
    if let Some(c) = &s.comfort {
        // One line: ISO 2631-1 at the driver's floor point (docs/comfort.md).
        comfort_line("driver's floor", c);
    }
    if let Some(c) = &s.comfort_seat {
        // And at the seat surface when the body file gives a seat.
        comfort_line(
            &format!(
                "driver's seat surface, seat resonance {:.2} Hz, |T| {:.2}",
                c.resonance_hz, c.peak_transmissibility
            ),
            &c.comfort,
        );
    }
    for l in &s.lift_off {
        println!(
            "  wheel {} off the road from {:.3} s for {:.3} s",
            l.wheel, l.start_s, l.duration_s
        );
    }
    if let Some(p) = s.plots.as_deref().filter(|p| p.starts_with("not written")) {
        eprintln!("warning: plots {p}");
    }
    if let Some(a) = &s.acquisition {
        println!(
            "  raw channels as computed; <channel>{} through the scene's acquisition chain ({}, on a {} Hz grid): accelerometers listed band-limited first, as the instrument saw them, forces and deflections raw first",
            a.suffix, a.description, a.grid_rate_hz
        );
    }
    let verdict = s.convergence.as_ref();
    let line = |name: &str, c: &ChannelSummary| {
        let e = &c.extremes;
        // A channel the convergence check judged and failed says so where its number is.
        let flag = verdict
            .and_then(|v| v.channels.get(name))
            .filter(|k| !k.converged)
            .map_or(String::new(), |k| {
                format!(
                    "  NOT CONVERGED (max {:.1} %, min {:.1} %, RMS {:.1} %)",
                    100.0 * k.max_diff,
                    100.0 * k.min_diff,
                    100.0 * k.rms_diff
                )
            });
        println!(
            "  {name:<30} min {:>11.4e} at {:>7.4} s   max {:>11.4e} at {:>7.4} s   |peak| {:>10.4e}  [{}]{flag}",
            e.min, e.t_min, e.max, e.t_max, e.abs_peak, c.unit
        );
    };
    let mut listed: Vec<(&String, &ChannelSummary)> = s
        .channels
        .iter()
        .filter(|(n, c)| !n.starts_with(channels::HITCH_ETA_PREFIX) && c.signal == Signal::Raw)
        .collect();
    // Natural order (`wheel_2` before `wheel_10`), as every listing of channels.
    towride_app::report::display::sort_natural(&mut listed, |e| e.0.as_str());
    for (name, c) in listed {
        // A raw channel with its band-limited twin: the one shown first as above.
        let twin = c
            .twin
            .as_ref()
            .and_then(|t| s.channels.get(t).map(|b| (t, b)));
        match twin {
            Some((t, b)) if b.shown => {
                line(t, b);
                line(name, c);
            }
            Some((t, b)) => {
                line(name, c);
                line(t, b);
            }
            None => line(name, c),
        }
    }
    if let Some(v) = verdict {
        let judged = v.channels.len() - v.below_floor.len();
        let below = if v.below_floor.is_empty() {
            String::new()
        } else {
            format!(
                "; {} below their floors (round-off, not results): {}",
                v.below_floor.len(),
                v.below_floor.join(", ")
            )
        };
        println!(
            "convergence (--check: rtol {:e} against {:e}, {} steps; max, min and RMS within {} %): {}{below}",
            // Round-off of rtol / 10 (1.0000000000000002e-6) is not a setting: 12 digits.
            short(v.rtol),
            short(v.check_rtol),
            v.check_steps,
            100.0 * v.threshold,
            if v.converged {
                format!("all {judged} judged channels converged")
            } else {
                format!(
                    "{} of {judged} channels NOT converged: {}",
                    v.failing.len(),
                    v.failing.join(", ")
                )
            }
        );
    }
}

/// The assumed values among the ten inputs the scene's key output is most sensitive to,
/// from the scene's latest sensitivity study in its default folder (none is run here).
fn assumed(scene: &Path) -> towride_app::study::sensitivity::assumed::AssumedInputs {
    use towride_app::study::sensitivity::{assumed::assumed_inputs, default_dir};
    assumed_inputs(scene, &default_dir(scene), 10)
}

/// Prints [`assumed`].
fn print_assumed(scene: &Path) {
    let a = assumed(scene);
    if let Some(note) = &a.note {
        println!("assumed inputs: {note}");
        return;
    }
    let output = a.output.as_deref().unwrap_or("the first output");
    if a.inputs.is_empty() {
        println!(
            "assumed inputs: none among the ten {output} is most sensitive to ({})",
            a.study.as_deref().unwrap_or("")
        );
        return;
    }
    println!(
        "assumed or unsourced values among the ten inputs {output} is most sensitive to ({}):",
        a.study.as_deref().unwrap_or("")
    );
    for i in &a.inputs {
        println!(
            "  {:>2}. {:<70} {:.3} {}{}",
            i.rank,
            i.parameter,
            i.sensitivity,
            i.class,
            if i.source.is_empty() {
                String::new()
            } else {
                format!(": {}", i.source)
            }
        );
    }
}

/// `x` rounded to 12 significant digits, so that `{:e}` prints 1e-6, not the round-off
/// of a division.
fn short(x: f64) -> f64 {
    format!("{x:.11e}").parse().unwrap_or(x)
}

/// One console line of a comfort evaluation at `place`.
fn comfort_line(place: &str, c: &towride_app::comfort::PointComfort) {
    let axes: Vec<String> = c
        .axes
        .iter()
        .map(|a| match a.below_resolution {
            true => format!("{} round-off (peak below 0.05 m/s^2)", a.channel),
            false => format!(
                "{} a_w {:.3} m/s^2, VDV {:.3} m/s^1.75, MTVV {:.3} m/s^2",
                a.channel, a.measures.rms_m_s2, a.measures.vdv_m_s1_75, a.measures.mtvv_m_s2
            ),
        })
        .collect();
    println!(
        "  comfort (ISO 2631-1, {place}{}): {}; a_v {}",
        if c.transient {
            ", transient: VDV and MTVV count"
        } else {
            ""
        },
        axes.join("; "),
        c.total_value_m_s2
            .map_or("-".into(), |v| format!("{v:.3} m/s^2"))
    );
}
