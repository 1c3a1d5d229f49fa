//! Issue 31 item 11: the validation pages as a user sees them (index, trends, a run's
//! report in headless Chromium at 1300 px) and the passage found at low speed.

use crate::towride_json;

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("towride-vpages-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    d
}

/// The shipped synthetic bump runs: at 10 km/h the bump's exit, 0.5 m after its entry,
/// was taken for the front axle's passage (1.926 m implied against the model's 2.462 m).
/// The implied wheelbase must be the model's within 1.5 % at 10 km/h and at 40 km/h.
#[test]
fn the_implied_wheelbase_is_the_model_s_at_10_and_40_kmh() {
    for run in [
        repo!("measurements/synthetic/bump_25mm_10kmh_empty.toml"),
        repo!("measurements/synthetic/bump_25mm_10kmh_200kg_behind_axle.toml"),
        repo!("measurements/synthetic/bump_25mm_40kmh_empty.toml"),
    ] {
        let out = tmp("wheelbase");
        let d = towride_json(&[
            "validate",
            run,
            "--json",
            "--no-plots",
            "--out",
            out.to_str().unwrap(),
        ]);
        let r = &d["runs"][0];
        let (implied, model) = (
            r["implied_wheelbase_m"].as_f64().unwrap(),
            r["wheelbase_m"].as_f64().unwrap(),
        );
        assert!(
            (implied / model - 1.0).abs() < 0.015,
            "{run}: implied wheelbase {implied:.3} m, the model's {model:.3} m"
        );
        std::fs::remove_dir_all(&out).ok();
    }
}

/// Six shipped synthetic runs (two obstacles, two loads, 10 and 30 km/h) validated once
/// into a folder shared by the page tests; their descriptors copied with absolute paths.
fn folder() -> &'static std::path::Path {
    static DIR: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let d = tmp("folder");
        let runs = d.join("runs");
        std::fs::create_dir_all(&runs).unwrap();
        let root = repo!("");
        for run in RUNS {
            let text = std::fs::read_to_string(format!("{root}measurements/synthetic/{run}.toml"))
                .unwrap()
                .replace("scene = \"../../", &format!("scene = \"{root}"))
                .replace(
                    "data = \"",
                    &format!("data = \"{root}measurements/synthetic/"),
                );
            std::fs::write(runs.join(format!("{run}.toml")), text).unwrap();
        }
        let out = d.join("out");
        crate::towride_ok(&[
            "validate",
            runs.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        out
    })
}

const RUNS: [&str; 6] = [
    "bump_25mm_10kmh_empty",
    "bump_25mm_30kmh_empty",
    "bump_25mm_10kmh_200kg_over_axle",
    "bump_25mm_30kmh_200kg_over_axle",
    "ramp_50mm_10kmh_empty",
    "ramp_50mm_30kmh_empty",
];

/// The run's group, from its name (obstacle_SPEEDkmh_load).
fn group_of(run: &str) -> (String, String) {
    let (obstacle, rest) = run.split_at(run.find("mm_").unwrap() + 2);
    let load = rest.splitn(3, '_').nth(2).unwrap();
    (obstacle.to_string(), load.to_string())
}

/// Layout figures of `page` in headless Chromium at 1300 px: a copy of the page runs a
/// script after its own that writes them to `<html data-measure>` as JSON: the window's
/// width, how far the page scrolls sideways, per table how many pixels of it are hidden
/// (past the window, or behind a scrolling box's edge), the first figure's width.
fn measure(page: &std::path::Path) -> serde_json::Value {
    const SCRIPT: &str = r#"<script>
const vw = document.documentElement.clientWidth;
const hidden = [...document.querySelectorAll("table")].map((t) => {
  let h = Math.max(0, t.getBoundingClientRect().right - vw);
  for (let a = t.parentElement; a; a = a.parentElement) h = Math.max(h, a.scrollWidth - a.clientWidth);
  return h;
});
const fig = document.querySelector("svg");
document.documentElement.setAttribute("data-measure", JSON.stringify({ vw, page: document.documentElement.scrollWidth - vw,
  hidden, svg: fig ? fig.getBoundingClientRect().width : null }));
</script></body>"#;
    let copy = page.with_extension("measure.html");
    let text = std::fs::read_to_string(page).unwrap();
    let text = match text.rfind("</body>") {
        Some(k) => format!("{}{SCRIPT}{}", &text[..k], &text[k + 7..]),
        None => format!("{text}{SCRIPT}"),
    };
    std::fs::write(&copy, text).unwrap();
    let profile = copy.with_extension("profile");
    let out = std::process::Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--virtual-time-budget=5000",
            "--window-size=1300,1000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("file://{}", copy.display()))
        .output()
        .expect("chromium (Debian package `chromium`) must be installed: .ci/run installs it");
    std::fs::remove_dir_all(&profile).ok();
    let dom = String::from_utf8_lossy(&out.stdout);
    let a = dom.find("data-measure=\"").expect("no measure") + 14;
    let json = dom[a..a + dom[a..].find('"').unwrap()]
        .replace("&quot;", "\"")
        .replace("&amp;", "&");
    serde_json::from_str(&json).unwrap()
}

