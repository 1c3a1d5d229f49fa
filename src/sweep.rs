//! `towride sweep SWEEP.toml [--jobs N] [--shard I/N] [--resume] [--keep-histories]
//! [--set FILE:PATH=VALUE] [--overrides FILE]` and `towride sweep merge`.

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use towride_app::sweep::exec::{merge, run_sweep_with, Options};
use towride_app::sweep::{parse_shard, Sweep};

use crate::CliResult;

#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepArgs {
    #[command(subcommand)]
    cmd: Option<SweepCmd>,
    /// The sweep file (TOML).
    #[arg(required = true)]
    file: Option<PathBuf>,
    /// Parallel cases (default: all cores).
    #[arg(long, value_parser = crate::bounded::jobs)]
    jobs: Option<usize>,
    /// Run only the cases with index mod N = I (0 <= I < N), for job arrays.
    #[arg(long)]
    shard: Option<String>,
    /// Output folder for summary.csv, summary.json, report.html, report.png (and cases/).
    #[arg(long, default_value = "out/sweep")]
    out: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
    /// Keep the cases an earlier, interrupted run of this sweep (and shard) left in
    /// --out (its summary or journal) and run only the others.
    #[arg(long)]
    resume: bool,
    /// Keep each case's outputs.csv, summary.json and report.html in
    /// OUT/cases/<case id>/ (linked from the sweep's report.html).
    #[arg(long)]
    keep_histories: bool,
    /// Give every case a convergence verdict: run it again at rtol and atol ten times
    /// tighter (twice the time) and record `converged [-]`, the worst difference [%] and
    /// the count of unconverged channels as figures (see `run --check`).
    #[arg(long)]
    check: bool,
    /// With --check: the relative difference a converged channel may show [%] (default 2).
    #[arg(long, requires = "check", value_parser = crate::bounded::share_pct)]
    check_threshold: Option<f64>,
    /// Leave the file's `[robustness]` block out: run and rank the grid alone (the block
    /// re-runs part of the grid once per moved value and end, many times its cost).
    #[arg(long)]
    no_robustness: bool,
    #[command(flatten)]
    inputs: crate::inputs::InputArgs,
}

#[derive(Subcommand, Debug)]
enum SweepCmd {
    /// Join shard summaries into one table ordered by case.
    Merge {
        /// Shard summary CSV files.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// The merged table.
        #[arg(long, default_value = "out/sweep/summary.csv")]
        out: PathBuf,
        /// Print what was merged as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Rank the values of one swept parameter (the crossbeam variants) by each figure of
    /// a summary, over the band the other parameters span: mean, smallest and largest,
    /// rank by the mean (lowest first), the best value per figure.
    Rank {
        /// A sweep's (or merge's) summary CSV.
        summary: PathBuf,
        /// The parameter whose values are ranked.
        #[arg(long, default_value = "hitch_variant")]
        by: String,
        /// Only these figures (names as in the summary, with or without the unit);
        /// default: every figure but solver effort and verdicts.
        #[arg(long, value_delimiter = ',')]
        figures: Vec<String>,
        /// Folder for ranking.csv, ranking.json and ranking.png (default: the summary's).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print the ranking as JSON.
        #[arg(long)]
        json: bool,
    },
}

/// `sweep rank`: the ranking table on the console, its files beside the summary.
fn rank(summary: &Path, by: &str, figures: &[String], out: Option<&Path>, json: bool) -> CliResult {
    let t = towride_app::sweep::page::read(summary)?;
    let r = towride_app::sweep::rank::rank(&t, by, figures)
        .map_err(|e| format!("{}: {e}", summary.display()))?;
    let dir = out.unwrap_or_else(|| summary.parent().unwrap_or(Path::new(".")));
    let files = towride_app::sweep::rank::write(&r, dir)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&r)?);
        return Ok(0);
    }
    println!(
        "{} ranked by {} over {} (mean, [smallest, largest]; 1 = lowest mean):",
        summary.display(),
        r.by,
        r.over.join(", ")
    );
    for f in &r.figures {
        println!(
            "  {}: best {} {}; spread over the band up to {:.0} % of the mean",
            f.figure,
            r.by,
            f.best,
            100.0 * f.largest_spread
        );
        for e in &f.entries {
            let note = match (e.missing, e.unconverged) {
                (0, 0) => String::new(),
                (m, u) => format!("  ({m} without a result, {u} not converged)"),
            };
            println!(
                "    {:>3}. {} {:<6} {:>12.5e} [{:.5e}, {:.5e}]{note}",
                e.rank, r.by, e.value, e.mean, e.min, e.max
            );
        }
    }
    if r.rankings_disagree {
        println!("the figures do not all rank the same {} first", r.by);
    }
    println!(
        "files: {}, {}, {}",
        files.csv.display(),
        files.json.display(),
        files.png.display()
    );
    Ok(0)
}

