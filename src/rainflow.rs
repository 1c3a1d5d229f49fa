//! `towride rainflow FILE.csv --column NAME`: the rainflow count (ASTM E1049-85 section
//! 5.4.4) of one column of any CSV with units in its header (a run's `outputs.csv`, a
//! logger export as text), its damage-equivalent load at N_ref cycles for slope m, and
//! Miner's damage sum when a reference strength is given (`docs/durability.md`).

use crate::CliResult;
use std::path::PathBuf;

use clap::Args;
use towride_app::durability::{self, csv::read_column, rainflow, RangeMeanMatrix, SnCurve};

/// Layout version of `--json`.
const SCHEMA_VERSION: u32 = 1;

#[derive(Args, Debug)]
pub struct RainflowArgs {
    /// CSV file with a header row (units as `name [unit]`).
    file: PathBuf,
    /// Column to count (its name, with or without the ` [unit]`).
    #[arg(long)]
    column: String,
    /// S-N slope m (default 3: IIW, welded steel, normal stress).
    #[arg(long, default_value_t = durability::DEFAULT_M)]
    m: f64,
    /// Reference cycle count N_ref of the DEL and of the S-N curve (default 2e6: IIW's
    /// FAT classes).
    #[arg(long, default_value_t = durability::DEFAULT_N_REF)]
    n_ref: f64,
    /// Reference range S_ref allowed N_ref times (column unit): prints Miner's damage sum.
    #[arg(long)]
    s_ref: Option<f64>,
    /// Hysteresis gate in the column's unit: reversals smaller than this are dropped.
    #[arg(long, default_value_t = 0.0)]
    gate: f64,
    /// Range bins of the range-mean matrix (means get the same number).
    #[arg(long, default_value_t = 32)]
    bins: usize,
    /// Directory for `rainflow_<column>.csv`, `_matrix.csv` and `.png`.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print one JSON document instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct Report {
    schema_version: u32,
    file: String,
    column: String,
    unit: Option<String>,
    samples: usize,
    turning_points: usize,
    gate: f64,
    cycles: f64,
    half_cycles: usize,
    full_cycles: usize,
    largest_range: f64,
    m: f64,
    n_ref: f64,
    del_at_n_ref: f64,
    s_ref: Option<f64>,
    damage: Option<f64>,
    files: Option<towride_app::report::rainflow::RainflowFiles>,
    counted: Vec<rainflow::Cycle>,
}

pub fn run(a: &RainflowArgs) -> CliResult {
    let col = read_column(&a.file, &a.column)?;
    let at = |e: durability::DurabilityError| {
        format!("{}: column `{}`: {e}", a.file.display(), col.name)
    };
    let tp = durability::turning_points(&col.values, a.gate).map_err(at)?;
    let cycles = durability::count(&tp);
    let del = durability::del(&cycles, a.m, a.n_ref).map_err(at)?;
    let damage = match a.s_ref {
        Some(s) => Some(durability::damage(
            &cycles,
            &SnCurve::new(a.m, s, a.n_ref).map_err(at)?,
        )),
        None => None,
    };
    let unit = col.unit.clone().unwrap_or_else(|| "-".into());
    let files = match &a.out {
        Some(dir) => {
            let stem = format!("rainflow_{}", col.name);
            let writes = [
                format!("{stem}.csv"),
                format!("{stem}_matrix.csv"),
                format!("{stem}.png"),
            ];
            let writes: Vec<&str> = writes.iter().map(String::as_str).collect();
            towride_app::atomic::claim(dir, "rainflow", &writes, std::slice::from_ref(&a.file))?;
            let matrix = RangeMeanMatrix::of(&cycles, a.bins, a.bins).map_err(at)?;
            let title = format!(
                "{} `{}`: {:.1} cycles, DEL {:.4e} {unit} at N_ref {:.0e} (m = {})",
                a.file.display(),
                col.name,
                rainflow::total_cycles(&cycles),
                del,
                a.n_ref,
                a.m
            );
            Some(towride_app::report::rainflow::write(
                dir, &col.name, &unit, &cycles, &matrix, &title,
            )?)
        }
        None => None,
    };
    let r = Report {
        schema_version: SCHEMA_VERSION,
        file: a.file.display().to_string(),
        column: col.name.clone(),
        unit: col.unit.clone(),
        samples: col.values.len(),
        turning_points: tp.len(),
        gate: a.gate,
        cycles: rainflow::total_cycles(&cycles),
        half_cycles: cycles.iter().filter(|c| c.count == 0.5).count(),
        full_cycles: cycles.iter().filter(|c| c.count == 1.0).count(),
        largest_range: cycles.iter().map(|c| c.range).fold(0.0, f64::max),
        m: a.m,
        n_ref: a.n_ref,
        del_at_n_ref: del,
        s_ref: a.s_ref,
        damage,
        files,
        counted: cycles,
    };
    if a.json {
        println!("{}", serde_json::to_string_pretty(&r)?);
        return Ok(0);
    }
    println!(
        "{} `{}`: {} samples, {} turning points (gate {} {unit})",
        r.file, r.column, r.samples, r.turning_points, r.gate
    );
    println!(
        "rainflow (ASTM E1049-85 5.4.4): {} cycles ({} full, {} half), largest range {:.6e} {unit}",
        r.cycles, r.full_cycles, r.half_cycles, r.largest_range
    );
    println!(
        "DEL at N_ref = {:.0e} cycles, m = {}: {:.6e} {unit}",
        r.n_ref, r.m, r.del_at_n_ref
    );
    if let (Some(s), Some(d)) = (r.s_ref, r.damage) {
        println!("Miner damage sum for S_ref = {s} {unit} at N_ref: {d:.6e}");
    }
    if let Some(f) = &r.files {
        println!("wrote {}, {} and {}", f.cycles_csv, f.matrix_csv, f.png);
    }
    Ok(0)
}
