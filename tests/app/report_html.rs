//! The run's HTML report: Welch spectra against Parseval and known tones, the page
//! self-contained (no network) with the run's data, and in headless Chromium (Debian
//! package `chromium`, installed by `.ci/run`) without a JavaScript error and with every
//! chart drawn.

use std::path::{Path, PathBuf};
use std::process::Command;

use towride_app::job::Job;
use towride_app::signal::psd::{segment_length, welch};
use towride_mbs::input::Loader;

#[test]
fn welch_psd_finds_tones_and_keeps_the_power() {
    let fs = 1000.0;
    let n = 4096;
    let (a1, f1, a2, f2) = (2.0, 50.0, 0.5, 125.0);
    let y: Vec<f64> = (0..n)
        .map(|k| {
            let t = k as f64 / fs;
            3.0 + a1 * (2.0 * std::f64::consts::PI * f1 * t).sin()
                + a2 * (2.0 * std::f64::consts::PI * f2 * t + 0.3).sin()
        })
        .collect();
    let len = segment_length(n, 1024);
    assert_eq!(len, 1024);
    let p = welch(&y, fs, len).unwrap();
    let df = p.freq[1] - p.freq[0];
    assert!((df - fs / 1024.0).abs() < 1e-12);
    // Parseval: the density integrates to the variance, a1²/2 + a2²/2 (the mean is
    // taken out per segment).
    let power: f64 = p.density.iter().sum::<f64>() * df;
    let want = (a1 * a1 + a2 * a2) / 2.0;
    assert!((power / want - 1.0).abs() < 0.01, "power {power} vs {want}");
    // The two largest local maxima lie within a bin of the tones.
    let mut peaks: Vec<(f64, f64)> = (1..p.density.len() - 1)
        .filter(|&k| p.density[k] > p.density[k - 1] && p.density[k] >= p.density[k + 1])
        .map(|k| (p.density[k], p.freq[k]))
        .collect();
    peaks.sort_by(|a, b| b.0.total_cmp(&a.0));
    assert!((peaks[0].1 - f1).abs() <= df, "{peaks:?}");
    assert!((peaks[1].1 - f2).abs() <= df, "{peaks:?}");
    // Too short, or not finite: no spectrum.
    assert!(welch(&y[..100], fs, 128).is_none());
    let mut bad = y.clone();
    bad[7] = f64::NAN;
    assert!(welch(&bad, fs, len).is_none());
}

/// Runs the default scene once and writes its files into a fresh folder.
fn default_run(tag: &str) -> (PathBuf, towride_app::job::RunResult) {
    let dir = std::env::temp_dir().join(format!("towride-report-{tag}-{}", std::process::id()));
    let job = Job::from_file(Path::new(repo!("scenes/default.toml")), &Loader::new()).unwrap();
    let mut res = job.run(&towride_mbs::progress::Silent).unwrap();
    towride_app::report::write_run(&mut res, &job.system, &dir).unwrap();
    (dir, res)
}

/// Number of bodies of the default scene's model.
fn default_bodies() -> usize {
    let job = Job::from_file(Path::new(repo!("scenes/default.toml")), &Loader::new()).unwrap();
    job.system.model.bodies.len()
}

/// The JSON the page embeds.
fn embedded(html: &str) -> serde_json::Value {
    let open = "<script type=\"application/json\" id=\"data\">";
    let start = html.find(open).unwrap() + open.len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end]).unwrap()
}

