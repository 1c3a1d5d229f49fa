//! `towride comfort FILE.csv --columns X,Y,Z`: ride comfort after ISO 2631-1:1997 of
//! acceleration columns of any CSV with units in its header (a run's `outputs.csv`, a
//! logger export): per column the weighted r.m.s. a_w, VDV, MTVV, peak and crest factor,
//! and the vibration total value of x, y and z (`docs/comfort.md`).

use crate::CliResult;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use towride_app::comfort::{self, Assessment, Axis, ColumnSpec, TimeBase, Weighting};

/// Layout version of `--json`.
const SCHEMA_VERSION: u32 = 1;

#[derive(Args, Debug)]
pub struct ComfortArgs {
    /// CSV file with a header row (units as `name [unit]`: accelerations in [m/s^2] or
    /// [g]).
    file: PathBuf,
    /// Acceleration columns, comma-separated, one per axis (names with or without the
    /// ` [unit]`).
    #[arg(long, value_delimiter = ',', required = true)]
    columns: Vec<String>,
    /// Each column's axis (x fore-aft, y lateral, z vertical), comma-separated; default:
    /// the name's last `_x`, `_y`, `_z`. The axis picks the weighting (Wd for x and y,
    /// Wk for z) and the k factor of the total value.
    #[arg(long, value_delimiter = ',')]
    axes: Vec<String>,
    /// Each column's weighting instead of its axis's (wk, wd, wf, wc, we),
    /// comma-separated; e.g. `wc` for a seat-back x column.
    #[arg(long, value_delimiter = ',')]
    weighting: Vec<String>,
    /// The time column [s] giving the sample rate.
    #[arg(long, default_value = "time", conflicts_with = "rate_hz")]
    time: String,
    /// Sample rate [Hz] of a file without a time column.
    #[arg(long)]
    rate_hz: Option<f64>,
    /// The k factors of the total value: comfort (1, 1, 1; ISO 2631-1 8.2.3) or
    /// health (1.4, 1.4, 1; 7.2.3), both for the seat surface.
    #[arg(long, value_enum, default_value_t = Use::Comfort)]
    assessment: Use,
    /// A car body file with a `[seat]` section (e.g. vehicles/fabia/body.toml): its
    /// seat model turns each vertical (z) column, taken as the floor under the seat,
    /// into the seat surface's acceleration before weighting; x and y pass through.
    #[arg(long)]
    seat: Option<PathBuf>,
    /// Print one JSON document instead of text.
    #[arg(long)]
    json: bool,
}

/// The seat applied, for `--json`.
#[derive(serde::Serialize)]
struct SeatUse {
    file: String,
    /// The z columns taken through the seat.
    columns: Vec<String>,
    resonance_hz: f64,
    peak_transmissibility: f64,
    model: comfort::Seat,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum Use {
    Comfort,
    Health,
}

#[derive(serde::Serialize)]
struct Report<'a> {
    schema_version: u32,
    file: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    seat: Option<SeatUse>,
    #[serde(flatten)]
    point: &'a comfort::PointComfort,
}

/// The per-column axis and weighting from the options.
fn specs(a: &ComfortArgs) -> Result<Vec<ColumnSpec>, String> {
    let per_column = |what: &str, n: usize| {
        if n != 0 && n != a.columns.len() {
            Err(format!(
                "--{what} lists {n} values for {} columns: give one per column",
                a.columns.len()
            ))
        } else {
            Ok(())
        }
    };
    per_column("axes", a.axes.len())?;
    per_column("weighting", a.weighting.len())?;
    let mut out = Vec::with_capacity(a.columns.len());
    for (i, column) in a.columns.iter().enumerate() {
        let axis = match a.axes.get(i) {
            Some(s) => Axis::parse(s)
                .ok_or_else(|| format!("--axes: `{s}` for column `{column}`: use x, y or z"))?,
            None => {
                Axis::of_name(column.split(" [").next().unwrap_or(column)).ok_or_else(|| {
                    format!("column `{column}`: its name does not end in _x, _y or _z; give --axes")
                })?
            }
        };
        let weighting = match a.weighting.get(i) {
            Some(s) => Weighting::parse(s).ok_or_else(|| {
                format!("--weighting: `{s}` for column `{column}`: use wk, wd, wf, wc or we")
            })?,
            None => axis.weighting(),
        };
        out.push(ColumnSpec {
            column: column.clone(),
            axis,
            weighting,
        });
    }
    Ok(out)
}

