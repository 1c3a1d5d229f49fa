//! Ranking the values of one swept parameter (the crossbeam variants) by each figure of
//! a sweep, over the band the other parameters span (speeds, loads): for every value the
//! figure's mean, smallest and largest over its completed cases, the rank by the mean's
//! magnitude (lowest first: loads, stresses, damage and accelerations are better small,
//! and a signed minimum such as the largest pull is better the nearer it is to zero), the
//! best value of each figure, so that where peak force, bracket load and damage rank
//! the variants differently shows at once. A figure that reads one signed peak at one
//! speed hides that spread; this is the summary a designer choosing a variant needs.
//!
//! Made from the summary CSV alone ([`super::page::Table`]), as the sweep's page is, so a
//! merged table of shards ranks the same.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::page::Table;
use crate::report::figure::{render, Axis, Figure, Panel, Style, Trace, PALETTE};
use crate::Error;

/// Schema of `ranking.json`.
pub const SCHEMA_VERSION: u32 = 1;

/// One value of the ranked parameter under one figure.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Entry {
    /// The parameter's value as written in the table.
    pub value: String,
    /// Mean of the figure over the value's completed cases.
    pub mean: f64,
    /// Smallest and largest over them.
    pub min: f64,
    /// See [`Entry::min`].
    pub max: f64,
    /// Completed cases with the figure.
    pub cases: usize,
    /// Cases without a result (failed, interrupted or an empty cell).
    pub missing: usize,
    /// Cases whose convergence verdict failed (`sweep --check`; 0 without it).
    pub unconverged: usize,
    /// 1 for the smallest mean.
    pub rank: usize,
}

/// One figure's ranking.
#[derive(Clone, Debug, Serialize)]
pub struct FigureRanking {
    /// The figure, `hitch_fx abs_peak [N]`.
    pub figure: String,
    /// In the order of the parameter's values in the table.
    pub entries: Vec<Entry>,
    /// The value ranked first.
    pub best: String,
    /// (max - min) / |mean| over the band, largest over the values: how much the other
    /// parameters move the figure compared with the differences being ranked.
    pub largest_spread: f64,
}

/// The ranking of a table by one parameter.
#[derive(Clone, Debug, Serialize)]
pub struct Ranking {
    /// Schema version of the JSON.
    pub schema_version: u32,
    /// The ranked parameter.
    pub by: String,
    /// The other parameters, whose values make the band.
    pub over: Vec<String>,
    /// Per figure.
    pub figures: Vec<FigureRanking>,
    /// True when not every figure ranks the same value first.
    pub rankings_disagree: bool,
}

/// Figures not worth ranking: solver effort and bookkeeping.
fn rankable(name: &str) -> bool {
    !(name.starts_with("steps")
        || name.contains("wall time")
        || name.starts_with("converged")
        || name.starts_with("convergence")
        || name.starts_with("unconverged"))
}

/// Ranks table `t` by parameter `by` over every rankable figure (or those of `only`,
/// matched by their names up to the unit).
pub fn rank(t: &Table, by: &str, only: &[String]) -> Result<Ranking, String> {
    let p = t.parameters.iter().position(|n| n == by).ok_or_else(|| {
        format!(
            "no swept parameter '{by}' (the table has {})",
            t.parameters.join(", ")
        )
    })?;
    let mut values: Vec<String> = Vec::new();
    for r in &t.rows {
        if !values.contains(&r.values[p]) {
            values.push(r.values[p].clone());
        }
    }
    let verdict = t.figures.iter().position(|f| f.starts_with("converged"));
    let stem = |f: &str| f.split(" [").next().unwrap_or(f).to_string();
    for o in only {
        if !t.figures.iter().any(|f| stem(f) == *o || f == o) {
            return Err(format!("no figure '{o}' in the table"));
        }
    }
    let mut figures = Vec::new();
    for (f, name) in t.figures.iter().enumerate() {
        let wanted = if only.is_empty() {
            rankable(name)
        } else {
            only.iter().any(|o| *o == stem(name) || o == name)
        };
        if !wanted {
            continue;
        }
        let mut entries: Vec<Entry> = values
            .iter()
            .map(|v| {
                let rows: Vec<_> = t.rows.iter().filter(|r| &r.values[p] == v).collect();
                let xs: Vec<f64> = rows
                    .iter()
                    .filter(|r| r.status == "completed")
                    .filter_map(|r| r.figures[f])
                    .filter(|x| x.is_finite())
                    .collect();
                let unconverged = verdict.map_or(0, |c| {
                    rows.iter().filter(|r| r.figures[c] == Some(0.0)).count()
                });
                let n = xs.len();
                Entry {
                    value: v.clone(),
                    mean: xs.iter().sum::<f64>() / n.max(1) as f64,
                    min: xs.iter().cloned().fold(f64::INFINITY, f64::min),
                    max: xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
                    cases: n,
                    missing: rows.len() - n,
                    unconverged,
                    rank: 0,
                }
            })
            .filter(|e| e.cases > 0)
            .collect();
        if entries.is_empty() {
            continue;
        }
        let mut order: Vec<usize> = (0..entries.len()).collect();
        // By magnitude: a figure's `min` is negative, and the most negative is the worst.
        order.sort_by(|&a, &b| entries[a].mean.abs().total_cmp(&entries[b].mean.abs()));
        for (r, &k) in order.iter().enumerate() {
            entries[k].rank = r + 1;
        }
        let largest_spread = entries
            .iter()
            .map(|e| (e.max - e.min) / e.mean.abs().max(f64::MIN_POSITIVE))
            .fold(0.0, f64::max);
        figures.push(FigureRanking {
            figure: name.clone(),
            best: entries[order[0]].value.clone(),
            entries,
            largest_spread,
        });
    }
    if figures.is_empty() {
        return Err("no figure with completed cases to rank".into());
    }
    let first = &figures[0].best;
    Ok(Ranking {
        schema_version: SCHEMA_VERSION,
        by: by.to_string(),
        over: t.parameters.iter().filter(|n| *n != by).cloned().collect(),
        rankings_disagree: figures.iter().any(|f| &f.best != first),
        figures,
    })
}

