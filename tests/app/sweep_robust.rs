//! The `[robustness]` block of a study file: Kendall's tau-b against hand counts and
//! scipy's values, a tiny study run whose verdicts are recomputed here from the runs'
//! own summary CSVs, values taken from a sensitivity study's ranking, and bad blocks
//! refused naming file, line and field.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use towride_app::sweep::exec::{run_sweep_with, Options};
use towride_app::sweep::robust_run::tau_b;
use towride_app::sweep::Sweep;
use towride_mbs::progress::Silent;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride-robust-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn kendall_tau_b_matches_a_hand_count_and_scipy_with_ties() {
    // x = 1 2 2 3 4, y = 1 3 2 2 5: of the 10 pairs, 7 concordant, 1 discordant ((2,3)
    // against (3,2)), 1 tied in x only ((2,3), (2,2)), 1 tied in y only ((2,2), (3,2)):
    // tau_b = (7 - 1) / sqrt((7 + 1 + 1)(7 + 1 + 1)) = 6 / 9.
    let t = tau_b(&[1.0, 2.0, 2.0, 3.0, 4.0], &[1.0, 3.0, 2.0, 2.0, 5.0]).unwrap();
    assert!((t - 6.0 / 9.0).abs() < 1e-15, "{t}");
    // scipy.stats.kendalltau's docstring example (x = [12, 2, 1, 12, 2], y = [1, 4, 7,
    // 1, 0]): -0.47140452079103173, the value scipy 1.17.1 gives here too.
    let t = tau_b(&[12.0, 2.0, 1.0, 12.0, 2.0], &[1.0, 4.0, 7.0, 1.0, 0.0]).unwrap();
    assert!((t + 0.471_404_520_791_031_73).abs() < 1e-14, "{t}");
    // Reversed order: -1; one ranking all tied, or one value: undefined.
    assert_eq!(
        tau_b(&[1.0, 2.0, 3.0, 4.0], &[4.0, 3.0, 2.0, 1.0]),
        Some(-1.0)
    );
    assert_eq!(tau_b(&[1.0, 2.0, 3.0], &[5.0, 5.0, 5.0]), None);
    assert_eq!(tau_b(&[1.0], &[1.0]), None);
}

/// A study of the thesis scene shortened to 1 s (the trailer meets the ramp at 0.49 s).
fn study(dir: &Path, variants: &str, robustness: &str) -> PathBuf {
    let f = dir.join("study.toml");
    let text = format!(
        "[sweep]\nname = \"tiny\"\nscene = \"{}\"\n\n\
         [[parameter]]\nname = \"hitch_variant\"\nfile = \"scenes/default.toml\"\n\
         path = \"scene.hitch_variant\"\nvalues = [{variants}]\n\n\
         [[parameter]]\nname = \"speed_km_h\"\nfile = \"scenes/default.toml\"\n\
         path = \"run.speed_km_h\"\nvalues = [40.0, 50.0]\n\n\
         [[parameter]]\nname = \"duration_s\"\nfile = \"scenes/default.toml\"\n\
         path = \"run.duration_s\"\nvalues = [1.0]\n\n\
         [robustness]\n{robustness}\n",
        repo!("scenes/default.toml")
    );
    std::fs::write(&f, text).unwrap();
    f
}

/// Mean of `figure` per variant over the completed rows of a summary CSV, read here.
fn means(csv: &str, figure: &str) -> BTreeMap<String, f64> {
    let mut r = csv::Reader::from_path(csv).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    let (v, s, f) = (col("hitch_variant"), col("status"), col(figure));
    let mut sums: BTreeMap<String, (f64, usize)> = BTreeMap::new();
    for rec in r.records() {
        let rec = rec.unwrap();
        if &rec[s] == "completed" {
            let e = sums.entry(rec[v].to_string()).or_default();
            e.0 += rec[f].parse::<f64>().unwrap();
            e.1 += 1;
        }
    }
    sums.into_iter()
        .map(|(k, (x, n))| (k, x / n as f64))
        .collect()
}

fn lowest(m: &BTreeMap<String, f64>) -> String {
    m.iter()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .unwrap()
        .0
        .clone()
}

