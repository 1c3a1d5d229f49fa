//! Damage per kilometre for a usage spectrum the study file declares (`[usage]`,
//! `docs/durability.md` "Damage per kilometre"): obstacles met per km and a mix of the
//! swept cases (speed, load) with their shares. Palmgren-Miner damage adds over the
//! passages (Miner 1945), so per km
//!
//! D_km = n_obstacles_per_km * sum_j share_j D_passage(case_j),
//!
//! for each value of the parameters the mix leaves free (the crossbeam variant), and
//! the distance to the allowable sum is D_allowable / D_km (IIW-2259-15, chapter 4:
//! D = 0.5 for steel; [`crate::durability::iiw::D_ALLOWABLE_STEEL`]).

use serde::{Deserialize, Serialize};

use super::page::Table;
use towride_mbs::input::provenance::{read_provenance, ProvenanceEntry};
use towride_mbs::input::{InputError, Source};
use towride_mbs::path;

/// The `[usage]` table as read.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(super) struct UsageIn {
    obstacles_per_km: f64,
    mix: Vec<toml::Table>,
}

/// One entry of the mix: the swept values it fixes and its share of the passages.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Mix {
    /// (parameter, value as TOML text), in the file's order.
    pub values: Vec<(String, String)>,
    /// Share of the passages [-] (the shares add to 1).
    pub share: f64,
}

/// A validated usage spectrum.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Usage {
    /// Obstacles (passages) per kilometre [1/km].
    pub obstacles_per_km: f64,
    /// The mix of cases.
    pub mix: Vec<Mix>,
    /// The source classes the study file gives the block's values (`usage.*`).
    pub provenance: Vec<ProvenanceEntry>,
}

/// The figures damage per km is made of: a per-passage Miner sum.
pub fn is_damage_figure(name: &str) -> bool {
    name.ends_with("damage per passage [-]")
}

impl UsageIn {
    /// Checks the block against the sweep's parameters (`name`, values as TOML text).
    pub(super) fn check(
        &self,
        src: &Source,
        params: &[(String, Vec<String>)],
    ) -> Result<Usage, InputError> {
        let opk = src.positive(&path!["usage", "obstacles_per_km"], self.obstacles_per_km)?;
        if self.mix.is_empty() {
            return Err(src.error(&path!["usage", "mix"], "is empty"));
        }
        let mut mix = Vec::new();
        let mut keys: Option<Vec<String>> = None;
        for (i, m) in self.mix.iter().enumerate() {
            let at = |k: &str| path!["usage", "mix", i, k.to_string()];
            let share = match m.get("share").and_then(|v| v.as_float()) {
                Some(s) => src.positive(&at("share"), s)?,
                None => return Err(src.error(&at("share"), "missing (a number > 0)")),
            };
            let mut values = Vec::new();
            for (k, v) in m.iter().filter(|(k, _)| k.as_str() != "share") {
                let Some((_, allowed)) = params.iter().find(|(n, _)| n == k) else {
                    return Err(src.error(&at(k), "is not a swept parameter"));
                };
                let text = towride_mbs::input::value_text(v);
                if !allowed.iter().any(|a| same_value(a, &text)) {
                    return Err(src.error(
                        &at(k),
                        format!("{text} is not among the swept values {allowed:?}"),
                    ));
                }
                values.push((k.clone(), text));
            }
            let these: Vec<String> = values.iter().map(|(k, _)| k.clone()).collect();
            if keys.get_or_insert_with(|| these.clone()) != &these {
                return Err(src.error(
                    &path!["usage", "mix", i],
                    "every entry must fix the same parameters",
                ));
            }
            mix.push(Mix { values, share });
        }
        let total: f64 = mix.iter().map(|m| m.share).sum();
        if (total - 1.0).abs() > 1e-9 {
            return Err(src.error(
                &path!["usage", "mix"],
                format!("the shares add to {total}, not 1"),
            ));
        }
        // The spectrum's tags, shown beside its damage (an assumed spectrum says so).
        let provenance = read_provenance(&src.path)
            .unwrap_or_default()
            .into_iter()
            .filter(|e| e.key.starts_with("usage."))
            .collect();
        Ok(Usage {
            obstacles_per_km: opk,
            mix,
            provenance,
        })
    }
}

/// Two values as TOML text or as written in a table: equal as numbers or as strings
/// without quotes.
pub(crate) fn same_value(a: &str, b: &str) -> bool {
    let t = |s: &str| s.trim().trim_matches('"').to_string();
    match (t(a).parse::<f64>(), t(b).parse::<f64>()) {
        (Ok(x), Ok(y)) => x == y,
        _ => t(a) == t(b),
    }
}

/// Damage per km of one group (the values of the parameters the mix leaves free).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PerKm {
    /// (parameter, value) of the group.
    pub group: Vec<(String, String)>,
    /// The per-passage figure it sums (`hitch_stress_mid_span IIW damage per passage [-]`).
    pub figure: String,
    /// Damage per km [1/km]; `None` when a case of the mix has no figure.
    pub damage_per_km: Option<f64>,
    /// Distance to the allowable Miner sum [km].
    pub km_to_allowable: Option<f64>,
}

/// Damage per km of every group and damage figure of `table`.
pub fn per_km(table: &Table, usage: &Usage) -> Vec<PerKm> {
    let fixed: Vec<&String> = usage.mix[0].values.iter().map(|(k, _)| k).collect();
    let free: Vec<usize> = (0..table.parameters.len())
        .filter(|&i| !fixed.contains(&&table.parameters[i]))
        .collect();
    let mut groups: Vec<Vec<String>> = Vec::new();
    for r in &table.rows {
        let g: Vec<String> = free.iter().map(|&i| r.values[i].clone()).collect();
        if !groups.contains(&g) {
            groups.push(g);
        }
    }
    let col = |n: &str| table.parameters.iter().position(|p| p == n);
    let mut out = Vec::new();
    for g in &groups {
        for (f, name) in table.figures.iter().enumerate() {
            if !is_damage_figure(name) {
                continue;
            }
            let d: Option<f64> = usage
                .mix
                .iter()
                .map(|m| {
                    let row = table.rows.iter().find(|r| {
                        r.status == "completed"
                            && free.iter().zip(g).all(|(&i, v)| &r.values[i] == v)
                            && m.values
                                .iter()
                                .all(|(k, v)| col(k).is_some_and(|c| same_value(&r.values[c], v)))
                    })?;
                    Some(m.share * row.figures[f]?)
                })
                .sum::<Option<f64>>()
                .map(|s| usage.obstacles_per_km * s);
            out.push(PerKm {
                group: free
                    .iter()
                    .zip(g)
                    .map(|(&i, v)| (table.parameters[i].clone(), v.clone()))
                    .collect(),
                figure: name.clone(),
                damage_per_km: d,
                km_to_allowable: d.map(|d| crate::durability::iiw::D_ALLOWABLE_STEEL / d),
            });
        }
    }
    out
}