pub fn run(a: &ComfortArgs) -> CliResult {
    let specs = specs(a).map_err(|e| format!("{}: {e}", a.file.display()))?;
    let time = match a.rate_hz {
        Some(r) => TimeBase::RateHz(r),
        None => TimeBase::Column(a.time.clone()),
    };
    let (rate, mut chans) = comfort::record::read(&a.file, &time, &specs)?;
    let seat = match &a.seat {
        // The error names the body file (and its line and field) itself.
        Some(f) => Some(through_seat(f, rate, &mut chans)?),
        None => None,
    };
    let assessment = match a.assessment {
        Use::Comfort => Assessment::Comfort,
        Use::Health => Assessment::Health,
    };
    let p = comfort::evaluate(&a.file.display().to_string(), rate, &chans, assessment)
        .map_err(|e| format!("{}: {e}", a.file.display()))?;
    if a.json {
        let r = Report {
            schema_version: SCHEMA_VERSION,
            file: a.file.display().to_string(),
            seat,
            point: &p,
        };
        println!("{}", serde_json::to_string_pretty(&r)?);
        return Ok(0);
    }
    let dur = p.axes.first().map_or(0.0, |x| x.measures.duration_s);
    println!(
        "{}: {} samples at {} Hz ({:.3} s), ISO 2631-1:1997",
        p.point,
        chans.first().map_or(0, |c| c.values_m_s2.len()),
        rate,
        dur
    );
    println!(
        "  {:<28} {:>4} {:>4} {:>4} {:>11} {:>13} {:>11} {:>11} {:>6}",
        "column",
        "unit",
        "axis",
        "W",
        "a_w [m/s^2]",
        "VDV [m/s^1.75]",
        "MTVV [m/s^2]",
        "peak [m/s^2]",
        "crest"
    );
    for x in &p.axes {
        let m = &x.measures;
        println!(
            "  {:<28} {:>4} {:>4} {:>4} {:>11.4e} {:>13.4e} {:>11.4e} {:>11.4e} {:>6.2}{}",
            x.channel,
            x.unit,
            format!("{:?}", x.axis).to_lowercase(),
            x.weighting.name(),
            m.rms_m_s2,
            m.vdv_m_s1_75,
            m.mtvv_m_s2,
            m.peak_m_s2,
            m.crest_factor,
            match (x.below_resolution, x.transient) {
                (true, _) => "  round-off (peak below 0.05 m/s^2)",
                (false, true) => "  transient",
                (false, false) => "",
            }
        );
    }
    match p.total_value_m_s2 {
        Some(v) => println!(
            "  vibration total value a_v ({:?}, k = {:?}): {v:.4e} m/s^2",
            assessment,
            assessment.k()
        ),
        None => println!("  no vibration total value: it needs one x, one y and one z column"),
    }
    if let Some(s) = &seat {
        println!(
            "  seat surface: {} through the seat of {} (largest |T| {:.3} at {:.3} Hz); x and y as the floor's",
            s.columns.join(", "),
            s.file,
            s.peak_transmissibility,
            s.resonance_hz
        );
    }
    if p.transient {
        println!("  transient: {}", p.note);
    }
    Ok(0)
}

/// Takes the z columns of `chans` through the seat of the body file `file` (their names
/// get ` (seat surface)`); an error when the file has no valid `[seat]` or no column is
/// vertical.
fn through_seat(
    file: &std::path::Path,
    rate: f64,
    chans: &mut [comfort::record::Channel],
) -> Result<SeatUse, String> {
    let seat = comfort::seat::read(file).map_err(|e| format!("--seat: {e}"))?;
    let filter = comfort::SeatFilter::new(&seat, rate);
    let mut columns = Vec::new();
    for c in chans.iter_mut().filter(|c| c.spec.axis == Axis::Z) {
        c.values_m_s2 = filter.apply(&c.values_m_s2);
        columns.push(c.name.clone());
        c.name = format!("{} (seat surface)", c.name);
    }
    if columns.is_empty() {
        return Err(format!(
            "--seat {}: no vertical (z) column to take through the seat",
            file.display()
        ));
    }
    let (resonance_hz, peak_transmissibility) = seat.resonance();
    Ok(SeatUse {
        file: file.display().to_string(),
        columns,
        resonance_hz,
        peak_transmissibility,
        model: seat,
    })
}
