//! The stress test of a scene: the thesis's integrator experiment and worse. Every case
//! is run and classified: completed or failed, and its hitch force's max, min and |peak|
//! against the reference's (the scene at rtol 1e-5). Cases that change only numerical
//! settings (step limits, tolerances, modes kept) must agree with it; cases that change
//! the physics (stiffness, masses, obstacle, speed, load) report their extremes and the
//! ratio of their |peak| to the reference's. Like is compared with like: max with max,
//! min with min, |peak| with |peak|, never a signed peak that may sit on the other side.

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::Serialize;

use super::{pool, total_wall, Reference};
use crate::error::{Error, Result};
use crate::job::{Extremes, Job, RunResult};
use crate::scene::Changes;
use towride_mbs::input::{Loader, Override};
use towride_mbs::progress::{Progress, StopOnly};
use towride_solver::{Method, SolverOptions};

/// Version of `stress.json`'s layout. 2: the signed `hitch_peak_n` and
/// `peak_deviation` are gone for max, min, |peak| and their ratios to the reference's.
/// 3: `status` and `interrupted` (a study stopped by Ctrl-C).
pub const SCHEMA_VERSION: u32 = 3;

/// Relative tolerance of the reference run.
pub const REFERENCE_RTOL: f64 = 1e-5;

/// Largest deviation of a same-physics case's |peak| from the reference's, as a
/// fraction of it (the |peak| on the reference's side: [`agrees`]).
pub const AGREEMENT: f64 = 0.02;

/// One stress case.
pub struct Case {
    /// The group it belongs to (`--only` selects groups).
    pub group: &'static str,
    /// What the case does.
    pub label: String,
    /// Only numerical settings change: the result must match the reference.
    pub same_physics: bool,
    /// Property overrides.
    pub props: Vec<Override>,
    /// Scene setting changes.
    pub scene: Changes,
    /// Relative tolerance, when changed.
    pub rtol: Option<f64>,
    /// Largest step, when changed [s].
    pub h_max: Option<f64>,
}

/// What a case gave.
#[derive(Clone, Debug, Serialize)]
pub struct Outcome {
    /// The case's group.
    pub group: String,
    /// The case.
    pub case: String,
    /// "completed" or "failed ...".
    pub status: String,
    /// Wall time, start included [s].
    pub wall_s: f64,
    /// Accepted steps.
    pub steps: usize,
    /// The hitch force's (`hitch_fx`) max [N].
    pub hitch_max_n: f64,
    /// Its min [N].
    pub hitch_min_n: f64,
    /// Its |peak|, max(|max|, |min|) [N].
    pub hitch_abs_peak_n: f64,
    /// |peak| / reference |peak| ([`ratio`]): 1.2 a fifth larger, whichever side it is
    /// on. For a case that changes the physics (speed, load, obstacle) it compares
    /// different experiments, not an error.
    pub abs_peak_ratio: f64,
    /// max / reference max.
    pub max_ratio: f64,
    /// min / reference min (both pulls: 1.2 a fifth larger pull).
    pub min_ratio: f64,
    /// RMS of the hitch-force difference over the reference's RMS.
    pub hitch_rms_deviation: f64,
    /// The case changes only numerical settings.
    pub same_physics: bool,
    /// Same-physics cases: |peak| within 2 % of the reference's, on the same side
    /// ([`agrees`]).
    pub agrees: Option<bool>,
}

/// The reference run of a stress test.
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceRun {
    /// Its relative tolerance.
    pub rtol: f64,
    /// The hitch force's max [N].
    pub hitch_max_n: f64,
    /// Its min [N].
    pub hitch_min_n: f64,
    /// Its |peak| [N].
    pub hitch_abs_peak_n: f64,
    /// Wall time [s].
    pub wall_s: f64,
}

