//! `towride run SCENE` and `towride run PLAN`: a vehicle scene from its start state (by
//! default static equilibrium at speed) to its end, written as `outputs.csv` (the fixed
//! channels, units in the headers) and `summary.json` (status, solver effort, per channel
//! max, min and their times).

use std::path::Path;

use serde_json::{json, Map, Value};

use crate::run::RunArgs;
use towride::model::run::{simulate, RunResult};
use towride::model::System;
use towride::scene::{self, plan, Scene};

pub fn run(a: &RunArgs) -> Result<i32, String> {
    if !plan::is_plan(&a.file) {
        let s = scene::load(&a.file).map_err(|e| e.to_string())?;
        return run_scene(&s, &a.out, a.json);
    }
    let p = plan::load(&a.file).map_err(|e| e.to_string())?;
    if a.list {
        for c in &p.cases {
            println!("{}", c.name);
        }
        return Ok(0);
    }
    for name in &a.case {
        if p.case(name).is_none() {
            return Err(format!(
                "{}: no case '{name}' (--list shows them)",
                a.file.display()
            ));
        }
    }
    let mut code = 0;
    for c in p
        .cases
        .iter()
        .filter(|c| a.case.is_empty() || a.case.contains(&c.name))
    {
        let s = p.scene(c).map_err(|e| e.to_string())?;
        code = code.max(run_scene(&s, &a.out.join(&c.name), a.json)?);
    }
    Ok(code)
}

fn run_scene(s: &Scene, out: &Path, quiet: bool) -> Result<i32, String> {
    let sys = System::new(s.model().clone());
    crate::model_check(&sys)?;
    let warnings = crate::redundancy_warnings(&sys);
    if !quiet {
        for w in &warnings {
            eprintln!("warning: {w}");
        }
    }
    let opts = s.solver_for(&sys);
    let (start, start_report) = towride::scene::exec::start(s, &opts)?;
    let pb = crate::progress((s.duration * s.sample_rate).round() as u64, quiet);
    let res = simulate(&sys, 0.0, s.duration, s.sample_rate, &opts, start, &pb);
    pb.finish_and_clear();
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let csv = out.join("outputs.csv");
    res.write_csv(&csv)
        .map_err(|e| format!("{}: {e}", csv.display()))?;
    let st = &res.stats;
    let plot = out.join("plots.png");
    let plot_error = crate::scene_report::plots(&res, &plot).err();
    let lift = crate::scene_report::lift_off(&res);
    let summary = json!({
        "scene": s.name,
        "file": s.file.display().to_string(),
        "status": if res.error.is_none() { "completed" } else { "failed" },
        "error": res.error.as_ref().map(|e| e.0.clone()),
        "failed_at_s": res.error.as_ref().map(|e| e.1),
        "wall_s": res.wall_s,
        "t_end": res.times.last().copied().unwrap_or(0.0),
        "steps": st.steps,
        "rejected_steps": st.rejected_steps,
        "newton_iterations": st.newton_iterations,
        "jacobian_evals": st.jacobian_evals,
        "matrix_rebuilds": st.matrix_rebuilds,
        "step_limiters": st.step_limiters.iter().map(|(u, n)| json!({"unknown": u, "steps": n})).collect::<Vec<_>>(),
        "speed_m_s": s.speed,
        "road": s.road_file.display().to_string(),
        "load_case": s.vehicle.design.trailer.as_ref().map(|t| t.load_case.clone()),
        "hitch_variant": s.vehicle.handles.hitch.as_ref().map(|h| h.variant),
        "equations": sys.size(),
        "unknowns": {"positions": sys.nq, "velocities": sys.nv, "multipliers": sys.m, "extension_states": sys.ne},
        "warnings": warnings,
        "start": start_report,
        "design": s.vehicle.design,
        "lift_off": lift,
        "skipped": skipped(&sys, st),
        "modal_energy": crate::scene_report::energy(&sys, &res),
        "plots": plot_error.as_ref().map_or(Value::String(plot.display().to_string()), |e| Value::String(format!("not written: {e}"))),
        "channels": channel_summary(&res),
    });
    let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
    std::fs::write(out.join("summary.json"), &text).map_err(|e| e.to_string())?;
    if quiet {
        println!("{text}");
    } else {
        println!(
            "{}: {} in {:.1} s wall, {} steps; outputs in {}",
            s.name,
            if res.error.is_none() {
                "completed"
            } else {
                "FAILED"
            },
            res.wall_s,
            st.steps,
            csv.display()
        );
        for l in &lift {
            println!(
                "  wheel {} off the road from {:.3} s for {:.3} s",
                l["wheel"].as_str().unwrap_or(""),
                l["start_s"].as_f64().unwrap_or(f64::NAN),
                l["duration_s"].as_f64().unwrap_or(f64::NAN)
            );
        }
        if let Some(e) = &plot_error {
            eprintln!("warning: plots not written: {e}");
        }
        if let Some(Value::Object(m)) = summary.get("channels") {
            for (name, c) in m.iter().filter(|(n, _)| !n.starts_with("hitch_eta_")) {
                println!(
                    "  {name:<20} min {:>11.4e} at {:>7.4} s   max {:>11.4e} at {:>7.4} s  [{}]",
                    c["min"].as_f64().unwrap_or(f64::NAN),
                    c["t_min"].as_f64().unwrap_or(f64::NAN),
                    c["max"].as_f64().unwrap_or(f64::NAN),
                    c["t_max"].as_f64().unwrap_or(f64::NAN),
                    c["unit"].as_str().unwrap_or("")
                );
            }
        }
    }
    if let Some((e, t)) = &res.error {
        eprintln!(
            "error: run stopped at t = {t:.6} s: {e}\n  results up to that time are in {}",
            csv.display()
        );
        return Ok(1);
    }
    Ok(0)
}

