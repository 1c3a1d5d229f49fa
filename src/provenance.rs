//! `towride provenance PATH...`: the source class (measured, published, scaled, assumed)
//! of every value of the property files under the paths, and the numbers without one.

use crate::CliResult;
use std::path::PathBuf;

use clap::Args;
use towride_mbs::input::provenance::{survey, SourceClass};

#[derive(Args, Debug)]
pub struct ProvenanceArgs {
    /// Property files or folders (searched for .toml and .tir files).
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// List only the values of this class (measured, published, scaled, assumed).
    #[arg(long)]
    class: Option<String>,
    /// Print a JSON document instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &ProvenanceArgs) -> CliResult {
    let class = match a.class.as_deref() {
        None => None,
        Some(w) => Some(
            SourceClass::ALL
                .into_iter()
                .find(|c| c.as_str() == w)
                .ok_or_else(|| {
                    format!("--class {w}: use measured, published, scaled or assumed")
                })?,
        ),
    };
    let mut s = survey(&a.paths)?;
    if let Some(c) = class {
        for f in &mut s.files {
            f.entries.retain(|e| e.class == c);
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&s)?);
    } else {
        for f in &s.files {
            if f.entries.is_empty() && f.untagged.is_empty() {
                continue;
            }
            println!("{}", f.file);
            for e in &f.entries {
                println!("  {:>4}  {:<9}  {}: {}", e.line, e.class, e.key, e.source);
            }
            for u in &f.untagged {
                println!("  {:>4}  UNTAGGED   {}", u.line, u.key);
            }
        }
        let counts: Vec<String> = s.counts.iter().map(|(c, n)| format!("{n} {c}")).collect();
        println!(
            "{} files: {}; {} numbers without a class",
            s.files.len(),
            counts.join(", "),
            s.untagged
        );
    }
    Ok(if s.untagged > 0 { 1 } else { 0 })
}
