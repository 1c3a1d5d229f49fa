//! `towride road ROAD.toml`: samples any road along its two tracks and writes the profile
//! (`road_profile.csv`, `road_profile.png`); for an ISO 8608 random road also each
//! track's displacement PSD against the class band (`road_psd.png`) and the verdict.

use crate::CliResult;
use std::path::PathBuf;

use clap::Args;
use towride_app::report::road::{sample, SampleRequest, WRITES};
use towride_mbs::road::Road;

#[derive(Args, Debug)]
pub struct RoadArgs {
    /// Road file (TOML with [road] and, for a flat road, [[obstacle]]).
    file: PathBuf,
    /// Output folder for road_profile.csv, road_profile.png and road_psd.png.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Length to sample [m] from the road's start (default: the road's data, or its
    /// obstacles plus 1 m; required for a flat road without obstacles).
    #[arg(long)]
    length_m: Option<f64>,
    /// Sample spacing [m] (default: a random road's own spacing, else 5 mm).
    #[arg(long)]
    dx_m: Option<f64>,
    /// Track width [m] for roads that have none (flat, height field); default: the road's.
    #[arg(long)]
    track_width_m: Option<f64>,
    /// Print a JSON document instead of text.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    inputs: crate::inputs::InputArgs,
}

pub fn run(a: &RoadArgs) -> CliResult {
    let loader = a.inputs.loader()?;
    let road = Road::from_file(&a.file, &loader)?;
    loader.check_used()?;
    for (name, v) in [
        ("--length-m", a.length_m),
        ("--dx-m", a.dx_m),
        ("--track-width-m", a.track_width_m),
    ] {
        if let Some(v) = v {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name}: must be a positive number, got {v}").into());
            }
        }
    }
    let spec = road.random_spec();
    let track_width = match (a.track_width_m, road.track_width()) {
        (Some(w), _) | (None, Some(w)) => w,
        (None, None) => {
            return Err(format!(
                "{}: this road has no tracks of its own: give --track-width-m",
                a.file.display()
            )
            .into())
        }
    };
    // 5 mm resolves the shipped obstacles' flanks (the shortest is 10 mm).
    let dx = a
        .dx_m
        .or(spec.map(|s| s.length / s.samples() as f64))
        .unwrap_or(0.005);
    let (x_from, x_to) = match (road.x_extent(), a.length_m) {
        (Some((lo, _)), Some(l)) => (lo.min(0.0), lo.min(0.0) + l),
        (None, Some(l)) => (0.0, l),
        (Some((lo, hi)), None) if spec.is_some() => (lo, hi),
        (Some((lo, hi)), None) => (lo.min(0.0), hi + 1.0),
        (None, None) => {
            return Err(format!(
                "{}: a road without obstacles or data has no length of its own: give --length-m",
                a.file.display()
            )
            .into())
        }
    };
    if (x_to - x_from) / dx > 5e7 {
        return Err(format!("--dx-m {dx}: {} samples is too many", (x_to - x_from) / dx).into());
    }
    let mut inputs = loader.files_read();
    inputs.push(a.file.clone());
    towride_app::atomic::claim(&a.out, "road", &WRITES, &inputs)?;
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let req = SampleRequest {
        x_from,
        x_to,
        dx,
        track_width,
    };
    let s = sample(&road, &a.file, &req, &a.out)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&s)?);
        return Ok(0);
    }
    println!("{}: {}", s.file, s.road);
    println!(
        "sampled x {:.3}..{:.3} m every {} m ({} points), tracks at y = +-{} m",
        s.x_from_m,
        s.x_to_m,
        s.dx_m,
        s.samples,
        s.track_width_m / 2.0
    );
    println!(
        "left z {:.4}..{:.4} m, right z {:.4}..{:.4} m",
        s.z_left_min_m, s.z_left_max_m, s.z_right_min_m, s.z_right_max_m
    );
    if let Some(p) = &s.psd {
        println!(
            "PSD (Welch, {} samples, {:.4} cycles/m): inside the {} band {:e}..{:e} m^3 at n0 from {} to {} cycles/m: left {:.1} % of {} bins (fitted Gd(n0) {:.3e} m^3), right {:.1} % (fitted {:.3e} m^3)",
            p.welch_segment,
            p.resolution_cycles_per_m,
            p.class.map_or("given".into(), |c| format!("class {c}")),
            p.lower_m3,
            p.upper_m3,
            p.band_cycles_per_m[0],
            p.band_cycles_per_m[1],
            100.0 * p.left.fraction_inside,
            p.left.bins_in_band,
            p.left.fitted_gd_n0_m3,
            100.0 * p.right.fraction_inside,
            p.right.fitted_gd_n0_m3
        );
        println!("wrote {}, {} and {}", s.csv, s.png, p.png);
    } else {
        println!("wrote {} and {}", s.csv, s.png);
    }
    Ok(0)
}