/// The files [`write`] made.
#[derive(Clone, Debug, Serialize)]
pub struct Files {
    /// `ranking.csv`: figure, value, mean, min, max, cases, missing, unconverged, rank.
    pub csv: PathBuf,
    /// `ranking.json`, the [`Ranking`].
    pub json: PathBuf,
    /// `ranking.png`: per figure the mean against the value with the band's min and max.
    pub png: PathBuf,
}

/// Writes `ranking.csv`, `ranking.json` and `ranking.png` of `r` into `dir`.
pub fn write(r: &Ranking, dir: &Path) -> Result<Files, Error> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let files = Files {
        csv: dir.join("ranking.csv"),
        json: dir.join("ranking.json"),
        png: dir.join("ranking.png"),
    };
    let mut csv = String::from("figure,value,mean,min,max,cases,missing,unconverged,rank\n");
    for f in &r.figures {
        for e in &f.entries {
            csv.push_str(&format!(
                "\"{}\",{},{},{},{},{},{},{},{}\n",
                f.figure, e.value, e.mean, e.min, e.max, e.cases, e.missing, e.unconverged, e.rank
            ));
        }
    }
    crate::atomic::write(&files.csv, csv).map_err(|e| Error::io(&files.csv, e))?;
    let json = serde_json::to_string_pretty(r).expect("a ranking serialises");
    crate::atomic::write(&files.json, json).map_err(|e| Error::io(&files.json, e))?;
    render(&files.png, &figure(r))?;
    Ok(files)
}

/// One panel per figure: the mean over the band against the ranked value (its position
/// in the table's order when the values are not numbers), the band's min and max beside.
fn figure(r: &Ranking) -> Figure {
    let panels = r
        .figures
        .iter()
        .map(|f| {
            let x = |k: usize, e: &Entry| e.value.parse::<f64>().unwrap_or(k as f64 + 1.0);
            let line = |g: fn(&Entry) -> f64| -> Vec<(f64, f64)> {
                f.entries
                    .iter()
                    .enumerate()
                    .map(|(k, e)| (x(k, e), g(e)))
                    .collect()
            };
            let (name, unit) = match f.figure.split_once(" [") {
                Some((n, u)) => (n.to_string(), u.trim_end_matches(']').to_string()),
                None => (f.figure.clone(), String::new()),
            };
            let band = Style {
                colour: PALETTE[1],
                width: 1,
                dot: 0.0,
            };
            Panel {
                // The x axis names the ranked parameter; a long figure name on the y
                // axis would run past the panel, so the title alone carries it there.
                title: format!("{name}: best {}", f.best),
                x: Axis::linear(r.by.clone()),
                y: Axis::linear(if name.len() > 28 {
                    format!("[{}]", crate::report::display::display_unit(&unit))
                } else {
                    format!("{name} [{}]", crate::report::display::display_unit(&unit))
                }),
                traces: vec![
                    Trace {
                        label: format!("mean over {}", r.over.join(", ")),
                        points: line(|e| e.mean),
                        style: Style {
                            colour: PALETTE[0],
                            width: 3,
                            dot: 4.0,
                        },
                    },
                    Trace {
                        label: "largest over the band".into(),
                        points: line(|e| e.max),
                        style: band,
                    },
                    Trace {
                        label: "smallest over the band".into(),
                        points: line(|e| e.min),
                        style: band,
                    },
                ],
            }
        })
        .collect();
    Figure {
        width: 1600,
        cols: 2,
        panel_height: 420,
        header: Vec::new(),
        panels,
    }
}
