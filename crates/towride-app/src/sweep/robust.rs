//! The `[robustness]` block of a study file: which property-file values to move, over
//! which range, on which part of the grid, to ask whether the ranking of the variants
//! holds when the inputs nobody measured move (docs/durability.md, "Robustness of the
//! ranking"). The runs and the comparison are in [`super::robust_run`].
//!
//! ```toml
//! [robustness]
//! params = ["box_trailer.toml:half.mass_kg"]  # FILE:PATH, as `sensitivity --params`
//! top = 3              # and/or the 3 highest-ranked [assumed] values of a study
//! study = "out/sensitivity/scenes_default/sensitivity.json"  # default: the scene's
//! range = 0.3          # each value times 1 -+ range (narrowed as sensitivity does)
//! by = "hitch_variant" # the ranked parameter (default: hitch_variant, else the first)
//! figures = ["hitch_fx abs_peak"]  # default: every figure `sweep rank` ranks
//! subset = { speed_km_h = [45.0, 50.0, 55.0] }  # part of the grid re-run
//! ```
//!
//! A value's range is the sensitivity machinery's: a study's own range for a value taken
//! from it (`top`), else [`crate::study::sensitivity::settings::range_of`] (1 -+ `range`
//! within the value's plausibility bounds or a tyre factor's open range).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::usage::same_value;
use crate::study::sensitivity::assumed::{ranked, Class};
use crate::study::sensitivity::params::{candidates, named, Param};
use crate::study::sensitivity::settings::range_of;
use crate::study::sensitivity::{default_dir, Settings};
use towride_mbs::input::provenance::read_provenance;
use towride_mbs::input::{InputError, Loader, Origin, Override, Source};
use towride_mbs::path;
use towride_mbs::tyre::factors;

/// The block as read.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(super) struct RobustnessIn {
    #[serde(default)]
    params: Vec<String>,
    top: Option<usize>,
    study: Option<String>,
    range: Option<f64>,
    by: Option<String>,
    #[serde(default)]
    figures: Vec<String>,
    #[serde(default)]
    subset: toml::Table,
}

/// One value moved to each end of its range.
#[derive(Clone, Debug, Serialize)]
pub struct Move {
    /// `FILE:PATH`.
    pub parameter: String,
    /// Where it came from: `params`, or `top` with the study's rank.
    pub from: String,
    /// Its source class (`assumed`, ..., `untagged`) as its file tags it.
    pub class: String,
    /// Its value in the files.
    pub base: f64,
    /// The scale factors of its range's ends [low, high].
    pub factors: [f64; 2],
    /// The overrides setting it to each end (with a ring tyre's independent factors held
    /// at their file values, see [`make_move`]).
    #[serde(skip)]
    pub ends: [Vec<Override>; 2],
    /// The block's field that names it (errors about it point there).
    #[serde(skip)]
    pub at: Box<InputError>,
}

/// A validated `[robustness]` block.
#[derive(Clone, Debug, Serialize)]
pub struct Robustness {
    /// The parameter whose values are ranked.
    pub by: String,
    /// The figures ranked (empty: every figure `sweep rank` ranks).
    pub figures: Vec<String>,
    /// The part of the grid re-run: (parameter, values as the sweep writes them).
    pub subset: Vec<(String, Vec<String>)>,
    /// The values moved.
    pub moves: Vec<Move>,
    /// Where `figures` is written (a figure the table lacks is blamed there).
    #[serde(skip)]
    pub figures_at: Box<InputError>,
}

