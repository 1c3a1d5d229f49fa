//! Runs that used to fail: Radau IIA gave up after ten error-test failures (a tight
//! reference at the ramp's foot) or ten Newton failures (a coupling head's play) in one
//! step, where RADAU5 keeps cutting the step; each now completes and agrees with a run at
//! a tolerance ten times tighter (docs/solver.md). The statics stalled within tolerance on
//! a sharply smoothed play; the start now finds the ball load of the play-free coupling
//! (docs/mechanism.md, "Statics").

const S: &str = "scenes/default.toml";
const H: &str = "vehicles/fabia/hitch.toml";

/// Runs the default scene with `sets` (and `extra` arguments) into a fresh folder; returns
/// the folder and the command's output.
fn run(tag: &str, sets: &[String], extra: &[&str]) -> (std::path::PathBuf, std::process::Output) {
    let dir = std::env::temp_dir().join(format!("towride_rej_{}_{tag}", std::process::id()));
    let mut args: Vec<String> = ["run", S, "--animation-rate-hz", "0", "--out"]
        .iter()
        .map(|a| a.to_string())
        .collect();
    args.push(dir.display().to_string());
    args.extend(extra.iter().map(|a| a.to_string()));
    for s in sets {
        args.extend(["--set".into(), s.clone()]);
    }
    let out = super::towride_ok(&args.iter().map(String::as_str).collect::<Vec<_>>());
    (dir, out)
}

/// hitch_fx |peak| [N] of the default scene with `sets`, after checking it completed.
fn peak(tag: &str, sets: &[String]) -> f64 {
    let (dir, out) = run(tag, sets, &["--json"]);
    std::fs::remove_dir_all(&dir).ok();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "completed", "{tag}: {}", v["error"]);
    v["channels"]["hitch_fx"]["abs_peak"].as_f64().unwrap()
}

/// The ball's vertical force [N] at the start of a short run of the default scene.
fn ball_load(tag: &str, sets: &[String]) -> f64 {
    let short = format!("{S}:run.duration_s=0.01");
    let (dir, _) = run(tag, &[sets, &[short]].concat(), &[]);
    let mut r = csv::Reader::from_path(dir.join("outputs.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let c = h.iter().position(|x| x.starts_with("hitch_fz ")).unwrap();
    let first = r.records().next().unwrap().unwrap();
    std::fs::remove_dir_all(&dir).ok();
    first[c].parse().unwrap()
}

fn tolerance(rtol: f64, atol_scale: f64) -> Vec<String> {
    vec![
        format!("{S}:solver.rtol={rtol:e}"),
        format!("{S}:run.atol_scale={atol_scale:e}"),
    ]
}

#[test]
fn a_tight_reference_passes_the_ramp_foot() {
    // Variant 10 at 60 km/h at rtol 1e-6: stopped at t = 0.049 s by ten error-test
    // failures as the front tyres' cams reached the ramp's foot.
    let case = [
        format!("{S}:scene.hitch_variant=10"),
        format!("{S}:run.speed_km_h=60"),
    ];
    let run = peak("ref", &[&case[..], &tolerance(1e-6, 1e-3)].concat());
    let tight = peak("tight", &[&case[..], &tolerance(1e-7, 1e-4)].concat());
    assert!((run / tight - 1.0).abs() < 1e-3, "{run} against {tight}");
}

#[test]
fn the_coupling_heads_play_runs_at_the_scenes_tolerance() {
    // 0.5 mm of play smoothed over 50 um at the scene's rtol 1e-4: stopped at t = 0.672 s
    // by ten Newton failures in one step.
    let law = "{ stiffness_n_m = 2.0e7, play_m = 5.0e-4, smoothing_m = 5.0e-5 }";
    let case = [
        format!("{H}:ball_coupling.kind=\"coupling_head\""),
        format!("{H}:ball_coupling.coupling_head.stiffness_n_m=[{law}, {law}, {law}]"),
    ];
    let run = peak("play", &case);
    let tight = peak("play_tight", &[&case[..], &tolerance(1e-5, 0.1)].concat());
    assert!((run / tight - 1.0).abs() < 2e-3, "{run} against {tight}");
}

#[test]
fn a_sharply_smoothed_play_starts_from_the_nose_load() {
    // 0.5 mm of play smoothed over 6.25 um: the statics' line search stalled at 2.6e-4 N
    // on the hitch, within the force tolerance, and the start failed.
    let law = "{ stiffness_n_m = 2.0e7, play_m = 5.0e-4, smoothing_m = 6.25e-6 }";
    let play = ball_load(
        "sharp",
        &[
            format!("{H}:ball_coupling.kind=\"coupling_head\""),
            format!("{H}:ball_coupling.coupling_head.stiffness_n_m=[{law}, {law}, {law}]"),
        ],
    );
    let ball = ball_load("ball", &[]);
    assert!(
        (play / ball - 1.0).abs() < 5e-3,
        "{play} N against {ball} N"
    );
}