#[test]
fn report_is_self_contained_and_carries_the_run() {
    let (dir, res) = default_run("page");
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    // Nothing fetched: no external scripts, styles, images or links (three.js holds an
    // image loader's `a.src=t`, which nothing calls).
    for attr in ["src=\"", "href=\"", "src='", "href='", "@import", "url("] {
        assert!(!html.contains(attr), "{attr} in the page");
    }
    assert!(html.contains("uPlot") && html.contains("THREE"));
    let d = embedded(&html);
    let chans = d["channels"].as_array().unwrap();
    assert_eq!(chans.len(), res.samples.channels.len());
    // hitch_fx decoded from the page's integers against the run's samples.
    let c = res
        .samples
        .channels
        .iter()
        .position(|c| c.name == "hitch_fx")
        .unwrap();
    let v = &chans[c]["v"];
    let s = v["s"].as_f64().unwrap();
    let q = v["q"].as_array().unwrap();
    assert_eq!(q.len(), res.samples.times.len());
    let peak = res.abs_peak("hitch_fx").unwrap();
    for (k, qk) in q.iter().enumerate() {
        let got = qk.as_f64().unwrap() * s;
        assert!(
            (got - res.samples.rows[k][c]).abs() <= 1e-6 * peak,
            "sample {k}: {got} vs {}",
            res.samples.rows[k][c]
        );
    }
    // Step history and spectra are there; the summary records the page.
    assert_eq!(
        d["steps"]["h"].as_array().unwrap().len(),
        res.summary.solver.steps
    );
    assert!(d["psd"]["density"][c].as_array().unwrap().len() > 100);
    // The 3D view: 200 Hz poses over the 3 s run, every body, a tyre per wheel, the road
    // with the ramp (50 mm, roads/ramp_thesis.toml).
    let v = &d["view"];
    let times = v["frames"]["t"]["q"].as_array().unwrap();
    assert_eq!(times.len(), 601);
    assert_eq!(
        v["bodies"].as_array().unwrap().len(),
        default_bodies(),
        "bodies drawn"
    );
    assert_eq!(v["tyres"].as_array().unwrap().len(), 6);
    let rows = v["road"]["z"].as_array().unwrap();
    let middle = &rows[rows.len() / 2];
    let top = middle
        .as_array()
        .unwrap()
        .iter()
        .map(|z| z.as_f64().unwrap())
        .fold(f64::NEG_INFINITY, f64::max);
    let base = middle[0].as_f64().unwrap();
    assert!(
        (top - base - 0.05).abs() < 1e-6,
        "ramp height {}",
        top - base
    );
    assert!(res
        .summary
        .report
        .as_deref()
        .unwrap()
        .ends_with("report.html"));
    std::fs::remove_dir_all(&dir).ok();
}

fn chromium(args: &[&str], profile: &Path) -> std::process::Output {
    Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            // WebGL for the 3D view in software (Chromium refuses the software fallback
            // without it in newer releases).
            "--enable-unsafe-swiftshader",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--virtual-time-budget=5000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(args)
        .output()
        .expect("chromium (Debian package `chromium`) must be installed: .ci/run installs it")
}

/// An attribute of the first tag `tag` in `dom`.
fn attribute(dom: &str, tag: &str, name: &str) -> Option<String> {
    let start = dom.find(&format!("<{tag}"))?;
    let end = start + dom[start..].find('>')?;
    let t = &dom[start..end];
    let key = format!("{name}=\"");
    let a = t.find(&key)? + key.len();
    Some(t[a..a + t[a..].find('"')?].to_string())
}

