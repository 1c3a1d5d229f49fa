//! What a run's figures and pages show a reader: the scene's `[[output]]` channels on a
//! page of their own with titles in words, angles in degrees (the CSV keeps radians),
//! channels in natural order, one display form of units, and tick labels without SI
//! prefixes (on an axis of seconds "10m" reads as ten minutes).

use std::path::{Path, PathBuf};

use towride_app::job::{Job, RunResult};
use towride_app::report::display::{display_unit, natural_cmp};
use towride_app::report::run_outputs::output_panels;
use towride_app::report::ticks::{labels, log_labels};
use towride_mbs::input::Loader;

/// The default scene (paths made absolute) asking for the four suspension travels (in
/// a shuffled order) and the body's pitch, run and written into a fresh folder.
fn run_with_outputs(tag: &str) -> (PathBuf, RunResult, Vec<String>) {
    let root = Path::new(repo!("")).canonicalize().unwrap();
    let text = std::fs::read_to_string(root.join("scenes/default.toml"))
        .unwrap()
        .replace("\"../", &format!("\"{}/", root.display()));
    let dir = std::env::temp_dir().join(format!("towride-runfigs-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let asked = [
        "susp_rr_travel",
        "susp_fl_travel",
        "susp_rl_travel",
        "susp_fr_travel",
        "body_pitch",
    ];
    let extra: String = asked
        .iter()
        .map(|q| format!("\n[[output]]\nquantity = \"{q}\"\n"))
        .collect();
    let file = dir.join("scene.toml");
    std::fs::write(&file, format!("{text}\n{extra}")).unwrap();
    let job = Job::from_file(&file, &Loader::new()).unwrap();
    let mut res = job.run(&towride_mbs::progress::Silent).unwrap();
    let out = dir.join("run");
    towride_app::report::write_run(&mut res, &job.system, &out).unwrap();
    (out, res, asked.iter().map(|s| s.to_string()).collect())
}

/// A column of `outputs.csv` by its header.
fn csv_column(path: &Path, header: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = head.iter().position(|h| *h == header).expect(header);
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

#[test]
fn output_channels_get_a_page_with_titles_in_words_and_angles_in_degrees() {
    let (dir, res, asked) = run_with_outputs("page");
    // The page is written and the summary names it.
    let png = dir.join("plots_outputs.png");
    let img = image::open(&png).expect("plots_outputs.png").to_rgb8();
    assert!(img.width() >= 1000 && img.height() >= 500);
    let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let s: serde_json::Value = serde_json::from_str(&summary).unwrap();
    assert_eq!(s["plots_outputs"].as_str(), png.to_str());

    let panels = output_panels(&res.samples, &asked);
    let titles: Vec<&str> = panels.iter().map(|p| p.title.as_str()).collect();
    assert_eq!(titles, ["suspension travel, car wheels", "body pitch"]);
    // Legend in natural order whatever order the scene asked in.
    let legend: Vec<&str> = panels[0].traces.iter().map(|t| t.label.as_str()).collect();
    assert_eq!(
        legend,
        [
            "susp_fl_travel",
            "susp_fr_travel",
            "susp_rl_travel",
            "susp_rr_travel"
        ]
    );
    assert_eq!(panels[0].y.label, "displacement [m]");
    // The pitch: radians in the CSV, degrees on the figure.
    let pitch = &panels[1];
    assert_eq!(pitch.y.label, "angle [deg]");
    let rad = csv_column(&dir.join("outputs.csv"), "body_pitch [rad]");
    let peak_rad = rad.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(peak_rad > 1e-3, "the ramp pitches the body: {peak_rad} rad");
    let drawn = &pitch.traces[0].points;
    assert_eq!(drawn.len(), rad.len());
    for (p, r) in drawn.iter().zip(&rad) {
        // CSV values carry ten significant digits.
        assert!((p.1 - r * 57.295_779_513_082_32).abs() <= 1e-8 * (1.0 + p.1.abs()));
    }
    std::fs::remove_dir_all(dir.parent().unwrap()).ok();
}

#[test]
fn channels_are_listed_in_natural_order() {
    let mut names = vec![
        "hitch_eta_10",
        "hitch_eta_2",
        "hitch_eta_1",
        "acc_x",
        "hitch_eta_11",
        "hitch_eta_9",
    ];
    names.sort_by(|a, b| natural_cmp(a, b));
    assert_eq!(
        names,
        [
            "acc_x",
            "hitch_eta_1",
            "hitch_eta_2",
            "hitch_eta_9",
            "hitch_eta_10",
            "hitch_eta_11"
        ]
    );
    // summary.json (and the report that embeds it) writes its channels in that order.
    let (dir, res, _) = run_with_outputs("order");
    let n = res
        .samples
        .channels
        .iter()
        .filter(|c| c.name.starts_with("hitch_eta_"))
        .count();
    assert!(n >= 10, "{n} modal coordinates");
    for file in ["summary.json", "report.html"] {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        let at = |k: usize| text.find(&format!("\"hitch_eta_{k}\":")).unwrap();
        for k in 1..n {
            assert!(at(k) < at(k + 1), "{file}: hitch_eta_{k} after {}", k + 1);
        }
    }
    std::fs::remove_dir_all(dir.parent().unwrap()).ok();
}

#[test]
fn units_have_one_display_form_on_figures_and_pages() {
    assert_eq!(display_unit("m/s^2"), "m/s²");
    assert_eq!(display_unit("rad/s^2"), "rad/s²");
    assert_eq!(display_unit("kg m^2"), "kg m²");
    assert_eq!(display_unit("N"), "N");
    let (dir, _, _) = run_with_outputs("units");
    // The CSV keeps ASCII.
    let csv = std::fs::read_to_string(dir.join("outputs.csv")).unwrap();
    assert!(csv.lines().next().unwrap().contains("trailer_ax [m/s^2]"));
    // The report's charts: legends and axes in the display form, angles in degrees.
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let open = "<script type=\"application/json\" id=\"data\">";
    let start = html.find(open).unwrap() + open.len();
    let end = start + html[start..].find("</script>").unwrap();
    let d: serde_json::Value = serde_json::from_str(&html[start..end]).unwrap();
    let chans = d["channels"].as_array().unwrap();
    let du = |name: &str| {
        chans.iter().find(|c| c["name"] == name).unwrap()["du"]
            .as_str()
            .unwrap()
            .to_string()
    };
    assert_eq!(du("trailer_ax"), "m/s²");
    assert_eq!(du("body_pitch"), "deg");
    assert_eq!(d["units"]["m/s^2"], "m/s²");
    for g in d["groups"].as_array().unwrap() {
        let y = g["y"].as_str().unwrap();
        assert!(!y.contains('^'), "axis {y}");
        assert!(!g["title"].as_str().unwrap().contains('*'), "{g}");
    }
    std::fs::remove_dir_all(dir.parent().unwrap()).ok();
}

#[test]
fn tick_labels_are_plain_numbers_without_si_prefixes() {
    let letters = |l: &Vec<String>| l.iter().any(|s| s.chars().any(|c| c.is_alphabetic()));
    // Wall times of 10 ms to 0.5 s: "10m" was read as ten minutes.
    let l = log_labels(&[0.01, 0.02, 0.05, 0.1, 0.2, 0.5], 2);
    assert_eq!(l, ["0.01", "0.02", "0.05", "0.1", "0.2", "0.5"]);
    // Beyond 0.001 every tick of the axis as a power of ten, none as a prefix.
    let l = log_labels(&[2e-4, 5e-4, 1e-3, 2e-3], 2);
    assert_eq!(l, ["2×10⁻⁴", "5×10⁻⁴", "10⁻³", "2×10⁻³"]);
    assert!(!letters(&l));
    let l = labels(&[0.0, 2e-8, 4e-8, 6e-8, 8e-8, 1e-7], 2e-8);
    assert!(!letters(&l), "{l:?}");
    assert_eq!(l[1], "0.2×10⁻⁷");
    // Tyre forces up to 12 kN in plain newtons.
    let l = labels(&[0.0, 4000.0, 8000.0, 12000.0], 4000.0);
    assert_eq!(l, ["0", "4000", "8000", "12000"]);
}
