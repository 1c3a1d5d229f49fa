//! `towride linear FILE` and `towride doctor FILE`: analyses before trusting a model
//! (a mechanism file or a vehicle scene).

use std::path::PathBuf;

use clap::Args;

use towride_app::job::Job;
use towride_mbs::model;
use towride_mbs::model::linear::{Mode, RootKind};
use towride_mbs::progress::Silent;

use crate::CliResult;

#[derive(Args, Debug)]
pub struct LinearArgs {
    /// A mechanism file or a scene (TOML).
    file: PathBuf,
    /// Linearise about the state of a run at this time [s] instead of the equilibrium.
    #[arg(long, value_parser = crate::bounded::time_s)]
    at: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Folder for the HTML page (`linear.html`: mode table and animated mode shapes).
    #[arg(long, default_value = "out")]
    out: PathBuf,
    #[command(flatten)]
    inputs: crate::inputs::InputArgs,
}

pub fn linear(a: &LinearArgs) -> CliResult {
    let mut job = Job::from_file(&a.file, &a.inputs.loader()?)?.without_view();
    if let Some(t) = a.at.filter(|t| *t > 0.0) {
        // The state of a run at t, started as the file says.
        job.settings.t_end = t;
        job.settings.sample_rate = job.settings.sample_rate.max(1.0 / t);
        let res = job.run(&Silent)?;
        if let Some((e, te)) = res.failure() {
            return Err(format!("run to t = {t} s failed at {te:.6} s: {e}").into());
        }
        let (t, y, _) = res.samples.last.ok_or("run produced no state")?;
        let lin = model::linear::linearise(&job.system, t, &y)?;
        return print_linear(
            a,
            &job.system,
            &y,
            &lin,
            &format!("state of the run at t = {t} s"),
        );
    }
    let sys = &job.system;
    let (t, y, at) = match a.at {
        None => {
            let st = model::statics::equilibrium(sys, 0.0, &job.solver)?;
            (0.0, st.y, "equilibrium".to_string())
        }
        Some(_) => {
            let (mut q, mut v) = sys.initial_q_v();
            let (y, _, _) = {
                let x = sys.ext_initial(&q, &v, 0.0);
                model::ic::initial_state(sys, 0.0, &mut q, &mut v, &x)?
            };
            (0.0, y, "initial state".to_string())
        }
    };
    let lin = model::linear::linearise(sys, t, &y)?;
    print_linear(a, sys, &y, &lin, &at)
}

fn print_linear(
    a: &LinearArgs,
    sys: &model::System,
    y: &[f64],
    lin: &model::linear::Linearisation,
    at: &str,
) -> CliResult {
    let page = towride_app::report::linear::write(&a.out, sys, y, lin, at)?;
    if a.json {
        // 2: every number's field names its unit (`t_s`, `real_1_per_s`, `imag_rad_per_s`).
        let v = serde_json::json!({"schema_version": 2, "model": sys.model.name, "linearised_at": at, "report": page.display().to_string(), "result": lin});
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(0);
    }
    println!(
        "{}: linearised about the {at}; {} degrees of freedom and {} first-order states (tyres, controllers): {} eigenvalues, {} modes (a conjugate pair listed once)",
        sys.model.name,
        lin.dof,
        lin.first_order_states,
        lin.eigenvalues,
        lin.modes.len()
    );
    match lin.stiffness_ratio {
        Some(s) => println!(
            "stiffness ratio S = {s:.3e}{}",
            if s > 200.0 { " (stiff)" } else { "" }
        ),
        None => println!("stiffness ratio S: undefined (fewer than two damped roots)"),
    }
    let zero: Vec<&Mode> = lin
        .modes
        .iter()
        .filter(|m| m.kind == RootKind::Zero)
        .collect();
    if !zero.is_empty() {
        // Free motions (lateral position, heading, travel): no vibration, no zeta.
        let names: Vec<String> = zero
            .iter()
            .map(|m| format!("{} {}", m.index, m.name))
            .collect();
        println!(
            "{} zero roots (below {} Hz: motions without restoring force, not vibrations): {}",
            zero.len(),
            RootKind::zero_hz(),
            names.join("; ")
        );
    }
    for m in lin.modes.iter().filter(|m| m.kind == RootKind::Unstable) {
        println!(
            "UNSTABLE root of this frozen state: mode {} {} grows at Re = {:.4} 1/s (doubles in {:.3} s)",
            m.index,
            m.name,
            m.real,
            m.doubling_time_s.unwrap_or(f64::NAN)
        );
    }
    println!(
        "{:>4} {:>14} {:>14} {:>9}  {:<34} dominant bodies / elements",
        "mode", "undamped [Hz]", "damped [Hz]", "zeta", "dominant motion (kinetic share)"
    );
    for m in lin.modes.iter().filter(|m| m.kind != RootKind::Zero) {
        let bodies: Vec<String> = m
            .bodies
            .iter()
            .take(3)
            .map(|s| format!("{} {:.0}%", s.name, 100.0 * s.share))
            .collect();
        let elems: Vec<String> = m
            .elements
            .iter()
            .take(2)
            .map(|s| format!("{} {:.0}%", s.name, 100.0 * s.share))
            .collect();
        let name = if m.name_share > 0.0 {
            format!("{} ({:.0}%)", m.name, 100.0 * m.name_share)
        } else {
            m.name.clone()
        };
        let zeta = if m.kind == RootKind::Unstable {
            "UNSTABLE".to_string()
        } else {
            format!("{:.4}", m.damping_ratio)
        };
        println!(
            "{:>4} {:>14.6} {:>14.6} {:>9}  {:<34} {} / {}",
            m.index,
            m.undamped_hz,
            m.damped_hz,
            zeta,
            name,
            bodies.join(", "),
            elems.join(", ")
        );
    }
    println!("mode shapes: {}", page.display());
    Ok(0)
}