/// The stress test's result.
#[derive(Clone, Debug, Serialize)]
pub struct Stress {
    /// Layout version.
    pub schema_version: u32,
    /// "completed", or "interrupted" (Ctrl-C): the cases not run or stopped say so.
    pub status: &'static str,
    /// Cases not run or stopped by the interruption.
    pub interrupted: usize,
    /// The scene file.
    pub scene: String,
    /// The reference run.
    pub reference: ReferenceRun,
    /// Cases run.
    pub cases: usize,
    /// Cases completed.
    pub completed: usize,
    /// Same-physics cases off by more than 2 %.
    pub same_physics_disagreeing: usize,
    /// Every case.
    pub outcomes: Vec<Outcome>,
}

fn ov(file: &str, path: &str, value: impl std::fmt::Display) -> Override {
    Override::program(file, path, value.to_string(), "stress case")
}

/// The stress cases, in report order.
pub fn cases() -> Vec<Case> {
    let base = |group, label: String, same: bool| Case {
        group,
        label,
        same_physics: same,
        props: vec![],
        scene: Changes::default(),
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
                "mounting.body_stiffness_n_m",
                format!("[{k:e}, {k:e}, {k:e}]"),
            )],
            ..base(
                "bushing stiffness",
                format!("bracket body side {k:.0e} N/m, bolts in series"),
                false,
            )
        });
    }
    out.push(Case {
        // The smallest mass the input checks accept (docs/reliability.md).
        props: vec![ov("trailer/box_trailer.toml", "wheel.mass_kg", "1e-6")],
        ..base(
            "mass ratio",
            "trailer rims 1e-6 kg (1e9 below the car body)".into(),
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
            scene: Changes {
                speed_km_h: Some(v),
                ..Default::default()
            },
            ..base("speed", format!("{v:.0} km/h"), false)
        });
    }
    for l in ["empty", "200kg_behind_axle"] {
        out.push(Case {
            scene: Changes {
                load_case: Some(l.into()),
                ..Default::default()
            },
            ..base("trailer load", l.to_string(), false)
        });
    }
    out
}

/// Runs the cases whose group contains `only` (all when `None`) on `jobs` threads, each
/// with the integration method `method` (the scene's when `None`; the reference keeps
/// the scene's).
pub fn run(
    scene: &Path,
    loader: &Loader,
    only: Option<&str>,
    method: Option<Method>,
    jobs: usize,
    progress: &dyn Progress,
) -> Result<Stress> {
    let stop = StopOnly(progress);
    let reference = Job::from_scene_file(scene, &Changes::default(), loader)?
        .without_view()
        .tune(|o| o.rtol = REFERENCE_RTOL)?
        .run(&stop)?;
    reference.require_completed()?;
    let refdata = Reference::of(&reference);
    let all: Vec<Case> = cases()
        .into_iter()
        .filter(|c| only.is_none_or(|o| c.group.contains(o)))
        .collect();
    if all.is_empty() {
        let mut groups: Vec<&str> = cases().iter().map(|c| c.group).collect();
        groups.dedup();
        return Err(crate::scene::SceneError::NoSuchCase(format!(
            "no stress group contains `{}` (groups: {})",
            only.unwrap_or(""),
            groups.join(", ")
        ))
        .into());
    }
    progress.begin(all.len() as u64);
    let outcomes: Vec<Outcome> = pool(jobs)?.install(|| {
        all.par_iter()
            .map(|c| {
                // Stopped: cases not begun say so, rather than failing or vanishing.
                if progress.cancelled() {
                    return Outcome {
                        status: super::NOT_RUN.into(),
                        ..blank(c)
                    };
                }
                let r = run_case(scene, loader, c, method, &stop);
                progress.inc(1);
                outcome(c, r, &refdata)
            })
            .collect()
    });
    progress.finish();
    let completed = outcomes.iter().filter(|o| o.status == "completed").count();
    let disagree = outcomes.iter().filter(|o| o.agrees == Some(false)).count();
    let interrupted = outcomes
        .iter()
        .filter(|o| super::stopped(&o.status))
        .count();
    Ok(Stress {
        schema_version: SCHEMA_VERSION,
        status: if interrupted > 0 {
            "interrupted"
        } else {
            "completed"
        },
        interrupted,
        scene: scene.display().to_string(),
        reference: ReferenceRun {
            rtol: REFERENCE_RTOL,
            hitch_max_n: refdata.extremes.max,
            hitch_min_n: refdata.extremes.min,
            hitch_abs_peak_n: refdata.extremes.abs_peak,
            wall_s: total_wall(&reference),
        },
        cases: outcomes.len(),
        completed,
        same_physics_disagreeing: disagree,
        outcomes,
    })
}

