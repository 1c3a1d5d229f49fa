//! The band-limited twins of a run's channels: each accelerometer, force and deflection
//! channel ([`channels::band`]) through the scene's acquisition chain
//! ([`crate::signal::acquisition`]), appended to the samples as `<name><suffix>`
//! (`acc_hitch_z_lp100`) after the raw channels, which stay as the model computed them.

use crate::error::SignalError;
use crate::scene::channels;
use crate::signal::acquisition::{band_limit, AcqFilter};
use towride_mbs::model::output::ChannelInfo;
use towride_mbs::model::run::Samples;

/// The channels among `names` that get a band-limited twin under `f`, with the twin's
/// name: (index in `names`, twin name).
pub fn twins<'a>(names: impl IntoIterator<Item = &'a str>, f: &AcqFilter) -> Vec<(usize, String)> {
    let suffix = f.suffix();
    names
        .into_iter()
        .enumerate()
        .filter(|(_, n)| channels::band(n).is_some())
        .map(|(k, n)| (k, format!("{n}{suffix}")))
        .collect()
}

/// Appends the band-limited twins of `samples`' channels (sampled every 1/`rate` s, as a
/// run samples them) through `f`; returns (raw column, twin column) pairs.
pub fn append(
    samples: &mut Samples,
    f: &AcqFilter,
    rate: f64,
) -> Result<Vec<(usize, usize)>, SignalError> {
    let pairs = twins(samples.channels.iter().map(|c| c.name.as_str()), f);
    let mut out = Vec::with_capacity(pairs.len());
    let mut columns = Vec::with_capacity(pairs.len());
    for (c, name) in pairs {
        let y: Vec<f64> = samples.rows.iter().map(|r| r[c]).collect();
        columns.push(band_limit(f, &y, rate)?);
        out.push((c, samples.channels.len()));
        let unit = samples.channels[c].unit;
        samples.channels.push(ChannelInfo {
            name,
            unit,
            angle: false,
        });
    }
    for (k, row) in samples.rows.iter_mut().enumerate() {
        row.extend(columns.iter().map(|v| v[k]));
    }
    Ok(out)
}