/// No table of `page` hides any of its width at 1300 px, nor does the page scroll sideways.
fn nothing_cut_off(page: &std::path::Path) -> serde_json::Value {
    let m = measure(page);
    let hidden: Vec<f64> = m["hidden"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(!hidden.is_empty(), "{}: no table", page.display());
    assert!(
        hidden.iter().all(|h| *h <= 1.0) && m["page"].as_f64().unwrap() <= 1.0,
        "{}: tables cut off by {hidden:?} px at 1300 px: {m}",
        page.display()
    );
    m
}

#[test]
fn the_index_is_styled_like_the_other_pages_and_fits() {
    let index = folder().join("index.html");
    let text = std::fs::read_to_string(&index).unwrap();
    let css =
        std::fs::read_to_string(repo!("crates/towride-app/src/report/assets/report.css")).unwrap();
    assert!(
        text.contains(css.trim()),
        "index.html without the reports' styles"
    );
    assert!(text.contains("<html lang=\"en\">") && text.contains("<meta charset=\"utf-8\">"));
    for run in RUNS {
        assert!(text.contains(&format!("{run}/report.html")), "{run}");
    }
    nothing_cut_off(&index);
}

#[test]
fn trends_fit_a_line_per_obstacle_and_load_case_at_full_width() {
    let dir = folder();
    let csv = std::fs::read_to_string(dir.join("trends.csv")).unwrap();
    let html = std::fs::read_to_string(dir.join("trends.html")).unwrap();
    let channel = "acc_wheel_front_left_z";
    let section = html
        .split(&format!("<h2 id=\"{channel}\">"))
        .nth(1)
        .and_then(|s| s.split("<h2").next())
        .expect("a section per channel");
    // Each group's least-squares slope of peak against speed, from the CSV's numbers.
    let mut points: std::collections::BTreeMap<(String, String), Vec<[f64; 3]>> =
        Default::default();
    for line in csv.lines().skip(1).filter(|l| l.starts_with(channel)) {
        let c: Vec<&str> = line.split(',').collect();
        let v = |k: usize| c[k].parse::<f64>().unwrap();
        points
            .entry(group_of(c[1]))
            .or_default()
            .push([v(2), v(3), v(4)]);
    }
    assert_eq!(points.len(), 3, "{points:?}");
    for ((obstacle, load), p) in &points {
        for (k, kind) in [(1, "measured"), (2, "simulated")] {
            let n = p.len() as f64;
            let mx = p.iter().map(|q| q[0]).sum::<f64>() / n;
            let my = p.iter().map(|q| q[k]).sum::<f64>() / n;
            let sxy: f64 = p.iter().map(|q| (q[0] - mx) * (q[k] - my)).sum();
            let sxx: f64 = p.iter().map(|q| (q[0] - mx).powi(2)).sum();
            let want = sxy / sxx;
            let key =
                format!("data-obstacle=\"{obstacle}\" data-load=\"{load}\" data-kind=\"{kind}\"");
            let at = section
                .find(&key)
                .unwrap_or_else(|| panic!("no {kind} line for {obstacle}, {load}"));
            let slope: f64 = section[at..]
                .split("data-slope=\"")
                .nth(1)
                .and_then(|s| s.split('"').next())
                .unwrap()
                .parse()
                .unwrap();
            // The CSV's numbers are rounded to 4-6 decimals.
            assert!(
                (slope - want).abs() <= 1e-4 * want.abs().max(1e-3),
                "{obstacle}, {load} {kind}: slope {slope}, least squares {want}"
            );
        }
    }
    assert_eq!(
        section.matches("class=\"fit\"").count(),
        6,
        "one line per group and kind"
    );
    // The legend names the load cases, the panels the obstacles.
    for name in ["empty", "200kg_over_axle", ">bump_25mm<", ">ramp_50mm<"] {
        assert!(section.contains(name), "{name}");
    }
    let m = nothing_cut_off(&dir.join("trends.html"));
    let w = m["svg"].as_f64().unwrap();
    assert!(w >= 800.0, "trend figure {w} px wide at 1300 px");
}

#[test]
fn a_run_page_s_tables_fit_and_its_spectra_resolve_body_modes_within_the_band() {
    let page = folder().join("bump_25mm_10kmh_empty").join("report.html");
    nothing_cut_off(&page);
    let text = std::fs::read_to_string(&page).unwrap();
    let a = text.find("id=\"data\">").unwrap() + 10;
    let d: serde_json::Value =
        serde_json::from_str(&text[a..a + text[a..].find("</script>").unwrap()]).unwrap();
    let f: Vec<f64> = d["psd"]["f"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    // The recording: 500 Hz through a 100 Hz low-pass (its descriptor); the model at 1 kHz.
    let (bin, top) = (f[1] - f[0], f[f.len() - 1]);
    assert!(bin <= 0.25, "bins {bin} Hz apart");
    assert!(top <= 100.0 && top > 100.0 - bin, "spectra up to {top} Hz");
    // The compared window of a 10 km/h run is nearly 4 s: one segment, 1 / T apart.
    let seg = d["psd"]["segment_s"].as_f64().unwrap();
    assert!(seg > 3.5, "segment {seg} s");
    for ch in d["psd"]["channels"].as_array().unwrap() {
        assert_eq!(ch["measured"].as_array().unwrap().len(), f.len());
    }
}

/// A run's page lists the notes made reading it, each on its line (it once said "3
/// repair(s) reading the CSV, first: ..." and never named the others): three samples
/// taken out of a shipped recording are three interpolation notes, all on the page.
#[test]
fn a_run_page_lists_every_repair() {
    let d = tmp("notes");
    std::fs::create_dir_all(&d).unwrap();
    let root = repo!("");
    let run = "bump_25mm_30kmh_empty";
    let csv = std::fs::read_to_string(format!("{root}measurements/synthetic/{run}.csv")).unwrap();
    // Data lines 300, 600 and 900 (a gap of one sample each) dropped.
    let mut data = 0;
    let kept: Vec<&str> = csv
        .lines()
        .filter(|l| {
            if l.starts_with('#') || l.starts_with("time") {
                return true;
            }
            data += 1;
            data % 300 != 0 || data > 900
        })
        .collect();
    std::fs::write(d.join(format!("{run}.csv")), kept.join("\n")).unwrap();
    let toml = std::fs::read_to_string(format!("{root}measurements/synthetic/{run}.toml"))
        .unwrap()
        .replace("scene = \"../../", &format!("scene = \"{root}"));
    std::fs::write(d.join(format!("{run}.toml")), toml).unwrap();
    let out = d.join("out");
    crate::towride_ok(&[
        "validate",
        d.join(format!("{run}.toml")).to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(out.join(run).join("report.html")).unwrap();
    let a = text.find("id=\"data\">").unwrap() + 10;
    let page: serde_json::Value =
        serde_json::from_str(&text[a..a + text[a..].find("</script>").unwrap()]).unwrap();
    let lines: Vec<&str> = page["header"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l[0].as_str().unwrap())
        .collect();
    let repairs: Vec<&&str> = lines
        .iter()
        .filter(|l| l.contains("missing sample(s)") && l.contains("interpolated"))
        .collect();
    assert_eq!(repairs.len(), 3, "{lines:#?}");
    std::fs::remove_dir_all(&d).ok();
}
