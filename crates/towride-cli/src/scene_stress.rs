//! `towride stress SCENE`: the thesis's integrator experiment and worse. Every case is
//! run and classified: completed or failed, and its hitch-force peak against the
//! reference (the scene at rtol 1e-5). Cases that change only numerical settings (step
//! limits, tolerances, modes kept) must agree with it; cases that change the physics
//! (stiffness, masses, obstacle, speed, load) report their peak and how far it moved.

use std::path::PathBuf;

use clap::Args;
use rayon::prelude::*;
use serde::Serialize;
use serde_json::json;

use crate::scene_bench::Reference;
use towride::input::overrides::Override;
use towride::scene::exec::run;
use towride::scene::Overrides;
use towride_solver::SolverOptions;

#[derive(Args, Debug)]
pub struct StressArgs {
    /// The scene file (the default scene's vehicle and road files are varied).
    pub scene: PathBuf,
    /// Parallel runs.
    #[arg(long)]
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
}

/// One stress case.
struct Case {
    group: &'static str,
    label: String,
    /// Only numerical settings change: the result must match the reference.
    same_physics: bool,
    props: Vec<Override>,
    scene: Overrides,
    rtol: Option<f64>,
    h_max: Option<f64>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Outcome {
    pub group: String,
    pub case: String,
    pub status: String,
    pub wall_s: f64,
    pub steps: usize,
    pub hitch_peak_n: f64,
    /// (peak - reference peak) / |reference peak|.
    pub peak_deviation: f64,
    pub hitch_rms_deviation: f64,
    pub same_physics: bool,
    /// Same-physics cases: peak within 2 % of the reference.
    pub agrees: Option<bool>,
}

fn ov(file: &str, path: &str, value: impl std::fmt::Display) -> Override {
    Override {
        file: file.into(),
        path: path.into(),
        value: value.to_string(),
    }
}

fn cases() -> Vec<Case> {
    let base = |group, label: String, same: bool| Case {
        group,
        label,
        same_physics: same,
        props: vec![],
        scene: Overrides::default(),
        rtol: None,
        h_max: None,
    };
    let mut out = Vec::new();
    // The thesis's settings: maximum step and a loose / tight error setting (it used
    // 5e-2 and 5e-4 N absolute on forces; here relative tolerances 1e-2 and 1e-4).
    for h in [5e-4, 1e-3, 2e-3, 5e-3] {
        for (name, rtol) in [("loose", 1e-2), ("tight", 1e-4)] {
            out.push(Case {
                rtol: Some(rtol),
                h_max: Some(h),
                ..base(
                    "thesis settings",
                    format!("h_max {h:.0e} s, {name} (rtol {rtol:.0e})"),
                    true,
                )
            });
        }
    }
    let hitch_fe = "hitch_crossbeam.toml";
    out.push(Case {
        props: vec![ov(hitch_fe, "selection.rule", "\"all\"")],
        ..base("modes", "all crossbeam modes".into(), true)
    });
    out.push(base("modes", "selected modes (file's rule)".into(), true));
    out.push(Case {
        props: vec![
            ov("fabia/hitch.toml", "hitch.bracket_mount", "\"fixed\""),
            ov(hitch_fe, "selection.rule", "\"list\""),
            ov(hitch_fe, "selection.modes", "[7, 8, 9]"),
        ],
        ..base(
            "mounting",
            "brackets on FIXED joints, three modes".into(),
            false,
        )
    });
    out.push(Case {
        props: vec![
            ov(hitch_fe, "selection.rule", "\"list\""),
            ov(hitch_fe, "selection.modes", "[7, 8, 9]"),
        ],
        ..base(
            "mounting",
            "brackets on bushings, three modes".into(),
            false,
        )
    });
    for k in [1e5, 1e6, 1e7, 1e8, 1e9] {
        out.push(Case {
            props: vec![ov(
                "fabia/hitch.toml",
                "bracket_bushing.stiffness_n_m",
                format!("[{k:e}, {k:e}, {k:e}]"),
            )],
            ..base(
                "bushing stiffness",
                format!("bracket bushings {k:.0e} N/m"),
                false,
            )
        });
    }
    out.push(Case {
        props: vec![ov("trailer/box_trailer.toml", "wheel.mass_kg", "1e-9")],
        ..base(
            "mass ratio",
            "trailer rims 1e-9 kg (1e12 below the car body)".into(),
            false,
        )
    });
    for h in [0.025, 0.05, 0.075, 0.1] {
        out.push(Case {
            props: vec![ov("ramp_thesis.toml", "obstacle[0].height_m", h)],
            ..base("obstacle height", format!("ramp {:.0} mm", h * 1e3), false)
        });
    }
    for v in [10.0, 20.0, 30.0, 40.0, 50.0, 60.0] {
        out.push(Case {
            scene: Overrides {
                speed_km_h: Some(v),
                ..Default::default()
            },
            ..base("speed", format!("{v:.0} km/h"), false)
        });
    }
    for l in ["empty", "200kg_behind_axle"] {
        out.push(Case {
            scene: Overrides {
                load_case: Some(l.into()),
                ..Default::default()
            },
            ..base("trailer load", l.to_string(), false)
        });
    }
    out
}

pub fn run_stress(a: &StressArgs) -> Result<i32, String> {
    let reference = run(
        &a.scene,
        &[],
        &Overrides::default(),
        &|o: &mut SolverOptions| o.rtol = 1e-5,
    )?;
    if let Some((e, t)) = &reference.result.error {
        return Err(format!("reference run failed at t = {t:.4} s: {e}"));
    }
    let refdata = Reference::of(&reference);
    let all: Vec<Case> = cases()
        .into_iter()
        .filter(|c| a.only.as_ref().is_none_or(|o| c.group.contains(o.as_str())))
        .collect();
    let jobs = a
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pb = crate::progress(all.len() as u64, a.json);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| e.to_string())?;
    let outcomes: Vec<Outcome> = pool.install(|| {
        all.par_iter()
            .map(|c| {
                let tune = |o: &mut SolverOptions| {
                    if let Some(m) = a.method {
                        o.method = m.into();
                    }
                    if let Some(r) = c.rtol {
                        o.rtol = r;
                    }
                    if let Some(h) = c.h_max {
                        o.h_max = h;
                    }
                };
                let r = run(&a.scene, &c.props, &c.scene, &tune);
                pb.inc(1);
                let mut o = Outcome {
                    group: c.group.into(),
                    case: c.label.clone(),
                    status: String::new(),
                    wall_s: f64::NAN,
                    steps: 0,
                    hitch_peak_n: f64::NAN,
                    peak_deviation: f64::NAN,
                    hitch_rms_deviation: f64::NAN,
                    same_physics: c.same_physics,
                    agrees: None,
                };
                match r {
                    Ok(r) if r.result.error.is_none() => {
                        let (peak, _, rms, _) = refdata.errors(&r);
                        o.status = "completed".into();
                        o.wall_s = r.wall_s;
                        o.steps = r.result.stats.steps;
                        o.hitch_peak_n = peak;
                        o.peak_deviation = (peak - refdata.peak) / refdata.peak.abs();
                        o.hitch_rms_deviation = rms;
                        o.agrees = c.same_physics.then_some(o.peak_deviation.abs() <= 0.02);
                    }
                    Ok(r) => {
                        let (e, t) = r.result.error.clone().unwrap_or_default();
                        o.status = format!("failed at t = {t:.4} s: {e}");
                    }
                    Err(e) => o.status = format!("failed: {e}"),
                }
                o
            })
            .collect()
    });
    pb.finish_and_clear();
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let completed = outcomes.iter().filter(|o| o.status == "completed").count();
    let disagree = outcomes.iter().filter(|o| o.agrees == Some(false)).count();
    let summary = json!({
        "scene": a.scene.display().to_string(),
        "reference": {"rtol": 1e-5, "hitch_peak_n": refdata.peak, "wall_s": reference.wall_s},
        "cases": outcomes.len(),
        "completed": completed,
        "same_physics_disagreeing": disagree,
        "outcomes": outcomes,
    });
    let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
    std::fs::write(a.out.join("stress.json"), &text).map_err(|e| e.to_string())?;
    if a.json {
        println!("{text}");
    } else {
        println!(
            "reference: hitch_fx peak {:.1} N ({:.2} s wall)",
            refdata.peak, reference.wall_s
        );
        for o in &outcomes {
            println!(
                "{:<18} {:<46} {:<10} peak {:>9.1} N  {:>+7.2} %  {:>6} steps {:>6.2} s {}",
                o.group,
                o.case,
                if o.status == "completed" {
                    "completed"
                } else {
                    "FAILED"
                },
                o.hitch_peak_n,
                100.0 * o.peak_deviation,
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
            "{completed} of {} completed; {disagree} same-physics case(s) off by more than 2 %; wrote {}",
            outcomes.len(),
            a.out.join("stress.json").display()
        );
    }
    Ok(if completed == outcomes.len() && disagree == 0 {
        0
    } else {
        1
    })
}