fn run_case(
    scene: &Path,
    base: &Loader,
    c: &Case,
    method: Option<Method>,
    stop: &dyn Progress,
) -> Result<RunResult> {
    let loader = base.extended(c.props.clone());
    Job::from_scene_file(scene, &c.scene, &loader)?
        .without_view()
        .tune(|o: &mut SolverOptions| {
            if let Some(m) = method {
                o.method = m;
            }
            if let Some(r) = c.rtol {
                o.rtol = r;
            }
            if let Some(h) = c.h_max {
                o.h_max = h;
            }
        })?
        .run(stop)
}

/// `value` over the reference's `reference` of the same kind (|peak| over |peak|, max
/// over max, min over min): 1.2 is a fifth larger on the same side.
pub fn ratio(value: f64, reference: f64) -> f64 {
    value / reference
}

/// A same-physics case agrees with the reference when its |peak| lies within
/// [`AGREEMENT`] of the reference's and on the same side (its larger magnitude is its
/// max where the reference's is, its min where the reference's is): the same test as
/// |peak - reference peak| <= 2 % |reference peak| on signed peaks, without one. A case
/// whose larger side changed deviates, however close the magnitudes.
pub fn agrees(case: &Extremes, reference: &Extremes) -> bool {
    let high = |e: &Extremes| e.max.abs() >= e.min.abs();
    high(case) == high(reference)
        && (case.abs_peak - reference.abs_peak).abs() <= AGREEMENT * reference.abs_peak
}

/// A case's outcome before anything is known of it.
fn blank(c: &Case) -> Outcome {
    Outcome {
        group: c.group.into(),
        case: c.label.clone(),
        status: String::new(),
        wall_s: f64::NAN,
        steps: 0,
        hitch_max_n: f64::NAN,
        hitch_min_n: f64::NAN,
        hitch_abs_peak_n: f64::NAN,
        abs_peak_ratio: f64::NAN,
        max_ratio: f64::NAN,
        min_ratio: f64::NAN,
        hitch_rms_deviation: f64::NAN,
        same_physics: c.same_physics,
        agrees: None,
    }
}

fn outcome(c: &Case, r: Result<RunResult>, refdata: &Reference) -> Outcome {
    let mut o = blank(c);
    match r {
        Ok(r) if r.completed() => {
            let e = refdata.errors(&r);
            o.status = "completed".into();
            o.wall_s = total_wall(&r);
            o.steps = r.summary.solver.steps;
            let (x, r) = (&e.extremes, &refdata.extremes);
            o.hitch_max_n = x.max;
            o.hitch_min_n = x.min;
            o.hitch_abs_peak_n = x.abs_peak;
            o.abs_peak_ratio = ratio(x.abs_peak, r.abs_peak);
            o.max_ratio = ratio(x.max, r.max);
            o.min_ratio = ratio(x.min, r.min);
            o.hitch_rms_deviation = e.hitch_rms;
            o.agrees = c.same_physics.then(|| agrees(x, r));
        }
        Ok(r) => match r.samples.interrupted {
            Some(t) => o.status = super::interrupted_at(t),
            None => {
                let (e, t) = r.failure().unwrap_or_default();
                o.status = format!("failed at t = {t:.4} s: {e}");
            }
        },
        Err(e) => o.status = format!("failed: {e}"),
    }
    o
}

impl Stress {
    /// True when every case completed and every same-physics case agrees.
    pub fn passed(&self) -> bool {
        self.completed == self.cases && self.same_physics_disagreeing == 0
    }

    /// Writes `stress.json` into `dir`.
    pub fn write(&self, dir: &Path) -> Result<PathBuf> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let json = dir.join("stress.json");
        let text = serde_json::to_string_pretty(self).unwrap_or_default();
        crate::atomic::write(&json, text).map_err(|e| Error::io(&json, e))?;
        Ok(json)
    }
}
