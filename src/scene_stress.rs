//! `towride stress SCENE`: the thesis's integrator-settings matrix and worse
//! (`towride_app::study::stress`), printed case by case.

use std::path::PathBuf;

use clap::Args;

use towride_app::study::stress;

use crate::CliResult;

#[derive(Args, Debug)]
pub struct StressArgs {
    /// The scene file (the default scene's vehicle and road files are varied).
    pub scene: PathBuf,
    /// Parallel runs.
    #[arg(long, value_parser = crate::bounded::jobs)]
    pub jobs: Option<usize>,
    /// Only the cases whose group contains this text.
    #[arg(long)]
    pub only: Option<String>,
    /// Integration method of the cases (default: the scene's); the reference keeps the
    /// scene's.
    #[arg(long, value_enum)]
    pub method: Option<crate::MethodArg>,
    #[arg(long, default_value = "out/stress")]
    pub out: PathBuf,
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub inputs: crate::inputs::InputArgs,
}

/// The |peak| against the reference's: an error for a same-physics case (`+0.12 % err`),
/// for a case that changes the physics (speed, load, obstacle) a ratio marked as such
/// (`2.72x of ref`), as it compares two different experiments. Magnitudes over
/// magnitudes: a larger push than the reference's pull reads as larger, not negative.
fn change(o: &stress::Outcome) -> String {
    if !o.abs_peak_ratio.is_finite() {
        format!("{:>13}", "")
    } else if o.same_physics {
        format!("{:>+8.2} % err", 100.0 * (o.abs_peak_ratio - 1.0))
    } else {
        format!("{:>6.2}x of ref", o.abs_peak_ratio)
    }
}

pub fn run_stress(a: &StressArgs) -> CliResult {
    let jobs = a
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    towride_app::atomic::claim(
        &a.out,
        "stress",
        &["stress.json"],
        std::slice::from_ref(&a.scene),
    )?;
    let loader = a.inputs.loader()?;
    crate::interrupt::install();
    let pb = crate::progress(0, a.json);
    let st = match stress::run(
        &a.scene,
        &loader,
        a.only.as_deref(),
        a.method.map(Into::into),
        jobs,
        &pb,
    ) {
        Err(_) if crate::interrupt::requested() => {
            eprintln!("interrupted during the reference run: no case ran, nothing written");
            return Ok(crate::interrupt::EXIT);
        }
        other => other?,
    };
    let path = st.write(&a.out)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&st)?);
    } else {
        println!(
            "reference: hitch_fx max {:.1} N, min {:.1} N, |peak| {:.1} N ({:.2} s wall)",
            st.reference.hitch_max_n,
            st.reference.hitch_min_n,
            st.reference.hitch_abs_peak_n,
            st.reference.wall_s
        );
        for o in &st.outcomes {
            println!(
                "{:<18} {:<46} {:<10} max {:>8.1} min {:>9.1} |peak| {:>8.1} N  {}  {:>6} steps {:>6.2} s {}",
                o.group,
                o.case,
                if o.status == "completed" {
                    "completed"
                } else if towride_app::study::stopped(&o.status) {
                    "STOPPED"
                } else {
                    "FAILED"
                },
                o.hitch_max_n,
                o.hitch_min_n,
                o.hitch_abs_peak_n,
                change(o),
                o.steps,
                o.wall_s,
                match o.agrees {
                    Some(true) => "agrees",
                    Some(false) => "DEVIATES",
                    None => "",
                }
            );
            if o.status != "completed" {
                println!("    {}", o.status);
            }
        }
        println!(
            "{} of {} completed; {} same-physics case(s) with |peak| off by more than 2 % or on the other side; wrote {}",
            st.completed,
            st.cases,
            st.same_physics_disagreeing,
            path.display()
        );
    }
    if st.interrupted > 0 {
        eprintln!(
            "interrupted: {} of {} cases not run or stopped (labelled in {}); run the study again for them",
            st.interrupted,
            st.cases,
            path.display()
        );
        return Ok(crate::interrupt::EXIT);
    }
    Ok(if st.passed() { 0 } else { 1 })
}