impl RobustnessIn {
    /// Checks the block against the sweep's parameters (`name`, values as TOML text)
    /// and resolves its values against the files `scene` reads.
    pub(super) fn check(
        &self,
        src: &Source,
        scene: &Path,
        params: &[(String, Vec<String>)],
    ) -> Result<Robustness, InputError> {
        let at = |k: &str| path!["robustness", k.to_string()];
        let range = match self.range {
            Some(r) if !(r > 0.0 && r < 1.0) => {
                return Err(src.error(&at("range"), format!("{r}: a fraction between 0 and 1")))
            }
            Some(r) => r,
            None => Settings::default().range,
        };
        let by = match &self.by {
            Some(b) if params.iter().any(|(n, _)| n == b) => b.clone(),
            Some(b) => return Err(src.error(&at("by"), format!("'{b}' is not a swept parameter"))),
            None => params
                .iter()
                .find(|(n, _)| n == "hitch_variant")
                .or(params.first())
                .map(|(n, _)| n.clone())
                .ok_or_else(|| src.error(&at("by"), "the sweep has no parameter to rank by"))?,
        };
        let mut subset = Vec::new();
        for (k, v) in &self.subset {
            let here = path!["robustness", "subset", k.clone()];
            let Some((_, allowed)) = params.iter().find(|(n, _)| n == k) else {
                return Err(src.error(&here, "is not a swept parameter"));
            };
            let list = v
                .as_array()
                .filter(|a| !a.is_empty())
                .ok_or_else(|| src.error(&here, "wants a non-empty list of the sweep's values"))?;
            let mut values = Vec::new();
            for x in list {
                let text = towride_mbs::input::value_text(x);
                let Some(a) = allowed.iter().find(|a| same_value(a, &text)) else {
                    return Err(src.error(
                        &here,
                        format!("{text} is not among the swept values {allowed:?}"),
                    ));
                };
                values.push(a.clone());
            }
            subset.push((k.clone(), values));
        }
        if self.params.is_empty() && self.top.is_none_or(|n| n == 0) {
            return Err(src.error(
                &path!["robustness"],
                "names no value to move: give `params` (FILE:PATH) or `top` (N > 0)",
            ));
        }
        let all = candidates(scene, &[]).map_err(|e| src.error(&at("params"), e.to_string()))?;
        let mut moves = Vec::new();
        for (i, name) in self.params.iter().enumerate() {
            let here = path!["robustness", "params", i];
            let p =
                named(&all, std::slice::from_ref(name)).map_err(|e| src.error(&here, e.message))?;
            let at = src.error(&here, "");
            moves.push(make_move(&p[0], "params", range_of(&p[0], range), &all, at));
        }
        if let Some(n) = self.top.filter(|&n| n > 0) {
            let file = match &self.study {
                Some(s) => src.existing_file(&at("study"), s)?,
                None => default_dir(scene).join("sensitivity.json"),
            };
            for m in top_assumed(src, scene, &file, n, &all, range)? {
                if !moves.iter().any(|q: &Move| q.parameter == m.parameter) {
                    moves.push(m);
                }
            }
        }
        // Each end must still build the scene: a refused value costs no runs.
        for m in &moves {
            for (e, ov) in m.ends.iter().enumerate() {
                let loader = Loader::with_overrides(ov.clone());
                // A job, as a case builds it: a scene or a mechanism.
                if let Err(err) = crate::job::Job::from_file(scene, &loader) {
                    return Err(InputError {
                        message: format!("{} x {}: {err}", m.parameter, m.factors[e]),
                        ..(*m.at).clone()
                    });
                }
            }
        }
        Ok(Robustness {
            by,
            figures: self.figures.clone(),
            subset,
            moves,
            figures_at: Box::new(src.error(&at("figures"), "")),
        })
    }
}

/// The `n` highest-ranked `[assumed]` values of the sensitivity study `file` of `scene`
/// (its ranking by the first output, [`ranked`]), each over the study's own range.
fn top_assumed(
    src: &Source,
    scene: &Path,
    file: &Path,
    n: usize,
    all: &[Param],
    range: f64,
) -> Result<Vec<Move>, InputError> {
    let here = path!["robustness", "top"];
    let r = ranked(scene, file).map_err(|note| src.error(&here, note))?;
    let mut out = Vec::new();
    for i in r
        .inputs
        .iter()
        .filter(|i| i.class == Class::Assumed)
        .take(n)
    {
        let name = &i.input.parameter;
        let p = named(all, std::slice::from_ref(name)).map_err(|e| {
            src.error(
                &here,
                format!("{name} of {}: {}", file.display(), e.message),
            )
        })?;
        let factors = i.range.unwrap_or_else(|| range_of(&p[0], range));
        let from = format!(
            "top: rank {} of {} by {}",
            i.input.rank,
            r.study,
            r.output.as_deref().unwrap_or("its first output")
        );
        out.push(make_move(&p[0], &from, factors, all, src.error(&here, "")));
    }
    if out.len() < n {
        return Err(src.error(
            &here,
            format!(
                "{n} assumed values wanted, {} has {}",
                file.display(),
                out.len()
            ),
        ));
    }
    Ok(out)
}

/// Value `p` moved to `factors`, its overrides blamed on `at` (the block's field). A
/// `.tir` value of a ring tyre that is not itself a factor (FREQ_WINDUP) moves with the
/// file's independent factors held at their values ([`candidates`] lists them), as the
/// sensitivity study moves it beside them: the values they drive (the longitudinal
/// stiffness, which must stay below the ring's) follow, and the tyre stays valid
/// (docs/road_tyre.md, "Independent factors of the ring tyre").
fn make_move(p: &Param, from: &str, factors: [f64; 2], all: &[Param], at: InputError) -> Move {
    let blame = |o: Override| Override {
        origin: Origin::File {
            file: Box::new(at.clone()),
            path: Box::new(at.clone()),
        },
        ..o
    };
    let held: Vec<Override> = all
        .iter()
        .filter(|q| q.file == p.file && q.path.starts_with(factors::PREFIX) && q.path != p.path)
        .filter(|_| {
            !p.path.starts_with(factors::PREFIX) && !factors::DRIVEN.contains(&p.path.as_str())
        })
        .map(|q| blame(q.scaled(1.0)))
        .collect();
    let end = |f: f64| {
        let mut v = vec![blame(p.scaled(f))];
        v.extend(held.iter().cloned());
        v
    };
    Move {
        parameter: p.name.clone(),
        from: from.into(),
        class: class_of(p),
        base: p.base_value(),
        factors,
        ends: [end(factors[0]), end(factors[1])],
        at: Box::new(at),
    }
}

/// The source class its file gives `p` (a tyre factor: the weakest of its sources').
fn class_of(p: &Param) -> String {
    let mut e = read_provenance(&p.disk_path).unwrap_or_default();
    e.extend(towride_mbs::tyre::factors::provenance(&e));
    e.iter()
        .find(|x| x.key == p.path)
        .map_or("untagged".into(), |x| x.class.as_str().into())
}