#[test]
fn report_opens_in_chromium_without_errors_and_draws_every_chart() {
    let (dir, _) = default_run("browser");
    let page = dir.join("report.html");
    let url = format!("file://{}", page.display());
    let profile = dir.join("profile");
    let out = chromium(&["--window-size=1400,1000", "--dump-dom", &url], &profile);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let dom = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        attribute(&dom, "html", "data-errors"),
        None,
        "JavaScript error"
    );
    let ready: usize = attribute(&dom, "body", "data-ready")
        .expect("the report's script did not finish")
        .parse()
        .unwrap();
    // The run page's 8 panels and the other channels, the spectrum, the step history.
    assert!(ready >= 11, "{ready} charts");
    let coloured = attribute(&dom, "body", "data-coloured-pixels").unwrap();
    let counts: Vec<usize> = coloured.split(',').map(|c| c.parse().unwrap()).collect();
    assert_eq!(counts.len(), ready);
    for (k, n) in counts.iter().enumerate() {
        assert!(*n > 500, "chart {k} drew {n} coloured pixels");
    }
    // The 3D view is drawn (WebGL works, or the test says why not) and moves: its pixels
    // at 5 % and at 50 % of the run.
    let view = attribute(&dom, "body", "data-view");
    assert_eq!(
        view.as_deref(),
        Some("ok"),
        "the 3D view was not drawn (WebGL in headless Chromium: --enable-unsafe-swiftshader)"
    );
    let px = attribute(&dom, "body", "data-view-pixels").unwrap();
    let shots: Vec<Vec<u64>> = px
        .split(';')
        .map(|p| p.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    for s in &shots {
        assert!(s[0] > 20_000, "3D view drew {} pixels: {px}", s[0]);
    }
    assert_ne!(
        shots[0][1], shots[1][1],
        "the 3D view does not change with time"
    );
    // Screenshots at two animation times (#view-t=...) differ in the view.
    let at = |t: &str| {
        let shot = dir.join(format!("view-{t}.png"));
        let arg = format!("--screenshot={}", shot.display());
        let u = format!("{url}#view-t={t}");
        let out = chromium(&["--window-size=1400,1000", &arg, &u], &profile);
        assert!(out.status.success());
        image::open(&shot).unwrap().to_rgb8()
    };
    let (a, b) = (at("0.07"), at("0.5"));
    let differ = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 30))
        .count();
    assert!(
        differ > 5000,
        "{differ} pixels differ between t = 0.07 s and 0.5 s"
    );
    // The screenshot as a user sees it is not blank: traces in colour.
    let shot = dir.join("shot.png");
    let arg = format!("--screenshot={}", shot.display());
    let out = chromium(&["--window-size=1400,1400", &arg, &url], &profile);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let img = image::open(&shot).unwrap().to_rgb8();
    let colour = img
        .pixels()
        .filter(|p| p.0.iter().max().unwrap() - p.0.iter().min().unwrap() > 40)
        .count();
    assert!(colour > 5000, "{colour} coloured pixels in the screenshot");
    // The comparison page of this run against itself opens without errors too.
    let run = towride_app::report::compare::load(&dir).unwrap();
    let runs = vec![run.clone(), run];
    let mut c = towride_app::report::compare::compare(&runs).unwrap();
    let cmp = dir.join("cmp");
    towride_app::report::compare::write(&runs, &mut c, &cmp, "png").unwrap();
    let url = format!("file://{}", cmp.join("compare.html").display());
    let out = chromium(&["--window-size=1400,1000", "--dump-dom", &url], &profile);
    let dom = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        attribute(&dom, "html", "data-errors"),
        None,
        "JavaScript error"
    );
    assert_eq!(attribute(&dom, "body", "data-ready").as_deref(), Some("1"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn linear_page_opens_in_chromium_and_animates_a_mode() {
    let dir = std::env::temp_dir().join(format!("towride-linear-{}", std::process::id()));
    let job = Job::from_file(Path::new(repo!("scenes/default.toml")), &Loader::new()).unwrap();
    let st = towride_mbs::model::statics::equilibrium(&job.system, 0.0, &job.solver).unwrap();
    let lin = towride_mbs::model::linear::linearise(&job.system, 0.0, &st.y).unwrap();
    let page =
        towride_app::report::linear::write(&dir, &job.system, &st.y, &lin, "equilibrium").unwrap();
    // The car body's bounce and pitch are named as such, in the 1-2 Hz ride band; its
    // roll about the low roll axis there too, where at rest, on the tyres' lateral
    // stiffness, it couples with the lateral motion (named by the larger share).
    for motion in ["bounce", "pitch"] {
        let name = format!("car_body {motion}");
        let m = lin.modes.iter().find(|m| m.name == name);
        let f = m.map(|m| m.undamped_hz).unwrap_or(f64::NAN);
        assert!((1.0..2.5).contains(&f), "{name}: {f} Hz");
    }
    let roll = |m: &towride_mbs::model::linear::Mode| {
        m.motions
            .iter()
            .find(|s| s.name == "car_body roll")
            .map_or(0.0, |s| s.share)
    };
    assert!(
        lin.modes
            .iter()
            .any(|m| (1.0..2.5).contains(&m.undamped_hz) && roll(m) > 0.3),
        "no car_body roll mode in 1-2.5 Hz"
    );
    let url = format!("file://{}#mode=12", page.display());
    let out = chromium(
        &["--window-size=1400,1000", "--dump-dom", &url],
        &dir.join("p"),
    );
    let dom = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        attribute(&dom, "html", "data-errors"),
        None,
        "JavaScript error"
    );
    assert_eq!(attribute(&dom, "body", "data-ready").as_deref(), Some("1"));
    assert_eq!(attribute(&dom, "body", "data-view").as_deref(), Some("ok"));
    let px = attribute(&dom, "body", "data-view-pixels").unwrap();
    let (a, b) = px.split_once(';').unwrap();
    assert_ne!(a, b, "the mode shape does not move");
    std::fs::remove_dir_all(&dir).ok();
}