/// Per channel (keyed by its fixed name): unit, max, min and their times.
fn channel_summary(res: &RunResult) -> Map<String, Value> {
    let mut m = Map::new();
    for (c, ch) in res.channels.iter().enumerate() {
        let (mut lo, mut hi, mut t_lo, mut t_hi) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0.0);
        for (t, row) in res.times.iter().zip(&res.rows) {
            if row[c] < lo {
                (lo, t_lo) = (row[c], *t);
            }
            if row[c] > hi {
                (hi, t_hi) = (row[c], *t);
            }
        }
        m.insert(
            ch.name.clone(),
            json!({"unit": ch.unit, "max": hi, "t_max": t_hi, "min": lo, "t_min": t_lo}),
        );
    }
    m
}

/// What the run did not compute, and why.
fn skipped(sys: &System, st: &towride_solver::Stats) -> Value {
    let mut q = [0u64; 3];
    for t in &sys.model.tyres {
        if let Some(c) = t.tyre.query_counts() {
            for k in 0..3 {
                q[k] += c[k];
            }
        }
    }
    let modes: Vec<Value> = sys
        .model
        .bodies
        .iter()
        .filter_map(|b| b.modal.as_ref().map(|m| (b, m)))
        .map(|(b, m)| {
            json!({"body": b.name, "modes_kept": m.data.modes.len(),
                   "why": "modes outside the body file's selection rule are not integrated"})
        })
        .collect();
    let solved = sys.model.accelerations == towride::model::desc::Accelerations::Solve;
    json!({
        "tyre_road_queries": q[0],
        "answered_from_memo": q[1],
        "answered_flat_without_search": q[2],
        "enveloping_searches": q[0] - q[1] - q[2],
        "why": "no tandem-cam search where the road under a tyre is flat; the last query is memoised",
        "modal_bodies": modes,
        "acceleration_solves": {
            "skipped": !solved,
            "why": if solved {
                "[run] accelerations = \"solve\": solved at every sample"
            } else {
                "sampled accelerations and hitch forces from the integrator's interpolant; the per-sample acceleration-level solve took about 30 % of a default run (docs/performance.md)"
            },
        },
        "jacobian_evaluations": {
            "evaluated": st.jacobian_evals,
            "matrices_recombined_without_evaluation": st.matrix_recombinations,
            "why": "a step change rebuilds the iteration matrix from the kept dF/dy and dF/dy' (jacobian_recombine); one evaluation costs about 25 Newton iterations",
        },
    })
}