/// The ranking's robustness: per perturbation and figure, tau-b and the best value.
fn print_robustness(r: &towride_app::sweep::robust_run::RobustnessRun) {
    let b = &r.block;
    println!(
        "robustness of the {} ranking ({}, {} cases per run, {:.1} s):",
        b.by, r.status, r.cases_per_run, r.wall_s
    );
    if let Some(n) = &r.note {
        println!("  {n}");
    }
    if let Some(nom) = &r.nominal {
        for f in &nom.figures {
            println!("  {}: nominal best {} {}", f.figure, b.by, f.best);
        }
    }
    for p in &r.perturbations {
        println!(
            "  {} x {:.3} ({}, {}){}",
            p.parameter,
            p.factor,
            p.end,
            p.class,
            p.note
                .as_deref()
                .map_or(String::new(), |n| format!(": {n}"))
        );
        for o in &p.outcomes {
            let held = match (o.stays_best, o.within_spread) {
                (true, _) => "stays best".to_string(),
                (false, w) => format!(
                    "nominal best {} now rank {}{}",
                    o.nominal_best,
                    o.nominal_best_rank,
                    if w { ", within the spread" } else { "" }
                ),
            };
            let tau = o.tau_b.map_or("-".to_string(), |t| format!("{t:+.3}"));
            println!("    {}: tau_b {tau}, best {}; {held}", o.figure, o.best);
        }
    }
}

pub fn run(a: &SweepArgs) -> CliResult {
    if let Some(SweepCmd::Rank {
        summary,
        by,
        figures,
        out,
        json,
    }) = &a.cmd
    {
        return rank(summary, by, figures, out.as_deref(), *json);
    }
    if let Some(SweepCmd::Merge { inputs, out, json }) = &a.cmd {
        let m = merge(inputs, out)?;
        if *json {
            println!("{}", serde_json::to_string_pretty(&m)?);
        } else {
            println!(
                "{} cases of {} merged into {}; page {}",
                m.cases,
                m.sweep,
                out.display(),
                m.report.as_deref().unwrap_or("-")
            );
        }
        return Ok(0);
    }
    let file = a.file.as_ref().ok_or("a sweep file is required")?;
    let mut sweep = Sweep::load(file)?;
    if a.no_robustness {
        sweep.robustness = None;
    }
    // The command line's overrides reach every case, under the case's own values.
    sweep.base = a.inputs.loader()?;
    sweep.produced_by = crate::inputs::stamp(&Default::default());
    let shard = match &a.shard {
        Some(s) => parse_shard(s)?,
        None => (0, 1),
    };
    let jobs = a
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pb = crate::progress(0, a.json);
    crate::interrupt::install();
    let opts = Options {
        jobs,
        resume: a.resume,
        keep_histories: a.keep_histories,
        check: a.check.then(|| {
            a.check_threshold
                .map_or(towride_app::job::convergence::DEFAULT_THRESHOLD, |p| {
                    p / 100.0
                })
        }),
    };
    let res = run_sweep_with(&sweep, shard, &a.out, &opts, &pb)?;
    let csv_path = res.summary_csv.clone().unwrap_or_default();
    if a.json {
        println!("{}", serde_json::to_string_pretty(&res)?);
    } else {
        println!(
            "{}: {} cases ({} failed, {} interrupted, {} kept from before) on {jobs} threads in {:.2} s; summary in {csv_path}; page {}",
            sweep.name,
            res.cases,
            res.failed,
            res.interrupted,
            res.resumed,
            res.wall_s,
            res.report.as_deref().unwrap_or("-"),
        );
        // Damage per km of the file's usage spectrum, per group and stress point.
        for u in res.usage.iter().flatten() {
            let g: Vec<String> = u.group.iter().map(|(k, v)| format!("{k}={v}")).collect();
            match (u.damage_per_km, u.km_to_allowable) {
                (Some(d), Some(km)) => println!(
                    "  usage {}: {} -> {d:.3e} per km, {km:.3e} km to D = 0.5",
                    g.join(" "),
                    u.figure
                ),
                _ => println!(
                    "  usage {}: {} -> a case of the mix has no result",
                    g.join(" "),
                    u.figure
                ),
            }
        }
        if let Some(r) = &res.robustness {
            print_robustness(r);
        }
        for r in res.rows.iter().filter(|r| r.status == "failed") {
            eprintln!(
                "  case {} {:?}: {}",
                r.index,
                r.values,
                r.error.as_deref().unwrap_or("")
            );
        }
    }
    let robust_cut = res
        .robustness
        .as_ref()
        .is_some_and(|r| r.status == "interrupted");
    if res.interrupted > 0 || robust_cut {
        let what = if res.interrupted > 0 {
            format!("{} cases not finished", res.interrupted)
        } else {
            "the robustness runs not finished".to_string()
        };
        eprintln!(
            "interrupted: {what}; `towride sweep {} --resume` runs them",
            file.display()
        );
        return Ok(crate::interrupt::EXIT);
    }
    Ok(if res.failed == 0 { 0 } else { 1 })
}
