//! A sweep's parameters checked against the files before the first case runs: every
//! distinct value of every parameter is applied alone (the others as the files give
//! them) and the scene read through the loader, without assembling or integrating. A
//! key path that matches nothing, a file the scene does not read, a value of the wrong
//! type or one set twice (also by `--set`) is then an error naming the sweep file, line
//! and field, instead of every case failing with it.
//!
//! A value of the same type as values that load, refused for what it is (a negative
//! mass, a bound), is not an error here: that case fails on its own while the others go
//! on (the sweep's contract for values a case cannot run with).

use std::path::PathBuf;

use rayon::prelude::*;

use super::Sweep;
use crate::error::{Error, Result};
use towride_mbs::input::{InputError, Loader, Override};

/// One probe: parameter `k`, value `i` of its list.
struct Probe {
    k: usize,
    i: usize,
    ov: Override,
}

/// Checks every parameter of `sweep` (see the module text) on `jobs` threads; returns
/// the files the scene reads (normalised, first-read order).
pub fn check(sweep: &Sweep, jobs: usize) -> Result<Vec<PathBuf>> {
    let mut probes = Vec::new();
    for (k, p) in sweep.parameters.iter().enumerate() {
        for (i, v) in p.values.iter().enumerate() {
            if p.values[..i].contains(v) {
                continue;
            }
            probes.push(Probe {
                k,
                i,
                ov: Override {
                    file: p.file.clone(),
                    path: p.path.clone(),
                    value: v.clone(),
                    origin: p.origin.clone(),
                },
            });
        }
    }
    let read = sweep.base.fresh();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .build()
        .map_err(|e| Error::io("thread pool", std::io::Error::other(e.to_string())))?;
    let results: Vec<std::result::Result<(), InputError>> = pool.install(|| {
        probes
            .par_iter()
            .map(|pr| load(sweep, &read.extended(vec![pr.ov.clone()])))
            .collect()
    });
    // Without probes (every value out of bounds, or no parameter) the scene alone.
    if probes.is_empty() {
        load(sweep, &read)?;
    }
    for (k, p) in sweep.parameters.iter().enumerate() {
        // The probes of this parameter and their errors located at the sweep file (the
        // override's fault); others are a case's own failure, reported when it runs.
        let mine: Vec<(&Probe, Option<&InputError>)> = probes
            .iter()
            .zip(&results)
            .filter(|(q, _)| q.k == k)
            .map(|(q, r)| (q, r.as_ref().err().filter(|e| e.file == p.values_at.file)))
            .collect();
        let mut loaded: Vec<&str> = mine
            .iter()
            .filter(|(_, e)| e.is_none())
            .map(|(q, _)| kind(&q.ov.value))
            .collect();
        loaded.sort();
        loaded.dedup();
        for (q, e) in &mine {
            let Some(e) = e else { continue };
            if loaded.is_empty() {
                // No value loads: the address (or what all values share) is wrong.
                return Err((*e).clone().into());
            }
            // A value of another type than the values that load: wrong type. One of the
            // same type fails on its value (a bound), which is that case's failure.
            let this = kind(&q.ov.value);
            if !loaded.contains(&this) {
                return Err(InputError {
                    field: format!("parameter[{k}].values[{}]", q.i),
                    message: format!(
                        "{} = {} is {this}, the values that load are {}: {}",
                        p.name,
                        p.values[q.i],
                        loaded.join(", "),
                        e.message
                    ),
                    ..(*p.values_at).clone()
                }
                .into());
            }
        }
    }
    Ok(read.files_read())
}

/// The scene (or mechanism) read through `loader`, overrides checked for use.
fn load(sweep: &Sweep, loader: &Loader) -> std::result::Result<(), InputError> {
    let path = &sweep.scene;
    if crate::scene::is_scene(path) {
        crate::scene::load_with(path, &crate::scene::Changes::default(), loader).map(drop)
    } else {
        let m = towride_mbs::model::spec::load(path, loader)?;
        drop(m);
        Ok(())
    }
}

/// The TOML kind of a value's text: number (integer or float), string, boolean, array,
/// table or date.
fn kind(value: &str) -> &'static str {
    use toml_edit::Value as V;
    match value.parse::<V>() {
        Ok(V::Integer(_) | V::Float(_)) => "a number",
        Ok(V::String(_)) => "a string",
        Ok(V::Boolean(_)) => "a boolean",
        Ok(V::Array(_)) => "an array",
        Ok(V::InlineTable(_)) => "a table",
        Ok(V::Datetime(_)) => "a date",
        Err(_) => "not TOML",
    }
}