#[derive(Args, Debug)]
pub struct DoctorArgs {
    /// A mechanism file or a scene (TOML).
    file: PathBuf,
    /// Step size for the condition-number estimate [s].
    #[arg(long, default_value_t = 1e-3, value_parser = crate::bounded::step_s)]
    step: f64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    inputs: crate::inputs::InputArgs,
}

pub fn doctor(a: &DoctorArgs) -> CliResult {
    let job = Job::from_file(&a.file, &a.inputs.loader()?)?;
    let rep = model::doctor::examine(&job.system, &job.solver, a.step);
    if a.json {
        // 2: the field names carry their units (`stiffness_n_per_m`, ...); 1 had none.
        let mut v = serde_json::to_value(&rep)?;
        if let Some(o) = v.as_object_mut() {
            o.insert("schema_version".into(), 2.into());
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(0);
    }
    println!(
        "{}: {} bodies, {} equations, {} constraint rows kept",
        rep.model, rep.bodies, rep.equations, rep.constraint_rows
    );
    if rep.redundant.is_empty() {
        println!("redundant constraints: none");
    } else {
        println!("redundant constraints: {} rows", rep.redundant.len());
        for r in &rep.redundant {
            println!("  {} (repeats {})", r.row, r.duplicates.join(", "));
        }
    }
    // Every number with its unit; ratios and condition numbers are dimensionless, [-].
    match rep.newton_condition {
        Some(k) => println!(
            "Newton matrix condition number at h = {:.0e} s: {k:.3e} [-]",
            rep.step_s
        ),
        None => println!("Newton matrix condition number: not estimated"),
    }
    println!(
        "mass ratio {:.3e} [-], inertia ratio {:.3e} [-] (largest over smallest)",
        rep.mass_ratio, rep.inertia_ratio
    );
    for b in &rep.bushings {
        let (k, m) = b.units();
        println!(
            "  bushing {} {}: {:.3e} {k} against {:.3e} {} -> {:.1} Hz",
            b.bushing, b.axis, b.stiffness, b.effective_inertia, m, b.frequency_hz
        );
    }
    if let Some(l) = &rep.linearisation {
        let top = l.modes.last().map(|m| m.undamped_hz).unwrap_or(0.0);
        let low = l
            .modes
            .iter()
            .map(|m| m.undamped_hz)
            .find(|f| *f > 1e-6)
            .unwrap_or(0.0);
        println!(
            "eigenvalues ({}): {} modes from {low:.4} Hz to {top:.4} Hz; stiffness ratio S = {}",
            rep.linearised_at,
            l.modes.len(),
            l.stiffness_ratio
                .map_or("undefined".into(), |s| format!("{s:.3e} [-]"))
        );
    }
    if rep.advice.is_empty() {
        println!("advice: nothing to report");
    } else {
        println!("advice:");
        for a in &rep.advice {
            println!("  - {a}");
        }
    }
    Ok(0)
}