#[test]
fn a_tiny_study_reports_tau_and_the_best_variant_its_runs_show() {
    let dir = tmp("tiny");
    let fx = "hitch_fx abs_peak [N]";
    let f = study(
        &dir,
        "1, 10",
        "params = [\"box_trailer.toml:half.mass_kg\"]\nrange = 0.3\n\
         figures = [\"hitch_fx abs_peak\"]\nsubset = { speed_km_h = [50] }",
    );
    let sweep = Sweep::load(&f).unwrap();
    let block = sweep.robustness.as_ref().unwrap();
    assert_eq!(block.by, "hitch_variant");
    assert_eq!(block.moves[0].class, "assumed");
    // 1 -+ 0.3 within the value's plausibility bounds.
    assert_eq!(block.moves[0].factors, [0.7, 1.3]);
    let out = dir.join("out");
    let opts = Options {
        jobs: 2,
        resume: false,
        keep_histories: false,
        check: None,
    };
    let res = run_sweep_with(&sweep, (0, 1), &out, &opts, &Silent).unwrap();
    assert_eq!(res.failed, 0);
    let r = res.robustness.as_ref().unwrap();
    assert_eq!((r.status.as_str(), r.cases_per_run), ("completed", 2));
    assert_eq!(r.perturbations.len(), 2);
    // The nominal ranking is the sweep's own cases at 50 km/h, recomputed from its CSV.
    let nominal: BTreeMap<String, f64> = {
        let csv = out.join("summary.csv");
        let mut rd = csv::Reader::from_path(&csv).unwrap();
        let h = rd.headers().unwrap().clone();
        let c = |n: &str| h.iter().position(|x| x == n).unwrap();
        rd.records()
            .map(|x| x.unwrap())
            .filter(|x| x[c("speed_km_h")].parse::<f64>().unwrap() == 50.0)
            .map(|x| (x[c("hitch_variant")].to_string(), x[c(fx)].parse().unwrap()))
            .collect()
    };
    assert_eq!(nominal.len(), 2);
    for (p, (end, factor)) in r.perturbations.iter().zip([("low", 0.7), ("high", 1.3)]) {
        assert_eq!((p.end.as_str(), p.factor), (end, factor));
        let o = &p.outcomes[0];
        assert_eq!(o.figure, fx);
        let pert = means(p.summary_csv.as_deref().unwrap(), fx);
        // The perturbed runs did move the force (the value reached the model).
        assert!(
            pert.iter().all(|(k, v)| (v - nominal[k]).abs() > 1e-6),
            "{pert:?}"
        );
        assert_eq!(o.best, lowest(&pert));
        assert_eq!(o.nominal_best, lowest(&nominal));
        assert_eq!(o.stays_best, o.best == o.nominal_best);
        // Two variants: tau-b is +1 when both rank them alike, -1 when swapped.
        let same = (nominal["1"] - nominal["10"]) * (pert["1"] - pert["10"]) > 0.0;
        let t = o.tau_b.unwrap();
        assert!((-1.0..=1.0).contains(&t));
        assert_eq!(t, if same { 1.0 } else { -1.0 });
    }
    // In summary.json and on the page.
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["schema_version"], 8);
    assert_eq!(
        v["robustness"]["perturbations"].as_array().unwrap().len(),
        2
    );
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(page.contains("\"robustness\":{") && page.contains("robustness-table"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn top_takes_the_highest_ranked_assumed_values_of_a_study_with_its_ranges() {
    let dir = tmp("top");
    // A study's ranking as `towride sensitivity` writes it: the body mass (scaled) first,
    // then two assumed values.
    let p = |name: &str, file: &str, path: &str, mu: f64, range: [f64; 2]| {
        serde_json::json!({"param": {"name": name, "file": file, "path": path},
            "mu_star_rel": [mu], "range": range})
    };
    let json = serde_json::json!({
        "file": repo!("scenes/default.toml"), "method": "morris",
        "outputs": [{"name": "hitch_fx.abs_peak"}],
        "params": [
            p("vehicles/trailer/box_trailer.toml:pivot_bushing.stiffness_n_m_rad",
              "vehicles/trailer/box_trailer.toml", "pivot_bushing.stiffness_n_m_rad", 0.1, [0.7, 1.3]),
            p("vehicles/trailer/box_trailer.toml:body.mass_kg",
              "vehicles/trailer/box_trailer.toml", "body.mass_kg", 0.5, [0.7, 1.3]),
            p("vehicles/trailer/box_trailer.toml:half.mass_kg",
              "vehicles/trailer/box_trailer.toml", "half.mass_kg", 0.2, [0.8, 1.25]),
        ]
    });
    std::fs::write(dir.join("sensitivity.json"), json.to_string()).unwrap();
    let f = study(&dir, "1, 10", "top = 2\nstudy = \"sensitivity.json\"");
    let s = Sweep::load(&f).unwrap();
    let m = &s.robustness.unwrap().moves;
    let names: Vec<&str> = m.iter().map(|m| m.parameter.as_str()).collect();
    assert_eq!(
        names,
        [
            "vehicles/trailer/box_trailer.toml:half.mass_kg",
            "vehicles/trailer/box_trailer.toml:pivot_bushing.stiffness_n_m_rad"
        ]
    );
    // The study's own range; ranks 2 and 3 (the scaled body mass is rank 1).
    assert_eq!(m[0].factors, [0.8, 1.25]);
    assert!(m[0].from.contains("rank 2") && m[1].from.contains("rank 3"));
    assert!(m.iter().all(|m| m.class == "assumed"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_ring_tyre_value_moves_with_the_tyre_factors_held_so_each_end_builds() {
    // FREQ_WINDUP x 0.7 alone leaves the file's longitudinal stiffness above the ring's
    // (the tyre is refused); with the factors held the stiffness follows the ring, as in
    // the sensitivity study. Each end is built when the block is read.
    let dir = tmp("windup");
    let f = study(
        &dir,
        "1, 10",
        "params = [\"trailer_155_80r13.tir:STRUCTURAL.FREQ_WINDUP\"]",
    );
    let s = Sweep::load(&f).unwrap();
    let m = &s.robustness.unwrap().moves[0];
    assert_eq!(m.class, "assumed");
    for end in &m.ends {
        assert_eq!(end[0].path, "STRUCTURAL.FREQ_WINDUP");
        let held: Vec<&str> = end[1..].iter().map(|o| o.path.as_str()).collect();
        assert!(
            held.len() == 7 && held.iter().all(|p| p.starts_with("factor.")),
            "{held:?}"
        );
    }
    // The raw value alone does not build: what the block avoids.
    let alone = towride_mbs::input::Loader::with_overrides(vec![m.ends[0][0].clone()]);
    let e = towride_app::job::Job::from_file(Path::new(repo!("scenes/default.toml")), &alone)
        .err()
        .expect("FREQ_WINDUP x 0.7 alone is refused")
        .to_string();
    assert!(e.contains("LONGITUDINAL_STIFFNESS"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_bad_robustness_block_is_refused_naming_file_line_and_field() {
    let dir = tmp("bad");
    // The block starts on line 23 of the study file written by `study`.
    for (block, line, field, says) in [
        (
            "params = [\"box_trailer.toml:no_such.mass_kg\"]",
            24,
            "robustness.params[0]",
            "no_such",
        ),
        (
            "params = [\"box_trailer.toml:half.mass_kg\"]\nrange = 1.5",
            25,
            "robustness.range",
            "1.5",
        ),
        (
            "params = [\"box_trailer.toml:half.mass_kg\"]\nsubset = { speed_km_h = [55.0] }",
            25,
            "robustness.subset.speed_km_h",
            "55",
        ),
        (
            "params = [\"box_trailer.toml:half.mass_kg\"]\nby = \"mass\"",
            25,
            "robustness.by",
            "mass",
        ),
        (
            "top = 2\nstudy = \"missing.json\"",
            25,
            "robustness.study",
            "missing.json",
        ),
        ("range = 0.2", 23, "robustness", "params"),
    ] {
        let f = study(&dir, "1, 10", block);
        let e = Sweep::load(&f).unwrap_err().to_string();
        assert!(
            e.contains(&format!("study.toml:{line}")) && e.contains(field) && e.contains(says),
            "{block}: {e}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
